/* Signal handling for interrupted runs (see signals.h). Only
 * async-signal-safe calls in the handlers: unlink, write, sigaction, raise,
 * clock_gettime. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdatomic.h>
#include <pthread.h>
#include <signal.h>
#include <time.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "util/signals.h"
#include "util/compat.h"

#define BW_MAX_TEMPORARY 8

static char                  bw_temporary[BW_MAX_TEMPORARY][PETSC_MAX_PATH_LEN + 64];
static volatile sig_atomic_t bw_ntemporary = 0;
static int                   bw_rank       = 0;
static const int             bw_signals[]  = {SIGTERM, SIGINT, SIGHUP, SIGCONT};

/* The launcher's kill sequence. Open MPI's mpiexec (4.x), told to stop by
 * SIGTERM or SIGINT, sends its ranks SIGCONT, waits a second, then SIGTERM,
 * and by then no longer forwards their output: a short run went on to write
 * its result in that second, and the line never reached the user. A SIGCONT
 * that does not end a stop is therefore the launcher stopping the job, and
 * is treated as the interruption it announces. A stop is seen by a thread
 * that only ticks a clock every BW_TICK_NS: after SIGSTOP (a scheduler's or
 * mpiexec's suspend) its last tick is old when SIGCONT resumes the process. */
#define BW_TICK_NS 50000000LL
#define BW_STOPPED_NS 400000000LL
/* monotonic nanoseconds of the last tick and of the last resume the ticker
 * saw (a gap between its ticks); lock-free atomics are safe in a handler */
static _Atomic long long bw_tick = 0, bw_resumed = -1000000000000LL;
static _Atomic int       bw_finishing = 0;
static _Atomic int       bw_said      = 0; /* the interruption's line was written */
/* BwDeadlineArm: monotonic nanoseconds of the deadline (0: none), and the
 * line; the message is written only while no deadline is armed */
static _Atomic long long bw_deadline = 0;
static char              bw_deadline_line[1024];
static void              BwDeadlinePassed(void);

static long long BwNow(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (long long)t.tv_sec * 1000000000LL + t.tv_nsec;
}

static void *BwTicker(void *arg)
{
  struct timespec nap = {0, BW_TICK_NS};
  (void)arg;
  for (;;) {
    long long now = BwNow(), last = bw_tick, deadline = bw_deadline;
    if (last && now - last > BW_STOPPED_NS) {
      bw_resumed = now;
      /* a stopped process makes no progress and is owed its time */
      if (deadline) bw_deadline = deadline + (now - last);
    } else if (deadline && now > deadline) BwDeadlinePassed();
    bw_tick = now;
    nanosleep(&nap, NULL);
  }
  return NULL;
}

/* SIGCONT after a stop: the ticker has not ticked since (the handler runs
 * first), or it has and saw the gap (it ran first). */
static int BwResumedFromStop(void)
{
  long long now = BwNow(), tick = bw_tick;
  if (!tick) return 1; /* no clock to tell: keep SIGCONT's meaning */
  return now - tick > BW_STOPPED_NS || now - bw_resumed < 2 * BW_STOPPED_NS;
}

static void BwSignalHandler(int sig)
{
  struct sigaction dfl;
  static const char line[] = "blockwall: error: interrupted by a signal; every output file is either complete or as it was\n";

  if (sig == SIGCONT) {
    /* after the run: a rank that ended first (with its error) makes the
     * launcher stop the others, which have nothing left to lose or say */
    if (BwResumedFromStop() || bw_finishing) return;
    sig = SIGTERM; /* the launcher's SIGTERM is a second away */
  }
  for (int k = 0; k < bw_ntemporary && k < BW_MAX_TEMPORARY; k++)
    if (bw_temporary[k][0]) (void)unlink(bw_temporary[k]);
  /* once per process: the launcher's SIGCONT and its SIGTERM can each be
   * taken by another thread at the same moment (the mask only holds within
   * one thread), and both handlers ran to here (errors.io.mpiexec_sigterm
   * saw the line twice on a loaded machine) */
  if (bw_rank == 0 && !atomic_exchange(&bw_said, 1) && write(STDERR_FILENO, line, sizeof(line) - 1) < 0) { /* nothing more to do */
  }
  memset(&dfl, 0, sizeof(dfl));
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  sigaction(sig, &dfl, NULL);
  raise(sig);
}

