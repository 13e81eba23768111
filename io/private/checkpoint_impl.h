/* checkpoint_impl.h -- private to io/: the header section of a checkpoint
 * (checkpoint.c writes it, checkpoint_read.c checks it) and the renaming
 * of a layer's "checkpoint: WHY" errors as "PATH: WHY". */
#ifndef MPGM_CHECKPOINT_IMPL_H
#define MPGM_CHECKPOINT_IMPL_H

#include <stdint.h>

#include "mpgm_base.h"

/* 1: sections of tag and length; 2: and a CRC-32 of each */
#define CK_FORMAT 2u
#define CK_ORDER 0x01020304u

typedef struct ck_header {
  char magic[8];       /* "MPGMCKPT" */
  uint32_t format;     /* CK_FORMAT */
  uint32_t order;      /* CK_ORDER as this machine stores it */
  uint32_t sizes;      /* sizeof double | long << 8 | int << 16 | pointer << 24 */
  uint32_t dim;        /* MPGM_DIM of the build that wrote it; 0 in the
                          checkpoints written before it was recorded (then
                          a padding of zeros): plane strain */
  char version[64];    /* mpgm_version() */
  uint64_t scene_hash; /* mpgm_hash64 of scene.json */
  int64_t step;        /* steps done */
} ck_header;

/* This machine's sizes as ck_header.sizes holds them. */
static inline uint32_t mpgm_ck_sizes(void) {
  return (uint32_t)(sizeof(double) | sizeof(long) << 8 | sizeof(int) << 16 | sizeof(void *) << 24);
}

/* An error a layer recorded as "checkpoint: WHY", as "PATH: WHY". */
int mpgm_ck_named(mpgm_ctx *ctx, const char *path, int err);

#endif
