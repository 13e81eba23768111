/* conn_par.c -- a point -> node connectivity built on the pool's threads
 * (mpgm_data.h, mpgm_conn_par_build).
 *
 * The points [0, np) are cut into contiguous ranges, one task each. A task
 * appends the entries of its points, in order, to a staging area of its
 * own; then every task copies its entries to their place in the
 * connectivity, behind those of the ranges before it. The entries, their
 * order and the offsets are those of a serial loop over the points,
 * whatever the number of threads. A task stops at its first failure; the
 * build reports the failure of the lowest point (the one a serial loop
 * stops at) and adds up the counters of the tasks up to it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_data.h"

/* ranges of at least CHUNK points */
#define CHUNK 256

void mpgm_conn_task_free(mpgm_conn_task *t) {
  free(t->node);
  free(t->N);
  free(t->dN);
  free(t->len);
  free(t->iscr);
  memset(t, 0, sizeof *t);
}

int mpgm_conn_task_iscr(mpgm_conn_task *t, size_t n) {
  if (n <= t->iscr_cap) return 0;
  size_t cap = t->iscr_cap ? t->iscr_cap : 4096;
  while (cap < n) cap *= 2;
  int *q = realloc(t->iscr, sizeof(int) * cap);
  if (!q) {
    t->why_nomem = 1;
    return MPGM_ERR_NOMEM;
  }
  t->iscr = q;
  t->iscr_cap = cap;
  return 0;
}

void mpgm_conn_par_free(mpgm_conn_par *cp) {
  if (!cp) return;
  for (int t = 0; t < MPGM_CONN_TASKS; t++) mpgm_conn_task_free(&cp->t[t]);
  cp->ntask = 0;
}

int mpgm_conn_task_room(mpgm_conn_task *t, int more) {
  if (t->n + more <= t->cap) return 0;
  int cap = t->cap ? t->cap : 1024;
  while (cap < t->n + more) cap *= 2;
  int *node = realloc(t->node, sizeof(int) * (size_t)cap);
  if (node) t->node = node;
  double *N = node ? realloc(t->N, sizeof(double) * (size_t)cap) : NULL;
  if (N) t->N = N;
  double *dN = N ? realloc(t->dN, sizeof(double) * MPGM_DIM * (size_t)cap) : NULL;
  if (!dN) {
    t->why_nomem = 1;
    return MPGM_ERR_NOMEM;
  }
  t->dN = dN;
  t->cap = cap;
  return 0;
}

typedef struct {
  mpgm_conn_par *cp;
  mpgm_conn *C;
  mpgm_conn_point_fn fn;
  void *arg;
} par_job;

static void stage_task(void *arg, int ti, int tid) {
  (void)tid;
  par_job *j = arg;
  mpgm_conn_task *t = &j->cp->t[ti];
  t->n = 0;
  t->err = 0;
  t->why_nomem = 0;
  t->msg[0] = '\0';
  t->t_aside = 0.0;
  memset(t->count, 0, sizeof t->count);
  const double t0 = mpgm_wtime();
  for (int p = t->p0; p < t->p1; p++) {
    const int n0 = t->n;
    const int err = j->fn(j->arg, p, t);
    t->len[p - t->p0] = t->n - n0;
    if (err) {
      t->err = err;
      t->fail = p;
      break;
    }
  }
  t->t_busy = mpgm_wtime() - t0;
}

/* The offsets of a task's points. */
static void fill_ptr(const mpgm_conn_task *t, mpgm_conn *C) {
  int k = t->off;
  for (int p = t->p0; p < t->p1; p++) {
    C->ptr[p] = k;
    k += t->len[p - t->p0];
  }
}

static void copy_task(void *arg, int ti, int tid) {
  (void)tid;
  const par_job *j = arg;
  const mpgm_conn_task *t = &j->cp->t[ti];
  mpgm_conn *C = j->C;
  fill_ptr(t, C);
  if (t->n == 0) return; /* no lists (a process without points): no arrays to copy */
  memcpy(C->node + t->off, t->node, sizeof(int) * (size_t)t->n);
  memcpy(C->N + t->off, t->N, sizeof(double) * (size_t)t->n);
  memcpy(C->dN + MPGM_DIM * (size_t)t->off, t->dN, sizeof(double) * MPGM_DIM * (size_t)t->n);
}

/* Cut [0, np) into ranges (one when serial) and give each task room for
 * its lengths. */
static int plan(mpgm_ctx *ctx, mpgm_conn_par *cp, int np, int serial) {
  cp->ntask = serial ? 1 : mpgm_ntask(np, CHUNK);
  for (int t = 0; t < cp->ntask; t++) {
    mpgm_conn_task *k = &cp->t[t];
    k->p0 = mpgm_task_begin(np, cp->ntask, t);
    k->p1 = mpgm_task_begin(np, cp->ntask, t + 1);
    if (k->p1 - k->p0 > k->lcap) {
      free(k->len);
      k->lcap = 0;
      MPGM_ALLOC(ctx, k->len, k->p1 - k->p0);
      k->lcap = k->p1 - k->p0;
    }
  }
  return 0;
}

/* A pool of one thread: one task, which stages straight into C's arrays
 * (lent for the build, no copy); C->g follows their size. */
