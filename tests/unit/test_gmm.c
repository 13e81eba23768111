/* test_gmm.c -- the GMM front end's node clouds (gmm/gmm.c): every cloud
 * holds exactly the nodes a brute-force search finds within the support
 * radius (MLS, LME), the connectivity reproduces constants and linear
 * fields with their gradients, radius growth reaches shape.min_nodes,
 * cloud enlargement rescues a quadratic MLS basis on a too-small support,
 * a point that cannot be rescued fails with a recoverable error, and a
 * node too close to another (mesh.min_node_distance) leaves the clouds.
 *
 * Tolerances: linear reproduction of LME holds to its Newton tolerance,
 * |sum N_a x_a - x| < tol_newton h = 1e-10 h; gradients (centred form) and
 * MLS to round-off of sums of ~30 O(1) terms. TOL_REPRO = 1e-9 (relative to
 * h or 1) leaves a margin of 10 over the Newton tolerance. The brute-force
 * comparison is exact except for nodes within 1e-9 r of the radius, whose
 * N is zero to round-off and may be dropped or kept. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include "mpgm_core_impl.h"
#include "mpgm_core.h"
#include "mpgm_scene_io.h"
#include "mpgm_discretisation.h"
#include "mpgm_fem.h"
#include "mpgm_gmm.h"
#include "mpgm_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define TOL_REPRO 1e-9

static int write_scene(const char *path) {
  FILE *f = fopen(path, "w");
  if (!f) return -1;
  fprintf(
      f,
      "{\"method\": \"gmm\", \"shape\": {\"kind\": \"mls\"},\n"
      " \"mesh\": {\"h\": 0.1371, \"domain\": {\"min\": [-0.213, -0.117], \"max\": [3.1, 1.27]}},\n"
      " \"materials\": {\"m\": {\"type\": \"neo_hookean\", \"density\": 2385.7, \"E\": 3.1e7, "
      "\"nu\": 0.287}},\n"
      " \"bodies\": [{\"material\": \"m\", \"rectangle\": {\"min\": [0.31, 0.17], \"max\": [2.71, "
      "0.93]}}],\n"
      " \"boundaries\": [{\"x\": 0.31, \"fix\": [\"x\", \"y\"]}],\n"
      " \"gravity\": [0.0, -9.81], \"probes\": {\"tip\": [2.71, 0.55], \"in\": [1.234, 0.567]},\n"
      " \"output\": {\"vtk\": \"none\"}}\n");
  return fclose(f);
}

/* Load the scene with overrides and set up the problem. */
static int make(const char *path, int nset, const char *const *sets, mpgm_ctx *ctx, mpgm_scene **s,
                mpgm_problem **pb) {
  mpgm_ctx_init(ctx);
  *s = NULL;
  *pb = NULL;
  int err = mpgm_scene_load(ctx, path, nset, sets, s);
  if (!err) err = mpgm_problem_create(ctx, *s, &mpgm_frontend_gmm, pb);
  return err;
}

static void destroy(mpgm_scene **s, mpgm_problem **pb) {
  mpgm_problem_destroy(pb);
  mpgm_scene_destroy(s);
}

/* Node lists sorted and unique; sum N = 1, sum N x = x, sum dN = 0,
 * sum x (x) dN = I. Returns the number of bad points. */
