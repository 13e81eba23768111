/* mpgm_core.h -- the shared updated-Lagrangian core: data model (points,
 * nodes, connectivity), the front-end seam, and the step.
 *
 * The core never asks which method runs it. A front end (gmm/: persistent
 * nodes with element connectivity or node clouds; mpm/: background grid reset
 * every step) creates nodes and points and, at the start of every step, fills
 * the connectivity (point -> nodes, N, grad N at the configuration of the
 * start of the step). The core then solves the step (Newmark predictor,
 * Newton on R and K = K_mat + K_geo (+ K_dyn)), and commits the points; the
 * front end's end_step moves or resets its nodes.
 */
#ifndef MPGM_CORE_H
#define MPGM_CORE_H

#include <math.h>

#include "mpgm_base.h"
#include "mpgm_integrator.h"
#include "mpgm_pool.h"
#include "mpgm_material.h"
#include "mpgm_scene.h"
#include "mpgm_shapefn.h"
#include "mpgm_solver.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Material points (integration points) as structure of arrays; the first
 *  n are material points, the next nprobe are massless tracers (probes)
 *  that are moved exactly as material points but never assembled. */
typedef struct mpgm_points {
  int n;          /**< material points                                 */
  int nprobe;     /**< probes: tracer points after the material points */
  int nsurf;      /**< surface tracers after the probes: points on the
                       bodies' boundaries where contact is enforced
                       (mpgm_cpoints); 0 without contact at points     */
  int nstate;     /**< state doubles per point (max over materials)    */
  double *x;      /**< current position, 2 per point [m]               */
  double *x0;     /**< initial position, 2 per point [m]               */
  double *u;      /**< total displacement, 2 per point [m]             */
  double *v;      /**< velocity, 2 per point [m/s]                     */
  double *a;      /**< acceleration, 2 per point [m/s^2]               */
  double *mass;   /**< mass [kg] (per unit thickness)                  */
  double *vol0;   /**< initial volume [m^3] (per unit thickness)       */
  double *vol;    /**< current volume [m^3]                            */
  double *F;      /**< committed deformation gradient, 4 per point     */
  double *sigma;  /**< committed Cauchy stress {xx, yy, xy, zz} [Pa]   */
  double *S0;     /**< initial (pre-)stress {xx, yy, xy, zz} [Pa] at the
                       initial configuration, pushed forward with F    */
  double *state;  /**< committed material state, nstate per point      */
  int *mat;       /**< material index                                  */
  int *body;      /**< body index                                      */
  int *id;        /**< the point's number at creation: points may be
                       reordered (mpgm_points_sort), ids stay          */
  /* trial values of the current Newton iterate (n material points) */
  double *F_t, *sigma_t, *D_t, *state_t, *vol_t, *dF_t;
} mpgm_points;

/** Nodes (degrees of freedom carriers). */
typedef struct mpgm_nodes {
  int n;          /**< nodes in use                                     */
  int cap;        /**< allocated nodes (n <= cap; MPM: the whole grid)  */
  double *mass;   /**< nodal mass projected from the points [kg]
                       (front ends that project; else 0)              */
  double *X;      /**< initial position, 2 per node [m]                 */
  double *x;      /**< position at the start of the step [m]            */
  double *u;      /**< total displacement at the start of the step [m]  */
  double *du;     /**< displacement increment of the step [m]           */
  double *v, *a;  /**< velocity / acceleration at the start of the step */
  double *v_new, *a_new; /**< Newmark-corrected values of the iterate   */
  unsigned char *fix;    /**< 2 per node: 1 when the component is fixed */
  signed char *contact;  /**< per node: 0, or +-(axis + 1) for a node on a
                              unilateral contact plane whose normal is that
                              axis, the body on the + or - side         */
  double *ubar;   /**< 2 per node: prescribed total displacement at the
                       end of the run (fixed components; ramped)        */
  int *dof;       /**< 2 per node: equation number, -1 when fixed       */
  int ndof;       /**< free equations                                   */
} mpgm_nodes;

/** Connectivity in CSR: point p is connected to node[ptr[p] .. ptr[p+1]). */
typedef struct mpgm_conn {
  int np;         /**< points covered (material + tracers)              */
  int cap;        /**< allocated entries                                */
  int *ptr;       /**< np + 1 offsets                                   */
  int *node;      /**< node ids                                         */
  double *N;      /**< shape function values                            */
  double *dN;     /**< grad N at the start-of-step configuration, 2 each */
  double *g;      /**< grad N at the current iterate, 2 each (work)     */
  int version;    /**< incremented by a front end when the node set,
                       fixity or matrix pattern changes                  */
  int map_version;/**< incremented when only the point -> node lists
                       changed (same nodes, fixity and pattern)          */
} mpgm_conn;

