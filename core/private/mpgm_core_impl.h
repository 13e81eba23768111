/* mpgm_core_impl.h -- private to core/ (and the white-box unit tests): the
 * problem and the pieces the step is made of (points' update, assembly,
 * pattern, Newton, contact). */
#ifndef MPGM_CORE_IMPL_H
#define MPGM_CORE_IMPL_H

#include <math.h>
#include <stdint.h>

#include "mpgm_core.h"
#include "mpgm_linsys.h"

/** Unilateral contact without slip at surface points (core/contact_points.c,
 *  docs/theory.md "Contact at surface points"): the pts.nsurf surface
 *  tracers (after the probes) move with the body like material points; one
 *  that reaches a contact plane is held at the place it reached by a
 *  penalty spring (both components: no slip) and let go where the spring
 *  would pull it back onto the plane. The grid nodes stay free. */
struct mpgm_cpoints {
  int first;          /**< index in pts of the first surface tracer     */
  int n;              /**< surface tracers                               */
  signed char *plane; /**< per tracer: scene boundary it is held on, -1  */
  unsigned char *flip;/**< per tracer: state changed in this step        */
  unsigned char *off; /**< per tracer: no shape functions this step (no
                           active cell near it): not enforced          */
  double *anchor;     /**< MPGM_DIM per tracer: where it is held [m]     */
  int held;           /**< tracers held now                              */
  long holds, releases; /**< changes of state over the run               */
  long unenforced;    /**< tracer-steps without shape functions          */
};

/** Step control across the run loop (run.c); kept in the problem, so that a
 *  run restored from a checkpoint continues with the step it had. */
typedef struct mpgm_stepper {
  double end, dt0; /**< end of the run (time, or load factor 1); the scene's step */
  double dt_now;   /**< the step now: halved by a cut, doubled back after easy steps */
  int level, easy; /**< cuts in force; converged steps in a row since */
  int wait;        /**< easy steps the next growth waits for (grow_after,
                        doubled by time.grow_backoff)                   */
  int grown;       /**< the step now is the first at a grown size      */
  int nout;        /**< output.times passed */
} mpgm_stepper;

struct mpgm_problem {
  mpgm_ctx *ctx;
  const mpgm_scene *scene;
  mpgm_effects fx;
  mpgm_points pts;
  mpgm_nodes nodes;
  mpgm_conn conn;
  const mpgm_frontend_type *fe;
  void *fe_data;
  const mpgm_integrator_type *integ; /**< the scene's time integrator  */
  void *integ_data;  /**< its data (create), or NULL                    */
  mpgm_observer obs[MPGM_OBSERVERS_MAX]; /**< observers of the steps     */
  int nobs;
  /* step */
  double t;          /**< time (dynamic) or load factor (static) at step start */
  double dt;         /**< time step [s] (dynamic) or load increment     */
  double lambda;     /**< load factor at the end of the step            */
  long step;         /**< steps completed                               */
  long newton_total; /**< Newton iterations over the run                */
  mpgm_newton_info last;
  mpgm_stepper sp;   /**< step control (run.c)                            */
  double work_int;   /**< dynamic: work of the stresses so far [J] (per
                          unit thickness; energy.c)                     */
  double work_ext;   /**< dynamic: work of gravity (and of a manufactured
                          solution's body force) so far [J]             */
  double ke_last;    /**< explicit with time.kinetic_damping: the points'
                          kinetic energy after the last step [J]        */
  double energy0;    /**< explicit: the energy at the start, the points'
                          kinetic energy [J] (energy.c, the balance)    */
  double energy_floor; /**< explicit: the smallest scale of the balance:
                          the most work gravity can do on the mass M in
                          mesh.domain, M sum_d |g_d| (max_d - min_d), or
                          1e-12 M c_max^2 when larger [J]               */
  double work_ext_max; /**< explicit: the largest |work_ext| so far [J]  */
  double *mms_b;     /**< manufactured solution: the body force per unit
                          mass at each material point, MPGM_DIM each,
                          at the time of the last mpgm_mms_forces       */
  const volatile sig_atomic_t *stop; /**< mpgm_run_control.stop of the run
                          in progress (NULL: none): Newton looks at it
                          before each iteration                          */
  int resumed;       /**< restored from a checkpoint (mpgm_problem_restore):
                          the run continues its step control and result */
  mpgm_pool *pool;   /**< worker threads (scene "threads")               */
  mpgm_linsys *ls;   /**< the implicit integrator's linear system (NULL
                          in an explicit run: it solves nothing)       */
  long contact_rounds; /**< extra solves of steps whose contact set changed */
  long step_cuts;    /**< steps rejected and retried with half the step
                          (time.max_cuts; run.c)                        */
  mpgm_cpoints cp;   /**< contact at surface points (fx.contact_points)  */
};

