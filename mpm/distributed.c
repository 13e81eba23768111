/* distributed.c -- the MPM front end on many processes (mpm_private.h):
 * the background grid's nodes partitioned over the processes
 * (mpgm_pgrid: PETSc's DMDA), each process holding the material points of
 * its own cells, the points that crossed into another process's cells
 * sent there at the start of every step (DMSwarm), and the sums over the
 * points at the nodes shared with other processes completed by the
 * partition's scatters. The probes stay on every process: each step one
 * process moves a probe, the one whose cell holds it, and the others take
 * its values at the step's end. On one process each function here does
 * nothing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpm_private.h"

/* The (i, j, k) of grid node id ((i, j, 0) in a plane grid). */
static void node_ijk(const mpgm_grid *g, int id, int ijk[3]) {
  const int w = g->nx + 1, l = w * (g->ny + 1);
  ijk[0] = id % w;
  ijk[1] = (id % l) / w;
  ijk[2] = MPGM_DIM == 3 ? id / l : 0;
}

/* The (i, j, k) of the square (cube) that holds x, as mpgm_grid_locate
 * finds it (without the local coordinates); -1 outside the grid. */
static int cube_of(const mpgm_grid *g, const double *x, int ijk[3]) {
  const int n[3] = {g->nx, g->ny, MPGM_DIM == 3 ? g->nz : 1};
  ijk[0] = ijk[1] = ijk[2] = 0;
  for (int k = 0; k < MPGM_DIM; k++) {
    const double s = (x[k] - g->min[k]) / g->h;
    if (!(s >= -1e-9 && s <= n[k] + 1e-9)) return -1;
    const int i = (int)s; /* (floor for s >= 0; below 0, within the tolerance, both clamp to 0) */
    ijk[k] = i < 0 ? 0 : i >= n[k] ? n[k] - 1 : i;
  }
  return 0;
}

/* The process whose cell holds x; -1 outside the grid (the point stays
 * where it is, and locate says so). */
static int owner_of(const mpm_data *d, const double *x) {
  int ijk[3];
  return cube_of(&d->g, x, ijk) ? -1 : mpgm_pgrid_owner(d->pg, ijk);
}

/* Persistent scratch of n doubles (the sums' values, the probes'): a
 * fresh block every step would cost its pages every step. */
double *mpgm_mpm_scratch(mpgm_ctx *ctx, mpm_data *d, size_t n) {
  if (n + 1 > d->xbufcap) {
    free(d->xbuf);
    d->xbufcap = 0;
    d->xbuf = malloc(sizeof(double) * (n + n / 8 + 1));
    if (!d->xbuf) {
      mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory (%zu values)", n);
      return NULL;
    }
    d->xbufcap = n + n / 8 + 1;
  }
  return d->xbuf;
}

/* Room for m points in the front end's per-point arrays and the
 * connectivity's lists. */
static int grow_points(const mpgm_fe_view *v, mpm_data *d, int m) {
  MPGM_CALL(mpgm_conn_reserve(v->ctx, v->conn, m, m * d->g.nn)); /* covers exactly m */
  if (m <= d->pcap) return 0;
  const int cap = m + m / 4 + 16;
  free(d->pcell), free(d->pxi), free(d->perm), free(d->pscr);
  d->pcell = NULL, d->pxi = NULL, d->perm = NULL, d->pscr = NULL;
  d->pcap = 0;
  MPGM_ALLOC(v->ctx, d->pcell, cap);
  MPGM_ALLOC(v->ctx, d->pxi, MPGM_DIM * (size_t)cap);
  MPGM_ALLOC(v->ctx, d->perm, cap);
  MPGM_ALLOC(v->ctx, d->pscr, MPGM_DIM * (size_t)cap);
  d->pcap = cap;
  return 0;
}

/* The material points this process keeps (its cells') and those that
 * arrive from the others (nothing is sent by `send` 0: the start, where
 * every process made the same points and keeps its own). */
