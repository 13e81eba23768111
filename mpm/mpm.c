/* mpm.c -- the grid-reset front end (mpgm_mpm.h). */
#include "mpgm_mpm.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpm_private.h"

static void mpm_destroy(void *self) {
  mpm_data *d = self;
  if (!d) return;
  free(d->pcell);
  free(d->pxi);
  free(d->gmap);
  free(d->cact);
  free(d->gfix);
  free(d->gcontact);
  free(d->gfree);
  free(d->lglob);
  free(d->plglob);
  free(d->pfix);
  free(d->pact);
  free(d->gm);
  free(d->light);
  mpgm_conn_release(&d->plists);
  mpgm_conn_release(&d->carry);
  free(d->gx);
#if MPM_PLANE_ONLY
  mpgm_kdtree_destroy(&d->tree);
  mpgm_clouds_destroy(d->clouds);
  mpgm_cpls_destroy(d->cpls);
#endif
  free(d->perm);
  free(d->pscr);
  free(d->sum);
  mpgm_conn_par_free(&d->par_build);
  mpgm_conn_task_free(&d->tail);
  mpgm_mpm_dist_free(d);
  free(d);
}

/* Whether grid node X lies on the edge of the grid's box. */
static int on_grid_edge(const mpgm_grid *g, const double X[MPGM_DIM]) {
  const double tol = 1e-9 * g->h;
  for (int c = 0; c < MPGM_DIM; c++)
    if (fabs(X[c] - g->min[c]) <= tol || fabs(X[c] - g->max[c]) <= tol) return 1;
  return 0;
}

/* Particles of every body at the Gauss points of the cells that lie in it
 * (mpgm_grid_fill: the rule GMM shares for its grid-filled bodies; the
 * first body containing a point owns it), the probes, and the tracers on
 * the bodies' boundaries of contact at points (after the probes). */
static int make_points(const mpgm_fe_view *v, const mpgm_grid *g) {
  const mpgm_scene *s = v->scene;
  mpgm_fill f;
  int err = mpgm_grid_fill(v->ctx, g, s, &f);
  const int nsurf = v->fx->contact_points ? mpgm_surface_tracers_count(s) : 0;
  if (!err) err = mpgm_points_alloc(v->ctx, v->pts, f.count, s->nprobe, nsurf, mpgm_scene_nstate(s));
  if (!err) mpgm_fill_points(&f, s, v->pts);
  mpgm_fill_free(&f);
  MPGM_CALL(err);
  mpgm_probes_place(v->pts, s);
  mpgm_surface_tracers_fill(v->pts, s);
  return 0;
}

