/* clouds.c -- node clouds and their meshfree shape functions, for every
 * front end that connects points to nodes by clouds (GMM: the persistent
 * nodes; MPM with meshfree kinds: the grid nodes). docs/theory.md,
 * section 13.
 *
 * Every material point is independent of the others: they run on the
 * pool's threads in ranges (mpgm_conn_par_build), the tracers after them
 * one by one; the result does not depend on the number of threads.
 *
 *   1. search (timed as "search"): the candidate nodes within the kind's
 *      support radius r0 of the point (kd-tree); while fewer than
 *      min_nodes, r *= 1.25 (counted: radius_growths);
 *   2. shape functions (timed as "shape") at the point's position over its
 *      cloud sorted by node id, with the kind's support set to the point's
 *      radius; LME warm-started from the point's last multiplier (a failed
 *      warm start is retried once from zero: shape_cold_restarts; probes,
 *      which use N only, are exempt from max_cond). On MPGM_ERR_SHAPE the
 *      cloud is enlarged: the next-nearest candidate at distance d sets
 *      r = max(r, 4/3 d), the cloud is searched again and the evaluation
 *      repeated (counted: cloud_enlargements), at most shape.max_enlarge
 *      times and never past MPGM_SHAPE_MAXNODE nodes; then the step fails
 *      with the recoverable MPGM_ERR_SHAPE (a surface point is left
 *      unenforced instead);
 *   3. the entries with N = 0 and grad N = 0 are dropped.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_discretisation.h"
#include "mpgm_kdtree.h"

#if MPGM_DIM != 2
#error "discretisation/clouds.c is written for plane strain only (MPGM_DIM = 2)"
#endif

/* the most growths per point (1.25^60 ~ 6e5: a search this wide that still
 * finds too few nodes means there are not that many) */
#define MAX_GROWTH 60

struct mpgm_clouds {
  const mpgm_shapefn_type *shape;
  mpgm_shape_params par; /**< the scene's parameters, h = mesh.h            */
  double r0;             /**< support radius of the kind [m]                */
  int min_nodes;         /**< smallest cloud                                */
  int max_enlarge;       /**< enlargements per point and step               */
  int m;                 /**< points                                        */
  double *lambda;        /**< LME multiplier per point (warm start),
                              MPGM_DIM each                                 */
  double *rad;           /**< search radius per point at the last build    */
  mpgm_conn_par par_build; /**< staging of the parallel build            */
  mpgm_conn_task tail;   /**< staging of the tracers, one at a time          */
  /* the step's candidates (set by mpgm_clouds_build) */
  const mpgm_kdtree *tree;
  const unsigned char *skip;
};

void mpgm_clouds_destroy(mpgm_clouds *c) {
  if (!c) return;
  free(c->lambda);
  free(c->rad);
  mpgm_conn_par_free(&c->par_build);
  mpgm_conn_task_free(&c->tail);
  free(c);
}

int mpgm_clouds_create(mpgm_ctx *ctx, const mpgm_scene *s, mpgm_clouds **out) {
  *out = NULL;
  MPGM_CHECK(ctx, !s->shape->needs_cell && s->shape->support_radius, MPGM_ERR_INPUT,
             "%s: shape.kind: node clouds need a meshfree kind, found \"%s\"", s->file, s->shape->name);
  mpgm_clouds *c;
  MPGM_ALLOC(ctx, c, 1);
  *out = c; /* from here the caller's mpgm_clouds_destroy frees it */
  c->shape = s->shape;
  c->par = s->shape_par;
  c->par.h = s->h;
  MPGM_CHECK(ctx, mpgm_shape_support_radius(s->shape, &c->par, &c->r0) == 0 && c->r0 > 0.0,
             MPGM_ERR_INPUT, "%s: shape: no support radius for kind \"%s\" (h = %g)", s->file,
             s->shape->name, s->h);
  c->min_nodes = mpgm_shape_min_nodes(&c->par);
  c->max_enlarge = c->par.max_enlarge;
  return 0;
}

