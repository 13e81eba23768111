/* gmm.c -- the Galerkin Meshfree Method front end (Iaconeta et al. 2017,
 * section 4.2, Algorithm 2): persistent nodes as in UL-FEM, but every
 * material point is connected to the cloud of nodes within the support
 * radius of a meshfree kind (MLS, LME), searched again at every step.
 *
 * Setup is that of the FEM front end (gmm/fem.c) when every body is a
 * rectangle and there is no obstacle: the rectangle bodies are meshed, the
 * nodes are the mesh nodes, the material points sit at the Gauss points of
 * the cells (mesh.ppc), boundaries fix nodes by predicate. The FEM front
 * end's data (the cells) is kept inside this front end's data, for the
 * mesh output only: the cells do not define the interpolation. Otherwise
 * (disk or polygon bodies, obstacles) the bodies are filled on the grid
 * (gmm_grid.c): MPM's material points, nodes at the grid nodes of their
 * cells, the obstacles' layers of fixed nodes; nodes with little mass are
 * left out of a step and carried along (mpgm_gmm_grid_park / _unpark).
 *
 * begin_step (docs/theory.md, section 13):
 *   1. search (timed as "search"): rebuild the kd-tree over the nodes'
 *      start-of-step positions; for every point and probe, the nodes within
 *      r0 = mpgm_shape_support_radius; while fewer than min_nodes, r *= 1.25
 *      (counted: radius_growths);
 *   2. shape functions (timed as "shape") at the point's current position,
 *      with the support radius of the kind set to the point's r; LME keeps
 *      its multiplier per point as warm start (a failed warm start is
 *      retried once from lambda = 0: shape_cold_restarts; probes, which use
 *      N only, are exempt from max_cond). On MPGM_ERR_SHAPE the cloud
 *      is enlarged: the next-nearest node (kNN, k = size + 1) at distance d
 *      sets r = max(r, 4/3 d), the cloud is searched again and the
 *      evaluation repeated (counted: cloud_enlargements), at most
 *      shape.max_enlarge times, and never past MPGM_SHAPE_MAXNODE nodes;
 *      then the step fails with the recoverable MPGM_ERR_SHAPE;
 *   3. the connectivity: each cloud sorted by node id, nodes with N = 0 and
 *      grad N = 0 dropped; conn.version is bumped when any list differs
 *      from the last step's (the core then rebuilds the pattern).
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "gmm_impl.h"
#include "mpgm_discretisation.h"
#include "mpgm_gmm.h"
#include "mpgm_kdtree.h"

#if MPGM_DIM != 2
#error "gmm/gmm.c is written for plane strain only (MPGM_DIM = 2)"
#endif

typedef struct gmm_data {
  mpgm_fem_cells *fem;   /**< rectangle bodies: the FE cells (for output)      */
  gmm_grid *grid;        /**< or, for grid-filled bodies, the output cells    */
  mpgm_kdtree *tree;     /**< over nodes.x (borrowed), rebuilt every step     */
  mpgm_clouds *clouds;   /**< the node clouds and their shape functions       */
  unsigned char *merged; /**< per node: left out of this step's clouds for
                              being close to another node (grid-filled)     */
  double dmin;           /**< that distance [m] (0: off)                      */
  mpgm_conn out;         /**< the step's connectivity before it is copied    */
  mpgm_conn carry;       /**< scratch of mpgm_tracers_carry                  */
  /* mesh.node_motion "interpolated" (else NULL) */
  mpgm_kdtree *tree_xs;  /**< over xs                                        */
  double *xs;            /**< MPGM_DIM per node: start-of-step positions     */
  unsigned char *skip;   /**< per node: not among the step's nodes           */
  /* shape.skin > 0 (else NULL) */
  mpgm_skin *skin;       /**< the pattern's lists, a skin wider than clouds */
  unsigned char *tan;    /**< shape.tangent_radius: per entry of the material
                              points, in the tangent (conn.tan)            */
  int tancap;            /**< room of tan                                   */
  double tan_r;          /**< the tangent's radius in h (0: whole clouds)   */
  unsigned char *fix;    /**< MPGM_DIM per node: the last step's fixity      */
  uint64_t lists_hash;   /**< restarts: hash of the last step's node lists  */
  int restored;          /**< lists_hash stands for the lists (a restart)   */
  int nfix;              /**< nodes of fix                                  */
} gmm_data;

