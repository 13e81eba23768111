/* mpgm_checkpoint.h -- checkpoint and restart of a run (output.
 * checkpoint_every, `mpgm run --restart DIR`; docs/scene-format.md
 * "Checkpoint and restart"). A checkpoint is DIR/checkpoint.mpgm: the
 * resolved scene, the problem's state (mpgm_problem_save), the output's
 * (mpgm_output_save) and the run's step cuts. A run restarted from it
 * continues bit for bit as the run that wrote it would have. */
#ifndef MPGM_CHECKPOINT_H
#define MPGM_CHECKPOINT_H

#include "mpgm_blob.h"
#include "mpgm_core.h"
#include "mpgm_output.h"
#include "mpgm_scene_io.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A checkpoint read back, before it is restored. */
typedef struct mpgm_checkpoint {
  char path[MPGM_PATH_LEN + 32]; /**< DIR/checkpoint.mpgm                 */
  mpgm_blob blob;     /**< its sections, read up to the problem's          */
  long step;          /**< steps done when it was written                  */
  unsigned long long scene_hash; /**< of scene_json                      */
  char *file;         /**< the scene file the run was started with         */
  char *scene_json;   /**< its resolved scene (JSON text)                  */
} mpgm_checkpoint;

/** DIR/checkpoint.mpgm into path (n bytes). */
void mpgm_checkpoint_path(const char *dir, char *path, size_t n);
/** Write the checkpoint of a run between two steps into DIR, atomically.
 *  Errors: MPGM_ERR_IO, MPGM_ERR_NOMEM. */
int mpgm_checkpoint_write(mpgm_ctx *ctx, const char *dir, const mpgm_problem *pb,
                          const mpgm_output *o, const mpgm_run_result *res);
/** Read DIR/checkpoint.mpgm and check it whole (mpgm_checkpoint_parse).
 *  A checkpoint.mpgm that is not a regular file (a FIFO, a folder) is
 *  refused by its name, before it is opened. Errors: MPGM_ERR_IO (cannot
 *  read), MPGM_ERR_INPUT ("PATH: ..."). */
int mpgm_checkpoint_read(mpgm_ctx *ctx, const char *dir, mpgm_checkpoint *ck);
/** The checkpoint held in buf (len bytes, malloc'd: ck owns it from here,
 *  also on failure), read as the file path: an mpgm checkpoint, every
 *  section whole (its length within the file, its CRC-32 that of its
 *  bytes, nothing after the last), of this machine's byte order and sizes,
 *  written by this very mpgm (version and commit) built for this dimension
 *  (a checkpoint that records none is plane strain's), its scene matching
 *  its hash. Errors: MPGM_ERR_INPUT "PATH: section 'TAG' is damaged (CRC
 *  ...)", "PATH: written by mpgm X ...", "PATH: written by a 3-D run;
 *  restart it with mpgm-3d", "PATH: not an mpgm checkpoint", ... */
int mpgm_checkpoint_parse(mpgm_ctx *ctx, const char *path, unsigned char *buf, size_t len,
                          mpgm_checkpoint *ck);
/** Restore a problem just created from the checkpoint's scene, the output
 *  state of its results folder DIR (mpgm_output_restore) and its result's
 *  step cuts, every count and index checked, up to the end of the file.
 *  Nothing is written: the folder is opened after (mpgm_output_resume),
 *  so that a checkpoint refused here leaves it untouched. Errors:
 *  MPGM_ERR_INPUT "PATH: ..." (another scene or layout, a section out of
 *  range), MPGM_ERR_NOMEM. */
int mpgm_checkpoint_restore(mpgm_ctx *ctx, mpgm_checkpoint *ck, mpgm_problem *pb, mpgm_output *o,
                            const char *dir, mpgm_run_result *res);
void mpgm_checkpoint_free(mpgm_checkpoint *ck);

#ifdef __cplusplus
}
#endif
#endif
