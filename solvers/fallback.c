/* fallback.c -- the composite backend of solver.linear_fallback: an
 * iterative backend (petsc) with a direct one for the matrices it
 * cannot solve.
 *
 * A Krylov solve can fail where the tangent itself is fine: GMRES with
 * ILU(0) breaks down (DIVERGED_BREAKDOWN) or stops at its iteration cap on
 * a tangent that UMFPACK factorises without complaint (the GMM-MLS column
 * at dt = 0.00125 s: every halving of the step failed the same way, and
 * the run stopped). Cutting the step is then a cure for the wrong
 * disease: the step is cut because the preconditioner is poor, not
 * because the physics asks for it, and the time step the answer is made
 * with changes for a reason that belongs to the linear algebra.
 *
 * Here, a solve the iterative part cannot finish (MPGM_ERR_LINEAR, or the
 * preconditioner failing in the solve: MPGM_ERR_SINGULAR) and a
 * preconditioner that cannot be built (factor: MPGM_ERR_SINGULAR) hand
 * the same matrix to the direct part, which factorises it and solves the
 * same right-hand side; further solves with that matrix (modified Newton,
 * low-rank contact updates) go to the direct part without trying the
 * Krylov solve again, and the next factor goes back to the iterative
 * part. Each matrix handed over is counted (MPGM_C_LINEAR_FALLBACKS) and
 * logged as a warning with the iterative part's reason. A matrix the
 * direct part also refuses is MPGM_ERR_SINGULAR, recoverable as before:
 * a step cut.
 *
 * The matrix is borrowed from factor to the next factor: the core keeps
 * its values those factorised until it factorises again (an iterative
 * backend multiplies by them too). The right-hand side is copied before
 * the Krylov solve, which may overwrite it (b and x may alias).
 *
 * The parts are full instances called through the generic wrappers, so
 * their analyses, factorisations, solves and iterations are timed and
 * counted as their own (the failed Krylov solve also in
 * MPGM_C_LINEAR_NOT_CONVERGED); the composite is not (type->composite).
 * The direct part is created and analysed when it is first needed, and
 * analysed again after a new pattern when it is next needed. There is no
 * part operation: a matrix handed to mpgm_solver_part (the consistent
 * mass matrix) goes through the fallback too, as a Krylov solve that
 * stops short says nothing wrong of the matrix (where auto's Cholesky
 * refusing a mass matrix does: it is not positive definite).
 */
#include "mpgm_solver.h"

#include <stdlib.h>
#include <string.h>

typedef struct fb_data {
  mpgm_solver_opts opts;   /**< handed to the parts (part, fallback NULL) */
  const mpgm_solver_type *fallback; /**< the direct backend               */
  mpgm_solver *iter;       /**< the iterative part (opts.part)            */
  mpgm_solver *direct;     /**< the direct part, created when first needed */
  const mpgm_csc *A;       /**< the matrix of the last factor (borrowed)  */
  const int *perm;         /**< ordering of the last analyse (borrowed)   */
  double *b;               /**< copy of the right-hand side (n)           */
  int n;                   /**< order of the analysed matrix               */
  int on_direct;           /**< the direct part holds A's factorisation    */
} fb_data;

static void fb_destroy(void *data) {
  fb_data *d = data;
  if (!d) return;
  mpgm_solver_destroy(&d->iter);
  mpgm_solver_destroy(&d->direct);
  free(d->b);
  free(d);
}

static int fb_create(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  MPGM_CHECK(ctx, opts->part && opts->part->iterative && opts->fallback &&
                      !opts->fallback->iterative,
             MPGM_ERR_INPUT, "solver.linear_fallback: needs an iterative backend (found %s) and a "
             "direct fallback (found %s)",
             opts->part ? opts->part->name : "none", opts->fallback ? opts->fallback->name : "none");
  fb_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *data = d;
  d->opts = *opts;
  d->opts.part = NULL;
  d->opts.fallback = NULL;
  d->fallback = opts->fallback;
  return mpgm_solver_create(ctx, opts->part, &d->opts, &d->iter);
}

static int fb_analyse(void *data, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm) {
  fb_data *d = data;
  if (A->n != d->n) {
    free(d->b);
    d->b = NULL;
    d->n = 0;
    MPGM_ALLOC(ctx, d->b, A->n > 0 ? A->n : 1);
    d->n = A->n;
  }
  d->perm = perm;
  d->A = NULL;
  d->on_direct = 0;
  if (d->direct) d->direct->analysed = 0;
  return mpgm_solver_analyse(d->iter, ctx, A, perm);
}

/* The iterative part could not do d->A (code err, its reason in ctx):
 * the direct part factorises it. Returns the direct part's code; when it
 * fails too, neither part holds a factorisation of A, and a solve before
 * the next factor is refused rather than made with older factors. */
