/* mpgm_parallel_ops.h -- what the module mpgm_par.so gives the loader for
 * the partitioned grid (mpgm_parallel.h): its record of operations,
 * "mpgm_par_module_grid". Each returns 0, or -1 with the reason in msg. */
#ifndef MPGM_PARALLEL_OPS_H
#define MPGM_PARALLEL_OPS_H

#include <stddef.h>

typedef struct mpgm_pgrid mpgm_pgrid;

typedef struct mpgm_pgrid_ops {
  int (*create)(void *comm, int dim, const int n[3], int dof, int width, const double *const w[3],
                mpgm_pgrid **g, char *msg, size_t len);
  void (*destroy)(mpgm_pgrid *g);
  void (*boxes)(const mpgm_pgrid *g, int lo[3], int hi[3], int glo[3], int ghi[3]);
  int (*owner)(const mpgm_pgrid *g, const int ijk[3]);
  int (*sum)(mpgm_pgrid *g, int n, const int *ijk, int w, double *val, char *msg, size_t len);
  int (*migrate)(mpgm_pgrid *g, int rec, int nout, const double *out, const int *dest, int *nin,
                 double **in, char *msg, size_t len);
} mpgm_pgrid_ops;

#endif
