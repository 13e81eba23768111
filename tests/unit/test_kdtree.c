/* test_kdtree.c -- the kd-tree (core/mpgm_kdtree.h) against brute force.
 *
 * Every answer must be IDENTICAL to a brute-force search: the same indices in
 * the same order and the same squared distances bit for bit. The order is
 * (d2, index), so even ties (grids, duplicates) have one right answer, and
 * kNN with ties at the k-th distance is compared exactly too.
 *
 * Point sets: uniform, clustered (gaussian blobs, one of width 1e-6),
 * collinear (diagonal and vertical), all duplicates, many duplicates, a grid
 * with exact binary spacing (exact ties, points exactly on the search circle),
 * exponentially skewed (x = 2^-i: the median fallback and the depth bound),
 * one point, none. Queries: points of the set, random points, perturbed
 * points, far points, grid nodes and cell centres. Radii 0, four scales,
 * 1e10 and infinity (plus exact multiples of the grid spacing); k = 1 .. 100
 * (sorted-array and heap paths), n and n + 5. Leaf sizes 1, 3, 16 (the
 * default), 64.
 * Then: too-small buffers, refit after small and large displacements (in
 * place and into a new array), rebuild (same, smaller and larger n), errors. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_kdtree.h"
#include "mpgm_test.h"

static const double PI = 3.14159265358979323846;

/* ------------------------------------------------------------ brute force */

typedef struct hit {
  double d2;
  int i;
} hit;

static int hit_cmp(const void *a, const void *b) {
  const hit *x = a, *y = b;
  if (x->d2 != y->d2) return x->d2 < y->d2 ? -1 : 1;
  return (x->i > y->i) - (x->i < y->i);
}

/* All n points sorted by (d2, index); the same arithmetic as the tree. */
static void brute_sorted(const double *xy, int n, const double q[2], hit *h) {
  for (int j = 0; j < n; j++) {
    const double dx = xy[2 * j] - q[0], dy = xy[2 * j + 1] - q[1];
    h[j].d2 = dx * dx + dy * dy;
    h[j].i = j;
  }
  qsort(h, (size_t)n, sizeof *h, hit_cmp);
}

/* Number of points in the closed ball of radius r. */
static int brute_count(const hit *h, int n, double r) {
  if (!(r >= 0.0)) return 0;
  const double r2 = r * r;
  int m = 0;
  while (m < n && h[m].d2 <= r2) m++;
  return m;
}

/* idx/d2 equal to the first m brute-force hits */
static int same_prefix(const hit *h, int m, const int *idx, const double *d2) {
  for (int a = 0; a < m; a++)
    if (idx[a] != h[a].i || d2[a] != h[a].d2) return 0;
  return 1;
}

/* idx/d2 (m of them, in any order) the same set as the first m brute-force
 * hits: sorted into scratch by (d2, index) and compared */
static int same_set(const hit *h, int m, const int *idx, const double *d2, hit *scratch) {
  for (int a = 0; a < m; a++) scratch[a].d2 = d2[a], scratch[a].i = idx[a];
  qsort(scratch, (size_t)m, sizeof *scratch, hit_cmp);
  for (int a = 0; a < m; a++)
    if (scratch[a].i != h[a].i || scratch[a].d2 != h[a].d2) return 0;
  return 1;
}

/* ------------------------------------------------------------ point sets */

static double gauss(rng *r) {
  const double u = uniform(r, 1e-300, 1.0), v = uniform(r, 0.0, 1.0);
  return sqrt(-2.0 * log(u)) * cos(2.0 * PI * v);
}

enum {
  SET_UNIFORM,
  SET_CLUSTERED,
  SET_DIAGONAL,
  SET_VERTICAL,
  SET_DUPLICATES,
  SET_MANY_DUP,
  SET_GRID,
  SET_SKEWED,
  SET_ONE,
  SET_EMPTY,
  SET_LARGE,
  SET_COUNT
};

static const char *set_name[SET_COUNT] = {
    "uniform",        "clustered",       "collinear diagonal", "collinear vertical",
    "all duplicates", "many duplicates", "grid (exact ties)",  "skewed 2^-i",
    "one point",      "no points",       "large uniform"};

static const int set_n[SET_COUNT] = {2500, 2500, 800, 800, 400, 1500, 1800, 900, 1, 0, 20000};

