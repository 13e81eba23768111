/* kdtree.c -- kd-tree over borrowed 2-D points (see mpgm_kdtree.h).
 *
 * 2-D only: the coordinates have stride MPGM_DIM, but boxes (box_add,
 * box_empty, the children's boxes in build_rec), the choice of the split
 * dimension, the finiteness checks, the query point (qx, qy), the squared
 * distances dx dx + dy dy, the bound g[0] + g[1] and the gaps pushed with
 * a subtree (g[dim], g[1 - dim]) are written out in x and y (3-D: a third
 * term, the other two gaps).
 *
 * Layout: nodes in one array in depth-first order, so the left child of node
 * i is i + 1 and the right child is stored; every node has its tight box.
 * Children come after their parent, which lets refit run one backward sweep.
 * Queries walk the tree with an explicit stack bounded by the depth bound of
 * the split rule (KD_STACK), visit the nearer child first, and prune a child
 * whose lower bound is beyond the current bound. As in nanoflann, the bound
 * is kept per dimension: g[d] is a squared distance along d that no point of
 * the subtree is closer than; at a split along d, a child's g[d] becomes the
 * larger of the parent's and the gap from q to the child's side facing the
 * other child (left: its max, right: its min along d), and its bound is
 * g[0] + g[1]. Only the parent's two child sides are read, never a whole box.
 * The gaps are rounded like the points' own dx, dy (side - q or q - side), and
 * rounding is monotonic, so a bound never exceeds the computed d2 of a point
 * it covers: pruning is exact, also at ties and after refit (when boxes of
 * siblings overlap the gaps are just 0). */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_kdtree.h"

#if MPGM_DIM != 2
#error "discretisation/kdtree.c is written for plane strain only (MPGM_DIM = 2)"
#endif

/* Explicit query stack. A child holds at most 7/8 of its parent's points and
 * a node with fewer than 2 points is a leaf, so depth <= log_{8/7}(n / 2) + 1
 * <= 161 for n < 2^31; the build checks it. */
#define KD_STACK 192

/* kNN sets up to this k keep a sorted array (insertion); larger ones a heap. */
#define KNN_SORTED_MAX 48

/* Results up to this many are sorted by insertion, more by heapsort. */
#define SORT_INSERTION_MAX 32

typedef struct kd_node {
  double lo[MPGM_DIM], hi[MPGM_DIM]; /* tight bounding box of its points   */
  int a;               /* leaf: first position in perm; internal: right child */
  int b;               /* leaf: one past the last position (> 0);
                          internal: -1 - split dimension                   */
} kd_node;

struct mpgm_kdtree {
  const double *xy;  /* borrowed coordinates, MPGM_DIM per point          */
  int n;             /* points                                            */
  int leaf_size;     /* maximum points per leaf                           */
  int built;         /* the structure is complete (refit may run)         */
  int valid;         /* built and boxes up to date; else queries give 0   */
  int *perm;         /* point indices, leaves own contiguous ranges       */
  int perm_cap;      /* allocated entries of perm                         */
  kd_node *nodes;    /* depth-first node array, root at 0                 */
  int nnodes;        /* nodes in use                                      */
  int nodes_cap;     /* allocated nodes                                   */
  int depth;         /* deepest leaf (edges from the root)                */
  int median_splits; /* internal nodes cut at the median                  */
};

/* ------------------------------------------------------------ small helpers */

/* (da, ia) < (db, ib): the order of all results */
static inline int before(double da, int ia, double db, int ib) {
  return da < db || (da == db && ia < ib);
}

#if defined(__GNUC__)
#define KD_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define KD_ALWAYS_INLINE inline
#endif

/* Per-dimension squared gaps from q to the root box (0 inside). */
static inline void root_gaps(const kd_node *root, const double q[MPGM_DIM], double g[MPGM_DIM]) {
  for (int d = 0; d < MPGM_DIM; d++) {
    const double a = root->lo[d] - q[d], b = q[d] - root->hi[d];
    const double gap = a > 0.0 ? a : b > 0.0 ? b : 0.0; /* not fmax: a libm call */
    g[d] = gap * gap;
  }
}

