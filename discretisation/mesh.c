/* mesh.c -- persistent-node FE problems over any conforming mesh of T3 or
 * Q4 cells: nodes, Gauss points, probes, boundaries, connectivity, and the
 * shape functions of every step (mpgm_discretisation.h); the structured
 * meshes of rectangle bodies. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_discretisation.h"

#if MPGM_DIM != 2
#error "discretisation/mesh.c is written for plane strain only (MPGM_DIM = 2)"
#endif

struct mpgm_fem_cells {
  int cell;        /**< mpgm_cell_kind of every cell                  */
  int nn;          /**< nodes per cell                                */
  int ncell;
  int *cnode;      /**< nn node ids per cell (counter-clockwise)       */
  int *cptr, *ctype; /**< CSR offsets and VTK types, for output        */
  int *pcell;      /**< cell of every point (material and tracer)      */
  double *pxi;     /**< local coordinates of every point, MPGM_DIM each */
};
typedef struct mpgm_fem_cells fem_data;

void mpgm_fem_cells_destroy(mpgm_fem_cells *d) {
  if (!d) return;
  free(d->cnode);
  free(d->cptr);
  free(d->ctype);
  free(d->pcell);
  free(d->pxi);
  free(d);
}

/* The coordinates of cell c's nodes (2-D only: x and y written out). */
static void cell_coords(const fem_data *d, const double *x, int c, double *xn) {
  const int *cn = d->cnode + (size_t)d->nn * c;
  for (int a = 0; a < d->nn; a++) {
    xn[MPGM_DIM * a] = x[MPGM_DIM * cn[a]];
    xn[MPGM_DIM * a + 1] = x[MPGM_DIM * cn[a] + 1];
  }
}