/* Fill xy with set s (n = set_n[s]); returns the grid spacing (grid) or 0. */
static double make_set(int s, double *xy, rng *r) {
  const int n = set_n[s];
  switch (s) {
  case SET_UNIFORM:
  case SET_LARGE:
    for (int i = 0; i < n; i++)
      xy[2 * i] = uniform(r, -1.3, 2.385), xy[2 * i + 1] = uniform(r, 0.25, 1.75);
    return 0;
  case SET_CLUSTERED: {
    const double c[5][3] = {
        {0.2, 0.3, 0.05}, {1.7, 0.4, 0.2}, {0.9, 1.6, 0.01}, {1.25, 1.25, 1e-6}, {-0.4, 1.1, 0.1}};
    for (int i = 0; i < n; i++) {
      const int b = i % 5;
      xy[2 * i] = c[b][0] + c[b][2] * gauss(r);
      xy[2 * i + 1] = c[b][1] + c[b][2] * gauss(r);
    }
    return 0;
  }
  case SET_DIAGONAL:
    for (int i = 0; i < n; i++) {
      const double t = uniform(r, 0.0, 1.0);
      xy[2 * i] = 0.3 + 1.7 * t, xy[2 * i + 1] = -0.2 + 0.6 * t;
    }
    return 0;
  case SET_VERTICAL:
    for (int i = 0; i < n; i++) xy[2 * i] = 0.385, xy[2 * i + 1] = uniform(r, -2.0, 2.0);
    return 0;
  case SET_DUPLICATES:
    for (int i = 0; i < n; i++) xy[2 * i] = 2.385, xy[2 * i + 1] = -1.125;
    return 0;
  case SET_MANY_DUP: {
    double loc[37][2];
    for (int k = 0; k < 37; k++) loc[k][0] = uniform(r, 0, 1), loc[k][1] = uniform(r, 0, 1);
    for (int i = 0; i < n; i++) {
      const int k = (int)uniform(r, 0, 37);
      xy[2 * i] = loc[k][0], xy[2 * i + 1] = loc[k][1];
    }
    return 0;
  }
  case SET_GRID: /* 45 x 40 nodes, spacing 1/8, shuffled numbering */
    for (int i = 0; i < n; i++)
      xy[2 * i] = -2.0 + 0.125 * (i % 45), xy[2 * i + 1] = 0.5 + 0.125 * (i / 45);
    for (int i = n - 1; i > 0; i--) {
      const int j = (int)uniform(r, 0, i + 1);
      double t = xy[2 * i];
      xy[2 * i] = xy[2 * j], xy[2 * j] = t;
      t = xy[2 * i + 1], xy[2 * i + 1] = xy[2 * j + 1], xy[2 * j + 1] = t;
    }
    return 0.125;
  case SET_SKEWED:
    for (int i = 0; i < n; i++)
      xy[2 * i] = ldexp(1.0, -i), xy[2 * i + 1] = (i % 3) * ldexp(1.0, -i);
    return 0;
  case SET_ONE:
    xy[0] = 0.6183, xy[1] = -0.385;
    return 0;
  default:
    return 0;
  }
}

/* nq query points for the set: its points, random points in the enlarged box,
 * perturbed points, far points, grid nodes and cell centres. */
static int make_queries(const double *xy, int n, double h, int nq_each, double *q, rng *r) {
  double lo[2] = {0, 0}, hi[2] = {1, 1};
  if (n > 0) {
    lo[0] = hi[0] = xy[0], lo[1] = hi[1] = xy[1];
    for (int i = 1; i < n; i++)
      for (int d = 0; d < 2; d++)
        lo[d] = fmin(lo[d], xy[2 * i + d]), hi[d] = fmax(hi[d], xy[2 * i + d]);
  }
  const double w = fmax(hi[0] - lo[0], hi[1] - lo[1]) + 0.1;
  int m = 0;
  for (int k = 0; k < nq_each && n > 0; k++, m++) {
    const int i = (int)uniform(r, 0, n);
    q[2 * m] = xy[2 * i], q[2 * m + 1] = xy[2 * i + 1];
  }
  for (int k = 0; k < nq_each; k++, m++)
    for (int d = 0; d < 2; d++) q[2 * m + d] = uniform(r, lo[d] - 0.1 * w, hi[d] + 0.1 * w);
  for (int k = 0; k < nq_each / 2 && n > 0; k++, m++) {
    const int i = (int)uniform(r, 0, n);
    for (int d = 0; d < 2; d++) q[2 * m + d] = xy[2 * i + d] * (1.0 + uniform(r, -1e-12, 1e-12));
  }
  const double far[4][2] = {{1e6, 0.5}, {-3e3, -2e3}, {0.5, 1e9}, {-1e-3, 7.5e2}};
  for (int k = 0; k < 4; k++, m++) q[2 * m] = far[k][0], q[2 * m + 1] = far[k][1];
  if (h > 0)
    for (int k = 0; k < nq_each; k++, m++) {
      const int i = (int)uniform(r, 0, n);
      q[2 * m] = xy[2 * i] + (k % 2) * 0.5 * h, q[2 * m + 1] = xy[2 * i + 1] + (k % 2) * 0.5 * h;
    }
  return m;
}

