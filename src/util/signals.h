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
/* Holds (blocks) the signals until BwSignalsInstall: around PetscInitialize,
 * which installs PETSc's own handlers, so that a signal sent meanwhile waits
 * for blockwall's handler instead of meeting PETSc's. Called after MPI_Init,
 * which can take seconds on a busy machine: a launcher's SIGKILL follows its
 * SIGTERM one second later, and a signal held that long is never handled. */
void BwSignalsHold(void);
/* Installs the handlers again after PetscInitialize (over PETSc's for these
 * signals) and releases the held signals; rank 0 of comm prints the line. */
PetscErrorCode BwSignalsInstall(MPI_Comm comm);
/* The run has ended (its result written or its error known): a launcher's
 * SIGCONT is no longer an interruption to report. */
void BwSignalsFinishing(void);
/* A temporary file a signal must remove / no longer remove. */
PetscErrorCode BwTemporaryAdd(const char path[]);
void           BwTemporaryRemove(const char path[]);
/* A deadline on a step that needs every rank (a collective HDF5 call):
 * if the step has not ended `seconds` from now, the process removes the
 * temporary files, prints "blockwall: error: <message>" (rank 0; the other
 * ranks wait 10 s longer and stay silent, so that the line comes once) and
 * exits with 1, which makes mpiexec end the job. A rank that left a
 * collective call early on an error (a full disk seen by one rank) would
 * otherwise leave the others waiting in it for ever. Arming again moves the
 * deadline and replaces the message; time spent stopped (SIGSTOP) does not
 * count. */
void BwDeadlineArm(double seconds, const char message[]);
void BwDeadlineDisarm(void);
/* A library was left in a state its own finalisation cannot survive (an
 * HDF5 file whose close failed): the run ends with its exit code but
 * without MPI_Finalize (main.c asks BwFinalizeSkipped). */
void      BwSkipFinalize(void);
PetscBool BwFinalizeSkipped(void);
/* rename(from[k], to[k]) for k < n with the signals blocked; the first that
 * fails is reported (errno kept) and the later ones are not made. */
int BwRenameAll(int n, const char *const from[], const char *const to[], int *failed);
