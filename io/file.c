/* file.c -- files written atomically ("PATH.tmp", then rename: a reader
 * never sees half a file, a failed write leaves the old file), files opened
 * for writing without blocking, folders made and emptied, and the check
 * that no command writes over its own input (overwrite.c). See
 * mpgm_file.h. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_file.h"

#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ------------------------------------------------------------------------ */
/* Files opened for writing                                                 */
/* ------------------------------------------------------------------------ */

int mpgm_open_write(mpgm_ctx *ctx, const char *path, int *fd_out) {
  *fd_out = -1;
  /* O_NONBLOCK: a FIFO without a reader fails at once (ENXIO) instead of
   * waiting for one for ever */
  const int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_NONBLOCK | O_NOCTTY | O_CLOEXEC, 0666);
  if (fd < 0 && errno == ENXIO)
    MPGM_ERROR(ctx, MPGM_ERR_IO, "%s: cannot write: a pipe or FIFO that nobody reads", path);
  MPGM_CHECK(ctx, fd >= 0, MPGM_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
  const int fl = fcntl(fd, F_GETFL);
  if (fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0) {
    const int e = errno;
    close(fd);
    MPGM_ERROR(ctx, MPGM_ERR_IO, "%s: cannot write: %s", path, strerror(e));
  }
  *fd_out = fd;
  return 0;
}

int mpgm_output_regular(mpgm_ctx *ctx, const char *path) {
  struct stat st;
  if (stat(path, &st) != 0 || S_ISREG(st.st_mode)) return 0; /* absent, or a file to replace */
  MPGM_ERROR(ctx, MPGM_ERR_IO, "%s: is %s, not a regular file: no output is written there", path,
             mpgm_file_kind((unsigned)st.st_mode));
}

int mpgm_fopen_write(mpgm_ctx *ctx, const char *path, FILE **f) {
  *f = NULL;
  int fd;
  MPGM_CALL(mpgm_open_write(ctx, path, &fd));
  *f = fdopen(fd, "w");
  if (*f) return 0;
  const int e = errno;
  close(fd);
  MPGM_ERROR(ctx, MPGM_ERR_IO, "%s: cannot write: %s", path, strerror(e));
}

/* ------------------------------------------------------------------------ */
/* Atomic files                                                             */
/* ------------------------------------------------------------------------ */

enum { TMPNAME_CAP = 4096 + 8 };

/* "path.tmp" into out[TMPNAME_CAP]; 0 if the name is too long. */
static int tmp_name(const char *path, char *out) {
  size_t n = strlen(path);
  if (n + 5 > TMPNAME_CAP) return 0;
  memcpy(out, path, n);
  memcpy(out + n, ".tmp", 5);
  return 1;
}

void mpgm_atomic_discard(const char *path, void *fp_) {
  FILE *fp = fp_;
  char t[TMPNAME_CAP];
  if (fp) fclose(fp);
  if (tmp_name(path, t)) remove(t);
}

/* Open "path.tmp" for binary writing; *fp_out receives the FILE *. */
int mpgm_atomic_open(mpgm_ctx *ctx, const char *path, void **fp_out) {
  MPGM_CHECK(ctx, path && *path && fp_out, MPGM_ERR_INPUT,
             "mpgm_atomic_open: empty path or NULL output");
  *fp_out = NULL;
  char t[TMPNAME_CAP];
  MPGM_CHECK(ctx, tmp_name(path, t), MPGM_ERR_IO, "%s: %s", path,
             strerror(ENAMETOOLONG));
  /* a new file of our own: whatever stands at PATH.tmp (a temporary a
   * killed run left, a FIFO, a symbolic link to elsewhere) is removed
   * first, not opened and written through */
  if (unlink(t) != 0 && errno != ENOENT)
    MPGM_ERROR(ctx, MPGM_ERR_IO, "%s: %s", t, strerror(errno));
  const int fd = open(t, O_WRONLY | O_CREAT | O_EXCL | O_NOCTTY | O_CLOEXEC, 0666);
  MPGM_CHECK(ctx, fd >= 0, MPGM_ERR_IO, "%s: %s", path, strerror(errno));
  FILE *fp = fdopen(fd, "wb");
  if (!fp) {
    const int e = errno;
    close(fd);
    remove(t);
    MPGM_ERROR(ctx, MPGM_ERR_IO, "%s: %s", path, strerror(e));
  }
  *fp_out = fp;
  return MPGM_OK;
}

