/* solver.c -- the backend list and the generic wrappers of the linear
 * solver family (timers and counters live here, not in the backends).
 * Adding a backend: write its .c, add one line to MPGM_SOLVER_LIST. */
#define _GNU_SOURCE /* RTLD_DEFAULT */
#include "mpgm_solver.h"

#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MPGM_SOLVER_LIST(X)                                                    \
  X(mpgm_solver_auto)                                                          \
  X(mpgm_solver_cholmod)                                                       \
  X(mpgm_solver_cholmod_simplicial)                                            \
  X(mpgm_solver_cholmod_supernodal)                                            \
  X(mpgm_solver_umfpack)                                                       \
  X(mpgm_solver_klu)                                                           \
  X(mpgm_solver_petsc) /* a module loaded on first use: plugin.c */

int mpgm_solver_plugin_load(const char *name, char *msg, size_t len); /* plugin.c */
void mpgm_solver_plugin_finalize(void);

#define MPGM_DECLARE(t) extern const mpgm_solver_type t;
MPGM_SOLVER_LIST(MPGM_DECLARE)
#undef MPGM_DECLARE

#define MPGM_ADDR(t) &t,
static const mpgm_solver_type *const all_types[] = {
    MPGM_SOLVER_LIST(MPGM_ADDR) NULL};
#undef MPGM_ADDR

/** All backends, NULL-terminated. */
const mpgm_solver_type *const *mpgm_solver_types(void) { return all_types; }

/** The backend named `name`; NULL if none (or name NULL). */
const mpgm_solver_type *mpgm_solver_type_find(const char *name) {
  if (!name) return NULL;
  for (int i = 0; all_types[i]; i++)
    if (strcmp(all_types[i]->name, name) == 0) return all_types[i];
  return NULL;
}

mpgm_solver_opts mpgm_solver_opts_default(void) {
  return (mpgm_solver_opts){.tol = 1e-10, .restart = 100, .max_iter = 5000, .symmetric = 1,
                            .refactor_iterations = 20};
}

int mpgm_solver_usable(const char *name, char *msg, size_t len) {
  if (!mpgm_solver_type_find(name)) {
    if (msg) snprintf(msg, len, "no backend \"%s\"", name);
    return 0;
  }
  return mpgm_solver_plugin_load(name, msg, len) == 0;
}

void mpgm_solver_finalize(void) { mpgm_solver_plugin_finalize(); }

int mpgm_solver_check(mpgm_ctx *ctx, const mpgm_solver_type *type, const mpgm_solver_opts *opts) {
  MPGM_CHECK(ctx, type != NULL && opts != NULL, MPGM_ERR_INPUT, "mpgm_solver_check: NULL argument");
  return type->check ? type->check(ctx, opts) : MPGM_OK;
}

/** Create an instance of `type` with options opts (NULL: the defaults)
 *  in *out (NULL on failure).
 *  Errors: MPGM_ERR_INPUT (NULL arguments, options out of range),
 *  MPGM_ERR_UNSUPPORTED (no create), MPGM_ERR_NOMEM, or the backend's
 *  code. A backend's create may leave half-built data behind on failure:
 *  it is released here. */
int mpgm_solver_create(mpgm_ctx *ctx, const mpgm_solver_type *type,
                       const mpgm_solver_opts *opts, mpgm_solver **out) {
  MPGM_CHECK(ctx, out != NULL && type != NULL, MPGM_ERR_INPUT,
             "mpgm_solver_create: NULL argument");
  *out = NULL;
  MPGM_CHECK(ctx, type->create != NULL, MPGM_ERR_UNSUPPORTED,
             "solver %s: no create operation", type->name);
  const mpgm_solver_opts def = mpgm_solver_opts_default();
  if (!opts) opts = &def;
  MPGM_CHECK(ctx, opts->tol > 0.0 && opts->tol < 1.0 && opts->restart >= 1 && opts->max_iter >= 1,
             MPGM_ERR_INPUT, "solver %s: options out of range (tol %g in (0, 1), restart %d >= 1, "
             "max_iter %d >= 1)", type->name, opts->tol, opts->restart, opts->max_iter);
  mpgm_solver *s;
  MPGM_ALLOC(ctx, s, 1);
  s->type = type;
  s->data = NULL;
  s->analysed = 0;
  int ierr = type->create(ctx, opts, &s->data);
  if (ierr) {
    mpgm_solver_destroy(&s);
    return ierr;
  }
  *out = s;
  return MPGM_OK;
}

/** Release an instance and set *s to NULL; accepts s == NULL, *s == NULL
 *  and half-built instances. */
void mpgm_solver_destroy(mpgm_solver **s) {
  if (!s || !*s) return;
  if ((*s)->type && (*s)->type->destroy) (*s)->type->destroy((*s)->data);
  free(*s);
  *s = NULL;
}