static int build_serial(mpgm_ctx *ctx, mpgm_conn_par *cp, mpgm_conn *C, par_job *j) {
  mpgm_conn_task *t = &cp->t[0];
  int *own_node = t->node, own_cap = t->cap;
  double *own_N = t->N, *own_dN = t->dN;
  t->node = C->node;
  t->N = C->N;
  t->dN = C->dN;
  t->cap = C->cap;
  stage_task(j, 0, 0);
  C->node = t->node;
  C->N = t->N;
  C->dN = t->dN;
  const int cap = t->cap;
  t->node = own_node;
  t->N = own_N;
  t->dN = own_dN;
  t->cap = own_cap;
  if (cap > C->cap) {
    double *g = realloc(C->g, sizeof(double) * MPGM_DIM * (size_t)cap);
    MPGM_CHECK(ctx, g, MPGM_ERR_NOMEM, "out of memory (connectivity of %d entries)", cap);
    C->g = g;
    C->cap = cap;
  }
  t->off = 0;
  return 0;
}

int mpgm_conn_par_build(mpgm_ctx *ctx, mpgm_pool *pool, mpgm_conn_par *cp, int np, mpgm_conn *C,
                        mpgm_conn_point_fn fn, void *arg, const mpgm_conn_task **failed) {
  *failed = NULL;
  C->rn = 0; /* the lists change */
  const int serial = mpgm_pool_size(pool) == 1;
  MPGM_CALL(plan(ctx, cp, np, serial));
  par_job j = {cp, C, fn, arg};
  const double t0 = mpgm_wtime();
  if (serial) MPGM_CALL(build_serial(ctx, cp, C, &j));
  else mpgm_pool_run(pool, cp->ntask, stage_task, &j);
  const double wall = mpgm_wtime() - t0;
  /* counters of the tasks a serial loop would have run */
  int last = cp->ntask - 1;
  for (int t = 0; t < cp->ntask; t++)
    if (cp->t[t].err) {
      last = t;
      break;
    }
  for (int t = 0; t <= last; t++)
    for (int c = 0; c < MPGM_C_COUNT; c++) ctx->count[c] += cp->t[t].count[c];
  /* the set-aside share of the threads' time, as a share of the wall time */
  double aside = 0.0, busy = 0.0;
  for (int t = 0; t < cp->ntask; t++) {
    aside += cp->t[t].t_aside;
    busy += cp->t[t].t_busy;
  }
  cp->t_aside = busy > 0.0 ? wall * fmin(1.0, aside / busy) : 0.0;
  if (cp->t[last].err) {
    const mpgm_conn_task *t = &cp->t[last];
    MPGM_CHECK(ctx, !t->why_nomem, MPGM_ERR_NOMEM, "out of memory (connectivity of point %d)",
               t->fail);
    *failed = t;
    return t->err;
  }
  if (serial) { /* the entries are in place */
    fill_ptr(cp->t, C);
    C->ptr[np] = cp->t[0].n;
    return 0;
  }
  int k = 0;
  for (int t = 0; t < cp->ntask; t++) {
    cp->t[t].off = k;
    k += cp->t[t].n;
  }
  MPGM_CALL(mpgm_conn_grow(ctx, C, 0, k));
  mpgm_pool_run(pool, cp->ntask, copy_task, &j);
  C->ptr[np] = k;
  return 0;
}

int mpgm_conn_runs(mpgm_ctx *ctx, mpgm_conn *c, int np) {
  if (c->rn == np) return 0;
  if (np > c->rcap) {
    free(c->rc);
    c->rcap = 0;
    MPGM_ALLOC(ctx, c->rc, np + np / 2 + 16);
    c->rcap = np + np / 2 + 16;
  }
  if (np > 0) c->rc[0] = 0;
  for (int p = 1; p < np; p++) c->rc[p] = (unsigned char)mpgm_conn_same(c, p);
  c->rn = np;
  return 0;
}

int mpgm_conn_transpose(mpgm_ctx *ctx, mpgm_conn *c, int np, int nnode) {
  const int nnz = c->ptr[np];
  if (nnode + 1 > c->tncap) {
    free(c->tptr);
    c->tncap = 0;
    MPGM_ALLOC(ctx, c->tptr, nnode + 1);
    c->tncap = nnode + 1;
  }
  if (nnz > c->tkcap) {
    free(c->tk);
    free(c->tp);
    free(c->tc);
    c->tp = NULL;
    c->tc = NULL;
    c->tkcap = 0;
    const int cap = nnz + nnz / 2 + 16;
    MPGM_ALLOC(ctx, c->tk, cap);
    MPGM_ALLOC(ctx, c->tp, cap);
    MPGM_ALLOC(ctx, c->tc, cap);
    c->tkcap = cap;
  }
  int *ptr = c->tptr;
  memset(ptr, 0, sizeof(int) * (size_t)(nnode + 1));
  for (int k = 0; k < nnz; k++) ptr[c->node[k] + 1]++;
  for (int i = 0; i < nnode; i++) ptr[i + 1] += ptr[i];
  /* fill in entry order, each node's next free place in ptr[I] (shifted
   * back afterwards) */
  for (int p = 0; p < np; p++) {
    const unsigned char cont = p > 0 && mpgm_conn_continues(c, np, p);
    for (int k = c->ptr[p]; k < c->ptr[p + 1]; k++) {
      const int e = ptr[c->node[k]]++;
      c->tk[e] = k;
      c->tp[e] = p;
      c->tc[e] = cont;
    }
  }
  for (int i = nnode; i > 0; i--) ptr[i] = ptr[i - 1];
  ptr[0] = 0;
  c->tn = nnode;
  return 0;
}
