/* skin.c -- sparsity patterns that outlive a step for node clouds
 * (shape.skin; docs/theory.md, section 13, "Pattern skin").
 *
 * A cloud changes whenever a point or a node crosses the support radius of
 * the other, so a front end that connects points by clouds would build a
 * new sparsity pattern, and the solver a new symbolic analysis, almost
 * every step. As molecular-dynamics neighbour lists do, the pattern is
 * built instead from lists one skin wider than the clouds: point p's list
 * holds the nodes within r_p + skin at the build, r_p its search radius
 * then. The lists are kept while every point's cloud is a subset of its
 * list, which is checked exactly at every step (one merge of two sorted
 * lists per point), not bounded by displacements: a body that moves or
 * turns as a whole keeps its lists however far it goes. Every coupling of
 * the clouds is then in the pattern, and the entries outside the clouds
 * are exact zeros of K: the answer is that of the pattern without skin,
 * up to the round-off of another elimination order.
 *
 * With a tangent radius rt (shape.tangent_radius) the lists hold the nodes
 * within min(r_p, rt) + skin, and they hold while every node of a cloud
 * within rt of its point is in its list. The tangent then couples only
 * the nodes of each point's list (conn.tan), while the residual takes the
 * whole cloud: K is that of smaller clouds, an approximation of the
 * Jacobian that modified Newton corrects by iterating on the exact R.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_discretisation.h"
#include "mpgm_kdtree.h"

/* a list longer than this (a very wide cloud plus its skin) gives up the
 * skin for the step: the clouds' own lists make the pattern */
#define SKIN_MAXLIST (4 * MPGM_SHAPE_MAXNODE)

struct mpgm_skin {
  double skin;  /**< [m]                                               */
  double rt;    /**< the tangent radius [m] (0: the clouds' own)       */
  int wide;     /**< the lists were built without the tangent radius  */
  int np;       /**< material points of the last build                 */
  int valid;    /**< the lists are built and usable                   */
  int *ptr;     /**< np + 1 offsets into node                          */
  int *node;    /**< the lists, each by increasing node id             */
  int cap;      /**< room of node                                      */
};

int mpgm_skin_create(mpgm_ctx *ctx, double skin, double rt, mpgm_skin **out) {
  *out = NULL;
  MPGM_CHECK(ctx, skin > 0.0 && isfinite(skin), MPGM_ERR_INPUT, "pattern skin %g m: expected > 0", skin);
  MPGM_CHECK(ctx, rt >= 0.0 && isfinite(rt), MPGM_ERR_INPUT, "tangent radius %g m: expected >= 0", rt);
  mpgm_skin *s;
  MPGM_ALLOC(ctx, s, 1);
  s->skin = skin;
  s->rt = rt;
  *out = s;
  return 0;
}

void mpgm_skin_destroy(mpgm_skin *s) {
  if (!s) return;
  free(s->ptr);
  free(s->node);
  free(s);
}

/* Room for np points (kept from build to build). */
static int size_for(mpgm_ctx *ctx, mpgm_skin *s, int np) {
  if (s->ptr && s->np == np) return 0;
  free(s->ptr);
  s->ptr = malloc(((size_t)np + 1) * sizeof(int));
  s->np = np;
  s->valid = 0;
  MPGM_CHECK(ctx, s->ptr, MPGM_ERR_NOMEM, "out of memory (pattern skin of %d points)", np);
  return 0;
}

/* The squared distance of x and y. */
static inline double dist2(const double *x, const double *y) {
  double d = 0.0;
  for (int i = 0; i < MPGM_DIM; i++) d += (x[i] - y[i]) * (x[i] - y[i]);
  return d;
}

/* 1 when every cloud of C (the first np lists, by increasing node id) is
 * within its point's list; with a tangent radius, every node of a cloud
 * within rt of its point (xp the points, xn the nodes), and tan (when not
 * NULL) marks the entries of C in the lists. */
