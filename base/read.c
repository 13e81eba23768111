/* read.c -- files opened for reading: regular files only, sizes bounded
 * (mpgm_base.h). Every reader of mpgm opens its input here, so the rule is
 * one piece of code: a FIFO or pipe would block the first read (or the open
 * itself) for ever, a device such as /dev/zero never ends, opening a device
 * can have effects of its own (a tape rewinds, a watchdog starts), and a
 * folder or a socket holds no content; all of these are refused, naming the
 * file and its kind, before anything could block. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_base.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

const char *mpgm_file_kind(unsigned mode) {
  return S_ISREG(mode)    ? "a regular file"
         : S_ISDIR(mode)  ? "a folder"
         : S_ISFIFO(mode) ? "a pipe or FIFO"
         : S_ISSOCK(mode) ? "a socket"
         : S_ISCHR(mode)  ? "a character device"
         : S_ISBLK(mode)  ? "a block device"
                          : "not a file of a known kind";
}

/* "64 MiB" (a whole power of two of KiB, MiB, GiB), else "N bytes". */
static void size_text(size_t n, char *buf, size_t cap) {
  static const char *const unit[] = {"GiB", "MiB", "KiB"};
  for (int k = 0; k < 3; k++) {
    const size_t u = (size_t)1 << (10 * (3 - k));
    if (n >= u && n % u == 0) {
      snprintf(buf, cap, "%zu %s", n / u, unit[k]);
      return;
    }
  }
  snprintf(buf, cap, "%zu bytes", n);
}

int mpgm_err_too_large(mpgm_ctx *ctx, const char *path, size_t max) {
  char m[48];
  size_text(max, m, sizeof m);
  MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: larger than %s, the most this file may have", path, m);
}

/* Refuse st unless it is a regular file of at most max bytes. */
static int check_stat(mpgm_ctx *ctx, const char *path, const struct stat *st, size_t max) {
  MPGM_CHECK(ctx, S_ISREG(st->st_mode), MPGM_ERR_INPUT, "%s: is %s, not a regular file", path,
             mpgm_file_kind((unsigned)st->st_mode));
  if (st->st_size > 0 && (unsigned long long)st->st_size > (unsigned long long)max)
    return mpgm_err_too_large(ctx, path, max);
  return 0;
}

int mpgm_open_regular(mpgm_ctx *ctx, const char *path, size_t max, int *fd_out, size_t *size) {
  *fd_out = -1;
  if (size) *size = 0;
  if (max > MPGM_READ_MAX) max = MPGM_READ_MAX;
  /* the name first (stat follows symbolic links): a device or a FIFO is
   * refused without being opened */
  struct stat st;
  if (stat(path, &st) == 0) MPGM_CALL(check_stat(ctx, path, &st, max));
  /* O_NONBLOCK: should the name have been replaced by a FIFO since, the
   * open does not wait for a writer */
  const int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  MPGM_CHECK(ctx, fd >= 0, MPGM_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  /* what was opened, whatever the name pointed to a moment before */
  int err = fstat(fd, &st) != 0
                ? mpgm_err_set(ctx, MPGM_ERR_IO, __FILE__, __LINE__, "%s: cannot open: %s", path,
                               strerror(errno))
                : check_stat(ctx, path, &st, max);
  const int fl = err ? 0 : fcntl(fd, F_GETFL);
  if (!err && (fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0))
    err = mpgm_err_set(ctx, MPGM_ERR_IO, __FILE__, __LINE__, "%s: cannot open: %s", path,
                       strerror(errno));
  if (err) {
    close(fd);
    return err;
  }
  *fd_out = fd;
  if (size) *size = st.st_size > 0 ? (size_t)st.st_size : 0;
  return 0;
}

int mpgm_fopen_regular(mpgm_ctx *ctx, const char *path, size_t max, FILE **f, size_t *size) {
  *f = NULL;
  int fd;
  MPGM_CALL(mpgm_open_regular(ctx, path, max, &fd, size));
  *f = fdopen(fd, "r");
  if (*f) return 0;
  const int e = errno;
  close(fd);
  MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "%s: cannot open: %s", path, strerror(e));
}

/* Read fd to its end into buf (cap bytes, growing), at most max + 1 bytes:
 * one more than allowed tells a file that grew past its bound. */
static int read_all(mpgm_ctx *ctx, const char *path, int fd, size_t max, char **buf, size_t *cap,
                    size_t *n) {
  for (;;) {
    if (*n + 1 >= *cap) {
      const size_t want = *cap < (max + 2) / 2 ? 2 * *cap : max + 2;
      char *nb = want > *cap ? realloc(*buf, want) : NULL;
      MPGM_CHECK(ctx, nb, MPGM_ERR_NOMEM, "%s: out of memory (%zu bytes)", path, want);
      *buf = nb;
      *cap = want;
    }
    const ssize_t k = read(fd, *buf + *n, *cap - *n - 1);
    if (k < 0 && errno == EINTR) continue;
    MPGM_CHECK(ctx, k >= 0, MPGM_ERR_IO, "%s: read error: %s", path, strerror(errno));
    if (k == 0) return 0;
    *n += (size_t)k;
    if (*n > max) return mpgm_err_too_large(ctx, path, max);
  }
}

int mpgm_read_file(mpgm_ctx *ctx, const char *path, size_t max, char **text, size_t *len) {
  *text = NULL;
  if (len) *len = 0;
  if (max > MPGM_READ_MAX) max = MPGM_READ_MAX;
  int fd;
  size_t size;
  MPGM_CALL(mpgm_open_regular(ctx, path, max, &fd, &size));
  /* the size the file has now, and room to see that it ends there (a file
   * of /proc says 0 and is read the same) */
  size_t cap = (size < 4096 ? 4096 : size + 2), n = 0;
  if (cap > max + 2) cap = max + 2;
  char *buf = malloc(cap);
  int err = buf ? read_all(ctx, path, fd, max, &buf, &cap, &n)
                : mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "%s: out of memory (%zu bytes)",
                               path, cap);
  close(fd);
  if (err) {
    free(buf);
    return err;
  }
  buf[n] = '\0';
  *text = buf;
  if (len) *len = n;
  return 0;
}

int mpgm_ends_with(const char *name, const char *suffix) {
  const size_t n = strlen(name), k = strlen(suffix);
  return n > k && strcmp(name + n - k, suffix) == 0;
}

int mpgm_path_below(const char *path) {
  if (!path[0] || path[0] == '/' || path[0] == '~') return 0;
  for (const char *p = path; *p;) {
    const size_t n = strcspn(p, "/");
    if (n == 2 && p[0] == '.' && p[1] == '.') return 0;
    p += n + (p[n] == '/');
  }
  return 1;
}