/* The per-point arrays for m points (made at the first build: the points
 * exist by then). */
static int size_for(mpgm_ctx *ctx, mpgm_clouds *c, int m) {
  if (c->lambda) return 0;
  c->m = m;
  MPGM_ALLOC(ctx, c->lambda, MPGM_DIM * (size_t)m);
  MPGM_ALLOC(ctx, c->rad, m);
  return 0;
}

double mpgm_clouds_radius(const mpgm_clouds *c) { return c->r0; }

const double *mpgm_clouds_radii(const mpgm_clouds *c) { return c->rad; }

int mpgm_clouds_save(const mpgm_clouds *c, mpgm_ctx *ctx, mpgm_blob *b) {
  const int m = c->lambda ? c->m : 0;
  MPGM_CALL(mpgm_blob_put(ctx, b, "clouds.m", &m, sizeof m));
  return mpgm_blob_put(ctx, b, "clouds.lambda", c->lambda, MPGM_DIM * (size_t)m * sizeof(double));
}

int mpgm_clouds_restore(mpgm_clouds *c, mpgm_ctx *ctx, mpgm_blob *b, int npts) {
  int m;
  MPGM_CALL(mpgm_blob_get(ctx, b, "clouds.m", &m, sizeof m));
  /* none before the first build; then one per point of the problem */
  MPGM_CHECK(ctx, (m == 0 || m == npts) && (!c->lambda || m == c->m), MPGM_ERR_INPUT,
             "checkpoint: section 'clouds.m': warm starts of %d points; the problem has %d", m,
             npts);
  if (m > 0) MPGM_CALL(size_for(ctx, c, m));
  MPGM_CALL(
      mpgm_blob_get(ctx, b, "clouds.lambda", c->lambda, MPGM_DIM * (size_t)m * sizeof(double)));
  for (size_t i = 0; i < MPGM_DIM * (size_t)m; i++)
    MPGM_CHECK(ctx, isfinite(c->lambda[i]), MPGM_ERR_INPUT,
               "checkpoint: section 'clouds.lambda': "
               "point %zu holds %g, not a finite number",
               i / MPGM_DIM, c->lambda[i]);
  return 0;
}

void mpgm_clouds_permute(mpgm_clouds *c, const int *perm, int n, double *scratch) {
  if (!c->lambda) return; /* no warm start yet */
  for (int i = 0; i < n; i++) { /* 2-D only: x and y written out */
    scratch[MPGM_DIM * i] = c->lambda[MPGM_DIM * perm[i]];
    scratch[MPGM_DIM * i + 1] = c->lambda[MPGM_DIM * perm[i] + 1];
  }
  memcpy(c->lambda, scratch, sizeof(double) * MPGM_DIM * (size_t)n);
}

/* Drop the skipped nodes from a search result of n (of which min(n, cap)
 * are in idx, d2); returns the new count. */
static int drop_skipped(const mpgm_clouds *c, int n, int cap, int *idx, double *d2) {
  if (!c->skip) return n;
  const int have = n < cap ? n : cap;
  int k = 0;
  for (int a = 0; a < have; a++) {
    if (c->skip[idx[a]]) continue;
    idx[k] = idx[a];
    d2[k++] = d2[a];
  }
  return n - (have - k);
}

/* Nodes within r of x into idx (at most cap), skipped nodes left out;
 * returns the count (which may exceed cap: then idx holds the cap
 * nearest). */
static int cloud(const mpgm_clouds *c, const double x[MPGM_DIM], double r, int cap, int *idx,
                 double *d2) {
  return drop_skipped(c, mpgm_kdtree_radius_set(c->tree, x, r, cap, idx, d2), cap, idx, d2);
}

/* The cloud of x: nodes within *r (starting at the caller's radius),
 * the radius grown x MPGM_SHAPE_GROWTH while the cloud holds fewer than
 * want nodes (each growth counted in *growths), unless stray_stop and no
 * node is within the first radius. Returns the count (see cloud). */