/* At internal node nd (index node) with the gaps g of its subtree: the
 * squared gaps along the split dimension of the left (gl) and right (gr)
 * child, never below g[dim]. */
static KD_ALWAYS_INLINE int child_gaps(const kd_node *nodes, const kd_node *nd,
                                       const double q[MPGM_DIM], const double g[MPGM_DIM],
                                       double *gl, double *gr) {
  const int dim = -1 - nd->b;
  const double a = q[dim] - nd[1].hi[dim];        /* left child = next node */
  const double b = nodes[nd->a].lo[dim] - q[dim]; /* right child            */
  const double l = a > 0.0 ? a * a : 0.0, r = b > 0.0 ? b * b : 0.0;
  *gl = l > g[dim] ? l : g[dim];
  *gr = r > g[dim] ? r : g[dim];
  return dim;
}

/* 2-D only (x and y written out), as box_empty. */
static inline void box_add(double lo[MPGM_DIM], double hi[MPGM_DIM], const double *p) {
  if (p[0] < lo[0]) lo[0] = p[0];
  if (p[0] > hi[0]) hi[0] = p[0];
  if (p[1] < lo[1]) lo[1] = p[1];
  if (p[1] > hi[1]) hi[1] = p[1];
}

static inline void box_empty(double lo[MPGM_DIM], double hi[MPGM_DIM]) {
  lo[0] = lo[1] = INFINITY;
  hi[0] = hi[1] = -INFINITY;
}

/* ------------------------------------------------------------ max-heap on (d2, idx) */

static void heap_sift_down(int *idx, double *d2, int m, int i) {
  const int ii = idx[i];
  const double di = d2[i];
  for (;;) {
    int c = 2 * i + 1;
    if (c >= m) break;
    if (c + 1 < m && before(d2[c], idx[c], d2[c + 1], idx[c + 1])) c++;
    if (!before(di, ii, d2[c], idx[c])) break;
    idx[i] = idx[c], d2[i] = d2[c];
    i = c;
  }
  idx[i] = ii, d2[i] = di;
}

static void heap_sift_up(int *idx, double *d2, int i) {
  const int ii = idx[i];
  const double di = d2[i];
  while (i > 0) {
    const int p = (i - 1) / 2;
    if (!before(d2[p], idx[p], di, ii)) break;
    idx[i] = idx[p], d2[i] = d2[p];
    i = p;
  }
  idx[i] = ii, d2[i] = di;
}

static void heapify(int *idx, double *d2, int m) {
  for (int i = m / 2 - 1; i >= 0; i--) heap_sift_down(idx, d2, m, i);
}

/* Sort a max-heap of m entries into ascending (d2, idx) order. */
static void heap_sort_down(int *idx, double *d2, int m) {
  for (int e = m - 1; e > 0; e--) {
    const int ti = idx[0];
    const double td = d2[0];
    idx[0] = idx[e], d2[0] = d2[e];
    idx[e] = ti, d2[e] = td;
    heap_sift_down(idx, d2, e, 0);
  }
}

static void insertion_sort(int *idx, double *d2, int m) {
  for (int i = 1; i < m; i++) {
    const int ii = idx[i];
    const double di = d2[i];
    int j = i;
    for (; j > 0 && before(di, ii, d2[j - 1], idx[j - 1]); j--)
      idx[j] = idx[j - 1], d2[j] = d2[j - 1];
    idx[j] = ii, d2[j] = di;
  }
}

static inline void swap_res(int *idx, double *d2, int a, int b) {
  const int ti = idx[a];
  const double td = d2[a];
  idx[a] = idx[b], d2[a] = d2[b];
  idx[b] = ti, d2[b] = td;
}

