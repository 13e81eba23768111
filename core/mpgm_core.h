/* mpgm_core.h -- the shared updated-Lagrangian core: a problem made of a
 * scene, a front end (mpgm_frontend.h) and a time integrator
 * (mpgm_integrator.h), stepped to the end with step control; what a run
 * reports.
 *
 * The core never asks which method runs it. A front end makes nodes and
 * points and, at the start of every step, fills the connectivity (point ->
 * nodes, N, grad N at the configuration of the start of the step); the
 * integrator solves the step (implicit Newmark: predictor, Newton on R and
 * K = K_mat + K_geo (+ K_dyn)) and commits the points; the front end's
 * end_step moves or resets its nodes. The problem itself is private to
 * core/; others see it through the functions below.
 */
#ifndef MPGM_CORE_H
#define MPGM_CORE_H

#include <signal.h>

#include "mpgm_data.h"
#include "mpgm_frontend.h"
#include "mpgm_integrator.h"
#include "mpgm_solver.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mpgm_problem mpgm_problem;

/** Newton statistics of the last step. */
typedef struct mpgm_newton_info {
  int iterations;   /**< Newton iterations (solves) of the step        */
  double res0;      /**< |R| at the predictor [N]                      */
  double res;       /**< final |R| [N]                                 */
  double res_rel;   /**< final |R| / reference                         */
  double du_rel;    /**< final |delta u| / |Delta u|                   */
  int nhist;        /**< entries of hist                                */
  double hist[64];  /**< |R| at each iteration of the step's last solve
                         (the first 64), for the convergence rate        */
} mpgm_newton_info;

/** Something that watches a problem's steps (output.matrices writes the
 *  linear systems). Either operation may be NULL; a non-zero return stops
 *  the step with that code. */
typedef struct mpgm_observer {
  void *user; /**< first argument of the operations                      */
  /** A step (step = steps done + 1) begins, also when it is retried. */
  int (*step_begin)(void *user, mpgm_ctx *ctx, long step);
  /** Newton is about to solve K delta = R of this step (K as it is, or
   *  was, factorised). */
  int (*system)(void *user, mpgm_ctx *ctx, long step, const mpgm_csc *K, const double *R);
} mpgm_observer;

#define MPGM_OBSERVERS_MAX 4

/** What a run has done so far (mpgm_problem_report): for summary.json and
 *  the run's outputs. */
typedef struct mpgm_report {
  long step;           /**< steps completed                             */
  double t;            /**< time [s] (dynamic) or load factor (static)  */
  double dt;           /**< the last step                               */
  double lambda;       /**< load factor at the end of the last step     */
  mpgm_newton_info last; /**< Newton in the last step                   */
  long newton_total;   /**< Newton iterations over the run              */
  long step_cuts;      /**< steps rejected and retried with half the step */
  long contact_resolves; /**< extra solves of steps whose contact set
                            changed                                    */
  int nodes;           /**< nodes in use                                */
  int ndof;            /**< equations of the last step                  */
  int nnz;             /**< entries of the last tangent's pattern       */
  int ncells;          /**< output cells of the front end               */
  int threads;         /**< worker threads of the point and assembly loops */
  const char *solver;  /**< the linear solver backend reported (auto: its
                            first choice)                              */
  int solver_iterative;/**< 1: an iterative backend                     */
  int have_solver_stats; /**< solver_stats holds the backend's figures  */
  mpgm_solver_stats solver_stats;
  int contact_points;  /**< surface points of contact at points (0: none) */
  int contact_points_held;  /**< held at the end                        */
  long contact_point_holds, contact_point_releases; /**< over the run     */
  long contact_points_unenforced; /**< point-steps without shape functions */
} mpgm_report;

/** Create a problem for a loaded scene with its front end (fe NULL: the
 *  scene's, scene->frontend): effects, solver, nodes and points, the
 *  integrator. Errors: the front end's, MPGM_ERR_INPUT (nothing to solve),
 *  MPGM_ERR_NOMEM. */
int mpgm_problem_create(mpgm_ctx *ctx, const mpgm_scene *scene, const mpgm_frontend_type *fe,
                        mpgm_problem **out);
/** Free a problem (accepts NULL, nulls the pointer). */
void mpgm_problem_destroy(mpgm_problem **pb);
/** One step to load factor / time pb->t + pb->dt: the front end's
 *  begin_step, the scene's integrator (solve and commit), the front end's
 *  end_step. On a recoverable failure nothing is committed. */
int mpgm_step(mpgm_problem *pb);
/** Checkpoints (core/checkpoint.c): between two steps, the state the run
 *  continues from -- step and step control, every committed array of the
 *  points and nodes, contact state, work counters, the front end's and the
 *  solver's own state -- appended to b. restore reads it into a problem
 *  just created from the same scene; its run (mpgm_problem_run) then
 *  continues with the next step and the result the caller restored, bit
 *  for bit as the run that saved it. Errors: MPGM_ERR_NOMEM; restore:
 *  MPGM_ERR_INPUT when b is of another scene or layout. */
int mpgm_problem_save(const mpgm_problem *pb, mpgm_blob *b);
int mpgm_problem_restore(mpgm_problem *pb, mpgm_blob *b);
/** Add an observer of the steps (copied; at most MPGM_OBSERVERS_MAX). */
int mpgm_problem_observe(mpgm_problem *pb, const mpgm_observer *obs);

