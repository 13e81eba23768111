/* checkpoint.c -- DIR/checkpoint.mpgm: the state a run continues from
 * (mpgm_checkpoint.h). One file of tagged sections with their CRC-32
 * (mpgm_blob.h), written atomically (DIR/checkpoint.mpgm.tmp, then
 * rename: a run killed while it writes leaves the previous checkpoint
 * whole):
 *   header      magic, format, byte order and sizes, mpgm's version, the
 *               scene's hash, the step, the dimension of the build
 *   scene.file  the scene file the run was started with
 *   scene.json  its resolved scene (what --restart runs)
 *   ...         the problem (mpgm_problem_save), the output
 *               (mpgm_output_save), the run's step cuts
 * Reading it back and checking it whole: checkpoint_read.c. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_checkpoint.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "checkpoint_impl.h"
#include "mpgm_file.h"

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
  h.sizes = mpgm_ck_sizes();
  h.dim = MPGM_DIM;
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

int mpgm_checkpoint_restore(mpgm_ctx *ctx, mpgm_checkpoint *ck, mpgm_problem *pb, mpgm_output *o,
                            const char *dir, mpgm_run_result *res) {
  int err = mpgm_problem_restore(pb, &ck->blob);
  if (err) return mpgm_ck_named(ctx, ck->path, err); /* a problem half restored is not reported on */
  mpgm_report r;
  mpgm_problem_report(pb, &r);
  if (r.step != ck->step)
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
  return mpgm_ck_named(ctx, ck->path, err);
}

