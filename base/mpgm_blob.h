/* mpgm_blob.h -- a growable binary buffer of tagged sections, for
 * checkpoints: each layer appends its state as sections (a tag, a length,
 * a CRC-32, the bytes) and reads them back in the same order. A section
 * read back must have the tag and the length the reader expects and the
 * CRC its bytes have, or the read fails with a message naming it: a
 * checkpoint of another layout (another version, another scene) is
 * refused, a damaged one too, never misread.
 *
 * Sections hold raw bytes of the machine that wrote them (doubles bit for
 * bit: a restart continues exactly); the file header (io/checkpoint.c)
 * records the version and the byte order.
 *
 * Layout of a section (MPGM_BLOB_HEAD bytes of head, then the data):
 *   tag    MPGM_BLOB_TAG bytes, NUL-padded
 *   length uint64, bytes of data
 *   crc    uint32, zlib's CRC-32 of the tag, the length and the data */
#ifndef MPGM_BLOB_H
#define MPGM_BLOB_H

#include <stddef.h>

#include "mpgm_base.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MPGM_BLOB_TAG 24 /**< bytes of a section tag, NUL included */
#define MPGM_BLOB_HEAD (MPGM_BLOB_TAG + 8 + 4) /**< tag, length, CRC-32 */

typedef struct mpgm_blob {
  unsigned char *buf;
  size_t len;  /**< bytes written (writer) or held (reader)   */
  size_t cap;  /**< allocated bytes                             */
  size_t pos;  /**< reader: next section                        */
} mpgm_blob;

/** Append a section: tag (at most MPGM_BLOB_TAG - 1 characters) and n
 *  bytes of data (data may be NULL when n is 0). Errors: MPGM_ERR_NOMEM. */
int mpgm_blob_put(mpgm_ctx *ctx, mpgm_blob *b, const char *tag, const void *data, size_t n);
/** Read the next section into data: it must be tagged tag, hold exactly n
 *  bytes and match its CRC. Errors: MPGM_ERR_INPUT "checkpoint: section
 *  ...: expected ..." or "... is damaged (CRC ...)"; the reader stays. */
int mpgm_blob_get(mpgm_ctx *ctx, mpgm_blob *b, const char *tag, void *data, size_t n);
/** The length of the next section, which must be tagged tag (for sections
 *  whose length the reader learns from the file). Errors: MPGM_ERR_INPUT. */
int mpgm_blob_peek(mpgm_ctx *ctx, const mpgm_blob *b, const char *tag, size_t *n);
/** Check the whole buffer from its first byte, whatever the reader's
 *  position: every section's head within the data, its tag a string, its
 *  length within the data and its CRC that of its bytes, and nothing after
 *  the last section. Errors: MPGM_ERR_INPUT "section 'TAG' ..." naming the
 *  first section that is wrong and what is wrong with it. */
int mpgm_blob_verify(mpgm_ctx *ctx, const mpgm_blob *b);
/** Free the buffer (the struct itself is the caller's). */
void mpgm_blob_free(mpgm_blob *b);

/** zlib's CRC-32 (ISO-HDLC) of n bytes, continuing crc (0 to start). */
unsigned long mpgm_crc32(unsigned long crc, const void *data, size_t n);
/** 64-bit FNV-1a hash of n bytes (a checkpoint's scene and layout). */
unsigned long long mpgm_hash64(const void *data, size_t n);

#ifdef __cplusplus
}
#endif
#endif
