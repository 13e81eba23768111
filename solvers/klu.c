/* klu.c -- sparse LU (KLU, int interface) for general square matrices.
 *
 * KLU (Davis & Palamadai Natarajan 2010) permutes the matrix to block
 * upper triangular form (BTF: a maximum transversal, then the strongly
 * connected components), orders each diagonal block with AMD and
 * factorises the blocks by left-looking Gilbert-Peierls LU with partial
 * pivoting (diagonal preferred, Common.tol = 0.001). It needs no BLAS and
 * was written for circuit matrices; the tangents of mpgm are irreducible,
 * so BTF finds one block and KLU is then a left-looking sparse LU after
 * AMD.
 *
 * A given order (solver.ordering geometric) is used as it is, for rows
 * and columns alike (klu_analyze_given with P = Q = perm), and BTF is then
 * switched off: BTF would renumber the equations within the single block
 * of our matrices in the order of its depth-first search, which would
 * throw the given order away.
 *
 * analyse keeps the Symbolic object while the pattern is unchanged;
 * factor runs klu_factor (a fresh pivot sequence) every time: klu_refactor
 * would reuse the last pivots without checking them. KLU has no iterative
 * refinement; solve adds it as UMFPACK does by default (at most
 * REFINE_STEPS steps x += A^-1 (b - A x), while the normwise backward
 * error |b - A x| / (|A| |x| + |b|) (infinity norms) is above machine
 * epsilon and at least halves), so the instance keeps a copy of the
 * pattern and of the factorised values: the core may refill its matrix
 * before it calls solve.
 */
#include "mpgm_solver.h"

#include <float.h>
#include <klu.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define REFINE_STEPS 2 /* UMFPACK's default (Control[UMFPACK_IRSTEP]) */

/** Instance data: one klu_common per instance, no globals. */
typedef struct klu_data {
  klu_common cm;          /**< KLU's parameters and statistics           */
  klu_symbolic *Symbolic; /**< ordering of the current pattern           */
  klu_numeric *Numeric;   /**< LU factors of the last successful factor  */
  int n;                  /**< order of the analysed pattern             */
  int nnz;                /**< entries of the analysed pattern           */
  int *Ap, *Ai;           /**< copy of the pattern (n + 1, nnz)          */
  double *Ax;             /**< copy of the factorised values (nnz)       */
  double anorm;           /**< |A| (infinity norm) of the factorised A  */
  double *x, *r, *t, *bw; /**< solution, residual, refined solution, copy
                               of b (n each)                              */
} klu_data;

static const char *status_str(int st) {
  switch (st) {
  case KLU_OK:
    return "ok";
  case KLU_SINGULAR:
    return "singular";
  case KLU_OUT_OF_MEMORY:
    return "out of memory";
  case KLU_INVALID:
    return "invalid input";
  case KLU_TOO_LARGE:
    return "integer overflow";
  default:
    return "unknown status";
  }
}

/* Record a failure of `what` from Common.status. */
static int fail(mpgm_ctx *ctx, const klu_data *d, const char *what) {
  const int st = d->cm.status;
  MPGM_ERROR(ctx, st == KLU_OUT_OF_MEMORY ? MPGM_ERR_NOMEM : MPGM_ERR_SOLVER,
             "klu: %s failed (status %d: %s)", what, st, status_str(st));
}

/* Allocate the instance with KLU's defaults (the options concern iterative
 * backends only). */
static int kl_create(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  (void)opts;
  klu_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *data = d;
  MPGM_CHECK(ctx, klu_defaults(&d->cm), MPGM_ERR_SOLVER, "klu: klu_defaults failed");
  d->cm.halt_if_singular = 1; /* a zero pivot stops klu_factor (KLU_SINGULAR) */
  return MPGM_OK;
}

/* Free the factors and the work vector; the pattern is forgotten. */
static void release(klu_data *d) {
  if (d->Numeric) klu_free_numeric(&d->Numeric, &d->cm);
  if (d->Symbolic) klu_free_symbolic(&d->Symbolic, &d->cm);
  free(d->Ap);
  free(d->Ai);
  free(d->Ax);
  free(d->x);
  free(d->r);
  free(d->t);
  free(d->bw);
  d->Ap = d->Ai = NULL;
  d->Ax = d->x = d->r = d->t = d->bw = NULL;
  d->n = d->nnz = 0;
}

