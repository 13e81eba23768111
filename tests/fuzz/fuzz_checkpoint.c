/* fuzz_checkpoint.c -- libFuzzer target over the checkpoint reader: the
 * whole-file check (sections, lengths, CRC-32s, the header, the scene and
 * its hash; mpgm_checkpoint_parse), the scene the checkpoint holds, and the
 * full restore into a problem of that scene (mpgm_checkpoint_restore: the
 * core's arrays and scalars, the front end's and the solver's state, the
 * output's histories and .pvd entries, the step cuts), every count and
 * index checked against the problem.
 *
 * Input: one flag byte, then the bytes of a checkpoint.mpgm. A CRC stops
 * almost every mutation at the first section it touches, so for 7 inputs
 * of 8 (flag % 8 != 0) the target mends the file first, the way a crafted
 * file would be made: it writes this mpgm's version into the header (a
 * corpus outlives the commit that wrote it) and recomputes the CRC of every
 * section up to the first whose length runs past the end; mutations of
 * counts and indices then reach the checks of what the sections hold. The
 * other inputs go through as they are, so that the CRC check is fuzzed too.
 * The scene's own hash is not mended: a mutated scene is refused there, and
 * problems are made only of the seeds' scenes (scripts/fuzz makes the seeds
 * by running small scenes of every front end with output.checkpoint_every).
 * With MPGM_FUZZ_STEPS set in the environment (30 times slower: not what
 * scripts/fuzz runs), a restore that succeeds goes on for one step when
 * the flag has bits 0x70: what a step indexes with the values restored
 * (points against the grid, equation numbers, lists of nodes) must have
 * been checked, or end in a clean failure of the step.
 *
 * A problem is made once per scene and kept (making one costs far more
 * than a restore); every check of a restore is against the scene and what
 * the same restore read, not against what an earlier input left, so a
 * problem that has been restored into serves the next input as a new one
 * would. The results folder named to the restore is never created: the
 * restore writes nothing (it aborts if anything appears in the working
 * folder, a fresh temporary one the target moves to at its start, so that
 * nothing is ever written into the source tree).
 *
 * Besides crashes, leaks and undefined behaviour (ASan, UBSan), it aborts
 * when a refusal leaves no message in the context, or when a message of a
 * refused checkpoint does not name the file.
 *
 * Build and run: scripts/fuzz (docs/architecture.md, section Tests). */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include "mpgm_checkpoint.h"
#include "mpgm_scene_io.h"

#define PATH       "fuzz/checkpoint.mpgm"
#define MAX_SCENES 16
/* the header section's data (io/checkpoint.c, ck_header): magic 8 bytes,
 * format, byte order, sizes and padding 4 each, then the version (64) */
#define AT_VERSION  24
#define VERSION_LEN 64

static void fail(const char *what, const char *msg) {
  fprintf(stderr, "fuzz_checkpoint: %s\n--- message:\n%s\n", what, msg ? msg : "");
  abort();
}

/* MPGM_FUZZ_VERBOSE set: each input's outcome on stderr (to replay one). */
static void say(const char *what, const char *msg) {
  if (getenv("MPGM_FUZZ_VERBOSE")) fprintf(stderr, "fuzz_checkpoint: %s: %s\n", what, msg);
}

/* A new temporary folder, kept empty: the results folder named to every
 * restore is in it (and never made: the restore writes nothing). */
static char tmpdir[64], outdir[80];
static int steps; /* MPGM_FUZZ_STEPS */

static void remove_tmpdir(void) {
  rmdir(tmpdir);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc;
  (void)argv;
  snprintf(tmpdir, sizeof tmpdir, "/tmp/mpgm-fuzz-checkpoint-XXXXXX");
  if (!mkdtemp(tmpdir)) fail("no temporary folder", tmpdir);
  atexit(remove_tmpdir);
  snprintf(outdir, sizeof outdir, "%s/out", tmpdir);
  steps = getenv("MPGM_FUZZ_STEPS") != NULL;
  return 0;
}

static void still_empty(void) {
  DIR *d = opendir(tmpdir);
  if (!d) fail("the temporary folder is gone", tmpdir);
  struct dirent *e;
  while ((e = readdir(d)))
    if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) fail("the restore wrote into", outdir);
  closedir(d);
}

/* This mpgm's version into the header, and every section's CRC made good
 * (sections as base/mpgm_blob.h lays them out). */