static void gmm_destroy(void *self) {
  gmm_data *d = self;
  if (!d) return;
  mpgm_fem_cells_destroy(d->fem);
  mpgm_gmm_grid_destroy(&d->grid);
  mpgm_kdtree_destroy(&d->tree);
  mpgm_clouds_destroy(d->clouds);
  free(d->merged);
  mpgm_conn_release(&d->out);
  mpgm_conn_release(&d->carry);
  mpgm_kdtree_destroy(&d->tree_xs);
  free(d->xs);
  free(d->skip);
  mpgm_skin_destroy(d->skin);
  free(d->tan);
  free(d->fix);
  free(d);
}

/* The tangent's radius in h: shape.tangent_radius, or where the kind's
 * weight falls to shape.tangent_tol (LME: sqrt(-ln tol / gamma)); 0 when
 * the kind has no such radius (gmm_check refuses that). */
static double tangent_radius(const mpgm_scene *s) {
  const mpgm_pattern_opts *o = &s->pattern;
  if (!(o->tangent_tol > 0.0)) return o->tangent_radius;
  mpgm_shape_params unit = s->shape_par; /* in units of h */
  unit.h = 1.0;
  double r = 0.0;
  return s->shape->weight_radius && s->shape->weight_radius(&unit, o->tangent_tol, &r) == 0 ? r : 0.0;
}

static int gmm_create(const mpgm_fe_view *v, void **self) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_scene *s = v->scene;
  gmm_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *self = d; /* from here gmm_destroy frees everything */
  MPGM_CALL(mpgm_clouds_create(ctx, s, &d->clouds));
  const double r0 = mpgm_clouds_radius(d->clouds);
  if (mpgm_gmm_uses_grid(s)) {
    /* disk and polygon bodies, obstacles: points and nodes on the grid */
    MPGM_CALL(mpgm_gmm_grid_setup(v, r0, &d->grid));
  } else {
    /* rectangles: nodes, points, probes, boundaries exactly those of UL-FEM */
    MPGM_CALL(mpgm_fem_rectangles(v, &d->fem));
  }
  if (d->grid && s->mesh_par.min_node_distance > 0.0) {
    d->dmin = s->mesh_par.min_node_distance * s->h;
    MPGM_ALLOC(ctx, d->merged, v->nodes->n);
  }
  MPGM_CALL(mpgm_kdtree_create(ctx, v->nodes->x, v->nodes->n, 0, &d->tree));
  if (s->pattern.skin > 0.0) {
    d->tan_r = tangent_radius(s);
    MPGM_CALL(mpgm_skin_create(ctx, s->pattern.skin * s->h, d->tan_r * s->h, &d->skin));
    MPGM_ALLOC(ctx, d->fix, MPGM_DIM * (size_t)v->nodes->n);
    d->nfix = v->nodes->n;
  }
  if (s->mesh_par.node_motion == MPGM_NODES_INTERPOLATED && v->fx->geometric) {
    MPGM_ALLOC(ctx, d->xs, MPGM_DIM * (size_t)v->nodes->n);
    MPGM_ALLOC(ctx, d->skip, v->nodes->n);
    memcpy(d->xs, v->nodes->x, sizeof(double) * MPGM_DIM * (size_t)v->nodes->n);
    MPGM_CALL(mpgm_kdtree_create(ctx, d->xs, v->nodes->n, 0, &d->tree_xs));
  }
  return 0;
}

/* Close nodes (mesh.min_node_distance): in node order, a free body node
 * not merged itself merges every free body node of higher number within
 * dmin of it. Two nodes that close carry nearly the same shape function at
 * every point (N_a / w_a depends on x_a continuously), so the difference
 * of their coefficients is a nearly singular mode of K and M; a merged
 * node is left out of every cloud for the step, parked by the light-node
 * rule (it has no mass) and carried along with its neighbours. */
static void merge_close(const mpgm_fe_view *v, gmm_data *d) {
  const mpgm_nodes *nd = v->nodes;
  const gmm_grid *g = d->grid;
  memset(d->merged, 0, (size_t)nd->n);
  int idx[64];
  double d2[64];
  for (int i = 0; i < nd->n; i++) {
    /* 2-D only: the fixity of x and y written out, here and below */
    if (d->merged[i] || g->obst[i] || g->fix0[MPGM_DIM * i] || g->fix0[MPGM_DIM * i + 1]) continue;
    const int k = mpgm_kdtree_radius(d->tree, nd->x + MPGM_DIM * i, d->dmin, 64, idx, d2);
    for (int a = 0; a < k && a < 64; a++) {
      const int j = idx[a];
      if (j <= i || d->merged[j] || g->obst[j] || g->fix0[MPGM_DIM * j] ||
          g->fix0[MPGM_DIM * j + 1])
        continue;
      d->merged[j] = 1;
      mpgm_count(v->ctx, MPGM_C_NODES_MERGED, 1);
    }
  }
}