/* Sort m unordered results by (d2, idx): introsort (quicksort, median of
 * three, heapsort when too deep, insertion sort for short runs). The keys
 * are distinct (distinct indices), so no care for equal keys is needed. */
static void sort_results(int *idx, double *d2, int m) {
  int budget = 2;
  for (int s = m; s > 1; s >>= 1) budget += 2;
  while (m > SORT_INSERTION_MAX) {
    if (--budget == 0) {
      heapify(idx, d2, m);
      heap_sort_down(idx, d2, m);
      return;
    }
    const int mid = m / 2;
    if (before(d2[mid], idx[mid], d2[0], idx[0])) swap_res(idx, d2, mid, 0);
    if (before(d2[m - 1], idx[m - 1], d2[0], idx[0])) swap_res(idx, d2, m - 1, 0);
    if (before(d2[m - 1], idx[m - 1], d2[mid], idx[mid])) swap_res(idx, d2, m - 1, mid);
    swap_res(idx, d2, mid, m - 2); /* pivot at m - 2; d2[0] <= it <= d2[m - 1] */
    const int pi = idx[m - 2];
    const double pd = d2[m - 2];
    int i = 0, j = m - 2;
    for (;;) {
      do i++;
      while (before(d2[i], idx[i], pd, pi));
      do j--;
      while (before(pd, pi, d2[j], idx[j]));
      if (i >= j) break;
      swap_res(idx, d2, i, j);
    }
    swap_res(idx, d2, i, m - 2);
    /* recurse into the smaller part, loop on the larger */
    if (i < m - 1 - i) {
      sort_results(idx, d2, i);
      idx += i + 1, d2 += i + 1, m -= i + 1;
    } else {
      sort_results(idx + i + 1, d2 + i + 1, m - i - 1);
      m = i;
    }
  }
  insertion_sort(idx, d2, m);
}

/* ------------------------------------------------------------ build */

static int new_node(mpgm_ctx *ctx, mpgm_kdtree *t, int *id) {
  if (t->nnodes == t->nodes_cap) {
    MPGM_CHECK(ctx, t->nodes_cap < INT_MAX / 2, MPGM_ERR_NOMEM, "kd-tree: too many nodes");
    const int cap = t->nodes_cap + t->nodes_cap / 2 + 16;
    kd_node *p = realloc(t->nodes, (size_t)cap * sizeof *p);
    MPGM_CHECK(ctx, p != NULL, MPGM_ERR_NOMEM, "kd-tree: out of memory (%d nodes)", cap);
    t->nodes = p, t->nodes_cap = cap;
  }
  *id = t->nnodes++;
  return 0;
}

/* Rearrange perm[lo..hi] (inclusive) so that position nth holds the point
 * whose coordinate d would be there in sorted order, smaller-or-equal ones
 * before and greater-or-equal ones after (Hoare's FIND). */
static void select_nth(int *perm, const double *xy, int d, int lo, int hi, int nth) {
#define KEY(i) xy[MPGM_DIM * (size_t)perm[i] + d]
  while (hi > lo) {
    const double a = KEY(lo), b = KEY(lo + (hi - lo) / 2), c = KEY(hi);
    const double pivot = a < b ? (b < c ? b : (a < c ? c : a)) : (a < c ? a : (b < c ? c : b));
    int i = lo, j = hi;
    while (i <= j) {
      while (KEY(i) < pivot) i++;
      while (KEY(j) > pivot) j--;
      if (i <= j) {
        const int s = perm[i];
        perm[i] = perm[j], perm[j] = s;
        i++, j--;
      }
    }
    if (nth <= j)
      hi = j;
    else if (nth >= i)
      lo = i;
    else
      break;
  }
#undef KEY
}

