/* cholmod.c -- sparse Cholesky (CHOLMOD, int interface) for symmetric
 * positive definite matrices: three backends that differ only in the
 * factorisation CHOLMOD is told to use (Common->supernodal): "cholmod"
 * lets CHOLMOD choose (supernodal when the analysis finds at least 40
 * flops per entry of L, CHOLMOD's default), "cholmod_simplicial" and
 * "cholmod_supernodal" force one.
 *
 * The core's mpgm_csc arrays are wrapped in a cholmod_sparse header without
 * copying (stype = 1: CHOLMOD reads the upper triangle of the full pattern).
 * analyse orders the pattern (AMD, or the caller's order) and builds the
 * symbolic factor once; factor
 * refills it numerically at every call (cholmod_factorize reuses L's
 * pattern). Common->final_ll is set so that simplicial factorisations are
 * LL' as well: a non-positive pivot is then reported (a simplicial LDL'
 * would silently factorise an indefinite matrix).
 */
#include "mpgm_solver.h"

#include <cholmod.h>
#include <stdlib.h>
#include <string.h>

/** Instance data: one cholmod_common per instance, no globals. */
typedef struct chol_data {
  cholmod_common cm;  /**< CHOLMOD's parameters, workspace and statistics */
  int started;        /**< 1 after cholmod_start (finish needed)          */
  cholmod_factor *L;  /**< symbolic after analyse, numeric after factor   */
  cholmod_dense *B;   /**< right-hand side copy (n x 1), kept per size     */
  cholmod_dense *X;   /**< solution, reused by cholmod_solve2            */
  cholmod_dense *Y;   /**< solve2 workspace                                */
  cholmod_dense *E;   /**< solve2 workspace                                */
  int n;              /**< order of the analysed pattern                  */
  int nnz;            /**< entries of the analysed pattern                */
  int factored;       /**< 1 while L holds a valid numeric factorisation  */
  double lnz;         /**< entries of L (sum of column counts)            */
  double fl;          /**< flop count of the factorisation (analysis)     */
} chol_data;

/* A cholmod_sparse view of A (no copy). */
static void wrap(const mpgm_csc *A, cholmod_sparse *As) {
  memset(As, 0, sizeof(*As));
  As->nrow = (size_t)A->n;
  As->ncol = (size_t)A->n;
  As->nzmax = (size_t)A->nnz;
  As->p = A->colptr;
  As->i = A->rowind;
  As->nz = NULL;
  As->x = A->val;
  As->z = NULL;
  As->stype = 1;
  As->itype = CHOLMOD_INT;
  As->xtype = CHOLMOD_REAL;
  As->dtype = CHOLMOD_DOUBLE;
  As->sorted = 1;
  As->packed = 1;
}

static const char *status_str(int status) {
  switch (status) {
  case CHOLMOD_OK: return "ok";
  case CHOLMOD_NOT_INSTALLED: return "method not installed";
  case CHOLMOD_OUT_OF_MEMORY: return "out of memory";
  case CHOLMOD_TOO_LARGE: return "integer overflow";
  case CHOLMOD_INVALID: return "invalid input";
  case CHOLMOD_GPU_PROBLEM: return "GPU problem";
  case CHOLMOD_NOT_POSDEF: return "matrix not positive definite";
  case CHOLMOD_DSMALL: return "tiny pivot";
  default: return "unknown status";
  }
}

/* Record a CHOLMOD failure (status < 0, or a NULL result) after `what`. */
static int fail(mpgm_ctx *ctx, const chol_data *d, const char *what) {
  int st = d->cm.status;
  MPGM_ERROR(ctx, st == CHOLMOD_OUT_OF_MEMORY ? MPGM_ERR_NOMEM : MPGM_ERR_SOLVER,
             "cholmod: %s failed (status %d: %s)", what, st, status_str(st));
}

/* Allocate the instance and start CHOLMOD with factorisation `kind`
 * (CHOLMOD_AUTO, CHOLMOD_SIMPLICIAL, CHOLMOD_SUPERNODAL). On failure the
 * half-built data stays in *data; the generic wrapper destroys it. */
static int create_kind(mpgm_ctx *ctx, void **data, int kind) {
  chol_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *data = d;
  MPGM_CHECK(ctx, cholmod_start(&d->cm), MPGM_ERR_SOLVER,
             "cholmod: cholmod_start failed (status %d)", d->cm.status);
  d->started = 1;
  d->cm.print = 0;     /* failures are reported through mpgm_ctx */
  d->cm.final_ll = 1;  /* LL' also for simplicial: detects indefiniteness */
  d->cm.supernodal = kind;
  return MPGM_OK;
}