/** The effects a scene calls for, decided when it loads. */
typedef struct mpgm_effects {
  int inertia;        /**< dynamic analysis: mass, Newmark, K_dyn       */
  int gravity;        /**< non-zero gravity: body-force loop            */
  int geometric;      /**< finite kinematics: K_geo and config update   */
  int plasticity;     /**< a plastic material is used                   */
  int prescribed;     /**< non-zero prescribed displacements            */
  int contact;        /**< unilateral contact at grid nodes (active set)  */
  int contact_points; /**< unilateral contact at surface points (penalty,
                           active set; core/contact_points.c)          */
  int prestress;      /**< a body has a geostatic initial stress         */
} mpgm_effects;

/** The effects a scene calls for: the one place they are decided (used by
 *  mpgm_problem_create and by `mpgm check`). */
void mpgm_effects_of_scene(const mpgm_scene *s, mpgm_effects *fx);

typedef struct mpgm_problem mpgm_problem;

/** How a front end updates the velocity of its points after a step. */
typedef enum {
  MPGM_PV_INTERPOLATE = 0, /**< v_p = sum N_I v_I (persistent nodes)      */
  MPGM_PV_NEWMARK = 1      /**< v_p += dt/2 (a_p^n + a_p^n+1), a_p^n+1 =
                                sum N_I a_I (eq 48; grid reset: MPM)     */
} mpgm_point_velocity;

/** Front-end operations (the seam between method and physics). */
typedef struct mpgm_frontend_ops {
  const char *name;
  int point_velocity; /**< mpgm_point_velocity                          */
  /** Create nodes, points (with probes) and fixity from the scene. */
  int (*setup)(mpgm_problem *pb);
  /** Fill pb->conn for the step (N, dN at the start-of-step configuration)
   *  and nodal v, a (history or projection). Bump conn.version when the
   *  node set, fixity or pattern changed (the core then renumbers the
   *  equations and rebuilds the pattern). */
  int (*begin_step)(mpgm_problem *pb);
  /** After the core committed the points: move/reset nodes. */
  int (*end_step)(mpgm_problem *pb);
  /** Cells for output (may be NULL: no mesh output). Borrowed arrays. */
  int (*cells)(mpgm_problem *pb, int *ncells, const int **ptr,
               const int **conn, const int **type);
  void (*destroy)(mpgm_problem *pb);
} mpgm_frontend_ops;

/** Unilateral contact without slip at surface points (core/contact_points.c,
 *  docs/theory.md "Contact at surface points"): the pts.nsurf surface
 *  tracers (after the probes) move with the body like material points; one
 *  that reaches a contact plane is held at the place it reached by a
 *  penalty spring (both components: no slip) and let go where the spring
 *  would pull it back onto the plane. The grid nodes stay free. */
typedef struct mpgm_cpoints {
  int first;          /**< index in pts of the first surface tracer     */
  int n;              /**< surface tracers                               */
  signed char *plane; /**< per tracer: scene boundary it is held on, -1  */
  unsigned char *flip;/**< per tracer: state changed in this step        */
  unsigned char *off; /**< per tracer: no shape functions this step (no
                           active cell near it): not enforced          */
  double *anchor;     /**< 2 per tracer: where it is held [m]            */
  int held;           /**< tracers held now                              */
  long holds, releases; /**< changes of state over the run               */
  long unenforced;    /**< tracer-steps without shape functions          */
} mpgm_cpoints;

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

/** Chunks of the threaded assembly; a constant, so that the order of the
 *  sums does not depend on the number of threads. */
#define MPGM_ASM_CHUNKS 16
/* Largest union of node clouds a batch of points may have in the
 * clouds' assembly (assembly.c, assemble_batch); at least the largest
 * cloud, MPGM_SHAPE_MAXNODE. */
#define MPGM_ASM_BATCH 128

/** First assembly task of phase ph (0..3; 4 gives the end): chunk
 *  interiors 0..C-1, interfaces between chunks c and c+1 with c even, with
 *  c odd, and the rest (one serial task), C = MPGM_ASM_CHUNKS. */
static inline int mpgm_asm_phase(int ph) {
  const int C = MPGM_ASM_CHUNKS, first[5] = {0, C, C + C / 2, 2 * C - 1, 2 * C};
  return first[ph];
}

