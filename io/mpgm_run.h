/* mpgm_run.h -- run a scene to the end: time/load loop, output, summary. */
#ifndef MPGM_RUN_H
#define MPGM_RUN_H

#include <signal.h>

#include "mpgm_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** How a run ended, for the caller's summary line (mpgm_run_opts.outcome):
 *  what summary.json records, in short. The main metrics are the
 *  reference's error metrics when the scene has a reference (those named
 *  *error*, else all of them), else the manufactured solution's errors,
 *  else the final displacement of the first two probes, else the bodies'
 *  reach (runout, height); then eps_p_max of a plastic run; at most
 *  MPGM_OUTCOME_METRICS. A run that did not complete has them at its last
 *  converged step (summary.json "metrics_at_stop"). */
#define MPGM_OUTCOME_METRICS 6
typedef struct mpgm_run_outcome {
  int set;           /**< 1 when filled: the run was set up and wrote (or
                          tried to write) its summary.json              */
  char status[16];   /**< summary.json "status": completed, failed,
                          interrupted, io_error                         */
  long steps, step_cuts;
  double t;          /**< the time (or load factor) reached              */
  double wall;       /**< wall time of the run [s]                       */
  int nmetric;
  struct {
    char name[64];
    double value;
  } metric[MPGM_OUTCOME_METRICS];
} mpgm_run_outcome;

typedef struct mpgm_run_opts {
  const char *out_dir; /**< results folder (overrides output.dir if set)  */
  int per_iteration;   /**< 1: log the time split of every step (level INFO,
                            for benchmarks)                              */
  struct mpgm_checkpoint *restart; /**< continue from this checkpoint (read
                            from out_dir by mpgm_checkpoint_read, of this
                            scene); NULL: a new run                       */
  const volatile sig_atomic_t *stop; /**< may be NULL; once *stop is
                            non-zero (a signal handler of the caller's
                            sets it) the run stops: an explicit step in
                            progress ends (it is short), an implicit one
                            is abandoned at its next Newton iteration
                            (nothing of it is committed). The last
                            converged step's fields (when not written
                            yet), the histories, a checkpoint to continue
                            from and summary.json (status "interrupted")
                            are written, and mpgm_run returns
                            MPGM_ERR_INTERRUPTED                          */
  volatile sig_atomic_t *running; /**< may be NULL; mpgm_run sets *running
                            to 1 once the problem is set up (the bodies
                            filled, the nodes and points made), before it
                            touches the results folder. Before that
                            nothing of the run is written, and a caller
                            may end the process at once on a signal
                            instead of asking *stop (a set-up of millions
                            of points takes seconds)                     */
  mpgm_run_outcome *outcome; /**< may be NULL; filled at the run's end
                            (outcome->set), whatever its status          */
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
