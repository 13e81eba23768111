/* par.c -- the module mpgm_par.so: MPI and PETSc for a run on many
 * processes (mpgm_parallel.h). MPI is started here with
 * MPI_Init_thread(MPI_THREAD_FUNNELED) -- the worker threads of the pool
 * never call MPI -- and PETSc over it; the run's communicator is a
 * duplicate of MPI_COMM_WORLD whose errors return to the caller. */
#include <mpi.h>
#include <petscsys.h>
#include <stdio.h>

#include "mpgm_base.h"

static MPI_Comm world = MPI_COMM_NULL;
static mpgm_comm the_comm;
static int started_mpi, started_petsc;

static MPI_Op op_of(mpgm_reduce op) {
  return op == MPGM_REDUCE_MIN ? MPI_MIN : op == MPGM_REDUCE_MAX ? MPI_MAX : MPI_SUM;
}

static int allreduce(void *impl, mpgm_reduce op, double *v, int n) {
  return MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, op_of(op), *(MPI_Comm *)impl) == MPI_SUCCESS
             ? 0 : -1;
}

static int allreduce_long(void *impl, mpgm_reduce op, long *v, int n) {
  return MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_LONG, op_of(op), *(MPI_Comm *)impl) == MPI_SUCCESS
             ? 0 : -1;
}

static int bcast(void *impl, void *buf, size_t bytes, int root) {
  if (bytes > (size_t)0x7fffffff) return -1;
  return MPI_Bcast(buf, (int)bytes, MPI_BYTE, root, *(MPI_Comm *)impl) == MPI_SUCCESS ? 0 : -1;
}

static int barrier(void *impl) { return MPI_Barrier(*(MPI_Comm *)impl) == MPI_SUCCESS ? 0 : -1; }

/* PETSc keeps the pointer to its arguments: static. */
static char **petsc_args(void) {
  static char a0[] = "mpgm", a1[] = "-no_signal_handler";
  static char *argv[] = {a0, a1, NULL};
  return argv;
}

int mpgm_par_module_start(const mpgm_comm **comm, char *msg, size_t len) {
  int done = 0, provided = 0;
  MPI_Initialized(&done);
  if (!done) {
    if (MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
      snprintf(msg, len, "MPI_Init_thread failed");
      return -1;
    }
    started_mpi = 1;
  }
  if (MPI_Comm_dup(MPI_COMM_WORLD, &world) != MPI_SUCCESS) {
    snprintf(msg, len, "MPI_Comm_dup of MPI_COMM_WORLD failed");
    return -1;
  }
  MPI_Comm_set_errhandler(world, MPI_ERRORS_RETURN);
  PetscBool up = PETSC_FALSE;
  PetscInitialized(&up);
  if (!up) {
    int argc = 2;
    char **argv = petsc_args();
    const PetscErrorCode e = PetscInitialize(&argc, &argv, NULL, NULL);
    if (e) {
      snprintf(msg, len, "PetscInitialize failed (error %d)", (int)e);
      return -1;
    }
    started_petsc = 1;
    PetscPushErrorHandler(PetscReturnErrorHandler, NULL);
  }
  the_comm = (mpgm_comm){.impl = &world, .allreduce = allreduce, .allreduce_long = allreduce_long,
                         .bcast = bcast, .barrier = barrier};
  MPI_Comm_rank(world, &the_comm.rank);
  MPI_Comm_size(world, &the_comm.size);
  /* the processes of the run on this machine (they share its cores) */
  MPI_Comm node;
  the_comm.local = 1;
  if (MPI_Comm_split_type(world, MPI_COMM_TYPE_SHARED, the_comm.rank, MPI_INFO_NULL, &node) == MPI_SUCCESS) {
    MPI_Comm_size(node, &the_comm.local);
    MPI_Comm_free(&node);
  }
  *comm = &the_comm;
  return 0;
}

void mpgm_par_module_finalize(void) {
  if (started_petsc) PetscFinalize();
  started_petsc = 0;
  if (world != MPI_COMM_NULL) MPI_Comm_free(&world);
  int done = 0;
  MPI_Finalized(&done);
  if (started_mpi && !done) MPI_Finalize();
  started_mpi = 0;
}
