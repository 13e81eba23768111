/* data.c -- the data model: allocation of points, nodes and connectivity,
 * their reordering, and the effects of a scene (mpgm_data.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_data.h"
#include "mpgm_integrator.h"


int mpgm_points_alloc(mpgm_ctx *ctx, mpgm_points *p, int n, int nprobe, int nsurf, int nstate) {
  const int m = n + nprobe + nsurf;
  p->n = n;
  p->nprobe = nprobe;
  p->nsurf = nsurf;
  p->nstate = nstate;
  MPGM_ALLOC(ctx, p->x, MPGM_DIM * m);
  MPGM_ALLOC(ctx, p->x0, MPGM_DIM * m);
  MPGM_ALLOC(ctx, p->u, MPGM_DIM * m);
  MPGM_ALLOC(ctx, p->v, MPGM_DIM * m);
  MPGM_ALLOC(ctx, p->a, MPGM_DIM * m);
  MPGM_ALLOC(ctx, p->mass, m);
  MPGM_ALLOC(ctx, p->vol0, m);
  MPGM_ALLOC(ctx, p->vol, m);
  MPGM_ALLOC(ctx, p->F, MPGM_TENSOR * m);
  MPGM_ALLOC(ctx, p->sigma, MPGM_NSTRESS * m);
  MPGM_ALLOC(ctx, p->S0, MPGM_NSTRESS * m);
  MPGM_ALLOC(ctx, p->r0, MPGM_TENSOR * m);
  MPGM_ALLOC(ctx, p->L, MPGM_TENSOR * m);
  MPGM_ALLOC(ctx, p->state, (size_t)nstate * m);
  MPGM_ALLOC(ctx, p->mat, m);
  MPGM_ALLOC(ctx, p->body, m);
  MPGM_ALLOC(ctx, p->id, m);
  for (int i = 0; i < m; i++) p->id[i] = i;
  p->cap = m;
  /* F_t, sigma_t and vol_t as long as F, sigma and vol: an explicit step
   * commits by swapping them (core/explicit.c, commit_stress) */
  MPGM_ALLOC(ctx, p->F_t, MPGM_TENSOR * m);
  MPGM_ALLOC(ctx, p->dF_t, MPGM_TENSOR * n);
  MPGM_ALLOC(ctx, p->sigma_t, MPGM_NSTRESS * m);
  MPGM_ALLOC(ctx, p->D_t, MPGM_NTANGENT * n);
  MPGM_ALLOC(ctx, p->state_t, (size_t)nstate * n);
  MPGM_ALLOC(ctx, p->vol_t, m);
  for (int i = 0; i < m; i++) /* F = I */
    for (int d = 0; d < MPGM_DIM; d++) p->F[MPGM_TENSOR * i + (MPGM_DIM + 1) * d] = 1.0;
  return 0;
}

void mpgm_point_set(mpgm_points *P, int p, const mpgm_scene *s, int body, const double x[MPGM_DIM],
                    double vol) {
  const mpgm_scene_body *bd = &s->bodies[body];
  const mpgm_material *mat = &s->mats[bd->material];
  for (int d = 0; d < MPGM_DIM; d++) {
    P->x[MPGM_DIM * p + d] = P->x0[MPGM_DIM * p + d] = x[d];
    P->v[MPGM_DIM * p + d] = bd->velocity[d];
  }
  P->vol[p] = P->vol0[p] = vol;
  P->mass[p] = mat->density * vol;
  /* the domain: a square (cube) of the point's volume (a layout may set
   * another) */
  const double hs = 0.5 * (MPGM_DIM == 2 ? sqrt(vol) : cbrt(vol));
  double *r0 = P->r0 + MPGM_TENSOR * p;
  for (int k = 0; k < MPGM_TENSOR; k++) r0[k] = MPGM_DIAG(k) ? hs : 0.0;
  P->mat[p] = bd->material;
  P->body[p] = body;
  if (mat->type->init_state && P->nstate) mat->type->init_state(mat, P->state + (size_t)P->nstate * p);
}

double mpgm_points_plastic_strain(const mpgm_points *P, const mpgm_material *mats, double *out) {
  double mx = 0.0;
  for (int p = 0; p < P->n; p++) {
    const mpgm_material *m = &mats[P->mat[p]];
    const double e = m->type->plastic_strain && P->nstate
                         ? m->type->plastic_strain(m, P->state + (size_t)P->nstate * p)
                         : 0.0;
    if (out) out[p] = e;
    if (e > mx) mx = e;
  }
  return mx;
}