static int exchange(const mpgm_fe_view *v, mpm_data *d, int send) {
  mpgm_ctx *ctx = v->ctx;
  mpgm_points *P = v->pts;
  const int np = P->n, rank = mpgm_ctx_rank(ctx), rec = mpgm_point_record_len(P);
  if (np + 1 > d->xcap) { /* (kept: a fresh block every step costs its pages) */
    free(d->xkeep), free(d->xdest);
    d->xcap = 0;
    d->xkeep = malloc((size_t)np + np / 8 + 1);
    d->xdest = malloc(sizeof(int) * ((size_t)np + np / 8 + 1));
    MPGM_CHECK(ctx, d->xkeep && d->xdest, MPGM_ERR_NOMEM, "out of memory (the points' owners)");
    d->xcap = np + np / 8 + 1;
  }
  unsigned char *keep = d->xkeep;
  int *dest = d->xdest, nout = 0, nin = 0;
  for (int p = 0; p < np; p++) {
    const int o = owner_of(d, P->x + MPGM_DIM * p);
    keep[p] = o < 0 || o == rank;
    if (!keep[p]) dest[nout++] = o;
  }
  long moving = nout;
  int err = send ? mpgm_allreduce_long(ctx, MPGM_REDUCE_SUM, &moving, 1) : 0;
  double *out = NULL, *in = NULL;
  if (!err && send && moving > 0) {
    out = malloc(sizeof(double) * ((size_t)rec * nout + 1));
    err = out ? 0 : mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory (%d "
                                 "points leaving)", nout);
    if (!err) mpgm_points_pack(P, keep, out);
    if (!err) err = mpgm_pgrid_migrate(ctx, d->pg, rec, nout, out, dest, &nin, &in);
  }
  if (!err && (nout > 0 || nin > 0)) err = mpgm_points_exchange(ctx, P, keep, nin, in);
  free(out), free(in);
  MPGM_CALL(err);
  return grow_points(v, d, P->n + P->nprobe + P->nsurf);
}

int mpgm_mpm_check(mpgm_ctx *ctx, const mpgm_scene *s) {
  const int np = mpgm_ctx_size(ctx);
  if (np == 1) return 0;
  const mpgm_shapefn_type *k = s->shape;
  /* the partition's ghost layers cover a cell's nodes and uGIMP's two
   * rings; clouds and CPDI's domains reach further */
  MPGM_CHECK(ctx, (k->needs_cell || k->grid_only) && !k->domain && !k->velocity_ls, MPGM_ERR_INPUT,
             "%s: shape.kind: method mpm runs shape.kind \"%s\" on one process only so far, and this "
             "run was started on %d (kinds that run on many: fe, ugimp); run it without mpiexec, "
             "or with -n 1", s->file, k->name, np);
  for (int i = 0; i < s->nbc; i++)
    MPGM_CHECK(ctx, s->bcs[i].condition != MPGM_COND_CONTACT, MPGM_ERR_INPUT,
               "%s: boundaries[%d].condition: method mpm enforces contact on one process only so "
               "far, and this run was started on %d; run it without mpiexec, or with -n 1", s->file,
               i, np);
  return 0;
}

/* The partition of the grid's nodes cut by the points per layer of cells
 * in each direction: this process's points, or with `all` every
 * process's (summed over them). The partition before, if any, is freed. */
static int partition(const mpgm_fe_view *v, mpm_data *d, int all) {
  const mpgm_grid *g = &d->g;
  const int n[3] = {g->nx + 1, g->ny + 1, MPGM_DIM == 3 ? g->nz + 1 : 1};
  const int nw = n[0] + n[1] + n[2];
  double *w = calloc((size_t)nw, sizeof(double));
  MPGM_CHECK(v->ctx, w, MPGM_ERR_NOMEM, "out of memory (the points' layers)");
  const double *const wd[3] = {w, w + n[0], w + n[0] + n[1]};
  for (int p = 0; p < v->pts->n; p++) {
    int ijk[3];
    if (cube_of(g, v->pts->x + MPGM_DIM * p, ijk)) continue;
    for (int k = 0; k < MPGM_DIM; k++) w[(k ? n[0] : 0) + (k > 1 ? n[1] : 0) + ijk[k]] += 1.0;
  }
  int err = all ? mpgm_allreduce(v->ctx, MPGM_REDUCE_SUM, w, nw) : 0;
  mpgm_pgrid *pg = NULL; /* (the stencil: the nodes a point's functions reach beyond its
                          * cell, one layer for the cell's own, two for uGIMP and CPDI) */
  if (!err) err = mpgm_pgrid_create(v->ctx, MPGM_DIM, n, MPM_XW, d->gridfn ? 2 : 1, wd, &pg);
  free(w);
  MPGM_CALL(err);
  mpgm_pgrid_destroy(&d->pg);
  d->pg = pg;
  return 0;
}