static int hand_over(fb_data *d, mpgm_ctx *ctx, int err) {
  mpgm_log(ctx, MPGM_LOG_WARNING, "%s; %s factorises this matrix instead (solver.linear_fallback)",
           ctx->msg[0] ? ctx->msg : mpgm_code_str(err), d->fallback->name);
  mpgm_err_clear(ctx);
  mpgm_count(ctx, MPGM_C_LINEAR_FALLBACKS, 1);
  const mpgm_csc *A = d->A;
  d->A = NULL;
  d->on_direct = 0;
  if (!d->direct) MPGM_CALL(mpgm_solver_create(ctx, d->fallback, &d->opts, &d->direct));
  if (!d->direct->analysed) MPGM_CALL(mpgm_solver_analyse(d->direct, ctx, A, d->perm));
  MPGM_CALL(mpgm_solver_factor(d->direct, ctx, A));
  d->A = A;
  d->on_direct = 1;
  return MPGM_OK;
}

/* The preconditioner; one that cannot be built hands A over at once. */
static int fb_factor(void *data, mpgm_ctx *ctx, const mpgm_csc *A) {
  fb_data *d = data;
  MPGM_CHECK(ctx, A->n == d->n, MPGM_ERR_INTERNAL,
             "solver.linear_fallback: factor of order %d, analysed %d", A->n, d->n);
  d->A = A;
  d->on_direct = 0;
  const int err = mpgm_solver_factor(d->iter, ctx, A);
  return err == MPGM_ERR_SINGULAR ? hand_over(d, ctx, err) : err;
}

/* The Krylov solve; one that fails hands A over and solves b again. */
static int fb_solve(void *data, mpgm_ctx *ctx, const double *b, double *x) {
  fb_data *d = data;
  MPGM_CHECK(ctx, d->A != NULL, MPGM_ERR_INTERNAL, "solver.linear_fallback: solve before factor");
  if (d->on_direct) return mpgm_solver_solve(d->direct, ctx, b, x);
  memcpy(d->b, b, (size_t)d->n * sizeof(double));
  int err = mpgm_solver_solve(d->iter, ctx, b, x);
  if (err != MPGM_ERR_LINEAR && err != MPGM_ERR_SINGULAR) return err;
  MPGM_CALL(hand_over(d, ctx, err));
  return mpgm_solver_solve(d->direct, ctx, d->b, x);
}

/* On the direct part: its own solve_many (CHOLMOD's supernodal solve does
 * the columns at once); else column by column, each with its fallback. */
static int fb_solve_many(void *data, mpgm_ctx *ctx, int nrhs, const double *B, double *X) {
  fb_data *d = data;
  if (d->on_direct) return mpgm_solver_solve_many(d->direct, ctx, d->n, nrhs, B, X);
  for (int j = 0; j < nrhs; j++)
    MPGM_CALL(fb_solve(d, ctx, B + (size_t)j * d->n, X + (size_t)j * d->n));
  return 0;
}

/* The iterative part's statistics; the factors and memory of the direct
 * part are added once it exists (its factors when it holds this matrix's). */
static int fb_stats(void *data, mpgm_solver_stats *st) {
  fb_data *d = data;
  int err = mpgm_solver_get_stats(d->iter, st);
  if (err == MPGM_ERR_UNSUPPORTED) err = 0;
  mpgm_solver_stats ds;
  if (d->direct && mpgm_solver_get_stats(d->direct, &ds) == 0) {
    if (d->on_direct) st->nnz_factor = ds.nnz_factor, st->flops = ds.flops;
    st->mem_peak += ds.mem_peak;
  }
  return err;
}

static int fb_step(void *data, mpgm_ctx *ctx, int *kept) {
  return mpgm_solver_step(((fb_data *)data)->iter, ctx, kept);
}

static int fb_tolerance(void *data, double tol) {
  return mpgm_solver_tolerance(((fb_data *)data)->iter, tol);
}

static const char *fb_backend(const void *data) {
  return mpgm_solver_name(((const fb_data *)data)->iter);
}

/* Checkpoint: the iterative part's state (nothing of the direct part
 * outlives its factorisation). */
static int fb_save(const void *data, mpgm_ctx *ctx, mpgm_blob *b) {
  return mpgm_solver_save(((const fb_data *)data)->iter, ctx, b);
}

static int fb_restore(void *data, mpgm_ctx *ctx, mpgm_blob *b) {
  fb_data *d = data;
  d->A = NULL;
  d->on_direct = 0;
  return mpgm_solver_restore(d->iter, ctx, b);
}

/** An iterative backend (opts.part) with a direct one (opts.fallback) for
 *  the matrices it cannot precondition or solve (solver.linear_fallback). */
const mpgm_solver_type mpgm_solver_fallback = {
    .name = "fallback",
    .doc = "an iterative backend whose failed solves (not converged, preconditioner "
           "failed) go to a direct backend for that matrix (solver.linear_fallback)",
    .iterative = 1,
    .composite = 1,
    .create = fb_create,
    .destroy = fb_destroy,
    .analyse = fb_analyse,
    .factor = fb_factor,
    .solve = fb_solve,
    .solve_many = fb_solve_many,
    .stats = fb_stats,
    .step = fb_step,
    .tolerance = fb_tolerance,
    .backend = fb_backend,
    .save = fb_save,
    .restore = fb_restore,
};