/* shape.skin: the pattern comes from the skin's lists. They are built
 * again when they no longer hold every cloud (a new pattern); with the
 * same lists, a change of fixity (a node parked or unparked) renumbers
 * the equations over the same node graph, and changed clouds alone keep
 * the pattern and its analysis (new groups only: conn.map_version;
 * counted in patterns_kept). same: the node lists are the last step's. */
/* FNV-1a over the node lists of m points. */
static uint64_t lists_hash(const mpgm_conn *C, int m) {
  uint64_t h = 1469598103934665603ull;
  const int *a[2] = {C->ptr, C->node};
  const size_t n[2] = {(size_t)m + 1, (size_t)C->ptr[m]};
  for (int w = 0; w < 2; w++)
    for (size_t i = 0; i < n[w]; i++) h = (h ^ (uint64_t)(uint32_t)a[w][i]) * 1099511628211ull;
  return h;
}

static int skin_versions(const mpgm_fe_view *v, gmm_data *d, int same) {
  mpgm_ctx *ctx = v->ctx;
  mpgm_conn *C = v->conn;
  const mpgm_nodes *nd = v->nodes;
  int rebuilt;
  const int ne = C->ptr[v->pts->n]; /* the material points' entries */
  if (d->tan_r > 0.0 && ne > d->tancap) {
    free(d->tan);
    d->tancap = 0;
    d->tan = malloc((size_t)ne + (size_t)ne / 4 + 1);
    MPGM_CHECK(ctx, d->tan, MPGM_ERR_NOMEM, "out of memory (the tangent's entries)");
    d->tancap = ne + ne / 4 + 1;
  }
  mpgm_timer_start(ctx, MPGM_T_ANALYSE);
  /* a dynamic run's first step solves M a_0 = R for the initial
   * acceleration (time.initial_acceleration) on the tangent's pattern:
   * Newton does not correct that solve, so that step takes whole clouds
   * (shape.tangent_radius); every other step, and static runs, the
   * tangent radius */
  const int wide = v->step == 0 && v->fx->inertia && v->scene->initial_accel;
  const int err = mpgm_skin_update(d->skin, ctx, v->pts->n, v->pts->x, mpgm_clouds_radii(d->clouds),
                                   v->nodes->x, C, d->tree, wide, d->tan, &rebuilt);
  mpgm_timer_stop(ctx, MPGM_T_ANALYSE);
  MPGM_CALL(err);
  /* after a restart the last step's lists are known by their hash (so
   * that the counts are those of the run that was not interrupted) */
  if (d->restored) same = lists_hash(C, C->np) == d->lists_hash;
  d->restored = 0;
  const int fix_same = memcmp(d->fix, nd->fix, MPGM_DIM * (size_t)nd->n) == 0;
  memcpy(d->fix, nd->fix, MPGM_DIM * (size_t)nd->n);
  C->pptr = mpgm_skin_ptr(d->skin);
  C->pnode = mpgm_skin_node(d->skin);
  C->tan = C->pptr && !wide ? d->tan : NULL; /* NULL without a tangent radius */
  if (rebuilt || !C->pptr) {
    C->pversion++;
    C->version++;
  } else if (!fix_same) {
    C->version++;
  } else if (!same) {
    C->map_version++;
    mpgm_count(ctx, MPGM_C_PATTERNS_KEPT, 1);
  }
  return 0;
}