/* The committed per-point arrays and their record widths (ints: -1). */
typedef struct {
  void **a;
  int w;
} point_array;

/* The committed per-point arrays of p, in the order of a point's record
 * (mpgm_points_pack). */
enum { NARR = 17 };
static void point_arrays(mpgm_points *p, point_array arr[NARR]) {
  const point_array a[NARR] = {
      {(void **)&p->x, MPGM_DIM},          {(void **)&p->x0, MPGM_DIM},
      {(void **)&p->u, MPGM_DIM},          {(void **)&p->v, MPGM_DIM},
      {(void **)&p->a, MPGM_DIM},          {(void **)&p->mass, 1},
      {(void **)&p->vol0, 1},              {(void **)&p->vol, 1},
      {(void **)&p->F, MPGM_TENSOR},       {(void **)&p->sigma, MPGM_NSTRESS},
      {(void **)&p->S0, MPGM_NSTRESS},     {(void **)&p->state, p->nstate},
      {(void **)&p->r0, MPGM_TENSOR},     {(void **)&p->L, MPGM_TENSOR},
      {(void **)&p->mat, -1},              {(void **)&p->body, -1},
      {(void **)&p->id, -1}};
  memcpy(arr, a, sizeof a);
}

int mpgm_point_record_len(const mpgm_points *P) {
  point_array arr[NARR];
  point_arrays((mpgm_points *)P, arr);
  int len = 0;
  for (int j = 0; j < NARR; j++) len += arr[j].w < 0 ? 1 : arr[j].w;
  return len;
}

/* Point p of the arrays arr into rec (point_arrays' order). */
static void pack(const point_array *arr, int p, double *rec) {
  for (int j = 0; j < NARR; j++) {
    const int w = arr[j].w;
    if (w < 0) *rec++ = (double)(*(int *const *)arr[j].a)[p]; /* exact: |int| < 2^53 */
    else {
      memcpy(rec, *(double *const *)arr[j].a + (size_t)w * p, sizeof(double) * (size_t)w);
      rec += w;
    }
  }
}

int mpgm_points_pack(const mpgm_points *P, const unsigned char *keep, double *out) {
  point_array arr[NARR];
  point_arrays((mpgm_points *)P, arr);
  const int rec = mpgm_point_record_len(P);
  int q = 0;
  for (int p = 0; p < P->n; p++)
    if (!keep[p]) pack(arr, p, out + (size_t)rec * q++);
  return q;
}

/* Record rec into row q of the arrays arr (point_arrays' order). */
static void unpack(const point_array *arr, int q, const double *rec) {
  for (int j = 0; j < NARR; j++) {
    const int w = arr[j].w;
    if (w < 0) (*(int **)arr[j].a)[q] = (int)*rec++;
    else {
      memcpy(*(double **)arr[j].a + (size_t)w * q, rec, sizeof(double) * (size_t)w);
      rec += w;
    }
  }
}

/* The trial arrays a moved row carries (the others are written by a step
 * before use), with their widths. */
enum { NTRIAL = 3 };
static void trial_carried(mpgm_points *p, point_array t[NTRIAL]) {
  const point_array a[NTRIAL] = {{(void **)&p->F_t, MPGM_TENSOR},
                                 {(void **)&p->sigma_t, MPGM_NSTRESS},
                                 {(void **)&p->vol_t, 1}};
  memcpy(t, a, sizeof a);
}

/* Room for cap rows in every per-point array, committed and trial. */
static int points_reserve(mpgm_ctx *ctx, mpgm_points *p, int cap) {
  point_array arr[NARR + 6];
  point_arrays(p, arr);
  const point_array t[6] = {{(void **)&p->F_t, MPGM_TENSOR},    {(void **)&p->dF_t, MPGM_TENSOR},
                            {(void **)&p->sigma_t, MPGM_NSTRESS}, {(void **)&p->D_t, MPGM_NTANGENT},
                            {(void **)&p->state_t, p->nstate},  {(void **)&p->vol_t, 1}};
  memcpy(arr + NARR, t, sizeof t);
  for (int j = 0; j < NARR + 6; j++) {
    const size_t row = arr[j].w < 0 ? sizeof(int) : sizeof(double) * (size_t)arr[j].w;
    void *g = realloc(*arr[j].a, row * (size_t)cap + 1);
    MPGM_CHECK(ctx, g, MPGM_ERR_NOMEM, "out of memory (room for %d points)", cap);
    *arr[j].a = g;
  }
  p->cap = cap;
  return 0;
}