static void mend(unsigned char *buf, size_t len) {
  size_t at = 0;
  for (int k = 0; at + MPGM_BLOB_HEAD <= len; k++) {
    uint64_t n;
    memcpy(&n, buf + at + MPGM_BLOB_TAG, sizeof n);
    if (n > len - at - MPGM_BLOB_HEAD) return;
    if (k == 0 && memcmp(buf, "header", 7) == 0 && n >= AT_VERSION + VERSION_LEN) {
      char *v = (char *)buf + at + MPGM_BLOB_HEAD + AT_VERSION;
      memset(v, 0, VERSION_LEN);
      snprintf(v, VERSION_LEN, "%s", mpgm_version());
    }
    uLong c = crc32_z(0, buf + at, MPGM_BLOB_TAG + 8);
    const uint32_t crc = (uint32_t)crc32_z(c, buf + at + MPGM_BLOB_HEAD, (size_t)n);
    memcpy(buf + at + MPGM_BLOB_TAG + 8, &crc, sizeof crc);
    at += MPGM_BLOB_HEAD + (size_t)n;
  }
}

/* The problems of the scenes seen, by the checkpoint's scene hash. */
static struct {
  unsigned long long hash;
  mpgm_scene *scene;
  mpgm_ctx *ctx; /* the problem's, as long as it lives */
  mpgm_problem *pb;
} made[MAX_SCENES];
static int nmade;

static int problem_of(const mpgm_checkpoint *ck) {
  for (int i = 0; i < nmade; i++)
    if (made[i].hash == ck->scene_hash) return i;
  if (nmade == MAX_SCENES) return -1;
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene *s = NULL;
  if (mpgm_scene_load_text(&ctx, ck->file, ck->scene_json, strlen(ck->scene_json), 0, NULL, &s)) {
    if (!ctx.msg[0]) fail("a checkpoint's scene refused without a message", NULL);
    return -1;
  }
  mpgm_ctx *pctx = malloc(sizeof *pctx);
  mpgm_problem *pb = NULL;
  if (pctx) mpgm_ctx_init(pctx);
  if (!pctx || mpgm_problem_create(pctx, s, NULL, &pb)) {
    free(pctx);
    mpgm_scene_destroy(&s);
    return -1;
  }
  made[nmade].hash = ck->scene_hash;
  made[nmade].scene = s;
  made[nmade].ctx = pctx;
  made[nmade].pb = pb;
  return nmade++;
}

/* A monitor that stops the run after its first step. */
static int stop_after_one(void *user, const mpgm_problem *pb, int fields, double wall) {
  (void)user;
  (void)pb;
  (void)fields;
  (void)wall;
  return MPGM_ERR_INTERRUPTED;
}

static void one_step(mpgm_ctx *ctx, mpgm_problem *pb, mpgm_run_result *res) {
  const mpgm_monitor mon = {.step = stop_after_one};
  const mpgm_run_control rc = {.monitor = &mon, .t0 = mpgm_wtime()};
  mpgm_problem_run(pb, &rc, res); /* whatever the step gives, but no crash */
  mpgm_err_clear(ctx);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  if (size < 1) return 0;
  const int as_is = data[0] % 8 == 0;
  const size_t len = size - 1;
  unsigned char *buf = malloc(len ? len : 1);
  if (!buf) return 0;
  memcpy(buf, data + 1, len);
  if (!as_is) mend(buf, len);
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_checkpoint ck;
  if (mpgm_checkpoint_parse(&ctx, PATH, buf, len, &ck)) { /* buf is freed */
    if (strncmp(ctx.msg, PATH ": ", strlen(PATH) + 2) != 0)
      fail("a refused checkpoint's message does not name the file", ctx.msg);
    say("refused", ctx.msg);
    return 0;
  }
  const int i = problem_of(&ck);
  if (i >= 0) {
    mpgm_ctx *pctx = made[i].ctx;
    mpgm_problem *pb = made[i].pb;
    mpgm_err_clear(pctx);
    mpgm_output o;
    memset(&o, 0, sizeof o);
    mpgm_run_result res = {.failed_step = -1};
    const int err = mpgm_checkpoint_restore(pctx, &ck, pb, &o, outdir, &res);
    if (err && strncmp(pctx->msg, PATH ": ", strlen(PATH) + 2) != 0)
      fail("a refused restore's message does not name the file", pctx->msg);
    say(err ? "restore refused" : "restored", err ? pctx->msg : made[i].scene->file);
    if (!err && steps && (data[0] & 0x70) == 0x70) one_step(pctx, pb, &res);
    mpgm_run_result_free(&res);
    mpgm_output_close(&o);
    still_empty();
  }
  mpgm_checkpoint_free(&ck);
  return 0;
}
