/* bench_kdtree.c -- build and query times of the kd-tree (core/mpgm_kdtree.h)
 * against brute force and nanoflann; prints the markdown section of
 * bench/results/kdtree.md (bench/kdtree runs it).
 *
 *   bench_kdtree [--quick] [--leaf L]
 *     --quick   sizes 1e4 and 1e5 only, no leaf-size table (a smoke run)
 *     --leaf L  our leaf size in the main tables (default MPGM_KDTREE_LEAF_SIZE)
 *
 * Points: n uniform random points in the unit square (stride 2, borrowed by
 * both trees). Queries: every point, once in storage order (random in space:
 * the cache-unfriendly order) and once in Morton (Z-curve) order (coherent,
 * as when a front end walks its nodes body by body). Radius
 * r = sqrt(24 / (pi n)): about 24.5 neighbours per query, the point itself
 * included. kNN: k = 16. Single thread. Every time is the minimum over
 * repetitions, ours and nanoflann interleaved. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_base.h"
#include "mpgm_kdtree.h"
#ifdef MPGM_HAVE_NANOFLANN
#include "nanoflann_bench.h"
#endif

#define KNN_K             16
#define RADIUS_NEIGHBOURS 24.0
#define BRUTE_BUDGET      1e8  /* distance evaluations per brute-force timing */
#define CAP               1024 /* radius result buffer */

static const double PI = 3.14159265358979323846;

/* ------------------------------------------------------------ helpers */

static uint64_t rng_state = 0x2545F4914F6CDD1DULL; /* the program's own state */

static double urand(void) {
  rng_state ^= rng_state >> 12;
  rng_state ^= rng_state << 25;
  rng_state ^= rng_state >> 27;
  return (double)((rng_state * 0x2545F4914F6CDD1DULL) >> 11) * 0x1.0p-53;
}

static void die(const mpgm_ctx *ctx) {
  fprintf(stderr, "bench_kdtree: %s\n", ctx->msg);
  exit(1);
}

static double min2(double a, double b) {
  return a < b ? a : b;
}

/* query orders */
enum { ORDER_RANDOM, ORDER_MORTON, NORDER };

typedef struct result {
  double build, rebuild, refit;       /* [s] */
  double radius[NORDER], knn[NORDER]; /* [s] for all n queries, per order */
  long rad_total;                     /* radius hits, summed over queries */
  double rad_sum, knn_sum;            /* checksums: largest d2 of each query */
  mpgm_kdtree_stats st;
} result;

/* The n points in Morton order of their 16-bit quantised coordinates. */
static uint64_t spread16(uint64_t v) {
  v &= 0xFFFF;
  v = (v | (v << 8)) & 0x00FF00FFULL;
  v = (v | (v << 4)) & 0x0F0F0F0FULL;
  v = (v | (v << 2)) & 0x33333333ULL;
  v = (v | (v << 1)) & 0x55555555ULL;
  return v;
}

static int u64_cmp(const void *a, const void *b) {
  const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
  return (x > y) - (x < y);
}

static void morton_order(const double *xy, int n, double *qs) {
  uint64_t *key = malloc((size_t)n * sizeof *key);
  if (!key) exit(1);
  for (int i = 0; i < n; i++) {
    const uint64_t ix = (uint64_t)(xy[2 * (size_t)i] * 65536.0),
                   iy = (uint64_t)(xy[2 * (size_t)i + 1] * 65536.0);
    key[i] = ((spread16(ix) | (spread16(iy) << 1)) << 32) | (uint64_t)i;
  }
  qsort(key, (size_t)n, sizeof *key, u64_cmp);
  for (int i = 0; i < n; i++) {
    const size_t j = (size_t)(key[i] & 0xFFFFFFFFULL);
    qs[2 * (size_t)i] = xy[2 * j], qs[2 * (size_t)i + 1] = xy[2 * j + 1];
  }
  free(key);
}

/* ------------------------------------------------------------ ours */

static double ours_build(const double *xy, int n, int leaf, mpgm_kdtree_stats *st) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_kdtree *t;
  const double t0 = mpgm_wtime();
  if (mpgm_kdtree_create(&ctx, xy, n, leaf, &t)) die(&ctx);
  const double dt = mpgm_wtime() - t0;
  if (st) mpgm_kdtree_get_stats(t, st);
  mpgm_kdtree_destroy(&t);
  return dt;
}