static int mpm_create(const mpgm_fe_view *v, void **self) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_scene *s = v->scene;
  mpm_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *self = d;
  MPGM_CALL(mpgm_grid_init(ctx, &d->g, s));
  const mpgm_grid *g = &d->g;
  MPGM_CALL(make_points(v, g));
  const int np = v->pts->n, nsurf = v->pts->nsurf;
  /* nodes: room for the whole grid; the step uses those of active cells */
  MPGM_CALL(mpgm_nodes_alloc(ctx, v->nodes, g->nnode));
  v->nodes->n = 0;
  const int m = np + s->nprobe + nsurf;
  MPGM_ALLOC(ctx, d->pcell, m);
  MPGM_ALLOC(ctx, d->pxi, MPGM_DIM * (size_t)m);
  MPGM_ALLOC(ctx, d->gmap, g->nnode);
  MPGM_ALLOC(ctx, d->cact, g->ncell);
  MPGM_ALLOC(ctx, d->gfix, MPGM_DIM * (size_t)g->nnode);
  MPGM_ALLOC(ctx, d->gcontact, g->nnode);
  MPGM_ALLOC(ctx, d->gfree, g->nnode);
  MPGM_ALLOC(ctx, d->lglob, g->nnode);
  MPGM_ALLOC(ctx, d->plglob, g->nnode);
  MPGM_ALLOC(ctx, d->pfix, MPGM_DIM * (size_t)g->nnode);
  MPGM_ALLOC(ctx, d->pact, g->ncell);
  d->pn = -1;
  MPGM_ALLOC(ctx, d->gm, g->nnode);
  MPGM_ALLOC(ctx, d->light, g->nnode);
  MPGM_CALL(mpgm_conn_reserve(ctx, v->conn, m, m * g->nn));
  MPGM_ALLOC(ctx, d->perm, m);
  MPGM_ALLOC(ctx, d->pscr, MPGM_DIM * (size_t)m);
  d->meshfree = !s->shape->needs_cell;
  d->gridfn = s->shape->grid_only;
  if (d->gridfn) { /* h and the particle half-width (scene load) */
    d->gpar = s->shape_par;
    d->gpar.h = s->h;
    for (int i = 0; i < MPGM_DIM; i++) { /* CPDI: corners stay on the grid */
      d->gpar.grid_lo[i] = g->min[i];
      d->gpar.grid_hi[i] = g->max[i];
    }
  } else if (d->meshfree) { /* clouds of grid nodes: the grid's nodes never move */
#if MPM_PLANE_ONLY
    MPGM_ALLOC(ctx, d->gx, MPGM_DIM * (size_t)g->nnode);
    for (int i = 0; i < g->nnode; i++) mpgm_grid_node(g, i, d->gx + MPGM_DIM * i);
    MPGM_CALL(mpgm_kdtree_create(ctx, d->gx, g->nnode, 0, &d->tree));
    MPGM_CALL(mpgm_clouds_create(ctx, s, &d->clouds));
#else
    MPGM_ERROR(ctx, MPGM_ERR_INTERNAL, "%s: meshfree kind \"%s\" in a 3-D build", s->file, s->shape->name);
#endif
  }
  /* grid boundaries: the grid never moves, so the fixity of every grid
   * node is decided once */
  for (int i = 0; i < s->nbc; i++) {
    /* contact at points acts on the bodies, not on grid nodes */
    if (mpgm_bc_at_points(&s->bcs[i])) continue;
    int hits = 0;
    for (int k = 0; k < g->nnode; k++) {
      double X[MPGM_DIM];
      mpgm_grid_node(g, k, X);
      if (!mpgm_boundary_selects(&s->bcs[i], X)) continue;
      hits++;
      char at[MPGM_POINT_STR];
      MPGM_CHECK(ctx, d->gpar.grid_order != 2 || on_grid_edge(g, X), MPGM_ERR_INPUT,
                 "%s: boundaries.%d (\"%s\"): with shape.grid_functions \"quadratic_bspline\" a "
                 "support holds the field only on the edge of the grid (mesh.domain), where one "
                 "node's spline alone is non-zero; found grid node %s inside it: expected the "
                 "grid's edge on the support", s->file, i, s->bcs[i].name, mpgm_point_str(X, at));
      for (int c = 0; c < MPGM_DIM; c++)
        d->gfix[MPGM_DIM * k + c] |= (unsigned char)s->bcs[i].fix[c];
      if (s->bcs[i].condition == MPGM_COND_CONTACT) /* normal axis, body side */
        d->gcontact[k] = (signed char)((s->bcs[i].select + 1) * s->bcs[i].side);
    }
    MPGM_CHECK(ctx, hits > 0, MPGM_ERR_INPUT,
               "%s: boundaries.%d (\"%s\"): expected a selector that picks grid nodes, found none "
               "within tol = %g", s->file, i, s->bcs[i].name, s->bcs[i].tol);
  }
  /* on many processes: the grid partitioned, this process's points kept */
  return mpgm_mpm_dist_create(v, d);
}

/* Cell of a probe: its own cell if active, else an active neighbour that
 * holds it on its boundary (a probe on the edge of the material). */
static int probe_cell(const mpm_data *d, const double x[MPGM_DIM], int *cell,
                      double xi[MPGM_DIM]) {
  if (d->cact[*cell]) return 0;
  int cand[27];
  const int nc = mpgm_grid_neighbours(&d->g, *cell, cand);
  for (int i = 0; i < nc; i++) {
    if (!d->cact[cand[i]]) continue;
    int nodes[MPGM_FE_MAXNODE];
    double xn[MPGM_DIM * MPGM_FE_MAXNODE], t[MPGM_DIM];
    mpgm_grid_cell(&d->g, cand[i], nodes, xn);
    if (mpgm_fe_local(d->g.cell, xn, x, t) == 0 && mpgm_fe_inside(d->g.cell, t, 1e-9)) {
      *cell = cand[i];
      memcpy(xi, t, sizeof t);
      return 0;
    }
  }
  return MPGM_ERR_DOMAIN;
}

#if MPM_PLANE_ONLY
/* Cell of a surface tracer: its own cell if active, else the active
 * neighbour whose centre is nearest (the tracer may sit just outside the
 * material: its shape functions there extrapolate the cell's linear
 * field). Returns 0, or 1 when no active cell is near (not enforced this
 * step). A tracer slightly outside the grid (a spring lets a held tracer
 * dip below a plane on the grid's edge) is located in the edge cell. */