/* n rows of array a from row src to row dst (they may overlap). */
static void row_copy(const point_array *a, int dst, int src, int n) {
  const size_t b = a->w < 0 ? sizeof(int) : sizeof(double) * (size_t)a->w;
  char *d = *a->a;
  memmove(d + b * (size_t)dst, d + b * (size_t)src, b * (size_t)n);
}

/* The committed F, sigma and vol of rows [r0, r1) into the trial rows. */
static void trial_fill(mpgm_points *p, int r0, int r1) {
  if (r1 <= r0) return;
  memcpy(p->F_t + MPGM_TENSOR * (size_t)r0, p->F + MPGM_TENSOR * (size_t)r0,
         sizeof(double) * MPGM_TENSOR * (size_t)(r1 - r0));
  memcpy(p->sigma_t + MPGM_NSTRESS * (size_t)r0, p->sigma + MPGM_NSTRESS * (size_t)r0,
         sizeof(double) * MPGM_NSTRESS * (size_t)(r1 - r0));
  memcpy(p->vol_t + r0, p->vol + r0, sizeof(double) * (size_t)(r1 - r0));
}

int mpgm_points_exchange(mpgm_ctx *ctx, mpgm_points *p, const unsigned char *keep, int nin,
                         const double *in) {
  const int n = p->n, m = n + p->nprobe + p->nsurf, ntr = m - n, rec = mpgm_point_record_len(p);
  int nk = 0;
  for (int i = 0; i < n; i++) nk += keep[i] != 0;
  const int n2 = nk + nin, m2 = n2 + ntr;
  if (m2 > p->cap) MPGM_CALL(points_reserve(ctx, p, m2 + m2 / 8 + 16));
  point_array arr[NARR], tr[NTRIAL];
  point_arrays(p, arr);
  trial_carried(p, tr);
  /* the tracers past the rows the material points will hold (up first,
   * when points arrive: rows n .. n2 are then free for them) */
  if (n2 > n)
    for (int j = 0; j < NARR + NTRIAL; j++) row_copy(j < NARR ? &arr[j] : &tr[j - NARR], n2, n, ntr);
  /* the points that left: their rows to the arrivals, then to the last
   * kept rows (from the end down) */
  int a = 0, top = n - 1;
  for (int i = 0; i < n && i < n2; i++) {
    if (keep[i]) continue;
    if (a < nin) {
      unpack(arr, i, in + (size_t)rec * a++);
    } else {
      while (top > i && !keep[top]) top--;
      for (int j = 0; j < NARR; j++) row_copy(&arr[j], i, top, 1);
      top--;
    }
    trial_fill(p, i, i + 1);
  }
  /* the arrivals past the old rows */
  for (int q = n; q < n2; q++) {
    unpack(arr, q, in + (size_t)rec * a++);
    trial_fill(p, q, q + 1);
  }
  /* the tracers down, when fewer points stay */
  if (n2 < n)
    for (int j = 0; j < NARR + NTRIAL; j++) row_copy(j < NARR ? &arr[j] : &tr[j - NARR], n2, n, ntr);
  p->n = n2;
  return 0;
}

typedef struct {
  const point_array *arr;
  void *const *fresh;
  const int *perm;
  int n, m;
} gather_job;

/* Task j: gather array j into its fresh buffer (probes copied as they are)
 * and swap it in. */
static void gather_task(void *arg, int j, int tid) {
  (void)tid;
  const gather_job *g = arg;
  const int w = g->arr[j].w, n = g->n, m = g->m;
  const int *perm = g->perm;
  if (w < 0) {
    const int *src = *g->arr[j].a;
    int *dst = g->fresh[j];
    for (int i = 0; i < n; i++) dst[i] = src[perm[i]];
    memcpy(dst + n, src + n, sizeof(int) * (size_t)(m - n));
  } else if (w > 0) {
    const double *src = *g->arr[j].a;
    double *dst = g->fresh[j];
    for (int i = 0; i < n; i++)
      memcpy(dst + (size_t)w * i, src + (size_t)w * perm[i], sizeof(double) * (size_t)w);
    memcpy(dst + (size_t)w * n, src + (size_t)w * n, sizeof(double) * (size_t)w * (size_t)(m - n));
  }
  if (w != 0) {
    free(*g->arr[j].a);
    *g->arr[j].a = g->fresh[j];
  } else {
    free(g->fresh[j]);
  }
}

