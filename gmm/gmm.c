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
#include <stdlib.h>
#include <string.h>

#include "gmm_impl.h"
#include "mpgm_discretisation.h"
#include "mpgm_gmm.h"
#include "mpgm_kdtree.h"

/* Radius growth factor while a cloud holds fewer than min_nodes nodes, and
 * the most growths per point (1.25^60 ~ 6e5: a search this wide that still
 * finds too few nodes means there are not that many) */
#define GMM_GROWTH     MPGM_SHAPE_GROWTH
#define GMM_MAX_GROWTH 60

typedef struct gmm_data {
  mpgm_fem_cells *fem;   /**< rectangle bodies: the FE cells (for output)      */
  gmm_grid *grid;        /**< or, for grid-filled bodies, the output cells    */
  mpgm_kdtree *tree;     /**< over nodes.x (borrowed), rebuilt every step     */
  mpgm_shape_params par; /**< the scene's parameters, h = mesh.h            */
  double r0;             /**< support radius of the kind [m]                  */
  int min_nodes;         /**< smallest cloud                                  */
  double *lambda;        /**< LME multiplier per point (warm start), 2 each   */
  unsigned char *merged; /**< per node: left out of this step's clouds for
                              being close to another node (grid-filled)     */
  double dmin;           /**< that distance [m] (0: off)                      */
  double *rad;           /**< search radius of every point this step [m]      */
  int *cptr;             /**< clouds of the search: CSR over the points       */
  int *cidx;
  int ccap;
  mpgm_conn out;          /**< the step's connectivity before it is copied    */
} gmm_data;

static void gmm_destroy(void *self) {
  gmm_data *d = self;
  if (!d) return;
  mpgm_fem_cells_destroy(d->fem);
  mpgm_gmm_grid_destroy(&d->grid);
  mpgm_kdtree_destroy(&d->tree);
  free(d->lambda);
  free(d->merged);
  free(d->rad);
  free(d->cptr);
  free(d->cidx);
  mpgm_conn_release(&d->out);
  free(d);
}

static int gmm_create(const mpgm_fe_view *v, void **self) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_scene *s = v->scene;
  gmm_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *self = d; /* from here gmm_destroy frees everything */
  MPGM_CHECK(ctx, !s->shape->needs_cell && s->shape->support_radius, MPGM_ERR_INPUT,
             "%s: shape.kind: method gmm needs a meshfree kind, found \"%s\"", s->file,
             s->shape->name);
  d->par = s->shape_par;
  d->par.h = s->h;
  MPGM_CHECK(ctx, mpgm_shape_support_radius(s->shape, &d->par, &d->r0) == 0 && d->r0 > 0.0,
             MPGM_ERR_INPUT, "%s: shape: no support radius for kind \"%s\" (h = %g)", s->file,
             s->shape->name, s->h);
  if (mpgm_gmm_uses_grid(s)) {
    /* disk and polygon bodies, obstacles: points and nodes on the grid */
    MPGM_CALL(mpgm_gmm_grid_setup(v, d->r0, &d->grid));
  } else {
    /* rectangles: nodes, points, probes, boundaries exactly those of UL-FEM */
    MPGM_CALL(mpgm_fem_rectangles(v, &d->fem));
  }
  if (d->grid && s->min_node_distance > 0.0) {
    d->dmin = s->min_node_distance * s->h;
    MPGM_ALLOC(ctx, d->merged, v->nodes->n);
  }
  d->min_nodes = s->min_nodes > 0 ? s->min_nodes : d->par.order == 2 ? 12 : 6;
  const int m = v->pts->n + v->pts->nprobe + v->pts->nsurf;
  MPGM_ALLOC(ctx, d->lambda, 2 * (size_t)m);
  MPGM_ALLOC(ctx, d->rad, m);
  MPGM_ALLOC(ctx, d->cptr, m + 1);
  MPGM_CALL(mpgm_conn_reserve(ctx, &d->out, m, 0));
  MPGM_CALL(mpgm_kdtree_create(ctx, v->nodes->x, v->nodes->n, 0, &d->tree));
  return 0;
}

/* Grow an int / double buffer to hold at least need entries (amortised:
 * doubling; only when a step needs more than any before). */