static int surface_cell(const mpm_data *d, const double x[MPGM_DIM], int *cell,
                        double xi[MPGM_DIM]) {
  const mpgm_grid *g = &d->g;
  /* 2-D only: the clamp, the cells' centres and distances written out */
  double xc[MPGM_DIM] = {fmin(fmax(x[0], g->min[0]), g->max[0]),
                         fmin(fmax(x[1], g->min[1]), g->max[1])};
  if (mpgm_grid_locate(g, xc, cell, xi)) return 1;
  int cand[19], best = -1;
  const int nc = mpgm_grid_neighbours(g, *cell, cand);
  cand[nc] = *cell;
  double dmin = INFINITY;
  for (int i = 0; i <= nc; i++) {
    if (!d->cact[cand[i]]) continue;
    int nodes[MPGM_FE_MAXNODE];
    double xn[MPGM_DIM * MPGM_FE_MAXNODE], c[MPGM_DIM] = {0};
    mpgm_grid_cell(g, cand[i], nodes, xn);
    for (int a = 0; a < g->nn; a++) {
      c[0] += xn[MPGM_DIM * a] / g->nn;
      c[1] += xn[MPGM_DIM * a + 1] / g->nn;
    }
    const double dist = hypot(c[0] - x[0], c[1] - x[1]);
    if (dist < dmin) {
      dmin = dist;
      best = cand[i];
    }
  }
  if (best < 0) return 1;
  int nodes[MPGM_FE_MAXNODE];
  double xn[MPGM_DIM * MPGM_FE_MAXNODE];
  mpgm_grid_cell(g, best, nodes, xn);
  if (mpgm_fe_local(g->cell, xn, x, xi)) return 1;
  *cell = best;
  return 0;
}
#endif

/* a[i] = a[perm[i]] for n records of w doubles, through scratch */
static void permute(double *a, double *scr, const int *perm, int n, int w) {
  for (int i = 0; i < n; i++)
    for (int c = 0; c < w; c++) scr[w * i + c] = a[w * perm[i] + c];
  memcpy(a, scr, sizeof(double) * (size_t)w * (size_t)n);
}

typedef struct {
  mpm_data *d;
  const mpgm_points *P;
  int ntask;
  int fail[MPGM_CONN_TASKS]; /* per task: its first point outside the grid, or P->n */
} locate_job;

/* The cells of task t's material points. */
static void locate_task(void *arg, int t, int tid) {
  (void)tid;
  locate_job *j = arg;
  const int np = j->P->n;
  const int p0 = mpgm_task_begin(np, j->ntask, t), p1 = mpgm_task_begin(np, j->ntask, t + 1);
  j->fail[t] = np;
  for (int p = p0; p < p1; p++)
    if (mpgm_grid_locate(&j->d->g, j->P->x + MPGM_DIM * p, j->d->pcell + p,
                         j->d->pxi + MPGM_DIM * p)) {
      j->fail[t] = p;
      return;
    }
}

/* Locate the points in the grid (the material points on the pool's
 * threads) and activate the cells holding material;
 * keep the particles in cell order in memory; the cells of the probes and
 * surface tracers. */
static int locate(const mpgm_fe_view *v, mpm_data *d) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_scene *s = v->scene;
  const mpgm_grid *g = &d->g;
  mpgm_points *P = v->pts;
  const int np = P->n, ms = P->n + P->nprobe, m = ms + P->nsurf;
  memset(d->cact, 0, (size_t)g->ncell);
  locate_job j = {d, P, mpgm_ntask(np, 1024), {0}};
  mpgm_pool_run(v->pool, j.ntask, locate_task, &j);
  for (int t = 0; t < j.ntask; t++) /* the lowest point outside the grid */
    if (j.fail[t] < np) {
      const int p = j.fail[t];
      char x0[MPGM_POINT_STR], x[MPGM_POINT_STR], lo[MPGM_POINT_STR], hi[MPGM_POINT_STR];
      MPGM_ERROR(ctx, MPGM_ERR_DOMAIN,
                 "step %ld: particle %d (body \"%s\", started at %s) is at %s, outside the "
                 "background grid from %s to %s (mesh.domain)", d->step, P->id[p],
                 s->bodies[P->body[p]].name, mpgm_point_str(P->x0 + MPGM_DIM * p, x0),
                 mpgm_point_str(P->x + MPGM_DIM * p, x), mpgm_point_str(g->min, lo),
                 mpgm_point_str(g->max, hi));
    }
  for (int p = 0; p < np; p++) d->cact[d->pcell[p]] = 1;
  for (int p = np; p < ms; p++) /* a probe outside the grid: carried (below) */
    if (mpgm_grid_locate(g, P->x + MPGM_DIM * p, d->pcell + p, d->pxi + MPGM_DIM * p))
      d->pcell[p] = -1;
  /* The particles of a cell are used together (one group in the
   * assembly): keep them together in memory. As they cross cells their
   * order decays (the rolling disk: 60 % of the cells scattered after 20
   * steps, and an assembly 1.5x slower); once more than 1/32 of the
   * particles follow one of a higher cell, reorder them by cell (stable
   * counting sort, O(particles)). */
  long descents = 0;
  for (int p = 1; p < np; p++) descents += d->pcell[p] < d->pcell[p - 1];
  if (descents > np / 32) {
    MPGM_CALL(mpgm_points_sort(ctx, v->pool, P, d->pcell, g->ncell, d->perm));
    /* the front end's own per-particle data moves along */
    permute(d->pxi, d->pscr, d->perm, np, MPGM_DIM);
#if MPM_PLANE_ONLY
    if (d->clouds) mpgm_clouds_permute(d->clouds, d->perm, np, d->pscr); /* LME warm starts */
#endif
    for (int p = 0; p < np; p++) d->pscr[p] = d->pcell[d->perm[p]];
    for (int p = 0; p < np; p++) d->pcell[p] = (int)d->pscr[p];
  }
  /* a probe in no cell holding material (the free surface sank below it)
   * gets no functions here: mpgm_tracers_carry moves it with its nearest
   * material point */
  for (int p = np; p < ms; p++)
    if (d->pcell[p] >= 0 && probe_cell(d, P->x + MPGM_DIM * p, d->pcell + p, d->pxi + MPGM_DIM * p))
      d->pcell[p] = -1;