static int gmm_begin_step(void *self, const mpgm_fe_view *v) {
  mpgm_ctx *ctx = v->ctx;
  gmm_data *d = self;
  mpgm_conn *C = v->conn;
  const int m = v->pts->n + v->pts->nprobe + v->pts->nsurf;
  /* the search structure over the nodes' start-of-step positions (timed
   * as "search", with the clouds' searches) */
  const double t0 = mpgm_wtime();
  MPGM_CALL(mpgm_kdtree_rebuild(ctx, d->tree, v->nodes->x, v->nodes->n));
  if (d->merged) merge_close(v, d);
  mpgm_timer_move(ctx, MPGM_T_SHAPE, MPGM_T_SEARCH, mpgm_wtime() - t0);
  if (v->pts->nsurf) mpgm_cpoints_enforce_all(v->cp);
  MPGM_CALL(mpgm_clouds_build(d->clouds, v, d->tree, d->merged, &d->out));
  /* grid-filled bodies: nodes with little mass are parked for the step */
  if (d->grid) MPGM_CALL(mpgm_gmm_grid_park(v, d->grid, d->tree, mpgm_clouds_radius(d->clouds), &d->out));
  /* probes and surface points without functions move with the material */
  MPGM_CALL(mpgm_tracers_carry(v, &d->out, &d->carry, NULL));
  const int k = d->out.ptr[m];
  /* a new pattern only when some point's node list changed */
  int same = C->np == m && C->ptr[m] == k;
  for (int p = 0; same && p <= m; p++) same = C->ptr[p] == d->out.ptr[p];
  if (same) same = memcmp(C->node, d->out.node, sizeof(int) * (size_t)k) == 0;
  MPGM_CALL(mpgm_conn_reserve(ctx, C, m, k));
  memcpy(C->ptr, d->out.ptr, sizeof(int) * (size_t)(m + 1));
  memcpy(C->node, d->out.node, sizeof(int) * (size_t)k);
  memcpy(C->N, d->out.N, sizeof(double) * (size_t)k);
  memcpy(C->dN, d->out.dN, MPGM_DIM * sizeof(double) * (size_t)k);
  if (d->skin) return skin_versions(v, d, same);
  if (!same) C->version++;
  return 0;
}

/* mesh.node_motion "interpolated" (docs/theory.md section 13, "node
 * motion"): a node that is not fixed in both components moves with the
 * step's displacement field at its start-of-step position,
 * u^h(x_I) = sum_J N_J(x_I) du_J, over the nodes the points used (parked
 * and merged nodes left out), instead of with its own coefficient du_I
 * (committed by the integrator); a fixed component keeps its prescribed
 * increment, an obstacle node stays. A node whose functions fail keeps
 * its coefficient's motion (counted: node_motion_fallbacks). */
static int move_interpolated(const mpgm_fe_view *v, gmm_data *d) {
  mpgm_ctx *ctx = v->ctx;
  mpgm_nodes *nd = v->nodes;
  const int n = nd->n;
  double *xs = d->xs;
  unsigned char *skip = d->skip;
  for (int i = 0; i < MPGM_DIM * n; i++) xs[i] = nd->x[i] - nd->du[i];
  for (int i = 0; i < n; i++)
    skip[i] = d->grid && (d->grid->parked[i] || (d->merged && d->merged[i]));
  const double t0 = mpgm_wtime();
  MPGM_CALL(mpgm_kdtree_rebuild(ctx, d->tree_xs, xs, n));
  mpgm_timer_move(ctx, MPGM_T_SHAPE, MPGM_T_SEARCH, mpgm_wtime() - t0);
  int idx[MPGM_SHAPE_MAXNODE];
  double N[MPGM_SHAPE_MAXNODE];
  for (int i = 0; i < n; i++) { /* 2-D only: x and y written out */
    if ((nd->fix[MPGM_DIM * i] && nd->fix[MPGM_DIM * i + 1]) || (d->grid && d->grid->obst[i]))
      continue;
    int k;
    if (mpgm_clouds_eval_at(d->clouds, ctx, d->tree_xs, skip, xs + MPGM_DIM * i, idx, N, &k)) {
      mpgm_count(ctx, MPGM_C_NODE_MOTION_FALLBACKS, 1);
      continue;
    }
    double du[MPGM_DIM] = {0};
    for (int a = 0; a < k; a++) {
      du[0] += N[a] * nd->du[MPGM_DIM * idx[a]];
      du[1] += N[a] * nd->du[MPGM_DIM * idx[a] + 1];
    }
    for (int c = 0; c < MPGM_DIM; c++)
      if (!nd->fix[MPGM_DIM * i + c]) nd->x[MPGM_DIM * i + c] = xs[MPGM_DIM * i + c] + du[c];
  }
  return 0;
}

