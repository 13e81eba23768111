/* plugin.c -- backends built as modules of their own and loaded on first
 * use: "petsc" (solvers/petsc/petsc.c, mpgm_petsc.so). The list holds a
 * stand-in record here whose create loads the module and whose operations
 * forward to the module's record, so a run that never asks for PETSc
 * never loads it, nor MPI (80 ms and a hundred libraries per command).
 * Where the module is looked for: mpgm_module.h.
 */
#include "mpgm_module.h"
#include "mpgm_petsc_options.h"
#include "mpgm_solver.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#define MODULE "mpgm_petsc.so"

static pthread_once_t load_once = PTHREAD_ONCE_INIT;
static void *handle;
static const mpgm_solver_type *real;
static void (*real_finalize)(void);

static void load(void) {
  handle = mpgm_module_open(MODULE);
  if (!handle) return;
  real = dlsym(handle, "mpgm_solver_petsc_module");
  *(void **)&real_finalize = dlsym(handle, "mpgm_solver_petsc_module_finalize");
  if (!real || !real_finalize) real = NULL;
}

int mpgm_solver_plugin_load(const char *name, char *msg, size_t len) {
  if (strcmp(name, "petsc") != 0) return 0;
  pthread_once(&load_once, load);
  if (!real && msg && len > 0) {
    if (handle) snprintf(msg, len, "%s: the module lacks its backend record", MODULE);
    else mpgm_module_why_not(MODULE, "PETSc", msg, len);
  }
  return real ? 0 : -1;
}

void mpgm_solver_plugin_finalize(void) {
  if (real_finalize) real_finalize();
  real_finalize = NULL;
}

static int px_create(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  char msg[512];
  MPGM_CHECK(ctx, mpgm_solver_plugin_load("petsc", msg, sizeof msg) == 0, MPGM_ERR_UNSUPPORTED,
             "solver petsc: %s", msg);
  return real->create(ctx, opts, data);
}
static void px_destroy(void *data) {
  if (real) real->destroy(data);
}
static int px_analyse(void *data, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm) {
  return real->analyse(data, ctx, A, perm);
}
static int px_factor(void *data, mpgm_ctx *ctx, const mpgm_csc *A) {
  return real->factor(data, ctx, A);
}
static int px_solve(void *data, mpgm_ctx *ctx, const double *b, double *x) {
  return real->solve(data, ctx, b, x);
}
static int px_stats(void *data, mpgm_solver_stats *st) { return real->stats(data, st); }
static int px_check(mpgm_ctx *ctx, const mpgm_solver_opts *opts) {
  char msg[512];
  MPGM_CHECK(ctx, mpgm_solver_plugin_load("petsc", msg, sizeof msg) == 0, MPGM_ERR_UNSUPPORTED,
             "solver petsc: %s", msg);
  return real->check(ctx, opts);
}
static int px_tolerance(void *data, double tol) { return real->tolerance(data, tol); }

/* PETSc's configurations that `mpgm bench-solvers` compares: CG or GMRES
 * with BoomerAMG, GAMG or incomplete factors, and MUMPS. */
static const mpgm_solver_preset petsc_presets[] = {
    {"cg-boomeramg", "-ksp_type cg -pc_type hypre -pc_hypre_type boomeramg", 1, 0},
    {"cg-gamg", "-ksp_type cg -pc_type gamg", 1, 0},
    {"cg-icc", "-ksp_type cg -pc_type icc", 1, 0},
    {"gmres-boomeramg", "-ksp_type gmres -pc_type hypre -pc_hypre_type boomeramg", 0, 0},
    {"gmres-gamg", "-ksp_type gmres -pc_type gamg", 0, 0},
    {"gmres-ilu", "-ksp_type gmres -pc_type ilu", 0, 0},
    {"mumps-cholesky", "-ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps -mat_mumps_icntl_10 -2", 1, 1},
    {"mumps-lu", "-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps -mat_mumps_icntl_10 -2", 0, 1},
    {NULL, NULL, 0, 0}};

/* solver.petsc held to mpgm's policy (mpgm_petsc_options.h) when the
 * scene loads, without PETSc; what PETSc makes of it is px_check's. */
static int petsc_policy(const void *field, char *why, size_t len) {
  char r[360];
  if (!mpgm_petsc_options_parse(field, NULL, r, sizeof r)) return 0;
  snprintf(why, len, "%s (docs/scene-format.md, \"PETSc options are confined\")", r);
  return 1;
}

static const mpgm_key_spec petsc_keys[] = {
    {.name = "petsc", .type = MPGM_KEY_STRING, .offset = offsetof(mpgm_solver_opts, petsc),
     .size = sizeof(((mpgm_solver_opts *)0)->petsc), .valid = petsc_policy, .unit = "-",
     .doc = "PETSc's KSP and PC options in its command-line syntax; \"\": CG + ICC(0) or GMRES + ILU(0)"},
};

/** PETSc's KSP + PC, loaded from mpgm_petsc.so on first use. */
const mpgm_solver_type mpgm_solver_petsc = {
    .name = "petsc",
    .doc = "PETSc Krylov solver and preconditioner (default CG + ICC(0) or GMRES + ILU(0); "
           "BoomerAMG, GAMG, MUMPS through solver.petsc)",
    .needs_spd = 0,
    .iterative = 1,
    .presets = petsc_presets,
    .keys = petsc_keys,
    .nkeys = sizeof petsc_keys / sizeof *petsc_keys,
    /* loaded with MPI as a module: 36 MiB resident on the column collapse
     * at h = 0.2 against UMFPACK (bench/notes/memory.md) */
    .library_bytes = 32.0 * 1048576.0,
    .create = px_create,
    .destroy = px_destroy,
    .analyse = px_analyse,
    .factor = px_factor,
    .solve = px_solve,
    .stats = px_stats,
    .tolerance = px_tolerance,
    .check = px_check,
};