/** Load factor at the end of the step being solved: static, the load
 *  factor t + dt itself (t counts load from 0 to 1); dynamic, the ramp of
 *  prescribed displacements, (t + dt) / end. At most 1. */
static inline double mpgm_load_factor(const mpgm_problem *pb) {
  const double end = pb->scene->analysis == MPGM_ANALYSIS_STATIC ? 1.0 : pb->scene->t_end;
  return fmin(1.0, (pb->t + pb->dt) / end);
}

/** Nested-dissection order of the n nodes of a graph (CSR ptr/adj) with
 *  coordinates x (MPGM_DIM per node): perm[k] = the node numbered k
 *  (core/ordering.c). Errors: MPGM_ERR_NOMEM. */
int mpgm_order_nodes(mpgm_ctx *ctx, int n, const int *ptr, const int *adj, const double *x,
                     int *perm);
/** Number equations of free components (node-major); sets nodes->ndof. */
void mpgm_nodes_number(mpgm_nodes *nd);

/** Evaluate trial state at the current increment nodes.du: F, stress
 *  and, when want_D, the tangents D and the current gradients conn.g
 *  (explicit schemes assemble no matrix; modified Newton solving with its
 *  kept factorisation needs none; the residual reads the start-of-step
 *  gradients). Exposed for tests. */
int mpgm_eval_points(mpgm_problem *pb, int want_D);
/** mpgm_eval_points without tangents on this thread, point by point in
 *  order, calling each(job, p, dF) as soon as point p's trial state is
 *  known (explicit schemes: its force added to the nodes while its lists
 *  are in cache), with its increment dF, which a 3-D build does not
 *  store in pts.dF_t. */
int mpgm_eval_points_each(mpgm_problem *pb, void (*each)(void *job, int p, const double *dF),
                          void *job);
/** Assemble R = f_ext - f_int (- f_inertia) and, if want_K, the tangent
 *  into pb->ls->K (pattern must exist). Exposed for tests. */
int mpgm_assemble(mpgm_problem *pb, int want_K);
/** Assemble R = f_ext - f_int (no inertia term) and K = M, the consistent
 *  mass matrix, with the same pattern (held contact components: identity
 *  rows). For the initial acceleration (step.c). */
int mpgm_assemble_mass(mpgm_problem *pb);
/** R = f_ext - f_int at the current iterate, without inertia and without
 *  HHT's weights (K untouched): the start-of-step forces of time.hht_alpha. */
int mpgm_assemble_static(mpgm_problem *pb);
/** (Re)build the sparsity pattern and scatter map from the connectivity. */
int mpgm_pattern_build(mpgm_problem *pb);

/** Support forces at the fixed components of the current iterate:
 *  r = f_int + f_inertia - f_ext there (0 at free components); r has
 *  MPGM_DIM doubles per node. Uses the trial state of the last
 *  mpgm_eval_points. */
int mpgm_reactions(mpgm_problem *pb, double *r);

/** Regroup the points by node list and rebuild the scatter maps (points ->
 *  matrix entries) for the current pattern; called when conn.map_version
 *  changed. */
int mpgm_scatter_build(mpgm_problem *pb);
/** Rebuild the scatter maps only (same groups and pattern): after the fixity
 *  of numbered components changed (contact nodes held or released). */
int mpgm_scatter_maps(mpgm_problem *pb);

/** Contact at surface points (core/contact_points.c). setup: after the
 *  front end created the surface tracers; tracers on a plane (within
 *  1e-6 h) start held where they are. */
int mpgm_cpoints_setup(mpgm_problem *pb);
void mpgm_cpoints_free(mpgm_cpoints *cp);
/** Add the springs of the held tracers to R (at the current increments)
 *  and, if want_K, to K; mass_only: the acceleration form of the springs
 *  (beta dt^2 k N N^T) for the initial acceleration, R unchanged. */
void mpgm_cpoints_assemble(mpgm_problem *pb, int want_K, int mass_only);
/** Active-set update at the current increments: hold the free tracers
 *  that crossed a plane (at the crossing), release the held ones the
 *  spring pulls; at most one change per tracer and step. Returns 1 when
 *  the set changed. */
