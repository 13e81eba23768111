/* test_ordering.c -- geometric nested dissection (core/ordering.c).
 *
 * Graphs: structured grids with the node graphs of Q4 (9-point) and T3
 * (7-point) meshes, a strip, a disk cut out of a grid, random points with
 * neighbours within a radius (node clouds), points on one line, duplicates,
 * one node, none. For every graph the order must be a permutation. Its
 * quality is measured by the fill of the Cholesky factor (CHOLMOD's
 * symbolic analysis with the order given) against AMD and against the
 * natural (row by row) order; and the factorisation with the given order
 * must solve the system (graph Laplacian + identity, 2 unknowns per node as
 * in the core) like the backend's own order, with CHOLMOD and UMFPACK, and
 * UMFPACK must keep the order's fill (L + U about twice CHOLMOD's L). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core_impl.h"
#include "mpgm_core.h"
#include "mpgm_solver.h"
#include "mpgm_test.h"

typedef struct graph {
  int n;
  double *x; /* 2 per node */
  int *ptr, *adj;
} graph;

static void graph_free(graph *g) {
  free(g->x);
  free(g->ptr);
  free(g->adj);
  memset(g, 0, sizeof *g);
}

/* Neighbours: nodes within distance r (the node itself included, as in the
 * core's node graph). O(n^2): the test graphs are small. */
static void graph_radius(graph *g, double r) {
  const int n = g->n;
  g->ptr = calloc((size_t)n + 1, sizeof(int));
  for (int pass = 0; pass < 2; pass++) {
    int e = 0;
    for (int i = 0; i < n; i++) {
      for (int j = 0; j < n; j++) {
        const double dx = g->x[2 * i] - g->x[2 * j], dy = g->x[2 * i + 1] - g->x[2 * j + 1];
        if (dx * dx + dy * dy <= r * r * (1 + 1e-12)) {
          if (pass) g->adj[e] = j;
          e++;
        }
      }
      if (!pass) g->ptr[i + 1] = e;
    }
    if (!pass) g->adj = malloc(((size_t)e + 1) * sizeof(int));
  }
}

/* nx x ny grid nodes, spacing 1; tri: the T3 graph (diagonal (i,j)-(i+1,j+1)
 * only), else the Q4 graph (both diagonals). keep (may be NULL) selects
 * nodes. */
static void graph_grid(graph *g, int nx, int ny, int tri, int (*keep)(double, double)) {
  int *id = malloc((size_t)nx * ny * sizeof(int));
  g->n = 0;
  g->x = malloc(2 * (size_t)nx * ny * sizeof(double));
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx; i++) {
      id[j * nx + i] = -1;
      if (keep && !keep(i, j)) continue;
      id[j * nx + i] = g->n;
      g->x[2 * g->n] = i;
      g->x[2 * g->n + 1] = j;
      g->n++;
    }
  g->ptr = calloc((size_t)g->n + 1, sizeof(int));
  g->adj = malloc(9 * (size_t)g->n * sizeof(int));
  int e = 0;
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx; i++) {
      const int I = id[j * nx + i];
      if (I < 0) continue;
      for (int dj = -1; dj <= 1; dj++)
        for (int di = -1; di <= 1; di++) {
          if (tri && di * dj < 0) continue;
          const int a = i + di, b = j + dj;
          if (a < 0 || b < 0 || a >= nx || b >= ny || id[b * nx + a] < 0) continue;
          g->adj[e++] = id[b * nx + a];
        }
      g->ptr[I + 1] = e;
    }
  free(id);
}

static int in_disk(double i, double j) { return (i - 30) * (i - 30) + (j - 30) * (j - 30) <= 900; }

static int is_permutation(const int *p, int n) {
  char *seen = calloc((size_t)n + 1, 1);
  int ok = 1;
  for (int k = 0; k < n && ok; k++) {
    ok = p[k] >= 0 && p[k] < n && !seen[p[k]];
    if (ok) seen[p[k]] = 1;
  }
  free(seen);
  return ok;
}

/* K = graph Laplacian + identity on 2 unknowns per node (the two
 * components coupled within a node and between neighbours), full pattern,
 * sorted rows. */
