/* plugin.c -- backends built as modules of their own and loaded on first
 * use: "petsc" (solvers/petsc/petsc.c, mpgm_petsc.so). The list holds a
 * stand-in record here whose create loads the module and whose operations
 * forward to the module's record, so a run that never asks for PETSc
 * never loads it, nor MPI (80 ms and a hundred libraries per command).
 *
 * The module is looked for in $MPGM_PLUGIN_DIR, then beside the running
 * executable, then in the build folder it was built in (MPGM_PLUGIN_DIR_BUILT,
 * so that the unit tests in build/tests find it too).
 */
#define _GNU_SOURCE /* dladdr-free: readlink of /proc/self/exe */
#include "mpgm_solver.h"

#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef MPGM_PLUGIN_DIR_BUILT
#define MPGM_PLUGIN_DIR_BUILT ""
#endif

#define MODULE "mpgm_petsc.so"

static pthread_once_t load_once = PTHREAD_ONCE_INIT;
static void *handle;
static const mpgm_solver_type *real;
static void (*real_finalize)(void);
static char why[PATH_MAX + 512]; /* why the module could not be loaded */

/* dlopen dir/MODULE; 1 on success. */
static int try_dir(const char *dir) {
  if (!dir || !*dir) return 0;
  char path[PATH_MAX + 64];
  snprintf(path, sizeof path, "%s/%s", dir, MODULE);
  if (access(path, R_OK) != 0) return 0;
  handle = dlopen(path, RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char *e = dlerror();
    snprintf(why, sizeof why, "%.*s: %.400s", PATH_MAX, path, e ? e : "dlopen failed");
    return 0;
  }
  return 1;
}

static void load(void) {
  char exe[PATH_MAX];
  const ssize_t l = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (l > 0) {
    exe[l] = '\0';
    char *slash = strrchr(exe, '/');
    if (slash) *slash = '\0';
  } else {
    exe[0] = '\0';
  }
  snprintf(why, sizeof why, "%s not found in $MPGM_PLUGIN_DIR, %s or %s (mpgm was built without "
           "PETSc: install petsc-dev, as scripts/setup.sh does, and build again)", MODULE,
           exe[0] ? exe : "the executable's folder", *MPGM_PLUGIN_DIR_BUILT ? MPGM_PLUGIN_DIR_BUILT
                                                                        : "the build folder");
  if (!try_dir(getenv("MPGM_PLUGIN_DIR")) && !try_dir(exe) && !try_dir(MPGM_PLUGIN_DIR_BUILT))
    return;
  real = dlsym(handle, "mpgm_solver_petsc_module");
  *(void **)&real_finalize = dlsym(handle, "mpgm_solver_petsc_module_finalize");
  if (!real || !real_finalize) {
    snprintf(why, sizeof why, "%s: the module lacks its backend record", MODULE);
    real = NULL;
  }
}

int mpgm_solver_plugin_load(const char *name, char *msg, size_t len) {
  if (strcmp(name, "petsc") != 0) return 0;
  pthread_once(&load_once, load);
  if (!real && msg) snprintf(msg, len, "%.*s", (int)(len > 0 ? len - 1 : 0), why);
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

/** PETSc's KSP + PC, loaded from mpgm_petsc.so on first use. */
const mpgm_solver_type mpgm_solver_petsc = {
    .name = "petsc",
    .doc = "PETSc Krylov solver and preconditioner (default CG + ICC(0) or GMRES + ILU(0); "
           "BoomerAMG, GAMG, MUMPS through solver.petsc)",
    .needs_spd = 0,
    .iterative = 1,
    .presets = petsc_presets,
    .create = px_create,
    .destroy = px_destroy,
    .analyse = px_analyse,
    .factor = px_factor,
    .solve = px_solve,
    .stats = px_stats,
    .tolerance = px_tolerance,
};