struct mpgm_problem {
  mpgm_ctx *ctx;
  const mpgm_scene *scene;
  mpgm_effects fx;
  mpgm_points pts;
  mpgm_nodes nodes;
  mpgm_conn conn;
  const mpgm_frontend_ops *fe;
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
  /* linear system */
  mpgm_csc K;
  int pattern_version; /**< conn.version the pattern was built for      */
  int graph_version; /**< conn.version the groups and node graph are of */
  int map_version;   /**< conn.map_version the scatter maps were built for */
  int factor_valid;  /**< the solver holds a factorisation of this pattern
                          (modified Newton may reuse it across steps)    */
  unsigned char *fix_factored; /**< nodes.fix when it was factorised: held
                          contact components have identity rows, so
                          a different held set is a different matrix    */
  /* points grouped by node list: the points of a group have identical
   * lists (the particles in one grid cell, the Gauss points of one
   * element), so they share a scatter map and one local matrix */
  int ngroups;
  int *order;        /**< material points, group after group            */
  int *grp_ptr;      /**< ngroups + 1 offsets into order                 */
  int *scatter;      /**< per group: 4 n_p^2 positions in K.val (-1: fixed
                          component)                                    */
  int *scatter_ptr;  /**< ngroups + 1 offsets of the groups' maps        */
  size_t scatter_cap; /**< allocated entries of scatter                 */
  int nomap;         /**< node clouds: K assembled by merging each column's
                          node list, no stored maps (assembly.c)        */
  int *nbr_ptr, *nbr; /**< node graph of the pattern: sorted neighbours  */
  int *nbr_off;      /**< per neighbour entry: offset of its rows in the
                          owner's columns                               */
  int *node_order;   /**< solver.ordering geometric: nodes in nested-
                          dissection order (of the graph version)       */
  int *perm;         /**< the equations in that order (K.n), handed to
                          the solver's analysis; NULL: its own order    */
  double *kloc;      /**< local matrices of the groups, one per thread
                          (kloc_size doubles each)                      */
  int kloc_size;     /**< 4 max n_p^2                                    */
  double *kbatch;    /**< node clouds: per thread, the summed local matrix
                          of a batch of nearby points over the union of
                          their clouds (4 MPGM_ASM_BATCH^2 doubles, zero
                          between batches), merged into K once (assembly.c) */
  int *kslot;        /**< node clouds: per thread and node, its place in
                          the batch's union (-1: none); kslot_n each     */
  int kslot_n;       /**< nodes kslot has room for, per thread           */
  /* threads (docs/architecture.md, "Threads"): the groups are cut into
   * MPGM_ASM_CHUNKS chunks along the group order; the assembly runs as
   * tasks over groups that share no node with another task of the same
   * phase, so tasks of a phase may run at once and every entry of R and K
   * receives its terms in one fixed order, whatever the number of
   * threads */
  mpgm_pool *pool;   /**< worker threads (scene "threads")               */
  int task_ptr[2 * MPGM_ASM_CHUNKS + 1]; /**< offsets into task_grp       */
  int *task_grp;     /**< groups, task after task, ascending in a task   */
  int tpt_ptr[2 * MPGM_ASM_CHUNKS + 1]; /**< offsets into task_pts        */
  int *task_pts;     /**< the tasks' points (their groups' points)       */
  double *R, *fext, *delta;
  double *dubar;     /**< 2 per node: prescribed increment of the step   */
  const double *lift; /**< when set (first iteration), assembly adds
                           -K_free,fixed * lift to R: the prescribed increment
                           enters Newton linearly, not as a jump of the
                           boundary nodes alone                           */
  mpgm_solver *solver;
  int symmetric;     /**< all tangents symmetric (static or dynamic)    */
  double *react;     /**< 2 per node: support force on the body at fixed
                          components (mpgm_reactions)                   */
  long contact_rounds; /**< extra solves of steps whose contact set changed */
  long step_cuts;    /**< steps rejected and retried with half the step
                          (time.max_cuts; run.c)                        */
  unsigned char *cflip; /**< per node: contact state changed in this step */
  mpgm_cpoints cp;   /**< contact at surface points (fx.contact_points)  */
};

/** Load factor at the end of the step being solved: static, the load
 *  factor t + dt itself (t counts load from 0 to 1); dynamic, the ramp of
 *  prescribed displacements, (t + dt) / end. At most 1. */