static int grown_cloud(const mpgm_clouds *c, const double x[MPGM_DIM], int want, int stray_stop,
                       double *r, int *idx, double *d2, long *growths) {
  int n = cloud(c, x, *r, MPGM_SHAPE_MAXNODE, idx, d2);
  if (stray_stop && n == 0) return 0;
  for (int g = 0; n < want && g < MAX_GROWTH; g++) {
    *r *= MPGM_SHAPE_GROWTH;
    (*growths)++;
    n = cloud(c, x, *r, MPGM_SHAPE_MAXNODE, idx, d2);
  }
  return n;
}

/* The squared distance of the (n+1)-th nearest node that is not skipped
 * (the nearest outside a cloud of n) into *dn2; 0 when there is none. */
static int next_nearest(const mpgm_clouds *c, const double x[MPGM_DIM], int n, double *dn2) {
  enum { CAP = 2 * MPGM_SHAPE_MAXNODE + 2 };
  int ib[CAP];
  double db[CAP];
  for (int kq = n + 1;; kq = kq * 2 < CAP ? kq * 2 : CAP) {
    const int kk = mpgm_kdtree_knn(c->tree, x, kq, ib, db);
    for (int a = 0, cnt = 0; a < kk; a++) {
      if (c->skip && c->skip[ib[a]]) continue;
      if (cnt++ == n) {
        *dn2 = db[a];
        return 1;
      }
    }
    if (kk < kq || kq == CAP) return 0;
  }
}

/* the widest range of values mpgm_sort_ints sorts through a bitmap */
#define SORT_BITMAP_WORDS 128

/* Distinct values a[0..n) in a range below 64 SORT_BITMAP_WORDS from lo:
 * set as bits, read back in order. Returns 0 (a unchanged) at a repeated
 * value. */
static int sort_by_bitmap(int *a, int n, int lo, int words) {
  uint64_t bits[SORT_BITMAP_WORDS];
  memset(bits, 0, sizeof(uint64_t) * (size_t)words);
  for (int i = 0; i < n; i++) {
    const unsigned v = (unsigned)(a[i] - lo);
    const uint64_t b = (uint64_t)1 << (v & 63);
    if (bits[v >> 6] & b) return 0;
    bits[v >> 6] |= b;
  }
  int k = 0;
  for (int w = 0; w < words; w++)
    for (uint64_t x = bits[w]; x; x &= x - 1) a[k++] = lo + 64 * w + __builtin_ctzll(x);
  return 1;
}

void mpgm_sort_ints(int *a, int n) {
  if (n < 2) return;
  /* a cloud's node ids lie within a few rows of the nodes' numbering: a
   * bitmap of their range orders them in O(n + range / 64) */
  int lo = a[0], hi = a[0];
  for (int i = 1; i < n; i++) {
    if (a[i] < lo) lo = a[i];
    if (a[i] > hi) hi = a[i];
  }
  if ((long)hi - lo < 64L * SORT_BITMAP_WORDS &&
      sort_by_bitmap(a, n, lo, (int)(((long)hi - lo) / 64 + 1)))
    return;
  for (int i = 1; i < n; i++) {
    const int v = a[i];
    int j = i - 1;
    while (j >= 0 && a[j] > v) {
      a[j + 1] = a[j];
      j--;
    }
    a[j + 1] = v;
  }
}

/* What point p is, for messages. */
static const char *kind_of(const mpgm_points *P, int p) {
  return p < P->n ? "point" : p < P->n + P->nprobe ? "probe" : "surface point";
}

/* The failure of point p's functions after enl enlargements (cloud of n
 * nodes within r): the message, naming the point, into t->msg. */