static int gmm_end_step(void *self, const mpgm_fe_view *v) {
  gmm_data *d = self;
  if (d->grid) mpgm_gmm_grid_unpark(v, d->grid);
  if (d->tree_xs) MPGM_CALL(move_interpolated(v, d));
  return 0;
}

/* The mesh of the setup, for output only (nodes persist, so the cells show
 * the deformed body; they are not the interpolation). */
static int gmm_cells(const void *self, mpgm_cells *out) {
  const gmm_data *d = self;
  if (!d->grid) return mpgm_fem_cells_output(d->fem, out);
  out->n = d->grid->ncell;
  out->ptr = d->grid->cptr;
  out->node = d->grid->cnode;
  out->type = d->grid->ctype;
  return 0;
}

/* Checkpoint: the LME warm starts (the nodes are the problem's, the clouds,
 * the kd-tree and the parked nodes are rebuilt every step). */
static int gmm_save(const void *self, mpgm_ctx *ctx, mpgm_blob *b) {
  const gmm_data *d = self;
  MPGM_CALL(mpgm_clouds_save(d->clouds, ctx, b));
  /* the skin's lists: a restarted run builds the pattern it would have
   * kept, and so gives the same bits */
  if (!d->skin) return 0;
  MPGM_CALL(mpgm_skin_save(d->skin, ctx, b));
  /* the lists of the step just ended (d->out is what the step used) */
  const uint64_t hash = d->out.ptr ? lists_hash(&d->out, d->out.np) : 0;
  MPGM_CALL(mpgm_blob_put(ctx, b, "gmm.lists_hash", &hash, sizeof hash));
  return mpgm_blob_put(ctx, b, "gmm.fix", d->fix, MPGM_DIM * (size_t)d->nfix);
}

static int gmm_restore(void *self, const mpgm_fe_view *v, mpgm_blob *b) {
  gmm_data *d = self;
  mpgm_ctx *ctx = v->ctx;
  const mpgm_points *P = v->pts;
  MPGM_CALL(mpgm_clouds_restore(d->clouds, ctx, b, P->n + P->nprobe + P->nsurf));
  if (!d->skin) return 0;
  MPGM_CALL(mpgm_skin_restore(d->skin, ctx, b, P->n, v->nodes->n));
  MPGM_CALL(mpgm_blob_get(ctx, b, "gmm.lists_hash", &d->lists_hash, sizeof d->lists_hash));
  MPGM_CALL(mpgm_blob_get(ctx, b, "gmm.fix", d->fix, MPGM_DIM * (size_t)d->nfix));
  for (int i = 0; i < MPGM_DIM * d->nfix; i++)
    MPGM_CHECK(ctx, d->fix[i] <= 1, MPGM_ERR_INPUT,
               "checkpoint: section 'gmm.fix': node %d "
               "component %d holds %d (0 or 1)",
               i / MPGM_DIM, i % MPGM_DIM, d->fix[i]);
  d->restored = 1;
  return 0;
}

/* The pattern's keys against each other and the kind; the nodes' motion
 * against the kinematics. */
static int gmm_check(mpgm_ctx *ctx, const mpgm_scene *s) {
  const mpgm_pattern_opts *o = &s->pattern;
  const double rt = tangent_radius(s);
  MPGM_CHECK(ctx, !(s->mesh_par.node_motion == MPGM_NODES_INTERPOLATED && s->kinematics == MPGM_KIN_SMALL),
             MPGM_ERR_INPUT, "%s: mesh.node_motion: \"interpolated\" moves the nodes, and under "
             "kinematics \"small\" nodes do not move: remove the key or use kinematics \"finite\"",
             s->file);
  if (o->tangent_tol > 0.0) {
    MPGM_CHECK(ctx, s->shape->weight_radius, MPGM_ERR_INPUT, "%s: shape.tangent_tol: a tangent cut "
               "where the weight falls to tol: expected a kind with such a weight (\"lme\"), found "
               "\"%s\" (use shape.tangent_radius)", s->file, s->shape->name);
    MPGM_CHECK(ctx, !(o->tangent_radius > 0.0), MPGM_ERR_INPUT, "%s: shape.tangent_tol: expected "
               "shape.tangent_radius or shape.tangent_tol, found both (radius %g h, tol %g)",
               s->file, o->tangent_radius, o->tangent_tol);
    MPGM_CHECK(ctx, rt > 0.0, MPGM_ERR_INPUT, "%s: shape.tangent_tol: no radius "
               "for tol %g with gamma %g", s->file, o->tangent_tol, s->shape_par.gamma);
  }
  MPGM_CHECK(ctx, !(rt > 0.0) || o->skin > 0.0, MPGM_ERR_INPUT, "%s: shape.%s: a "
             "tangent of smaller clouds is built on the pattern skin's lists: expected shape.skin "
             "> 0, found %g", s->file, o->tangent_tol > 0.0 ? "tangent_tol" : "tangent_radius", o->skin);
  return 0;
}