static int check_reproduction(const mpgm_problem *pb, int order2, double *worst) {
  const mpgm_conn *C = &pb->conn;
  const double *X = pb->nodes.x, h = pb->scene->h;
  const int m = pb->pts.n + pb->pts.nprobe;
  int bad = 0;
  *worst = 0.0;
  for (int p = 0; p < m; p++) {
    const double *x = pb->pts.x + 2 * p;
    double s = 0, sx = 0, sy = 0, g[2] = {0, 0}, G[4] = {0, 0, 0, 0}, q = 0;
    int sorted = 1;
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      if (k > C->ptr[p] && C->node[k - 1] >= I) sorted = 0;
      const double N = C->N[k], dx = X[2 * I] - x[0], dy = X[2 * I + 1] - x[1];
      s += N;
      sx += N * dx;
      sy += N * dy;
      q += N * dx * dy; /* quadratic reproduction: sum N (x_a - x)(y_a - y) = 0 */
      g[0] += C->dN[2 * k];
      g[1] += C->dN[2 * k + 1];
      G[0] += X[2 * I] * C->dN[2 * k];
      G[1] += X[2 * I] * C->dN[2 * k + 1];
      G[2] += X[2 * I + 1] * C->dN[2 * k];
      G[3] += X[2 * I + 1] * C->dN[2 * k + 1];
    }
    double e = fabs(s - 1.0);
    e = fmax(e, fmax(fabs(sx), fabs(sy)) / h);
    /* gradients: material points only. A probe uses N alone and is
     * evaluated without the condition limit (gmm.c): on the boundary its
     * LME Hessian may be ill-conditioned and its grad N inaccurate */
    if (p < pb->pts.n) {
      e = fmax(e, fmax(fabs(g[0]), fabs(g[1])) * h);
      e = fmax(e, fmax(fmax(fabs(G[0] - 1.0), fabs(G[1])), fmax(fabs(G[2]), fabs(G[3] - 1.0))));
    }
    if (order2) e = fmax(e, fabs(q) / (h * h));
    *worst = fmax(*worst, e);
    if (!(e <= TOL_REPRO) || !sorted) bad++;
  }
  return bad;
}

/* Every cloud against a brute-force search over all nodes: nodes in the
 * list lie within r; nodes strictly inside (d < (1 - 1e-9) r) are listed. */
static void check_clouds(const char *label, const mpgm_problem *pb) {
  const mpgm_scene *s = pb->scene;
  double r = 0.0;
  mpgm_shape_params par = s->shape_par;
  mpgm_shape_support_radius(s->shape, &par, &r);
  const mpgm_conn *C = &pb->conn;
  const double *X = pb->nodes.x;
  const int m = pb->pts.n + pb->pts.nprobe;
  int outside = 0, missing = 0;
  long entries = 0;
  unsigned char *in = calloc((size_t)pb->nodes.n, 1);
  for (int p = 0; p < m && in; p++) {
    const double *x = pb->pts.x + 2 * p;
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      const double dx = X[2 * I] - x[0], dy = X[2 * I + 1] - x[1];
      if (dx * dx + dy * dy > r * r) outside++;
      in[I] = 1;
      entries++;
    }
    for (int I = 0; I < pb->nodes.n; I++) {
      const double dx = X[2 * I] - x[0], dy = X[2 * I + 1] - x[1];
      if (sqrt(dx * dx + dy * dy) < (1.0 - 1e-9) * r && !in[I]) missing++;
    }
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) in[C->node[k]] = 0;
  }
  free(in);
  mpgm_test(in != NULL || m == 0, "%s: workspace", label);
  mpgm_test(outside == 0 && missing == 0,
            "%s: %d clouds (%ld entries, r = %.4f m = %.3f h) equal the brute-force search: %d "
            "listed outside r, %d inside r missing",
            label, m, entries, r, r / s->h, outside, missing);
}

