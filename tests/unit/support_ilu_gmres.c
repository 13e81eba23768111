/* support_ilu_gmres.c -- restarted GMRES with an ILU(0) preconditioner, a
 * backend for the unit tests only: a small iterative backend that needs no
 * PETSc and reports a zero pivot of its preconditioner at factor, so that
 * test_solver_fallback can drive solvers/fallback.c through every way an
 * iterative part fails. Until issue 19 it was the scene backend
 * `solver.linear` "gmres"; PETSc's GMRES + ILU(0) replaced it there, being
 * faster on every system of bench/solvers that either converged on
 * (docs/benchmarks.md, "Sparse linear solvers").
 *
 * factor computes the incomplete LU factorisation of A on A's own pattern
 * (ILU(0): L unit lower triangular, U upper triangular, L + U - I with the
 * pattern of A, (L U)_ij = A_ij on that pattern); solve runs GMRES(m)
 * (solvers/krylov.c: right preconditioning, modified Gram-Schmidt, x_0 = 0)
 * until |b - A x| <= opts.tol |b| or fails (MPGM_ERR_LINEAR, recoverable)
 * after opts.max_iter iterations in all.
 *
 * The instance keeps its own copy of the pattern (analyse) and of the
 * factorised values (factor): GMRES multiplies by A in solve. A given
 * order is not used.
 */
#include "mpgm_krylov.h"
#include "mpgm_solver.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/** Instance data: pattern, values, ILU(0) factors, Krylov workspace. */
typedef struct gm_data {
  mpgm_solver_opts opts;       /**< tol, restart, max_iter                      */
  int n, nnz;                  /**< order, entries                              */
  int *Ap, *Ai;                /**< copy of the pattern (n + 1, nnz)             */
  double *Ax;                  /**< copy of the factorised values (nnz)          */
  int *diag;                   /**< position of A_jj in column j (n)             */
  int *mark;                   /**< ILU workspace: position of row i in the
                                    current column, -1 otherwise (n)             */
  double *lu;                  /**< ILU(0) factors on A's pattern: L below the
                                    diagonal (unit diagonal not stored), U on
                                    and above it (nnz)                           */
  double *rs;                  /**< row sums of |A| (n)                          */
  mpgm_gmres_ws ws;            /**< Krylov workspace                            */
  double anorm;                /**< |A| (infinity norm) of the factorised A    */
  int factored;                /**< 1 while lu holds the factors of Ax          */
  int iterations;              /**< iterations of the last solve                */
  double flops;                /**< flops of the last ILU(0) factorisation      */
  double mem;                  /**< bytes allocated for the current pattern     */
  double mem_peak;             /**< largest mem since the instance was created  */
} gm_data;

/* Allocate the instance; the options are copied. */
static int gm_create(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  gm_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *data = d;
  d->opts = *opts;
  return MPGM_OK;
}

/* Free the pattern-sized arrays. */
static void release(gm_data *d) {
  free(d->Ap);
  free(d->Ai);
  free(d->Ax);
  free(d->diag);
  free(d->mark);
  free(d->lu);
  free(d->rs);
  mpgm_gmres_ws_free(&d->ws);
  d->Ap = d->Ai = d->diag = d->mark = NULL;
  d->Ax = d->lu = d->rs = NULL;
  d->n = d->nnz = 0;
  d->factored = 0;
  d->mem = 0.0;
}

/* Free everything; accepts NULL and half-built data. */
static void gm_destroy(void *data) {
  gm_data *d = data;
  if (!d) return;
  release(d);
  free(d);
}

/* Copy the pattern, find the diagonal entries, size the workspace (the
 * given order is not used; see the file comment). Errors: MPGM_ERR_NOMEM. */
