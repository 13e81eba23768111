/* blob.c -- tagged binary sections (mpgm_blob.h). */
#include "mpgm_blob.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* A section: tag (MPGM_BLOB_TAG bytes, NUL-padded), length (uint64), data. */
#define HEAD (MPGM_BLOB_TAG + sizeof(uint64_t))

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
  memcpy(p + MPGM_BLOB_TAG, &len, sizeof len);
  if (n) memcpy(p + HEAD, data, n);
  b->len = need;
  return 0;
}

int mpgm_blob_peek(mpgm_ctx *ctx, const mpgm_blob *b, const char *tag, size_t *n) {
  *n = 0;
  MPGM_CHECK(ctx, b->pos + HEAD <= b->len, MPGM_ERR_INPUT,
             "checkpoint: expected section '%s', found the end of the data", tag);
  const unsigned char *p = b->buf + b->pos;
  char found[MPGM_BLOB_TAG];
  memcpy(found, p, MPGM_BLOB_TAG);
  found[MPGM_BLOB_TAG - 1] = '\0';
  MPGM_CHECK(ctx, strcmp(found, tag) == 0, MPGM_ERR_INPUT,
             "checkpoint: expected section '%s', found '%s' (written by another layout)", tag, found);
  uint64_t len;
  memcpy(&len, p + MPGM_BLOB_TAG, sizeof len);
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
  if (n) memcpy(data, b->buf + b->pos + HEAD, n);
  b->pos += HEAD + n;
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