/* Flush and close the temporary, then rename it to path. On any failure the
 * temporary is removed, path is left as it was, and MPGM_ERR_IO returned. */
int mpgm_atomic_close(mpgm_ctx *ctx, const char *path, void *fp_) {
  FILE *fp = fp_;
  char t[TMPNAME_CAP];
  if (!path || !tmp_name(path, t)) {
    if (fp) fclose(fp);
    MPGM_ERROR(ctx, MPGM_ERR_INPUT, "mpgm_atomic_close: bad path");
  }
  MPGM_CHECK(ctx, fp != NULL, MPGM_ERR_INPUT, "%s: no file to close", path);
  int err = 0;
  errno = 0;
  if (fflush(fp) != 0) err = errno ? errno : EIO;
  if (!err && ferror(fp)) err = EIO; /* an earlier write failed */
  errno = 0;
  if (fclose(fp) != 0 && !err) err = errno ? errno : EIO;
  if (!err && rename(t, path) != 0) err = errno ? errno : EIO;
  if (err) remove(t);
  MPGM_CHECK(ctx, !err, MPGM_ERR_IO, "%s: %s", path, strerror(err));
  return MPGM_OK;
}

int mpgm_mkdir_p(mpgm_ctx *ctx, const char *dir) {
  char buf[MPGM_PATH_LEN + 32];
  snprintf(buf, sizeof buf, "%s", dir);
  for (char *p = buf + 1;; p++) {
    if (*p == '/' || *p == '\0') {
      const char c = *p;
      *p = '\0';
      if (mkdir(buf, 0777) != 0 && errno != EEXIST)
        MPGM_ERROR(ctx, MPGM_ERR_IO, "%s: cannot create folder: %s", buf, strerror(errno));
      struct stat st;
      if (stat(buf, &st) != 0 || !S_ISDIR(st.st_mode))
        MPGM_ERROR(ctx, MPGM_ERR_IO, "%s: exists and is not a folder", buf);
      *p = c;
      if (c == '\0') break;
    }
  }
  return 0;
}

int mpgm_remove_files(mpgm_ctx *ctx, const char *dir, const char *prefix, const char *suffix) {
  DIR *dd = opendir(dir);
  if (!dd) return 0;
  const size_t lp = strlen(prefix), ls = strlen(suffix);
  struct dirent *e;
  int err = 0;
  while (!err && (e = readdir(dd))) {
    const size_t l = strlen(e->d_name);
    if (l < lp + ls || strncmp(e->d_name, prefix, lp) != 0 || strcmp(e->d_name + l - ls, suffix) != 0)
      continue;
    char f[MPGM_PATH_LEN + 512];
    snprintf(f, sizeof f, "%s/%s", dir, e->d_name);
    if (remove(f) != 0)
      err = mpgm_err_set(ctx, MPGM_ERR_IO, __FILE__, __LINE__, "%s: cannot remove: %s", f, strerror(errno));
  }
  closedir(dd);
  return err;
}

int mpgm_write_json(mpgm_ctx *ctx, const char *path, const void *json) {
  char *text = cJSON_Print((const cJSON *)json);
  MPGM_CHECK(ctx, text, MPGM_ERR_NOMEM, "out of memory (JSON)");
  void *fv;
  int err = mpgm_atomic_open(ctx, path, &fv);
  if (!err) {
    fputs(text, (FILE *)fv);
    fputc('\n', (FILE *)fv);
    err = mpgm_atomic_close(ctx, path, fv);
  }
  free(text);
  return err;
}