#if MPM_PLANE_ONLY
  if (m > ms) mpgm_cpoints_enforce_all(v->cp);
  for (int p = ms; p < m; p++)
    if (surface_cell(d, P->x + MPGM_DIM * p, d->pcell + p, d->pxi + MPGM_DIM * p))
      mpgm_cpoints_unenforce(v->cp, p - ms);
#else
  (void)m;
#endif
  return 0;
}

typedef struct {
  const mpgm_fe_view *v;
  const mpm_data *d;
} shape_job;

/* FE shape functions of point p in its cell of the undeformed grid, with
 * grid node ids. */
static int cell_point(void *arg, int p, mpgm_conn_task *t) {
  const shape_job *j = arg;
  const mpgm_grid *g = &j->d->g;
  const int nn = g->nn;
  if (mpgm_conn_task_room(t, nn)) return MPGM_ERR_NOMEM;
  const int k = t->n;
#if MPGM_DIM == 3
  /* in 3-D only the fe kind has cells, the grid's cubes: N and grad N
   * from the local coordinates, no Jacobian */
  const int *pc = j->d->pcell;
  /* the node ids of p - 1 again when it was staged just before in the
   * same cell (the material points' tasks; not the tracers' tail task) */
  const int again = nn == MPGM_FE_MAXNODE && p > t->p0 && p < t->p1 && k >= nn && pc[p] == pc[p - 1] &&
                    t->len[p - 1 - t->p0] == nn;
  if (again) /* a copy of fixed length, inlined (not a library call a point) */
    memcpy(t->node + k, t->node + k - MPGM_FE_MAXNODE, sizeof(int) * MPGM_FE_MAXNODE);
  else
    mpgm_grid_cell(g, pc[p], t->node + k, NULL); /* grid ids for now */
  mpgm_fe_cube(j->d->pxi + MPGM_DIM * p, g->h, t->N + k, t->dN + MPGM_DIM * k);
  t->n = k + nn;
  return 0;
#else
  const mpgm_points *P = j->v->pts;
  double xn[MPGM_DIM * MPGM_FE_MAXNODE];
  mpgm_grid_cell(g, j->d->pcell[p], t->node + k, xn); /* grid ids for now */
  mpgm_shape_query q = {.n = nn, .xn = xn, .cell = g->cell};
  memcpy(q.xp, P->x + MPGM_DIM * p, sizeof q.xp);
  memcpy(q.xi, j->d->pxi + MPGM_DIM * p, sizeof q.xi);
  const int err = j->v->scene->shape->eval(&q, t->N + k, t->dN + MPGM_DIM * k);
  if (err) {
    char at[MPGM_POINT_STR];
    snprintf(t->msg, sizeof t->msg, "step %ld: %s shape functions failed at point %d at %s",
             j->d->step, j->v->scene->shape->name, p < P->n ? P->id[p] : p - P->n,
             mpgm_point_str(P->x + MPGM_DIM * p, at));
    return err;
  }
  t->n = k + nn;
  return 0;
#endif
}

/* A grid kind's functions at point p from the grid nodes that may reach
 * it: uGIMP the 4 x 4 block around its square (every node within h + lp
 * < 1.5 h); a kind with a domain (CPDI; its half-axes r1, r2, none for a
 * tracer) every node within h (quadratic B-splines: 2 h) of the domain's
 * bounding box. The zero ones dropped, appended to t (grid node ids); 0,
 * or the evaluation's error with its reason in t->msg. */
