/* test_solver_fallback.c -- solver.linear_fallback (solvers/fallback.c):
 * an iterative backend (GMRES + ILU(0) of support_ilu_gmres.c, so the
 * test needs no PETSc)
 * whose failed solves go to a direct backend (umfpack).
 *
 * The direct part must give the direct backend's own answer to the bit
 * (the same matrix, the same right-hand side, also when b and x alias
 * and after the Krylov solve overwrote x); each matrix handed over is
 * counted once, with the Krylov failure still counted as such, and
 * logged as a warning; later solves with that factorisation stay on the
 * direct part; the next factor goes back to the iterative part; a
 * preconditioner that cannot be built (ILU(0)'s zero pivot) hands over at
 * factor; a matrix both refuse is the recoverable MPGM_ERR_SINGULAR, and
 * no solve is then made with older factors; a new pattern is analysed
 * again by the direct part; the composite refuses parts of the wrong
 * kinds. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_solver.h"
#include "mpgm_test.h"

extern const mpgm_solver_type test_solver_ilu_gmres; /* support_ilu_gmres.c */
extern const mpgm_solver_type mpgm_solver_umfpack;

/* The 5-point matrix of a convection-diffusion problem on an nx x ny grid:
 * unsymmetric, diagonally dominant, solvable by GMRES + ILU(0) in a few
 * tens of iterations (not in 3). */
static int convection(int nx, int ny, mpgm_csc *A) {
  const int n = nx * ny;
  memset(A, 0, sizeof *A);
  A->n = n;
  A->colptr = malloc(((size_t)n + 1) * sizeof(int));
  A->rowind = malloc(5 * (size_t)n * sizeof(int));
  A->val = malloc(5 * (size_t)n * sizeof(double));
  if (!A->colptr || !A->rowind || !A->val) return -1;
  int k = 0;
  for (int c = 0; c < n; c++) { /* column c: rows c - nx, c - 1, c, c + 1, c + nx */
    const int cx = c % nx, rows[5] = {c - nx, cx > 0 ? c - 1 : -1, c, cx < nx - 1 ? c + 1 : -1,
                                      c + nx};
    const double v[5] = {-1.3, -1.2, 4.05 + 0.01 * (c % 7), -0.8, -0.7};
    A->colptr[c] = k;
    for (int i = 0; i < 5; i++)
      if (rows[i] >= 0 && rows[i] < n) A->rowind[k] = rows[i], A->val[k++] = v[i];
  }
  A->colptr[n] = A->nnz = k;
  return 0;
}

static void release(mpgm_csc *A) {
  free(A->colptr);
  free(A->rowind);
  free(A->val);
  memset(A, 0, sizeof *A);
}

/* x = A^-1 b by UMFPACK alone (the answer the fallback must give). */
static int direct(const mpgm_csc *A, const double *b, double *x) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_solver *s = NULL;
  int e = mpgm_solver_create(&ctx, &mpgm_solver_umfpack, NULL, &s);
  if (!e) e = mpgm_solver_analyse(s, &ctx, A, NULL);
  if (!e) e = mpgm_solver_factor(s, &ctx, A);
  if (!e) e = mpgm_solver_solve(s, &ctx, b, x);
  mpgm_solver_destroy(&s);
  return e;
}

static int warnings;
static char last_warning[1024];
static void logger(void *user, int level, const char *msg) {
  (void)user;
  if (level != MPGM_LOG_WARNING) return;
  warnings++;
  strncpy(last_warning, msg, sizeof last_warning - 1);
}

static mpgm_solver_opts opts_with(const mpgm_solver_type *part, const mpgm_solver_type *fb) {
  mpgm_solver_opts o = mpgm_solver_opts_default();
  o.symmetric = 0;
  o.max_iter = 3; /* too few for the convection matrix: every solve fails */
  o.part = part;
  o.fallback = fb;
  return o;
}

static int same(const double *a, const double *b, int n) {
  return memcmp(a, b, (size_t)n * sizeof(double)) == 0;
}

/* |b - A x| / |b| */
static double residual(const mpgm_csc *A, const double *b, const double *x) {
  double rr = 0.0, bb = 0.0;
  double *r = calloc((size_t)A->n, sizeof(double));
  if (!r) return INFINITY;
  for (int c = 0; c < A->n; c++)
    for (int k = A->colptr[c]; k < A->colptr[c + 1]; k++) r[A->rowind[k]] += A->val[k] * x[c];
  for (int i = 0; i < A->n; i++) rr += (b[i] - r[i]) * (b[i] - r[i]), bb += b[i] * b[i];
  free(r);
  return sqrt(rr / bb);
}

/* Solves that fail hand the matrix over; then the same factorisation
 * stays direct; the next factor tries Krylov again. */