static int grow_int(mpgm_ctx *ctx, int **a, size_t need, size_t *cap) {
  if (need <= *cap) return 0;
  size_t nc = *cap ? *cap : 1024;
  while (nc < need) nc *= 2;
  int *p = realloc(*a, nc * sizeof **a);
  MPGM_CHECK(ctx, p, MPGM_ERR_NOMEM, "out of memory (node clouds of %zu entries)", nc);
  *a = p;
  *cap = nc;
  return 0;
}


/* Drop the merged nodes from a search result of n (of which min(n, cap)
 * are in idx, d2); returns the new count. */
static int drop_merged(const gmm_data *d, int n, int cap, int *idx, double *d2) {
  if (!d->merged) return n;
  const int have = n < cap ? n : cap;
  int k = 0;
  for (int a = 0; a < have; a++) {
    if (d->merged[idx[a]]) continue;
    idx[k] = idx[a];
    d2[k++] = d2[a];
  }
  return n - (have - k);
}

/* Nodes within r of x into idx (at most cap), merged nodes left out;
 * returns the count (which may exceed cap: then idx holds the cap
 * nearest). */
static int cloud(const gmm_data *d, const double x[2], double r, int cap, int *idx, double *d2) {
  return drop_merged(d, mpgm_kdtree_radius(d->tree, x, r, cap, idx, d2), cap, idx, d2);
}

/* The squared distance of the (n+1)-th nearest node that is not merged
 * (the nearest outside a cloud of n) into *dn2; 0 when there is none. */
static int next_nearest(const gmm_data *d, const double x[2], int n, double *dn2) {
  enum { CAP = 2 * MPGM_SHAPE_MAXNODE + 2 };
  int ib[CAP];
  double db[CAP];
  for (int kq = n + 1;; kq = kq * 2 < CAP ? kq * 2 : CAP) {
    const int kk = mpgm_kdtree_knn(d->tree, x, kq, ib, db);
    for (int a = 0, cnt = 0; a < kk; a++) {
      if (d->merged && d->merged[ib[a]]) continue;
      if (cnt++ == n) {
        *dn2 = db[a];
        return 1;
      }
    }
    if (kk < kq || kq == CAP) return 0;
  }
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
    if (d->merged[i] || g->obst[i] || g->fix0[2 * i] || g->fix0[2 * i + 1]) continue;
    const int k = mpgm_kdtree_radius(d->tree, nd->x + 2 * i, d->dmin, 64, idx, d2);
    for (int a = 0; a < k && a < 64; a++) {
      const int j = idx[a];
      if (j <= i || d->merged[j] || g->obst[j] || g->fix0[2 * j] || g->fix0[2 * j + 1]) continue;
      d->merged[j] = 1;
      mpgm_count(v->ctx, MPGM_C_NODES_MERGED, 1);
    }
  }
}

static void sort_by_node(int n, int *idx) {
  for (int i = 1; i < n; i++) {
    const int v = idx[i];
    int j = i - 1;
    while (j >= 0 && idx[j] > v) {
      idx[j + 1] = idx[j];
      j--;
    }
    idx[j + 1] = v;
  }
}

/* Phase 1: clouds of every point (and probe) from the radius search, with
 * radius growth up to min_nodes nodes. */
static int search_clouds(const mpgm_fe_view *v, gmm_data *d) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_points *P = v->pts;
  const int m = P->n + P->nprobe + P->nsurf, nnode = v->nodes->n;
  const int want = d->min_nodes < nnode ? d->min_nodes : nnode;
  MPGM_CALL(mpgm_kdtree_rebuild(ctx, d->tree, v->nodes->x, nnode));
  if (d->merged) merge_close(v, d);
  size_t cap = (size_t)d->ccap;
  int idx[MPGM_SHAPE_MAXNODE];
  double d2[MPGM_SHAPE_MAXNODE];
  d->cptr[0] = 0;
  for (int p = 0; p < m; p++) {
    const double *x = P->x + 2 * p;
    double r = d->r0;
    int n = cloud(d, x, r, MPGM_SHAPE_MAXNODE, idx, d2);
    for (int g = 0; n < want && g < GMM_MAX_GROWTH; g++) {
      r *= GMM_GROWTH;
      mpgm_count(ctx, MPGM_C_RADIUS_GROWTHS, 1);
      n = cloud(d, x, r, MPGM_SHAPE_MAXNODE, idx, d2);
    }
    MPGM_CHECK(ctx, n <= MPGM_SHAPE_MAXNODE, MPGM_ERR_INPUT,
               "%s: shape: step %ld: %s %d at (%g, %g) has %d nodes within its support radius "
               "%g m, more than MPGM_SHAPE_MAXNODE = %d: lower shape.radius / shape.dilation "
               "(mls) or raise shape.gamma (lme)",
               v->scene->file, v->step + 1, p < P->n ? "point" : p < P->n + P->nprobe ? "probe" : "surface point",
               p < P->n ? P->id[p] : p - P->n, x[0], x[1], n, r, MPGM_SHAPE_MAXNODE);
    d->rad[p] = r;
    MPGM_CALL(grow_int(ctx, &d->cidx, (size_t)d->cptr[p] + (size_t)n, &cap));
    memcpy(d->cidx + d->cptr[p], idx, sizeof(int) * (size_t)n);
    d->cptr[p + 1] = d->cptr[p] + n;
  }
  d->ccap = (int)cap;
  return 0;
}