/* Free everything; accepts NULL and half-built data. */
static void kl_destroy(void *data) {
  klu_data *d = data;
  if (!d) return;
  release(d);
  free(d);
}

/* BTF + AMD ordering of A's pattern (or perm as given, without BTF).
 * Errors: MPGM_ERR_NOMEM, MPGM_ERR_SOLVER. */
static int kl_analyse(void *data, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm) {
  klu_data *d = data;
  release(d);
  MPGM_ALLOC(ctx, d->Ap, A->n + 1);
  MPGM_ALLOC(ctx, d->Ai, A->nnz);
  MPGM_ALLOC(ctx, d->Ax, A->nnz);
  MPGM_ALLOC(ctx, d->x, A->n);
  MPGM_ALLOC(ctx, d->r, A->n);
  MPGM_ALLOC(ctx, d->t, A->n);
  MPGM_ALLOC(ctx, d->bw, A->n);
  memcpy(d->Ap, A->colptr, ((size_t)A->n + 1) * sizeof(int));
  memcpy(d->Ai, A->rowind, (size_t)A->nnz * sizeof(int));
  if (perm) {
    d->cm.btf = 0;
    d->Symbolic = klu_analyze_given(A->n, d->Ap, d->Ai, (int *)perm, (int *)perm, &d->cm);
  } else {
    d->cm.btf = 1;
    d->cm.ordering = 0; /* AMD */
    d->Symbolic = klu_analyze(A->n, d->Ap, d->Ai, &d->cm);
  }
  if (!d->Symbolic) return fail(ctx, d, perm ? "klu_analyze_given" : "klu_analyze");
  d->n = A->n;
  d->nnz = A->nnz;
  return MPGM_OK;
}

/* LU factorisation of A (pattern as analysed); the previous factors are
 * freed first. Singular: MPGM_ERR_SINGULAR (recoverable). Errors:
 * MPGM_ERR_INTERNAL (not analysed / other pattern), MPGM_ERR_NOMEM,
 * MPGM_ERR_SOLVER. */
static int kl_factor(void *data, mpgm_ctx *ctx, const mpgm_csc *A) {
  klu_data *d = data;
  MPGM_CHECK(ctx, d->Symbolic && A->n == d->n && A->nnz == d->nnz, MPGM_ERR_INTERNAL,
             "klu: factor of order %d (%d entries), analysed %d (%d)", A->n, A->nnz, d->n, d->nnz);
  if (d->Numeric) klu_free_numeric(&d->Numeric, &d->cm);
  memcpy(d->Ax, A->val, (size_t)d->nnz * sizeof(double));
  double *rs = d->r; /* row sums of |A|: its infinity norm */
  memset(rs, 0, (size_t)d->n * sizeof(double));
  for (int k = 0; k < d->nnz; k++) rs[d->Ai[k]] += fabs(d->Ax[k]);
  d->anorm = 0.0;
  for (int i = 0; i < d->n; i++) d->anorm = fmax(d->anorm, rs[i]);
  d->Numeric = klu_factor(d->Ap, d->Ai, d->Ax, d->Symbolic, &d->cm);
  if (d->cm.status == KLU_SINGULAR) {
    if (d->Numeric) klu_free_numeric(&d->Numeric, &d->cm);
    MPGM_ERROR(
        ctx, MPGM_ERR_SINGULAR,
        "klu: matrix singular (zero pivot in column %d of %d, at step %d of the elimination)",
        d->cm.singular_col, d->n, d->cm.numerical_rank);
  }
  if (!d->Numeric || d->cm.status < 0) {
    if (d->Numeric) klu_free_numeric(&d->Numeric, &d->cm);
    return fail(ctx, d, "klu_factor");
  }
  /* the flop count is a statistic only: a failure here is not the run's */
  if (!klu_flops(d->Symbolic, d->Numeric, &d->cm)) d->cm.flops = 0.0;
  d->cm.status = KLU_OK;
  return MPGM_OK;
}

