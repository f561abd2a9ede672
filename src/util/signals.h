/* Interrupted runs leave nothing behind: SIGTERM, SIGINT and SIGHUP remove
 * the temporary files of the output being written (the target itself is
 * only ever replaced by a rename of a complete file), print one line, and
 * end the process with the signal. The renames that publish a result are
 * made with those signals blocked, so an interruption sees the old files or
 * the new ones, never a mix.
 *
 * A signal handler can reach only static data: the temporary paths live in
 * a fixed table here, the one global state of blockwall, by necessity. */
#pragma once
#include <petscsys.h>

/* Installs the handlers and starts the clock that tells a launcher's
 * SIGCONT from a resume (signals.c), first thing in main, so that a signal
 * during MPI's start-up is seen too; the rank that prints is the launcher's
 * until MPI runs. Returns non-zero when a handler cannot be installed. */
int BwSignalsInstallEarly(void);
/* Installs the handlers again after PetscInitialize (over PETSc's for these
 * signals); rank 0 of comm prints the line. */
PetscErrorCode BwSignalsInstall(MPI_Comm comm);
/* The run has ended (its result written or its error known): a launcher's
 * SIGCONT is no longer an interruption to report. */
void BwSignalsFinishing(void);
/* A temporary file a signal must remove / no longer remove. */
PetscErrorCode BwTemporaryAdd(const char path[]);
void           BwTemporaryRemove(const char path[]);
/* rename(from[k], to[k]) for k < n with the signals blocked; the first that
 * fails is reported (errno kept) and the later ones are not made. */
int BwRenameAll(int n, const char *const from[], const char *const to[], int *failed);
