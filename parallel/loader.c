/* loader.c -- the launcher's environment, and the module that starts MPI
 * (mpgm_parallel.h). */
#include "mpgm_parallel.h"

#include "mpgm_module.h"
#include "mpgm_parallel_ops.h"

#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>

#define MODULE "mpgm_par.so"

int mpgm_parallel_launched(int *rank, const char **var) {
  static const char *const sizes[][2] = {{"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"},
                                         {"PMI_SIZE", "PMI_RANK"},
                                         {"MV2_COMM_WORLD_SIZE", "MV2_COMM_WORLD_RANK"}};
  *rank = 0;
  *var = NULL;
  for (size_t i = 0; i < sizeof sizes / sizeof *sizes; i++) {
    const char *s = getenv(sizes[i][0]), *r = getenv(sizes[i][1]);
    const long n = s ? strtol(s, NULL, 10) : 0;
    if (n > 1) {
      *rank = r ? (int)strtol(r, NULL, 10) : 0;
      *var = sizes[i][0];
      return n > 1000000 ? 1000000 : (int)n;
    }
  }
  return 1;
}

typedef int (*start_fn)(const mpgm_comm **comm, char *msg, size_t len);
static void (*finalize_fn)(void);
static const mpgm_pgrid_ops *grid_ops;

int mpgm_parallel_start(const mpgm_comm **comm, char *msg, size_t len) {
  *comm = NULL;
  msg[0] = '\0';
  static void *handle;
  if (handle) {
    snprintf(msg, len, "MPI was started once already in this process");
    return -1;
  }
  handle = mpgm_module_open(MODULE);
  if (!handle) {
    mpgm_module_why_not(MODULE, "MPI and PETSc", msg, len);
    return -1;
  }
  start_fn start;
  *(void **)&start = dlsym(handle, "mpgm_par_module_start");
  *(void **)&finalize_fn = dlsym(handle, "mpgm_par_module_finalize");
  grid_ops = dlsym(handle, "mpgm_par_module_grid");
  if (!start || !finalize_fn || !grid_ops) {
    snprintf(msg, len, "%s: the module lacks its start or its end", MODULE);
    finalize_fn = NULL;
    return -1;
  }
  return start(comm, msg, len);
}

void mpgm_parallel_finalize(void) {
  if (finalize_fn) finalize_fn();
  finalize_fn = NULL;
}

/* ---- the partitioned grid, through the module's record ----------------- */

int mpgm_pgrid_create(mpgm_ctx *ctx, int dim, const int n[3], int dof, int width,
                      const double *const weight[3], mpgm_pgrid **g) {
  *g = NULL;
  MPGM_CHECK(ctx, ctx->comm && grid_ops, MPGM_ERR_INTERNAL,
             "a partitioned grid needs the processes started (mpgm_parallel_start)");
  char msg[512];
  if (grid_ops->create(ctx->comm->impl, dim, n, dof, width, weight, g, msg, sizeof msg) == 0) return 0;
  mpgm_pgrid_destroy(g);
  MPGM_ERROR(ctx, MPGM_ERR_INTERNAL, "process %d: the partitioned grid: %s", ctx->comm->rank, msg);
}

void mpgm_pgrid_destroy(mpgm_pgrid **g) {
  if (*g && grid_ops) grid_ops->destroy(*g);
  *g = NULL;
}

void mpgm_pgrid_boxes(const mpgm_pgrid *g, int lo[3], int hi[3], int glo[3], int ghi[3]) {
  grid_ops->boxes(g, lo, hi, glo, ghi);
}

int mpgm_pgrid_owner(const mpgm_pgrid *g, const int ijk[3]) { return grid_ops->owner(g, ijk); }

int mpgm_pgrid_sum(mpgm_ctx *ctx, mpgm_pgrid *g, int n, const int *ijk, int w, double *val) {
  char msg[512];
  MPGM_CHECK(ctx, grid_ops->sum(g, n, ijk, w, val, msg, sizeof msg) == 0, MPGM_ERR_INTERNAL,
             "process %d: the sums at shared nodes: %s", ctx->comm->rank, msg);
  return 0;
}

int mpgm_pgrid_migrate(mpgm_ctx *ctx, mpgm_pgrid *g, int rec, int nout, const double *out,
                       const int *dest, int *nin, double **in) {
  char msg[512];
  MPGM_CHECK(ctx, grid_ops->migrate(g, rec, nout, out, dest, nin, in, msg, sizeof msg) == 0,
             MPGM_ERR_INTERNAL, "process %d: the points' migration: %s", ctx->comm->rank, msg);
  return 0;
}
