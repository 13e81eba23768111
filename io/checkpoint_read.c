/* checkpoint_read.c -- DIR/checkpoint.mpgm read back and checked whole
 * before anything is restored from it (mpgm_checkpoint.h): every section
 * whole, its header of this machine, this mpgm and this build's dimension,
 * its scene matching its hash. Apart from checkpoint.c (the writing and the
 * restoring, which need the problem) so that the checks link without it. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_checkpoint.h"

#include <errno.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "checkpoint_impl.h"
#include "mpgm_file.h"

void mpgm_checkpoint_path(const char *dir, char *path, size_t n) {
  snprintf(path, n, "%s/checkpoint.mpgm", dir);
}

/* See checkpoint_impl.h. */
int mpgm_ck_named(mpgm_ctx *ctx, const char *path, int err) {
  if (!err || !ctx->msg[0] || strncmp(ctx->msg, path, strlen(path)) == 0) return err;
  char msg[sizeof ctx->msg];
  snprintf(msg, sizeof msg, "%s", ctx->msg);
  const int code = ctx->code ? ctx->code : err;
  mpgm_err_clear(ctx);
  const char *why = strncmp(msg, "checkpoint: ", 12) == 0 ? msg + 12 : msg;
  return mpgm_err_set(ctx, code, __FILE__, __LINE__, "%s: %s", path, why);
}

/* n bytes of text from a file as a string for a message (non-printable
 * bytes as '?'). */
static void text_of(const unsigned char *p, size_t n, char *out) {
  size_t i = 0;
  for (; i + 1 < n && p[i]; i++) out[i] = p[i] >= 0x20 && p[i] < 0x7f ? (char)p[i] : '?';
  out[i] = '\0';
}

static uint32_t swapped(uint32_t x) {
  return x >> 24 | (x >> 8 & 0xff00u) | (x << 8 & 0xff0000u) | x << 24;
}

/* The first bytes: a checkpoint of this format and byte order, or refused
 * at once (a file of another format would only read as damaged). */
static int sniff(mpgm_ctx *ctx, const char *path, const unsigned char *p, size_t len) {
  MPGM_CHECK(ctx, len > 0, MPGM_ERR_INPUT, "%s: not an mpgm checkpoint (an empty file)", path);
  const int tagged = len >= 7 && memcmp(p, "header", 7) == 0;
  /* format 1 had no CRC: its header's data began 4 bytes earlier */
  const size_t v1 = MPGM_BLOB_TAG + 8;
  if (tagged && len >= v1 + sizeof(ck_header) && memcmp(p + v1, "MPGMCKPT", 8) == 0) {
    uint32_t format;
    char version[64];
    memcpy(&format, p + v1 + 8, sizeof format);
    text_of(p + v1 + offsetof(ck_header, version), sizeof version, version);
    MPGM_ERROR(ctx, MPGM_ERR_INPUT,
               "%s: written by mpgm %s (checkpoint format %u); this is mpgm "
               "%s (format %u): a checkpoint continues only with the mpgm that wrote it",
               path, version, format, mpgm_version(), CK_FORMAT);
  }
  MPGM_CHECK(ctx,
             tagged && len >= MPGM_BLOB_HEAD + sizeof(ck_header) &&
                 memcmp(p + MPGM_BLOB_HEAD, "MPGMCKPT", 8) == 0,
             MPGM_ERR_INPUT, "%s: not an mpgm checkpoint", path);
  ck_header h;
  memcpy(&h, p + MPGM_BLOB_HEAD, sizeof h);
  MPGM_CHECK(ctx, h.order != swapped(CK_ORDER), MPGM_ERR_INPUT,
             "%s: written on a machine of another byte order", path);
  return 0;
}

/* The header, once the file is known whole: this machine, this mpgm, this
 * build's dimension. */