static void build_matrix(const graph *g, mpgm_csc *A) {
  const int n = 2 * g->n;
  A->n = n;
  A->colptr = calloc((size_t)n + 1, sizeof(int));
  A->rowind = malloc(2 * ((size_t)g->ptr[g->n] + 1) * 2 * sizeof(int));
  A->val = malloc(2 * ((size_t)g->ptr[g->n] + 1) * 2 * sizeof(double));
  int e = 0;
  for (int J = 0; J < g->n; J++) {
    /* the neighbour list sorted (grid lists are; radius lists are) */
    for (int c = 0; c < 2; c++) {
      const int deg = g->ptr[J + 1] - g->ptr[J];
      for (int t = g->ptr[J]; t < g->ptr[J + 1]; t++) {
        const int I = g->adj[t];
        for (int r = 0; r < 2; r++) {
          A->rowind[e] = 2 * I + r;
          double v = I == J ? (r == c ? deg + 1.0 : 0.25) : (r == c ? -1.0 : -0.1);
          A->val[e++] = v;
        }
      }
      A->colptr[2 * J + c + 1] = e;
    }
  }
  A->nnz = e;
  A->symmetric = 1;
}

static void sort_lists(graph *g) {
  for (int i = 0; i < g->n; i++) {
    int *l = g->adj + g->ptr[i], m = g->ptr[i + 1] - g->ptr[i];
    for (int a = 1; a < m; a++)
      for (int b = a; b > 0 && l[b - 1] > l[b]; b--) {
        const int t = l[b];
        l[b] = l[b - 1];
        l[b - 1] = t;
      }
  }
}

/* Entries of L and the solution error for one backend and order. */
static double factor_fill(const mpgm_solver_type *type, const mpgm_csc *A, const int *perm,
                          double *err) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_solver *s = NULL;
  double fill = -1;
  *err = INFINITY;
  if (mpgm_solver_create(&ctx, type, NULL, &s) == 0 && mpgm_solver_analyse(s, &ctx, A, perm) == 0 &&
      mpgm_solver_factor(s, &ctx, A) == 0) {
    /* x_true = (1, 2, 3, ...) / n; b = A x_true */
    const int n = A->n;
    double *xt = malloc((size_t)n * sizeof(double)), *b = calloc((size_t)n, sizeof(double));
    for (int i = 0; i < n; i++) xt[i] = (i + 1.0) / n;
    for (int j = 0; j < n; j++)
      for (int k = A->colptr[j]; k < A->colptr[j + 1]; k++) b[A->rowind[k]] += A->val[k] * xt[j];
    if (mpgm_solver_solve(s, &ctx, b, b) == 0) {
      *err = 0;
      for (int i = 0; i < n; i++) *err = fmax(*err, fabs(b[i] - xt[i]));
    }
    mpgm_solver_stats st;
    if (mpgm_solver_get_stats(s, &st) == 0) fill = st.nnz_factor;
    free(xt);
    free(b);
  }
  if (ctx.code) printf("  solver %s: %s\n", type->name, ctx.msg);
  mpgm_solver_destroy(&s);
  return fill;
}

/* Order g, check the permutation, and (when max_ratio > 0) compare the
 * fill with AMD's (at most max_ratio times) and the natural order's. */
