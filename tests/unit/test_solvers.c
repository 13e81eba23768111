/* test_solvers.c -- conformance suite run over every linear solver backend
 * in mpgm_solver_types(): no per-backend code, one check per line.
 *
 * Matrices are 5-point stencils on an nx x ny grid stored with the full
 * pattern (both triangles, sorted rows), as the core stores its tangent:
 *   A(r,c) = s (w(r,c) + conv sgn(c - r))  for grid neighbours r, c,
 *   A(c,c) = s (shift + sum_q |w(c,q)|),   w(r,c) = -(1 + 0.3 sin(0.7 (r+c)))
 * so conv = 0 gives a symmetric matrix, SPD for shift > 0 and indefinite
 * for a negative shift well inside the spectrum (about [shift, shift + 8]).
 *
 * Checks: known SPD system (residual and error), refactorisation with new
 * values and no new analysis (ctx counters), in-place solve, statistics,
 * a new pattern, an unsymmetric system (needs_spd = 0), an indefinite
 * symmetric system (MPGM_ERR_SINGULAR for SPD-only backends, followed by a
 * successful refactorisation; solved otherwise), zero and structurally
 * singular matrices (MPGM_ERR_SINGULAR), a given elimination order, misuse
 * and NULL destroys.
 *
 * Iterative backends (type->iterative) are held to their tolerance
 * (ITER_BE, ITER_FE) instead of round-off; on the indefinite matrices they
 * may fail to converge, with the recoverable MPGM_ERR_LINEAR and a
 * message; check_iterative tests their options.
 *
 * A backend with presets (type->presets: PETSc's KSP and PC choices) runs
 * the suite once with its default options and once per preset, named
 * "backend:preset"; a preset for symmetric positive definite matrices
 * only (spd_only) skips the unsymmetric system.
 */
#include "mpgm_blob.h"
#include "mpgm_solver.h"
#include "mpgm_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SCALE 2.385e3 /* high-entropy magnitude of the entries */

/* The configuration under test: the backend's default options or one of
 * its presets. */
static struct {
  char name[64];         /* "backend" or "backend:preset" */
  mpgm_solver_opts opts; /* what every instance is created with */
  int spd_only;          /* the preset's spd_only */
  int iterative;         /* held to a tolerance: the type says, unless the
                            preset is direct */
} cur;

/* ---- test matrices ------------------------------------------------------ */
static double weight(int r, int c) { return -(1.0 + 0.3 * sin(0.7 * (r + c))); }

/* Grid neighbours of node c in increasing order (the rows of column c
 * besides c itself); returns their number. Node `hole` (or -1) is absent:
 * it has no neighbours and is no one's neighbour. */
static int neighbours(int nx, int ny, int c, int hole, int q[4]) {
  int cx = c % nx, cy = c / nx, m = 0;
  if (c == hole) return 0;
  if (cy > 0) q[m++] = c - nx;
  if (cx > 0) q[m++] = c - 1;
  if (cx < nx - 1) q[m++] = c + 1;
  if (cy < ny - 1) q[m++] = c + nx;
  int k = 0;
  for (int i = 0; i < m; i++)
    if (q[i] != hole) q[k++] = q[i];
  return k;
}

/* Allocate and fill A (see the file comment). Returns 0 or -1 (no memory). */
static int build(int nx, int ny, int hole, double shift, double conv,
                 double s, mpgm_csc *A) {
  const int n = nx * ny;
  A->n = n;
  A->colptr = malloc(((size_t)n + 1) * sizeof(int));
  A->rowind = malloc(5 * (size_t)n * sizeof(int));
  A->val = malloc(5 * (size_t)n * sizeof(double));
  if (!A->colptr || !A->rowind || !A->val) return -1;
  int k = 0;
  for (int c = 0; c < n; c++) {
    int q[4], m = neighbours(nx, ny, c, hole, q);
    double diag = shift;
    for (int i = 0; i < m; i++) diag += fabs(weight(c, q[i]));
    A->colptr[c] = k;
    int i = 0;
    for (; i < m && q[i] < c; i++, k++) { /* rows above the diagonal */
      A->rowind[k] = q[i];
      A->val[k] = s * (weight(q[i], c) + conv);
    }
    if (c != hole) {
      A->rowind[k] = c;
      A->val[k++] = s * diag;
    }
    for (; i < m; i++, k++) {
      A->rowind[k] = q[i];
      A->val[k] = s * (weight(q[i], c) - conv);
    }
  }
  A->colptr[n] = k;
  A->nnz = k;
  A->symmetric = conv == 0.0;
  return 0;
}

static void release(mpgm_csc *A) {
  free(A->colptr);
  free(A->rowind);
  free(A->val);
  memset(A, 0, sizeof(*A));
}

/* y = A x */
static void matvec(const mpgm_csc *A, const double *x, double *y) {
  for (int i = 0; i < A->n; i++) y[i] = 0.0;
  for (int c = 0; c < A->n; c++)
    for (int k = A->colptr[c]; k < A->colptr[c + 1]; k++)
      y[A->rowind[k]] += A->val[k] * x[c];
}

/* max-row-sum norm */
static double norm_inf_A(const mpgm_csc *A) {
  double *rs = calloc((size_t)A->n, sizeof(double)), m = 0.0;
  if (!rs) return NAN;
  for (int k = 0; k < A->nnz; k++) rs[A->rowind[k]] += fabs(A->val[k]);
  for (int i = 0; i < A->n; i++) m = rs[i] > m ? rs[i] : m;
  free(rs);
  return m;
}