/* ------------------------------------------------------------ comparison */

typedef struct bufs {
  int *idx;
  double *d2;
} bufs;

/* All radii and k for one tree against the precomputed brute-force lists. */
static void compare_tree(const char *name, int leaf, const mpgm_kdtree *t, const double *xy, int n,
                         const double *q, int nq, const hit *brute, double h, bufs *b) {
  double lo[2] = {0, 0}, hi[2] = {1, 1};
  if (n > 0) {
    lo[0] = hi[0] = xy[0], lo[1] = hi[1] = xy[1];
    for (int i = 1; i < n; i++)
      for (int d = 0; d < 2; d++)
        lo[d] = fmin(lo[d], xy[2 * i + d]), hi[d] = fmax(hi[d], xy[2 * i + d]);
  }
  const double L = hypot(hi[0] - lo[0], hi[1] - lo[1]) + 1e-3;
  double radii[16] = {0.0, 1e-3 * L, 0.02 * L, 0.08 * L, 0.3 * L, 1e10, INFINITY};
  int nr = 7;
  if (h > 0) radii[nr++] = h, radii[nr++] = 2 * h, radii[nr++] = 5 * h, radii[nr++] = 0.5 * h;
  hit *scratch = malloc(sizeof(hit) * (size_t)(n > 0 ? n : 1));
  mpgm_test(scratch != NULL, "scratch for the unordered radius search");
  if (!scratch) return;
  for (int a = 0; a < nr; a++) {
    int bad = 0, bad_small = 0, bad_set = 0, total = 0;
    const int stride = radii[a] >= 1e10 ? 4 : 1; /* huge: all points, every 4th query */
    for (int k = 0; k < nq; k += stride) {
      const hit *hb = brute + (size_t)k * n;
      const int m = brute_count(hb, n, radii[a]);
      const int got = mpgm_kdtree_radius(t, q + 2 * k, radii[a], n, b->idx, b->d2);
      bad += got != m || !same_prefix(hb, m, b->idx, b->d2);
      total += m;
      /* unordered: the same set; with a buffer of m/2, the nearest in order */
      const int gs = mpgm_kdtree_radius_set(t, q + 2 * k, radii[a], n, b->idx, b->d2);
      bad_set += gs != m || !same_set(hb, m, b->idx, b->d2, scratch);
      if (m > 1 && mpgm_kdtree_radius_set(t, q + 2 * k, radii[a], m / 2, b->idx, b->d2) != m)
        bad_set++;
      else if (m > 1)
        bad_set += !same_prefix(hb, m / 2, b->idx, b->d2);
      /* too small buffers (every third query): the full count, the nearest
       * cap in order */
      const int caps[3] = {0, m / 2, m - 1};
      for (int c = 0; c < 3 && m > 0 && k % (3 * stride) == 0; c++) {
        const int cap = caps[c];
        const int g = mpgm_kdtree_radius(t, q + 2 * k, radii[a], cap, cap ? b->idx : NULL,
                                         cap ? b->d2 : NULL);
        bad_small += g != m || !same_prefix(hb, cap, b->idx, b->d2);
      }
    }
    mpgm_test(bad == 0,
              "%s (n = %d, leaf %d): radius %.4g, %d queries (%d hits) = brute force (%d differ)",
              name, n, leaf, radii[a], (nq + stride - 1) / stride, total, bad);
    mpgm_test(bad_small == 0,
              "%s (n = %d, leaf %d): radius %.4g, buffers of 0, m/2, m-1: count m, the nearest cap "
              "(%d differ)",
              name, n, leaf, radii[a], bad_small);
    mpgm_test(bad_set == 0,
              "%s (n = %d, leaf %d): radius %.4g, unordered search: the same set, the nearest "
              "m/2 in order with a buffer of m/2 (%d differ)",
              name, n, leaf, radii[a], bad_set);
  }
  free(scratch);
  const int ks[8] = {1, 2, 7, 16, 33, 100, n, n + 5};
  for (int a = 0; a < 8; a++) {
    const int kk = ks[a];
    if (kk < 1 || (a < 6 && kk > n + 5)) continue;
    int bad = 0;
    const int stride = kk >= n ? 4 : 1; /* all points, every 4th query */
    for (int k = 0; k < nq; k += stride) {
      const hit *hb = brute + (size_t)k * n;
      const int want = kk < n ? kk : n;
      const int got = mpgm_kdtree_knn(t, q + 2 * k, kk, b->idx, b->d2);
      bad += got != want || !same_prefix(hb, want, b->idx, b->d2);
    }
    mpgm_test(bad == 0, "%s (n = %d, leaf %d): knn k = %d, %d queries = brute force (%d differ)",
              name, n, leaf, kk, (nq + stride - 1) / stride, bad);
  }
}