int mpgm_points_sort(mpgm_ctx *ctx, mpgm_pool *pool, mpgm_points *p, const int *key, int nkey,
                     int *perm_out) {
  const int n = p->n, m = p->n + p->nprobe + p->nsurf;
  if (n <= 1) {
    if (perm_out && n == 1) perm_out[0] = 0;
    return 0;
  }
  point_array arr[NARR];
  point_arrays(p, arr);
  void *fresh[NARR] = {NULL};
  int *perm = perm_out ? perm_out : malloc(sizeof(int) * (size_t)n);
  int *cnt = calloc((size_t)nkey + 1, sizeof(int));
  int ok = perm && cnt;
  for (int j = 0; j < NARR && ok; j++) {
    const size_t bytes = arr[j].w < 0 ? sizeof(int) : sizeof(double) * (size_t)arr[j].w;
    ok = (fresh[j] = malloc(bytes * (size_t)p->cap + 1)) != NULL; /* (the room stays) */
  }
  if (!ok) { /* nothing moved yet */
    for (int j = 0; j < NARR; j++) free(fresh[j]);
    if (!perm_out) free(perm);
    free(cnt);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (sorting %d points)", n);
  }
  for (int i = 0; i < n; i++) cnt[key[i] + 1]++;
  for (int k = 0; k < nkey; k++) cnt[k + 1] += cnt[k];
  for (int i = 0; i < n; i++) perm[cnt[key[i]]++] = i;
  /* one gather pass per array, the arrays on the pool's threads */
  gather_job g = {arr, fresh, perm, n, m};
  mpgm_pool_run(pool, NARR, gather_task, &g);
  if (!perm_out) free(perm);
  free(cnt);
  mpgm_count(ctx, MPGM_C_POINT_SORTS, 1);
  return 0;
}

void mpgm_points_free(mpgm_points *p) {
  void *arr[] = {p->x, p->x0, p->u, p->v, p->a, p->mass, p->vol0, p->vol, p->F,
                 p->sigma, p->S0, p->r0, p->L, p->state, p->mat, p->body, p->id, p->F_t, p->dF_t, p->sigma_t,
                 p->D_t, p->state_t, p->vol_t};
  for (size_t i = 0; i < sizeof arr / sizeof arr[0]; i++) free(arr[i]);
  memset(p, 0, sizeof *p);
}

int mpgm_nodes_alloc(mpgm_ctx *ctx, mpgm_nodes *nd, int n) {
  nd->n = n;
  nd->cap = n;
  MPGM_ALLOC(ctx, nd->mass, n);
  MPGM_ALLOC(ctx, nd->X, MPGM_DIM * n);
  MPGM_ALLOC(ctx, nd->x, MPGM_DIM * n);
  MPGM_ALLOC(ctx, nd->u, MPGM_DIM * n);
  MPGM_ALLOC(ctx, nd->du, MPGM_DIM * n);
  MPGM_ALLOC(ctx, nd->v, MPGM_DIM * n);
  MPGM_ALLOC(ctx, nd->a, MPGM_DIM * n);
  MPGM_ALLOC(ctx, nd->v_new, MPGM_DIM * n);
  MPGM_ALLOC(ctx, nd->a_new, MPGM_DIM * n);
  MPGM_ALLOC(ctx, nd->fix, MPGM_DIM * n);
  MPGM_ALLOC(ctx, nd->contact, n);
  MPGM_ALLOC(ctx, nd->ubar, MPGM_DIM * n);
  MPGM_ALLOC(ctx, nd->dof, MPGM_DIM * n);
  return 0;
}

void mpgm_nodes_free(mpgm_nodes *nd) {
  void *arr[] = {nd->contact, nd->mass, nd->X, nd->x, nd->u, nd->du, nd->v, nd->a, nd->v_new, nd->a_new,
                 nd->fix, nd->ubar, nd->dof};
  for (size_t i = 0; i < sizeof arr / sizeof arr[0]; i++) free(arr[i]);
  memset(nd, 0, sizeof *nd);
}