static int check_header(mpgm_ctx *ctx, const char *path, mpgm_checkpoint *ck) {
  ck_header h;
  MPGM_CALL(mpgm_blob_get(ctx, &ck->blob, "header", &h, sizeof h));
  char version[sizeof h.version];
  text_of((const unsigned char *)h.version, sizeof version, version);
  MPGM_CHECK(ctx, h.order == CK_ORDER && h.sizes == mpgm_ck_sizes(), MPGM_ERR_INPUT,
             "%s: written on a machine of another byte order or word size", path);
  MPGM_CHECK(ctx, h.format == CK_FORMAT && strcmp(version, mpgm_version()) == 0, MPGM_ERR_INPUT,
             "%s: written by mpgm %s (checkpoint format %u); this is mpgm %s (format %u): a "
             "checkpoint continues only with the mpgm that wrote it",
             path, version, h.format, mpgm_version(), CK_FORMAT);
  /* one build's state is not the other's (2-D and 3-D points, nodes and
   * stresses differ in size); 0: written before the dimension was
   * recorded, by plane strain, the only build then */
  const uint32_t dim = h.dim ? h.dim : 2;
  MPGM_CHECK(ctx, dim == 2 || dim == 3, MPGM_ERR_INPUT, "%s: section 'header': dimension %u", path,
             (unsigned)h.dim);
  /* MPGM_ERR_DIMENSION: mpgm hands a 3-D checkpoint's restart to mpgm-3d */
  MPGM_CHECK(ctx, dim == MPGM_DIM, MPGM_ERR_DIMENSION, "%s: written by a %u-D run; restart it with %s",
             path, (unsigned)dim, dim == 3 ? "mpgm-3d" : "mpgm (the plane-strain build)");
  MPGM_CHECK(ctx, h.step >= 0, MPGM_ERR_INPUT, "%s: section 'header': step %lld", path,
             (long long)h.step);
  ck->step = (long)h.step;
  ck->scene_hash = h.scene_hash;
  return 0;
}

/* A string section (NUL-terminated within it) into a new allocation. */
static int get_string(mpgm_ctx *ctx, mpgm_blob *b, const char *tag, char **out) {
  size_t n;
  MPGM_CALL(mpgm_blob_peek(ctx, b, tag, &n));
  MPGM_CHECK(ctx, n > 0, MPGM_ERR_INPUT, "checkpoint: empty section '%s'", tag);
  char *s = malloc(n);
  MPGM_CHECK(ctx, s, MPGM_ERR_NOMEM, "out of memory (checkpoint)");
  const int err = mpgm_blob_get(ctx, b, tag, s, n);
  if (!err && (s[n - 1] != '\0' || strlen(s) != n - 1)) {
    free(s);
    MPGM_ERROR(ctx, MPGM_ERR_INPUT, "checkpoint: section '%s' is not a string", tag);
  }
  if (err) free(s);
  else *out = s;
  return err;
}

int mpgm_checkpoint_parse(mpgm_ctx *ctx, const char *path, unsigned char *buf, size_t len,
                          mpgm_checkpoint *ck) {
  memset(ck, 0, sizeof *ck);
  snprintf(ck->path, sizeof ck->path, "%s", path);
  ck->blob.buf = buf;
  ck->blob.len = ck->blob.cap = len;
  /* every section whole before any is read: a damaged file is refused
   * whole, naming the first section that is wrong */
  int err = sniff(ctx, ck->path, buf, len);
  if (!err) err = mpgm_ck_named(ctx, ck->path, mpgm_blob_verify(ctx, &ck->blob));
  if (!err) err = check_header(ctx, ck->path, ck);
  if (!err) err = get_string(ctx, &ck->blob, "scene.file", &ck->file);
  if (!err) err = get_string(ctx, &ck->blob, "scene.json", &ck->scene_json);
  if (!err && mpgm_hash64(ck->scene_json, strlen(ck->scene_json)) != ck->scene_hash)
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                       "%s: damaged (the scene does not "
                       "match its hash)",
                       ck->path);
  if (err) mpgm_checkpoint_free(ck);
  return mpgm_ck_named(ctx, ck->path, err);
}

int mpgm_checkpoint_read(mpgm_ctx *ctx, const char *dir, mpgm_checkpoint *ck) {
  memset(ck, 0, sizeof *ck);
  char path[sizeof ck->path];
  mpgm_checkpoint_path(dir, path, sizeof path);
  struct stat st;
  MPGM_CHECK(ctx, stat(dir, &st) == 0 && S_ISDIR(st.st_mode), MPGM_ERR_INPUT,
             "--restart %s: no such folder", dir);
  const int there = stat(path, &st) == 0;
  MPGM_CHECK(ctx, there || errno != ENOENT, MPGM_ERR_INPUT,
             "--restart %s: the folder holds no checkpoint.mpgm (a run writes one every "
             "output.checkpoint_every steps, that key is 0, none, by default, and when a signal "
             "stops it)",
             dir);
  char *buf;
  size_t len;
  /* a FIFO, device or folder is refused by its name, never opened
   * (mpgm_read_file) */
  MPGM_CALL(mpgm_read_file(ctx, path, SIZE_MAX - 1, &buf, &len));
  return mpgm_checkpoint_parse(ctx, path, (unsigned char *)buf, len, ck);
}

void mpgm_checkpoint_free(mpgm_checkpoint *ck) {
  mpgm_blob_free(&ck->blob);
  free(ck->file);
  free(ck->scene_json);
  ck->file = ck->scene_json = NULL;
}
