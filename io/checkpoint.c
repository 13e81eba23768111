/* checkpoint.c -- DIR/checkpoint.mpgm: the state a run continues from
 * (mpgm_checkpoint.h). One file of tagged sections with their CRC-32
 * (mpgm_blob.h), written atomically (DIR/checkpoint.mpgm.tmp, then
 * rename: a run killed while it writes leaves the previous checkpoint
 * whole):
 *   header      magic, format, byte order and sizes, mpgm's version, the
 *               scene's hash, the step
 *   scene.file  the scene file the run was started with
 *   scene.json  its resolved scene (what --restart runs)
 *   ...         the problem (mpgm_problem_save), the output
 *               (mpgm_output_save), the run's step cuts */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_checkpoint.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "mpgm_file.h"

/* 1: sections of tag and length; 2: and a CRC-32 of each */
#define CK_FORMAT 2u
#define CK_ORDER 0x01020304u

typedef struct ck_header {
  char magic[8];       /* "MPGMCKPT" */
  uint32_t format;     /* CK_FORMAT */
  uint32_t order;      /* CK_ORDER as this machine stores it */
  uint32_t sizes;      /* sizeof double | long << 8 | int << 16 | pointer << 24 */
  uint32_t pad;
  char version[64];    /* mpgm_version() */
  uint64_t scene_hash; /* mpgm_hash64 of scene.json */
  int64_t step;        /* steps done */
} ck_header;

static uint32_t sizes(void) {
  return (uint32_t)(sizeof(double) | sizeof(long) << 8 | sizeof(int) << 16 | sizeof(void *) << 24);
}

void mpgm_checkpoint_path(const char *dir, char *path, size_t n) {
  snprintf(path, n, "%s/checkpoint.mpgm", dir);
}

/* The run's step cuts so far (summary.json lists them). */
static int cuts_save(mpgm_ctx *ctx, mpgm_blob *b, const mpgm_run_result *res) {
  MPGM_CALL(mpgm_blob_put(ctx, b, "run.ncuts", &res->ncuts, sizeof res->ncuts));
  return mpgm_blob_put(ctx, b, "run.cuts", res->cuts, sizeof(mpgm_cut) * (size_t)res->ncuts);
}

/* The cuts read back: each of a step done by then, in order, with finite
 * times, a recoverable code and its message a string. */
static int cuts_restore(mpgm_ctx *ctx, mpgm_blob *b, long step, mpgm_run_result *res) {
  int n;
  MPGM_CALL(mpgm_blob_get(ctx, b, "run.ncuts", &n, sizeof n));
  MPGM_CHECK(ctx, n >= 0 && n <= MPGM_CUTS_MAX, MPGM_ERR_INPUT,
             "checkpoint: section 'run.ncuts': %d step cuts (0 to %d)", n, MPGM_CUTS_MAX);
  memset(res, 0, sizeof *res);
  res->failed_step = -1;
  if (n) {
    res->cuts = calloc(MPGM_CUTS_MAX, sizeof *res->cuts);
    MPGM_CHECK(ctx, res->cuts, MPGM_ERR_NOMEM, "out of memory (checkpoint)");
  }
  res->ncuts = n;
  MPGM_CALL(mpgm_blob_get(ctx, b, "run.cuts", res->cuts, sizeof(mpgm_cut) * (size_t)n));
  for (int i = 0; i < n; i++) {
    const mpgm_cut *c = &res->cuts[i];
    MPGM_CHECK(ctx,
               c->step >= 1 && c->step <= step && (i == 0 || c->step >= c[-1].step) &&
                   isfinite(c->t) && isfinite(c->dt) && c->dt > 0.0 && c->code > 0 &&
                   memchr(c->reason, '\0', sizeof c->reason),
               MPGM_ERR_INPUT,
               "checkpoint: section 'run.cuts': cut %d (of step %ld at %g, step "
               "%g, code %d) is not one of a run at step %ld",
               i, c->step, c->t, c->dt, c->code, step);
  }
  return 0;
}

/* The whole checkpoint into b. */
static int build(mpgm_ctx *ctx, mpgm_blob *b, const mpgm_problem *pb, const mpgm_output *o,
                 const mpgm_run_result *res, const char *scene_json) {
  const mpgm_scene *s = mpgm_problem_scene(pb);
  mpgm_report r;
  mpgm_problem_report(pb, &r);
  ck_header h;
  memset(&h, 0, sizeof h);
  memcpy(h.magic, "MPGMCKPT", 8);
  h.format = CK_FORMAT;
  h.order = CK_ORDER;
  h.sizes = sizes();
  snprintf(h.version, sizeof h.version, "%s", mpgm_version());
  h.scene_hash = mpgm_hash64(scene_json, strlen(scene_json));
  h.step = r.step;
  MPGM_CALL(mpgm_blob_put(ctx, b, "header", &h, sizeof h));
  MPGM_CALL(mpgm_blob_put(ctx, b, "scene.file", s->file, strlen(s->file) + 1));
  MPGM_CALL(mpgm_blob_put(ctx, b, "scene.json", scene_json, strlen(scene_json) + 1));
  MPGM_CALL(mpgm_problem_save(pb, b));
  MPGM_CALL(mpgm_output_save(o, ctx, b));
  return cuts_save(ctx, b, res);
}

