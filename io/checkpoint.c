/* checkpoint.c -- DIR/checkpoint.mpgm: the state a run continues from
 * (mpgm_checkpoint.h). One file of tagged sections (mpgm_blob.h), written
 * atomically (DIR/checkpoint.mpgm.tmp, then rename: a run killed while it
 * writes leaves the previous checkpoint whole):
 *   header      magic, format, byte order and sizes, mpgm's version, the
 *               scene's hash, the step
 *   scene.file  the scene file the run was started with
 *   scene.json  its resolved scene (what --restart runs)
 *   ...         the problem (mpgm_problem_save), the output
 *               (mpgm_output_save), the run's step cuts */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_checkpoint.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "mpgm_file.h"

#define CK_FORMAT 1u
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

static int cuts_restore(mpgm_ctx *ctx, mpgm_blob *b, mpgm_run_result *res) {
  int n;
  MPGM_CALL(mpgm_blob_get(ctx, b, "run.ncuts", &n, sizeof n));
  MPGM_CHECK(ctx, n >= 0 && n <= MPGM_CUTS_MAX, MPGM_ERR_INPUT, "checkpoint: %d step cuts", n);
  memset(res, 0, sizeof *res);
  res->failed_step = -1;
  if (n) {
    res->cuts = calloc(MPGM_CUTS_MAX, sizeof *res->cuts);
    MPGM_CHECK(ctx, res->cuts, MPGM_ERR_NOMEM, "out of memory (checkpoint)");
  }
  res->ncuts = n;
  return mpgm_blob_get(ctx, b, "run.cuts", res->cuts, sizeof(mpgm_cut) * (size_t)n);
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

/* The header of the checkpoint at path, checked against this mpgm. */
static int check_header(mpgm_ctx *ctx, const char *path, mpgm_checkpoint *ck) {
  ck_header h;
  size_t n;
  MPGM_CHECK(ctx, ck->blob.len >= 8 && memcmp(ck->blob.buf, "header", 6) == 0 &&
                      mpgm_blob_peek(ctx, &ck->blob, "header", &n) == 0 && n == sizeof h,
             MPGM_ERR_INPUT, "%s: not an mpgm checkpoint", path);
  MPGM_CALL(mpgm_blob_get(ctx, &ck->blob, "header", &h, sizeof h));
  h.version[sizeof h.version - 1] = '\0';
  MPGM_CHECK(ctx, memcmp(h.magic, "MPGMCKPT", 8) == 0, MPGM_ERR_INPUT, "%s: not an mpgm checkpoint",
             path);
  MPGM_CHECK(ctx, h.order == CK_ORDER && h.sizes == sizes(), MPGM_ERR_INPUT,
             "%s: written on a machine of another byte order or word size", path);
  MPGM_CHECK(ctx, h.format == CK_FORMAT && strcmp(h.version, mpgm_version()) == 0, MPGM_ERR_INPUT,
             "%s: written by mpgm %s (checkpoint format %u); this is mpgm %s (format %u): a "
             "checkpoint continues only with the mpgm that wrote it", path, h.version, h.format,
             mpgm_version(), CK_FORMAT);
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
  if (!err && s[n - 1] != '\0') {
    free(s);
    MPGM_ERROR(ctx, MPGM_ERR_INPUT, "checkpoint: section '%s' is not a string", tag);
  }
  if (err) free(s);
  else *out = s;
  return err;
}

int mpgm_checkpoint_read(mpgm_ctx *ctx, const char *dir, mpgm_checkpoint *ck) {
  memset(ck, 0, sizeof *ck);
  mpgm_checkpoint_path(dir, ck->path, sizeof ck->path);
  struct stat st;
  MPGM_CHECK(ctx, stat(dir, &st) == 0 && S_ISDIR(st.st_mode), MPGM_ERR_INPUT,
             "--restart %s: no such folder", dir);
  MPGM_CHECK(ctx, stat(ck->path, &st) == 0 || errno != ENOENT, MPGM_ERR_INPUT,
             "--restart %s: the folder holds no checkpoint.mpgm (a run writes one every "
             "output.checkpoint_every steps, that key is 0, none, by default, and when a signal "
             "stops it)", dir);
  char *buf;
  size_t len;
  MPGM_CALL(mpgm_read_file(ctx, ck->path, SIZE_MAX - 1, &buf, &len));
  ck->blob.buf = (unsigned char *)buf;
  ck->blob.len = ck->blob.cap = len;
  int err = check_header(ctx, ck->path, ck);
  if (!err) err = get_string(ctx, &ck->blob, "scene.file", &ck->file);
  if (!err) err = get_string(ctx, &ck->blob, "scene.json", &ck->scene_json);
  if (!err && mpgm_hash64(ck->scene_json, strlen(ck->scene_json)) != ck->scene_hash)
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: damaged (the scene does not "
                       "match its hash)", ck->path);
  if (err) mpgm_checkpoint_free(ck);
  return err;
}

int mpgm_checkpoint_restore(mpgm_ctx *ctx, mpgm_checkpoint *ck, mpgm_problem *pb, mpgm_output *o,
                            const char *dir, mpgm_run_result *res) {
  int err = mpgm_problem_restore(pb, &ck->blob);
  if (!err) err = mpgm_output_resume(ctx, o, pb, dir, &ck->blob);
  if (!err) err = cuts_restore(ctx, &ck->blob, res);
  if (!err && ck->blob.pos != ck->blob.len)
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: %zu bytes after the last "
                       "section (another layout)", ck->path, ck->blob.len - ck->blob.pos);
  if (err && ctx->msg[0] && strncmp(ctx->msg, ck->path, strlen(ck->path)) != 0) {
    char msg[sizeof ctx->msg];
    snprintf(msg, sizeof msg, "%s", ctx->msg);
    const int code = ctx->code;
    mpgm_err_clear(ctx);
    const char *why = strncmp(msg, "checkpoint: ", 12) == 0 ? msg + 12 : msg;
    mpgm_err_set(ctx, code, __FILE__, __LINE__, "%s: %s", ck->path, why);
  }
  return err;
}

void mpgm_checkpoint_free(mpgm_checkpoint *ck) {
  mpgm_blob_free(&ck->blob);
  free(ck->file);
  free(ck->scene_json);
  ck->file = ck->scene_json = NULL;
}