static int grid_point(void *arg, int p, mpgm_conn_task *t) {
  const shape_job *j = arg;
  const mpgm_fe_view *v = j->v;
  const mpgm_grid *g = &j->d->g;
  const mpgm_points *P = v->pts;
  const double *x = P->x + MPGM_DIM * p;
  double r[MPGM_TENSOR], *dom = NULL;
  if (p < P->n && v->scene->shape->domain) {
    mpgm_point_domain(P, p, r);
    dom = r;
  }
  /* the block of grid lines lo .. hi along each axis */
  int lo[MPGM_DIM], hi[MPGM_DIM];
  long count = 1;
  const int pad = j->d->gpar.grid_order == 2; /* the splines reach 1.5 h */
  for (int a = 0; a < MPGM_DIM; a++) {
    if (v->scene->shape->domain) { /* the domain's bounding box along a */
      double e = 0.0;
      for (int c = 0; dom && c < MPGM_DIM; c++) e += fabs(dom[MPGM_DIM * c + a]);
      lo[a] = mpgm_grid_line(g, a, x[a] - e) - pad;
      hi[a] = mpgm_grid_line(g, a, x[a] + e) + 1 + pad;
    } else {
      lo[a] = mpgm_grid_line(g, a, x[a]) - 1;
      hi[a] = lo[a] + 3;
    }
    count *= (long)hi[a] - lo[a] + 1;
  }
  const char *why = NULL;
  if (v->scene->shape->domain && count > MPGM_SHAPE_MAXNODE)
    why = "the particle's domain spans more grid nodes than a point may have (MPGM_SHAPE_MAXNODE)";
  int id[MPGM_SHAPE_MAXNODE], n = 0, err = MPGM_ERR_SHAPE, clamped = 0;
  double xn[MPGM_DIM * MPGM_SHAPE_MAXNODE], N[MPGM_SHAPE_MAXNODE], dN[MPGM_DIM * MPGM_SHAPE_MAXNODE];
  const int nl[3] = {g->nx, g->ny, MPGM_DIM == 3 ? g->nz : 0};
  const int k0 = MPGM_DIM == 3 ? lo[MPGM_DIM - 1] : 0, k1 = MPGM_DIM == 3 ? hi[MPGM_DIM - 1] : 0;
  for (int kk = k0; kk <= k1 && !why; kk++)
    for (int jj = lo[1]; jj <= hi[1]; jj++)
      for (int i = lo[0]; i <= hi[0]; i++) {
        if (i < 0 || jj < 0 || kk < 0 || i > nl[0] || jj > nl[1] || kk > nl[2]) continue;
        id[n] = (kk * (g->ny + 1) + jj) * (g->nx + 1) + i;
        mpgm_grid_node(g, id[n], xn + MPGM_DIM * n);
        n++;
      }
  if (!why) {
    mpgm_shape_info info = {0};
    mpgm_shape_query q = {.n = n, .xn = xn, .cell = -1, .par = &j->d->gpar, .info = &info,
                          .domain = dom};
    memcpy(q.xp, x, sizeof q.xp);
    err = n ? v->scene->shape->eval(&q, N, dN) : MPGM_ERR_SHAPE;
    why = n ? info.msg : "no grid node near";
    clamped = info.clamped;
  }
  char at[MPGM_POINT_STR], from[MPGM_POINT_STR];
  if (err && p < P->n)
    snprintf(t->msg, sizeof t->msg, "step %ld: %s shape functions failed at point %d (body "
             "\"%s\", started at %s) at %s: %s", j->d->step, v->scene->shape->name, P->id[p],
             v->scene->bodies[P->body[p]].name, mpgm_point_str(P->x0 + MPGM_DIM * p, from),
             mpgm_point_str(x, at), why ? why : "?");
  else if (err)
    snprintf(t->msg, sizeof t->msg, "step %ld: %s shape functions failed at tracer %d at %s: %s",
             j->d->step, v->scene->shape->name, p - P->n, mpgm_point_str(x, at), why ? why : "?");
  if (err) return err;
  t->count[MPGM_C_DOMAIN_CLAMPS] += clamped;
  if (mpgm_conn_task_room(t, n)) return MPGM_ERR_NOMEM;
  for (int a = 0; a < n; a++) {
    int nonzero = N[a] != 0.0;
    for (int c = 0; c < MPGM_DIM; c++) nonzero |= dN[MPGM_DIM * a + c] != 0.0;
    if (nonzero) mpgm_conn_task_push(t, id[a], N[a], dN + MPGM_DIM * a);
  }
  return 0;
}

/* The functions of the tracers (probes, surface points) one by one after
 * the material points, from entry C->ptr[P->n]: a probe in no cell holding
 * material, or whose evaluation fails, gets none (it is carried), nor
 * does a surface point (not enforced in this step). */