static int shape_failed(const mpgm_clouds *c, const mpgm_fe_view *v, int p, int err, int enl, int n,
                        double r, const char *why, mpgm_conn_task *t) {
  const mpgm_scene *s = v->scene;
  const mpgm_points *P = v->pts;
  const double *x = P->x + MPGM_DIM * p;
  if (p < P->n)
    snprintf(t->msg, sizeof t->msg,
             "step %ld: %s shape functions failed at point %d (body \"%s\", started at (%g, "
             "%g)) at (%g, %g) after %d cloud enlargement(s) (cloud of %d nodes within %g "
             "m; shape.max_enlarge = %d): %s",
             v->step + 1, c->shape->name, P->id[p], s->bodies[P->body[p]].name,
             P->x0[MPGM_DIM * p], P->x0[MPGM_DIM * p + 1], x[0], x[1], enl, n, r,
             c->max_enlarge, why ? why : "?");
  else if (p < P->n + P->nprobe)
    snprintf(t->msg, sizeof t->msg,
             "step %ld: %s shape functions failed at probe \"%s\" at (%g, %g) after %d cloud "
             "enlargement(s) (cloud of %d nodes within %g m): %s",
             v->step + 1, c->shape->name, s->probes[p - P->n].name, x[0], x[1], enl, n, r,
             why ? why : "?");
  else
    snprintf(t->msg, sizeof t->msg,
             "step %ld: %s shape functions failed at surface point %d at (%g, %g) after %d cloud "
             "enlargement(s) (cloud of %d nodes within %g m): %s",
             v->step + 1, c->shape->name, p - P->n - P->nprobe, x[0], x[1], enl, n, r,
             why ? why : "?");
  return err;
}

/* Phase 2 for one point: N and grad N over its cloud (n nodes idx within
 * r) at its position, with enlargements on MPGM_ERR_SHAPE; the non-zero
 * entries appended to t. Counters and the time of the extra searches go to
 * t (this runs on a worker thread). */
static int shape_point(const mpgm_clouds *c, const mpgm_fe_view *v, int p, int n, double r,
                       int *idx, double *d2, mpgm_conn_task *t) {
  const mpgm_points *P = v->pts;
  const double *xn_all = mpgm_kdtree_points(c->tree), *x = P->x + MPGM_DIM * p;
  double xn[MPGM_DIM * MPGM_SHAPE_MAXNODE], N[MPGM_SHAPE_MAXNODE], dN[MPGM_DIM * MPGM_SHAPE_MAXNODE];
  mpgm_shape_info info = {0};
  int err = 0, enl = 0;
  for (;; enl++) {
    mpgm_sort_ints(idx, n);
    for (int a = 0; a < n; a++) { /* 2-D only: x and y written out */
      xn[MPGM_DIM * a] = xn_all[MPGM_DIM * idx[a]];
      xn[MPGM_DIM * a + 1] = xn_all[MPGM_DIM * idx[a] + 1];
    }
    mpgm_shape_params par;
    mpgm_shape_params_for_radius(&c->par, c->r0, r, &par);
    /* a probe uses N only (its grad N is never assembled): the condition
     * limit, which guards grad N, does not apply. A probe on the boundary
     * of the body (the cantilever's tip) is on the hull of its cloud, where
     * cond(J) of LME grows like 1 / (Newton residual) past 1e12 */
    if (p >= P->n) par.max_cond = 1e300;
    /* 2-D only: the query's position written out (mpgm_shapefn.h) */
    const mpgm_shape_query q = {.n = n, .xn = xn, .xp = {x[0], x[1]}, .cell = -1, .par = &par,
                                .lambda = c->lambda + MPGM_DIM * p, .info = &info};
    /* an LME warm start that stalls is retried once from lambda = 0
     * before the cloud is enlarged */
    err = n > 0 ? mpgm_shape_eval_retry(c->shape, &q, N, dN, &t->count[MPGM_C_COLD_RESTARTS])
                : MPGM_ERR_SHAPE;
    if (!err && p == 0 && mpgm_fault_due(v->ctx, MPGM_ERR_SHAPE, v->step + 1)) { /* tests */
      err = MPGM_ERR_SHAPE;
      info.msg = "failure made on purpose (MPGM_TEST_FAULT)";
    }
    if (n == 0) info.msg = "no node within the support radius";
    /* a point with no node within its support is not enlarged: the
     * nearest node may be across the domain; nor one whose grid lacks
     * nodes (uGIMP: more nodes cannot supply them) */
    if (err != MPGM_ERR_SHAPE || enl >= c->max_enlarge || n == 0 ||
        info.reason == MPGM_SHAPE_OFF_GRID)
      break;
    /* enlarge: the next-nearest node outside the cloud */
    const double t0 = mpgm_wtime();
    double dn2;
    const int more = next_nearest(c, x, n, &dn2);
    int nn = n;
    if (more) {
      r = fmax(r * (1.0 + 1e-9), MPGM_SHAPE_ENLARGE * sqrt(dn2));
      nn = cloud(c, x, r, MPGM_SHAPE_MAXNODE, idx, d2);
    }
    t->t_aside += mpgm_wtime() - t0;
    if (!more || nn > MPGM_SHAPE_MAXNODE) { /* no node left, or the cloud is full */
      info.msg = !more ? "every node is in the cloud already"
                       : "the enlarged cloud would exceed MPGM_SHAPE_MAXNODE nodes";
      break;
    }
    t->count[MPGM_C_CLOUD_ENLARGEMENTS]++;
    n = nn;
  }
  /* MPGM_ERR_SHAPE (recoverable), or a fatal MPGM_ERR_INPUT */
  if (err) return shape_failed(c, v, p, err, enl, n, r, info.msg, t);
  c->rad[p] = r;
  if (mpgm_conn_task_room(t, n)) return MPGM_ERR_NOMEM;
  for (int a = 0; a < n; a++) {
    if (N[a] == 0.0 && dN[MPGM_DIM * a] == 0.0 && dN[MPGM_DIM * a + 1] == 0.0)
      continue; /* outside the support */
    mpgm_conn_task_push(t, idx[a], N[a], dN + MPGM_DIM * a);
  }
  return 0;
}