/* Cheap consistency checks of a matrix handed to a backend. */
static int check_csc(mpgm_ctx *ctx, const mpgm_solver *s, const mpgm_csc *A) {
  MPGM_CHECK(ctx, A != NULL, MPGM_ERR_INPUT, "solver %s: NULL matrix",
             s->type->name);
  MPGM_CHECK(ctx, A->n > 0, MPGM_ERR_INPUT,
             "solver %s: matrix of order %d", s->type->name, A->n);
  MPGM_CHECK(ctx, A->colptr && A->rowind && A->val, MPGM_ERR_INTERNAL,
             "solver %s: matrix arrays missing", s->type->name);
  MPGM_CHECK(ctx, A->colptr[0] == 0 && A->colptr[A->n] == A->nnz,
             MPGM_ERR_INTERNAL,
             "solver %s: colptr[0] = %d, colptr[n] = %d, nnz = %d",
             s->type->name, A->colptr[0], A->colptr[A->n], A->nnz);
  return MPGM_OK;
}

/** Symbolic analysis of A's pattern (call again when the pattern changes).
 *  Times MPGM_T_ANALYSE, counts ctx->count[MPGM_C_ANALYSES] (every call that reaches
 *  the backend). Errors: MPGM_ERR_INPUT, MPGM_ERR_UNSUPPORTED, backend's. */
int mpgm_solver_analyse(mpgm_solver *s, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm) {
  MPGM_CHECK(ctx, s != NULL, MPGM_ERR_INPUT, "mpgm_solver_analyse: NULL solver");
  if (!s->type->analyse)
    MPGM_ERROR(ctx, MPGM_ERR_UNSUPPORTED, "solver %s: no analyse operation",
               s->type->name);
  MPGM_CALL(check_csc(ctx, s, A));
  s->analysed = 0;
  if (s->type->composite) { /* its parts time and count themselves */
    MPGM_CALL(s->type->analyse(s->data, ctx, A, perm));
    s->analysed = 1;
    return MPGM_OK;
  }
  mpgm_timer_start(ctx, MPGM_T_ANALYSE);
  int ierr = s->type->analyse(s->data, ctx, A, perm);
  mpgm_timer_stop(ctx, MPGM_T_ANALYSE);
  mpgm_count(ctx, MPGM_C_ANALYSES, 1);
  if (ierr) return ierr;
  s->analysed = 1;
  return MPGM_OK;
}

/** Numeric factorisation of A (pattern as analysed). Times MPGM_T_FACTOR,
 *  counts ctx->count[MPGM_C_FACTORIZATIONS]. Errors: MPGM_ERR_SINGULAR (recoverable:
 *  singular / not positive definite), MPGM_ERR_INTERNAL (not analysed),
 *  MPGM_ERR_UNSUPPORTED, backend's. */
int mpgm_solver_factor(mpgm_solver *s, mpgm_ctx *ctx, const mpgm_csc *A) {
  MPGM_CHECK(ctx, s != NULL, MPGM_ERR_INPUT, "mpgm_solver_factor: NULL solver");
  if (!s->type->factor)
    MPGM_ERROR(ctx, MPGM_ERR_UNSUPPORTED, "solver %s: no factor operation",
               s->type->name);
  MPGM_CALL(check_csc(ctx, s, A));
  MPGM_CHECK(ctx, s->analysed, MPGM_ERR_INTERNAL,
             "solver %s: factor called before analyse", s->type->name);
  if (s->type->composite) return s->type->factor(s->data, ctx, A);
  mpgm_timer_start(ctx, MPGM_T_FACTOR);
  int ierr = s->type->factor(s->data, ctx, A);
  mpgm_timer_stop(ctx, MPGM_T_FACTOR);
  mpgm_count(ctx, MPGM_C_FACTORIZATIONS, 1);
  return ierr;
}

/** x = A^-1 b with the last factorisation (b and x of length n, may
 *  alias). Times MPGM_T_SOLVE, counts ctx->count[MPGM_C_SOLVES] (and the iterations
 *  of an iterative backend in ctx->count[MPGM_C_LINEAR_ITERATIONS], also when it did
 *  not converge, and such a solve in ctx->count[MPGM_C_LINEAR_NOT_CONVERGED]). Errors: MPGM_ERR_INPUT, MPGM_ERR_UNSUPPORTED,
 *  MPGM_ERR_LINEAR (iterative, recoverable), backend's. */