static double norm_inf(const double *v, int n) {
  double m = 0.0;
  for (int i = 0; i < n; i++) m = fabs(v[i]) > m ? fabs(v[i]) : m;
  return m;
}

/* Work vectors of one system with known solution xt and b = A xt. */
typedef struct vecs { double *xt, *b, *x, *r; } vecs;

static int vecs_alloc(int n, vecs *v) {
  v->xt = malloc((size_t)n * sizeof(double));
  v->b = malloc((size_t)n * sizeof(double));
  v->x = malloc((size_t)n * sizeof(double));
  v->r = malloc((size_t)n * sizeof(double));
  return (v->xt && v->b && v->x && v->r) ? 0 : -1;
}
static void vecs_free(vecs *v) {
  free(v->xt); free(v->b); free(v->x); free(v->r);
}
static void known_rhs(const mpgm_csc *A, vecs *v) {
  for (int i = 0; i < A->n; i++) v->xt[i] = 1.2345 + sin(0.37 * i) + 0.01 * i;
  matvec(A, v->xt, v->b);
}

/* Tolerances of an iterative backend, from its default options: the
 * backward error it guarantees is about opts.tol (10 tol allows for the
 * 2-norm of the stopping test against the infinity norms here), and the
 * forward error of these grids (condition numbers below 100) 1000 tol. */
#define ITER_BE (10.0 * mpgm_solver_opts_default().tol)
#define ITER_FE (1e3 * mpgm_solver_opts_default().tol)

/* Check a solution x of A x = b against xt: normwise backward error
 * ||b - A x|| / (||A|| ||x|| + ||b||) and forward error ||x - xt|| / ||xt||
 * (inf norms); an iterative backend to its tolerance (ITER_BE, ITER_FE). */
static void check_solution(const mpgm_solver_type *t, const char *what,
                           const mpgm_csc *A, vecs *v, double tol_err) {
  (void)t; /* the configuration under test (cur) decides */
  const char *name = cur.name;
  const double tol_be = cur.iterative ? ITER_BE : 1e-14;
  if (cur.iterative && tol_err < ITER_FE) tol_err = ITER_FE;
  const int n = A->n;
  matvec(A, v->x, v->r);
  for (int i = 0; i < n; i++) v->r[i] = v->b[i] - v->r[i];
  double be = norm_inf(v->r, n) /
              (norm_inf_A(A) * norm_inf(v->x, n) + norm_inf(v->b, n));
  for (int i = 0; i < n; i++) v->r[i] = v->x[i] - v->xt[i];
  double fe = norm_inf(v->r, n) / norm_inf(v->xt, n);
  mpgm_test_abs(be, 0.0, tol_be, "%s: %s: backward error", name, what);
  mpgm_test_abs(fe, 0.0, tol_err, "%s: %s: forward error", name, what);
}

/* ---- per-backend checks ------------------------------------------------- */