/* GMM's keys of "shape" (docs/scene-format.md, "shape"): the pattern skin
 * keeps the pattern while the clouds stay within a tenth of h more than
 * their radius (docs/benchmarks.md: the rolling disk's GMM-LME 1.45x
 * faster, the column collapse unchanged) */
static const mpgm_key_spec gmm_shape_keys[] = {
    {.name = "skin", .type = MPGM_KEY_REAL, .offset = offsetof(mpgm_pattern_opts, skin),
     .def = 0.1, .lo = 0.0, .hi = 10.0, .unit = "-",
     .doc = "the sparsity pattern's skin, a multiple of mesh.h; 0: a pattern per change of a cloud"},
    {.name = "tangent_radius", .type = MPGM_KEY_REAL,
     .offset = offsetof(mpgm_pattern_opts, tangent_radius), .def = 0.0, .lo = 0.0, .hi = 1000.0,
     .unit = "-", .doc = "the tangent couples each point's nodes within this multiple of h; 0: all"},
    {.name = "tangent_tol", .type = MPGM_KEY_REAL, .offset = offsetof(mpgm_pattern_opts, tangent_tol),
     .def = 0.0, .lo = 0.0, .hi = 1.0, .hi_open = 1, .unit = "-",
     .doc = "the tangent's radius where the kind's weight falls to this value; 0: off"},
};

/* GMM's keys of "mesh" (docs/scene-format.md, "mesh"): the light-node
 * and close-node rules of bodies filled on the grid, and how the nodes
 * move (docs/theory.md section 13) */
static const char *const node_motion_names[] = {"coefficient", "interpolated", NULL}; /* = mpgm_node_motion */
static const mpgm_key_spec gmm_mesh_keys[] = {
    MPGM_LIGHT_NODE_KEY,
    {.name = "min_node_distance", .type = MPGM_KEY_REAL,
     .offset = offsetof(mpgm_mesh_params, min_node_distance), .def = 0.0, .lo = 0.0, .hi = 1.0,
     .hi_open = 1, .unit = "-",
     .doc = "a free node closer than this times h to a lower-numbered one leaves the step; 0: off"},
    {.name = "node_motion", .type = MPGM_KEY_CHOICE, .offset = offsetof(mpgm_mesh_params, node_motion),
     .def = MPGM_NODES_COEFFICIENT, .lo = MPGM_NODES_COEFFICIENT, .choices = node_motion_names,
     .unit = "-", .doc = "the nodes move by their coefficients' increments or by the interpolated field"},
};

const mpgm_frontend_type mpgm_frontend_gmm = {
    .name = "gmm",
    .doc = "Galerkin Meshfree Method: the nodes of UL-FEM (or of bodies filled on a grid) "
           "connected to every point by a node cloud searched again each step",
    .persistent_nodes = 1,
    .point_velocity = MPGM_PV_INTERPOLATE,
    .shapes = MPGM_FE_SHAPE_CLOUD,
    .geometries = 1u << MPGM_GEOM_RECTANGLE | 1u << MPGM_GEOM_DISK | 1u << MPGM_GEOM_POLYGON,
    .conditions = MPGM_FE_COND_FIX | MPGM_FE_COND_DISPLACEMENT | MPGM_FE_COND_CONTACT_POINTS,
    .obstacles = 1,
    .shape_keys = gmm_shape_keys,
    .nshape_keys = sizeof gmm_shape_keys / sizeof *gmm_shape_keys,
    .mesh_keys = gmm_mesh_keys,
    .nmesh_keys = sizeof gmm_mesh_keys / sizeof *gmm_mesh_keys,
    .check = gmm_check,
    .create = gmm_create,
    .destroy = gmm_destroy,
    .begin_step = gmm_begin_step,
    .end_step = gmm_end_step,
    .cells = gmm_cells,
    .save = gmm_save,
    .restore = gmm_restore,
};