static int gm_analyse(void *data, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm) {
  (void)perm;
  gm_data *d = data;
  release(d);
  const int n = A->n, nnz = A->nnz;
  MPGM_ALLOC(ctx, d->Ap, n + 1);
  MPGM_ALLOC(ctx, d->Ai, nnz);
  MPGM_ALLOC(ctx, d->Ax, nnz);
  MPGM_ALLOC(ctx, d->lu, nnz);
  MPGM_ALLOC(ctx, d->diag, n);
  MPGM_ALLOC(ctx, d->mark, n);
  MPGM_ALLOC(ctx, d->rs, n);
  MPGM_CALL(mpgm_gmres_ws_alloc(ctx, &d->ws, n, d->opts.restart));
  memcpy(d->Ap, A->colptr, ((size_t)n + 1) * sizeof(int));
  memcpy(d->Ai, A->rowind, (size_t)nnz * sizeof(int));
  for (int j = 0; j < n; j++) {
    d->diag[j] = -1;
    d->mark[j] = -1;
    for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++)
      if (A->rowind[p] == j) d->diag[j] = p;
  }
  d->n = n;
  d->nnz = nnz;
  d->mem = (double)(n + 1 + nnz + 2 * n) * sizeof(int) + (2.0 * nnz + n) * sizeof(double) +
           mpgm_gmres_ws_bytes(n, d->ws.m);
  if (d->mem > d->mem_peak) d->mem_peak = d->mem;
  return MPGM_OK;
}

/* ILU(0) of A on its pattern, column by column (left-looking): column j
 * of U and L receives the updates of the columns k < j with U_kj != 0, in
 * increasing k, restricted to the pattern of column j. A zero or
 * non-finite pivot, or a column without a diagonal entry:
 * MPGM_ERR_SINGULAR (recoverable). Errors: MPGM_ERR_INTERNAL (not analysed
 * / other pattern). */
static int gm_factor(void *data, mpgm_ctx *ctx, const mpgm_csc *A) {
  gm_data *d = data;
  MPGM_CHECK(ctx, d->lu && A->n == d->n && A->nnz == d->nnz, MPGM_ERR_INTERNAL,
             "ilu_gmres: factor of order %d (%d entries), analysed %d (%d)", A->n, A->nnz, d->n,
             d->nnz);
  const int n = d->n, *Ap = d->Ap, *Ai = d->Ai, *diag = d->diag;
  int *mark = d->mark;
  double *lu = d->lu;
  d->factored = 0;
  memcpy(d->Ax, A->val, (size_t)d->nnz * sizeof(double));
  memcpy(lu, A->val, (size_t)d->nnz * sizeof(double));
  double *rs = d->rs; /* row sums of |A|: its infinity norm, for the round-off floor */
  memset(rs, 0, (size_t)n * sizeof(double));
  for (int k = 0; k < d->nnz; k++) rs[Ai[k]] += fabs(d->Ax[k]);
  d->anorm = 0.0;
  for (int i = 0; i < n; i++) d->anorm = fmax(d->anorm, rs[i]);
  double flops = 0.0;
  for (int j = 0; j < n; j++) {
    if (diag[j] < 0)
      MPGM_ERROR(ctx, MPGM_ERR_SINGULAR,
                 "ilu_gmres: ILU(0) of a matrix without diagonal entry in "
                 "column %d of %d (structurally singular)",
                 j, n);
    for (int p = Ap[j]; p < Ap[j + 1]; p++) mark[Ai[p]] = p;
    for (int p = Ap[j]; p < diag[j]; p++) { /* U_kj, k = Ai[p] < j, ascending */
      const int k = Ai[p];
      const double ukj = lu[p];
      if (ukj == 0.0) continue;
      for (int q = diag[k] + 1; q < Ap[k + 1]; q++) { /* L_ik, i > k */
        const int pos = mark[Ai[q]];
        if (pos >= 0) {
          lu[pos] -= lu[q] * ukj;
          flops += 2.0;
        }
      }
    }
    for (int p = Ap[j]; p < Ap[j + 1]; p++) mark[Ai[p]] = -1;
    const double piv = lu[diag[j]];
    if (!(piv != 0.0 && isfinite(piv)))
      MPGM_ERROR(ctx, MPGM_ERR_SINGULAR,
                 "ilu_gmres: ILU(0) pivot %g in column %d of %d (the matrix "
                 "is singular, or too far from diagonally dominant for ILU(0))",
                 piv, j, n);
    for (int p = diag[j] + 1; p < Ap[j + 1]; p++) lu[p] /= piv;
    flops += Ap[j + 1] - diag[j] - 1;
  }
  d->flops = flops;
  d->factored = 1;
  return MPGM_OK;
}