static int still_holds(const mpgm_skin *s, int np, const mpgm_conn *C, const double *xp,
                       const double *xn, double rt, unsigned char *tan) {
  if (!s->valid || s->np != np) return 0;
  const double rt2 = rt * rt;
  for (int p = 0; p < np; p++) {
    int t = s->ptr[p];
    const int tend = s->ptr[p + 1];
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      while (t < tend && s->node[t] < C->node[k]) t++;
      const int in = t < tend && s->node[t] == C->node[k];
      if (tan) tan[k] = (unsigned char)in;
      if (in) continue;
      if (rt == 0.0 || dist2(xp + MPGM_DIM * p, xn + MPGM_DIM * C->node[k]) <= rt2) return 0;
    }
  }
  return 1;
}

/* The lists: for each point the nodes of tree within rp + skin. 0, or 1
 * when a list would exceed SKIN_MAXLIST (the skin is given up). */
static int build(mpgm_ctx *ctx, mpgm_skin *s, const double *xp, const double *rp, double rt,
                 const mpgm_kdtree *tree, int *overflow) {
  int idx[SKIN_MAXLIST];
  double d2[SKIN_MAXLIST];
  *overflow = 0;
  int k = 0;
  s->ptr[0] = 0;
  for (int p = 0; p < s->np; p++) {
    const double r = rt > 0.0 && rt < rp[p] ? rt : rp[p];
    const int n = mpgm_kdtree_radius_set(tree, xp + MPGM_DIM * p, r + s->skin, SKIN_MAXLIST, idx, d2);
    if (n > SKIN_MAXLIST) {
      *overflow = 1;
      return 0;
    }
    if (k + n > s->cap) {
      const int cap = 2 * (k + n) + 1024;
      int *node = realloc(s->node, (size_t)cap * sizeof(int));
      MPGM_CHECK(ctx, node, MPGM_ERR_NOMEM, "out of memory (pattern skin lists)");
      s->node = node;
      s->cap = cap;
    }
    mpgm_sort_ints(idx, n);
    memcpy(s->node + k, idx, sizeof(int) * (size_t)n);
    k += n;
    s->ptr[p + 1] = k;
  }
  return 0;
}

int mpgm_skin_update(mpgm_skin *s, mpgm_ctx *ctx, int np, const double *xp, const double *rp,
                     const double *xn, const mpgm_conn *C, const mpgm_kdtree *tree,
                     int wide, unsigned char *tan, int *rebuilt) {
  *rebuilt = 0;
  const double rt = wide ? 0.0 : s->rt;
  if (rt == 0.0) tan = NULL;
  /* lists built wide are built again once the tangent radius applies,
   * unless no cloud reaches past it (then they are the narrow lists) */
  int narrow = 0;
  if (s->wide && rt > 0.0)
    for (int p = 0; p < np && !narrow; p++) narrow = rp[p] > rt;
  if (!narrow) s->wide = s->wide && rt == 0.0;
  if (!narrow && still_holds(s, np, C, xp, xn, rt, tan)) return 0;
  *rebuilt = 1;
  MPGM_CALL(size_for(ctx, s, np));
  int overflow;
  MPGM_CALL(build(ctx, s, xp, rp, rt, tree, &overflow));
  s->valid = !overflow;
  s->wide = s->rt > 0.0 && rt == 0.0;
  /* the new lists' marks (they hold every cloud by construction) */
  if (s->valid && tan) still_holds(s, np, C, xp, xn, rt, tan);
  return 0;
}

const int *mpgm_skin_ptr(const mpgm_skin *s) { return s->valid ? s->ptr : NULL; }

const int *mpgm_skin_node(const mpgm_skin *s) { return s->valid ? s->node : NULL; }