/* Known SPD system, refactorisation, in-place solve, stats, new pattern. */
static void check_spd(const mpgm_solver_type *t) {
  const char *nm = cur.name;
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0}, B = {0};
  vecs v = {0}, w = {0};
  mpgm_solver *s = NULL;
  if (build(17, 13, -1, 0.3817, 0.0, SCALE, &A) || vecs_alloc(A.n, &v) ||
      vecs_alloc(A.n, &w)) {
    mpgm_test(0, "%s: allocation", nm);
    goto done;
  }
  known_rhs(&A, &v);
  int ierr = mpgm_solver_create(&ctx, t, &cur.opts, &s);
  mpgm_test(ierr == 0 && s != NULL, "%s: create (%d)", nm, ierr);
  if (ierr) goto done;
  int e1 = mpgm_solver_analyse(s, &ctx, &A, NULL);
  int e2 = mpgm_solver_factor(s, &ctx, &A);
  int e3 = mpgm_solver_solve(s, &ctx, v.b, v.x);
  mpgm_test(e1 == 0 && e2 == 0 && e3 == 0,
            "%s: SPD 17x13: analyse, factor, solve return %d %d %d (%s)", nm,
            e1, e2, e3, ctx.msg);
  check_solution(t, "SPD 17x13", &A, &v, 1e-12);

  mpgm_solver_stats st;
  ierr = mpgm_solver_get_stats(s, &st);
  /* 0: not known, which only an iterative backend may say (hypre keeps
   * its hierarchy to itself) */
  mpgm_test(ierr == 0 && (st.nnz_factor >= A.n || (t->iterative && st.nnz_factor == 0.0)) &&
                st.flops >= 0.0,
            "%s: stats (%d): nnz(factor) = %g >= n = %d%s, flops = %g", nm, ierr,
            st.nnz_factor, A.n, t->iterative ? " or 0" : "", st.flops);
  /* at least the factors' values (8 bytes per entry) */
  mpgm_test(st.mem_peak >= 8.0 * st.nnz_factor && st.mem_peak < 1e9,
            "%s: stats: peak memory %g bytes >= 8 nnz(factor)", nm, st.mem_peak);
  mpgm_test(t->iterative ? st.iterations > 0 && ctx.count[MPGM_C_LINEAR_ITERATIONS] == st.iterations
                         : st.iterations == 0 && ctx.count[MPGM_C_LINEAR_ITERATIONS] == 0,
            "%s: stats: %d iterations, %ld counted in ctx (%s)", nm, st.iterations,
            ctx.count[MPGM_C_LINEAR_ITERATIONS], t->iterative ? "iterative" : "direct: none");

  /* new values, same pattern: factor again without a new analysis */
  if (build(17, 13, -1, 1.713, 0.0, 1.37 * SCALE, &B)) {
    mpgm_test(0, "%s: allocation", nm);
    goto done;
  }
  memcpy(A.val, B.val, (size_t)A.nnz * sizeof(double));
  known_rhs(&A, &w);
  e2 = mpgm_solver_factor(s, &ctx, &A);
  e3 = mpgm_solver_solve(s, &ctx, w.b, w.x);
  mpgm_test(e2 == 0 && e3 == 0, "%s: refactor, solve return %d %d", nm, e2, e3);
  check_solution(t, "SPD refactored", &A, &w, 1e-12);
  mpgm_test(ctx.count[MPGM_C_ANALYSES] == 1 && ctx.count[MPGM_C_FACTORIZATIONS] == 2 &&
                ctx.count[MPGM_C_SOLVES] == 2,
            "%s: counters: %ld analyses (1), %ld factorizations (2), %ld "
            "solves (2)", nm, ctx.count[MPGM_C_ANALYSES], ctx.count[MPGM_C_FACTORIZATIONS],
            ctx.count[MPGM_C_SOLVES]);
  mpgm_test(ctx.t[MPGM_T_ANALYSE] >= 0.0 && ctx.t[MPGM_T_FACTOR] > 0.0 &&
                ctx.t[MPGM_T_SOLVE] > 0.0,
            "%s: timers analyse %g, factor %g, solve %g s", nm,
            ctx.t[MPGM_T_ANALYSE], ctx.t[MPGM_T_FACTOR], ctx.t[MPGM_T_SOLVE]);

  /* in place: x and b alias */
  memcpy(w.x, w.b, (size_t)A.n * sizeof(double));
  e3 = mpgm_solver_solve(s, &ctx, w.x, w.x);
  mpgm_test(e3 == 0, "%s: in-place solve returns %d", nm, e3);
  check_solution(t, "in-place solve", &A, &w, 1e-12);

  /* a new pattern: analyse again on the same instance */
  release(&B);
  vecs_free(&w);
  memset(&w, 0, sizeof(w));
  if (build(11, 19, -1, 0.5273, 0.0, SCALE, &B) || vecs_alloc(B.n, &w)) {
    mpgm_test(0, "%s: allocation", nm);
    goto done;
  }
  known_rhs(&B, &w);
  e1 = mpgm_solver_analyse(s, &ctx, &B, NULL);
  e2 = mpgm_solver_factor(s, &ctx, &B);
  e3 = mpgm_solver_solve(s, &ctx, w.b, w.x);
  mpgm_test(e1 == 0 && e2 == 0 && e3 == 0 && ctx.count[MPGM_C_ANALYSES] == 2,
            "%s: new pattern 11x19: analyse, factor, solve return %d %d %d, "
            "%ld analyses (2)", nm, e1, e2, e3, ctx.count[MPGM_C_ANALYSES]);
  check_solution(t, "new pattern 11x19", &B, &w, 1e-12);
  mpgm_test(ctx.code == 0, "%s: no error recorded (%s)", nm, ctx.msg);

done:
  mpgm_solver_destroy(&s);
  mpgm_test(s == NULL, "%s: destroy nulls the pointer", nm);
  release(&A);
  release(&B);
  vecs_free(&v);
  vecs_free(&w);
}

/* One system on a fresh instance; returns the factor's code (solution
 * checked when it is 0). may_fail: an iterative backend may fail to
 * converge (MPGM_ERR_LINEAR, recorded with a message). */
static int solve_fresh(const mpgm_solver_type *t, const char *what,
                       const mpgm_csc *A, double tol_err, int may_fail, mpgm_ctx *ctx) {
  const char *nm = cur.name;
  mpgm_solver *s = NULL;
  vecs v = {0};
  int ef = -1000;
  if (vecs_alloc(A->n, &v)) {
    mpgm_test(0, "%s: allocation", nm);
    goto done;
  }
  known_rhs(A, &v);
  int ierr = mpgm_solver_create(ctx, t, &cur.opts, &s);
  if (ierr == 0) ierr = mpgm_solver_analyse(s, ctx, A, NULL);
  mpgm_test(ierr == 0, "%s: %s: create and analyse return %d", nm, what, ierr);
  if (ierr) goto done;
  ef = mpgm_solver_factor(s, ctx, A);
  if (ef == 0) {
    int es = mpgm_solver_solve(s, ctx, v.b, v.x);
    if (t->iterative && may_fail && es == MPGM_ERR_LINEAR) {
      mpgm_test(ctx->code == MPGM_ERR_LINEAR && ctx->msg[0] != '\0',
                "%s: %s: not converged, recoverable MPGM_ERR_LINEAR recorded (allowed for an "
                "iterative backend): %s", nm, what, ctx->msg);
    } else {
      mpgm_test(es == 0, "%s: %s: solve returns %d", nm, what, es);
      check_solution(t, what, A, &v, tol_err);
    }
  } else {
    /* no valid factorisation: solve must refuse, not crash */
    int es = mpgm_solver_solve(s, ctx, v.b, v.x);
    mpgm_test(es != 0, "%s: %s: solve after a failed factor refused (%d)", nm,
              what, es);
  }
done:
  mpgm_solver_destroy(&s);
  vecs_free(&v);
  return ef;
}

/* A matrix with a layout (mpgm_csc.layout): the grid's equations as the
 * free components of nodes of two, every third node's second component
 * fixed (no equation), so blocks have holes. Every backend solves it as
 * without the layout; PETSc's GAMG takes it in blocks of 2 (its stats
 * say so) and refuses a layout that numbers an equation twice; the
 * others leave the block size 0. */
