/* fuzz_scene.c -- libFuzzer target over what reads user input: the strict
 * JSON check, cJSON, the scene reader with its validation (every family's
 * part, the front end's trait checks) and the --set parser.
 *
 * Input: the scene text, then optionally --set arguments, each after a byte
 * 0x01 (a byte no JSON text may hold outside a string, and no string may
 * hold raw), e.g. "{...}\x01mesh.h=0.1\x01method=gmm". An argument is cut at
 * its first NUL byte, as the command line would.
 *
 * Besides crashes, leaks and undefined behaviour (the build adds ASan and
 * UBSan), it checks two properties and aborts when one fails:
 *   - a scene that loads resolves to JSON that passes the strict check;
 *   - that resolved scene loads again, to the same resolved scene (what
 *     mpgm study relies on when it compares a run's saved scene).
 * A refused input must leave a message in the context.
 *
 * Build and run: scripts/fuzz (docs/architecture.md, section Tests). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_json_reader.h"
#include "mpgm_scene_io.h"

#define MAX_SETS 16

static void fail(const char *what, const char *a, const char *b) {
  fprintf(stderr, "fuzz_scene: %s\n--- first:\n%s\n--- second:\n%s\n", what, a ? a : "",
          b ? b : "");
  abort();
}

/* The resolved scene loads again to itself. */
static void round_trip(const mpgm_scene *s) {
  char *text = mpgm_scene_resolved_json(s);
  if (!text) return; /* out of memory */
  const size_t len = strlen(text);
  if (jr_strict_check(text, len, NULL, NULL, 0)) fail("the resolved scene is not strict JSON", text, NULL);
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene *again = NULL;
  if (mpgm_scene_load_text(&ctx, "fuzz.json", text, len, 0, NULL, &again))
    fail("the resolved scene does not load again", text, ctx.msg);
  char *text2 = mpgm_scene_resolved_json(again);
  if (text2 && strcmp(text, text2) != 0) fail("the resolved scene resolves to another", text, text2);
  free(text2);
  mpgm_scene_destroy(&again);
  free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *in = (const char *)data;
  const char *sep = memchr(in, 0x01, size);
  const size_t len = sep ? (size_t)(sep - in) : size;
  /* the --set arguments, NUL-terminated copies */
  char *args[MAX_SETS];
  int nset = 0;
  for (const char *p = sep; p && nset < MAX_SETS;) {
    const char *q = p + 1, *next = memchr(q, 0x01, size - (size_t)(q - in));
    const size_t n = (size_t)((next ? next : in + size) - q);
    args[nset] = malloc(n + 1);
    if (!args[nset]) break;
    memcpy(args[nset], q, n);
    args[nset][n] = '\0';
    nset++;
    p = next;
  }
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene *s = NULL;
  const int err = mpgm_scene_load_text(&ctx, "fuzz.json", in, len, nset, (const char *const *)args, &s);
  if (err && !ctx.msg[0]) fail("refused without a message", NULL, NULL);
  if (!err) round_trip(s);
  mpgm_scene_destroy(&s);
  for (int i = 0; i < nset; i++) free(args[i]);
  return 0;
}
