/* test_checkpoint.c -- the dimension in a checkpoint's header
 * (mpgm_checkpoint_parse): a checkpoint of this build's dimension is read,
 * one of the other build's is refused with an error that names the build
 * to restart it with, one written before the dimension was recorded (0 in
 * its header) is plane strain's, a dimension neither 2 nor 3 is refused.
 * Built in both dimensions (the 3-D build links without the problem:
 * checkpoint_read.c). The checkpoints are made here, section by section
 * (mpgm_blob_put), as checkpoint.c writes them. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_test.h"
#include "mpgm_checkpoint.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "checkpoint_impl.h"

static const char *const path = "/nowhere/checkpoint.mpgm";

/* A checkpoint whose header records dimension dim, parsed: its error code
 * (0: read), the message into msg. */
static int parse_dim(uint32_t dim, char *msg, size_t cap, long *step) {
  static const char scene[] = "{\"method\": \"mpm\"}";
  ck_header h;
  memset(&h, 0, sizeof h);
  memcpy(h.magic, "MPGMCKPT", 8);
  h.format = CK_FORMAT;
  h.order = CK_ORDER;
  h.sizes = mpgm_ck_sizes();
  h.dim = dim;
  snprintf(h.version, sizeof h.version, "%s", mpgm_version());
  h.scene_hash = mpgm_hash64(scene, strlen(scene));
  h.step = 7;
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_blob b = {0};
  int err = mpgm_blob_put(&ctx, &b, "header", &h, sizeof h);
  if (!err) err = mpgm_blob_put(&ctx, &b, "scene.file", "a.json", 7);
  if (!err) err = mpgm_blob_put(&ctx, &b, "scene.json", scene, sizeof scene);
  if (err) {
    mpgm_blob_free(&b);
    snprintf(msg, cap, "%s", ctx.msg);
    return -100;
  }
  mpgm_checkpoint ck;
  err = mpgm_checkpoint_parse(&ctx, path, b.buf, b.len, &ck); /* ck owns b.buf */
  *step = err ? -1 : ck.step;
  snprintf(msg, cap, "%s", ctx.msg);
  if (!err) mpgm_checkpoint_free(&ck);
  return err;
}

int main(void) {
  char msg[sizeof ((mpgm_ctx *)0)->msg];
  long step;
  int err = parse_dim(MPGM_DIM, msg, sizeof msg, &step);
  mpgm_test(err == 0 && step == 7, "a checkpoint of this build's dimension (%d) is read (%s)", MPGM_DIM, msg);
#if MPGM_DIM == 2
  err = parse_dim(3, msg, sizeof msg, &step);
  mpgm_test(err == MPGM_ERR_DIMENSION && strstr(msg, path) && strstr(msg, "written by a 3-D run; restart it with mpgm-3d"),
            "a 3-D checkpoint is refused: %s", msg);
  err = parse_dim(0, msg, sizeof msg, &step);
  mpgm_test(err == 0 && step == 7, "a checkpoint without a dimension (before it was recorded) is read (%s)", msg);
#else
  err = parse_dim(2, msg, sizeof msg, &step);
  mpgm_test(err == MPGM_ERR_DIMENSION && strstr(msg, path) && strstr(msg, "written by a 2-D run; restart it with mpgm"),
            "a 2-D checkpoint is refused: %s", msg);
  err = parse_dim(0, msg, sizeof msg, &step);
  mpgm_test(err == MPGM_ERR_DIMENSION && strstr(msg, "written by a 2-D run"),
            "a checkpoint without a dimension (plane strain's) is refused: %s", msg);
#endif
  err = parse_dim(7, msg, sizeof msg, &step);
  mpgm_test(err == MPGM_ERR_INPUT && strstr(msg, "section 'header': dimension 7"),
            "a dimension neither 2 nor 3 is refused: %s", msg);
  return mpgm_test_summary();
}