static void check_layout(const mpgm_solver_type *t) {
  const char *nm = cur.name;
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0};
  int *dof = NULL;
  double *x = NULL;
  if (build(17, 13, -1, 0.3817, 0.0, SCALE, &A)) {
    mpgm_test(0, "%s: allocation", nm);
    return;
  }
  const int nnode = A.n; /* enough: the rest of the nodes fully fixed */
  dof = malloc(sizeof(int) * 2 * (size_t)nnode);
  x = malloc(sizeof(double) * 2 * (size_t)nnode);
  int e = 0;
  for (int v = 0; v < nnode; v++)
    for (int c = 0; c < 2; c++) {
      dof[2 * v + c] = e < A.n && !(c == 1 && v % 3 == 0) ? e++ : -1;
      x[2 * v + c] = c == 0 ? 0.1 * (v % 17) : 0.1 * (v / 17) + 0.01 * c;
    }
  mpgm_dof_layout L = {2, nnode, dof, x};
  A.layout = &L;
  solve_fresh(t, "with a layout", &A, 1e-10, 0, &ctx);
  const int gamg = strstr(cur.opts.petsc, "gamg") != NULL;
  mpgm_solver *s = NULL;
  mpgm_solver_stats st = {0};
  int err = mpgm_solver_create(&ctx, t, &cur.opts, &s);
  if (!err) err = mpgm_solver_analyse(s, &ctx, &A, NULL);
  if (!err) err = mpgm_solver_factor(s, &ctx, &A);
  if (!err && mpgm_solver_get_stats(s, &st) != 0) st.block_size = 0;
  mpgm_test(err == 0 && st.block_size == (gamg ? 2 : 0), "%s: block size %d with a layout "
            "(expected %d)", nm, st.block_size, gamg ? 2 : 0);
  mpgm_solver_destroy(&s);
  dof[2 * 2] = dof[0]; /* node 2's first component: equation 0 again */
  mpgm_err_clear(&ctx);
  err = mpgm_solver_create(&ctx, t, &cur.opts, &s);
  if (!err) err = mpgm_solver_analyse(s, &ctx, &A, NULL);
  mpgm_test(gamg ? err == MPGM_ERR_INTERNAL && strstr(ctx.msg, "twice") : err == 0,
            "%s: a layout numbering an equation twice: %d (%s)", nm, err, ctx.msg);
  mpgm_solver_destroy(&s);
  free(dof);
  free(x);
  release(&A);
}

/* Indefinite symmetric system: MPGM_ERR_SINGULAR for SPD-only backends,
 * solved (forward error <= tol_err) otherwise. */
static void check_indefinite(const mpgm_solver_type *t, int nx, int ny,
                             double tol_err) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0};
  char what[64];
  snprintf(what, sizeof(what), "indefinite %dx%d", nx, ny);
  if (build(nx, ny, -1, -3.1, 0.0, SCALE, &A) == 0) {
    int ef = solve_fresh(t, what, &A, tol_err, 1, &ctx);
    if (t->needs_spd)
      mpgm_test(ef == MPGM_ERR_SINGULAR && ctx.code == MPGM_ERR_SINGULAR &&
                    ctx.msg[0] != '\0',
                "%s: %s: MPGM_ERR_SINGULAR (%d) recorded: %s", cur.name, what,
                ef, ctx.msg);
    else
      mpgm_test(ef == 0, "%s: %s: factor returns %d (%s)", cur.name, what, ef,
                ctx.msg);
  }
  release(&A);
}

/* Factor indefinite values, then SPD values on the same instance (no new
 * analysis): the second factorisation and the solve must succeed. */
static void check_recovery(const mpgm_solver_type *t, int nx, int ny) {
  const char *nm = cur.name;
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0}, S = {0};
  mpgm_solver *s = NULL;
  vecs v = {0};
  char what[80];
  snprintf(what, sizeof(what), "%dx%d refactor after indefinite values", nx,
           ny);
  if (build(nx, ny, -1, -3.1, 0.0, SCALE, &A) == 0 &&
      build(nx, ny, -1, 0.3817, 0.0, SCALE, &S) == 0 &&
      vecs_alloc(S.n, &v) == 0 && mpgm_solver_create(&ctx, t, &cur.opts, &s) == 0 &&
      mpgm_solver_analyse(s, &ctx, &A, NULL) == 0) {
    mpgm_solver_factor(s, &ctx, &A); /* fails for SPD-only backends */
    mpgm_err_clear(&ctx);
    known_rhs(&S, &v);
    int ef = mpgm_solver_factor(s, &ctx, &S);
    int es = mpgm_solver_solve(s, &ctx, v.b, v.x);
    mpgm_test(ef == 0 && es == 0, "%s: %s: factor, solve %d %d", nm, what, ef,
              es);
    check_solution(t, what, &S, &v, 1e-12);
  } else {
    mpgm_test(0, "%s: %s: set-up (%s)", nm, what, ctx.msg);
  }
  mpgm_solver_destroy(&s);
  vecs_free(&v);
  release(&S);
  release(&A);
}