/* Node over perm[begin, end) with tight box (lo, hi); appends the subtree. */
static int build_rec(mpgm_ctx *ctx, mpgm_kdtree *t, int begin, int end, const double lo[MPGM_DIM],
                     const double hi[MPGM_DIM], int depth) {
  int id = 0;
  MPGM_CALL(new_node(ctx, t, &id));
  kd_node *nd = &t->nodes[id];
  nd->lo[0] = lo[0], nd->lo[1] = lo[1], nd->hi[0] = hi[0], nd->hi[1] = hi[1];
  if (depth > t->depth) t->depth = depth;
  const int count = end - begin;
  const int d = (hi[1] - lo[1]) > (hi[0] - lo[0]); /* 2-D only: the wider side */
  if (count <= t->leaf_size || !(hi[d] > lo[d])) { /* small, or identical points */
    nd->a = begin, nd->b = end;
    return 0;
  }
  MPGM_CHECK(ctx, depth + 1 < KD_STACK, MPGM_ERR_INTERNAL,
             "kd-tree: depth %d exceeds the bound of the split rule", depth + 1);

  /* middle split of the widest side; both child boxes in the same pass */
  const double *xy = t->xy;
  int *perm = t->perm;
  double cut = 0.5 * lo[d] + 0.5 * hi[d];
  if (!(cut > lo[d]) || cut > hi[d]) cut = hi[d]; /* adjacent doubles */
  double llo[MPGM_DIM], lhi[MPGM_DIM], rlo[MPGM_DIM], rhi[MPGM_DIM];
  box_empty(llo, lhi), box_empty(rlo, rhi);
  /* Lomuto partition, the swap done by selects: the loads depend only on
   * perm[k] (read in order), so the processor keeps many of them in flight
   * (a Hoare partition's data-dependent branches cost 20 % at 1e6 points) */
  int i = begin;
  for (int k = begin; k < end; k++) {
    const int pk = perm[k], pi = perm[i];
    const double *p = xy + MPGM_DIM * (size_t)pk;
    const double x = p[0], y = p[1]; /* 2-D only: the boxes in x and y */
    const int left = p[d] < cut;
    perm[k] = left ? pi : pk;
    perm[i] = left ? pk : pi;
    i += left;
    if (left) {
      llo[0] = x < llo[0] ? x : llo[0], lhi[0] = x > lhi[0] ? x : lhi[0];
      llo[1] = y < llo[1] ? y : llo[1], lhi[1] = y > lhi[1] ? y : lhi[1];
    } else {
      rlo[0] = x < rlo[0] ? x : rlo[0], rhi[0] = x > rhi[0] ? x : rhi[0];
      rlo[1] = y < rlo[1] ? y : rlo[1], rhi[1] = y > rhi[1] ? y : rhi[1];
    }
  }
  int mid = i;
  const int small = mid - begin < end - mid ? mid - begin : end - mid;
  if ((long)small * 8 < count) { /* too unbalanced: median split */
    mid = begin + count / 2;
    select_nth(perm, xy, d, begin, end - 1, mid);
    box_empty(llo, lhi), box_empty(rlo, rhi);
    for (int k = begin; k < mid; k++) box_add(llo, lhi, xy + MPGM_DIM * (size_t)perm[k]);
    for (int k = mid; k < end; k++) box_add(rlo, rhi, xy + MPGM_DIM * (size_t)perm[k]);
    t->median_splits++;
  }
  MPGM_CALL(build_rec(ctx, t, begin, mid, llo, lhi, depth + 1));
  t->nodes[id].a = t->nnodes; /* the right child comes next */
  t->nodes[id].b = -1 - d;
  return build_rec(ctx, t, mid, end, rlo, rhi, depth + 1);
}