int mpgm_skin_save(const mpgm_skin *s, mpgm_ctx *ctx, mpgm_blob *b) {
  /* valid 2: lists built wide (a format of valid 0 or 1 before) */
  const int head[2] = {s->valid ? 1 + s->wide : 0, s->np};
  MPGM_CALL(mpgm_blob_put(ctx, b, "skin.head", head, sizeof head));
  if (!s->valid) return 0;
  MPGM_CALL(mpgm_blob_put(ctx, b, "skin.ptr", s->ptr, ((size_t)s->np + 1) * sizeof(int)));
  return mpgm_blob_put(ctx, b, "skin.node", s->node, (size_t)s->ptr[s->np] * sizeof(int));
}

/* The lists read back: offsets from 0 up, each list of at most
 * SKIN_MAXLIST increasing node numbers below nnode (still_holds and the
 * pattern index with them). */
static int check_lists(const mpgm_skin *s, mpgm_ctx *ctx, int nnode) {
  MPGM_CHECK(ctx, s->ptr[0] == 0, MPGM_ERR_INPUT,
             "checkpoint: section 'skin.ptr': the first "
             "list starts at %d, not 0",
             s->ptr[0]);
  for (int p = 0; p < s->np; p++) {
    const int n = s->ptr[p + 1] - s->ptr[p];
    MPGM_CHECK(ctx, s->ptr[p + 1] >= s->ptr[p] && n <= SKIN_MAXLIST, MPGM_ERR_INPUT,
               "checkpoint: section 'skin.ptr': point %d's list runs from %d to %d (at most %d "
               "nodes)",
               p, s->ptr[p], s->ptr[p + 1], SKIN_MAXLIST);
  }
  for (int p = 0; p < s->np; p++)
    for (int k = s->ptr[p]; k < s->ptr[p + 1]; k++)
      MPGM_CHECK(ctx,
                 s->node[k] >= 0 && s->node[k] < nnode &&
                     (k == s->ptr[p] || s->node[k] > s->node[k - 1]),
                 MPGM_ERR_INPUT,
                 "checkpoint: section 'skin.node': point %d's list holds node %d (of %d, in "
                 "increasing order)",
                 p, s->node[k], nnode);
  return 0;
}

int mpgm_skin_restore(mpgm_skin *s, mpgm_ctx *ctx, mpgm_blob *b, int np, int nnode) {
  int head[2];
  MPGM_CALL(mpgm_blob_get(ctx, b, "skin.head", head, sizeof head));
  s->valid = 0;
  if (!head[0]) return 0;
  MPGM_CHECK(ctx, head[0] >= 0 && head[0] <= 2 && head[1] == np, MPGM_ERR_INPUT,
             "checkpoint: "
             "section 'skin.head': lists of kind %d for %d points; the problem has %d",
             head[0], head[1], np);
  s->wide = head[0] == 2;
  MPGM_CALL(size_for(ctx, s, head[1]));
  MPGM_CALL(mpgm_blob_get(ctx, b, "skin.ptr", s->ptr, ((size_t)s->np + 1) * sizeof(int)));
  const int k = s->ptr[s->np];
  MPGM_CHECK(ctx, k >= 0 && k <= (long)s->np * SKIN_MAXLIST, MPGM_ERR_INPUT,
             "checkpoint: section "
             "'skin.ptr': lists of %d entries for %d points",
             k, s->np);
  size_t len;
  MPGM_CALL(mpgm_blob_peek(ctx, b, "skin.node", &len));
  MPGM_CHECK(ctx, len == (size_t)k * sizeof(int), MPGM_ERR_INPUT,
             "checkpoint: section 'skin.node' "
             "holds %zu bytes, 'skin.ptr' says %zu",
             len, (size_t)k * sizeof(int));
  if (k > s->cap) {
    free(s->node);
    s->node = malloc(((size_t)k + 1) * sizeof(int));
    s->cap = s->node ? k : 0;
    MPGM_CHECK(ctx, s->node, MPGM_ERR_NOMEM, "out of memory (pattern skin lists)");
  }
  MPGM_CALL(mpgm_blob_get(ctx, b, "skin.node", s->node, (size_t)k * sizeof(int)));
  MPGM_CALL(check_lists(s, ctx, nnode));
  s->valid = 1;
  return 0;
}