static double ours_radius(const mpgm_kdtree *t, const double *q, int nq, double r, long *total,
                          double *sum) {
  int idx[CAP];
  double d2[CAP];
  long tot = 0;
  double s = 0;
  const double t0 = mpgm_wtime();
  for (int k = 0; k < nq; k++) {
    const int m = mpgm_kdtree_radius(t, q + 2 * (size_t)k, r, CAP, idx, d2);
    tot += m;
    if (m) s += d2[(m < CAP ? m : CAP) - 1];
  }
  const double dt = mpgm_wtime() - t0;
  *total = tot, *sum = s;
  return dt;
}

static double ours_knn(const mpgm_kdtree *t, const double *q, int nq, int k, double *sum) {
  int idx[KNN_K];
  double d2[KNN_K];
  double s = 0;
  const double t0 = mpgm_wtime();
  for (int j = 0; j < nq; j++) {
    const int m = mpgm_kdtree_knn(t, q + 2 * (size_t)j, k, idx, d2);
    if (m) s += d2[m - 1];
  }
  *sum = s;
  return mpgm_wtime() - t0;
}

/* ------------------------------------------------------------ brute force */

/* Radius: scan, collect, sort by insertion (the results are few). */
static double brute_radius(const double *xy, int n, const double *q, int nq, double r) {
  static int idx[CAP];
  static double d2[CAP];
  const double r2 = r * r;
  volatile long sink = 0;
  const double t0 = mpgm_wtime();
  for (int k = 0; k < nq; k++) {
    const double qx = q[2 * (size_t)k], qy = q[2 * (size_t)k + 1];
    int m = 0;
    for (int j = 0; j < n; j++) {
      const double dx = xy[2 * (size_t)j] - qx, dy = xy[2 * (size_t)j + 1] - qy;
      const double d = dx * dx + dy * dy;
      if (d <= r2 && m < CAP) idx[m] = j, d2[m++] = d;
    }
    for (int a = 1; a < m; a++) {
      const double da = d2[a];
      const int ia = idx[a];
      int b = a;
      for (; b > 0 && d2[b - 1] > da; b--) d2[b] = d2[b - 1], idx[b] = idx[b - 1];
      d2[b] = da, idx[b] = ia;
    }
    sink += m;
  }
  return mpgm_wtime() - t0;
}

/* kNN: scan with a sorted array of the k best. */
static double brute_knn(const double *xy, int n, const double *q, int nq, int k) {
  int idx[KNN_K];
  double d2[KNN_K];
  volatile double sink = 0;
  const double t0 = mpgm_wtime();
  for (int a = 0; a < nq; a++) {
    const double qx = q[2 * (size_t)a], qy = q[2 * (size_t)a + 1];
    int m = 0;
    for (int j = 0; j < n; j++) {
      const double dx = xy[2 * (size_t)j] - qx, dy = xy[2 * (size_t)j + 1] - qy;
      const double d = dx * dx + dy * dy;
      if (m == k && d >= d2[k - 1]) continue;
      int b = m < k ? m++ : k - 1;
      for (; b > 0 && d2[b - 1] > d; b--) d2[b] = d2[b - 1], idx[b] = idx[b - 1];
      d2[b] = d, idx[b] = j;
    }
    sink += d2[m - 1];
  }
  return mpgm_wtime() - t0;
}

/* ------------------------------------------------------------ one size */

/* Ours with leaf size leaf, nanoflann with nf_leaf, over n points; queries
 * in the orders of qs[0 .. norder - 1] (each the n points). */
