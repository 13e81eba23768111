/* blob.c -- tagged binary sections (mpgm_blob.h), each with a CRC-32 of
 * its head and bytes (zlib's): a bit flipped anywhere in a checkpoint is
 * found before anything is read from it. */
#include "mpgm_blob.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#define HEAD   MPGM_BLOB_HEAD
#define AT_LEN MPGM_BLOB_TAG       /* offset of the length in a head */
#define AT_CRC (MPGM_BLOB_TAG + 8) /* offset of the CRC in a head    */
_Static_assert(HEAD == AT_CRC + sizeof(uint32_t), "section head: tag, length, CRC");

unsigned long mpgm_crc32(unsigned long crc, const void *data, size_t n) {
  return crc32_z(crc, data, n);
}

/* The CRC a section at p with n bytes of data should record: of its tag
 * and length, then of its data. */
static uint32_t section_crc(const unsigned char *p, size_t n) {
  uLong c = crc32_z(0, p, AT_CRC);
  return (uint32_t)crc32_z(c, p + HEAD, n);
}

/* The tag at p as text for a message: non-printable bytes as '?'. */
static void tag_text(const unsigned char *p, char out[MPGM_BLOB_TAG]) {
  int i = 0;
  for (; i < MPGM_BLOB_TAG - 1 && p[i]; i++)
    out[i] = p[i] >= 0x20 && p[i] < 0x7f ? (char)p[i] : '?';
  out[i] = '\0';
}

int mpgm_blob_put(mpgm_ctx *ctx, mpgm_blob *b, const char *tag, const void *data, size_t n) {
  MPGM_CHECK(ctx, strlen(tag) < MPGM_BLOB_TAG, MPGM_ERR_INTERNAL, "checkpoint tag '%s' too long", tag);
  const size_t need = b->len + HEAD + n;
  if (need > b->cap) {
    size_t cap = b->cap ? b->cap : 1 << 16;
    while (cap < need) cap *= 2;
    unsigned char *nb = realloc(b->buf, cap);
    MPGM_CHECK(ctx, nb, MPGM_ERR_NOMEM, "out of memory (checkpoint of %zu bytes)", cap);
    b->buf = nb;
    b->cap = cap;
  }
  unsigned char *p = b->buf + b->len;
  memset(p, 0, MPGM_BLOB_TAG);
  memcpy(p, tag, strlen(tag));
  const uint64_t len = n;
  memcpy(p + AT_LEN, &len, sizeof len);
  if (n) memcpy(p + HEAD, data, n);
  const uint32_t crc = section_crc(p, n);
  memcpy(p + AT_CRC, &crc, sizeof crc);
  b->len = need;
  return 0;
}

int mpgm_blob_peek(mpgm_ctx *ctx, const mpgm_blob *b, const char *tag, size_t *n) {
  *n = 0;
  MPGM_CHECK(ctx, b->pos <= b->len && HEAD <= b->len - b->pos, MPGM_ERR_INPUT,
             "checkpoint: expected section '%s', found the end of the data", tag);
  const unsigned char *p = b->buf + b->pos;
  char found[MPGM_BLOB_TAG];
  tag_text(p, found);
  MPGM_CHECK(ctx, strncmp((const char *)p, tag, MPGM_BLOB_TAG) == 0, MPGM_ERR_INPUT,
             "checkpoint: expected section '%s', found '%s' (written by another layout)", tag,
             found);
  uint64_t len;
  memcpy(&len, p + AT_LEN, sizeof len);
  MPGM_CHECK(ctx, len <= b->len - b->pos - HEAD, MPGM_ERR_INPUT,
             "checkpoint: section '%s' of %llu bytes runs past the end of the data", tag,
             (unsigned long long)len);
  *n = (size_t)len;
  return 0;
}