/** Sees every converged step of a run (the run's outputs). */
typedef struct mpgm_monitor {
  void *user; /**< first argument of step                              */
  /** After each converged step; fields: a VTK output is due (output.every,
   *  output.times, the end); wall: the step's wall time [s]. A non-zero
   *  return stops the run with that code. */
  int (*step)(void *user, const mpgm_problem *pb, int fields, double wall);
  /** Optional: every output.checkpoint_every steps (not after the last),
   *  after step: write a checkpoint (mpgm_problem_save). A non-zero return
   *  stops the run with that code. */
  int (*checkpoint)(void *user, const mpgm_problem *pb);
} mpgm_monitor;

/** How mpgm_problem_run runs. */
typedef struct mpgm_run_control {
  const mpgm_monitor *monitor; /**< may be NULL                            */
  int time_split;  /**< 1: log every step's time split (level INFO)        */
  double t0;       /**< wall clock at the start of the run (mpgm_wtime), for
                        the progress line's elapsed time and ETA          */
  const volatile sig_atomic_t *stop; /**< may be NULL; once *stop is
                        non-zero (a signal handler sets it) the run stops
                        before the next step, or abandons the step in
                        progress at its next Newton iteration (nothing of
                        it is committed: the problem is as the last
                        converged step left it), and returns
                        MPGM_ERR_INTERRUPTED                              */
} mpgm_run_control;

/** A rejected (cut) step. */
typedef struct mpgm_cut {
  long step;        /**< the step's number                               */
  double t, dt;     /**< the end time (or load factor) and step tried     */
  int code;         /**< the recoverable error                           */
  char reason[1024];/**< its message                                     */
} mpgm_cut;

#define MPGM_CUTS_MAX 100 /**< cuts a run result records                */

/** How a run ended. */
typedef struct mpgm_run_result {
  int failed;        /**< 1: a step failed for good                       */
  long failed_step;  /**< that step, -1 if none                           */
  char message[1280];/**< "step K (t = T) failed: why"; "" if none         */
  int ncuts;         /**< cuts recorded (the first MPGM_CUTS_MAX)          */
  mpgm_cut *cuts;    /**< them (free with mpgm_run_result_free)           */
} mpgm_run_result;

/** Run the problem from its start to the scene's end (time.end, or load
 *  factor 1) in steps of the scene's size, with step control: a step that
 *  fails recoverably is retried with half the step, down to time.max_cuts
 *  halvings; after time.grow_after converged steps the step doubles back;
 *  a step that would pass one of output.times ends on it. Cuts are logged
 *  (WARNING) and recorded, every step logs a progress line (PROGRESS).
 *  Returns 0, the code of the step that failed (res->failed, the message
 *  in res->message, the step's own in ctx), the monitor's code, or
 *  MPGM_ERR_INTERRUPTED when rc->stop asked for a stop between steps or
 *  in one (the step abandoned, its work counters undone). */
int mpgm_problem_run(mpgm_problem *pb, const mpgm_run_control *rc, mpgm_run_result *res);
void mpgm_run_result_free(mpgm_run_result *r);

/** The scene, effects, points, nodes of a problem (borrowed). */
const mpgm_scene *mpgm_problem_scene(const mpgm_problem *pb);
const mpgm_effects *mpgm_problem_effects(const mpgm_problem *pb);
const mpgm_points *mpgm_problem_points(const mpgm_problem *pb);
const mpgm_nodes *mpgm_problem_nodes(const mpgm_problem *pb);
/** The front end's cells for output: 1, or 0 when it has none (out->n =
 *  0). */
int mpgm_problem_cells(const mpgm_problem *pb, mpgm_cells *out);
/** The front end's background grid for output (mpgm_frontend.h): 1, or 0
 *  when it has none (*out zeroed). */
struct mpgm_background;
int mpgm_problem_background(const mpgm_problem *pb, struct mpgm_background *out);
/** What the run has done so far. */
void mpgm_problem_report(const mpgm_problem *pb, mpgm_report *r);

/** Energy and momentum of a dynamic run after its last step (energy.c,
 *  docs/theory.md section 19), per unit thickness. */
typedef struct mpgm_energy {
  double kinetic;   /**< sum_p m_p |v_p|^2 / 2 [J]                        */
  double work_int;  /**< work of the stresses so far [J]: the strain energy
                         of elastic bodies, plus what plasticity dissipated */
  double work_ext;  /**< work of gravity so far [J]                       */
  double total;     /**< kinetic + work_int - work_ext: constant while no
                         other force (contact, supports in motion) works */
  double momentum[MPGM_DIM]; /**< sum_p m_p v_p [kg m/s]                  */
  double node_momentum[MPGM_DIM]; /**< sum_I m_I v_I of the last step's nodes, m_I =
                         sum_p N_Ip m_p (the points' at step 0)          */
} mpgm_energy;
void mpgm_problem_energy(const mpgm_problem *pb, mpgm_energy *e);

/** With a manufactured solution (scene "manufactured"): the RMS errors of
 *  Tran et al. 2019 eq 47 over the material points at the current time,
 *  err = {displacement [m], velocity [m/s], Cauchy stress [Pa] (the
 *  in-plane tensor's Frobenius norm)}; returns 1. Without one: 0, NaNs. */
int mpgm_problem_mms_errors(const mpgm_problem *pb, double err[3]);

#ifdef __cplusplus
}
#endif
#endif
