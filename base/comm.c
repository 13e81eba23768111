/* comm.c -- the collectives of a run on many processes, through the
 * context's communicator (mpgm_comm, mpgm_base.h); the identity on one. */
#include "mpgm_base.h"

int mpgm_allreduce(mpgm_ctx *ctx, mpgm_reduce op, double *v, int n) {
  const mpgm_comm *c = ctx->comm;
  if (!c || c->size == 1 || n <= 0) return 0;
  MPGM_CHECK(ctx, c->allreduce(c->impl, op, v, n) == 0, MPGM_ERR_INTERNAL,
             "MPI_Allreduce of %d value(s) on process %d of %d failed", n, c->rank, c->size);
  return 0;
}

int mpgm_allreduce_long(mpgm_ctx *ctx, mpgm_reduce op, long *v, int n) {
  const mpgm_comm *c = ctx->comm;
  if (!c || c->size == 1 || n <= 0) return 0;
  MPGM_CHECK(ctx, c->allreduce_long(c->impl, op, v, n) == 0, MPGM_ERR_INTERNAL,
             "MPI_Allreduce of %d integer(s) on process %d of %d failed", n, c->rank, c->size);
  return 0;
}

int mpgm_bcast(mpgm_ctx *ctx, void *buf, size_t bytes, int root) {
  const mpgm_comm *c = ctx->comm;
  if (!c || c->size == 1 || bytes == 0) return 0;
  MPGM_CHECK(ctx, c->bcast(c->impl, buf, bytes, root) == 0, MPGM_ERR_INTERNAL,
             "MPI_Bcast of %zu bytes from process %d failed", bytes, root);
  return 0;
}