int mpgm_mpm_dist_create(const mpgm_fe_view *v, mpm_data *d) {
  d->pcap = v->pts->n + v->pts->nprobe + v->pts->nsurf;
  if (mpgm_ctx_size(v->ctx) == 1) return 0;
  /* the slabs cut where they share the points evenly (every process has
   * them all now) */
  MPGM_CALL(partition(v, d, 0));
  return exchange(v, d, 0);
}

int mpgm_mpm_dist_migrate(const mpgm_fe_view *v, mpm_data *d) {
  if (!d->pg) return 0;
  /* rebalancing: the points have drifted apart since the last cut (the
   * imbalance above MPM_REBALANCE and a tenth above what the cut left) */
  double imb;
  MPGM_CALL(mpgm_imbalance(v->ctx, v->pts->n, &imb));
  const int cut = imb > MPM_REBALANCE && imb > 1.1 * d->imb_cut;
  if (cut) MPGM_CALL(partition(v, d, 1));
  MPGM_CALL(exchange(v, d, 1));
  if (!cut) return 0;
  const double was = imb;
  MPGM_CALL(mpgm_imbalance(v->ctx, v->pts->n, &d->imb_cut));
  mpgm_log(v->ctx, MPGM_LOG_INFO, "step %ld: the grid's slabs cut again by the points: imbalance "
           "%.3f -> %.3f (most points on a process over the mean)", v->step + 1, was, d->imb_cut);
  return 0;
}

/* The sums at n grid nodes (ids gid) of w values each in val. */
static int sums_at(mpgm_ctx *ctx, mpm_data *d, int n, const int *gid, int w, double *val) {
  if (n > d->nx || !d->xijk) { /* (room for one at least: a process without points sums too) */
    free(d->xijk);
    d->xijk = NULL;
    d->nx = 0;
    MPGM_ALLOC(ctx, d->xijk, MPGM_DIM * ((size_t)n + n / 8 + 1));
    d->nx = n + n / 8 + 1;
  }
  for (int i = 0; i < n; i++) {
    int ijk[3];
    node_ijk(&d->g, gid[i], ijk);
    memcpy(d->xijk + MPGM_DIM * i, ijk, sizeof(int) * MPGM_DIM);
  }
  return mpgm_pgrid_sum(ctx, d->pg, n, d->xijk, w, val);
}

int mpgm_mpm_node_sums(void *self, mpgm_ctx *ctx, int w, double *val) {
  mpm_data *d = self;
  if (!d->pg) return 0;
  MPGM_CHECK(ctx, w >= 1 && w <= MPM_XW, MPGM_ERR_INTERNAL, "sums of %d values per node", w);
  return sums_at(ctx, d, d->nstep, d->lglob, w, val);
}

int mpgm_mpm_dist_owned(const mpgm_fe_view *v, mpm_data *d) {
  if (!d->pg) return 0;
  if (d->g.nnode > d->nowned_cap) {
    free(d->nowned);
    d->nowned_cap = 0;
    MPGM_ALLOC(v->ctx, d->nowned, d->g.nnode);
    d->nowned_cap = d->g.nnode;
  }
  const int rank = mpgm_ctx_rank(v->ctx);
  for (int i = 0; i < d->nstep; i++) {
    int ijk[3];
    node_ijk(&d->g, d->lglob[i], ijk);
    d->nowned[i] = mpgm_pgrid_owner(d->pg, ijk) == rank;
  }
  v->nodes->owned = d->nowned;
  return 0;
}

/* The light-node rule on many processes: its masses are the sums over
 * every process's points, and the heaviest node is the run's. The sums
 * are taken at the nodes this process's points reach, and at those of the
 * probes it moves: a probe's node may carry only another process's mass. */