static inline double mpgm_load_factor(const mpgm_problem *pb) {
  const double end = pb->scene->analysis == MPGM_ANALYSIS_STATIC ? 1.0 : pb->scene->t_end;
  return fmin(1.0, (pb->t + pb->dt) / end);
}

/** Create a problem for a loaded scene with a front end. */
int mpgm_problem_create(mpgm_ctx *ctx, const mpgm_scene *scene,
                        const mpgm_frontend_ops *fe, mpgm_problem **out);
void mpgm_problem_destroy(mpgm_problem **pb);

/** Allocate points (n material, nprobe probes, nsurf surface tracers) with
 *  nstate doubles. */
int mpgm_points_alloc(mpgm_ctx *ctx, mpgm_points *p, int n, int nprobe, int nsurf, int nstate);
/** Material point p of scene body `body` at (x, y) with volume vol [m^3]:
 *  position, mass (density x volume), the body's initial velocity,
 *  material, and the material's initial state. */
void mpgm_point_set(mpgm_points *P, int p, const mpgm_scene *s, int body, double x, double y,
                    double vol);
/** Equivalent plastic strain of the n material points into out (may be
 *  NULL; 0 for points whose material has no plastic_strain operation).
 *  Returns the largest value (0 when there is none). */
double mpgm_points_plastic_strain(const mpgm_points *P, const mpgm_material *mats, double *out);
/** Reorder the material points (not the probes) by key[p] in [0, nkey),
 *  stably (counting sort), so that points that share nodes lie together in
 *  memory: every committed per-point array moves, ids included; the trial
 *  arrays are not moved (they are recomputed before use); the arrays move
 *  on the pool's threads (NULL: the caller's). perm (n ints,
 *  may be NULL) receives the old index of each new position, for the
 *  caller's own per-point arrays. */
int mpgm_points_sort(mpgm_ctx *ctx, mpgm_pool *pool, mpgm_points *p, const int *key, int nkey,
                     int *perm);
/** Nested-dissection order of the n nodes of a graph (CSR ptr/adj) with
 *  coordinates x (2 per node): perm[k] = the node numbered k
 *  (core/ordering.c). Errors: MPGM_ERR_NOMEM. */
int mpgm_order_nodes(mpgm_ctx *ctx, int n, const int *ptr, const int *adj, const double *x,
                     int *perm);
/** Allocate nodes. */
int mpgm_nodes_alloc(mpgm_ctx *ctx, mpgm_nodes *nd, int n);
/** Make room for nnz connectivity entries over np points. */
int mpgm_conn_reserve(mpgm_ctx *ctx, mpgm_conn *c, int np, int nnz);
/** Make room for at least nnz entries keeping the first `keep` entries of
 *  node, N and dN (a front end filling lists of unknown length); grows
 *  geometrically. */
int mpgm_conn_grow(mpgm_ctx *ctx, mpgm_conn *c, int keep, int nnz);
/** Number equations of free components (node-major); sets nodes->ndof. */
void mpgm_nodes_number(mpgm_nodes *nd);

/** One step to load factor / time pb->t + pb->dt: the front end's
 *  begin_step, the scene's integrator (solve and commit), the front end's
 *  end_step. On a recoverable failure nothing is committed. */
int mpgm_step(mpgm_problem *pb);
/** Add an observer of the steps (copied; at most MPGM_OBSERVERS_MAX). */
int mpgm_problem_observe(mpgm_problem *pb, const mpgm_observer *obs);

/** Evaluate trial state at the current increment nodes.du: F, stress,
 *  tangent and current gradients (exposed for tests). */
int mpgm_eval_points(mpgm_problem *pb);
/** Assemble R = f_ext - f_int (- f_inertia) and, if want_K, the tangent
 *  into pb->K (pattern must exist). Exposed for tests. */
int mpgm_assemble(mpgm_problem *pb, int want_K);
/** Assemble R = f_ext - f_int (no inertia term) and K = M, the consistent
 *  mass matrix, with the same pattern (held contact components: identity
 *  rows). For the initial acceleration (step.c). */
int mpgm_assemble_mass(mpgm_problem *pb);
/** (Re)build the sparsity pattern and scatter map from the connectivity. */
int mpgm_pattern_build(mpgm_problem *pb);

/** Support forces at the fixed components of the current iterate:
 *  r = f_int + f_inertia - f_ext there (0 at free components); r has 2
 *  doubles per node. Uses the trial state of the last mpgm_eval_points. */
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
/** External force (gravity times load factor) into pb->fext. */
int mpgm_body_force(mpgm_problem *pb);

#ifdef __cplusplus
}
#endif
#endif