int mpgm_cpoints_update(mpgm_problem *pb);
/** solver.contact_rank (core/lowrank.c). reset: after a factorisation of
 *  the tangent, which holds the springs held now (no columns). update:
 *  after the surface points' set changed with the factorisation kept,
 *  the columns of the springs that differ from the factorised ones (one
 *  solve per new column); *applied = 0 when they are more than
 *  contact_rank or their capacitance is near singular (then refactorise).
 *  apply: turn x = K0^-1 b into the solution with the corrected matrix. */
int mpgm_lowrank_reset(mpgm_problem *pb);
int mpgm_lowrank_update(mpgm_problem *pb, int *applied);
void mpgm_lowrank_apply(mpgm_problem *pb, double *x);
void mpgm_lowrank_free(mpgm_lowrank *lr);

/** solver.newton "bfgs" (core/bfgs.c). setup: the arrays (nothing for
 *  another Newton); reset: forget the pairs (a new Newton solve); solve:
 *  delta from R, with the factorisation (and the contact changes on it
 *  when reuse) corrected by the pairs since it was made; a fresh
 *  factorisation (reuse 0) forgets them. */
int mpgm_bfgs_setup(mpgm_problem *pb);
void mpgm_bfgs_free(mpgm_bfgs *b);
void mpgm_bfgs_reset(mpgm_problem *pb);
int mpgm_bfgs_solve(mpgm_problem *pb, int reuse);
/** The factor of gravity at time t: static, the load factor; dynamic, the
 *  scene's ramp (gravity_ramp; 1 without one). */
static inline double mpgm_gravity_factor(const mpgm_problem *pb, double t) {
  return pb->fx.inertia ? mpgm_gravity_ramp(pb->scene, t) : pb->lambda;
}
/** A run on many processes: the sums at the step's nodes of w values per
 *  node (the front end's node_sums); nothing on one process. */
static inline int mpgm_node_sums(mpgm_problem *pb, int w, double *val) {
  if (mpgm_ctx_size(pb->ctx) == 1 || !pb->fe->node_sums) return 0;
  return pb->fe->node_sums(pb->fe_data, pb->ctx, w, val);
}
/** External force (gravity times its factor at time t) into pb->ls->fext. */
int mpgm_body_force(mpgm_problem *pb, double t);


/** The local indices 0 .. nk - 1 of nodes[] in increasing node number
 *  (insertion sort: node lists are short), into srt. */
static inline void mpgm_argsort_nodes(const int *nodes, int nk, int *srt) {
  for (int a = 0; a < nk; a++) {
    int w = a;
    while (w > 0 && nodes[srt[w - 1]] > nodes[a]) {
      srt[w] = srt[w - 1];
      w--;
    }
    srt[w] = a;
  }
}

/** Add the work of the stresses over the step about to be committed (the
 *  points' trial arrays against the committed ones) to pb->work_int
 *  (energy.c). */
void mpgm_work_internal(mpgm_problem *pb);
/** The term of material point p in it (small: kinematics "small"), for a
 *  pass that has the point's trial arrays at hand (the explicit step's
 *  fused stress and force pass): summed over p in order, the same sum. */
double mpgm_point_work(const mpgm_points *P, int p, const double *dF, int small);
/** Kinetic energy of the material points, sum_p m_p |v_p|^2 / 2 [J]
 *  (per unit thickness; energy.c). */
double mpgm_kinetic_energy(const mpgm_points *P);
/** The factor of the energy balance of explicit runs (mpgm_energy_guard). */
#define MPGM_ENERGY_FACTOR 10.0
/** The energy balance of an explicit run after a converged step: the
 *  total kinetic + work_int - work_ext may not grow above its start
 *  energy0 by more than MPGM_ENERGY_FACTOR times the largest of energy0,
 *  the largest |work_ext| so far and energy_floor. 0, or MPGM_ERR_DIVERGED
 *  with the balance in the context (energy.c). */
int mpgm_energy_guard(mpgm_problem *pb);

/** Manufactured solution (manufactured.c): the points' velocity and
 *  acceleration at t = 0 and the body-force array; then the body force
 *  per unit mass at every material point at time t (pb->mms_b). */