int mpgm_blob_get(mpgm_ctx *ctx, mpgm_blob *b, const char *tag, void *data, size_t n) {
  size_t len;
  MPGM_CALL(mpgm_blob_peek(ctx, b, tag, &len));
  MPGM_CHECK(ctx, len == n, MPGM_ERR_INPUT,
             "checkpoint: section '%s' holds %zu bytes, expected %zu (another scene or layout)", tag,
             len, n);
  const unsigned char *p = b->buf + b->pos;
  uint32_t rec;
  memcpy(&rec, p + AT_CRC, sizeof rec);
  const uint32_t crc = section_crc(p, n);
  MPGM_CHECK(ctx, rec == crc, MPGM_ERR_INPUT,
             "checkpoint: section '%s' is damaged (CRC 0x%08lx recorded, 0x%08lx found)", tag,
             (unsigned long)rec, (unsigned long)crc);
  if (n) memcpy(data, p + HEAD, n);
  b->pos += HEAD + n;
  return 0;
}

/* Section k (at byte at) of b: its head, tag and length, its CRC. */
static int verify_one(mpgm_ctx *ctx, const mpgm_blob *b, size_t at, int k, const char *last,
                      size_t *next, char tag[MPGM_BLOB_TAG]) {
  const size_t left = b->len - at;
  MPGM_CHECK(ctx, left >= HEAD, MPGM_ERR_INPUT,
             "checkpoint: %zu bytes after the last section "
             "'%s', too few for a section (truncated in a section's head, or bytes appended)",
             left, last);
  const unsigned char *p = b->buf + at;
  tag_text(p, tag);
  /* a tag is a string of at most MPGM_BLOB_TAG - 1 bytes, NUL-padded */
  int t = 0;
  while (t < MPGM_BLOB_TAG && p[t]) t++;
  int pad = t < MPGM_BLOB_TAG && t > 0;
  for (int i = t; pad && i < MPGM_BLOB_TAG; i++) pad = p[i] == 0;
  for (int i = 0; pad && i < t; i++) pad = p[i] >= 0x20 && p[i] < 0x7f;
  MPGM_CHECK(ctx, pad, MPGM_ERR_INPUT,
             "checkpoint: section %d (at byte %zu, after '%s') is "
             "damaged: its tag '%s' is not a name",
             k + 1, at, last, tag);
  uint64_t len;
  memcpy(&len, p + AT_LEN, sizeof len);
  MPGM_CHECK(ctx, len <= left - HEAD, MPGM_ERR_INPUT,
             "checkpoint: section '%s' (at byte %zu) "
             "of %llu bytes runs past the end of the file (%zu bytes left): truncated or damaged",
             tag, at, (unsigned long long)len, left - HEAD);
  uint32_t rec;
  memcpy(&rec, p + AT_CRC, sizeof rec);
  const uint32_t crc = section_crc(p, (size_t)len);
  MPGM_CHECK(ctx, rec == crc, MPGM_ERR_INPUT,
             "checkpoint: section '%s' is damaged (CRC 0x%08lx recorded, 0x%08lx found)", tag,
             (unsigned long)rec, (unsigned long)crc);
  *next = at + HEAD + (size_t)len;
  return 0;
}

int mpgm_blob_verify(mpgm_ctx *ctx, const mpgm_blob *b) {
  char tag[MPGM_BLOB_TAG], last[MPGM_BLOB_TAG] = "(none)";
  size_t at = 0;
  for (int k = 0; at < b->len; k++) {
    MPGM_CALL(verify_one(ctx, b, at, k, last, &at, tag));
    memcpy(last, tag, sizeof last);
  }
  return 0;
}

void mpgm_blob_free(mpgm_blob *b) {
  free(b->buf);
  memset(b, 0, sizeof *b);
}

unsigned long long mpgm_hash64(const void *data, size_t n) {
  const unsigned char *p = data;
  uint64_t h = 1469598103934665603ull;
  for (size_t i = 0; i < n; i++) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}