static void run_kind(const char *path, const char *kind) {
  char label[64], set[64];
  snprintf(label, sizeof label, "%s", kind);
  snprintf(set, sizeof set, "shape.kind=%s", kind);
  const char *sets[] = {set};
  mpgm_ctx ctx;
  mpgm_scene *s;
  mpgm_problem *pb;
  int err = make(path, 1, sets, &ctx, &s, &pb);
  mpgm_test(err == 0, "%s: scene and problem (%s)", label, ctx.msg);
  if (err) {
    destroy(&s, &pb);
    return;
  }
  const int v0 = pb->conn.version;
  err = mpgm_begin_step(pb);
  mpgm_test(err == 0, "%s: begin_step (%s)", label, ctx.msg);
  if (err) {
    destroy(&s, &pb);
    return;
  }
  mpgm_test(pb->conn.version != v0,
            "%s: first step replaces the cells' connectivity (version %d -> %d)", label, v0,
            pb->conn.version);
  check_clouds(label, pb);
  double worst;
  const int bad = check_reproduction(pb, 0, &worst);
  mpgm_test(
      bad == 0,
      "%s: sorted lists; sum N = 1 and linear reproduction at every point and "
      "probe, sum grad N = 0 and sum x (x) grad N = I at every point (worst %.2e <= %.0e; %d bad)",
      label, worst, TOL_REPRO, bad);
  mpgm_test(ctx.count[MPGM_C_RADIUS_GROWTHS] == 0 && ctx.count[MPGM_C_CLOUD_ENLARGEMENTS] == 0,
            "%s: default parameters: no radius growth (%ld), no enlargement (%ld)", label,
            ctx.count[MPGM_C_RADIUS_GROWTHS], ctx.count[MPGM_C_CLOUD_ENLARGEMENTS]);
  /* the same node positions again: same lists, no new pattern */
  const int v1 = pb->conn.version;
  err = mpgm_begin_step(pb);
  mpgm_test(err == 0 && pb->conn.version == v1, "%s: unchanged clouds keep conn.version (%d, %d)",
            label, v1, pb->conn.version);
  /* nodes moved by a smooth displacement that keeps the lines x = const
   * straight (the tip probe stays on the hull of the nodes; in a run a
   * probe moves by sum N du and stays inside): clouds follow */
  for (int I = 0; I < pb->nodes.n; I++) {
    const double X = pb->nodes.X[2 * I], Y = pb->nodes.X[2 * I + 1];
    pb->nodes.x[2 * I] = X + 0.0731 * X * Y + 0.021 * X;
    pb->nodes.x[2 * I + 1] = Y - 0.0853 * X * X / 7.3;
  }
  const int np = pb->pts.n + pb->pts.nprobe;
  for (int p = 0; p < np; p++) { /* points follow the same map */
    const double X = pb->pts.x0[2 * p], Y = pb->pts.x0[2 * p + 1];
    pb->pts.x[2 * p] = X + 0.0731 * X * Y + 0.021 * X;
    pb->pts.x[2 * p + 1] = Y - 0.0853 * X * X / 7.3;
  }
  err = mpgm_begin_step(pb);
  mpgm_test(err == 0, "%s: begin_step on moved nodes (%s)", label, ctx.msg);
  if (!err) {
    snprintf(label, sizeof label, "%s, moved nodes", kind);
    check_clouds(label, pb);
    const int b2 = check_reproduction(pb, 0, &worst);
    mpgm_test(b2 == 0, "%s: reproduction at every point (worst %.2e; %d bad)", label, worst, b2);
  }
  destroy(&s, &pb);
}

static void run_growth(const char *path) {
  const char *sets[] = {"shape.min_nodes=40"};
  mpgm_ctx ctx;
  mpgm_scene *s;
  mpgm_problem *pb;
  int err = make(path, 1, sets, &ctx, &s, &pb);
  if (!err) err = mpgm_begin_step(pb);
  mpgm_test(err == 0, "mls, min_nodes = 40: begin_step (%s)", ctx.msg);
  if (!err) {
    int small = 0;
    const int m = pb->pts.n + pb->pts.nprobe;
    for (int p = 0; p < m; p++) small += pb->conn.ptr[p + 1] - pb->conn.ptr[p] < 40;
    mpgm_test(ctx.count[MPGM_C_RADIUS_GROWTHS] > 0 && small == 0,
              "mls, min_nodes = 40: %ld radius growths; every cloud has >= 40 nodes (%d smaller)",
              ctx.count[MPGM_C_RADIUS_GROWTHS], small);
    double worst;
    const int bad = check_reproduction(pb, 0, &worst);
    mpgm_test(bad == 0, "mls, min_nodes = 40: reproduction (worst %.2e; %d bad)", worst, bad);
  }
  destroy(&s, &pb);
}