/* Unsymmetric, indefinite, zero and structurally singular matrices. */
static void check_hard(const mpgm_solver_type *t) {
  const char *nm = cur.name;
  mpgm_ctx ctx;
  mpgm_csc A = {0};

  if (!t->needs_spd && !cur.spd_only) { /* convection-diffusion, cell Peclet about 0.8 */
    mpgm_ctx_init(&ctx);
    if (build(17, 13, -1, 0.05, 0.8, SCALE, &A) == 0) {
      int ef = solve_fresh(t, "unsymmetric 17x13", &A, 1e-12, 0, &ctx);
      mpgm_test(ef == 0, "%s: unsymmetric 17x13: factor returns %d (%s)", nm,
                ef, ctx.msg);
    }
    release(&A);
  }

  /* indefinite symmetric (shift -3.1 inside the spectrum); the larger grid
   * makes CHOLMOD choose its supernodal factorisation */
  check_indefinite(t, 17, 13, 1e-10);
  check_indefinite(t, 100, 100, 1e-8);

  /* a larger SPD system (supernodal in CHOLMOD) */
  mpgm_ctx_init(&ctx);
  if (build(100, 100, -1, 0.3817, 0.0, SCALE, &A) == 0) {
    int ef = solve_fresh(t, "SPD 100x100", &A, 1e-12, 0, &ctx);
    mpgm_test(ef == 0, "%s: SPD 100x100: factor returns %d (%s)", nm, ef,
              ctx.msg);
  }
  release(&A);

  /* recovery after a failed factorisation (simplicial and supernodal) */
  check_recovery(t, 17, 13);
  check_recovery(t, 100, 100);

  /* zero values on the full pattern */
  mpgm_ctx_init(&ctx);
  if (build(17, 13, -1, 0.3817, 0.0, 0.0, &A) == 0) {
    int ef = solve_fresh(t, "zero matrix", &A, 1e-12, 0, &ctx);
    mpgm_test(ef == MPGM_ERR_SINGULAR && ctx.code == MPGM_ERR_SINGULAR,
              "%s: zero matrix: MPGM_ERR_SINGULAR (%d): %s", nm, ef, ctx.msg);
  }
  release(&A);

  /* structurally singular: node 100 has an empty row and column */
  mpgm_ctx_init(&ctx);
  if (build(17, 13, 100, 0.3817, 0.0, SCALE, &A) == 0) {
    int ef = solve_fresh(t, "structurally singular", &A, 1e-12, 0, &ctx);
    mpgm_test(ef == MPGM_ERR_SINGULAR && ctx.code == MPGM_ERR_SINGULAR,
              "%s: empty column: MPGM_ERR_SINGULAR (%d): %s", nm, ef, ctx.msg);
  }
  release(&A);
}

/* A non-singular unsymmetric matrix whose first elimination step leaves a
 * zero pivot: [1 1 0; 2 2 1; 0 1 1] (det -1). Direct backends pivot past
 * it; PETSc's default GMRES + ILU(0) shifts it (ILU(0) keeps the pattern,
 * which here is the whole of LU) and GMRES still converges: a tangent of
 * the column collapse had such a pivot and stopped the run. */
static void check_zero_pivot(const mpgm_solver_type *t) {
  static int colptr[] = {0, 2, 5, 7}, rowind[] = {0, 1, 0, 1, 2, 1, 2};
  static double val[] = {1, 2, 1, 2, 1, 1, 1};
  const mpgm_csc A = {3, 7, colptr, rowind, val, 0, NULL};
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  const int ef = solve_fresh(t, "zero pivot 3x3", &A, 1e-10, 0, &ctx);
  mpgm_test(ef == 0, "%s: zero pivot 3x3: factor returns %d (%s)", cur.name, ef, ctx.msg);
}

/* Iterative backends: the options are honoured. A short restart still
 * converges (over several cycles); an iteration cap too small fails with
 * the recoverable MPGM_ERR_LINEAR, a message, the iterations counted, and
 * the last iterate in x; options out of range are refused at create. */
static void check_iterative(const mpgm_solver_type *t) {
  const char *nm = cur.name;
  mpgm_ctx ctx;
  mpgm_csc A = {0};
  vecs v = {0};
  mpgm_solver *s = NULL;
  if (build(100, 100, -1, 0.3817, 0.0, SCALE, &A) || vecs_alloc(A.n, &v)) {
    mpgm_test(0, "%s: allocation", nm);
    goto done;
  }
  known_rhs(&A, &v);
  mpgm_solver_opts o = cur.opts;
  o.restart = 4;
  mpgm_ctx_init(&ctx);
  int e = mpgm_solver_create(&ctx, t, &o, &s);
  if (!e) e = mpgm_solver_analyse(s, &ctx, &A, NULL);
  if (!e) e = mpgm_solver_factor(s, &ctx, &A);
  if (!e) e = mpgm_solver_solve(s, &ctx, v.b, v.x);
  mpgm_solver_stats st = {0};
  mpgm_solver_get_stats(s, &st);
  mpgm_test(e == 0 && st.iterations > o.restart, "%s: restart %d: converges (%d), %d iterations "
            "(%s)", nm, o.restart, e, st.iterations, ctx.msg);
  if (!e) check_solution(t, "restart 4", &A, &v, 1e-12);
  mpgm_solver_destroy(&s);

  o = cur.opts;
  o.max_iter = 3;
  mpgm_ctx_init(&ctx);
  e = mpgm_solver_create(&ctx, t, &o, &s);
  if (!e) e = mpgm_solver_analyse(s, &ctx, &A, NULL);
  if (!e) e = mpgm_solver_factor(s, &ctx, &A);
  for (int i = 0; i < A.n; i++) v.x[i] = NAN;
  if (!e) e = mpgm_solver_solve(s, &ctx, v.b, v.x);
  mpgm_solver_get_stats(s, &st);
  int finite = 1;
  for (int i = 0; i < A.n; i++) finite &= isfinite(v.x[i]) != 0;
  mpgm_test(e == MPGM_ERR_LINEAR && ctx.code == MPGM_ERR_LINEAR && strstr(ctx.msg, "3 iterations") &&
                st.iterations == 3 && ctx.count[MPGM_C_LINEAR_ITERATIONS] == 3 && finite,
            "%s: max_iter 3: MPGM_ERR_LINEAR (%d) after %d iterations (%ld counted), last iterate "
            "in x: %s", nm, e, st.iterations, ctx.count[MPGM_C_LINEAR_ITERATIONS], ctx.msg);
  mpgm_solver_destroy(&s);

  o = cur.opts;
  o.tol = 0.0;
  mpgm_ctx_init(&ctx);
  e = mpgm_solver_create(&ctx, t, &o, &s);
  mpgm_test(e == MPGM_ERR_INPUT && s == NULL, "%s: tol 0 refused (%d): %s", nm, e, ctx.msg);
done:
  mpgm_solver_destroy(&s);
  vecs_free(&v);
  release(&A);
}

