/* comm.c -- the collectives of a run on many processes, through the
 * context's communicator (mpgm_comm, mpgm_base.h); the identity on one. */
#include "mpgm_base.h"

#include <string.h>

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

int mpgm_agree(mpgm_ctx *ctx, int err) {
  const mpgm_comm *c = ctx->comm;
  if (!c || c->size == 1) return err;
  long who = err ? c->rank : c->size; /* the first process that failed */
  if (c->allreduce_long(c->impl, MPGM_REDUCE_MIN, &who, 1)) {
    mpgm_err_clear(ctx);
    MPGM_ERROR(ctx, MPGM_ERR_INTERNAL, "MPI_Allreduce of the processes' outcomes failed on process %d "
               "of %d", c->rank, c->size);
  }
  if (who == c->size) return 0;
  struct {
    int code;
    char msg[sizeof ctx->msg];
  } m;
  memset(&m, 0, sizeof m);
  if (c->rank == who) {
    m.code = err;
    memcpy(m.msg, ctx->msg, sizeof m.msg);
  }
  if (c->bcast(c->impl, &m, sizeof m, (int)who)) {
    mpgm_err_clear(ctx);
    MPGM_ERROR(ctx, MPGM_ERR_INTERNAL, "MPI_Bcast of process %ld's failure failed", who);
  }
  if (c->rank == who) return err;
  mpgm_err_clear(ctx);
  m.msg[sizeof m.msg - 1] = '\0';
  return mpgm_err_set(ctx, m.code, __FILE__, __LINE__, "process %ld of %d: %.1000s", who, c->size, m.msg);
}

int mpgm_imbalance(mpgm_ctx *ctx, long n, double *imb) {
  long sum = n, most = n;
  MPGM_CALL(mpgm_allreduce_long(ctx, MPGM_REDUCE_SUM, &sum, 1));
  MPGM_CALL(mpgm_allreduce_long(ctx, MPGM_REDUCE_MAX, &most, 1));
  *imb = sum > 0 ? (double)most * mpgm_ctx_size(ctx) / (double)sum : 1.0;
  return 0;
}