int mpgm_checkpoint_write(mpgm_ctx *ctx, const char *dir, const mpgm_problem *pb,
                          const mpgm_output *o, const mpgm_run_result *res) {
  char *scene_json = mpgm_scene_resolved_json(mpgm_problem_scene(pb));
  MPGM_CHECK(ctx, scene_json, MPGM_ERR_NOMEM, "out of memory (checkpoint)");
  mpgm_blob b = {0};
  int err = build(ctx, &b, pb, o, res, scene_json);
  free(scene_json);
  char path[MPGM_PATH_LEN + 32];
  mpgm_checkpoint_path(dir, path, sizeof path);
  void *fv = NULL;
  if (!err) err = mpgm_atomic_open(ctx, path, &fv);
  if (!err) {
    FILE *f = fv;
    if (fwrite(b.buf, 1, b.len, f) != b.len) {
      const int e = errno;
      mpgm_atomic_discard(path, f);
      err = mpgm_err_set(ctx, MPGM_ERR_IO, __FILE__, __LINE__, "%s: %s", path, strerror(e ? e : EIO));
    } else {
      /* on disk before it replaces the last one: a crash of the machine
       * leaves one whole checkpoint, old or new */
      fflush(f);
      fsync(fileno(f));
      err = mpgm_atomic_close(ctx, path, f);
    }
  }
  mpgm_blob_free(&b);
  return err;
}

/* An error a layer recorded as "checkpoint: WHY", as "PATH: WHY". */
static int named(mpgm_ctx *ctx, const char *path, int err) {
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

/* The header, once the file is known whole: this machine, this mpgm. */
static int check_header(mpgm_ctx *ctx, const char *path, mpgm_checkpoint *ck) {
  ck_header h;
  MPGM_CALL(mpgm_blob_get(ctx, &ck->blob, "header", &h, sizeof h));
  char version[sizeof h.version];
  text_of((const unsigned char *)h.version, sizeof version, version);
  MPGM_CHECK(ctx, h.order == CK_ORDER && h.sizes == sizes(), MPGM_ERR_INPUT,
             "%s: written on a machine of another byte order or word size", path);
  MPGM_CHECK(ctx, h.format == CK_FORMAT && strcmp(version, mpgm_version()) == 0, MPGM_ERR_INPUT,
             "%s: written by mpgm %s (checkpoint format %u); this is mpgm %s (format %u): a "
             "checkpoint continues only with the mpgm that wrote it",
             path, version, h.format, mpgm_version(), CK_FORMAT);
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
  if (!err) err = named(ctx, ck->path, mpgm_blob_verify(ctx, &ck->blob));
  if (!err) err = check_header(ctx, ck->path, ck);
  if (!err) err = get_string(ctx, &ck->blob, "scene.file", &ck->file);
  if (!err) err = get_string(ctx, &ck->blob, "scene.json", &ck->scene_json);
  if (!err && mpgm_hash64(ck->scene_json, strlen(ck->scene_json)) != ck->scene_hash)
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                       "%s: damaged (the scene does not "
                       "match its hash)",
                       ck->path);
  if (err) mpgm_checkpoint_free(ck);
  return named(ctx, ck->path, err);
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

int mpgm_checkpoint_restore(mpgm_ctx *ctx, mpgm_checkpoint *ck, mpgm_problem *pb, mpgm_output *o,
                            const char *dir, mpgm_run_result *res) {
  int err = mpgm_problem_restore(pb, &ck->blob);
  mpgm_report r;
  mpgm_problem_report(pb, &r);
  if (!err && r.step != ck->step)
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                       "checkpoint: section 'core': "
                       "step %ld; section 'header' says %ld",
                       r.step, ck->step);
  if (!err) err = mpgm_output_restore(ctx, o, pb, dir, &ck->blob);
  if (!err) err = cuts_restore(ctx, &ck->blob, ck->step, res);
  if (!err && ck->blob.pos != ck->blob.len)
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                       "checkpoint: section '%s' after "
                       "the last one this scene reads (another layout)",
                       (const char *)ck->blob.buf + ck->blob.pos);
  return named(ctx, ck->path, err);
}

void mpgm_checkpoint_free(mpgm_checkpoint *ck) {
  mpgm_blob_free(&ck->blob);
  free(ck->file);
  free(ck->scene_json);
  ck->file = ck->scene_json = NULL;
}
