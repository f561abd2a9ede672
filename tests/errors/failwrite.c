/* A fault injector for the output tests, loaded with LD_PRELOAD: the
 * system's write calls on blockwall's temporary result files (names with
 * ".tmp-") fail with ENOSPC once the file would occupy more than
 * BW_FAIL_AFTER bytes of disk (a disk that fills while the file is written,
 * which the free-space check before writing cannot see; truncating the file
 * frees the space again, as on a real disk), or are each delayed by
 * BW_WRITE_DELAY_MS (time to interrupt a run while it writes). Other files
 * are untouched. BW_FAKE_FREE makes statvfs report that many bytes free (a
 * full disk seen before writing). Only for tests/errors/check_io.py. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <time.h>
#include <unistd.h>

/* Is fd a temporary result file? Then may this write of n bytes go on? */
static int bw_allowed(int fd, size_t n)
{
  char        link[64], path[4096];
  ssize_t     len;
  const char *limit = getenv("BW_FAIL_AFTER"), *delay = getenv("BW_WRITE_DELAY_MS");

  snprintf(link, sizeof(link), "/proc/self/fd/%d", fd);
  len = readlink(link, path, sizeof(path) - 1);
  if (len <= 0) return 1;
  path[len] = 0;
  if (!strstr(path, ".tmp-")) return 1;
  if (delay) {
    long            ms = atol(delay); /* tv_nsec must stay below 1e9: whole seconds go to tv_sec */
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
  }
  if (limit) {
    struct stat st;
    if (fstat(fd, &st) == 0 && (long long)st.st_blocks * 512 + (long long)n > atoll(limit)) {
      errno = ENOSPC;
      return 0;
    }
  }
  return 1;
}

ssize_t write(int fd, const void *buf, size_t n)
{
  static ssize_t (*real)(int, const void *, size_t);
  if (!real) real = (ssize_t(*)(int, const void *, size_t))dlsym(RTLD_NEXT, "write");
  if (!bw_allowed(fd, n)) return -1;
  return real(fd, buf, n);
}

ssize_t pwrite(int fd, const void *buf, size_t n, off_t off)
{
  static ssize_t (*real)(int, const void *, size_t, off_t);
  if (!real) real = (ssize_t(*)(int, const void *, size_t, off_t))dlsym(RTLD_NEXT, "pwrite");
  if (!bw_allowed(fd, n)) return -1;
  return real(fd, buf, n, off);
}

ssize_t pwrite64(int fd, const void *buf, size_t n, off_t off)
{
  static ssize_t (*real)(int, const void *, size_t, off_t);
  if (!real) real = (ssize_t(*)(int, const void *, size_t, off_t))dlsym(RTLD_NEXT, "pwrite64");
  if (!bw_allowed(fd, n)) return -1;
  return real(fd, buf, n, off);
}

static size_t bw_iov_bytes(const struct iovec *iov, int cnt)
{
  size_t n = 0;
  for (int k = 0; k < cnt; k++) n += iov[k].iov_len;
  return n;
}

ssize_t pwritev(int fd, const struct iovec *iov, int cnt, off_t off)
{
  static ssize_t (*real)(int, const struct iovec *, int, off_t);
  if (!real) real = (ssize_t(*)(int, const struct iovec *, int, off_t))dlsym(RTLD_NEXT, "pwritev");
  if (!bw_allowed(fd, bw_iov_bytes(iov, cnt))) return -1;
  return real(fd, iov, cnt, off);
}

ssize_t pwritev64(int fd, const struct iovec *iov, int cnt, off_t off)
{
  static ssize_t (*real)(int, const struct iovec *, int, off_t);
  if (!real) real = (ssize_t(*)(int, const struct iovec *, int, off_t))dlsym(RTLD_NEXT, "pwritev64");
  if (!bw_allowed(fd, bw_iov_bytes(iov, cnt))) return -1;
  return real(fd, iov, cnt, off);
}

ssize_t writev(int fd, const struct iovec *iov, int cnt)
{
  static ssize_t (*real)(int, const struct iovec *, int);
  if (!real) real = (ssize_t(*)(int, const struct iovec *, int))dlsym(RTLD_NEXT, "writev");
  if (!bw_allowed(fd, bw_iov_bytes(iov, cnt))) return -1;
  return real(fd, iov, cnt);
}

static int bw_fake_free(struct statvfs *st)
{
  const char *fake = getenv("BW_FAKE_FREE");
  if (!fake) return 0;
  st->f_bavail = st->f_bfree = (fsblkcnt_t)(atoll(fake) / (long long)(st->f_frsize ? st->f_frsize : 4096));
  return 0;
}

int statvfs(const char *path, struct statvfs *st)
{
  static int (*real)(const char *, struct statvfs *);
  if (!real) real = (int (*)(const char *, struct statvfs *))dlsym(RTLD_NEXT, "statvfs");
  if (real(path, st)) return -1;
  return bw_fake_free(st);
}

int statvfs64(const char *path, struct statvfs64 *st)
{
  static int (*real)(const char *, struct statvfs64 *);
  const char *fake = getenv("BW_FAKE_FREE");
  if (!real) real = (int (*)(const char *, struct statvfs64 *))dlsym(RTLD_NEXT, "statvfs64");
  if (real(path, st)) return -1;
  if (fake) st->f_bavail = st->f_bfree = (fsblkcnt64_t)(atoll(fake) / (long long)(st->f_frsize ? st->f_frsize : 4096));
  return 0;
}
