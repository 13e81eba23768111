/* pool.c -- worker threads for mpgm's own loops (see mpgm_pool.h). */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_pool.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

/* Spin iterations of a worker waiting for the next run before it sleeps
 * (about 10-20 us), and of the caller waiting for the last task. */
#define SPIN_WAIT 4000

struct mpgm_pool {
  int size; /* threads in all, caller included */
  pthread_t *th;
  pthread_mutex_t mu;
  pthread_cond_t start, done;
  atomic_uint gen;    /* run counter: a change starts the workers   */
  atomic_int next;    /* next task to hand out                      */
  atomic_int pending; /* workers still inside the current run       */
  int stop;
  int ntask;
  mpgm_pool_fn fn;
  void *arg;
};

static inline void cpu_relax(void) {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

static void drain(mpgm_pool *pl, int tid) {
  for (;;) {
    const int t = atomic_fetch_add_explicit(&pl->next, 1, memory_order_relaxed);
    if (t >= pl->ntask) break;
    pl->fn(pl->arg, t, tid);
  }
}

typedef struct {
  mpgm_pool *pl;
  int tid;
} worker_arg;

static void *worker(void *p) {
  worker_arg *wa = p;
  mpgm_pool *pl = wa->pl;
  const int tid = wa->tid;
  free(wa);
  /* runs are counted from 0 at creation; a run may start before this
   * thread does, so do not read the counter here */
  unsigned seen = 0u;
  for (;;) {
    int spin = 0;
    unsigned g;
    while ((g = atomic_load_explicit(&pl->gen, memory_order_acquire)) == seen && spin < SPIN_WAIT) {
      cpu_relax();
      spin++;
    }
    if (g == seen) {
      pthread_mutex_lock(&pl->mu);
      while ((g = atomic_load_explicit(&pl->gen, memory_order_acquire)) == seen && !pl->stop)
        pthread_cond_wait(&pl->start, &pl->mu);
      const int stop = pl->stop;
      pthread_mutex_unlock(&pl->mu);
      if (stop && g == seen) return NULL;
    }
    seen = g;
    drain(pl, tid);
    if (atomic_fetch_sub_explicit(&pl->pending, 1, memory_order_acq_rel) == 1) {
      pthread_mutex_lock(&pl->mu);
      pthread_cond_signal(&pl->done);
      pthread_mutex_unlock(&pl->mu);
    }
  }
}

int mpgm_ncores(void) {
  const long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n >= 1 ? (int)n : 1;
}

int mpgm_pool_create(mpgm_ctx *ctx, int nthreads, mpgm_pool **out) {
  *out = NULL;
  if (nthreads <= 0) nthreads = mpgm_ncores();
  mpgm_pool *pl;
  MPGM_ALLOC(ctx, pl, 1);
  pl->size = 1;
  pthread_mutex_init(&pl->mu, NULL);
  pthread_cond_init(&pl->start, NULL);
  pthread_cond_init(&pl->done, NULL);
  atomic_init(&pl->gen, 0u);
  atomic_init(&pl->next, 0);
  atomic_init(&pl->pending, 0);
  *out = pl;
  if (nthreads == 1) return 0;
  pl->th = calloc((size_t)nthreads, sizeof(pthread_t));
  if (!pl->th) {
    mpgm_pool_destroy(out);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (thread pool of %d)", nthreads);
  }
  for (int i = 1; i < nthreads; i++) {
    worker_arg *wa = malloc(sizeof *wa);
    if (wa) *wa = (worker_arg){pl, i};
    if (!wa || pthread_create(&pl->th[i], NULL, worker, wa) != 0) {
      free(wa);
      mpgm_pool_destroy(out);
      MPGM_ERROR(ctx, MPGM_ERR_INTERNAL, "could not start worker thread %d of %d", i, nthreads);
    }
    pl->size = i + 1;
  }
  return 0;
}

void mpgm_pool_destroy(mpgm_pool **pool) {
  if (!pool || !*pool) return;
  mpgm_pool *pl = *pool;
  pthread_mutex_lock(&pl->mu);
  pl->stop = 1;
  pthread_cond_broadcast(&pl->start);
  pthread_mutex_unlock(&pl->mu);
  for (int i = 1; i < pl->size; i++) pthread_join(pl->th[i], NULL);
  pthread_cond_destroy(&pl->start);
  pthread_cond_destroy(&pl->done);
  pthread_mutex_destroy(&pl->mu);
  free(pl->th);
  free(pl);
  *pool = NULL;
}

int mpgm_pool_size(const mpgm_pool *pool) { return pool ? pool->size : 1; }

void mpgm_pool_run(mpgm_pool *pl, int ntask, mpgm_pool_fn fn, void *arg) {
  if (ntask <= 0) return;
  if (!pl || pl->size == 1 || ntask == 1) {
    for (int t = 0; t < ntask; t++) fn(arg, t, 0);
    return;
  }
  pthread_mutex_lock(&pl->mu);
  pl->fn = fn;
  pl->arg = arg;
  pl->ntask = ntask;
  atomic_store_explicit(&pl->next, 0, memory_order_relaxed);
  atomic_store_explicit(&pl->pending, pl->size - 1, memory_order_relaxed);
  atomic_fetch_add_explicit(&pl->gen, 1u, memory_order_release);
  pthread_cond_broadcast(&pl->start);
  pthread_mutex_unlock(&pl->mu);
  drain(pl, 0);
  for (int spin = 0; spin < SPIN_WAIT; spin++) {
    if (atomic_load_explicit(&pl->pending, memory_order_acquire) == 0) return;
    cpu_relax();
  }
  pthread_mutex_lock(&pl->mu);
  while (atomic_load_explicit(&pl->pending, memory_order_acquire) > 0)
    pthread_cond_wait(&pl->done, &pl->mu);
  pthread_mutex_unlock(&pl->mu);
}