static int tracer_shape(const mpgm_fe_view *v, mpm_data *d, shape_job *j,
                        mpgm_conn_point_fn fn) {
  const mpgm_points *P = v->pts;
  mpgm_conn *C = v->conn;
  const int ms = P->n + P->nprobe, m = ms + P->nsurf;
  mpgm_conn_task *t = &d->tail;
  int k = C->ptr[P->n];
  for (int p = P->n; p < m; p++) {
    C->ptr[p] = k;
    if (p >= ms && mpgm_cpoints_unenforced(v->cp, p - ms)) continue; /* no shape functions */
    if (p < ms && d->pcell[p] < 0) continue;                          /* a probe carried */
    t->n = 0;
    memset(t->count, 0, sizeof t->count);
    const int err = fn(j, p, t);
    MPGM_CHECK(v->ctx, err != MPGM_ERR_NOMEM, err, "out of memory (functions of a tracer)");
    if (err == MPGM_ERR_SHAPE && p >= ms) mpgm_cpoints_unenforce(v->cp, p - ms);
    if (err == MPGM_ERR_SHAPE) continue;
    if (err) MPGM_ERROR(v->ctx, err, "%s", t->msg);
    for (int i = 0; i < MPGM_C_COUNT; i++) v->ctx->count[i] += t->count[i];
    MPGM_CALL(mpgm_conn_grow(v->ctx, C, k, k + t->n));
    memcpy(C->node + k, t->node, sizeof(int) * (size_t)t->n);
    memcpy(C->N + k, t->N, sizeof(double) * (size_t)t->n);
    memcpy(C->dN + MPGM_DIM * (size_t)k, t->dN, sizeof(double) * MPGM_DIM * (size_t)t->n);
    k += t->n;
  }
  C->ptr[m] = k;
  return 0;
}

/* FE (cell kinds) or grid-kind functions at every point: the material
 * points on the pool's threads, where a failure is the step's
 * (recoverable) failure; then the tracers. */
static int point_shape(const mpgm_fe_view *v, mpm_data *d) {
  shape_job j = {v, d};
  const mpgm_conn_point_fn fn = d->gridfn ? grid_point : cell_point;
  const mpgm_conn_task *failed;
  const int err = mpgm_conn_par_build(v->ctx, v->pool, &d->par_build, v->pts->n, v->conn, fn, &j,
                                      &failed);
  if (err && failed) MPGM_ERROR(v->ctx, err, "%s", failed->msg);
  if (err) return err;
  return tracer_shape(v, d, &j, fn);
}

/* The nodes of the step: the grid nodes that are not light (they carry
 * mass), in grid order (node-major equation numbers stay banded), with
 * their fixity; the connectivity in step node ids. */
static void step_nodes(const mpgm_fe_view *v, mpm_data *d) {
  const mpgm_grid *g = &d->g;
  mpgm_nodes *nd = v->nodes;
  mpgm_conn *C = v->conn;
  int n = 0;
  for (int i = 0; i < g->nnode; i++) {
    d->gmap[i] = -1;
    if (d->light[i]) continue;
    d->gmap[i] = n;
    mpgm_grid_node(g, i, nd->X + MPGM_DIM * n);
    memcpy(nd->x + MPGM_DIM * n, nd->X + MPGM_DIM * n, sizeof(double) * MPGM_DIM);
    nd->contact[n] = d->gcontact[i];
    d->lglob[n] = i;
    for (int c = 0; c < MPGM_DIM; c++) {
      nd->u[MPGM_DIM * n + c] = nd->du[MPGM_DIM * n + c] = nd->ubar[MPGM_DIM * n + c] = 0.0;
      /* a contact node starts as the last step left it */
      nd->fix[MPGM_DIM * n + c] = d->gcontact[i] && d->gfree[i] ? 0 : d->gfix[MPGM_DIM * i + c];
    }
    n++;
  }
  nd->n = d->nstep = n;
  for (int k = 0; k < C->ptr[C->np]; k++) C->node[k] = d->gmap[C->node[k]];
}


/* FE: the same active cells, nodes and fixity give the same pattern (new
 * maps only); clouds change with every particle move. */