static void check_solves(void) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_ctx_set_logger(&ctx, logger, NULL, MPGM_LOG_WARNING);
  mpgm_csc A = {0};
  mpgm_solver *s = NULL;
  const mpgm_solver_opts o = opts_with(&test_solver_ilu_gmres, &mpgm_solver_umfpack);
  double *b = NULL, *x = NULL, *ref = NULL;
  if (convection(30, 30, &A) || !(b = malloc(900 * sizeof(double))) ||
      !(x = malloc(900 * sizeof(double))) || !(ref = malloc(900 * sizeof(double))) ||
      mpgm_solver_create(&ctx, &mpgm_solver_fallback, &o, &s)) {
    mpgm_test(0, "fallback: set-up (%s)", ctx.msg);
    goto done;
  }
  for (int i = 0; i < A.n; i++) b[i] = sin(0.37 * i) + 0.1;
  direct(&A, b, ref);
  memcpy(x, b, 900 * sizeof(double));
  int e = mpgm_solver_analyse(s, &ctx, &A, NULL);
  if (!e) e = mpgm_solver_factor(s, &ctx, &A);
  if (!e) e = mpgm_solver_solve(s, &ctx, x, x); /* b and x alias */
  mpgm_test(e == 0 && ctx.code == 0 && same(x, ref, A.n),
            "fallback: a Krylov solve stopped at 3 iterations is solved by umfpack, to umfpack's "
            "bits, with b and x aliased (%d; %s)", e, ctx.msg);
  mpgm_test(ctx.count[MPGM_C_LINEAR_FALLBACKS] == 1 && ctx.count[MPGM_C_LINEAR_NOT_CONVERGED] == 1 &&
                ctx.count[MPGM_C_LINEAR_ITERATIONS] == 3,
            "fallback: one matrix handed over (%ld), the failed Krylov solve counted (%ld, %ld "
            "iterations)", ctx.count[MPGM_C_LINEAR_FALLBACKS],
            ctx.count[MPGM_C_LINEAR_NOT_CONVERGED], ctx.count[MPGM_C_LINEAR_ITERATIONS]);
  mpgm_test(warnings == 1 && strstr(last_warning, "3 iterations") &&
                strstr(last_warning, "umfpack factorises"),
            "fallback: one warning, with GMRES's reason and the fallback: \"%s\"", last_warning);
  /* another right-hand side, the same factorisation: straight to umfpack */
  for (int i = 0; i < A.n; i++) b[i] = cos(0.11 * i);
  direct(&A, b, ref);
  e = mpgm_solver_solve(s, &ctx, b, x);
  mpgm_test(e == 0 && same(x, ref, A.n) && ctx.count[MPGM_C_LINEAR_FALLBACKS] == 1 &&
                ctx.count[MPGM_C_LINEAR_NOT_CONVERGED] == 1 && ctx.count[MPGM_C_LINEAR_ITERATIONS] == 3,
            "fallback: a second solve with that factorisation goes to umfpack without a Krylov "
            "try (%d; %ld handed over, %ld iterations)", e, ctx.count[MPGM_C_LINEAR_FALLBACKS],
            ctx.count[MPGM_C_LINEAR_ITERATIONS]);
  /* a new factor goes back to GMRES: with a loose tolerance it succeeds */
  e = mpgm_solver_factor(s, &ctx, &A);
  if (!e) e = mpgm_solver_tolerance(s, 0.9);
  if (!e) e = mpgm_solver_solve(s, &ctx, b, x);
  mpgm_test(e == 0 && residual(&A, b, x) <= 0.9 && ctx.count[MPGM_C_LINEAR_FALLBACKS] == 1 &&
                ctx.count[MPGM_C_LINEAR_ITERATIONS] > 3,
            "fallback: the next factor is GMRES's again (tolerance 0.9: converged, |r|/|b| = %.3f, "
            "%ld handed over)", residual(&A, b, x), ctx.count[MPGM_C_LINEAR_FALLBACKS]);
  /* several right-hand sides through solve_many, after a hand-over */
  e = mpgm_solver_tolerance(s, 1e-10);
  if (!e) e = mpgm_solver_factor(s, &ctx, &A);
  double *B = calloc(2 * 900, sizeof(double)), *R = calloc(2 * 900, sizeof(double));
  if (B && R) {
    for (int i = 0; i < 2 * A.n; i++) B[i] = sin(0.01 * i * i);
    direct(&A, B, R);
    direct(&A, B + A.n, R + A.n);
    if (!e) e = mpgm_solver_solve_many(s, &ctx, A.n, 2, B, B);
    mpgm_test(e == 0 && same(B, R, 2 * A.n) && ctx.count[MPGM_C_LINEAR_FALLBACKS] == 2,
              "fallback: two right-hand sides at once, aliased: umfpack's bits (%d; %ld handed "
              "over)", e, ctx.count[MPGM_C_LINEAR_FALLBACKS]);
    /* again with that factorisation: the direct part's own solve_many */
    for (int i = 0; i < 2 * A.n; i++) B[i] = cos(0.02 * i);
    direct(&A, B, R);
    direct(&A, B + A.n, R + A.n);
    const long its = ctx.count[MPGM_C_LINEAR_ITERATIONS];
    if (!e) e = mpgm_solver_solve_many(s, &ctx, A.n, 2, B, B);
    mpgm_test(e == 0 && same(B, R, 2 * A.n) && ctx.count[MPGM_C_LINEAR_FALLBACKS] == 2 &&
                  ctx.count[MPGM_C_LINEAR_ITERATIONS] == its,
              "fallback: two more right-hand sides with that factorisation go to umfpack at once, "
              "no Krylov try (%d; %ld handed over)", e, ctx.count[MPGM_C_LINEAR_FALLBACKS]);
  }
  free(B);
  free(R);