/* The options concern iterative backends only. */
static int chol_create(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  (void)opts;
  return create_kind(ctx, data, CHOLMOD_AUTO);
}
static int chol_create_simplicial(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  (void)opts;
  return create_kind(ctx, data, CHOLMOD_SIMPLICIAL);
}
static int chol_create_supernodal(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  (void)opts;
  return create_kind(ctx, data, CHOLMOD_SUPERNODAL);
}

/* Free the factor, the dense arrays and the common; accepts NULL and
 * half-built data. */
static void chol_destroy(void *data) {
  chol_data *d = data;
  if (!d) return;
  if (d->started) {
    cholmod_free_factor(&d->L, &d->cm);
    cholmod_free_dense(&d->B, &d->cm);
    cholmod_free_dense(&d->X, &d->cm);
    cholmod_free_dense(&d->Y, &d->cm);
    cholmod_free_dense(&d->E, &d->cm);
    cholmod_finish(&d->cm);
  }
  free(d);
}

/* Fill-reducing ordering and symbolic factorisation of A's pattern;
 * replaces the previous symbolic factor. Errors: MPGM_ERR_NOMEM,
 * MPGM_ERR_SOLVER. */
static int chol_analyse(void *data, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm) {
  chol_data *d = data;
  cholmod_sparse As;
  wrap(A, &As);
  cholmod_free_factor(&d->L, &d->cm);
  d->factored = 0;
  d->n = d->nnz = 0;
  /* a given order is used as it is (one method, CHOLMOD_GIVEN; the
   * default list would also run AMD and keep the better of the two) */
  d->cm.nmethods = perm ? 1 : 0;
  d->cm.method[0].ordering = CHOLMOD_GIVEN;
  d->L = cholmod_analyze_p(&As, (int *)perm, NULL, 0, &d->cm);
  if (!d->L) return fail(ctx, d, "cholmod_analyze");
  d->n = A->n;
  d->nnz = A->nnz;
  /* exact (structural) entry count of L: the column counts of the
   * analysis, excluding zeros added by supernodal amalgamation */
  const int *cc = d->L->ColCount;
  double lnz = 0.0;
  for (int j = 0; j < A->n; j++) lnz += cc[j];
  d->lnz = lnz;
  d->fl = d->cm.fl;
  if (d->B && d->B->nrow != (size_t)A->n) cholmod_free_dense(&d->B, &d->cm);
  if (!d->B) {
    d->B = cholmod_allocate_dense((size_t)A->n, 1, (size_t)A->n, CHOLMOD_REAL,
                                  &d->cm);
    if (!d->B) return fail(ctx, d, "cholmod_allocate_dense");
  }
  return MPGM_OK;
}

/* Numeric factorisation A = L L' (pattern as analysed). Not positive
 * definite: MPGM_ERR_SINGULAR (recoverable; L is refilled by the next
 * call). Errors: MPGM_ERR_INTERNAL (not analysed / other pattern),
 * MPGM_ERR_NOMEM, MPGM_ERR_SOLVER. */
static int chol_factor(void *data, mpgm_ctx *ctx, const mpgm_csc *A) {
  chol_data *d = data;
  MPGM_CHECK(ctx, d->L && A->n == d->n && A->nnz == d->nnz, MPGM_ERR_INTERNAL,
             "cholmod: factor of order %d (%d entries), analysed %d (%d)",
             A->n, A->nnz, d->n, d->nnz);
  cholmod_sparse As;
  wrap(A, &As);
  d->factored = 0;
  int ok = cholmod_factorize(&As, d->L, &d->cm);
  if (!ok || d->cm.status < 0) return fail(ctx, d, "cholmod_factorize");
  if (d->cm.status == CHOLMOD_NOT_POSDEF || d->L->minor < d->L->n)
    MPGM_ERROR(ctx, MPGM_ERR_SINGULAR,
               "cholmod: matrix not positive definite (pivot %zu of %d in "
               "the fill-reducing order)",
               (size_t)d->L->minor, A->n);
  if (!d->L->is_ll && !d->L->is_super) {
    /* guard: an LDL' factor is only accepted with a positive D */
    const int *Lp = d->L->p;
    const double *Lx = d->L->x;
    for (int j = 0; j < A->n; j++)
      if (!(Lx[Lp[j]] > 0.0))
        MPGM_ERROR(ctx, MPGM_ERR_SINGULAR,
                   "cholmod: matrix not positive definite (pivot %d of %d in "
                   "the fill-reducing order)", j, A->n);
  }
  d->factored = 1;
  return MPGM_OK;
}