/* r = b - A x with the factorised values; returns the normwise backward
 * error |r| / (|A| |x| + |b|) in infinity norms (0 when that is 0). */
static double residual(const klu_data *d, const double *b, const double *x, double *r) {
  const int n = d->n;
  memcpy(r, b, (size_t)n * sizeof(double));
  double xn = 0.0, bn = 0.0, rn = 0.0;
  for (int j = 0; j < n; j++) {
    for (int p = d->Ap[j]; p < d->Ap[j + 1]; p++) r[d->Ai[p]] -= d->Ax[p] * x[j];
    xn = fmax(xn, fabs(x[j]));
    bn = fmax(bn, fabs(b[j]));
  }
  for (int i = 0; i < n; i++) rn = fmax(rn, fabs(r[i]));
  const double den = d->anorm * xn + bn;
  return den > 0.0 ? rn / den : 0.0;
}

/* x = A^-1 b with the last factorisation and iterative refinement (b and
 * x may alias). Errors: MPGM_ERR_INTERNAL (no valid factorisation),
 * MPGM_ERR_SOLVER. */
static int kl_solve(void *data, mpgm_ctx *ctx, const double *b, double *x) {
  klu_data *d = data;
  MPGM_CHECK(ctx, d->Numeric != NULL, MPGM_ERR_INTERNAL,
             "klu: solve without a valid factorisation");
  const size_t bytes = (size_t)d->n * sizeof(double);
  memcpy(d->bw, b, bytes);
  memcpy(d->x, b, bytes);
  if (!klu_solve(d->Symbolic, d->Numeric, d->n, 1, d->x, &d->cm)) return fail(ctx, d, "klu_solve");
  double berr = residual(d, d->bw, d->x, d->r);
  for (int step = 0; step < REFINE_STEPS && berr > DBL_EPSILON; step++) {
    if (!klu_solve(d->Symbolic, d->Numeric, d->n, 1, d->r, &d->cm))
      return fail(ctx, d, "klu_solve");
    for (int i = 0; i < d->n; i++) d->t[i] = d->x[i] + d->r[i];
    const double e = residual(d, d->bw, d->t, d->r);
    if (!(e < berr)) break; /* no better: keep x */
    double *tmp = d->x;
    d->x = d->t;
    d->t = tmp;
    const int halved = e <= 0.5 * berr;
    berr = e;
    if (!halved) break;
  }
  memcpy(x, d->x, bytes);
  return MPGM_OK;
}

/* Entries of L + U (both with their diagonal) and of the off-diagonal
 * blocks of the BTF form; flops of the last factorisation (klu_flops);
 * KLU's peak memory since the instance was created (Common.mempeak) plus
 * the instance's copies of the matrix and its vectors. */
static int kl_stats(void *data, mpgm_solver_stats *st) {
  const klu_data *d = data;
  st->nnz_factor = 0.0;
  st->flops = 0.0;
  const double n = d->n, nnz = d->nnz;
  st->mem_peak =
      (double)d->cm.mempeak + (n + 1 + nnz) * sizeof(int) + (nnz + 4 * n) * sizeof(double);
  if (!d->Numeric) return MPGM_OK;
  st->nnz_factor = (double)d->Numeric->lnz + (double)d->Numeric->unz + (double)d->Numeric->nzoff;
  st->flops = d->cm.flops;
  return MPGM_OK;
}

/** KLU: BTF + AMD, left-looking sparse LU with partial pivoting, for
 *  general square matrices. Singular: MPGM_ERR_SINGULAR. */
const mpgm_solver_type mpgm_solver_klu = {
    .name = "klu",
    .doc = "sparse LU, left-looking with partial pivoting after BTF and AMD (KLU), any square "
           "matrix",
    .needs_spd = 0,
    .create = kl_create,
    .destroy = kl_destroy,
    .analyse = kl_analyse,
    .factor = kl_factor,
    .solve = kl_solve,
    .stats = kl_stats,
};