/* Check that every coordinate is finite; box of all points. */
static int check_points(mpgm_ctx *ctx, const double *xy, int n, double lo[MPGM_DIM],
                        double hi[MPGM_DIM]) {
  double nan_if_bad = 0.0;
  box_empty(lo, hi);
  for (int i = 0; i < n; i++) {
    const double *p = xy + MPGM_DIM * (size_t)i;
    nan_if_bad += p[0] * 0.0 + p[1] * 0.0; /* NaN for Inf or NaN */
    box_add(lo, hi, p);
  }
  if (nan_if_bad == 0.0) return 0;
  for (int i = 0; i < n; i++)
    MPGM_CHECK(ctx, isfinite(xy[MPGM_DIM * (size_t)i]) && isfinite(xy[MPGM_DIM * (size_t)i + 1]),
               MPGM_ERR_INPUT, "kd-tree: point %d = (%g, %g) is not finite", i,
               xy[MPGM_DIM * (size_t)i], xy[MPGM_DIM * (size_t)i + 1]);
  return 0;
}

int mpgm_kdtree_rebuild(mpgm_ctx *ctx, mpgm_kdtree *t, const double *xy, int n) {
  MPGM_CHECK(ctx, t != NULL, MPGM_ERR_INPUT, "kd-tree: rebuild of a NULL tree");
  const int same_n = t->built && n == t->n;
  t->built = t->valid = 0;
  t->nnodes = 0;
  t->depth = 0;
  t->median_splits = 0;
  MPGM_CHECK(ctx, n >= 0, MPGM_ERR_INPUT, "kd-tree: %d points", n);
  MPGM_CHECK(ctx, xy != NULL || n == 0, MPGM_ERR_INPUT, "kd-tree: NULL coordinates for %d points",
             n);
  t->xy = xy;
  t->n = 0;
  if (n == 0) {
    t->built = t->valid = 1;
    return 0;
  }
  double lo[MPGM_DIM], hi[MPGM_DIM];
  MPGM_CALL(check_points(ctx, xy, n, lo, hi));
  if (n > t->perm_cap) {
    int *p = realloc(t->perm, (size_t)n * sizeof *p);
    MPGM_CHECK(ctx, p != NULL, MPGM_ERR_NOMEM, "kd-tree: out of memory (%d indices)", n);
    t->perm = p, t->perm_cap = n;
  }
  if (!same_n)
    for (int i = 0; i < n; i++) t->perm[i] = i;
  if (t->nodes_cap == 0) { /* typical: ~n / (0.7 leaf_size) leaves */
    const long guess = 4L * n / t->leaf_size + 16;
    const int cap = guess < INT_MAX / 2 ? (int)guess : INT_MAX / 2;
    t->nodes = malloc((size_t)cap * sizeof *t->nodes);
    MPGM_CHECK(ctx, t->nodes != NULL, MPGM_ERR_NOMEM, "kd-tree: out of memory (%d nodes)", cap);
    t->nodes_cap = cap;
  }
  t->n = n;
  MPGM_CALL(build_rec(ctx, t, 0, n, lo, hi, 0));
  t->built = t->valid = 1;
  return 0;
}

int mpgm_kdtree_create(mpgm_ctx *ctx, const double *xy, int n, int leaf_size, mpgm_kdtree **out) {
  *out = NULL;
  mpgm_kdtree *t;
  MPGM_ALLOC(ctx, t, 1);
  t->leaf_size = leaf_size > 0 ? leaf_size : MPGM_KDTREE_LEAF_SIZE;
  const int ierr = mpgm_kdtree_rebuild(ctx, t, xy, n);
  if (ierr) {
    mpgm_kdtree_destroy(&t);
    return ierr;
  }
  *out = t;
  return 0;
}

