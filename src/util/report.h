/* BwReport: named values a run records about itself (the /solver
 * attributes): each object adds its own, the output writes them all, so
 * that output/ needs no object's insides. Names are unique: setting one
 * again replaces it. Identical on every rank. */
#pragma once
#include <petscsys.h>

typedef enum { BW_REPORT_REAL, BW_REPORT_INT, BW_REPORT_STRING } BwReportType;

typedef struct {
  char         name[64];
  BwReportType type;
  PetscReal    real;
  long long    integer;
  char        *text;
} BwReportItem;

typedef struct _n_BwReport *BwReport;
struct _n_BwReport {
  PetscInt      n, max;
  BwReportItem *item;
};

PetscErrorCode BwReportCreate(BwReport *report);
PetscErrorCode BwReportReal(BwReport report, const char name[], PetscReal value);
PetscErrorCode BwReportInt(BwReport report, const char name[], long long value);
PetscErrorCode BwReportString(BwReport report, const char name[], const char text[]);
/* The value of a real or integer item as a real, or def when absent. */
PetscReal      BwReportGetReal(BwReport report, const char name[], PetscReal def);
PetscErrorCode BwReportDestroy(BwReport *report);
