/* mpgm_frontend.h -- the front-end family: how nodes and connectivity come
 * to be. UL-FEM (persistent nodes, element connectivity), GMM (persistent
 * nodes, node clouds) and MPM (a background grid reset every step) differ
 * only here, as Algorithms 1 and 2 of Iaconeta et al. (2017) differ only
 * in their first and last phases.
 *
 * A front end is one type record (const mpgm_frontend_type) with its
 * traits and operations; the list of all of them is frontends/
 * frontend_list.c. It sees a narrow view of the problem (mpgm_fe_view):
 * the data it makes and fills, never the core's problem. It reports its
 * timers and counters through the context (mpgm_timer_move, mpgm_count)
 * and marks surface points it cannot serve through mpgm_cpoints_unenforce.
 */
#ifndef MPGM_FRONTEND_H
#define MPGM_FRONTEND_H

#include "mpgm_data.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Contact at surface points (core/contact_points.c): the state the core
 *  keeps; a front end only says which surface points it gave no shape
 *  functions in the current step. */
typedef struct mpgm_cpoints mpgm_cpoints;

/** Every surface point is enforced (a front end's begin_step starts from
 *  here). */
void mpgm_cpoints_enforce_all(mpgm_cpoints *cp);
/** Surface point i (0 .. pts.nsurf - 1) has no shape functions in this
 *  step: its contact is not enforced (counted once per point and step). */
void mpgm_cpoints_unenforce(mpgm_cpoints *cp, int i);
/** 1 when surface point i is not enforced in this step. */
int mpgm_cpoints_unenforced(const mpgm_cpoints *cp, int i);

/** What a front end sees of the problem. The core makes it for each call;
 *  a front end keeps none of its pointers beyond the call (the context
 *  excepted). */
typedef struct mpgm_fe_view {
  mpgm_ctx *ctx;            /**< errors, timers, counters, logger        */
  const mpgm_scene *scene;  /**< the loaded scene                        */
  const mpgm_effects *fx;   /**< the effects the scene calls for         */
  mpgm_points *pts;         /**< the points: create allocates them       */
  mpgm_nodes *nodes;        /**< the nodes: create allocates them        */
  mpgm_conn *conn;          /**< the connectivity begin_step fills       */
  mpgm_pool *pool;          /**< worker threads                          */
  mpgm_cpoints *cp;         /**< contact at surface points; NULL without */
  long step;                /**< steps completed                         */
  double t;                 /**< time (dynamic) or load factor (static) at
                                 the start of the step                   */
  double dt;                /**< the step                                */
  double lambda;            /**< load factor at the end of the step (the
                                 ramp of prescribed displacements)       */
} mpgm_fe_view;

/** How a front end updates the velocity of its points after a step. */
typedef enum {
  MPGM_PV_INTERPOLATE = 0, /**< v_p = sum N_I v_I (persistent nodes)      */
  MPGM_PV_NEWMARK = 1      /**< v_p += dt/2 (a_p^n + a_p^n+1), a_p^n+1 =
                                sum N_I a_I (eq 48; grid reset: MPM)     */
} mpgm_point_velocity;

/** Shape-function kinds a front end accepts (mpgm_frontend_type.shapes). */
enum {
  MPGM_FE_SHAPE_CELL = 1 << 0, /**< kinds evaluated on a cell (fe)         */
  MPGM_FE_SHAPE_CLOUD = 1 << 1 /**< meshfree kinds over node clouds (mls,
                                    lme)                                 */
};

/** Analyses a front end runs on many processes (mpgm_frontend_type.processes). */
enum {
  MPGM_FE_MANY_EXPLICIT = 1 << 0, /**< time.analysis "explicit"             */
  MPGM_FE_MANY_IMPLICIT = 1 << 1  /**< the implicit analyses (static, quasi-
                                       static, dynamic)                   */
};

/** Boundary conditions a front end supports (mpgm_frontend_type.conditions). */
enum {
  MPGM_FE_COND_FIX = 1 << 0,            /**< fixed components: "fix", stick,
                                             slip                        */
  MPGM_FE_COND_DISPLACEMENT = 1 << 1,   /**< non-zero prescribed values  */
  MPGM_FE_COND_CONTACT_NODES = 1 << 2,  /**< "contact" held at the nodes on
                                             the plane                   */
  MPGM_FE_COND_CONTACT_POINTS = 1 << 3  /**< "contact" held at surface
                                             points (penalty)            */
};

/** Cells for output (borrowed arrays): n cells, node ids node[ptr[c] ..
 *  ptr[c + 1]), VTK cell type type[c]. */
typedef struct mpgm_cells {
  int n;
  const int *ptr, *node, *type;
} mpgm_cells;

