/* test_blob.c -- the tagged sections of checkpoints (base/blob.c): a
 * round trip of sections of every size (empty included) to the byte; a
 * section read under another tag or size, past the end of the data, or
 * with a length that runs past it is refused with MPGM_ERR_INPUT and a
 * message naming the section, and the reader does not move; the hash
 * tells apart texts that differ in one bit. */
#include <stdlib.h>
#include <string.h>

#include "mpgm_blob.h"
#include "mpgm_test.h"

static void check_round_trip(void) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_blob b = {0};
  double x[3] = {1.0 / 3.0, -0.0, 6.02214076e23};
  int k = 42;
  char big[100000];
  for (size_t i = 0; i < sizeof big; i++) big[i] = (char)(i * 7);
  mpgm_test(mpgm_blob_put(&ctx, &b, "x", x, sizeof x) == 0, "put x");
  mpgm_test(mpgm_blob_put(&ctx, &b, "empty", NULL, 0) == 0, "put an empty section");
  mpgm_test(mpgm_blob_put(&ctx, &b, "k", &k, sizeof k) == 0, "put k");
  mpgm_test(mpgm_blob_put(&ctx, &b, "big", big, sizeof big) == 0, "put 100 kB (the buffer grows)");
  mpgm_test(mpgm_blob_put(&ctx, &b, "a tag of 24 characters..", &k, sizeof k) != 0,
            "a tag of MPGM_BLOB_TAG characters is refused");
  mpgm_ctx_init(&ctx);

  mpgm_blob r = {.buf = b.buf, .len = b.len};
  double y[3];
  int kk = 0;
  size_t n = 1;
  char *big2 = malloc(sizeof big);
  mpgm_test(mpgm_blob_get(&ctx, &r, "x", y, sizeof y) == 0 && memcmp(x, y, sizeof x) == 0,
            "x read back to the bit");
  mpgm_test(mpgm_blob_peek(&ctx, &r, "empty", &n) == 0 && n == 0, "the empty section has 0 bytes");
  mpgm_test(mpgm_blob_get(&ctx, &r, "empty", NULL, 0) == 0, "the empty section is read");
  const size_t at = r.pos;
  mpgm_test(mpgm_blob_get(&ctx, &r, "kk", &kk, sizeof kk) == MPGM_ERR_INPUT &&
                strstr(ctx.msg, "expected section 'kk', found 'k'") && r.pos == at,
            "another tag is refused, the reader stays (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  mpgm_test(mpgm_blob_get(&ctx, &r, "k", &x, sizeof x) == MPGM_ERR_INPUT &&
                strstr(ctx.msg, "holds 4 bytes, expected 24") && r.pos == at,
            "another size is refused (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  mpgm_test(mpgm_blob_get(&ctx, &r, "k", &kk, sizeof kk) == 0 && kk == 42, "k read back");
  mpgm_test(mpgm_blob_get(&ctx, &r, "big", big2, sizeof big) == 0 && memcmp(big, big2, sizeof big) == 0,
            "100 kB read back");
  mpgm_test(r.pos == r.len, "every byte read");
  mpgm_test(mpgm_blob_peek(&ctx, &r, "more", &n) == MPGM_ERR_INPUT && strstr(ctx.msg, "end of the data"),
            "past the end: refused (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);

  /* the same data cut short inside the last section */
  mpgm_blob t = {.buf = b.buf, .len = b.len - 1};
  mpgm_test(mpgm_blob_get(&ctx, &t, "x", y, sizeof y) == 0 && mpgm_blob_get(&ctx, &t, "empty", NULL, 0) == 0 &&
                mpgm_blob_get(&ctx, &t, "k", &kk, sizeof kk) == 0,
            "the whole sections of truncated data are read");
  mpgm_test(mpgm_blob_get(&ctx, &t, "big", big2, sizeof big) == MPGM_ERR_INPUT &&
                strstr(ctx.msg, "runs past the end"),
            "a truncated section is refused (%s)", ctx.msg);
  free(big2);
  mpgm_blob_free(&b);
  mpgm_test(b.buf == NULL && b.len == 0, "freed");
}

static void check_hash(void) {
  char s[] = "{\"mesh\": {\"h\": 0.05}}";
  const unsigned long long h = mpgm_hash64(s, strlen(s));
  mpgm_test(h == mpgm_hash64(s, strlen(s)), "the hash is a function of the bytes");
  s[10] ^= 1;
  mpgm_test(h != mpgm_hash64(s, strlen(s)), "one bit changes it");
  mpgm_test(mpgm_hash64("", 0) == 1469598103934665603ull, "FNV-1a of nothing is its offset basis");
}

int main(void) {
  check_round_trip();
  check_hash();
  return mpgm_test_summary();
}