/* x = A^-1 b with the last factorisation (b and x may alias).
 * Errors: MPGM_ERR_INTERNAL (no valid factorisation), MPGM_ERR_NOMEM,
 * MPGM_ERR_SOLVER. */
static int chol_solve(void *data, mpgm_ctx *ctx, const double *b, double *x) {
  chol_data *d = data;
  MPGM_CHECK(ctx, d->factored, MPGM_ERR_INTERNAL,
             "cholmod: solve without a valid factorisation");
  const size_t n = (size_t)d->n;
  memcpy(d->B->x, b, n * sizeof(double));
  if (!cholmod_solve2(CHOLMOD_A, d->L, d->B, NULL, &d->X, NULL, &d->Y, &d->E,
                      &d->cm))
    return fail(ctx, d, "cholmod_solve2");
  memcpy(x, d->X->x, n * sizeof(double));
  return MPGM_OK;
}

/* X = A^-1 B for nrhs columns in one supernodal (BLAS 3) solve: a view of
 * B as a cholmod_dense, the result copied into X (may alias B).
 * Errors: as chol_solve. */
static int chol_solve_many(void *data, mpgm_ctx *ctx, int nrhs, const double *B, double *X) {
  chol_data *d = data;
  MPGM_CHECK(ctx, d->factored, MPGM_ERR_INTERNAL,
             "cholmod: solve without a valid factorisation");
  if (nrhs == 0) return MPGM_OK;
  const size_t n = (size_t)d->n;
  cholmod_dense Bd = {.nrow = n, .ncol = (size_t)nrhs, .nzmax = n * (size_t)nrhs, .d = n,
                      .x = (void *)B, .xtype = CHOLMOD_REAL, .dtype = CHOLMOD_DOUBLE};
  cholmod_dense *Xd = cholmod_solve(CHOLMOD_A, d->L, &Bd, &d->cm);
  if (!Xd) return fail(ctx, d, "cholmod_solve");
  memcpy(X, Xd->x, n * (size_t)nrhs * sizeof(double));
  cholmod_free_dense(&Xd, &d->cm);
  return MPGM_OK;
}

/* Entries of L and flop count of the factorisation (from the analysis);
 * CHOLMOD's peak memory since cholmod_start (Common->memory_usage: the
 * factor, its workspace and the dense vectors of solve2). */
static int chol_stats(void *data, mpgm_solver_stats *st) {
  const chol_data *d = data;
  st->nnz_factor = d->L ? d->lnz : 0.0;
  st->flops = d->L ? d->fl : 0.0;
  st->mem_peak = d->started ? (double)d->cm.memory_usage : 0.0;
  return MPGM_OK;
}

/** CHOLMOD LL' for symmetric positive definite matrices; reads the upper
 *  triangle. Indefinite: MPGM_ERR_SINGULAR. Supernodal or simplicial as
 *  CHOLMOD chooses (Common->supernodal = CHOLMOD_AUTO). */
const mpgm_solver_type mpgm_solver_cholmod = {
    .name = "cholmod",
    .doc = "sparse Cholesky LL' (CHOLMOD, supernodal or simplicial as it chooses), SPD only",
    .needs_spd = 1,
    .create = chol_create,
    .destroy = chol_destroy,
    .analyse = chol_analyse,
    .factor = chol_factor,
    .solve = chol_solve,
    .solve_many = chol_solve_many,
    .stats = chol_stats,
};

/** As mpgm_solver_cholmod, always simplicial (CHOLMOD_SIMPLICIAL). */
const mpgm_solver_type mpgm_solver_cholmod_simplicial = {
    .name = "cholmod_simplicial",
    .doc = "sparse Cholesky LL' (CHOLMOD, simplicial: column by column), SPD only",
    .needs_spd = 1,
    .create = chol_create_simplicial,
    .destroy = chol_destroy,
    .analyse = chol_analyse,
    .factor = chol_factor,
    .solve = chol_solve,
    .solve_many = chol_solve_many,
    .stats = chol_stats,
};

/** As mpgm_solver_cholmod, always supernodal (CHOLMOD_SUPERNODAL). */
const mpgm_solver_type mpgm_solver_cholmod_supernodal = {
    .name = "cholmod_supernodal",
    .doc = "sparse Cholesky LL' (CHOLMOD, supernodal: dense blocks through the BLAS), SPD only",
    .needs_spd = 1,
    .create = chol_create_supernodal,
    .destroy = chol_destroy,
    .analyse = chol_analyse,
    .factor = chol_factor,
    .solve = chol_solve,
    .solve_many = chol_solve_many,
    .stats = chol_stats,
};