typedef struct {
  mpgm_clouds *c;
  const mpgm_fe_view *v;
  int want; /**< smallest cloud: min_nodes, or every node when fewer */
} cloud_job;

/* Phase 1 for the points of task t: the clouds from the radius search,
 * with radius growth up to min_nodes nodes, into t->iscr (per point: the
 * offset of its nodes, their count, which may exceed MPGM_SHAPE_MAXNODE,
 * and the growths of its radius; then the nodes), timed into t_aside. */
static int search_range(const cloud_job *j, mpgm_conn_task *t) {
  const mpgm_clouds *c = j->c;
  const mpgm_points *P = j->v->pts;
  const int np = t->p1 - t->p0;
  const double t0 = mpgm_wtime();
  size_t used = 3 * (size_t)np;
  int err = mpgm_conn_task_iscr(t, used + 16 * (size_t)np);
  int idx[MPGM_SHAPE_MAXNODE];
  double d2[MPGM_SHAPE_MAXNODE];
  for (int p = t->p0; p < t->p1 && !err; p++) {
    double r = c->r0;
    long growths = 0;
    /* a probe or surface point with no node within its support is away
     * from the material: it gets no functions (mpgm_tracers_carry then
     * moves it with the material), never a radius grown across the
     * domain */
    const int n = grown_cloud(c, P->x + MPGM_DIM * p, j->want, p >= P->n, &r, idx, d2, &growths);
    const int have = n < MPGM_SHAPE_MAXNODE ? n : MPGM_SHAPE_MAXNODE;
    err = mpgm_conn_task_iscr(t, used + (size_t)have);
    if (err) break;
    int *h = t->iscr + 3 * (p - t->p0);
    h[0] = (int)used;
    h[1] = n;
    h[2] = (int)growths;
    memcpy(t->iscr + used, idx, sizeof(int) * (size_t)have);
    used += (size_t)have;
    t->count[MPGM_C_RADIUS_GROWTHS] += growths;
  }
  t->t_aside += mpgm_wtime() - t0;
  return err;
}