/* brute-force lists of all queries */
static hit *brute_lists(const double *xy, int n, const double *q, int nq) {
  hit *h = malloc(((size_t)nq * n + 1) * sizeof *h);
  for (int k = 0; k < nq; k++) brute_sorted(xy, n, q + 2 * k, h + (size_t)k * n);
  return h;
}

/* ------------------------------------------------------------ tests */

static void test_sets(rng *r) {
  const int leaves[4] = {1, 3, 0, 64}; /* 0: the default (16) */
  for (int s = 0; s < SET_COUNT; s++) {
    const int n = set_n[s];
    double *xy = malloc((2 * (size_t)n + 2) * sizeof *xy);
    const double h = make_set(s, xy, r);
    const int nq_each = s == SET_LARGE ? 8 : 24;
    double q[2 * 120];
    const int nq = make_queries(xy, n, h, nq_each, q, r);
    hit *brute = brute_lists(xy, n, q, nq);
    bufs b = {malloc(((size_t)n + 8) * sizeof(int)), malloc(((size_t)n + 8) * sizeof(double))};
    for (int l = 0; l < 4; l++) {
      if (s == SET_LARGE && l != 2) continue;
      mpgm_ctx ctx;
      mpgm_ctx_init(&ctx);
      mpgm_kdtree *t = NULL;
      const int ierr = mpgm_kdtree_create(&ctx, n ? xy : NULL, n, leaves[l], &t);
      mpgm_test(ierr == 0 && t != NULL, "%s: create (leaf %d) %s", set_name[s], leaves[l], ctx.msg);
      if (ierr) continue;
      mpgm_kdtree_stats st;
      mpgm_kdtree_get_stats(t, &st);
      const int leaf = st.leaf_size;
      const double bound = n > 1 ? log(n) / log(8.0 / 7.0) : 0.0;
      mpgm_test(st.n == n && mpgm_kdtree_size(t) == n, "%s (leaf %d): size %d", set_name[s], leaf,
                n);
      mpgm_test(st.depth <= bound && (n == 0 ? st.nodes == 0 : st.nodes == 2 * st.leaves - 1),
                "%s (leaf %d): depth %d <= log_{8/7} n = %.1f, %d nodes = 2 x %d leaves - 1 (%d "
                "median splits)",
                set_name[s], leaf, st.depth, bound, st.nodes, st.leaves, st.median_splits);
      compare_tree(set_name[s], leaf, t, xy, n, q, nq, brute, h, &b);
      mpgm_kdtree_destroy(&t);
      mpgm_test(t == NULL, "%s: destroy nulls the pointer", set_name[s]);
    }
    free(b.idx), free(b.d2), free(brute), free(xy);
  }
}