int mpgm_fem_cells_create(const mpgm_fe_view *v, const mpgm_fem_mesh *m, mpgm_fem_cells **out) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_scene *s = v->scene;
  fem_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *out = d; /* from here the caller's mpgm_fem_cells_destroy frees it */
  d->cell = m->cell;
  d->nn = mpgm_fe_nnode(m->cell);
  d->ncell = m->ncell;
  const int npts = m->ncell * s->ppc;
  MPGM_CALL(mpgm_nodes_alloc(ctx, v->nodes, m->nnode));
  MPGM_CALL(mpgm_points_alloc(ctx, v->pts, npts, s->nprobe, 0, mpgm_scene_nstate(s)));
  MPGM_ALLOC(ctx, d->cnode, (size_t)d->nn * m->ncell);
  MPGM_ALLOC(ctx, d->cptr, m->ncell + 1);
  MPGM_ALLOC(ctx, d->ctype, m->ncell);
  MPGM_ALLOC(ctx, d->pcell, npts + s->nprobe);
  MPGM_ALLOC(ctx, d->pxi, MPGM_DIM * (size_t)(npts + s->nprobe));
  memcpy(d->cnode, m->cnode, sizeof(int) * (size_t)d->nn * m->ncell);
  mpgm_nodes *nd = v->nodes;
  mpgm_points *P = v->pts;
  memcpy(nd->X, m->X, sizeof(double) * MPGM_DIM * (size_t)m->nnode);
  memcpy(nd->x, m->X, sizeof(double) * MPGM_DIM * (size_t)m->nnode);
  double gxi[MPGM_DIM * 9], gw[9]; /* rules of up to 9 points */
  MPGM_CALL(mpgm_points_rule(s, m->cell, gxi, gw));
  int p = 0;
  for (int c = 0; c < m->ncell; c++) {
    const int b = m->cbody[c];
    const mpgm_scene_body *bd = &s->bodies[b];
    const int *cn = d->cnode + (size_t)d->nn * c;
    d->cptr[c + 1] = d->cptr[c] + d->nn;
    d->ctype[c] = m->cell == MPGM_CELL_Q4 ? 9 : 5; /* VTK_QUAD, VTK_TRIANGLE */
    /* 2-D only: velocities, positions and local coordinates written out in
     * x and y here and for the probes below */
    for (int a = 0; a < d->nn; a++) {
      nd->v[MPGM_DIM * cn[a]] = bd->velocity[0];
      nd->v[MPGM_DIM * cn[a] + 1] = bd->velocity[1];
    }
    double xn[MPGM_DIM * MPGM_FE_MAXNODE];
    cell_coords(d, nd->X, c, xn);
    for (int g = 0; g < s->ppc; g++, p++) {
      double N[MPGM_FE_MAXNODE], dN[MPGM_DIM * MPGM_FE_MAXNODE], detJ;
      int err = mpgm_fe_eval(m->cell, xn, gxi + MPGM_DIM * g, N, dN, &detJ);
      MPGM_CHECK(ctx, !err, err, "%s: cell %d of body \"%s\" is inverted (det J = %g)", s->file, c,
                 bd->name, detJ);
      double x[MPGM_DIM] = {0, 0}; /* 2-D only: x and y written out */
      for (int a = 0; a < d->nn; a++) {
        x[0] += N[a] * xn[MPGM_DIM * a];
        x[1] += N[a] * xn[MPGM_DIM * a + 1];
      }
      mpgm_point_set(P, p, s, b, x, gw[g] * detJ);
      d->pcell[p] = c;
      d->pxi[MPGM_DIM * p] = gxi[MPGM_DIM * g];
      d->pxi[MPGM_DIM * p + 1] = gxi[MPGM_DIM * g + 1];
    }
  }
  /* probes: the cell holding the reference position */
  for (int k = 0; k < s->nprobe; k++, p++) {
    const double *xp = s->probes[k].x;
    int found = -1;
    for (int cc = 0; cc < d->ncell && found < 0; cc++) {
      double xn[MPGM_DIM * MPGM_FE_MAXNODE], xi[MPGM_DIM];
      cell_coords(d, nd->X, cc, xn);
      if (mpgm_fe_local(m->cell, xn, xp, xi) == 0 && mpgm_fe_inside(m->cell, xi, 1e-10)) {
        found = cc;
        d->pxi[MPGM_DIM * p] = xi[0];
        d->pxi[MPGM_DIM * p + 1] = xi[1];
      }
    }
    MPGM_CHECK(ctx, found >= 0, MPGM_ERR_INPUT,
               "%s: probes.%s: expected a position inside a body, found (%g, %g)", s->file,
               s->probes[k].name, xp[0], xp[1]);
    d->pcell[p] = found;
    P->x[MPGM_DIM * p] = P->x0[MPGM_DIM * p] = xp[0];
    P->x[MPGM_DIM * p + 1] = P->x0[MPGM_DIM * p + 1] = xp[1];
  }
  MPGM_CALL(mpgm_nodes_apply_boundaries(ctx, s, nd));
  /* connectivity pattern: fixed for the whole run */
  const int np = npts + s->nprobe;
  MPGM_CALL(mpgm_conn_reserve(ctx, v->conn, np, np * d->nn));
  for (int q = 0; q < np; q++) {
    v->conn->ptr[q + 1] = v->conn->ptr[q] + d->nn;
    memcpy(v->conn->node + v->conn->ptr[q], d->cnode + (size_t)d->nn * d->pcell[q],
           sizeof(int) * d->nn);
  }
  v->conn->version = 1;
  return 0;
}

int mpgm_fem_cells_shape(const mpgm_fem_cells *d, const mpgm_fe_view *v) {
  mpgm_conn *C = v->conn;
  const double *x = v->nodes->x;
  const int np = v->pts->n + v->pts->nprobe;
  for (int p = 0; p < np; p++) {
    const int k0 = C->ptr[p];
    double xn[MPGM_DIM * MPGM_FE_MAXNODE];
    cell_coords(d, x, d->pcell[p], xn);
    int err = mpgm_fe_eval(d->cell, xn, d->pxi + MPGM_DIM * p, C->N + k0, C->dN + MPGM_DIM * k0,
                           NULL);
    if (err && p < v->pts->n)
      MPGM_ERROR(v->ctx, err, "cell %d of point %d is inverted (det J <= 0)", d->pcell[p], p);
  }
  return 0;
}