/* Phase 2 for one point: N and grad N over its cloud at its position, with
 * enlargements on MPGM_ERR_SHAPE; appends the non-zero entries to the
 * output at *k. *t_search accumulates the time of the extra searches. */
static int shape_point(const mpgm_fe_view *v, gmm_data *d, int p, int *k, double *t_search) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_scene *s = v->scene;
  const mpgm_points *P = v->pts;
  const double *xn_all = v->nodes->x, *x = P->x + 2 * p;
  int idx[MPGM_SHAPE_MAXNODE + 1];
  double d2[MPGM_SHAPE_MAXNODE + 1], xn[2 * MPGM_SHAPE_MAXNODE], N[MPGM_SHAPE_MAXNODE],
      dN[2 * MPGM_SHAPE_MAXNODE];
  int n = d->cptr[p + 1] - d->cptr[p];
  memcpy(idx, d->cidx + d->cptr[p], sizeof(int) * (size_t)n);
  double r = d->rad[p];
  mpgm_shape_info info = {0};
  int err = 0, enl = 0;
  for (;; enl++) {
    sort_by_node(n, idx);
    for (int a = 0; a < n; a++) {
      xn[2 * a] = xn_all[2 * idx[a]];
      xn[2 * a + 1] = xn_all[2 * idx[a] + 1];
    }
    mpgm_shape_params par;
    mpgm_shape_params_for_radius(&d->par, d->r0, r, &par);
    /* a probe uses N only (its grad N is never assembled): the condition
     * limit, which guards grad N, does not apply. A probe on the boundary
     * of the body (the cantilever's tip) is on the hull of its cloud, where
     * cond(J) of LME grows like 1 / (Newton residual) past 1e12 */
    if (p >= P->n) par.max_cond = 1e300;
    const mpgm_shape_query q = {.n = n,
                                .xn = xn,
                                .xp = {x[0], x[1]},
                                .cell = -1,
                                .par = &par,
                                .lambda = d->lambda + 2 * p,
                                .info = &info};
    /* an LME warm start that stalls is retried once from lambda = 0
     * before the cloud is enlarged */
    err = n > 0 ? mpgm_shape_eval_retry(s->shape, &q, N, dN, &ctx->count[MPGM_C_COLD_RESTARTS]) : MPGM_ERR_SHAPE;
    if (n == 0) info.msg = "no node within the support radius";
    if (err != MPGM_ERR_SHAPE || enl >= s->max_enlarge) break;
    /* enlarge: the next-nearest node outside the cloud */
    const double t0 = mpgm_wtime();
    double dn2;
    const int more = next_nearest(d, x, n, &dn2);
    int nn = n;
    if (more) {
      r = fmax(r * (1.0 + 1e-9), MPGM_SHAPE_ENLARGE * sqrt(dn2));
      nn = cloud(d, x, r, MPGM_SHAPE_MAXNODE, idx, d2);
    }
    *t_search += mpgm_wtime() - t0;
    if (!more || nn > MPGM_SHAPE_MAXNODE) { /* no node left, or the cloud is full */
      info.msg = !more ? "every node is in the cloud already"
                            : "the enlarged cloud would exceed MPGM_SHAPE_MAXNODE nodes";
      break;
    }
    mpgm_count(ctx, MPGM_C_CLOUD_ENLARGEMENTS, 1);
    n = nn;
  }
  const int surf = p - (P->n + P->nprobe); /* >= 0: a surface point */
  if (err == MPGM_ERR_SHAPE && surf >= 0) {
    /* no functions at a surface point: contact is not enforced there in
     * this step (counted), and the point does not move */
    mpgm_err_clear(ctx);
    mpgm_cpoints_unenforce(v->cp, surf);
    return 0;
  }
  if (err) { /* MPGM_ERR_SHAPE (recoverable), or a fatal MPGM_ERR_INPUT */
    if (p < P->n)
      MPGM_ERROR(ctx, err,
                 "step %ld: %s shape functions failed at point %d (body \"%s\", started at (%g, "
                 "%g)) at (%g, %g) after %d cloud enlargement(s) (cloud of %d nodes within %g "
                 "m; shape.max_enlarge = %d): %s",
                 v->step + 1, s->shape->name, P->id[p], s->bodies[P->body[p]].name, P->x0[2 * p],
                 P->x0[2 * p + 1], x[0], x[1], enl, n, r, s->max_enlarge,
                 info.msg ? info.msg : "?");
    MPGM_ERROR(ctx, err,
               "step %ld: %s shape functions failed at probe \"%s\" at (%g, %g) after %d cloud "
               "enlargement(s) (cloud of %d nodes within %g m): %s",
               v->step + 1, s->shape->name, s->probes[p - P->n].name, x[0], x[1], enl, n, r,
               info.msg ? info.msg : "?");
  }
  MPGM_CALL(mpgm_conn_grow(ctx, &d->out, *k, *k + n));
  for (int a = 0; a < n; a++) {
    if (N[a] == 0.0 && dN[2 * a] == 0.0 && dN[2 * a + 1] == 0.0) continue; /* outside the support */
    d->out.node[*k] = idx[a];
    d->out.N[*k] = N[a];
    d->out.dN[2 * *k] = dN[2 * a];
    d->out.dN[2 * *k + 1] = dN[2 * a + 1];
    (*k)++;
  }
  return 0;
}

