/* mpgm_pool.h -- a small fixed pool of worker threads for mpgm's own loops
 * (material update, assembly).
 *
 * mpgm_pool_run hands tasks 0..ntask-1 out to the calling thread and the
 * workers (first come, first served) and returns when every task is done.
 * Which thread runs a task is not deterministic; callers make the result
 * independent of it by giving each task its own output (disjoint entries or
 * per-task slots), so a run gives the same bits with any number of threads.
 *
 * Between runs the workers spin for a few microseconds (back-to-back runs,
 * e.g. the phases of one assembly, then cost no wake-up) and then sleep on a
 * condition variable, so an idle pool costs no CPU while the sparse solver
 * works.
 */
#ifndef MPGM_POOL_H
#define MPGM_POOL_H

#include "mpgm_base.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mpgm_pool mpgm_pool;

/** Task body: task index and the running thread's index (0 = caller,
 *  1..size-1 = workers), for per-thread scratch. */
typedef void (*mpgm_pool_fn)(void *arg, int task, int tid);

/** Create a pool of nthreads threads in all, the caller included (so
 *  nthreads - 1 workers; 1 creates none). nthreads <= 0: one per online
 *  core. MPGM_ERR_NOMEM or MPGM_ERR_INTERNAL (thread creation) recorded in
 *  ctx. */
int mpgm_pool_create(mpgm_ctx *ctx, int nthreads, mpgm_pool **out);
/** Stop and join the workers; *pool = NULL. NULL-safe. */
void mpgm_pool_destroy(mpgm_pool **pool);
/** Threads in all (1 for a NULL pool). */
int mpgm_pool_size(const mpgm_pool *pool);
/** Run fn(arg, task, tid) for every task in [0, ntask); returns when all
 *  have run. A NULL pool runs them in order on the caller. */
void mpgm_pool_run(mpgm_pool *pool, int ntask, mpgm_pool_fn fn, void *arg);
/** Online cores of this machine (>= 1). */
int mpgm_ncores(void);

#ifdef __cplusplus
}
#endif
#endif
