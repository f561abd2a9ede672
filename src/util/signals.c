/* Signal handling for interrupted runs (see signals.h). Only
 * async-signal-safe calls in the handler: unlink, write, sigaction, raise. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include "util/signals.h"
#include "util/compat.h"

#define BW_MAX_TEMPORARY 8

static char                  bw_temporary[BW_MAX_TEMPORARY][PETSC_MAX_PATH_LEN + 64];
static volatile sig_atomic_t bw_ntemporary = 0;
static int                   bw_rank       = 0;
static const int             bw_signals[]  = {SIGTERM, SIGINT, SIGHUP};

static void BwSignalHandler(int sig)
{
  struct sigaction dfl;
  static const char line[] = "blockwall: error: interrupted by a signal; every output file is either complete or as it was\n";

  for (int k = 0; k < bw_ntemporary && k < BW_MAX_TEMPORARY; k++)
    if (bw_temporary[k][0]) (void)unlink(bw_temporary[k]);
  if (bw_rank == 0 && write(STDERR_FILENO, line, sizeof(line) - 1) < 0) { /* nothing more to do */
  }
  memset(&dfl, 0, sizeof(dfl));
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  sigaction(sig, &dfl, NULL);
  raise(sig);
}

PetscErrorCode BwSignalsInstall(MPI_Comm comm)
{
  struct sigaction sa;
  PetscMPIInt      rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  bw_rank = rank;
  memset(&sa, 0, sizeof(sa));
  sa.sa_handler = BwSignalHandler;
  sigemptyset(&sa.sa_mask);
  for (size_t k = 0; k < sizeof(bw_signals) / sizeof(bw_signals[0]); k++) sigaddset(&sa.sa_mask, bw_signals[k]);
  for (size_t k = 0; k < sizeof(bw_signals) / sizeof(bw_signals[0]); k++) PetscCheck(sigaction(bw_signals[k], &sa, NULL) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS, "cannot install a signal handler: %s", strerror(errno));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The table is changed with the signals blocked, so the handler never sees
 * a half-written entry. */
static void BwSignalsBlock(sigset_t *old, PetscBool block)
{
  sigset_t set;

  if (!block) {
    sigprocmask(SIG_SETMASK, old, NULL);
    return;
  }
  sigemptyset(&set);
  for (size_t k = 0; k < sizeof(bw_signals) / sizeof(bw_signals[0]); k++) sigaddset(&set, bw_signals[k]);
  sigprocmask(SIG_BLOCK, &set, old);
}

PetscErrorCode BwTemporaryAdd(const char path[])
{
  sigset_t old;
  int      slot = -1;

  PetscFunctionBeginUser;
  PetscCheck(strlen(path) < sizeof(bw_temporary[0]), PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "temporary path too long: %s", path);
  BwSignalsBlock(&old, PETSC_TRUE);
  for (int k = 0; k < bw_ntemporary && k < BW_MAX_TEMPORARY && slot < 0; k++)
    if (!bw_temporary[k][0]) slot = k;
  if (slot < 0 && bw_ntemporary < BW_MAX_TEMPORARY) slot = bw_ntemporary++;
  if (slot >= 0) snprintf(bw_temporary[slot], sizeof(bw_temporary[slot]), "%s", path);
  BwSignalsBlock(&old, PETSC_FALSE);
  PetscCheck(slot >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "more than %d temporary files at once", BW_MAX_TEMPORARY);
  PetscFunctionReturn(PETSC_SUCCESS);
}

void BwTemporaryRemove(const char path[])
{
  sigset_t old;

  BwSignalsBlock(&old, PETSC_TRUE);
  for (int k = 0; k < bw_ntemporary && k < BW_MAX_TEMPORARY; k++)
    if (!strcmp(bw_temporary[k], path)) bw_temporary[k][0] = 0;
  BwSignalsBlock(&old, PETSC_FALSE);
}

int BwRenameAll(int n, const char *const from[], const char *const to[], int *failed)
{
  sigset_t old;
  int      rc = 0;

  *failed = -1;
  BwSignalsBlock(&old, PETSC_TRUE);
  for (int k = 0; k < n && !rc; k++) {
    rc = rename(from[k], to[k]);
    if (rc) *failed = k;
    else
      for (int j = 0; j < bw_ntemporary && j < BW_MAX_TEMPORARY; j++)
        if (!strcmp(bw_temporary[j], from[k])) bw_temporary[j][0] = 0;
  }
  {
    int saved = errno;
    BwSignalsBlock(&old, PETSC_FALSE);
    errno = saved;
  }
  return rc;
}