static void run_enlarge(const char *path) {
  /* quadratic MLS (6 terms) on a support of 0.9 h with min_nodes = 1:
   * the first clouds hold 1-4 nodes and every evaluation fails (too few);
   * enlargement must rescue every point */
  const char *sets[] = {"shape.order=2", "shape.radius=0.12339", "shape.min_nodes=1"};
  mpgm_ctx ctx;
  mpgm_scene *s;
  mpgm_problem *pb;
  int err = make(path, 3, sets, &ctx, &s, &pb);
  if (!err) err = mpgm_begin_step(pb);
  mpgm_test(err == 0, "mls quadratic, R = 0.9 h, min_nodes = 1: begin_step (%s)", ctx.msg);
  if (!err) {
    double worst;
    const int bad = check_reproduction(pb, 1, &worst);
    mpgm_test(ctx.count[MPGM_C_CLOUD_ENLARGEMENTS] > 0 && bad == 0,
              "enlargement: %ld enlargements rescue every point; quadratic reproduction (worst "
              "%.2e; %d bad)",
              ctx.count[MPGM_C_CLOUD_ENLARGEMENTS], worst, bad);
  }
  destroy(&s, &pb);
  /* the same with no enlargement allowed: a recoverable failure naming the
   * point and the reason */
  const char *sets0[] = {"shape.order=2", "shape.radius=0.12339", "shape.min_nodes=1",
                         "shape.max_enlarge=0"};
  err = make(path, 4, sets0, &ctx, &s, &pb);
  mpgm_test(err == 0, "max_enlarge = 0: problem (%s)", ctx.msg);
  if (!err) {
    err = mpgm_begin_step(pb);
    mpgm_test(
        err == MPGM_ERR_SHAPE && strstr(ctx.msg, "point 0") && strstr(ctx.msg, "too few nodes"),
        "max_enlarge = 0: MPGM_ERR_SHAPE (%d) naming the point and the reason: %s", err, ctx.msg);
  }
  destroy(&s, &pb);
}

/* mesh.min_node_distance (grid-filled GMM): a node moved to 0.2 h from a
 * lower-numbered neighbour is left out of every cloud and parked (fixed)
 * for the step; the other points' functions are evaluated without it, so
 * they still reproduce linear fields exactly; with the rule off (0) the
 * node stays in the clouds. */
static void run_merge(const char *path) {
  for (int on = 0; on < 2; on++) {
    const char *sets[] = {"obstacles=[{\"y\": 0.0201, \"side\": \"below\"}]", "boundaries=[]",
                          on ? "mesh.min_node_distance=0.3" : "mesh.min_node_distance=0"};
    const char *label = on ? "min_node_distance 0.3" : "min_node_distance 0";
    mpgm_ctx ctx;
    mpgm_scene *s;
    mpgm_problem *pb;
    int err = make(path, 3, sets, &ctx, &s, &pb);
    if (!err) err = mpgm_begin_step(pb);
    mpgm_test(err == 0 && ctx.count[MPGM_C_NODES_MERGED] == 0,
              "%s: grid-filled body, first step: no node merged (%ld) (%s)", label,
              ctx.count[MPGM_C_NODES_MERGED], err ? ctx.msg : "ok");
    if (err) {
      destroy(&s, &pb);
      continue;
    }
    /* the body node nearest the body's centre, and its nearest higher-numbered free neighbour */
    const double *X = pb->nodes.x, h = s->h;
    int i = -1, j = -1;
    double best = INFINITY;
    for (int a = 0; a < pb->nodes.n; a++) {
      const double dx = X[2 * a] - 1.5, dy = X[2 * a + 1] - 0.55, d = dx * dx + dy * dy;
      if (!pb->nodes.fix[2 * a] && d < best) best = d, i = a;
    }
    best = INFINITY;
    for (int a = i + 1; a < pb->nodes.n; a++) {
      const double dx = X[2 * a] - X[2 * i], dy = X[2 * a + 1] - X[2 * i + 1], d = dx * dx + dy * dy;
      if (!pb->nodes.fix[2 * a] && d < best) best = d, j = a;
    }
    mpgm_test(i >= 0 && j > i && fabs(sqrt(best) - h) < 1e-9 * h,
              "%s: neighbours %d and %d, h apart", label, i, j);
    if (i < 0 || j <= i) {
      destroy(&s, &pb);
      continue;
    }
    pb->nodes.x[2 * j] = X[2 * i] + 0.2 * (X[2 * j] - X[2 * i]);
    pb->nodes.x[2 * j + 1] = X[2 * i + 1] + 0.2 * (X[2 * j + 1] - X[2 * i + 1]);
    err = mpgm_begin_step(pb);
    int uses = 0;
    for (int k = 0; !err && k < pb->conn.ptr[pb->pts.n + pb->pts.nprobe]; k++) uses += pb->conn.node[k] == j;
    double worst = 0.0;
    const int bad = err ? -1 : check_reproduction(pb, 0, &worst);
    if (on) {
      mpgm_test(err == 0 && ctx.count[MPGM_C_NODES_MERGED] == 1 && uses == 0 && pb->nodes.fix[2 * j] &&
                    pb->nodes.fix[2 * j + 1] && !pb->nodes.fix[2 * i],
                "%s: node %d at 0.2 h from node %d: merged (%ld), in no cloud (%d uses), parked "
                "(fixed) for the step, node %d free (%s)",
                label, j, i, ctx.count[MPGM_C_NODES_MERGED], uses, i, err ? ctx.msg : "ok");
      mpgm_test(bad == 0,
                "%s: functions evaluated without the merged node reproduce linear fields at every "
                "point (worst %.2e <= %.0e; %d bad)",
                label, worst, TOL_REPRO, bad);
    } else {
      mpgm_test(err == 0 && ctx.count[MPGM_C_NODES_MERGED] == 0 && uses > 0 && !pb->nodes.fix[2 * j],
                "%s: node %d at 0.2 h from node %d stays in %d clouds, free (%s)", label, j, i,
                uses, err ? ctx.msg : "ok");
    }
    destroy(&s, &pb);
  }
}