static int gmm_begin_step(void *self, const mpgm_fe_view *v) {
  mpgm_ctx *ctx = v->ctx;
  gmm_data *d = self;
  mpgm_conn *C = v->conn;
  const int m = v->pts->n + v->pts->nprobe + v->pts->nsurf;
  /* the core times begin_step as "shape": the search time is moved from
   * "shape" to "search", so that the two add up to the call */
  double t0 = mpgm_wtime();
  MPGM_CALL(search_clouds(v, d));
  double ts = mpgm_wtime() - t0;
  /* room for every cloud of the search (enlargements may add more) */
  MPGM_CALL(mpgm_conn_grow(ctx, &d->out, 0, d->cptr[m]));
  if (v->pts->nsurf) mpgm_cpoints_enforce_all(v->cp);
  int k = 0;
  for (int p = 0; p < m; p++) {
    d->out.ptr[p] = k;
    const int err = shape_point(v, d, p, &k, &ts);
    if (err) {
      mpgm_timer_move(ctx, MPGM_T_SHAPE, MPGM_T_SEARCH, ts);
      return err;
    }
  }
  d->out.ptr[m] = k;
  mpgm_timer_move(ctx, MPGM_T_SHAPE, MPGM_T_SEARCH, ts);
  /* grid-filled bodies: nodes with little mass are parked for the step */
  if (d->grid) {
    MPGM_CALL(mpgm_gmm_grid_park(v, d->grid, d->tree, d->r0, &d->out));
    k = d->out.ptr[m];
  }
  /* a new pattern only when some point's node list changed */
  int same = C->np == m && C->ptr[m] == k;
  for (int p = 0; same && p <= m; p++) same = C->ptr[p] == d->out.ptr[p];
  if (same) same = memcmp(C->node, d->out.node, sizeof(int) * (size_t)k) == 0;
  MPGM_CALL(mpgm_conn_reserve(ctx, C, m, k));
  memcpy(C->ptr, d->out.ptr, sizeof(int) * (size_t)(m + 1));
  memcpy(C->node, d->out.node, sizeof(int) * (size_t)k);
  memcpy(C->N, d->out.N, sizeof(double) * (size_t)k);
  memcpy(C->dN, d->out.dN, 2 * sizeof(double) * (size_t)k);
  if (!same) C->version++;
  return 0;
}

static int gmm_end_step(void *self, const mpgm_fe_view *v) {
  gmm_data *d = self;
  if (d->grid) mpgm_gmm_grid_unpark(v, d->grid);
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
    .create = gmm_create,
    .destroy = gmm_destroy,
    .begin_step = gmm_begin_step,
    .end_step = gmm_end_step,
    .cells = gmm_cells,
};