int mpgm_fem_cells_output(const mpgm_fem_cells *d, mpgm_cells *out) {
  out->n = d->ncell;
  out->ptr = d->cptr;
  out->node = d->cnode;
  out->type = d->ctype;
  return 0;
}

/* Cells of a body meshed nx x ny over [min, max]; count (if not NULL)
 * accumulates its nodes and cells, unclamped, in double. 2-D only, as the
 * structured meshes of rectangles below: squares nx x ny in x and y. */
static void body_grid(const mpgm_scene *s, const mpgm_scene_body *b, int *nx, int *ny,
                      double count[2]) {
  const double fx = fmax(1.0, ceil((b->max[0] - b->min[0]) / s->h - 1e-9));
  const double fy = fmax(1.0, ceil((b->max[1] - b->min[1]) / s->h - 1e-9));
  if (count) {
    count[0] += (fx + 1.0) * (fy + 1.0);
    count[1] += fx * fy;
  }
  /* clamp before converting: a tiny h overflows int (fem_setup checks the
   * size in double first) */
  *nx = fx > 1e9 ? 1000000000 : (int)fx;
  *ny = fy > 1e9 ? 1000000000 : (int)fy;
}

int mpgm_fem_rectangles(const mpgm_fe_view *v, mpgm_fem_cells **out) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_scene *s = v->scene;
  const int per_sq = s->cell == MPGM_CELL_Q4 ? 1 : 2, nn = mpgm_fe_nnode(s->cell);
  /* count: in double first, so a tiny h cannot overflow the integers */
  double count[2] = {0.0, 0.0};
  int nx, ny;
  for (int b = 0; b < s->nbody; b++) body_grid(s, &s->bodies[b], &nx, &ny, count);
  MPGM_CHECK(ctx, count[0] < 5e7 && count[1] * per_sq * s->ppc < 1e8, MPGM_ERR_INPUT,
             "%s: mesh.h: expected a mesh of at most 5e7 nodes and 1e8 points, found %.4g nodes "
             "and %.4g points (h = %g)", s->file, count[0], count[1] * per_sq * s->ppc, s->h);
  const int nnode = (int)count[0], ncell = (int)count[1] * per_sq;
  double *X = malloc(sizeof(double) * MPGM_DIM * (size_t)nnode);
  int *cnode = malloc(sizeof(int) * (size_t)nn * ncell), *cbody = malloc(sizeof(int) * (size_t)ncell);
  if (!X || !cnode || !cbody) {
    free(X); free(cnode); free(cbody);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (mesh of %d nodes)", nnode);
  }
  int n0 = 0, c = 0;
  for (int b = 0; b < s->nbody; b++) {
    const mpgm_scene_body *bd = &s->bodies[b];
    body_grid(s, bd, &nx, &ny, NULL);
    const double hx = (bd->max[0] - bd->min[0]) / nx, hy = (bd->max[1] - bd->min[1]) / ny;
    for (int j = 0; j <= ny; j++)
      for (int i = 0; i <= nx; i++) {
        const int k = n0 + j * (nx + 1) + i;
        X[MPGM_DIM * k] = i == nx ? bd->max[0] : bd->min[0] + i * hx;
        X[MPGM_DIM * k + 1] = j == ny ? bd->max[1] : bd->min[1] + j * hy;
      }
    for (int j = 0; j < ny; j++)
      for (int i = 0; i < nx; i++) {
        const int q[4] = {n0 + j * (nx + 1) + i, n0 + j * (nx + 1) + i + 1,
                          n0 + (j + 1) * (nx + 1) + i + 1, n0 + (j + 1) * (nx + 1) + i};
        const int tri[2][3] = {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
        for (int t = 0; t < per_sq; t++, c++) {
          memcpy(cnode + (size_t)nn * c, per_sq == 1 ? q : tri[t], sizeof(int) * nn);
          cbody[c] = b;
        }
      }
    n0 += (nx + 1) * (ny + 1);
  }
  const mpgm_fem_mesh mesh = {s->cell, nnode, X, ncell, cnode, cbody};
  int err = mpgm_fem_cells_create(v, &mesh, out);
  free(X);
  free(cnode);
  free(cbody);
  return err;
}