int mpgm_mpm_dist_light(const mpgm_fe_view *v, mpm_data *d) {
  if (!d->pg) return 0;
  const mpgm_grid *g = &d->g;
  const mpgm_conn *C = v->conn;
  const int first = v->pts->n;
  for (int i = 0; i < g->nnode; i++) d->light[i] = d->gm[i] > 0.0; /* light as scratch: set below */
  for (int k = 0; k < v->pts->nprobe; k++)
    for (int e = C->ptr[first + k]; !d->pskip[k] && e < C->ptr[first + k + 1]; e++) d->light[C->node[e]] = 1;
  int n = 0;
  for (int i = 0; i < g->nnode; i++)
    if (d->light[i]) d->gmap[n++] = i; /* gmap as scratch: step_nodes sets it anew */
  double *m = mpgm_mpm_scratch(v->ctx, d, (size_t)n);
  if (!m) return MPGM_ERR_NOMEM;
  for (int i = 0; i < n; i++) m[i] = d->gm[d->gmap[i]];
  int err = sums_at(v->ctx, d, n, d->gmap, 1, m);
  double mmax = 0.0;
  for (int i = 0; i < n && !err; i++) {
    d->gm[d->gmap[i]] = m[i];
    mmax = fmax(mmax, m[i]);
  }
  MPGM_CALL(err);
  MPGM_CALL(mpgm_allreduce(v->ctx, MPGM_REDUCE_MAX, &mmax, 1));
  const double cut = v->scene->mesh_par.min_node_mass * mmax;
  for (int i = 0; i < g->nnode; i++) d->light[i] = !(d->gm[i] > cut); /* mpgm_light_nodes' rule */
  return 0;
}

/* sync 0: the mover of every probe, the process whose cell holds it now
 * (a probe outside the grid: the first process); sync 1: the probes'
 * position, displacement, velocity and acceleration, which only the
 * mover's step set, on every process. The others give zeros to a sum,
 * which leaves the mover's numbers exact. */
int mpgm_mpm_dist_probes(const mpgm_fe_view *v, mpm_data *d, int sync) {
  mpgm_points *P = v->pts;
  const int np = P->nprobe, rank = mpgm_ctx_rank(v->ctx);
  if (!d->pg || np == 0) return 0;
  if (!d->powner) {
    MPGM_ALLOC(v->ctx, d->powner, np);
    MPGM_ALLOC(v->ctx, d->pskip, np + P->nsurf);
  }
  if (!sync) {
    for (int k = 0; k < np; k++) {
      const int o = owner_of(d, P->x + MPGM_DIM * (P->n + k));
      d->powner[k] = o < 0 ? 0 : o;
      d->pskip[k] = d->powner[k] != rank;
    }
    return 0;
  }
  double *const arr[4] = {P->x, P->u, P->v, P->a};
  const size_t w = 4 * MPGM_DIM;
  double *buf = mpgm_mpm_scratch(v->ctx, d, w * (size_t)np);
  if (!buf) return MPGM_ERR_NOMEM;
  memset(buf, 0, sizeof(double) * w * (size_t)np);
  for (int k = 0; k < np; k++)
    for (int j = 0; d->powner[k] == rank && j < 4; j++)
      memcpy(buf + w * k + MPGM_DIM * j, arr[j] + MPGM_DIM * (P->n + k), sizeof(double) * MPGM_DIM);
  const int err = mpgm_allreduce(v->ctx, MPGM_REDUCE_SUM, buf, (int)w * np);
  for (int k = 0; k < np && !err; k++)
    for (int j = 0; j < 4; j++)
      memcpy(arr[j] + MPGM_DIM * (P->n + k), buf + w * k + MPGM_DIM * j, sizeof(double) * MPGM_DIM);
  return err;
}

void mpgm_mpm_dist_free(mpm_data *d) {
  free(d->nowned);
  free(d->xkeep);
  free(d->xdest);
  free(d->powner);
  free(d->pskip);
  mpgm_pgrid_destroy(&d->pg);
  free(d->xijk);
  free(d->xbuf);
}