static int pattern_version(const mpgm_fe_view *v, mpm_data *d) {
  const mpgm_nodes *nd = v->nodes;
  const mpgm_conn *C = v->conn;
  const int n = nd->n;
  /* cells: the node set, the active cells (which give the pattern) and
   * the fixity of the last step; clouds: the node set and the lists of the
   * last begin_step (whose pattern the core holds) */
  int same = n == d->pn && memcmp(d->lglob, d->plglob, sizeof(int) * (size_t)n) == 0;
  if (!d->meshfree) {
    same = same && memcmp(d->cact, d->pact, (size_t)d->g.ncell) == 0;
  } else {
    const mpgm_conn *L = &d->plists;
    same = same && L->np == C->np && L->ptr && L->ptr[L->np] == C->ptr[C->np] &&
           memcmp(L->ptr, C->ptr, sizeof(int) * (size_t)(C->np + 1)) == 0 &&
           memcmp(L->node, C->node, sizeof(int) * (size_t)C->ptr[C->np]) == 0;
  }
  /* the fixity of contact nodes does not change the pattern (they keep
   * their equations), only the maps */
  for (int i = 0; i < MPGM_DIM * n && same; i++)
    same = nd->contact[i / MPGM_DIM] || nd->fix[i] == d->pfix[i];
  if (same) v->conn->map_version++;
  else v->conn->version++;
  if (!d->meshfree) return 0;
  /* clouds: this begin_step's node set and lists, for the next one */
  d->pn = n;
  memcpy(d->plglob, d->lglob, sizeof(int) * (size_t)n);
  memcpy(d->pfix, nd->fix, MPGM_DIM * (size_t)n);
  MPGM_CALL(mpgm_conn_reserve(v->ctx, &d->plists, C->np, 0));
  MPGM_CALL(mpgm_conn_grow(v->ctx, &d->plists, 0, C->ptr[C->np]));
  memcpy(d->plists.ptr, C->ptr, sizeof(int) * (size_t)(C->np + 1));
  memcpy(d->plists.node, C->node, sizeof(int) * (size_t)C->ptr[C->np]);
  return 0;
}

/* Reset the grid; locate the points; activate cells; shape functions at
 * the undeformed grid; the light-node rule (mesh.min_node_mass: the raw
 * nodal masses decide which nodes get equations, and the functions of the
 * points that lost one are renormalised); project mass, momentum and
 * inertia (eqs 38-41). */
static int mpm_begin_step(void *self, const mpgm_fe_view *v) {
  mpm_data *d = self;
  /* on many processes: the points that crossed into another's cells go there */
  MPGM_CALL(mpgm_mpm_dist_migrate(v, d));
  MPGM_CALL(mpgm_mpm_dist_probes(v, d, 0)); /* and which process moves each probe */
  const mpgm_points *P = v->pts;
  const int m = P->n + P->nprobe + P->nsurf;
  d->step++;
  int err = locate(v, d);
  /* meshfree kinds (LME-MPM, MLS-MPM): the clouds of grid nodes at the
   * undeformed grid, ids of grid nodes (discretisation/clouds.c) */
#if MPM_PLANE_ONLY
  if (!err)
    err = d->meshfree && !d->gridfn ? mpgm_clouds_build(d->clouds, v, d->tree, NULL, v->conn)
                                    : point_shape(v, d);
#else
  if (!err) err = point_shape(v, d);
#endif
  MPGM_CALL(mpgm_agree(v->ctx, err)); /* many processes: a point failed on one of them */
  memset(d->light, 0, (size_t)d->g.nnode);
#if MPGM_DIM == 3 /* the runs of the run sums (mpgm_data.h) */
  MPGM_CALL(mpgm_conn_runs(v->ctx, v->conn, P->n));
#endif
  mpgm_light_nodes(v->conn, P->n, P->mass, d->g.nnode, NULL, v->scene->mesh_par.min_node_mass, d->gm, d->light);
  MPGM_CALL(mpgm_mpm_dist_light(v, d)); /* on many processes: by the run's nodal masses */
  MPGM_CALL(mpgm_agree(v->ctx, mpgm_light_drop(v->ctx, v->conn, m, d->light, P, v->cp, v->step,
                                                v->scene->mesh_par.min_node_mass)));
  step_nodes(v, d);
  MPGM_CALL(mpgm_mpm_dist_owned(v, d)); /* many processes: which nodes are this one's */
  /* probes and surface points without functions move with the material */
  MPGM_CALL(mpgm_tracers_carry(v, v->conn, &d->carry, d->pskip));
  MPGM_CALL(mpgm_mpm_project(v, d));
  return pattern_version(v, d);
}

/* The grid is reset when the next step begins; only the contact state of
 * the grid nodes is kept, as the next step's first guess. */
static int mpm_end_step(void *self, const mpgm_fe_view *v) {
  mpm_data *d = self;
  MPGM_CALL(mpgm_mpm_dist_probes(v, d, 1)); /* many processes: the probes' movers' values */
  const mpgm_nodes *nd = v->nodes;
  memset(d->gfree, 0, (size_t)d->g.nnode);
  for (int i = 0; i < nd->n; i++)
    if (nd->contact[i]) { /* released: every component free */
      int free_all = 1;
      for (int c = 0; c < MPGM_DIM; c++) free_all &= !nd->fix[MPGM_DIM * i + c];
      d->gfree[d->lglob[i]] = (unsigned char)free_all;
    }
  d->pn = nd->n;
  memcpy(d->plglob, d->lglob, sizeof(int) * (size_t)nd->n);
  memcpy(d->pfix, nd->fix, MPGM_DIM * (size_t)nd->n);
  memcpy(d->pact, d->cact, (size_t)d->g.ncell);
  return 0;
}