int mpgm_solver_solve(mpgm_solver *s, mpgm_ctx *ctx, const double *b,
                      double *x) {
  MPGM_CHECK(ctx, s != NULL && b != NULL && x != NULL, MPGM_ERR_INPUT,
             "mpgm_solver_solve: NULL argument");
  if (!s->type->solve)
    MPGM_ERROR(ctx, MPGM_ERR_UNSUPPORTED, "solver %s: no solve operation",
               s->type->name);
  if (s->type->composite) return s->type->solve(s->data, ctx, b, x);
  mpgm_timer_start(ctx, MPGM_T_SOLVE);
  int ierr = s->type->solve(s->data, ctx, b, x);
  mpgm_timer_stop(ctx, MPGM_T_SOLVE);
  mpgm_count(ctx, MPGM_C_SOLVES, 1);
  mpgm_solver_stats st;
  if (s->type->iterative && mpgm_solver_get_stats(s, &st) == 0)
    mpgm_count(ctx, MPGM_C_LINEAR_ITERATIONS, st.iterations);
  if (ierr == MPGM_ERR_LINEAR) mpgm_count(ctx, MPGM_C_LINEAR_NOT_CONVERGED, 1);
  return ierr;
}

int mpgm_solver_solve_many(mpgm_solver *s, mpgm_ctx *ctx, int n, int nrhs, const double *B,
                           double *X) {
  MPGM_CHECK(ctx, s != NULL && B != NULL && X != NULL && nrhs >= 0 && n > 0, MPGM_ERR_INPUT,
             "mpgm_solver_solve_many: NULL argument or no equations");
  if (!s->type->solve_many) {
    for (int j = 0; j < nrhs; j++)
      MPGM_CALL(mpgm_solver_solve(s, ctx, B + (size_t)j * n, X + (size_t)j * n));
    return 0;
  }
  if (s->type->composite) return s->type->solve_many(s->data, ctx, nrhs, B, X);
  mpgm_timer_start(ctx, MPGM_T_SOLVE);
  const int ierr = s->type->solve_many(s->data, ctx, nrhs, B, X);
  mpgm_timer_stop(ctx, MPGM_T_SOLVE);
  mpgm_count(ctx, MPGM_C_SOLVES, nrhs);
  return ierr;
}

/** Statistics of the last factorisation into *st (zeroed first).
 *  Returns MPGM_ERR_UNSUPPORTED when the backend has no stats operation
 *  (there is no context to record a message in), MPGM_ERR_INPUT on NULL. */
int mpgm_solver_get_stats(mpgm_solver *s, mpgm_solver_stats *st) {
  if (!s || !st) return MPGM_ERR_INPUT;
  memset(st, 0, sizeof(*st));
  if (!s->type->stats) return MPGM_ERR_UNSUPPORTED;
  return s->type->stats(s->data, st);
}

int mpgm_solver_tolerance(mpgm_solver *s, double tol) {
  if (!s || !(tol > 0.0 && tol < 1.0)) return MPGM_ERR_INPUT;
  return s->type->tolerance ? s->type->tolerance(s->data, tol) : MPGM_OK;
}

int mpgm_solver_step(mpgm_solver *s, mpgm_ctx *ctx, int *kept) {
  *kept = 1;
  return s && s->type->step ? s->type->step(s->data, ctx, kept) : MPGM_OK;
}

const char *mpgm_solver_name(const mpgm_solver *s) {
  return s->type->backend ? s->type->backend(s->data) : s->type->name;
}

int mpgm_solver_save(const mpgm_solver *s, mpgm_ctx *ctx, mpgm_blob *b) {
  char name[MPGM_BLOB_TAG] = "";
  snprintf(name, sizeof name, "%s", s->type->name);
  MPGM_CALL(mpgm_blob_put(ctx, b, "solver", name, sizeof name));
  return s->type->save ? s->type->save(s->data, ctx, b) : 0;
}

int mpgm_solver_restore(mpgm_solver *s, mpgm_ctx *ctx, mpgm_blob *b) {
  char name[MPGM_BLOB_TAG], want[MPGM_BLOB_TAG] = "";
  snprintf(want, sizeof want, "%s", s->type->name);
  MPGM_CALL(mpgm_blob_get(ctx, b, "solver", name, sizeof name));
  name[MPGM_BLOB_TAG - 1] = '\0';
  MPGM_CHECK(ctx, strcmp(name, want) == 0, MPGM_ERR_INPUT,
             "checkpoint: written with solver \"%s\", this run uses \"%s\"", name, want);
  s->analysed = 0;
  return s->type->restore ? s->type->restore(s->data, ctx, b) : 0;
}

mpgm_solver *mpgm_solver_part(mpgm_solver *s) {
  return s->type->part ? s->type->part(s->data) : s;
}

int mpgm_solver_threads(int n) {
  if (n <= 0) return 0;
  int applied = 0;
  /* OpenBLAS; other BLAS libraries have no such call (nothing to do) */
  void (*blas)(int) = (void (*)(int))dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
  if (blas) {
    blas(n);
    applied |= 1;
  }
  /* max active levels 0: every parallel region runs on one thread (the
   * num_threads clauses of the library cannot raise it) */
  void (*levels)(int) = (void (*)(int))dlsym(RTLD_DEFAULT, "omp_set_max_active_levels");
  if (levels) {
    levels(0);
    applied |= 2;
  }
  return applied;
}