/** A front end's structured background grid for output (borrowed): the
 *  grid (mpgm_grid.h: its nodes and cells), and the nodes of the last step
 *  on it: node k < n of mpgm_nodes is grid node lglob[k] (n 0 before the
 *  first step). */
struct mpgm_grid;
typedef struct mpgm_background {
  const struct mpgm_grid *grid;
  int n;
  const int *lglob;
} mpgm_background;

typedef struct mpgm_frontend_type {
  const char *name;       /**< the scene's "method" that selects it         */
  const char *doc;        /**< one line for docs and messages            */
  /* traits: what the scene loader lets through (frontend_check.c) */
  int persistent_nodes;   /**< 1: nodes carry the body and persist (their
                               boundaries must meet a body); 0: a grid
                               reset every step (must meet mesh.domain)  */
  int point_velocity;     /**< mpgm_point_velocity                       */
  unsigned shapes;        /**< MPGM_FE_SHAPE_* bits                      */
  unsigned geometries;    /**< bit 1 << g for each mpgm_geometry g        */
  unsigned conditions;    /**< MPGM_FE_COND_* bits                       */
  int obstacles;          /**< 1: takes rigid obstacles (node layers)     */
  int explicit_schemes;   /**< 1: takes time.analysis "explicit" (lumped
                               mass on nodes it projects every step)     */
  unsigned processes;     /**< MPGM_FE_MANY_* bits: the analyses it runs
                               on many processes (mpiexec -n P, P > 1);
                               a scene it cannot run so is refused at load */
  /** Optional: its own keys of the scene's "shape" section (beside the
   *  kind's), read into mpgm_scene.pattern (nshape_keys of them); another
   *  method's scene refuses them by this front end's name. */
  const mpgm_key_spec *shape_keys;
  int nshape_keys;
  /** Optional: its keys of the scene's "mesh" (the rules for its nodes),
   *  read into mpgm_scene.mesh_par (nmesh_keys of them); another method's
   *  scene refuses them by this front end's name. */
  const mpgm_key_spec *mesh_keys;
  int nmesh_keys;
  /** Optional: rules of this front end beyond its traits, as
   *  MPGM_ERR_INPUT with "FILE: json.path: expected ..., found ...". */
  int (*check)(mpgm_ctx *ctx, const mpgm_scene *s);
  /** Make the nodes (with their fixity and initial velocity) and the
   *  points (material points, probes, surface points) into v->nodes and
   *  v->pts; *self receives the front end's own data (destroy releases it
   *  even when create failed half way). */
  int (*create)(const mpgm_fe_view *v, void **self);
  void (*destroy)(void *self); /**< accepts NULL and half-built data    */
  /** Fill v->conn for the step (N, grad N at the start-of-step
   *  configuration) and the nodal v, a (history or projection); bump
   *  conn.version when the node set, fixity or pattern changed (the core
   *  then renumbers the equations and rebuilds the pattern), conn.
   *  map_version when only the point -> node lists changed. */
  int (*begin_step)(void *self, const mpgm_fe_view *v);
  /** After the integrator committed the step: move, keep or forget the
   *  nodes. */
  int (*end_step)(void *self, const mpgm_fe_view *v);
  /** Optional (a front end that runs on many processes): val holds w
   *  values per node of the step (nodes->n), this process's part of sums
   *  over the points; on return each node's w values are the sums of
   *  every process's parts there (the nodes shared with other processes
   *  get theirs). Collective: every process calls it. */
  int (*node_sums)(void *self, mpgm_ctx *ctx, int w, double *val);
  /** Optional: cells for output (a mesh.pvd next to points.pvd). */
  int (*cells)(const void *self, mpgm_cells *out);
  /** Optional: the background grid (output.grid: a grid.pvd series of
   *  every grid cell with the last step's nodal values). */
  void (*background)(const void *self, mpgm_background *out);
  /** Optional: the front end's own state that later steps depend on and
   *  begin_step does not rebuild (LME warm starts, the contact state of a
   *  reset grid), appended to a checkpoint / read back after create
   *  (mpgm_problem_save / _restore; mpgm_blob.h). restore sees the points
   *  and nodes as the checkpoint had them (v): every count and index it
   *  reads must be checked against them (MPGM_ERR_INPUT "checkpoint:
   *  section 'TAG': ..."), as a damaged file may hold any. */
  int (*save)(const void *self, mpgm_ctx *ctx, struct mpgm_blob *b);
  int (*restore)(void *self, const mpgm_fe_view *v, struct mpgm_blob *b);
} mpgm_frontend_type;

#ifdef __cplusplus
}
#endif
#endif