int mpgm_kdtree_refit(mpgm_ctx *ctx, mpgm_kdtree *t, const double *xy) {
  MPGM_CHECK(ctx, t != NULL, MPGM_ERR_INPUT, "kd-tree: refit of a NULL tree");
  MPGM_CHECK(ctx, t->built, MPGM_ERR_INPUT,
             "kd-tree: refit of a tree that was never built successfully");
  if (xy) t->xy = xy;
  if (t->n == 0) return 0;
  xy = t->xy;
  t->valid = 0;
  double nan_if_bad = 0.0;
  for (int i = t->nnodes - 1; i >= 0; i--) { /* children come after parents */
    kd_node *nd = &t->nodes[i];
    if (nd->b >= 0) {
      box_empty(nd->lo, nd->hi);
      for (int k = nd->a; k < nd->b; k++) {
        const double *p = xy + MPGM_DIM * (size_t)t->perm[k];
        nan_if_bad += p[0] * 0.0 + p[1] * 0.0;
        box_add(nd->lo, nd->hi, p);
      }
    } else {
      const kd_node *l = nd + 1, *r = &t->nodes[nd->a];
      for (int d = 0; d < MPGM_DIM; d++) {
        nd->lo[d] = l->lo[d] < r->lo[d] ? l->lo[d] : r->lo[d];
        nd->hi[d] = l->hi[d] > r->hi[d] ? l->hi[d] : r->hi[d];
      }
    }
  }
  if (nan_if_bad != 0.0) {
    double lo[MPGM_DIM], hi[MPGM_DIM];
    MPGM_CALL(check_points(ctx, xy, t->n, lo, hi));
  }
  t->valid = 1;
  return 0;
}

void mpgm_kdtree_destroy(mpgm_kdtree **t) {
  if (!t || !*t) return;
  free((*t)->perm);
  free((*t)->nodes);
  free(*t);
  *t = NULL;
}

/* ------------------------------------------------------------ radius search */

typedef struct rad_out {
  int *idx;
  double *d2;
  int cap; /* buffer capacity                              */
  int cnt; /* points found so far (may exceed cap)         */
} rad_out;

/* The buffer is full: keep the cap nearest in a max-heap. */
static void rad_overflow(rad_out *o, int j, double d) {
  if (o->cap == 0) return;
  if (o->cnt == o->cap) heapify(o->idx, o->d2, o->cap);
  if (before(d, j, o->d2[0], o->idx[0])) {
    o->idx[0] = j, o->d2[0] = d;
    heap_sift_down(o->idx, o->d2, o->cap, 0);
  }
}

/* The ball's points into o (the cap nearest when more); o->cnt counts them
 * all. The order is the tree's: mpgm_kdtree_radius sorts them. */
static void radius_search(const mpgm_kdtree *t, const double q[MPGM_DIM], double radius,
                          rad_out *out) {
  const double qx = q[0], qy = q[1], r2 = radius * radius;
  const double *xy = t->xy;
  const int *perm = t->perm;
  const kd_node *nodes = t->nodes;
  rad_out o = *out;
  struct {
    int node;
    double g[MPGM_DIM];
  } stack[KD_STACK];
  int sp = 0, node = 0;
  double g[MPGM_DIM];
  root_gaps(&nodes[0], q, g);
  if (g[0] + g[1] > r2) node = -1;
  while (node >= 0) {
    const kd_node *nd = &nodes[node];
    if (nd->b >= 0) {
      for (int k = nd->a; k < nd->b; k++) {
        const int j = perm[k];
        const double dx = xy[MPGM_DIM * (size_t)j] - qx, dy = xy[MPGM_DIM * (size_t)j + 1] - qy;
        const double d = dx * dx + dy * dy; /* 2-D only */
        if (d <= r2) {
          if (o.cnt < o.cap)
            o.idx[o.cnt] = j, o.d2[o.cnt] = d;
          else
            rad_overflow(&o, j, d);
          o.cnt++;
        }
      }
    } else {
      double gl, gr;
      const int dim = child_gaps(nodes, nd, q, g, &gl, &gr);
      const double go = g[1 - dim]; /* 2-D only: the other dimension's gap */
      const double ml = dim ? go + gl : gl + go, mr = dim ? go + gr : gr + go;
      if (mr <= r2) {
        stack[sp].node = nd->a, stack[sp].g[dim] = gr, stack[sp].g[1 - dim] = go;
        sp++;
      }
      if (ml <= r2) {
        node++, g[dim] = gl;
        continue;
      }
    }
    if (sp == 0) break;
    --sp;
    node = stack[sp].node, g[0] = stack[sp].g[0], g[1] = stack[sp].g[1];
  }
  *out = o;
}