/* Point p: its cloud (the range's search at its first point), then its
 * functions (phase 2). */
static int cloud_point(void *arg, int p, mpgm_conn_task *t) {
  const cloud_job *j = arg;
  const mpgm_clouds *c = j->c;
  const mpgm_fe_view *v = j->v;
  const mpgm_points *P = v->pts;
  if (p == t->p0 && search_range(j, t)) return MPGM_ERR_NOMEM;
  const int *h = t->iscr + 3 * (p - t->p0), n = h[1];
  int idx[MPGM_SHAPE_MAXNODE + 1];
  double d2[MPGM_SHAPE_MAXNODE + 1];
  double r = c->r0;
  for (int g = 0; g < h[2]; g++) r *= MPGM_SHAPE_GROWTH; /* as grown_cloud grew it */
  if (n > MPGM_SHAPE_MAXNODE) {
    const double *x = P->x + MPGM_DIM * p;
    snprintf(t->msg, sizeof t->msg,
             "%s: shape: step %ld: %s %d at (%g, %g) has %d nodes within its support radius "
             "%g m, more than MPGM_SHAPE_MAXNODE = %d: lower shape.radius / shape.dilation "
             "(mls) or raise shape.gamma (lme)",
             v->scene->file, v->step + 1, kind_of(P, p), p < P->n ? P->id[p] : p - P->n, x[0],
             x[1], n, r, MPGM_SHAPE_MAXNODE);
    return MPGM_ERR_INPUT;
  }
  memcpy(idx, t->iscr + h[0], sizeof(int) * (size_t)n);
  return shape_point(c, v, p, n, r, idx, d2, t);
}

/* The tracers (probes, surface points) one by one after the material
 * points, from entry k of out: one that fails gets no functions (contact
 * is not enforced at a surface point in this step): mpgm_tracers_carry
 * moves it with its nearest material point. */
static int tracers(mpgm_clouds *c, cloud_job *j, mpgm_conn *out, int *k) {
  const mpgm_fe_view *v = j->v;
  mpgm_ctx *ctx = v->ctx;
  const mpgm_points *P = v->pts;
  const int m = P->n + P->nprobe + P->nsurf;
  mpgm_conn_task *t = &c->tail;
  for (int p = P->n; p < m; p++) {
    out->ptr[p] = *k;
    t->n = 0;
    t->p0 = p;
    t->p1 = p + 1;
    memset(t->count, 0, sizeof t->count);
    const int err = cloud_point(j, p, t);
    for (int i = 0; i < MPGM_C_COUNT; i++) ctx->count[i] += t->count[i];
    if (err == MPGM_ERR_SHAPE) {
      const int surf = p - (P->n + P->nprobe); /* >= 0: a surface point */
      if (surf >= 0) mpgm_cpoints_unenforce(v->cp, surf);
      continue;
    }
    MPGM_CHECK(ctx, err != MPGM_ERR_NOMEM, err, "out of memory (functions of a tracer)");
    if (err) MPGM_ERROR(ctx, err, "%s", t->msg);
    MPGM_CALL(mpgm_conn_grow(ctx, out, *k, *k + t->n));
    memcpy(out->node + *k, t->node, sizeof(int) * (size_t)t->n);
    memcpy(out->N + *k, t->N, sizeof(double) * (size_t)t->n);
    memcpy(out->dN + MPGM_DIM * (size_t)*k, t->dN, sizeof(double) * MPGM_DIM * (size_t)t->n);
    *k += t->n;
  }
  out->ptr[m] = *k;
  return 0;
}

