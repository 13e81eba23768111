/* reuse.c -- the composite backend of Newton-Krylov (solver.newton
 * "krylov"): a direct backend's last factorisation as the preconditioner
 * of GMRES on the current matrix.
 *
 * Full Newton factorises the tangent at every iteration; modified Newton
 * solves with an old factorisation and converges linearly. Here every
 * iteration solves with the current tangent K_k, by GMRES right-
 * preconditioned with the factors of an earlier K_j (solvers/krylov.c),
 * so Newton keeps its quadratic convergence (to the forcing tolerance,
 * mpgm_solver_tolerance) and a factorisation serves as long as it
 * preconditions well. factor copies the values (GMRES multiplies by them)
 * and factorises only when the part has no factorisation of this pattern
 * or the last solve took more than opts.refactor_iterations Krylov
 * iterations; otherwise the factorisation is kept (counted:
 * MPGM_C_FACTOR_REUSES). A solve that has not converged after 4 x
 * refactor_iterations with an old factorisation refactorises at once and
 * solves again (then GMRES converges in an iteration or two: the
 * preconditioner is the inverse).
 *
 * The part is a full instance (created from opts.part: auto, cholmod,
 * umfpack, klu, ...); its analyses and factorisations go through the
 * generic wrappers and are timed and counted as usual. The GMRES solve is
 * timed here as one solve (MPGM_T_SOLVE, MPGM_C_SOLVES, its iterations in
 * MPGM_C_LINEAR_ITERATIONS); inside it the part's factors are applied
 * through its own solve operation, not the wrapper (the solve timer is
 * already running). The composite itself is not timed by the wrappers
 * (type->composite).
 */
#include "mpgm_krylov.h"
#include "mpgm_solver.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct reuse_data {
  mpgm_solver_opts opts; /**< restart, refactor_iterations, tol, the part */
  mpgm_solver *part;     /**< the direct backend                         */
  mpgm_csc A;            /**< copy of the pattern and of the last values  */
  mpgm_gmres_ws ws;      /**< Krylov workspace                           */
  double tol;            /**< the next solve's tolerance                  */
  double anorm;          /**< |A| (infinity norm) of the values held: the
                              round-off stop (a direct solve of a stiff
                              tangent leaves |b - A x| / |b| near 1e-10)  */
  double *rs;            /**< row sums of |A| (n)                         */
  int valid;             /**< the part holds a factorisation of this pattern */
  int refactor;          /**< the next factor refactorises               */
  int fresh;             /**< that factorisation is of the values held   */
  int iterations;        /**< Krylov iterations of the last solve        */
} reuse_data;

static void release(reuse_data *d) {
  free(d->A.colptr);
  free(d->A.rowind);
  free(d->A.val);
  free(d->rs);
  d->rs = NULL;
  memset(&d->A, 0, sizeof d->A);
  mpgm_gmres_ws_free(&d->ws);
  d->valid = d->fresh = d->refactor = 0;
}

static void reuse_destroy(void *data) {
  reuse_data *d = data;
  if (!d) return;
  release(d);
  mpgm_solver_destroy(&d->part);
  free(d);
}

static int reuse_create(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  MPGM_CHECK(ctx, opts->part && !opts->part->iterative && opts->refactor_iterations >= 1,
             MPGM_ERR_INPUT, "solver.newton krylov: needs a direct backend (found %s) and "
             "refactor_iterations >= 1 (found %d)", opts->part ? opts->part->name : "none",
             opts->refactor_iterations);
  reuse_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *data = d;
  d->opts = *opts;
  d->tol = opts->tol;
  mpgm_solver_opts po = *opts;
  po.part = NULL;
  return mpgm_solver_create(ctx, opts->part, &po, &d->part);
}