/* Move the points, refit, compare; then rebuild. */
static void test_refit_rebuild(rng *r) {
  for (int s = SET_UNIFORM; s <= SET_CLUSTERED; s++) {
    const int n = set_n[s], nbig = n + 777;
    double *xy = malloc(2 * (size_t)nbig * sizeof *xy),
           *xy2 = malloc(2 * (size_t)nbig * sizeof *xy2);
    make_set(s, xy, r);
    bufs b = {malloc((size_t)nbig * sizeof(int)), malloc((size_t)nbig * sizeof(double))};
    mpgm_ctx ctx;
    mpgm_ctx_init(&ctx);
    mpgm_kdtree *t = NULL;
    if (mpgm_kdtree_create(&ctx, xy, n, 0, &t)) {
      mpgm_test(0, "refit %s: create: %s", set_name[s], ctx.msg);
      continue;
    }
    mpgm_kdtree_stats st0;
    mpgm_kdtree_get_stats(t, &st0);
    double q[2 * 120];
    const double h = 0.03; /* ~ the spacing of 2500 points on 3.7 x 1.5 */
    /* 1. small random displacement, in place; 2. large (scramble), in place;
     * 3. into a new array */
    const double amp[3] = {1.5 * h, 2.0, 0.7 * h};
    const char *what[3] = {"small displacement, in place", "large displacement, in place",
                           "displacement into a new array"};
    for (int pass = 0; pass < 3; pass++) {
      double *dst = pass == 2 ? xy2 : xy;
      for (int i = 0; i < 2 * n; i++) dst[i] = xy[i] + uniform(r, -amp[pass], amp[pass]);
      const int ierr = mpgm_kdtree_refit(&ctx, t, pass == 2 ? xy2 : NULL);
      mpgm_test(ierr == 0 && mpgm_kdtree_points(t) == dst,
                "refit %s: %s returns 0, points at the array", set_name[s], what[pass]);
      mpgm_kdtree_stats st;
      mpgm_kdtree_get_stats(t, &st);
      mpgm_test(st.nodes == st0.nodes && st.depth == st0.depth, "refit %s: %s keeps the structure",
                set_name[s], what[pass]);
      const int nq = make_queries(dst, n, 0, 24, q, r);
      hit *brute = brute_lists(dst, n, q, nq);
      char name[160];
      snprintf(name, sizeof name, "refit %s, %s", set_name[s], what[pass]);
      compare_tree(name, st.leaf_size, t, dst, n, q, nq, brute, 0, &b);
      free(brute);
    }
    /* rebuild: same n (moved points), fewer points, more points (grows) */
    const int ns[3] = {n, n / 3, nbig};
    for (int pass = 0; pass < 3; pass++) {
      const int m = ns[pass];
      for (int i = 0; i < 2 * m; i++) xy[i] = uniform(r, -0.5, 0.5) + (i < 2 * n ? xy2[i] : 0.385);
      const int ierr = mpgm_kdtree_rebuild(&ctx, t, xy, m);
      mpgm_test(ierr == 0 && mpgm_kdtree_size(t) == m, "rebuild %s with n = %d: returns 0, %s",
                set_name[s], m, ctx.msg);
      const int nq = make_queries(xy, m, 0, 24, q, r);
      hit *brute = brute_lists(xy, m, q, nq);
      char name[160];
      snprintf(name, sizeof name, "rebuild %s to n = %d", set_name[s], m);
      compare_tree(name, st0.leaf_size, t, xy, m, q, nq, brute, 0, &b);
      free(brute);
    }
    mpgm_kdtree_destroy(&t);
    free(b.idx), free(b.d2), free(xy), free(xy2);
  }
}