/* A given elimination order (solver.ordering geometric hands one to
 * analyse): the solution is the same. The order is a deterministic
 * shuffle: odd equations backwards, then even ones forwards. */
static void check_given_order(const mpgm_solver_type *t) {
  const char *nm = cur.name;
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0};
  vecs v = {0};
  mpgm_solver *s = NULL;
  int *perm = NULL;
  const double conv = t->needs_spd || cur.spd_only ? 0.0 : 0.3;
  if (build(23, 11, -1, 0.3817, conv, SCALE, &A) || vecs_alloc(A.n, &v) ||
      !(perm = malloc((size_t)A.n * sizeof(int)))) {
    mpgm_test(0, "%s: allocation", nm);
    goto done;
  }
  int k = 0;
  for (int i = (A.n - 1) % 2 ? A.n - 1 : A.n - 2; i >= 0; i -= 2) perm[k++] = i;
  for (int i = 0; i < A.n; i += 2) perm[k++] = i;
  known_rhs(&A, &v);
  int e = mpgm_solver_create(&ctx, t, &cur.opts, &s);
  if (!e) e = mpgm_solver_analyse(s, &ctx, &A, perm);
  if (!e) e = mpgm_solver_factor(s, &ctx, &A);
  if (!e) e = mpgm_solver_solve(s, &ctx, v.b, v.x);
  mpgm_test(e == 0 && k == A.n, "%s: given order, %s 23x11: analyse, factor, solve return %d (%s)",
            nm, conv ? "unsymmetric" : "SPD", e, ctx.msg);
  if (!e) check_solution(t, "given order", &A, &v, 1e-12);
done:
  mpgm_solver_destroy(&s);
  free(perm);
  vecs_free(&v);
  release(&A);
}

/* Misuse through the wrappers and NULL destroys. */
/* A checkpoint of "auto" whose part in use is a Cholesky it says it does
 * not have (a fuzzed file: scripts/fuzz found it) is refused, and the
 * solver keeps a part its name can be read from. The section's layout is
 * auto.c's auto_state. */
static void check_auto_restore(void) {
  const struct {
    int on_lu, has_chol, hold, hold_len;
    long switches, lu_steps;
  } st = {0, 0, 0, 0, 0, 0};
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_solver_opts o = mpgm_solver_opts_default();
  mpgm_solver *s = NULL;
  mpgm_blob b = {0};
  const mpgm_solver_type *t = mpgm_solver_type_find("auto");
  int e = t ? mpgm_solver_create(&ctx, t, &o, &s) : MPGM_ERR_INTERNAL;
  char name[MPGM_BLOB_TAG] = "auto";
  if (!e) e = mpgm_blob_put(&ctx, &b, "solver", name, sizeof name);
  if (!e) e = mpgm_blob_put(&ctx, &b, "solver.auto", &st, sizeof st);
  mpgm_test(e == 0, "auto: a checkpoint section made (%d)", e);
  if (!e) {
    e = mpgm_solver_restore(s, &ctx, &b);
    mpgm_test(e == MPGM_ERR_INPUT && strstr(ctx.msg, "Cholesky in use but absent"),
              "auto: Cholesky in use but absent is refused (%s)", ctx.msg);
    const char *nm = mpgm_solver_name(s);
    mpgm_test(nm && nm[0], "auto: still named after the refusal (%s)", nm ? nm : "NULL");
  }
  mpgm_blob_free(&b);
  mpgm_solver_destroy(&s);
}

static void check_misuse(const mpgm_solver_type *t) {
  const char *nm = cur.name;
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0};
  mpgm_solver *s = NULL;
  double b[4] = {1, 2, 3, 4}, x[4];
  t->destroy(NULL);
  mpgm_solver_destroy(NULL);
  mpgm_solver_destroy(&s);
  mpgm_test(s == NULL, "%s: destroy(NULL) accepted", nm);
  if (build(2, 2, -1, 0.3817, 0.0, SCALE, &A) == 0 &&
      mpgm_solver_create(&ctx, t, &cur.opts, &s) == 0) {
    int ef = mpgm_solver_factor(s, &ctx, &A);
    mpgm_test(ef == MPGM_ERR_INTERNAL, "%s: factor before analyse refused (%d)",
              nm, ef);
    mpgm_err_clear(&ctx);
    int ea = mpgm_solver_analyse(s, &ctx, &A, NULL);
    int es = mpgm_solver_solve(s, &ctx, b, x);
    mpgm_test(ea == 0 && es != 0, "%s: solve before factor refused (%d)", nm,
              es);
  } else {
    mpgm_test(0, "%s: misuse set-up", nm);
  }
  mpgm_solver_destroy(&s); /* analysed, never factorised */
  mpgm_test(s == NULL, "%s: destroy of an unfactorised instance", nm);
  release(&A);
}

/* ---- a backend without optional operations ------------------------------ */
static int bare_create(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  (void)ctx;
  (void)opts;
  *data = NULL;
  return 0;
}
static void bare_destroy(void *data) { (void)data; }
static const mpgm_solver_type bare = {.name = "bare", .doc = "no operations",
                                      .create = bare_create,
                                      .destroy = bare_destroy};