static int reuse_analyse(void *data, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm) {
  reuse_data *d = data;
  release(d);
  MPGM_ALLOC(ctx, d->A.colptr, A->n + 1);
  MPGM_ALLOC(ctx, d->A.rowind, A->nnz > 0 ? A->nnz : 1);
  MPGM_ALLOC(ctx, d->A.val, A->nnz > 0 ? A->nnz : 1);
  MPGM_ALLOC(ctx, d->rs, A->n);
  memcpy(d->A.colptr, A->colptr, ((size_t)A->n + 1) * sizeof(int));
  memcpy(d->A.rowind, A->rowind, (size_t)A->nnz * sizeof(int));
  d->A.n = A->n;
  d->A.nnz = A->nnz;
  MPGM_CALL(mpgm_gmres_ws_alloc(ctx, &d->ws, A->n, d->opts.restart));
  return mpgm_solver_analyse(d->part, ctx, A, perm);
}

/* The part factorises the values held. */
static int refactor(reuse_data *d, mpgm_ctx *ctx) {
  d->valid = d->fresh = 0;
  MPGM_CALL(mpgm_solver_factor(d->part, ctx, &d->A));
  d->valid = d->fresh = 1;
  d->refactor = 0;
  return MPGM_OK;
}

static int reuse_factor(void *data, mpgm_ctx *ctx, const mpgm_csc *A) {
  reuse_data *d = data;
  MPGM_CHECK(ctx, A->n == d->A.n && A->nnz == d->A.nnz, MPGM_ERR_INTERNAL,
             "reuse: factor of order %d (%d entries), analysed %d (%d)", A->n, A->nnz, d->A.n,
             d->A.nnz);
  memcpy(d->A.val, A->val, (size_t)A->nnz * sizeof(double));
  d->A.symmetric = A->symmetric;
  memset(d->rs, 0, (size_t)A->n * sizeof(double));
  for (int k = 0; k < A->nnz; k++) d->rs[A->rowind[k]] += fabs(A->val[k]);
  d->anorm = 0.0;
  for (int i = 0; i < A->n; i++) d->anorm = fmax(d->anorm, d->rs[i]);
  if (!d->valid || d->refactor) return refactor(d, ctx);
  d->fresh = 0;
  mpgm_count(ctx, MPGM_C_FACTOR_REUSES, 1);
  return MPGM_OK;
}

/* y = A x with the values held. */
static void matvec(void *user, const double *x, double *y) {
  const mpgm_csc *A = &((const reuse_data *)user)->A;
  memset(y, 0, (size_t)A->n * sizeof(double));
  for (int j = 0; j < A->n; j++) {
    const double xj = x[j];
    if (xj == 0.0) continue;
    for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) y[A->rowind[p]] += A->val[p] * xj;
  }
}

/* z = M^-1 v with the part's factors (the instance that factorised: a
 * composite's part in use). */
static int precondition(void *user, mpgm_ctx *ctx, const double *v, double *z) {
  mpgm_solver *p = mpgm_solver_part(((reuse_data *)user)->part);
  return p->type->solve(p->data, ctx, v, z);
}

/* GMRES to the tolerance; with an old factorisation, at most
 * 4 refactor_iterations before it refactorises and solves again. */
static int krylov(reuse_data *d, mpgm_ctx *ctx, const double *b, double *x, mpgm_gmres_result *r) {
  const mpgm_krylov_op op = {.user = d, .matvec = matvec, .precond = precondition,
                             .anorm = d->anorm};
  const int cap = d->fresh ? d->opts.max_iter : 4 * d->opts.refactor_iterations;
  MPGM_CALL(mpgm_gmres(&d->ws, ctx, &op, b, x, d->tol, cap, r));
  d->iterations = r->iterations;
  if (r->converged || d->fresh) return MPGM_OK;
  mpgm_timer_stop(ctx, MPGM_T_SOLVE); /* the factorisation times itself */
  const int err = refactor(d, ctx);
  mpgm_timer_start(ctx, MPGM_T_SOLVE);
  MPGM_CALL(err);
  const int before = r->iterations;
  MPGM_CALL(mpgm_gmres(&d->ws, ctx, &op, b, x, d->tol, d->opts.max_iter, r));
  r->iterations += before;
  d->iterations = r->iterations;
  return MPGM_OK;
}