static int int_cmp(const void *a, const void *b) {
  const int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

/* mpgm_sort_ints (the clouds' node lists) against qsort: distinct values
 * in a narrow range (its bitmap), repeated values, a wide range and
 * negative values (its insertion sort), and the edge of the bitmap's range. */
static void run_sort_ints(void) {
  unsigned s = 12345u;
  const int spans[6] = {1, 60, 900, 8191, 8192, 1 << 30};
  for (int c = 0; c < 6; c++)
    for (int rep = 0; rep < 2; rep++) /* rep 1: repeated values allowed */
      for (int trial = 0; trial < 50; trial++) {
        int a[200], b[200];
        const int n = trial % 2 ? 1 + trial * 3 : trial, base = c == 5 ? -(1 << 29) : 77;
        for (int i = 0; i < n; i++) {
          s = s * 1103515245u + 12345u;
          a[i] = base + (int)((s >> 1) % (unsigned)spans[c]);
        }
        if (!rep) { /* distinct: drop repeats */
          int m = 0;
          for (int i = 0; i < n; i++) {
            int seen = 0;
            for (int k = 0; k < m && !seen; k++) seen = a[k] == a[i];
            if (!seen) a[m++] = a[i];
          }
          memcpy(b, a, sizeof(int) * (size_t)m);
          mpgm_sort_ints(a, m);
          qsort(b, (size_t)m, sizeof(int), int_cmp);
          mpgm_test(m == 0 || memcmp(a, b, sizeof(int) * (size_t)m) == 0,
                    "sort_ints: %d distinct values in a range of %d", m, spans[c]);
        } else {
          memcpy(b, a, sizeof(int) * (size_t)n);
          mpgm_sort_ints(a, n);
          qsort(b, (size_t)n, sizeof(int), int_cmp);
          mpgm_test(n == 0 || memcmp(a, b, sizeof(int) * (size_t)n) == 0,
                    "sort_ints: %d values with repeats in a range of %d", n, spans[c]);
        }
      }
}

int main(void) {
  run_sort_ints();
  char dir[] = "/tmp/mpgm_test_gmm_XXXXXX";
  if (!mkdtemp(dir)) {
    mpgm_test(0, "mkdtemp");
    return mpgm_test_summary();
  }
  char path[512];
  snprintf(path, sizeof path, "%s/gmm.json", dir);
  if (write_scene(path))
    mpgm_test(0, "write %s", path);
  else {
    run_kind(path, "mls");
    run_kind(path, "lme");
    run_growth(path);
    run_enlarge(path);
    run_merge(path);
  }
  remove(path);
  rmdir(dir);
  return mpgm_test_summary();
}