static int BwSignalsSetHandlers(void)
{
  struct sigaction sa;

  memset(&sa, 0, sizeof(sa));
  sa.sa_handler = BwSignalHandler;
  sigemptyset(&sa.sa_mask);
  for (size_t k = 0; k < sizeof(bw_signals) / sizeof(bw_signals[0]); k++) sigaddset(&sa.sa_mask, bw_signals[k]);
  for (size_t k = 0; k < sizeof(bw_signals) / sizeof(bw_signals[0]); k++)
    if (sigaction(bw_signals[k], &sa, NULL)) return -1;
  return 0;
}

static void     BwSignalsBlock(sigset_t *old, PetscBool block);
static sigset_t bw_before_hold; /* the mask before BwSignalsHold */
static int      bw_held;

/* The launcher's rank, before MPI can tell it (Open MPI, PMIx, PMI, Slurm). */
static int BwLauncherRank(void)
{
  static const char *const names[] = {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID"};
  for (size_t k = 0; k < sizeof(names) / sizeof(names[0]); k++) {
    const char *v = getenv(names[k]);
    if (v && *v) return atoi(v);
  }
  return 0;
}

int BwSignalsInstallEarly(void)
{
  pthread_t      ticker;
  pthread_attr_t attr;
  sigset_t       all, old;

  bw_rank = BwLauncherRank();
  if (BwSignalsSetHandlers()) return -1;
  /* the ticker takes no signal: they are all handled by the threads that work */
  sigfillset(&all);
  pthread_sigmask(SIG_SETMASK, &all, &old);
  if (!pthread_attr_init(&attr)) {
    pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
    (void)pthread_create(&ticker, &attr, BwTicker, NULL); /* without it SIGCONT is ignored, as before */
    pthread_attr_destroy(&attr);
  }
  pthread_sigmask(SIG_SETMASK, &old, NULL);
  return 0;
}

void BwSignalsHold(void)
{
  if (bw_held) return;
  BwSignalsBlock(&bw_before_hold, PETSC_TRUE);
  bw_held = 1;
}

void BwSignalsFinishing(void) { bw_finishing = 1; }

PetscErrorCode BwSignalsInstall(MPI_Comm comm)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  bw_rank = rank;
  PetscCheck(BwSignalsSetHandlers() == 0, PETSC_COMM_SELF, PETSC_ERR_SYS, "cannot install a signal handler: %s", strerror(errno));
  if (bw_held) {
    bw_held = 0;
    BwSignalsBlock(&bw_before_hold, PETSC_FALSE);
  }
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

/* From the ticker thread: only async-signal-safe calls, as in a handler. */
static void BwDeadlinePassed(void)
{
  for (int k = 0; k < bw_ntemporary && k < BW_MAX_TEMPORARY; k++)
    if (bw_temporary[k][0]) (void)unlink(bw_temporary[k]);
  if (bw_rank == 0 && write(STDERR_FILENO, bw_deadline_line, strlen(bw_deadline_line)) < 0) { /* nothing more to do */
  }
  _exit(1);
}

void BwDeadlineArm(double seconds, const char message[])
{
  bw_deadline = 0;
  snprintf(bw_deadline_line, sizeof(bw_deadline_line), "blockwall: error: %s\n", message);
  bw_deadline = BwNow() + (long long)((seconds + (bw_rank ? 10 : 0)) * 1e9);
}

void BwDeadlineDisarm(void) { bw_deadline = 0; }

static PetscBool bw_skip_finalize = PETSC_FALSE;
void             BwSkipFinalize(void) { bw_skip_finalize = PETSC_TRUE; }
PetscBool        BwFinalizeSkipped(void) { return bw_skip_finalize; }

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
