/* auto.c -- the composite backend "auto": Cholesky (CHOLMOD) for symmetric
 * matrices with an LU (UMFPACK) fallback, LU alone for unsymmetric ones.
 *
 * A symmetric tangent is usually positive definite, and Cholesky then costs
 * half of LU. It is not always: geometric stiffness under compression, a
 * light node in a compressed region. When Cholesky refuses the matrix
 * (MPGM_ERR_SINGULAR), the same matrix is factorised by LU, and LU is kept
 * for that step and the next hold - 1 steps (the hold doubles, 1, 2, 4, ...
 * 64, while Cholesky keeps failing when it is tried again, and is reset by
 * a success). A tangent that is indefinite for a few steps then costs LU
 * only on those steps; one that stays indefinite costs a failed Cholesky
 * every 64 steps. The holds are counted in steps: the caller says when a
 * new step begins (mpgm_solver_step).
 *
 * The parts are full instances called through the generic wrappers, so
 * their analyses, factorisations and solves are timed and counted as the
 * parts' own; the composite itself is neither timed nor counted
 * (type->composite). The LU part is created and analysed when it is first
 * needed; a new pattern (analyse) analyses the part in use and marks the
 * other one for analysis when it is next used.
 */
#include "mpgm_solver.h"

#include <limits.h>
#include <stdlib.h>

extern const mpgm_solver_type mpgm_solver_cholmod;
extern const mpgm_solver_type mpgm_solver_umfpack;

/* longest run of steps on LU before Cholesky is tried again */
#define HOLD_MAX 64

typedef struct auto_data {
  mpgm_solver_opts opts; /**< handed to the parts                      */
  mpgm_solver *chol;    /**< Cholesky part; NULL for unsymmetric matrices */
  mpgm_solver *lu;      /**< LU part (created when first needed)        */
  mpgm_solver *active;  /**< the part that factorises now               */
  const int *perm;      /**< ordering of the last analyse (borrowed)    */
  int n;                /**< order of the analysed matrix                */
  int hold;             /**< steps on LU left before Cholesky again     */
  int hold_len;         /**< length of the last hold (0 after a success) */
  long switches;        /**< falls from Cholesky to LU                   */
  long lu_steps;        /**< steps solved with the LU fallback           */
} auto_data;

static void auto_destroy(void *data) {
  auto_data *d = data;
  if (!d) return;
  mpgm_solver_destroy(&d->chol);
  mpgm_solver_destroy(&d->lu);
  free(d);
}

static int auto_create(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  auto_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *data = d;
  d->opts = *opts;
  if (opts->symmetric) {
    MPGM_CALL(mpgm_solver_create(ctx, &mpgm_solver_cholmod, opts, &d->chol));
    d->active = d->chol;
  } else {
    MPGM_CALL(mpgm_solver_create(ctx, &mpgm_solver_umfpack, opts, &d->lu));
    d->active = d->lu;
  }
  return 0;
}

/* The part in use, analysed for the current pattern. */
static int ready(auto_data *d, mpgm_ctx *ctx, const mpgm_csc *A) {
  if (!d->active->analysed) MPGM_CALL(mpgm_solver_analyse(d->active, ctx, A, d->perm));
  return 0;
}

static int auto_analyse(void *data, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm) {
  auto_data *d = data;
  /* a matrix that is not symmetric goes to LU for good */
  if (!A->symmetric && d->chol) {
    if (!d->lu) MPGM_CALL(mpgm_solver_create(ctx, &mpgm_solver_umfpack, &d->opts, &d->lu));
    mpgm_solver_destroy(&d->chol);
    d->active = d->lu;
  }
  d->perm = perm;
  d->n = A->n;
  if (d->chol) d->chol->analysed = 0;
  if (d->lu) d->lu->analysed = 0;
  return ready(d, ctx, A);
}

/* Cholesky refused A: LU factorises it, for this step and hold_len - 1
 * more. Returns LU's code. */
static int fall_back(auto_data *d, mpgm_ctx *ctx, const mpgm_csc *A) {
  if (!d->lu) MPGM_CALL(mpgm_solver_create(ctx, &mpgm_solver_umfpack, &d->opts, &d->lu));
  mpgm_err_clear(ctx);
  d->active = d->lu;
  d->switches++;
  d->lu_steps++;
  d->hold_len = d->hold_len ? 2 * d->hold_len : 1;
  if (d->hold_len > HOLD_MAX) d->hold_len = HOLD_MAX;
  d->hold = d->hold_len;
  MPGM_CALL(ready(d, ctx, A));
  return mpgm_solver_factor(d->active, ctx, A);
}

static int auto_factor(void *data, mpgm_ctx *ctx, const mpgm_csc *A) {
  auto_data *d = data;
  MPGM_CALL(ready(d, ctx, A));
  const int err = mpgm_solver_factor(d->active, ctx, A);
  if (d->active != d->chol) return err;
  if (err == MPGM_ERR_SINGULAR) return fall_back(d, ctx, A);
  if (!err) d->hold_len = 0; /* Cholesky works again */
  return err;
}