/* The ball of both radius searches into o: the count, and the points in
 * the tree's order, or the cap nearest in order when there are more. */
static void ball(const mpgm_kdtree *t, const double q[MPGM_DIM], double radius, int cap, int *idx,
                 double *d2, rad_out *o) {
  *o = (rad_out){idx, d2, cap > 0 ? cap : 0, 0};
  if (!t || !t->valid || t->n == 0 || !(radius >= 0.0) || !isfinite(q[0]) || !isfinite(q[1]))
    return;
  radius_search(t, q, radius, o);
  if (o->cnt > o->cap) heap_sort_down(o->idx, o->d2, o->cap);
}

int mpgm_kdtree_radius(const mpgm_kdtree *t, const double q[MPGM_DIM], double radius, int cap,
                       int *idx, double *d2) {
  rad_out o;
  ball(t, q, radius, cap, idx, d2, &o);
  if (o.cnt <= o.cap) sort_results(o.idx, o.d2, o.cnt);
  return o.cnt;
}

int mpgm_kdtree_radius_set(const mpgm_kdtree *t, const double q[MPGM_DIM], double radius, int cap,
                           int *idx, double *d2) {
  rad_out o;
  ball(t, q, radius, cap, idx, d2, &o);
  return o.cnt;
}

/* ------------------------------------------------------------ k nearest */

typedef struct knn_set {
  int *idx;
  double *d2;
  int k, cnt;
  double worst; /* d2 of the k-th (INFINITY until k are held)        */
  int worst_i;  /* its index (INT_MAX until k are held)              */
} knn_set;

/* Insert into the sorted array (k <= KNN_SORTED_MAX); (d, j) beats the worst. */
static inline void knn_insert_sorted(knn_set *s, int j, double d) {
  int i = s->cnt < s->k ? s->cnt++ : s->k - 1;
  for (; i > 0 && s->d2[i - 1] > d; i--) s->idx[i] = s->idx[i - 1], s->d2[i] = s->d2[i - 1];
  for (; i > 0 && s->d2[i - 1] == d && s->idx[i - 1] > j; i--) /* ties: by index */
    s->idx[i] = s->idx[i - 1], s->d2[i] = s->d2[i - 1];
  s->idx[i] = j, s->d2[i] = d;
  if (s->cnt == s->k) s->worst = s->d2[s->k - 1], s->worst_i = s->idx[s->k - 1];
}

/* Insert into the max-heap (large k); (d, j) beats the worst. */
static void knn_insert_heap(knn_set *s, int j, double d) {
  if (s->cnt < s->k) {
    s->idx[s->cnt] = j, s->d2[s->cnt] = d;
    heap_sift_up(s->idx, s->d2, s->cnt++);
  } else {
    s->idx[0] = j, s->d2[0] = d;
    heap_sift_down(s->idx, s->d2, s->k, 0);
  }
  if (s->cnt == s->k) s->worst = s->d2[0], s->worst_i = s->idx[0];
}

/* The kNN walk; sorted is a constant in each caller, so the insertion choice
 * is compiled out of the leaf loop. */