static void check_graph(const char *name, graph *g, double max_ratio, double max_natural) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  int *perm = malloc(((size_t)g->n + 1) * sizeof(int));
  int err = mpgm_order_nodes(&ctx, g->n, g->ptr, g->adj, g->x, perm);
  mpgm_test(err == 0, "%s: ordering returns %d", name, err);
  mpgm_test(is_permutation(perm, g->n), "%s: a permutation of the %d nodes", name, g->n);
  if (g->n == 0 || max_ratio <= 0) {
    free(perm);
    return;
  }
  mpgm_csc A = {0};
  build_matrix(g, &A);
  int *dperm = malloc((size_t)A.n * sizeof(int)), *natural = malloc((size_t)A.n * sizeof(int));
  for (int k = 0; k < g->n; k++) {
    dperm[2 * k] = 2 * perm[k];
    dperm[2 * k + 1] = 2 * perm[k] + 1;
  }
  for (int k = 0; k < A.n; k++) natural[k] = k;
  double e_nd, e_amd, e_nat, e_lu;
  const mpgm_solver_type *chol = mpgm_solver_type_find("cholmod");
  const double f_nd = factor_fill(chol, &A, dperm, &e_nd);
  const double f_amd = factor_fill(chol, &A, NULL, &e_amd);
  const double f_nat = factor_fill(chol, &A, natural, &e_nat);
  const double f_lu = factor_fill(mpgm_solver_type_find("umfpack"), &A, dperm, &e_lu);
  printf("  %-14s n = %5d  fill: nested dissection %8.0f, AMD %8.0f (%.2f), natural %9.0f "
         "(%.2f)\n", name, A.n, f_nd, f_amd, f_nd / f_amd, f_nat, f_nd / f_nat);
  mpgm_test(e_nd <= 1e-10 && e_amd <= 1e-10 && e_lu <= 1e-10,
            "%s: solution with the given order (cholmod %.1e, umfpack %.1e; AMD %.1e)", name,
            e_nd, e_lu, e_amd);
  mpgm_test(f_nd > 0 && f_nd <= max_ratio * f_amd, "%s: fill %.0f <= %.2f x AMD's %.0f", name,
            f_nd, max_ratio, f_amd);
  /* UMFPACK with the order given uses it for rows and columns alike (its
   * symmetric strategy): L + U then hold about twice the entries of L */
  mpgm_test(f_lu > 0 && f_lu <= 2.05 * f_nd, "%s: umfpack L + U %.0f <= 2.05 x cholmod's L %.0f",
            name, f_lu, f_nd);
  mpgm_test(f_nd <= max_natural * f_nat, "%s: fill %.0f <= %.2f x the natural order's %.0f", name,
            f_nd, max_natural, f_nat);
  free(dperm);
  free(natural);
  free(A.colptr);
  free(A.rowind);
  free(A.val);
  free(perm);
}

int main(void) {
  graph g = {0};
  /* square grids: nested dissection is the optimal order class here */
  graph_grid(&g, 80, 80, 0, NULL);
  check_graph("Q4 grid 80^2", &g, 1.0, 0.5);
  graph_free(&g);
  graph_grid(&g, 80, 80, 1, NULL);
  check_graph("T3 grid 80^2", &g, 1.0, 0.5);
  graph_free(&g);
  /* a disk of grid nodes (the MPM rolling disk's shape) */
  graph_grid(&g, 61, 61, 1, in_disk);
  check_graph("T3 disk", &g, 1.05, 0.5);
  graph_free(&g);
  /* a strip 8 nodes high: AMD is near-banded and hard to beat */
  graph_grid(&g, 200, 8, 0, NULL);
  check_graph("Q4 strip", &g, 1.4, 1.0);
  graph_free(&g);
  /* random points with radius neighbours (node clouds): straight cuts
   * through an irregular graph give wider separators than AMD's implicit
   * ones (measured 1.33 x AMD's fill) */
  rng r = {.s = 12345};
  g.n = 1500;
  g.x = malloc(2 * (size_t)g.n * sizeof(double));
  for (int i = 0; i < 2 * g.n; i++) g.x[i] = uniform(&r, 0.0, 1.0);
  graph_radius(&g, 0.06);
  sort_lists(&g);
  check_graph("random cloud", &g, 1.4, 0.5);
  graph_free(&g);
  /* degenerate coordinates: all on one vertical line (a path graph, which
   * the natural order factorises without fill; dissection adds about one
   * entry per node and level: measured 1.54 x), all at one point */
  g.n = 300;
  g.x = malloc(2 * (size_t)g.n * sizeof(double));
  for (int i = 0; i < g.n; i++) {
    g.x[2 * i] = 1.0;
    g.x[2 * i + 1] = i;
  }
  graph_radius(&g, 1.5);
  check_graph("line", &g, 1.6, 1.6);
  for (int i = 0; i < 2 * g.n; i++) g.x[i] = 0.5;
  check_graph("duplicates", &g, 0, 0);
  graph_free(&g);
  /* one node, none */
  int ptr1[2] = {0, 1}, adj1[1] = {0}, perm1[1] = {-1};
  double x1[2] = {0, 0};
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_test(mpgm_order_nodes(&ctx, 1, ptr1, adj1, x1, perm1) == 0 && perm1[0] == 0, "one node");
  mpgm_test(mpgm_order_nodes(&ctx, 0, ptr1, adj1, x1, perm1) == 0, "no node");
  return mpgm_test_summary();
}