static void run_size(const double *xy, int n, int leaf, int nf_leaf, int reps_build, int reps_query,
                     const double *const *qs, int norder, result *ours, result *nf) {
  const double r = sqrt(RADIUS_NEIGHBOURS / (PI * n));
  memset(ours, 0, sizeof *ours), memset(nf, 0, sizeof *nf);
  ours->build = ours->rebuild = ours->refit = nf->build = INFINITY;
  for (int o = 0; o < NORDER; o++)
    ours->radius[o] = ours->knn[o] = nf->radius[o] = nf->knn[o] = INFINITY;
  (void)nf_leaf;
  /* build: fresh create (identity order), alternating with nanoflann */
  for (int rep = 0; rep < reps_build; rep++) {
    ours->build = min2(ours->build, ours_build(xy, n, leaf, &ours->st));
#ifdef MPGM_HAVE_NANOFLANN
    const double t0 = mpgm_wtime();
    void *b = nf_create(xy, n, nf_leaf);
    nf->build = min2(nf->build, mpgm_wtime() - t0);
    nf_destroy(b);
#endif
  }
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_kdtree *t;
  if (mpgm_kdtree_create(&ctx, xy, n, leaf, &t)) die(&ctx);
  /* rebuild and refit after the points moved a quarter of their spacing:
   * alternate between xy and a displaced copy */
  double *xd = malloc(2 * (size_t)n * sizeof *xd);
  if (!xd) exit(1);
  const double h = 1.0 / sqrt((double)n);
  for (size_t i = 0; i < 2 * (size_t)n; i++) xd[i] = xy[i] + 0.25 * h * (2.0 * urand() - 1.0);
  for (int rep = 0; rep < 2 * reps_build; rep++) {
    const double *x = rep % 2 ? xy : xd;
    double t0 = mpgm_wtime();
    if (mpgm_kdtree_refit(&ctx, t, x)) die(&ctx);
    ours->refit = min2(ours->refit, mpgm_wtime() - t0);
    t0 = mpgm_wtime();
    if (mpgm_kdtree_rebuild(&ctx, t, x, n)) die(&ctx);
    ours->rebuild = min2(ours->rebuild, mpgm_wtime() - t0);
  }
  free(xd);
  if (mpgm_kdtree_rebuild(&ctx, t, xy, n)) die(&ctx); /* back to xy for the queries */
#ifdef MPGM_HAVE_NANOFLANN
  void *b = nf_create(xy, n, nf_leaf);
  uint32_t nidx[KNN_K];
  double nd2[KNN_K];
#endif
  for (int o = 0; o < norder; o++) {
    const double *q = qs[o];
    for (int rep = 0; rep < reps_query; rep++) {
      ours->radius[o] =
          min2(ours->radius[o], ours_radius(t, q, n, r, &ours->rad_total, &ours->rad_sum));
#ifdef MPGM_HAVE_NANOFLANN
      double t0 = mpgm_wtime();
      nf->rad_total = nf_radius_all(b, q, n, r, &nf->rad_sum);
      nf->radius[o] = min2(nf->radius[o], mpgm_wtime() - t0);
#endif
      ours->knn[o] = min2(ours->knn[o], ours_knn(t, q, n, KNN_K, &ours->knn_sum));
#ifdef MPGM_HAVE_NANOFLANN
      t0 = mpgm_wtime();
      nf->knn_sum = nf_knn_all(b, q, n, KNN_K, nidx, nd2);
      nf->knn[o] = min2(nf->knn[o], mpgm_wtime() - t0);
#endif
    }
  }
#ifdef MPGM_HAVE_NANOFLANN
  nf_destroy(b);
#endif
  mpgm_kdtree_destroy(&t);
}

/* ------------------------------------------------------------ report */

static void cell_ratio(double a, double b, int have) {
  if (have)
    printf(" %.2f |", a / b);
  else
    printf(" n/a |");
}

static void cell_time(double t, double scale, int have, const char *fmt) {
  if (have) {
    printf(" ");
    printf(fmt, t * scale);
    printf(" |");
  } else
    printf(" n/a |");
}

