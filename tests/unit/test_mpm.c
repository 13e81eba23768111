/* test_mpm.c -- the grid-reset front end: background grid location, the
 * projection of mass, momentum and inertia (conservation to round-off),
 * activation of cells and nodes, and a particle leaving the grid.
 *
 * Tolerances: sums over ~1e3 particles of O(1) terms: round-off ~1e-13
 * relative; TEST_TOL4 (~3.6e-12) leaves a margin of ~30. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include "mpgm_core_impl.h"
#include "mpgm_core.h"
#include "mpgm_scene_io.h"
#include "mpgm_grid.h"
#include "mpgm_mpm.h"
#include "mpgm_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int write_scene(const char *path, const char *cell, const char *analysis) {
  FILE *f = fopen(path, "w");
  if (!f) return -1;
  fprintf(f,
          "{\"method\": \"mpm\", \"mesh\": {\"h\": 0.0917, \"cell\": \"%s\",\n"
          "  \"domain\": {\"min\": [-0.213, -0.117], \"max\": [1.931, 1.27]}},\n"
          " \"time\": {\"analysis\": \"%s\", \"dt\": 0.0123, \"end\": 0.1},\n"
          " \"materials\": {\"m\": {\"type\": \"neo_hookean\", \"density\": 2385.7, \"E\": 3.1e7, \"nu\": 0.287}},\n"
          " \"bodies\": [{\"material\": \"m\", \"disk\": {\"centre\": [0.712, 0.583], \"radius\": 0.4137},\n"
          "              \"velocity\": [1.37, -0.53]},\n"
          "            {\"material\": \"m\", \"rectangle\": {\"min\": [1.21, 0.05], \"max\": [1.83, 0.41]}}],\n"
          " \"boundaries\": [{\"y\": -0.117, \"condition\": \"stick\"}],\n"
          " \"gravity\": [0.0, -9.81], \"probes\": {\"c\": [0.712, 0.583]},\n"
          " \"output\": {\"vtk\": \"none\"}}\n",
          cell, analysis);
  return fclose(f);
}

static void test_grid(const mpgm_problem *pb, const mpgm_grid *g, rng *r) {
  (void)pb;
  int bad_inside = 0, bad_map = 0;
  for (int t = 0; t < 2000; t++) {
    const double x[2] = {uniform(r, g->min[0], g->max[0]), uniform(r, g->min[1], g->max[1])};
    int c;
    double xi[2], N[4], xn[8];
    int nodes[4];
    if (mpgm_grid_locate(g, x, &c, xi)) { bad_inside++; continue; }
    if (!mpgm_fe_inside(g->cell, xi, 1e-12)) bad_inside++;
    mpgm_grid_cell(g, c, nodes, xn);
    mpgm_fe_ref(g->cell, xi, N, NULL);
    double y[2] = {0, 0};
    for (int a = 0; a < g->nn; a++) {
      y[0] += N[a] * xn[2 * a];
      y[1] += N[a] * xn[2 * a + 1];
    }
    if (fabs(y[0] - x[0]) > 1e-12 || fabs(y[1] - x[1]) > 1e-12) bad_map++;
  }
  mpgm_test(bad_inside == 0, "%s grid: 2000 random points located in a cell holding them (%d bad)",
            g->cell == MPGM_CELL_Q4 ? "Q4" : "T3", bad_inside);
  mpgm_test(bad_map == 0, "%s grid: local coordinates map back to the point to 1e-12 (%d bad)",
            g->cell == MPGM_CELL_Q4 ? "Q4" : "T3", bad_map);
  int c;
  double xi[2];
  const double out[2] = {g->max[0] + 1e-3, 0.5 * (g->min[1] + g->max[1])};
  mpgm_test(mpgm_grid_locate(g, out, &c, xi) == MPGM_ERR_DOMAIN, "point outside the grid: MPGM_ERR_DOMAIN");
}

static void run(const char *dir, const char *cell, const char *analysis, rng *r) {
  char path[512];
  snprintf(path, sizeof path, "%s/mpm_%s_%s.json", dir, cell, analysis);
  if (write_scene(path, cell, analysis)) { mpgm_test(0, "write %s", path); return; }
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene *s = NULL;
  mpgm_problem *pb = NULL;
  int err = mpgm_scene_load(&ctx, path, 0, NULL, &s);
  if (!err) err = mpgm_problem_create(&ctx, s, &mpgm_frontend_mpm, &pb);
  mpgm_test(err == 0, "%s %s: scene and problem (%s)", cell, analysis, ctx.msg);
  if (err) { mpgm_scene_destroy(&s); return; }
  mpgm_grid g;
  mpgm_grid_init(&ctx, &g, s);
  if (strcmp(analysis, "static") == 0) test_grid(pb, &g, r);
  mpgm_points *P = &pb->pts;
  /* give the particles a non-trivial velocity and acceleration field */
  for (int p = 0; p < P->n; p++)
    for (int c = 0; c < 2; c++) {
      P->v[2 * p + c] += uniform(r, -2.3, 2.3);
      P->a[2 * p + c] = uniform(r, -7.1, 7.1);
    }
  err = mpgm_begin_step(pb);
  mpgm_test(err == 0, "%s %s: begin_step (%s)", cell, analysis, ctx.msg);
  double mp = 0, mn = 0, qp[2] = {0, 0}, qn[2] = {0, 0}, fp[2] = {0, 0}, fn[2] = {0, 0};
  for (int p = 0; p < P->n; p++) {
    mp += P->mass[p];
    for (int c = 0; c < 2; c++) {
      qp[c] += P->mass[p] * P->v[2 * p + c];
      fp[c] += P->mass[p] * P->a[2 * p + c];
    }
  }
  const mpgm_nodes *nd = &pb->nodes;
  for (int i = 0; i < nd->n; i++) {
    mn += nd->mass[i];
    for (int c = 0; c < 2; c++) {
      qn[c] += nd->mass[i] * nd->v[2 * i + c];
      fn[c] += nd->mass[i] * nd->a[2 * i + c];
    }
  }
  mpgm_test_rel(mn, mp, TEST_TOL4, "%s %s: nodal mass = particle mass (%d particles, %d nodes)", cell,
                analysis, P->n, nd->n);
  if (strcmp(analysis, "dynamic") == 0)
    for (int c = 0; c < 2; c++) {
      const double sc = fabs(qp[0]) + fabs(qp[1]), sf = fabs(fp[0]) + fabs(fp[1]);
      mpgm_test_abs(qn[c], qp[c], TEST_TOL4 * sc, "%s: nodal momentum %c = particle momentum", cell, "xy"[c]);
      mpgm_test_abs(fn[c], fp[c], TEST_TOL4 * sf, "%s: nodal inertia force %c = particle's", cell, "xy"[c]);
    }
  /* partition of unity of every particle's connectivity; only nodes of
   * active cells with mass carry equations */
  int bad = 0, zero_mass = 0;
  for (int p = 0; p < P->n + P->nprobe; p++) {
    double sN = 0;
    for (int k = pb->conn.ptr[p]; k < pb->conn.ptr[p + 1]; k++) sN += pb->conn.N[k];
    if (fabs(sN - 1.0) > 1e-12) bad++;
  }
  for (int i = 0; i < nd->n; i++) zero_mass += !(nd->mass[i] > 0.0);
  mpgm_test(bad == 0, "%s %s: sum N = 1 for every particle and probe (%d bad)", cell, analysis, bad);
  mpgm_test(zero_mass == 0, "%s %s: no node of the step has zero mass", cell, analysis);
  int fixed_on_floor = 1;
  for (int i = 0; i < nd->n; i++)
    if (fabs(nd->X[2 * i + 1] + 0.117) < 1e-12) fixed_on_floor &= nd->fix[2 * i] && nd->fix[2 * i + 1];
  mpgm_test(fixed_on_floor, "%s %s: stick floor fixes both components of its grid nodes", cell, analysis);
  /* a particle outside the grid is a clear error naming it */
  P->x[2 * 7] = g.max[0] + 0.5;
  mpgm_err_clear(&ctx);
  err = mpgm_begin_step(pb);
  mpgm_test(err == MPGM_ERR_DOMAIN && strstr(ctx.msg, "particle 7") && strstr(ctx.msg, "outside the background grid"),
            "%s %s: a particle leaving the grid is MPGM_ERR_DOMAIN naming it: %s", cell, analysis, ctx.msg);
  mpgm_problem_destroy(&pb);
  mpgm_scene_destroy(&s);
  mpgm_test(pb == NULL, "destroy nulls the pointer");
}

