/* BwReport: a small list of named values (see report.h). */
#include <string.h>
#include "util/report.h"
#include "util/compat.h"

PetscErrorCode BwReportCreate(BwReport *report)
{
  PetscFunctionBeginUser;
  PetscCall(PetscNew(report));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BwReportSlot(BwReport r, const char name[], BwReportItem **it)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < r->n; i++)
    if (!strcmp(r->item[i].name, name)) {
      PetscCall(PetscFree(r->item[i].text));
      *it = &r->item[i];
      PetscFunctionReturn(PETSC_SUCCESS);
    }
  if (r->n == r->max) {
    BwReportItem *more;
    r->max = PetscMax(2 * r->max, 32);
    PetscCall(PetscCalloc1(r->max, &more));
    PetscCall(PetscArraycpy(more, r->item, r->n));
    PetscCall(PetscFree(r->item));
    r->item = more;
  }
  *it = &r->item[r->n++];
  PetscCall(PetscMemzero(*it, sizeof(**it)));
  PetscCall(PetscStrncpy((*it)->name, name, sizeof((*it)->name)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwReportReal(BwReport r, const char name[], PetscReal v)
{
  BwReportItem *it;

  PetscFunctionBeginUser;
  PetscCall(BwReportSlot(r, name, &it));
  it->type = BW_REPORT_REAL;
  it->real = v;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwReportInt(BwReport r, const char name[], long long v)
{
  BwReportItem *it;

  PetscFunctionBeginUser;
  PetscCall(BwReportSlot(r, name, &it));
  it->type    = BW_REPORT_INT;
  it->integer = v;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BwReportString(BwReport r, const char name[], const char text[])
{
  BwReportItem *it;

  PetscFunctionBeginUser;
  PetscCall(BwReportSlot(r, name, &it));
  it->type = BW_REPORT_STRING;
  PetscCall(PetscStrallocpy(text ? text : "", &it->text));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscReal BwReportGetReal(BwReport r, const char name[], PetscReal def)
{
  for (PetscInt i = 0; i < r->n; i++)
    if (!strcmp(r->item[i].name, name)) return r->item[i].type == BW_REPORT_INT ? (PetscReal)r->item[i].integer : r->item[i].type == BW_REPORT_REAL ? r->item[i].real : def;
  return def;
}

PetscErrorCode BwReportDestroy(BwReport *report)
{
  PetscFunctionBeginUser;
  if (!*report) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt i = 0; i < (*report)->n; i++) PetscCall(PetscFree((*report)->item[i].text));
  PetscCall(PetscFree((*report)->item));
  PetscCall(PetscFree(*report));
  PetscFunctionReturn(PETSC_SUCCESS);
}