static int auto_solve(void *data, mpgm_ctx *ctx, const double *b, double *x) {
  auto_data *d = data;
  return mpgm_solver_solve(d->active, ctx, b, x);
}

static int auto_solve_many(void *data, mpgm_ctx *ctx, int nrhs, const double *B, double *X) {
  auto_data *d = data;
  return mpgm_solver_solve_many(d->active, ctx, d->n, nrhs, B, X);
}

/* A new step: on LU, count the step, or go back to Cholesky when the hold
 * has run out (the factorisation held is then not the part's in use). */
static int auto_step(void *data, mpgm_ctx *ctx, int *kept) {
  (void)ctx;
  auto_data *d = data;
  *kept = 1;
  if (!d->chol || d->active == d->chol) return 0;
  if (--d->hold <= 0) {
    d->active = d->chol;
    *kept = 0;
  } else {
    d->lu_steps++;
  }
  return 0;
}

static int auto_stats(void *data, mpgm_solver_stats *st) {
  auto_data *d = data;
  const int err = mpgm_solver_get_stats(d->active, st);
  st->switches = d->switches;
  st->fallback_steps = d->lu_steps;
  return err == MPGM_ERR_UNSUPPORTED ? 0 : err;
}

static const char *auto_backend(const void *data) {
  const auto_data *d = data;
  return (d->chol ? d->chol : d->lu)->type->name;
}

static mpgm_solver *auto_part(void *data) { return ((auto_data *)data)->active; }

/* Checkpoint: the part in use and the holds (the parts' factorisations are
 * rebuilt). {lu active, chol present, hold, hold_len} and the tallies. */
typedef struct auto_state {
  int on_lu, has_chol, hold, hold_len;
  long switches, lu_steps;
} auto_state;

static int auto_save(const void *data, mpgm_ctx *ctx, mpgm_blob *b) {
  const auto_data *d = data;
  const auto_state st = {d->active == d->lu, d->chol != NULL, d->hold, d->hold_len, d->switches,
                         d->lu_steps};
  return mpgm_blob_put(ctx, b, "solver.auto", &st, sizeof st);
}

static int auto_restore(void *data, mpgm_ctx *ctx, mpgm_blob *b) {
  auto_data *d = data;
  auto_state st;
  MPGM_CALL(mpgm_blob_get(ctx, b, "solver.auto", &st, sizeof st));
  MPGM_CHECK(ctx,
             (st.on_lu == 0 || st.on_lu == 1) && (st.has_chol == 0 || st.has_chol == 1) &&
                 st.hold >= 0 && st.hold <= HOLD_MAX && st.hold_len >= 0 &&
                 st.hold_len <= HOLD_MAX && st.switches >= 0 && st.switches <= LONG_MAX / 2 &&
                 st.lu_steps >= 0 && st.lu_steps <= LONG_MAX / 2,
             MPGM_ERR_INPUT,
             "checkpoint: section 'solver.auto': out of range (LU %d, Cholesky %d, "
             "hold %d of %d, %ld switches, %ld LU steps)",
             st.on_lu, st.has_chol, st.hold, st.hold_len, st.switches, st.lu_steps);
  /* checked before anything changes: a refused section leaves the solver
   * as it was (with a part in use, which the run's report reads) */
  MPGM_CHECK(ctx, st.on_lu || st.has_chol, MPGM_ERR_INPUT,
             "checkpoint: section 'solver.auto': Cholesky in use but absent");
  if (!st.has_chol) mpgm_solver_destroy(&d->chol); /* a matrix was not symmetric */
  if (st.on_lu && !d->lu) MPGM_CALL(mpgm_solver_create(ctx, &mpgm_solver_umfpack, &d->opts, &d->lu));
  d->active = st.on_lu ? d->lu : d->chol;
  MPGM_CHECK(ctx, d->active, MPGM_ERR_INPUT, "checkpoint: solver auto without a part in use");
  if (d->chol) d->chol->analysed = 0;
  if (d->lu) d->lu->analysed = 0;
  d->hold = st.hold, d->hold_len = st.hold_len, d->switches = st.switches, d->lu_steps = st.lu_steps;
  return 0;
}

const mpgm_solver_type mpgm_solver_auto = {
    .name = "auto",
    .doc = "CHOLMOD for symmetric matrices, UMFPACK when one is not positive definite "
           "(held 1, 2, 4, ... 64 steps) or not symmetric",
    .needs_spd = 0,
    .composite = 1,
    .create = auto_create,
    .destroy = auto_destroy,
    .analyse = auto_analyse,
    .factor = auto_factor,
    .solve = auto_solve,
    .solve_many = auto_solve_many,
    .stats = auto_stats,
    .step = auto_step,
    .backend = auto_backend,
    .part = auto_part,
    .save = auto_save,
    .restore = auto_restore,
};