/* mpgm_points_sort: a stable reorder by key that moves every committed
 * array with its point (checked through the ids) and leaves the probes. */
static void test_points_sort(rng *r) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_points P;
  memset(&P, 0, sizeof P);
  const int n = 257, nprobe = 2, ns = 3, nkey = 17;
  if (mpgm_points_alloc(&ctx, &P, n, nprobe, 0, ns)) {
    mpgm_test(0, "points_sort: allocation");
    return;
  }
  int key[257], perm[257];
  /* every value a function of the id, so the check can recompute it */
#define VAL(i, c) (1000.0 * (i) + (c))
  for (int i = 0; i < n + nprobe; i++) {
    for (int c = 0; c < 2; c++) {
      P.x[2 * i + c] = VAL(i, c); P.x0[2 * i + c] = VAL(i, c + 2); P.u[2 * i + c] = VAL(i, c + 4);
      P.v[2 * i + c] = VAL(i, c + 6); P.a[2 * i + c] = VAL(i, c + 8);
    }
    P.mass[i] = VAL(i, 10); P.vol0[i] = VAL(i, 11); P.vol[i] = VAL(i, 12);
    for (int c = 0; c < 4; c++) { P.F[4 * i + c] = VAL(i, 13 + c); P.sigma[4 * i + c] = VAL(i, 17 + c); P.S0[4 * i + c] = VAL(i, 21 + c); }
    for (int c = 0; c < ns; c++) P.state[ns * i + c] = VAL(i, 25 + c);
    for (int c = 0; c < 4; c++) { P.r0[4 * i + c] = VAL(i, 40 + c); P.L[4 * i + c] = VAL(i, 44 + c); }
    P.mat[i] = i % 3; P.body[i] = i % 5;
    if (i < n) key[i] = (int)uniform(r, 0, nkey);
  }
  int err = mpgm_points_sort(&ctx, NULL, &P, key, nkey, perm);
  int ok = !err && ctx.count[MPGM_C_POINT_SORTS] == 1, sorted = 1, stable = 1, moved = 1, probes = 1;
  for (int q = 0; q < n; q++) {
    const int i = P.id[q];
    if (i != perm[q]) ok = 0;
    if (q && key[perm[q]] < key[perm[q - 1]]) sorted = 0;
    if (q && key[perm[q]] == key[perm[q - 1]] && perm[q] < perm[q - 1]) stable = 0;
    for (int c = 0; c < 2; c++)
      moved &= P.x[2 * q + c] == VAL(i, c) && P.x0[2 * q + c] == VAL(i, c + 2) && P.u[2 * q + c] == VAL(i, c + 4) &&
               P.v[2 * q + c] == VAL(i, c + 6) && P.a[2 * q + c] == VAL(i, c + 8);
    moved &= P.mass[q] == VAL(i, 10) && P.vol0[q] == VAL(i, 11) && P.vol[q] == VAL(i, 12);
    for (int c = 0; c < 4; c++)
      moved &= P.F[4 * q + c] == VAL(i, 13 + c) && P.sigma[4 * q + c] == VAL(i, 17 + c) && P.S0[4 * q + c] == VAL(i, 21 + c);
    for (int c = 0; c < ns; c++) moved &= P.state[ns * q + c] == VAL(i, 25 + c);
    for (int c = 0; c < 4; c++) moved &= P.r0[4 * q + c] == VAL(i, 40 + c) && P.L[4 * q + c] == VAL(i, 44 + c);
    moved &= P.mat[q] == i % 3 && P.body[q] == i % 5;
  }
  for (int i = n; i < n + nprobe; i++) probes &= P.id[i] == i && P.x[2 * i] == VAL(i, 0) && P.mass[i] == VAL(i, 10);
#undef VAL
  mpgm_test(ok && sorted && stable, "points_sort: %d points ordered by key, stably, ids = perm", n);
  mpgm_test(moved, "points_sort: every committed array moved with its point");
  mpgm_test(probes, "points_sort: probes stay in place");
  void *arr[] = {P.x, P.x0, P.u, P.v, P.a, P.mass, P.vol0, P.vol, P.F, P.sigma, P.S0, P.r0, P.L,
                 P.state, P.mat, P.body, P.id, P.F_t, P.dF_t, P.sigma_t, P.D_t, P.state_t, P.vol_t};
  for (size_t i = 0; i < sizeof arr / sizeof arr[0]; i++) free(arr[i]);
}

int main(void) {
  char dir[] = "/tmp/mpgm_test_mpm_XXXXXX";
  if (!mkdtemp(dir)) { perror("mkdtemp"); return 1; }
  rng r = {0x9E3779B97F4A7C15ULL};
  test_points_sort(&r);
  for (int c = 0; c < 2; c++) {
    run(dir, c ? "tri" : "quad", "static", &r);
    run(dir, c ? "tri" : "quad", "dynamic", &r);
  }
  char cmd[600];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
  return mpgm_test_summary();
}