static void test_errors(void) {
  mpgm_ctx ctx;
  mpgm_kdtree *t = (mpgm_kdtree *)&ctx; /* must be overwritten with NULL */
  double xy[8] = {0.25, 1.5, 2.385, -0.5, 1.125, 0.75, -3.0, 4.0};

  mpgm_ctx_init(&ctx);
  int ierr = mpgm_kdtree_create(&ctx, xy, -1, 0, &t);
  mpgm_test(ierr == MPGM_ERR_INPUT && t == NULL && ctx.code == MPGM_ERR_INPUT,
            "create with n = -1: MPGM_ERR_INPUT, no tree (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  ierr = mpgm_kdtree_create(&ctx, NULL, 3, 0, &t);
  mpgm_test(ierr == MPGM_ERR_INPUT && t == NULL,
            "create with NULL coordinates: MPGM_ERR_INPUT (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  xy[5] = NAN;
  ierr = mpgm_kdtree_create(&ctx, xy, 4, 0, &t);
  mpgm_test(ierr == MPGM_ERR_INPUT && t == NULL && strstr(ctx.msg, "point 2") != NULL,
            "create with a NaN at point 2: MPGM_ERR_INPUT naming it (%s)", ctx.msg);
  xy[5] = 0.75;

  mpgm_ctx_init(&ctx);
  ierr = mpgm_kdtree_create(&ctx, xy, 4, 2, &t);
  mpgm_test(ierr == 0 && t != NULL, "create over 4 points, leaf 2");
  if (ierr) return;
  int idx[8];
  double d2[8];
  const double q[2] = {0.2, 1.4}, qnan[2] = {NAN, 0.0}, qinf[2] = {0.0, -INFINITY};
  mpgm_test(mpgm_kdtree_radius(t, q, -1.0, 8, idx, d2) == 0, "radius < 0 finds nothing");
  mpgm_test(mpgm_kdtree_radius(t, q, NAN, 8, idx, d2) == 0, "radius NaN finds nothing");
  mpgm_test(mpgm_kdtree_radius(t, qnan, 1e9, 8, idx, d2) == 0, "NaN query finds nothing");
  mpgm_test(mpgm_kdtree_knn(t, qinf, 2, idx, d2) == 0, "infinite query: knn gives 0");
  mpgm_test(mpgm_kdtree_knn(t, q, 0, idx, d2) == 0 && mpgm_kdtree_knn(t, q, -3, idx, d2) == 0,
            "knn with k <= 0 gives 0");
  mpgm_test(mpgm_kdtree_radius(t, q, INFINITY, 0, NULL, NULL) == 4,
            "radius infinity with cap 0 and NULL buffers counts all 4");

  xy[2] = INFINITY;
  mpgm_ctx_init(&ctx);
  ierr = mpgm_kdtree_refit(&ctx, t, NULL);
  mpgm_test(ierr == MPGM_ERR_INPUT && strstr(ctx.msg, "point 1") != NULL,
            "refit with an infinite point 1: MPGM_ERR_INPUT naming it (%s)", ctx.msg);
  mpgm_test(mpgm_kdtree_size(t) == 0 && mpgm_kdtree_knn(t, q, 2, idx, d2) == 0,
            "after the failed refit the tree answers nothing");
  xy[2] = 2.385;
  mpgm_ctx_init(&ctx);
  ierr = mpgm_kdtree_refit(&ctx, t, NULL);
  mpgm_test(ierr == 0 && mpgm_kdtree_knn(t, q, 1, idx, d2) == 1 && idx[0] == 0,
            "a good refit restores it: nearest of (0.2, 1.4) is point 0");

  xy[7] = NAN;
  mpgm_ctx_init(&ctx);
  ierr = mpgm_kdtree_rebuild(&ctx, t, xy, 4);
  mpgm_test(ierr == MPGM_ERR_INPUT && mpgm_kdtree_size(t) == 0,
            "rebuild with a NaN: MPGM_ERR_INPUT, empty tree (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  ierr = mpgm_kdtree_refit(&ctx, t, NULL);
  mpgm_test(ierr == MPGM_ERR_INPUT, "refit after a failed rebuild: MPGM_ERR_INPUT (%s)", ctx.msg);
  xy[7] = 4.0;
  mpgm_ctx_init(&ctx);
  ierr = mpgm_kdtree_rebuild(&ctx, t, xy, 4);
  mpgm_test(ierr == 0 && mpgm_kdtree_radius(t, q, 1e3, 8, idx, d2) == 4, "rebuild repairs it");

  mpgm_kdtree_destroy(&t);
  mpgm_test(t == NULL, "destroy nulls the pointer");
  mpgm_kdtree_destroy(&t);
  mpgm_kdtree_destroy(NULL);
  mpgm_test(1, "destroy accepts a NULL tree and a NULL pointer");
}

int main(void) {
  rng r = {0x9E3779B97F4A7C15ULL};
  test_sets(&r);
  test_refit_rebuild(&r);
  test_errors();
  return mpgm_test_summary();
}