done:
  mpgm_solver_destroy(&s);
  free(b);
  free(x);
  free(ref);
  release(&A);
}

/* 3 x 3 with ILU(0)'s second pivot zero (A = [1 1 0; 2 2 1; 0 1 1], det -1):
 * the preconditioner cannot be built, and factor hands A over at once. A
 * singular 2 x 2 ([1 1; 1 1]) is refused by both parts. */
static void check_factor(void) {
  static int cp3[] = {0, 2, 5, 7}, ri3[] = {0, 1, 0, 1, 2, 1, 2};
  static double v3[] = {1, 2, 1, 2, 1, 1, 1};
  static int cp2[] = {0, 2, 4}, ri2[] = {0, 1, 0, 1};
  static double v2[] = {1, 1, 1, 1};
  const mpgm_csc A = {3, 7, cp3, ri3, v3, 0, NULL}, S = {2, 4, cp2, ri2, v2, 0, NULL};
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_solver *s = NULL;
  const mpgm_solver_opts o = opts_with(&test_solver_ilu_gmres, &mpgm_solver_umfpack);
  double b[3] = {1, 2, 3}, x[3], ref[3];
  direct(&A, b, ref);
  int e = mpgm_solver_create(&ctx, &mpgm_solver_fallback, &o, &s);
  if (!e) e = mpgm_solver_analyse(s, &ctx, &A, NULL);
  if (!e) e = mpgm_solver_factor(s, &ctx, &A);
  const long fb = ctx.count[MPGM_C_LINEAR_FALLBACKS];
  if (!e) e = mpgm_solver_solve(s, &ctx, b, x);
  mpgm_test(e == 0 && fb == 1 && same(x, ref, 3) && ctx.count[MPGM_C_LINEAR_NOT_CONVERGED] == 0,
            "fallback: ILU(0)'s zero pivot hands the matrix over at factor (%ld), umfpack's "
            "bits: x = (%g, %g, %g) (%d; %s)", fb, x[0], x[1], x[2], e, ctx.msg);
  /* a new pattern (order 2): the direct part analyses it again */
  e = mpgm_solver_analyse(s, &ctx, &S, NULL);
  if (!e) e = mpgm_solver_factor(s, &ctx, &S);
  mpgm_test(e == MPGM_ERR_SINGULAR && ctx.code == MPGM_ERR_SINGULAR && ctx.msg[0] &&
                ctx.count[MPGM_C_LINEAR_FALLBACKS] == 2 && ctx.count[MPGM_C_ANALYSES] == 4,
            "fallback: a singular matrix is refused by both parts: MPGM_ERR_SINGULAR (%d), "
            "recoverable, \"%s\"; %ld analyses (4: each part, each pattern)", e, ctx.msg,
            ctx.count[MPGM_C_ANALYSES]);
  /* neither part holds its factorisation: no solve with older factors */
  double c[2] = {1, 1}, y[2] = {0, 0};
  mpgm_ctx_init(&ctx);
  e = mpgm_solver_solve(s, &ctx, c, y);
  mpgm_test(e == MPGM_ERR_INTERNAL && y[0] == 0.0 && y[1] == 0.0,
            "fallback: a solve after both parts refused the matrix is refused (%d: %s), not made "
            "with the 3 x 3's factors", e, ctx.msg);
  mpgm_solver_destroy(&s);
}

/* The composite takes an iterative part and a direct fallback only. */
static void check_refusals(void) {
  const struct {
    const mpgm_solver_type *part, *fb;
    const char *what;
  } bad[] = {{&mpgm_solver_umfpack, &mpgm_solver_umfpack, "a direct part"},
             {&test_solver_ilu_gmres, &test_solver_ilu_gmres, "an iterative fallback"},
             {&test_solver_ilu_gmres, NULL, "no fallback"},
             {NULL, &mpgm_solver_umfpack, "no part"}};
  for (int i = 0; i < 4; i++) {
    mpgm_ctx ctx;
    mpgm_ctx_init(&ctx);
    mpgm_solver *s = NULL;
    const mpgm_solver_opts o = opts_with(bad[i].part, bad[i].fb);
    const int e = mpgm_solver_create(&ctx, &mpgm_solver_fallback, &o, &s);
    mpgm_test(e == MPGM_ERR_INPUT && s == NULL && strstr(ctx.msg, "linear_fallback"),
              "fallback: %s refused (%d): %s", bad[i].what, e, ctx.msg);
    mpgm_solver_destroy(&s);
  }
}

int main(void) {
  check_solves();
  check_factor();
  check_refusals();
  return mpgm_test_summary();
}