static void check_wrappers(void) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_solver *s = NULL;
  mpgm_csc A = {0};
  mpgm_solver_stats st;
  int ierr = mpgm_solver_create(&ctx, &bare, NULL, &s);
  mpgm_test(ierr == 0 && s, "bare backend: create (%d)", ierr);
  if (!ierr && build(2, 2, -1, 1.0, 0.0, 1.0, &A) == 0) {
    ierr = mpgm_solver_analyse(s, &ctx, &A, NULL);
    mpgm_test(ierr == MPGM_ERR_UNSUPPORTED && ctx.code == MPGM_ERR_UNSUPPORTED,
              "missing analyse: MPGM_ERR_UNSUPPORTED recorded (%s)", ctx.msg);
    ierr = mpgm_solver_get_stats(s, &st);
    mpgm_test(ierr == MPGM_ERR_UNSUPPORTED, "missing stats: %d", ierr);
  }
  mpgm_solver_destroy(&s);
  release(&A);
}

/* The composite "auto" on symmetric matrices: a matrix Cholesky refuses is
 * factorised by LU, which is then held for 1, 2, 4, ... steps; Cholesky is
 * tried again when a hold runs out (the factorisation held is then not the
 * one solve would use), and a success resets the hold. */
static void check_auto_holds(void) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0}, S = {0};
  mpgm_solver *s = NULL;
  mpgm_solver_stats st;
  vecs v = {0};
  int kept[6], e[8];
  const mpgm_solver_type *t = mpgm_solver_type_find("auto");
  if (!t || build(9, 7, -1, -3.1, 0.0, SCALE, &A) || build(9, 7, -1, 0.3817, 0.0, SCALE, &S) ||
      vecs_alloc(S.n, &v) || mpgm_solver_create(&ctx, t, &cur.opts, &s) ||
      mpgm_solver_analyse(s, &ctx, &A, NULL)) {
    mpgm_test(0, "auto holds: set-up (%s)", ctx.msg);
    goto done;
  }
  mpgm_test(strcmp(mpgm_solver_name(s), "cholmod") == 0, "auto: reports as %s (cholmod)",
            mpgm_solver_name(s));
  /* step 1: Cholesky refuses A, LU solves it (hold 1) */
  e[0] = mpgm_solver_step(s, &ctx, &kept[0]);
  e[1] = mpgm_solver_factor(s, &ctx, &A);
  known_rhs(&A, &v);
  e[2] = mpgm_solver_solve(s, &ctx, v.b, v.x);
  mpgm_solver_get_stats(s, &st);
  mpgm_test(!e[0] && kept[0] && !e[1] && !e[2] && ctx.code == 0 && st.switches == 1 &&
                st.fallback_steps == 1 && mpgm_solver_part(s)->type == mpgm_solver_type_find("umfpack"),
            "auto: indefinite A on LU after Cholesky refused it (%d %d %d, switches %ld, LU steps "
            "%ld, no error left: %s)", e[0], e[1], e[2], st.switches, st.fallback_steps, ctx.msg);
  check_solution(t, "indefinite on LU", &A, &v, 1e-12);
  /* step 2: the hold of 1 has run out: Cholesky again, refuses, hold 2 */
  mpgm_solver_step(s, &ctx, &kept[1]);
  mpgm_solver_factor(s, &ctx, &A);
  /* steps 3 and 4: the first stays on LU (counted), the second tries
   * Cholesky on the SPD S, which resets the hold */
  mpgm_solver_step(s, &ctx, &kept[2]);
  mpgm_solver_get_stats(s, &st);
  const long sw3 = st.switches, lu3 = st.fallback_steps;
  mpgm_solver_step(s, &ctx, &kept[3]);
  e[3] = mpgm_solver_factor(s, &ctx, &S);
  /* step 5: A again: a hold of 1, not 4 */
  mpgm_solver_step(s, &ctx, &kept[4]);
  e[4] = mpgm_solver_factor(s, &ctx, &A);
  mpgm_solver_step(s, &ctx, &kept[5]);
  mpgm_solver_get_stats(s, &st);
  mpgm_test(!kept[1] && kept[2] && sw3 == 2 && lu3 == 3 && !kept[3] && !e[3] && kept[4] && !e[4] &&
                !kept[5] && st.switches == 3 && st.fallback_steps == 4,
            "auto: holds of 1 and 2 steps, reset by a Cholesky success (kept %d %d %d %d %d, "
            "switches %ld then %ld, LU steps %ld then %ld)", kept[1], kept[2], kept[3], kept[4],
            kept[5], sw3, st.switches, lu3, st.fallback_steps);
  mpgm_test(ctx.count[MPGM_C_ANALYSES] == 2 && ctx.count[MPGM_C_FACTORIZATIONS] == 7,
            "auto: the parts count, the composite does not: 2 analyses (Cholesky at the start, "
            "LU when first used; one pattern), 7 factorisations (3 refused by Cholesky) (got "
            "%ld, %ld)",
            ctx.count[MPGM_C_ANALYSES], ctx.count[MPGM_C_FACTORIZATIONS]);
done:
  mpgm_solver_destroy(&s);
  vecs_free(&v);
  release(&S);
  release(&A);
}

/* Newton-Krylov's composite (reuse) around a direct part: the first solve
 * factorises; new values keep the factorisation while GMRES converges
 * within refactor_iterations (counted in MPGM_C_FACTOR_REUSES), each
 * solve to its tolerance; values far from the factorised ones need more
 * iterations, and the next factor refactorises; a tighter tolerance
 * (mpgm_solver_tolerance) is met. */