/* y = A x with the factorised values. */
static void matvec(void *user, const double *x, double *y) {
  const gm_data *d = user;
  memset(y, 0, (size_t)d->n * sizeof(double));
  for (int j = 0; j < d->n; j++) {
    const double xj = x[j];
    if (xj == 0.0) continue;
    for (int p = d->Ap[j]; p < d->Ap[j + 1]; p++) y[d->Ai[p]] += d->Ax[p] * xj;
  }
}

/* z = M^-1 v = U^-1 L^-1 v (z and v may alias). */
static int precondition(void *user, mpgm_ctx *ctx, const double *v, double *z) {
  (void)ctx;
  const gm_data *d = user;
  const int n = d->n, *Ap = d->Ap, *Ai = d->Ai, *diag = d->diag;
  const double *lu = d->lu;
  if (z != v) memcpy(z, v, (size_t)n * sizeof(double));
  for (int j = 0; j < n; j++) { /* L, unit diagonal, by columns */
    const double zj = z[j];
    if (zj == 0.0) continue;
    for (int q = diag[j] + 1; q < Ap[j + 1]; q++) z[Ai[q]] -= lu[q] * zj;
  }
  for (int j = n - 1; j >= 0; j--) { /* U, by columns */
    z[j] /= lu[diag[j]];
    const double zj = z[j];
    if (zj == 0.0) continue;
    for (int q = Ap[j]; q < diag[j]; q++) z[Ai[q]] -= lu[q] * zj;
  }
  return MPGM_OK;
}

/* x = A^-1 b to |b - A x| <= tol |b|, or to round-off (a stalled residual
 * with a backward error below the kernel's floor) when tol asks for more
 * than the system's round-off allows (b and x may alias). Not converged
 * within max_iter iterations, or a residual that is not finite:
 * MPGM_ERR_LINEAR (recoverable; x holds the last iterate). Errors:
 * MPGM_ERR_INTERNAL (no valid factorisation). */
static int gm_solve(void *data, mpgm_ctx *ctx, const double *b, double *x) {
  gm_data *d = data;
  MPGM_CHECK(ctx, d->factored, MPGM_ERR_INTERNAL, "ilu_gmres: solve without a valid factorisation");
  const mpgm_krylov_op op = {.user = d, .matvec = matvec, .precond = precondition,
                             .anorm = d->anorm};
  mpgm_gmres_result r;
  MPGM_CALL(mpgm_gmres(&d->ws, ctx, &op, b, x, d->opts.tol, d->opts.max_iter, &r));
  d->iterations = r.iterations;
  if (!isfinite(r.relres))
    MPGM_ERROR(ctx, MPGM_ERR_LINEAR, "ilu_gmres: %s not finite after %d iterations",
               r.iterations ? "residual" : "right-hand side", r.iterations);
  if (!r.converged)
    MPGM_ERROR(ctx, MPGM_ERR_LINEAR,
               "ilu_gmres: not converged in %d iterations (solver.linear_max_iterations; restart %d): "
               "|b - A x| / |b| = %.3e > %.3e (solver.linear_tol)",
               r.iterations, d->ws.m, r.relres, d->opts.tol);
  return MPGM_OK;
}

/* Newton's forcing term: the next solves' tolerance. */
static int gm_tolerance(void *data, double tol) {
  ((gm_data *)data)->opts.tol = tol;
  return MPGM_OK;
}

/* Entries of the ILU(0) factors (those of A), flops of the factorisation,
 * the most bytes the instance's arrays took, iterations of the last
 * solve. */
static int gm_stats(void *data, mpgm_solver_stats *st) {
  const gm_data *d = data;
  st->nnz_factor = d->factored ? d->nnz : 0.0;
  st->flops = d->factored ? d->flops : 0.0;
  st->mem_peak = d->mem_peak;
  st->iterations = d->iterations;
  return MPGM_OK;
}

/** Restarted GMRES, right-preconditioned with ILU(0), for general square
 *  matrices; converges to opts.tol or fails with MPGM_ERR_LINEAR (tests). */
const mpgm_solver_type test_solver_ilu_gmres = {
    .name = "ilu_gmres",
    .doc = "restarted GMRES with an ILU(0) preconditioner (iterative), any square matrix",
    .needs_spd = 0,
    .iterative = 1,
    .create = gm_create,
    .destroy = gm_destroy,
    .analyse = gm_analyse,
    .factor = gm_factor,
    .solve = gm_solve,
    .stats = gm_stats,
    .tolerance = gm_tolerance,
};
