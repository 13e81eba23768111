/* mpgm_run.h -- run a scene to the end: time/load loop, output, summary. */
#ifndef MPGM_RUN_H
#define MPGM_RUN_H

#include <signal.h>

#include "mpgm_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mpgm_run_opts {
  const char *out_dir; /**< results folder (overrides output.dir if set)  */
  int per_iteration;   /**< 1: log the time split of every step (level INFO,
                            for benchmarks)                              */
  struct mpgm_checkpoint *restart; /**< continue from this checkpoint (read
                            from out_dir by mpgm_checkpoint_read, of this
                            scene); NULL: a new run                       */
  const volatile sig_atomic_t *stop; /**< may be NULL; once *stop is
                            non-zero (a signal handler of the caller's
                            sets it) the run stops after the step in
                            progress: that step's fields, the histories, a
                            checkpoint to continue from and summary.json
                            (status "interrupted") are written, and
                            mpgm_run returns MPGM_ERR_INTERRUPTED          */
} mpgm_run_opts;

/** Run a loaded scene with its front end (scene->frontend). Writes DIR/summary.json (also on
 *  failure, with status "failed" and where it stopped), DIR/probes.csv,
 *  VTK files and .pvd collections. Returns 0 or the error code (message in
 *  ctx): negative fatal / positive recoverable codes of the failing step,
 *  MPGM_ERR_IO when output cannot be written. Messages go to the context's
 *  logger: a line per step (MPGM_LOG_PROGRESS), step cuts (WARNING), the
 *  time split (INFO, opts->per_iteration). */
int mpgm_run(mpgm_ctx *ctx, const mpgm_scene *scene, const mpgm_run_opts *opts);

/** Effects of a scene as a cJSON object {"inertia": bool, ...}; used by
 *  `mpgm check` and summary.json. Returns a cJSON * (as void *). */
void *mpgm_effects_json(const mpgm_effects *fx);

#ifdef __cplusplus
}
#endif
#endif
