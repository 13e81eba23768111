/* mpgm_blob.h -- a growable binary buffer of tagged sections, for
 * checkpoints: each layer appends its state as sections (a tag, a length,
 * the bytes) and reads them back in the same order. A section read back
 * must have the tag and the length the reader expects, or the read fails
 * with a message naming both: a checkpoint of another layout (another
 * version, another scene) is refused, never misread.
 *
 * Sections hold raw bytes of the machine that wrote them (doubles bit for
 * bit: a restart continues exactly); the file header (io/checkpoint.c)
 * records the version and the byte order. */
#ifndef MPGM_BLOB_H
#define MPGM_BLOB_H

#include <stddef.h>

#include "mpgm_base.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MPGM_BLOB_TAG 24 /**< bytes of a section tag, NUL included */

typedef struct mpgm_blob {
  unsigned char *buf;
  size_t len;  /**< bytes written (writer) or held (reader)   */
  size_t cap;  /**< allocated bytes                             */
  size_t pos;  /**< reader: next section                        */
} mpgm_blob;

/** Append a section: tag (at most MPGM_BLOB_TAG - 1 characters) and n
 *  bytes of data (data may be NULL when n is 0). Errors: MPGM_ERR_NOMEM. */
int mpgm_blob_put(mpgm_ctx *ctx, mpgm_blob *b, const char *tag, const void *data, size_t n);
/** Read the next section into data: it must be tagged tag and hold exactly
 *  n bytes. Errors: MPGM_ERR_INPUT "checkpoint section ...: expected ...". */
int mpgm_blob_get(mpgm_ctx *ctx, mpgm_blob *b, const char *tag, void *data, size_t n);
/** The length of the next section, which must be tagged tag (for sections
 *  whose length the reader learns from the file). Errors: MPGM_ERR_INPUT. */
int mpgm_blob_peek(mpgm_ctx *ctx, const mpgm_blob *b, const char *tag, size_t *n);
/** Free the buffer (the struct itself is the caller's). */
void mpgm_blob_free(mpgm_blob *b);

/** 64-bit FNV-1a hash of n bytes (a checkpoint's scene and layout). */
unsigned long long mpgm_hash64(const void *data, size_t n);

#ifdef __cplusplus
}
#endif
#endif
