/* test_blob.c -- the tagged sections of checkpoints (base/blob.c): a
 * round trip of sections of every size (empty included) to the byte; a
 * section read under another tag or size, past the end of the data, or
 * with a length that runs past it is refused with MPGM_ERR_INPUT and a
 * message naming the section, and the reader does not move; the hash
 * tells apart texts that differ in one bit. The CRC-32 of each section: the
 * standard check value, the layout of a head (tag, length, CRC of both and
 * the data), a damaged section refused by the read and by the whole-buffer
 * check, which also finds every single bit flipped anywhere in a buffer,
 * bytes after the last section and a section cut short. */
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

static void check_crc(void) {
  mpgm_test(mpgm_crc32(0, "123456789", 9) == 0xcbf43926ul, "CRC-32 of \"123456789\" is 0xcbf43926");
  mpgm_test(mpgm_crc32(mpgm_crc32(0, "1234", 4), "56789", 5) == 0xcbf43926ul, "CRC-32 continues");
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_blob b = {0};
  const double v[4] = {2.385, -1.0 / 7.0, 1e-300, 6.5};
  const int k = 17;
  mpgm_test(mpgm_blob_put(&ctx, &b, "pts.v", v, sizeof v) == 0 &&
                mpgm_blob_put(&ctx, &b, "none", NULL, 0) == 0 &&
                mpgm_blob_put(&ctx, &b, "k", &k, sizeof k) == 0,
            "three sections put");
  mpgm_test(b.len == 3 * MPGM_BLOB_HEAD + sizeof v + sizeof k, "a head is %d bytes",
            MPGM_BLOB_HEAD);
  /* the head: tag, length, then the CRC of both and of the data */
  unsigned rec;
  memcpy(&rec, b.buf + MPGM_BLOB_TAG + 8, sizeof rec);
  const unsigned long want = mpgm_crc32(mpgm_crc32(0, b.buf, MPGM_BLOB_TAG + 8), v, sizeof v);
  mpgm_test(rec == want, "the CRC recorded is that of the tag, the length and the data");
  mpgm_test(mpgm_blob_verify(&ctx, &b) == 0, "the buffer verifies (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  /* one bit of a double flipped: the read refuses it and stays */
  b.buf[MPGM_BLOB_HEAD + 9] ^= 0x10;
  double y[4];
  mpgm_test(mpgm_blob_get(&ctx, &b, "pts.v", y, sizeof y) == MPGM_ERR_INPUT &&
                strstr(ctx.msg, "section 'pts.v' is damaged (CRC 0x") && b.pos == 0,
            "a flipped bit is refused by the read (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  mpgm_test(mpgm_blob_verify(&ctx, &b) == MPGM_ERR_INPUT &&
                strstr(ctx.msg, "section 'pts.v' is damaged"),
            "and by the whole-buffer check (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  b.buf[MPGM_BLOB_HEAD + 9] ^= 0x10;
  /* every single bit flipped anywhere, in heads and data alike, is found */
  int missed = 0;
  for (size_t i = 0; i < 8 * b.len; i++) {
    b.buf[i / 8] ^= (unsigned char)(1u << (i % 8));
    missed += mpgm_blob_verify(&ctx, &b) == 0;
    b.buf[i / 8] ^= (unsigned char)(1u << (i % 8));
    mpgm_ctx_init(&ctx);
  }
  mpgm_test(missed == 0, "all %zu single-bit flips are found (%d missed)", 8 * b.len, missed);
  mpgm_test(mpgm_blob_verify(&ctx, &b) == 0, "the buffer is whole again");
  /* cut short inside the last section, or bytes after it */
  mpgm_blob t = {.buf = b.buf, .len = b.len - 1};
  mpgm_test(mpgm_blob_verify(&ctx, &t) == MPGM_ERR_INPUT && strstr(ctx.msg, "section 'k'") &&
                strstr(ctx.msg, "runs past the end"),
            "a buffer cut inside a section is refused (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  mpgm_test(mpgm_blob_put(&ctx, &b, "k", &k, sizeof k) == 0, "a fourth section");
  t = (mpgm_blob){.buf = b.buf, .len = b.len - MPGM_BLOB_HEAD - sizeof k + 5};
  mpgm_test(mpgm_blob_verify(&ctx, &t) == MPGM_ERR_INPUT &&
                strstr(ctx.msg, "5 bytes after the last section 'k', too few for a section"),
            "bytes after the last section are refused (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  memset(b.buf + b.len - MPGM_BLOB_HEAD - sizeof k, 0, MPGM_BLOB_TAG);
  mpgm_test(mpgm_blob_verify(&ctx, &b) == MPGM_ERR_INPUT && strstr(ctx.msg, "section 4 ") &&
                strstr(ctx.msg, "is not a name"),
            "a head without a tag is refused (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  t = (mpgm_blob){0};
  mpgm_test(mpgm_blob_verify(&ctx, &t) == 0, "no data: no section to be wrong");
  mpgm_blob_free(&b);
}

int main(void) {
  check_round_trip();
  check_hash();
  check_crc();
  return mpgm_test_summary();
}
