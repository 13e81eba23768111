/* umfpack.c -- sparse LU (UMFPACK, int/double interface) for general
 * square matrices.
 *
 * analyse keeps the Symbolic object while the pattern is unchanged; factor
 * replaces the Numeric object; solve runs umfpack_di_wsolve with
 * iterative refinement and preallocated workspace. Refinement needs the
 * very matrix that was factorised, so the instance keeps its own copy of
 * the pattern (made in analyse) and of the values (made in factor): the
 * core may refill its matrix before it calls solve.
 */
#include "mpgm_solver.h"

#include <stdlib.h>
#include <string.h>
#include <umfpack.h>

/** Instance data. */
typedef struct umf_data {
  void *Symbolic;   /**< symbolic analysis of the current pattern      */
  void *Numeric;    /**< LU factors of the last successful factor      */
  double Control[UMFPACK_CONTROL]; /**< parameters (defaults)            */
  double Info[UMFPACK_INFO];       /**< statistics of the last call      */
  int n;            /**< order of the analysed pattern                 */
  int nnz;          /**< entries of the analysed pattern               */
  int *Ap, *Ai;     /**< owned copy of the pattern (n + 1, nnz)         */
  double *Ax;       /**< owned copy of the factorised values (nnz)      */
  int *Wi;          /**< wsolve workspace (n)                           */
  double *W;        /**< wsolve workspace (5 n, refinement)             */
  double *bw;       /**< copy of b (n): b and x may alias               */
  double flops;     /**< flop count of the last factorisation          */
  double mem_peak;  /**< largest UMFPACK peak seen (symbolic + numeric)
                         [bytes], without the copies above            */
} umf_data;

/* Record a failure of `what` with UMFPACK status st (< 0). */
static int fail(mpgm_ctx *ctx, int st, const char *what) {
  int code = MPGM_ERR_SOLVER;
  const char *s = "error";
  switch (st) {
  case UMFPACK_ERROR_out_of_memory: code = MPGM_ERR_NOMEM; s = "out of memory"; break;
  case UMFPACK_ERROR_invalid_matrix: s = "invalid matrix"; break;
  case UMFPACK_ERROR_different_pattern:
    code = MPGM_ERR_INTERNAL; s = "pattern changed since the analysis"; break;
  case UMFPACK_ERROR_argument_missing: s = "argument missing"; break;
  case UMFPACK_ERROR_n_nonpositive: s = "n <= 0"; break;
  case UMFPACK_ERROR_invalid_Symbolic_object: s = "invalid Symbolic"; break;
  case UMFPACK_ERROR_invalid_Numeric_object: s = "invalid Numeric"; break;
  case UMFPACK_ERROR_internal_error: s = "internal error"; break;
  default: break;
  }
  MPGM_ERROR(ctx, code, "umfpack: %s failed (status %d: %s)", what, st, s);
}

/* Allocate the instance with default controls (the options concern
 * iterative backends only). */
static int umf_create(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  (void)opts;
  umf_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *data = d;
  umfpack_di_defaults(d->Control);
  d->Control[UMFPACK_PRL] = 0; /* failures are reported through mpgm_ctx */
  return MPGM_OK;
}

/* Release the factors and the pattern-sized arrays. */
static void release(umf_data *d) {
  if (d->Numeric) umfpack_di_free_numeric(&d->Numeric);
  if (d->Symbolic) umfpack_di_free_symbolic(&d->Symbolic);
  free(d->Ap); free(d->Ai); free(d->Ax);
  free(d->Wi); free(d->W); free(d->bw);
  d->Ap = d->Ai = d->Wi = NULL;
  d->Ax = d->W = d->bw = NULL;
  d->n = d->nnz = 0;
}

/* Free everything; accepts NULL and half-built data. */
static void umf_destroy(void *data) {
  umf_data *d = data;
  if (!d) return;
  release(d);
  free(d);
}

/* Column pre-ordering (perm as given, or UMFPACK's own when NULL) and
 * symbolic analysis of A's pattern (the previous Symbolic and Numeric are
 * freed). Errors: MPGM_ERR_NOMEM, MPGM_ERR_SOLVER. */
static int umf_analyse(void *data, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm) {
  umf_data *d = data;
  const int n = A->n, nnz = A->nnz;
  release(d);
  MPGM_ALLOC(ctx, d->Ap, n + 1);
  MPGM_ALLOC(ctx, d->Ai, nnz);
  MPGM_ALLOC(ctx, d->Ax, nnz);
  MPGM_ALLOC(ctx, d->Wi, n);
  MPGM_ALLOC(ctx, d->W, 5 * (size_t)n);
  MPGM_ALLOC(ctx, d->bw, n);
  memcpy(d->Ap, A->colptr, ((size_t)n + 1) * sizeof(int));
  memcpy(d->Ai, A->rowind, (size_t)nnz * sizeof(int));
  /* the values only guide the choice of strategy here */
  /* a given order is symmetric (rows and columns alike): with it UMFPACK
   * must use its symmetric strategy (diagonal pivots preferred), or it
   * treats the order as a column pre-order only (unsymmetric strategy)
   * and on the rolling disk's tangent fills 6x more (factorisation 344
   * instead of 46 ms) */
  d->Control[UMFPACK_STRATEGY] = perm ? UMFPACK_STRATEGY_SYMMETRIC : UMFPACK_STRATEGY_AUTO;
  int st = umfpack_di_qsymbolic(n, n, d->Ap, d->Ai, A->val, perm, &d->Symbolic, d->Control,
                                d->Info);
  if (st < 0) {
    d->Symbolic = NULL;
    return fail(ctx, st, "umfpack_di_symbolic");
  }
  d->n = n;
  d->nnz = nnz;
  return MPGM_OK;
}