int mpgm_clouds_build(mpgm_clouds *c, const mpgm_fe_view *v, const mpgm_kdtree *tree,
                      const unsigned char *skip, mpgm_conn *out) {
  mpgm_ctx *ctx = v->ctx;
  const int m = v->pts->n + v->pts->nprobe + v->pts->nsurf;
  MPGM_CALL(size_for(ctx, c, m));
  MPGM_CHECK(ctx, m == c->m, MPGM_ERR_INTERNAL, "node clouds of %d points, asked for %d", c->m, m);
  c->tree = tree;
  c->skip = skip;
  const int nnode = mpgm_kdtree_size(tree);
  cloud_job j = {c, v, c->min_nodes < nnode ? c->min_nodes : nnode};
  MPGM_CALL(mpgm_conn_reserve(ctx, out, m, 0));
  /* the material points on the pool's threads; the caller times this as
   * "shape": the search's share is moved to "search", so that the two
   * add up to the call */
  const mpgm_conn_task *failed;
  const int err = mpgm_conn_par_build(ctx, v->pool, &c->par_build, v->pts->n, out, cloud_point, &j,
                                      &failed);
  mpgm_timer_move(ctx, MPGM_T_SHAPE, MPGM_T_SEARCH, c->par_build.t_aside);
  if (err && failed) MPGM_ERROR(ctx, err, "%s", failed->msg);
  if (err) return err;
  int k = out->ptr[v->pts->n];
  return tracers(c, &j, out, &k);
}

int mpgm_clouds_eval_at(mpgm_clouds *c, mpgm_ctx *ctx, const mpgm_kdtree *tree,
                        const unsigned char *skip, const double x[MPGM_DIM], int *idx, double *N,
                        int *n_out) {
  *n_out = 0;
  c->tree = tree;
  c->skip = skip;
  const int nnode = mpgm_kdtree_size(tree), want = c->min_nodes < nnode ? c->min_nodes : nnode;
  double d2[MPGM_SHAPE_MAXNODE], xn[MPGM_DIM * MPGM_SHAPE_MAXNODE], dN[MPGM_DIM * MPGM_SHAPE_MAXNODE];
  double r = c->r0;
  long growths = 0; /* not the points' radius_growths */
  const int n = grown_cloud(c, x, want, 0, &r, idx, d2, &growths);
  if (n == 0 || n > MPGM_SHAPE_MAXNODE) return MPGM_ERR_SHAPE;
  mpgm_sort_ints(idx, n);
  const double *xa = mpgm_kdtree_points(tree);
  for (int a = 0; a < n; a++) { /* 2-D only: x and y written out */
    xn[MPGM_DIM * a] = xa[MPGM_DIM * idx[a]];
    xn[MPGM_DIM * a + 1] = xa[MPGM_DIM * idx[a] + 1];
  }
  mpgm_shape_params par;
  mpgm_shape_params_for_radius(&c->par, c->r0, r, &par);
  par.max_cond = 1e300; /* N only */
  double lambda[MPGM_DIM] = {0};
  mpgm_shape_info info = {0};
  const mpgm_shape_query q = {.n = n, .xn = xn, .xp = {x[0], x[1]}, .cell = -1, .par = &par,
                              .lambda = lambda, .info = &info};
  int err = mpgm_shape_eval_retry(c->shape, &q, N, dN, &ctx->count[MPGM_C_COLD_RESTARTS]);
  if (err == MPGM_ERR_SHAPE) {
    /* a position on the hull of its cloud (a node on the body's outline),
     * where LME's multiplier runs to infinity: once more 1e-3 of the way
     * towards the cloud's centroid, inside the hull */
    double cx[MPGM_DIM] = {0};
    for (int a = 0; a < n; a++) { /* 2-D only */
      cx[0] += xn[MPGM_DIM * a] / n;
      cx[1] += xn[MPGM_DIM * a + 1] / n;
    }
    const mpgm_shape_query q2 = {.n = n, .xn = xn, .xp = {x[0] + 1e-3 * (cx[0] - x[0]),
                                                         x[1] + 1e-3 * (cx[1] - x[1])},
                                 .cell = -1, .par = &par, .lambda = lambda, .info = &info};
    lambda[0] = lambda[1] = 0.0;
    err = mpgm_shape_eval_retry(c->shape, &q2, N, dN, &ctx->count[MPGM_C_COLD_RESTARTS]);
  }
  if (!err) *n_out = n;
  return err;
}