static void check_reuse(const char *part) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0}, B = {0}, C = {0};
  vecs v = {0};
  mpgm_solver *s = NULL;
  mpgm_solver_opts o = mpgm_solver_opts_default();
  o.part = mpgm_solver_type_find(part);
  o.refactor_iterations = 8;
  o.tol = 1e-8;
  if (build(40, 30, -1, 0.3817, 0.0, SCALE, &A) || build(40, 30, -1, 0.40, 0.0, 1.01 * SCALE, &B) ||
      build(40, 30, -1, 3.0, 0.0, 0.2 * SCALE, &C) || vecs_alloc(A.n, &v) ||
      mpgm_solver_create(&ctx, &mpgm_solver_reuse, &o, &s)) {
    mpgm_test(0, "reuse(%s): set-up (%s)", part, ctx.msg);
    goto done;
  }
  const mpgm_csc *seq[] = {&A, &B, &B, &C, &C};
  const int n = (int)(sizeof seq / sizeof seq[0]);
  long fac[5], reu[5];
  int its[5], err[5];
  mpgm_solver_analyse(s, &ctx, &A, NULL);
  for (int k = 0; k < n; k++) {
    if (k == 2) mpgm_solver_tolerance(s, 1e-11);
    known_rhs(seq[k], &v);
    err[k] = mpgm_solver_factor(s, &ctx, seq[k]);
    if (!err[k]) err[k] = mpgm_solver_solve(s, &ctx, v.b, v.x);
    mpgm_solver_stats st;
    mpgm_solver_get_stats(s, &st);
    its[k] = st.iterations;
    fac[k] = ctx.count[MPGM_C_FACTORIZATIONS];
    reu[k] = ctx.count[MPGM_C_FACTOR_REUSES];
    matvec(seq[k], v.x, v.r);
    double rr = 0.0, bb = 0.0;
    for (int i = 0; i < A.n; i++) rr += (v.b[i] - v.r[i]) * (v.b[i] - v.r[i]), bb += v.b[i] * v.b[i];
    const double tol = k < 2 ? 1e-8 : 1e-11;
    mpgm_test(err[k] == 0 && sqrt(rr / bb) <= tol, "reuse(%s): system %d: solved (%d) to "
              "|b - A x| / |b| = %.2e <= %g in %d iterations (%s)", part, k, err[k], sqrt(rr / bb),
              tol, its[k], ctx.msg);
  }
  mpgm_test(fac[0] == 1 && its[0] <= 2 && reu[0] == 0,
            "reuse(%s): the first solve factorises and converges at once (%ld factorisation, %d "
            "iterations)", part, fac[0], its[0]);
  mpgm_test(fac[1] == 1 && reu[1] == 1 && its[1] > its[0] && its[1] <= 8,
            "reuse(%s): nearby values keep the factorisation (%ld reused, %d iterations)", part,
            reu[1], its[1]);
  mpgm_test(fac[3] + (its[3] > 8) >= 2 && fac[4] <= 3 && its[4] <= 2,
            "reuse(%s): far values: %d iterations, then a new factorisation (%ld in all) and %d "
            "iterations", part, its[3], fac[4], its[4]);
  mpgm_test(ctx.count[MPGM_C_SOLVES] == n && ctx.count[MPGM_C_ANALYSES] == 1,
            "reuse(%s): %ld solves counted (%d), %ld analyses (1)", part, ctx.count[MPGM_C_SOLVES], n,
            ctx.count[MPGM_C_ANALYSES]);
done:
  mpgm_solver_destroy(&s);
  vecs_free(&v);
  release(&A);
  release(&B);
  release(&C);
}

int main(void) {
  cur.opts = mpgm_solver_opts_default();
  const mpgm_solver_type *const *types = mpgm_solver_types();
  int ntypes = 0;
  while (types[ntypes]) ntypes++;
  mpgm_test(ntypes >= 2, "solver list holds %d backends", ntypes);
  mpgm_test(mpgm_solver_type_find("no_such_solver") == NULL &&
                mpgm_solver_type_find(NULL) == NULL,
            "unknown names are not found");
  check_wrappers();
  check_auto_holds();
  check_reuse("cholmod");
  check_reuse("umfpack");
  check_reuse("auto");
  for (int i = 0; types[i]; i++) {
    const mpgm_solver_type *t = types[i];
    mpgm_test(mpgm_solver_type_find(t->name) == t, "%s: found by name",
              t->name);
    char why[512];
    if (!mpgm_solver_usable(t->name, why, sizeof why)) {
      mpgm_test(0, "%s: usable (%s)", t->name, why);
      continue;
    }
    for (int k = -1; k < 0 || (t->presets && t->presets[k].name); k++) {
      cur.opts = mpgm_solver_opts_default();
      cur.spd_only = k >= 0 && t->presets[k].spd_only;
      cur.iterative = t->iterative && !(k >= 0 && t->presets[k].direct);
      snprintf(cur.name, sizeof cur.name, "%s%s%s", t->name, k >= 0 ? ":" : "",
               k >= 0 ? t->presets[k].name : "");
      if (k >= 0) snprintf(cur.opts.petsc, sizeof cur.opts.petsc, "%s", t->presets[k].options);
      check_spd(t);
      check_hard(t);
      if (k < 0 && !t->needs_spd) check_zero_pivot(t);
      check_given_order(t);
      check_layout(t);
      if (cur.iterative) check_iterative(t);
      check_misuse(t);
    }
  }
  check_auto_restore();
  return mpgm_test_summary();
}
