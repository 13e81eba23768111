/* mpgm_parallel.h -- a run on many processes (issue 54): MPI and PETSc
 * started by the program (app/) when an MPI launcher started it as one of
 * several, and ended when it ends; the context's communicator
 * (mpgm_comm, mpgm_base.h) over them.
 *
 * MPI and PETSc live in a module of their own (parallel/mpi/par.c,
 * mpgm_par.so, found as mpgm_module.h says), so that a run on one process
 * -- without a launcher, or under mpiexec -n 1 -- neither loads nor starts
 * them: it runs exactly as it always has. */
#ifndef MPGM_PARALLEL_H
#define MPGM_PARALLEL_H

#include "mpgm_base.h"

/** The number of processes an MPI launcher started, known from its
 *  environment before MPI starts (Open MPI's OMPI_COMM_WORLD_SIZE, PMI_SIZE
 *  of MPICH, Intel MPI and Slurm's PMI, MVAPICH's MV2_COMM_WORLD_SIZE): 1
 *  when none says more. *rank is this process's, *var the variable that
 *  told (NULL for 1). */
int mpgm_parallel_launched(int *rank, const char **var);

/** Load mpgm_par.so and start MPI (MPI_Init_thread, MPI_THREAD_FUNNELED:
 *  only the main thread calls MPI) and PETSc over it: *comm is the
 *  run's communicator, valid until mpgm_parallel_finalize. Once per
 *  process. 0, or -1 with the reason in msg (len bytes). */
int mpgm_parallel_start(const mpgm_comm **comm, char *msg, size_t len);

/** End PETSc and MPI if mpgm_parallel_start started them (app/ calls it
 *  at exit; nothing otherwise). */
void mpgm_parallel_finalize(void);

/* ---- Partitioned grid -------------------------------------------------
 * A structured grid of n[0] x n[1] (x n[2]) nodes, numbered (i, j, k),
 * partitioned over the run's processes in boxes (PETSc's DMDA): each
 * process owns the nodes lo <= (i, j, k) < hi and sees a ghosted box
 * `width` nodes wider on each side; a cell (i, j, k) -- the nodes i .. i+1
 * in each direction -- belongs to the process that owns its node (i, j, k).
 * A process's points lie in its own cells, so the nodes their shape
 * functions reach lie in its ghosted box when the width covers the reach. */
typedef struct mpgm_pgrid mpgm_pgrid;

/** The partition of the context's processes (ctx->comm) with dof values
 *  per node. PETSc chooses how many processes share each direction; where
 *  they cut it, weight says (NULL: even slabs of nodes): weight[d][i], for
 *  the n[d] nodes of direction d, is the work of the cells whose lowest
 *  node has index i there (a grid's points per layer of cells), and the
 *  cuts give each slab as near an equal share of it as the stencil allows
 *  (each slab at least width + 1 nodes). All processes call it with the
 *  same arguments. */
int mpgm_pgrid_create(mpgm_ctx *ctx, int dim, const int n[3], int dof, int width,
                      const double *const weight[3], mpgm_pgrid **g);
/** Free it (NULL-safe; all processes). */
void mpgm_pgrid_destroy(mpgm_pgrid **g);
/** This process's owned box [lo, hi) and ghosted box [glo, ghi) (any may
 *  be NULL; the unused third direction of a plane grid is [0, 1)). */
void mpgm_pgrid_boxes(const mpgm_pgrid *g, int lo[3], int hi[3], int glo[3], int ghi[3]);
/** The process that owns node (or cell) ijk (a node past the last slab of
 *  a direction counts in it). */
int mpgm_pgrid_owner(const mpgm_pgrid *g, const int ijk[3]);
/** The sums over the processes at shared nodes: each gives its n nodes
 *  (ijk, dim per node, within its ghosted box; each node once) with w
 *  values each in val (1 <= w <= dof, the same w on every process), and
 *  gets back in val, at each of them, the sum of every process's values
 *  there (DMLocalToGlobal with ADD_VALUES, then DMGlobalToLocal, on a
 *  DMDA of w fields with the grid's partition: the scatters move w values
 *  per node, not dof). Collective. */
int mpgm_pgrid_sum(mpgm_ctx *ctx, mpgm_pgrid *g, int n, const int *ijk, int w, double *val);
/** Records of rec doubles sent to other processes (a DMSwarm of type
 *  basic: DMSwarmMigrate): out holds nout records, record i for process
 *  dest[i]; *in (malloc'd, the caller frees it) gets the *nin records this
 *  process now holds: those sent to it, and those of out whose dest was
 *  itself. Collective; rec the same on every call of one grid. */
int mpgm_pgrid_migrate(mpgm_ctx *ctx, mpgm_pgrid *g, int rec, int nout, const double *out,
                       const int *dest, int *nin, double **in);

#endif