/* x = K^-1 b to |b - K x| <= tol |b| (b and x may alias). */
static int reuse_solve(void *data, mpgm_ctx *ctx, const double *b, double *x) {
  reuse_data *d = data;
  MPGM_CHECK(ctx, d->valid, MPGM_ERR_INTERNAL, "reuse: solve without a factorisation");
  mpgm_gmres_result r = {0};
  mpgm_timer_start(ctx, MPGM_T_SOLVE);
  const int err = krylov(d, ctx, b, x, &r);
  mpgm_timer_stop(ctx, MPGM_T_SOLVE);
  mpgm_count(ctx, MPGM_C_SOLVES, 1);
  mpgm_count(ctx, MPGM_C_LINEAR_ITERATIONS, r.iterations);
  MPGM_CALL(err);
  if (r.iterations > d->opts.refactor_iterations) d->refactor = 1;
  if (!r.converged) {
    mpgm_count(ctx, MPGM_C_LINEAR_NOT_CONVERGED, 1);
    MPGM_ERROR(ctx, MPGM_ERR_LINEAR, "Newton-Krylov: GMRES preconditioned by a new factorisation "
               "did not converge in %d iterations: |b - K x| / |b| = %.3e > %.3e", r.iterations,
               r.relres, d->tol);
  }
  return MPGM_OK;
}

static int reuse_tolerance(void *data, double tol) {
  ((reuse_data *)data)->tol = tol;
  return MPGM_OK;
}

static int reuse_step(void *data, mpgm_ctx *ctx, int *kept) {
  reuse_data *d = data;
  MPGM_CALL(mpgm_solver_step(d->part, ctx, kept));
  if (!*kept) d->valid = 0;
  return MPGM_OK;
}

static int reuse_stats(void *data, mpgm_solver_stats *st) {
  reuse_data *d = data;
  const int err = mpgm_solver_get_stats(d->part, st);
  st->iterations = d->iterations;
  st->mem_peak += (d->A.n + 1 + d->A.nnz) * sizeof(int) + d->A.nnz * sizeof(double) +
                  mpgm_gmres_ws_bytes(d->A.n, d->ws.m);
  return err == MPGM_ERR_UNSUPPORTED ? 0 : err;
}

static const char *reuse_backend(const void *data) {
  return mpgm_solver_name(((const reuse_data *)data)->part);
}

static mpgm_solver *reuse_part(void *data) {
  return mpgm_solver_part(((reuse_data *)data)->part);
}

/* Checkpoint: the part's state (its factorisation is rebuilt). */
static int reuse_save(const void *data, mpgm_ctx *ctx, mpgm_blob *b) {
  return mpgm_solver_save(((const reuse_data *)data)->part, ctx, b);
}

static int reuse_restore(void *data, mpgm_ctx *ctx, mpgm_blob *b) {
  reuse_data *d = data;
  d->valid = 0;
  return mpgm_solver_restore(d->part, ctx, b);
}

/** Newton-Krylov: GMRES on the current matrix, preconditioned by the last
 *  factorisation of opts.part. */
const mpgm_solver_type mpgm_solver_reuse = {
    .name = "reuse",
    .doc = "GMRES preconditioned by a direct backend's last factorisation, refactorised when "
           "GMRES needs more than solver.refactor_iterations (solver.newton krylov)",
    .iterative = 1,
    .composite = 1,
    .create = reuse_create,
    .destroy = reuse_destroy,
    .analyse = reuse_analyse,
    .factor = reuse_factor,
    .solve = reuse_solve,
    .stats = reuse_stats,
    .tolerance = reuse_tolerance,
    .step = reuse_step,
    .backend = reuse_backend,
    .part = reuse_part,
    .save = reuse_save,
    .restore = reuse_restore,
};
