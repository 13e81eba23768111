/* mesh.c -- persistent-node FE problems over any conforming mesh of T3 or
 * Q4 cells (2-D) or H8 cells (3-D): nodes, Gauss points, probes,
 * boundaries, connectivity, and the shape functions of every step
 * (mpgm_discretisation.h); the structured meshes of rectangle (box)
 * bodies. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_discretisation.h"


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

/* The coordinates of cell c's nodes. */
static void cell_coords(const fem_data *d, const double *x, int c, double *xn) {
  const int *cn = d->cnode + (size_t)d->nn * c;
  for (int a = 0; a < d->nn; a++)
    memcpy(xn + MPGM_DIM * a, x + MPGM_DIM * cn[a], sizeof(double) * MPGM_DIM);
}

/* The VTK cell type of a kind: VTK_TRIANGLE, VTK_QUAD, VTK_HEXAHEDRON. */
static int vtk_type(int cell) {
  return cell == MPGM_CELL_H8 ? 12 : cell == MPGM_CELL_Q4 ? 9 : 5;
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
  double gxi[MPGM_DIM * MPGM_MAXRULE], gw[MPGM_MAXRULE];
  MPGM_CALL(mpgm_points_rule(s, m->cell, gxi, gw));
  int p = 0;
  for (int c = 0; c < m->ncell; c++) {
    const int b = m->cbody[c];
    const mpgm_scene_body *bd = &s->bodies[b];
    const int *cn = d->cnode + (size_t)d->nn * c;
    d->cptr[c + 1] = d->cptr[c] + d->nn;
    d->ctype[c] = vtk_type(m->cell);
    for (int a = 0; a < d->nn; a++)
      memcpy(nd->v + MPGM_DIM * cn[a], bd->velocity, sizeof(double) * MPGM_DIM);
    double xn[MPGM_DIM * MPGM_FE_MAXNODE];
    cell_coords(d, nd->X, c, xn);
    for (int g = 0; g < s->ppc; g++, p++) {
      double N[MPGM_FE_MAXNODE], dN[MPGM_DIM * MPGM_FE_MAXNODE], detJ;
      int err = mpgm_fe_eval(m->cell, xn, gxi + MPGM_DIM * g, N, dN, &detJ);
      MPGM_CHECK(ctx, !err, err, "%s: cell %d of body \"%s\" is inverted (det J = %g)", s->file, c,
                 bd->name, detJ);
      double x[MPGM_DIM] = {0};
      for (int a = 0; a < d->nn; a++)
        for (int k = 0; k < MPGM_DIM; k++) x[k] += N[a] * xn[MPGM_DIM * a + k];
      mpgm_point_set(P, p, s, b, x, gw[g] * detJ);
      d->pcell[p] = c;
      memcpy(d->pxi + MPGM_DIM * p, gxi + MPGM_DIM * g, sizeof(double) * MPGM_DIM);
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
        memcpy(d->pxi + MPGM_DIM * p, xi, sizeof xi);
      }
    }
    char at[MPGM_POINT_STR];
    MPGM_CHECK(ctx, found >= 0, MPGM_ERR_INPUT,
               "%s: probes.%s: expected a position inside a body, found %s", s->file,
               s->probes[k].name, mpgm_point_str(xp, at));
    d->pcell[p] = found;
    for (int i = 0; i < MPGM_DIM; i++) P->x[MPGM_DIM * p + i] = P->x0[MPGM_DIM * p + i] = xp[i];
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

/* The cells of a body meshed n[0] x n[1] (x n[2]) over its box [min,
 * max]; count (if not NULL) accumulates its nodes and cells, unclamped, in
 * double. */
static void body_grid(const mpgm_scene *s, const mpgm_scene_body *b, int n[MPGM_DIM],
                      double count[2]) {
  double nodes = 1.0, cells = 1.0;
  for (int d = 0; d < MPGM_DIM; d++) {
    const double f = fmax(1.0, ceil((b->max[d] - b->min[d]) / s->h - 1e-9));
    nodes *= f + 1.0;
    cells *= f;
    /* clamp before converting: a tiny h overflows int (the caller checks
     * the size in double first) */
    n[d] = f > 1e9 ? 1000000000 : (int)f;
  }
  if (count) {
    count[0] += nodes;
    count[1] += cells;
  }
}

/* The nodes of a body's structured mesh, from node n0 on: (i, j(, k)) at
 * n0 + (k (ny + 1) + j) (nx + 1) + i, the last one of a row on the box's
 * far side exactly. */
static void body_nodes(const mpgm_scene_body *bd, const int n[MPGM_DIM], int n0, double *X) {
  double h[MPGM_DIM];
  int total = 1;
  for (int d = 0; d < MPGM_DIM; d++) {
    h[d] = (bd->max[d] - bd->min[d]) / n[d];
    total *= n[d] + 1;
  }
  for (int k = 0; k < total; k++)
    for (int d = 0, r = k; d < MPGM_DIM; r /= n[d] + 1, d++) {
      const int i = r % (n[d] + 1);
      X[MPGM_DIM * (n0 + k) + d] = i == n[d] ? bd->max[d] : bd->min[d] + i * h[d];
    }
}

/* The cells of square (cube) q of a body's mesh: Q4 its corners, T3 two
 * triangles, H8 the bottom face then the top; returns how many. */
static int square_cells(int cell, const int n[MPGM_DIM], int n0, int q, int *cnode) {
  const int w = n[0] + 1, i = q % n[0], j = (q / n[0]) % n[1];
  const int k = MPGM_DIM == 3 ? q / (n[0] * n[1]) : 0;
  const int l = MPGM_DIM == 3 ? w * (n[1] + 1) : 0;
  int c[8];
  for (int t = 0; t < (MPGM_DIM == 3 ? 2 : 1); t++) {
    const int b = n0 + (k + t) * l;
    c[4 * t + 0] = b + j * w + i;
    c[4 * t + 1] = b + j * w + i + 1;
    c[4 * t + 2] = b + (j + 1) * w + i + 1;
    c[4 * t + 3] = b + (j + 1) * w + i;
  }
  if (cell != MPGM_CELL_T3) {
    memcpy(cnode, c, sizeof(int) * (size_t)mpgm_fe_nnode(cell));
    return 1;
  }
  const int tri[6] = {c[0], c[1], c[2], c[0], c[2], c[3]};
  memcpy(cnode, tri, sizeof tri);
  return 2;
}

int mpgm_fem_rectangles(const mpgm_fe_view *v, mpgm_fem_cells **out) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_scene *s = v->scene;
  const int per_sq = s->cell == MPGM_CELL_T3 ? 2 : 1, nn = mpgm_fe_nnode(s->cell);
  /* count: in double first, so a tiny h cannot overflow the integers */
  double count[2] = {0.0, 0.0};
  int n[MPGM_DIM];
  for (int b = 0; b < s->nbody; b++) body_grid(s, &s->bodies[b], n, count);
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
    body_grid(s, &s->bodies[b], n, NULL);
    body_nodes(&s->bodies[b], n, n0, X);
    int nsq = 1, nodes = 1;
    for (int d = 0; d < MPGM_DIM; d++) nsq *= n[d], nodes *= n[d] + 1;
    for (int q = 0; q < nsq; q++) {
      const int k = square_cells(s->cell, n, n0, q, cnode + (size_t)nn * c);
      for (int t = 0; t < k; t++) cbody[c++] = b;
    }
    n0 += nodes;
  }
  const mpgm_fem_mesh mesh = {s->cell, nnode, X, ncell, cnode, cbody};
  int err = mpgm_fem_cells_create(v, &mesh, out);
  free(X);
  free(cnode);
  free(cbody);
  return err;
}