int mpgm_conn_grow(mpgm_ctx *ctx, mpgm_conn *c, int keep, int nnz) {
  if (nnz <= c->cap) return 0;
  const size_t cap = (size_t)nnz + (size_t)nnz / 2 + 16;
  MPGM_CHECK(ctx, cap <= INT32_MAX, MPGM_ERR_NOMEM, "connectivity of %zu entries", cap);
  int *node = malloc(cap * sizeof(int));
  double *N = malloc(cap * sizeof(double)), *dN = malloc(MPGM_DIM * cap * sizeof(double));
  double *g = malloc(MPGM_DIM * cap * sizeof(double));
  if (!node || !N || !dN || !g) {
    free(node);
    free(N);
    free(dN);
    free(g);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (connectivity of %zu entries)", cap);
  }
  if (keep > 0) {
    memcpy(node, c->node, sizeof(int) * (size_t)keep);
    memcpy(N, c->N, sizeof(double) * (size_t)keep);
    memcpy(dN, c->dN, MPGM_DIM * sizeof(double) * (size_t)keep);
  }
  free(c->node);
  free(c->N);
  free(c->dN);
  free(c->g);
  c->node = node;
  c->N = N;
  c->dN = dN;
  c->g = g;
  c->cap = (int)cap;
  return 0;
}

void mpgm_nodes_number(mpgm_nodes *nd) {
  int k = 0;
  /* contact nodes keep their equations while held (held components get
   * identity rows), so that the matrix pattern does not depend on the
   * active set */
  for (int i = 0; i < MPGM_DIM * nd->n; i++)
    nd->dof[i] = nd->fix[i] && !nd->contact[i / MPGM_DIM] ? -1 : k++;
  nd->ndof = k;
}

int mpgm_conn_reserve(mpgm_ctx *ctx, mpgm_conn *c, int np, int nnz) {
  /* the first time exactly; a growth (points arriving from other
   * processes) with an eighth to spare, so that a count that goes up by a
   * few points at a time does not take fresh pages at every step */
  if (np + 1 > 0 && (!c->ptr || c->pcap < np + 1)) {
    const int room = c->ptr ? np + 1 + (np + 1) / 8 : np + 1;
    free(c->ptr);
    c->pcap = 0;
    MPGM_ALLOC(ctx, c->ptr, room);
    c->pcap = room;
  }
  c->np = np;
  if (nnz > c->cap) {
    if (c->cap > 0) nnz += nnz / 8;
    free(c->node);
    free(c->N);
    free(c->dN);
    free(c->g);
    c->node = NULL; c->N = c->dN = c->g = NULL;
    c->cap = 0;
    MPGM_ALLOC(ctx, c->node, nnz);
    MPGM_ALLOC(ctx, c->N, nnz);
    MPGM_ALLOC(ctx, c->dN, MPGM_DIM * (size_t)nnz);
    MPGM_ALLOC(ctx, c->g, MPGM_DIM * (size_t)nnz);
    c->cap = nnz;
  }
  return 0;
}

void mpgm_conn_release(mpgm_conn *c) {
  free(c->ptr);
  free(c->node);
  free(c->N);
  free(c->dN);
  free(c->g);
  free(c->tptr);
  free(c->tk);
  free(c->tp);
  free(c->tc);
  free(c->rc);
  memset(c, 0, sizeof *c);
}

void mpgm_effects_of_scene(const mpgm_scene *s, mpgm_effects *fx) {
  memset(fx, 0, sizeof *fx);
  fx->inertia = s->analysis != MPGM_ANALYSIS_STATIC;
  for (int d = 0; d < MPGM_DIM; d++) fx->gravity |= s->gravity[d] != 0.0;
  fx->geometric = s->kinematics == MPGM_KIN_FINITE;
  for (int i = 0; i < s->nmat; i++) fx->plasticity |= s->mats[i].plastic;
  for (int i = 0; i < s->nbc; i++) {
    for (int d = 0; d < MPGM_DIM; d++)
      fx->prescribed |= s->bcs[i].fix[d] && s->bcs[i].displacement[d] != 0.0;
    fx->contact |= s->bcs[i].condition == MPGM_COND_CONTACT && !mpgm_bc_at_points(&s->bcs[i]);
    fx->contact_points |= mpgm_bc_at_points(&s->bcs[i]);
  }
  for (int i = 0; i < s->nbody; i++) fx->prestress |= s->bodies[i].geostatic;
  fx->manufactured = s->manufactured;
  fx->tangent = !s->integrator || s->integrator->implicit;
}