/* LU factorisation of A (pattern as analysed); the previous Numeric is
 * freed first. Singular: MPGM_ERR_SINGULAR (recoverable). Errors:
 * MPGM_ERR_INTERNAL (not analysed / other pattern), MPGM_ERR_NOMEM,
 * MPGM_ERR_SOLVER. */
static int umf_factor(void *data, mpgm_ctx *ctx, const mpgm_csc *A) {
  umf_data *d = data;
  MPGM_CHECK(ctx, d->Symbolic && A->n == d->n && A->nnz == d->nnz,
             MPGM_ERR_INTERNAL,
             "umfpack: factor of order %d (%d entries), analysed %d (%d)",
             A->n, A->nnz, d->n, d->nnz);
  if (d->Numeric) umfpack_di_free_numeric(&d->Numeric);
  d->flops = 0.0;
  memcpy(d->Ax, A->val, (size_t)d->nnz * sizeof(double));
  int st = umfpack_di_numeric(d->Ap, d->Ai, d->Ax, d->Symbolic, &d->Numeric,
                              d->Control, d->Info);
  if (st == UMFPACK_WARNING_singular_matrix) {
    umfpack_di_free_numeric(&d->Numeric);
    MPGM_ERROR(ctx, MPGM_ERR_SINGULAR,
               "umfpack: matrix singular (order %d, %g zero pivots)", d->n,
               (double)d->n - d->Info[UMFPACK_UDIAG_NZ]);
  }
  if (st < 0) {
    if (d->Numeric) umfpack_di_free_numeric(&d->Numeric);
    return fail(ctx, st, "umfpack_di_numeric");
  }
  d->flops = d->Info[UMFPACK_FLOPS];
  const double peak = d->Info[UMFPACK_PEAK_MEMORY] * d->Info[UMFPACK_SIZE_OF_UNIT];
  if (peak > d->mem_peak) d->mem_peak = peak;
  return MPGM_OK;
}

/* x = A^-1 b with the last factorisation (b and x may alias), iterative
 * refinement against the factorised values. Errors: MPGM_ERR_INTERNAL (no
 * valid factorisation), MPGM_ERR_SINGULAR, MPGM_ERR_SOLVER. */
static int umf_solve(void *data, mpgm_ctx *ctx, const double *b, double *x) {
  umf_data *d = data;
  MPGM_CHECK(ctx, d->Numeric != NULL, MPGM_ERR_INTERNAL,
             "umfpack: solve without a valid factorisation");
  memcpy(d->bw, b, (size_t)d->n * sizeof(double));
  int st = umfpack_di_wsolve(UMFPACK_A, d->Ap, d->Ai, d->Ax, x, d->bw,
                             d->Numeric, d->Control, d->Info, d->Wi, d->W);
  if (st == UMFPACK_WARNING_singular_matrix)
    MPGM_ERROR(ctx, MPGM_ERR_SINGULAR, "umfpack: singular matrix in solve");
  if (st < 0) return fail(ctx, st, "umfpack_di_wsolve");
  return MPGM_OK;
}

/* Entries of L + U (umfpack_di_get_lunz; both count their diagonal) and
 * the flop count of the last factorisation; zeros when not factorised.
 * Peak memory: UMFPACK's (Info[UMFPACK_PEAK_MEMORY] units of
 * Info[UMFPACK_SIZE_OF_UNIT] bytes) plus the instance's copies of the
 * matrix and the wsolve workspace. */
static int umf_stats(void *data, mpgm_solver_stats *st) {
  umf_data *d = data;
  st->nnz_factor = 0.0;
  st->flops = 0.0;
  const double n = d->n, nnz = d->nnz;
  st->mem_peak = d->mem_peak + (n + 1 + nnz + n) * sizeof(int) + (nnz + 6 * n) * sizeof(double);
  if (!d->Numeric) return MPGM_OK;
  int lnz, unz, nrow, ncol, nz_udiag;
  if (umfpack_di_get_lunz(&lnz, &unz, &nrow, &ncol, &nz_udiag, d->Numeric) ==
      UMFPACK_OK)
    st->nnz_factor = (double)lnz + (double)unz;
  st->flops = d->flops;
  return MPGM_OK;
}

/** UMFPACK LU with partial pivoting for general square matrices.
 *  Singular: MPGM_ERR_SINGULAR. */
const mpgm_solver_type mpgm_solver_umfpack = {
    .name = "umfpack",
    .doc = "sparse LU with partial pivoting (UMFPACK), any square matrix",
    .needs_spd = 0,
    .create = umf_create,
    .destroy = umf_destroy,
    .analyse = umf_analyse,
    .factor = umf_factor,
    .solve = umf_solve,
    .stats = umf_stats,
};