static KD_ALWAYS_INLINE int knn_walk(const mpgm_kdtree *t, double qx, double qy, int k, int *idx,
                                     double *d2, const int sorted) {
  const double *xy = t->xy;
  const int *perm = t->perm;
  const kd_node *nodes = t->nodes;
  knn_set s = {idx, d2, k, 0, INFINITY, INT_MAX};
  const double q[MPGM_DIM] = {qx, qy};
  struct {
    int node;
    double m, g[MPGM_DIM]; /* bound and gaps of the pending subtree */
  } stack[KD_STACK];
  int sp = 0, node = 0;
  double g[MPGM_DIM];
  root_gaps(&nodes[0], q, g);
  for (;;) {
    const kd_node *nd = &nodes[node];
    if (nd->b >= 0) {
      for (int m = nd->a; m < nd->b; m++) {
        const int j = perm[m];
        const double dx = xy[MPGM_DIM * (size_t)j] - qx, dy = xy[MPGM_DIM * (size_t)j + 1] - qy;
        const double d = dx * dx + dy * dy; /* 2-D only */
        if (d < s.worst || (d == s.worst && j < s.worst_i)) {
          if (sorted)
            knn_insert_sorted(&s, j, d);
          else
            knn_insert_heap(&s, j, d);
        }
      }
    } else {
      double gl, gr;
      const int dim = child_gaps(nodes, nd, q, g, &gl, &gr);
      const double go = g[1 - dim]; /* 2-D only: the other dimension's gap */
      const double ml = dim ? go + gl : gl + go, mr = dim ? go + gr : gr + go;
      int near = node + 1, far = nd->a;
      double mn = ml, mf = mr, gn = gl, gf = gr;
      if (mr < ml) near = nd->a, far = node + 1, mn = mr, mf = ml, gn = gr, gf = gl;
      /* <=: a point at the bound with a smaller index still gets in */
      if (mf <= s.worst) {
        stack[sp].node = far, stack[sp].m = mf, stack[sp].g[dim] = gf, stack[sp].g[1 - dim] = go;
        sp++;
      }
      if (mn <= s.worst) {
        node = near, g[dim] = gn;
        continue;
      }
    }
    do {
      if (sp == 0) goto done;
      --sp;
    } while (stack[sp].m > s.worst);
    node = stack[sp].node, g[0] = stack[sp].g[0], g[1] = stack[sp].g[1];
  }
done:
  if (!sorted) heap_sort_down(s.idx, s.d2, s.cnt);
  return s.cnt;
}

static int knn_small(const mpgm_kdtree *t, double qx, double qy, int k, int *idx, double *d2) {
  return knn_walk(t, qx, qy, k, idx, d2, 1);
}

static int knn_large(const mpgm_kdtree *t, double qx, double qy, int k, int *idx, double *d2) {
  return knn_walk(t, qx, qy, k, idx, d2, 0);
}

int mpgm_kdtree_knn(const mpgm_kdtree *t, const double q[MPGM_DIM], int k, int *idx, double *d2) {
  if (!t || !t->valid || t->n == 0 || k <= 0 || !isfinite(q[0]) || !isfinite(q[1])) return 0;
  if (k >= t->n) return mpgm_kdtree_radius(t, q, INFINITY, t->n, idx, d2); /* all, sorted */
  if (k <= KNN_SORTED_MAX) return knn_small(t, q[0], q[1], k, idx, d2);
  return knn_large(t, q[0], q[1], k, idx, d2);
}

/* ------------------------------------------------------------ inspection */

int mpgm_kdtree_size(const mpgm_kdtree *t) {
  return t && t->valid ? t->n : 0;
}

const double *mpgm_kdtree_points(const mpgm_kdtree *t) {
  return t ? t->xy : NULL;
}

void mpgm_kdtree_get_stats(const mpgm_kdtree *t, mpgm_kdtree_stats *s) {
  memset(s, 0, sizeof *s);
  if (!t) return;
  s->n = mpgm_kdtree_size(t);
  s->leaf_size = t->leaf_size;
  s->nodes = t->valid ? t->nnodes : 0;
  for (int i = 0; i < s->nodes; i++) s->leaves += t->nodes[i].b >= 0;
  s->depth = t->depth;
  s->median_splits = t->median_splits;
  s->bytes =
      sizeof *t + (size_t)t->perm_cap * sizeof *t->perm + (size_t)t->nodes_cap * sizeof *t->nodes;
}