int mpgm_mms_setup(mpgm_problem *pb);
const double *mpgm_mms_forces(mpgm_problem *pb, double t);
/** The manufactured body force of the points at t, NULL without one. The
 *  manufactured solutions and contact are still plane strain: a 3-D build
 *  leaves out their files (manufactured.c, contact_nodes.c,
 *  contact_points.c), the scene reader refuses a 3-D scene that asks for
 *  them, and their calls compile out (#if MPGM_DIM == 2 at each). */
#if MPGM_DIM == 2
#define MPGM_MMS_FORCES(pb, t) ((pb)->fx.manufactured ? mpgm_mms_forces(pb, t) : NULL)
#else
#define MPGM_MMS_FORCES(pb, t) ((void)(pb), (void)(t), (const double *)NULL)
#endif

/** The view of the problem a front end gets (mpgm_frontend.h). */
void mpgm_problem_view(mpgm_problem *pb, mpgm_fe_view *v);
/** The front end's begin_step (timed as "shape"); sets pb->lambda. */
int mpgm_begin_step(mpgm_problem *pb);
/** Release the arrays of points and nodes (data.c). */
void mpgm_points_free(mpgm_points *p);
void mpgm_nodes_free(mpgm_nodes *nd);

/** State of Newton's method on one step (newton.c). */
typedef struct mpgm_newton {
  int warm;        /**< started from the current increments (a re-solve) */
  int it;          /**< the current iterate: corrections made so far       */
  double fnorm;    /**< |f_ext| over the free equations                   */
  double ref;      /**< reference norm: max(|R_0|, fnorm), and a re-solve's
                        at least the step's (pb->ls->step_ref)             */
  double res;      /**< |R| at the current iterate                        */
  double res_prev; /**< |R| at the previous one                           */
  int factored;    /**< a factorisation for this pattern and fixity exists */
  int want_K;      /**< the last residual call assembled K too            */
  double eta;      /**< the last forcing term (solver.forcing)            */
  double rh[4];    /**< |R| of the last four iterates, newest first       */
  double omega;    /**< factor on the corrections (solver.relaxation)     */
  double res_stall; /**< |R| where the iteration was found stalled        */
  int it_stall;    /**< the iterate at which it was (0: none)             */
  int searchable;  /**< the last correction came from the tangent at the
                        iterate it started from and lifted nothing
                        (solver.line_search may shorten it)            */
} mpgm_newton;

/** Body force, predictor (du = 0, or dt v with time.predictor velocity;
 *  prescribed increments lifted into the first iteration) and reference
 *  norms; warm: keep the free increments (a re-solve). Resets pb->last. */
int mpgm_newton_init(mpgm_problem *pb, mpgm_newton *nt, int warm);
/** Constitutive update and R (and K when the next correction needs it) at
 *  the current increments; |R| into nt->res and pb->last. Errors:
 *  MPGM_ERR_NAN, the point update's. */
int mpgm_newton_residual(mpgm_problem *pb, mpgm_newton *nt);
/** *done = 1 when the iterate is converged (rtol, atol or dtol). Errors:
 *  MPGM_ERR_NOT_CONVERGED (max_iterations reached), MPGM_ERR_DIVERGED. */
int mpgm_newton_test(mpgm_problem *pb, const mpgm_newton *nt, int *done);
/** One correction: the observers see K delta = R; factorise (or reuse the
 *  factorisation, modified Newton), solve, du += delta. */
int mpgm_newton_iterate(mpgm_problem *pb, mpgm_newton *nt);
/** Analyse K's pattern in the solver unless it is analysed, with its
 *  layout (the nodes' equations and positions: block size and near-null
 *  space for the backends that use them). */
int mpgm_problem_analyse(mpgm_problem *pb);

/** Active-set update of unilateral contact at the current increments
 *  (contact_nodes.c). Returns a mask of what changed: 1 contact nodes,
 *  2 surface points. */
int mpgm_contact_update(mpgm_problem *pb);

/** Drop what a step rebuilds when missing (equation numbers, point groups,
 *  node graph, pattern, scatter maps, the solver's analysis, the
 *  factorisation): after a checkpoint is written or restored
 *  (checkpoint.c), so that both runs rebuild them from the same state. */
void mpgm_problem_drop_rebuilt(mpgm_problem *pb);
/** Where the run of scene s ends (time.end, or load factor 1) and its
 *  step before any cut (time.dt, 1 / load_steps, or time.end when the CFL
 *  limit gives the steps): the step control's start (run.c), which a
 *  checkpoint must match (checkpoint.c). */
void mpgm_run_span(const mpgm_scene *s, double *end, double *dt0);

#endif