int main(int argc, char **argv) {
  int quick = 0, leaf = MPGM_KDTREE_LEAF_SIZE;
  for (int a = 1; a < argc; a++) {
    if (!strcmp(argv[a], "--quick"))
      quick = 1;
    else if (!strcmp(argv[a], "--leaf") && a + 1 < argc)
      leaf = atoi(argv[++a]);
    else {
      fprintf(stderr, "usage: bench_kdtree [--quick] [--leaf L]\n");
      return 2;
    }
  }
#ifdef MPGM_HAVE_NANOFLANN
  const int have_nf = 1;
  const int nfv = nf_version();
#else
  const int have_nf = 0;
  const int nfv = 0;
#endif
  const int sizes[3] = {10000, 100000, 1000000};
  const int nsizes = quick ? 2 : 3;
  const int nmax = sizes[nsizes - 1];
  double *xy = malloc(2 * (size_t)nmax * sizeof *xy), *xs = malloc(2 * (size_t)nmax * sizeof *xs);
  if (!xy || !xs) return 1;
  const double *qs[NORDER] = {xy, xs};

  result ours[3], nf[3];
  double brute_rad[3], brute_knn_t[3];
  int brute_nq[3];
  for (int s = 0; s < nsizes; s++) {
    const int n = sizes[s];
    for (size_t i = 0; i < 2 * (size_t)n; i++) xy[i] = urand();
    morton_order(xy, n, xs);
    fprintf(stderr, "bench_kdtree: n = %d\n", n);
    run_size(xy, n, leaf, 10, n >= 1000000 ? 3 : 5, n >= 1000000 ? 2 : 3, qs, NORDER, &ours[s],
             &nf[s]);
    /* brute force on a sample of the queries, scaled to all n */
    int nq = (int)(BRUTE_BUDGET / n);
    if (nq > n) nq = n;
    brute_nq[s] = nq;
    brute_rad[s] = brute_radius(xy, n, xy, nq, sqrt(RADIUS_NEIGHBOURS / (PI * n))) * n / nq;
    brute_knn_t[s] = brute_knn(xy, n, xy, nq, KNN_K) * n / nq;
  }

  /* leaf-size table at n = 1e5 */
  const int leaves[] = {4, 6, 8, 10, 12, 16, 24, 32};
  const int nleaves = quick ? 0 : (int)(sizeof leaves / sizeof leaves[0]);
  result tl_ours[8], tl_nf[8];
  const int ntune = 100000;
  for (size_t i = 0; i < 2 * (size_t)ntune; i++) xy[i] = urand();
  morton_order(xy, ntune, xs);
  for (int l = 0; l < nleaves; l++) {
    fprintf(stderr, "bench_kdtree: leaf %d\n", leaves[l]);
    run_size(xy, ntune, leaves[l], leaves[l], 3, 2, qs, NORDER, &tl_ours[l], &tl_nf[l]);
  }

  /* ---------------------------------------------------------- markdown */
  printf("## kd-tree\n\n");
  printf("`core/mpgm_kdtree.h` (leaf size %d) against brute force and ", leaf);
  if (have_nf) {
    const char *pkg = getenv("MPGM_NANOFLANN_PKG"); /* set by bench/kdtree from dpkg */
    printf("nanoflann %s (`NANOFLANN_VERSION` 0x%x; `KDTreeSingleIndexAdaptor`, DIM = 2, "
           "`L2_Simple_Adaptor`, uint32 indices, its default leaf size 10)",
           pkg && *pkg ? pkg : "", nfv);
  } else
    printf("nanoflann (not found: install `libnanoflann-dev` for those columns)");
  printf(". Both index the same borrowed interleaved array and are compiled with the build's "
         "Release flags (`-O3`, no `-march`). Points: n uniform random in the unit square. "
         "Queries: every point, in storage order (random in space) and in Morton (Z-curve) order "
         "(coherent, as when a front end walks its nodes body by body). Radius r = sqrt(%.0f / (pi "
         "n)) "
         "(closed ball for ours, open for nanoflann; no point lies on a circle here), results "
         "sorted by distance in both; kNN k = %d. One thread; each time is the minimum over "
         "repeated runs (builds 5, query sweeps 3; 3 and 2 at 1e6 and in the leaf table), ours and "
         "nanoflann "
         "interleaved; ours/nanoflann < 1: ours is faster. \"refit\" (mpgm_kdtree_refit: "
         "boxes recomputed, structure kept) and \"rebuild\" (memory reused, the previous "
         "permutation as the starting order) follow a random displacement of every point by up "
         "to a quarter of the mean spacing. Brute force is timed on the first "
         "min(n, 1e8 / n) queries and scaled to n queries (column \"brute queries timed\"). "
         "Generated by `bench/kdtree`.\n\n",
         RADIUS_NEIGHBOURS, KNN_K);

  printf("| n | build ours [ms] | build nanoflann [ms] | ours/nanoflann | rebuild ours after a "
         "move [ms] | refit ours after a move [ms] | leaves | depth | tree memory [MB] |\n");
  printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int s = 0; s < nsizes; s++) {
    printf("| %d | %.2f |", sizes[s], 1e3 * ours[s].build);
    cell_time(nf[s].build, 1e3, have_nf, "%.2f");
    cell_ratio(ours[s].build, nf[s].build, have_nf);
    printf(" %.2f | %.2f | %d | %d | %.1f |\n", 1e3 * ours[s].rebuild, 1e3 * ours[s].refit,
           ours[s].st.leaves, ours[s].st.depth, ours[s].st.bytes / 1048576.0);
  }
  printf(
      "\n| n | query | query order | neighbours (mean) | ours [µs/query] | nanoflann [µs/query] | "
      "ours/nanoflann | brute force [µs/query] | brute queries timed | brute/ours |\n");
  printf("|---:|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  int cross_ok = 1;
  const char *order_name[NORDER] = {"random", "Morton"};
  for (int s = 0; s < nsizes; s++) {
    const double n = sizes[s];
    for (int kind = 0; kind < 2; kind++)
      for (int o = 0; o < NORDER; o++) {
        const double to = kind ? ours[s].knn[o] : ours[s].radius[o];
        const double tn = kind ? nf[s].knn[o] : nf[s].radius[o];
        const double tb = kind ? brute_knn_t[s] : brute_rad[s];
        if (kind)
          printf("| %d | kNN, k = %d | %s | %d |", sizes[s], KNN_K, order_name[o], KNN_K);
        else
          printf("| %d | radius | %s | %.1f |", sizes[s], order_name[o], ours[s].rad_total / n);
        printf(" %.3f |", 1e6 * to / n);
        cell_time(tn / n, 1e6, have_nf, "%.3f");
        cell_ratio(to, tn, have_nf);
        if (o == ORDER_RANDOM)
          printf(" %.1f | %d | %.0f |\n", 1e6 * tb / n, brute_nq[s], tb / to);
        else
          printf(" | | |\n");
      }
    if (have_nf) /* checksums of the last order run, the same for both */
      cross_ok &= ours[s].rad_total == nf[s].rad_total && ours[s].rad_sum == nf[s].rad_sum &&
                  ours[s].knn_sum == nf[s].knn_sum;
  }
  if (have_nf)
    printf(
        "\nCross-check against nanoflann: radius hit counts, largest distance per query and k-th "
        "kNN distance per query (summed) %s.\n",
        cross_ok ? "identical at every size" : "DIFFER (see bench_kdtree)");

  if (nleaves) {
    printf("\nLeaf size, n = %d, both trees at the same leaf size (build [ms]; queries "
           "[µs/query], random / Morton order):\n\n",
           ntune);
    printf("| leaf | build ours | build nanoflann | radius ours | radius nanoflann | kNN ours | "
           "kNN nanoflann |\n");
    printf("|---:|---:|---:|---:|---:|---:|---:|\n");
    for (int l = 0; l < nleaves; l++) {
      const result *a = &tl_ours[l], *b = &tl_nf[l];
      const double us = 1e6 / ntune;
      printf("| %d | %.2f |", leaves[l], 1e3 * a->build);
      cell_time(b->build, 1e3, have_nf, "%.2f");
      printf(" %.3f / %.3f |", us * a->radius[0], us * a->radius[1]);
      if (have_nf)
        printf(" %.3f / %.3f |", us * b->radius[0], us * b->radius[1]);
      else
        printf(" n/a |");
      printf(" %.3f / %.3f |", us * a->knn[0], us * a->knn[1]);
      if (have_nf)
        printf(" %.3f / %.3f |", us * b->knn[0], us * b->knn[1]);
      else
        printf(" n/a |");
      printf("\n");
    }
  }

  if (have_nf) {
    double worst = 0;
    const char *what = "";
    int worst_n = 0;
    for (int s = 0; s < nsizes; s++) {
      const double rr[5] = {ours[s].build / nf[s].build, ours[s].radius[0] / nf[s].radius[0],
                            ours[s].knn[0] / nf[s].knn[0], ours[s].radius[1] / nf[s].radius[1],
                            ours[s].knn[1] / nf[s].knn[1]};
      const char *names[5] = {"build", "radius (random order)", "kNN (random order)",
                              "radius (Morton order)", "kNN (Morton order)"};
      for (int m = 0; m < 5; m++)
        if (rr[m] > worst) worst = rr[m], what = names[m], worst_n = sizes[s];
    }
    printf("\nAim (issue): within 1.3x of nanoflann in build and query time: %s (largest ratio "
           "ours/nanoflann %.2f, %s at n = %d).\n",
           worst <= 1.3 ? "met" : "NOT met", worst, what, worst_n);
  }
  free(xy), free(xs);
  return 0;
}