/* The grid and the last step's nodes on it (output.grid). */
static void mpm_background(const void *self, mpgm_background *out) {
  const mpm_data *d = self;
  out->grid = &d->g;
  out->n = d->pn > 0 ? d->pn : 0;
  out->lglob = d->lglob;
}

/* Checkpoint: the grid nodes' contact state (the next step's first guess),
 * the steps begun, the LME warm starts. */
static int mpm_save(const void *self, mpgm_ctx *ctx, mpgm_blob *b) {
  const mpm_data *d = self;
  MPGM_CALL(mpgm_blob_put(ctx, b, "mpm.gfree", d->gfree, (size_t)d->g.nnode));
  MPGM_CALL(mpgm_blob_put(ctx, b, "mpm.step", &d->step, sizeof d->step));
#if MPM_PLANE_ONLY
  return d->clouds ? mpgm_clouds_save(d->clouds, ctx, b) : 0;
#else
  return 0;
#endif
}

static int mpm_restore(void *self, const mpgm_fe_view *v, mpgm_blob *b) {
  mpm_data *d = self;
  mpgm_ctx *ctx = v->ctx;
  MPGM_CALL(mpgm_blob_get(ctx, b, "mpm.gfree", d->gfree, (size_t)d->g.nnode));
  for (int i = 0; i < d->g.nnode; i++)
    MPGM_CHECK(ctx, d->gfree[i] <= 1, MPGM_ERR_INPUT,
               "checkpoint: section 'mpm.gfree': grid node "
               "%d holds %d (0 or 1)",
               i, d->gfree[i]);
  MPGM_CALL(mpgm_blob_get(ctx, b, "mpm.step", &d->step, sizeof d->step));
  /* steps begun: the steps done and those retried */
  MPGM_CHECK(ctx, d->step >= v->step && d->step <= LONG_MAX / 2, MPGM_ERR_INPUT,
             "checkpoint: section 'mpm.step': %ld steps "
             "begun, %ld done",
             d->step, v->step);
#if MPM_PLANE_ONLY
  const mpgm_points *P = v->pts;
  return d->clouds ? mpgm_clouds_restore(d->clouds, ctx, b, P->n + P->nprobe + P->nsurf) : 0;
#else
  return 0;
#endif
}

/* MPM's key of "mesh": the light-node rule (docs/theory.md, "tiny-mass
 * nodes") */
static const mpgm_key_spec mpm_mesh_keys[] = {MPGM_LIGHT_NODE_KEY};

const mpgm_frontend_type mpgm_frontend_mpm = {
    .name = "mpm",
    .doc = "Material Point Method: a background grid emptied and projected on every step, "
           "points carried through it",
    .persistent_nodes = 0,
    .point_velocity = MPGM_PV_NEWMARK,
#if MPGM_DIM == 2
    .shapes = MPGM_FE_SHAPE_CELL | MPGM_FE_SHAPE_CLOUD,
    .geometries = 1u << MPGM_GEOM_RECTANGLE | 1u << MPGM_GEOM_DISK | 1u << MPGM_GEOM_POLYGON |
                  1u << MPGM_GEOM_RING,
    .conditions = MPGM_FE_COND_FIX | MPGM_FE_COND_CONTACT_NODES | MPGM_FE_COND_CONTACT_POINTS,
#else /* boxes, balls, cylinders, prisms; supports (contact comes later) */
    .shapes = MPGM_FE_SHAPE_CELL | MPGM_FE_SHAPE_CLOUD, /* (the grid kinds) */
    .geometries = 1u << MPGM_GEOM_BOX | 1u << MPGM_GEOM_SPHERE | 1u << MPGM_GEOM_POLYGON |
                  1u << MPGM_GEOM_CYLINDER,
    .conditions = MPGM_FE_COND_FIX,
#endif
    .obstacles = 0,
    .explicit_schemes = 1,
    .processes = MPGM_FE_MANY_EXPLICIT,
    .mesh_keys = mpm_mesh_keys,
    .nmesh_keys = sizeof mpm_mesh_keys / sizeof *mpm_mesh_keys,
    .create = mpm_create,
    .destroy = mpm_destroy,
    .begin_step = mpm_begin_step,
    .end_step = mpm_end_step,
    .check = mpgm_mpm_check,
    .node_sums = mpgm_mpm_node_sums,
    .background = mpm_background,
    .save = mpm_save,
    .restore = mpm_restore,
};
