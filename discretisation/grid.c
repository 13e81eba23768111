/* grid.c -- structured background grid (mpgm_grid.h): squares nx x ny in
 * 2-D (Q4 or two T3 each), cubes nx x ny x nz of H8 cells in 3-D. The
 * plane code is the one written out in x and y before the grid had a 3-D
 * build, kept as it was so that 2-D runs are unchanged to the bit; the 3-D
 * functions follow it (grid_3d below). */
#include "mpgm_grid.h"

#include <math.h>

#if MPGM_DIM == 2

int mpgm_grid_init(mpgm_ctx *ctx, mpgm_grid *g, const mpgm_scene *s) {
  g->cell = s->cell;
  g->nn = mpgm_fe_nnode(s->cell);
  g->h = s->h;
  const double fx = ceil((s->dom_max[0] - s->dom_min[0]) / s->h - 1e-9);
  const double fy = ceil((s->dom_max[1] - s->dom_min[1]) / s->h - 1e-9);
  const double per = s->cell == MPGM_CELL_Q4 ? 1.0 : 2.0;
  MPGM_CHECK(ctx, (fx + 1) * (fy + 1) < 5e7 && fx * fy * per * s->ppc < 1e8, MPGM_ERR_INPUT,
             "%s: mesh.h: expected a background grid of at most 5e7 nodes and 1e8 Gauss points "
             "over mesh.domain, found %.4g nodes (h = %g)", s->file, (fx + 1) * (fy + 1), s->h);
  g->nx = fx < 1 ? 1 : (int)fx;
  g->ny = fy < 1 ? 1 : (int)fy;
  g->nz = 0;
  for (int d = 0; d < MPGM_DIM; d++) g->min[d] = s->dom_min[d];
  g->max[0] = g->min[0] + g->nx * g->h;
  g->max[1] = g->min[1] + g->ny * g->h;
  g->nnode = (g->nx + 1) * (g->ny + 1);
  g->ncell = g->nx * g->ny * (int)per;
  return 0;
}

void mpgm_grid_node(const mpgm_grid *g, int id, double X[MPGM_DIM]) {
  const int i = id % (g->nx + 1), j = id / (g->nx + 1);
  X[0] = g->min[0] + i * g->h;
  X[1] = g->min[1] + j * g->h;
}

void mpgm_grid_cell(const mpgm_grid *g, int c, int *nodes, double *xn) {
  const int sq = g->cell == MPGM_CELL_Q4 ? c : c / 2;
  const int i = sq % g->nx, j = sq / g->nx, w = g->nx + 1;
  const int q[4] = {j * w + i, j * w + i + 1, (j + 1) * w + i + 1, (j + 1) * w + i};
  if (g->cell == MPGM_CELL_Q4) {
    for (int a = 0; a < 4; a++) nodes[a] = q[a];
  } else if (c % 2 == 0) {
    nodes[0] = q[0]; nodes[1] = q[1]; nodes[2] = q[2];
  } else {
    nodes[0] = q[0]; nodes[1] = q[2]; nodes[2] = q[3];
  }
  if (xn)
    for (int a = 0; a < g->nn; a++) mpgm_grid_node(g, nodes[a], xn + MPGM_DIM * a);
}

int mpgm_grid_locate(const mpgm_grid *g, const double x[MPGM_DIM], int *cell,
                     double xi[MPGM_DIM]) {
  const double s = (x[0] - g->min[0]) / g->h, t = (x[1] - g->min[1]) / g->h;
  const double tol = 1e-9;
  if (!(s >= -tol && s <= g->nx + tol && t >= -tol && t <= g->ny + tol)) return MPGM_ERR_DOMAIN;
  int i = (int)floor(s), j = (int)floor(t);
  if (i < 0) i = 0;
  if (j < 0) j = 0;
  if (i >= g->nx) i = g->nx - 1;
  if (j >= g->ny) j = g->ny - 1;
  const double fs = s - i, ft = t - j; /* in [0, 1] */
  const int sq = j * g->nx + i;
  if (g->cell == MPGM_CELL_Q4) {
    *cell = sq;
    xi[0] = 2.0 * fs - 1.0;
    xi[1] = 2.0 * ft - 1.0;
  } else if (fs >= ft) { /* lower-right triangle (q0, q1, q2) */
    *cell = 2 * sq;
    xi[0] = fs - ft;
    xi[1] = ft;
  } else { /* upper-left triangle (q0, q2, q3) */
    *cell = 2 * sq + 1;
    xi[0] = fs;
    xi[1] = ft - fs;
  }
  return 0;
}

int mpgm_grid_neighbours(const mpgm_grid *g, int c, int *out) {
  const int per = g->cell == MPGM_CELL_Q4 ? 1 : 2;
  const int sq = c / per, i0 = sq % g->nx, j0 = sq / g->nx;
  int n = 0;
  for (int j = j0 - 1; j <= j0 + 1; j++)
    for (int i = i0 - 1; i <= i0 + 1; i++) {
      if (i < 0 || j < 0 || i >= g->nx || j >= g->ny) continue;
      for (int t = 0; t < per; t++) {
        const int cc = (j * g->nx + i) * per + t;
        if (cc != c) out[n++] = cc;
      }
    }
  return n;
}

#else /* MPGM_DIM == 3 */

int mpgm_grid_init(mpgm_ctx *ctx, mpgm_grid *g, const mpgm_scene *s) {
  MPGM_CHECK(ctx, s->cell == MPGM_CELL_H8, MPGM_ERR_INPUT,
             "%s: mesh.cell: expected \"hex\" in 3-D (H8 cells), found another kind", s->file);
  g->cell = s->cell;
  g->nn = mpgm_fe_nnode(s->cell);
  g->h = s->h;
  double f[3], nodes = 1.0, cells = 1.0;
  for (int d = 0; d < 3; d++) {
    f[d] = ceil((s->dom_max[d] - s->dom_min[d]) / s->h - 1e-9);
    if (f[d] < 1) f[d] = 1;
    nodes *= f[d] + 1;
    cells *= f[d];
  }
  MPGM_CHECK(ctx, nodes < 5e7 && cells * s->ppc < 1e8, MPGM_ERR_INPUT,
             "%s: mesh.h: expected a background grid of at most 5e7 nodes and 1e8 Gauss points "
             "over mesh.domain, found %.4g nodes (h = %g)", s->file, nodes, s->h);
  g->nx = (int)f[0];
  g->ny = (int)f[1];
  g->nz = (int)f[2];
  for (int d = 0; d < 3; d++) {
    g->min[d] = s->dom_min[d];
    g->max[d] = g->min[d] + f[d] * g->h;
  }
  g->nnode = (g->nx + 1) * (g->ny + 1) * (g->nz + 1);
  g->ncell = g->nx * g->ny * g->nz;
  return 0;
}

void mpgm_grid_node(const mpgm_grid *g, int id, double X[MPGM_DIM]) {
  const int w = g->nx + 1, l = w * (g->ny + 1);
  const int k = id / l, j = (id % l) / w, i = id % w;
  X[0] = g->min[0] + i * g->h;
  X[1] = g->min[1] + j * g->h;
  X[2] = g->min[2] + k * g->h;
}

void mpgm_grid_cell(const mpgm_grid *g, int c, int *nodes, double *xn) {
  const int q = c / g->nx, k = q / g->ny; /* two divisions for i, j, k */
  const int i = c - q * g->nx, j = q - k * g->ny;
  const int w = g->nx + 1, l = w * (g->ny + 1);
  for (int t = 0; t < 2; t++) { /* the bottom face, then the top one */
    const int b = (k + t) * l;
    nodes[4 * t + 0] = b + j * w + i;
    nodes[4 * t + 1] = b + j * w + i + 1;
    nodes[4 * t + 2] = b + (j + 1) * w + i + 1;
    nodes[4 * t + 3] = b + (j + 1) * w + i;
  }
  if (xn)
    for (int a = 0; a < 8; a++) mpgm_grid_node(g, nodes[a], xn + MPGM_DIM * a);
}

int mpgm_grid_locate(const mpgm_grid *g, const double x[MPGM_DIM], int *cell,
                     double xi[MPGM_DIM]) {
  const int n[3] = {g->nx, g->ny, g->nz};
  const double tol = 1e-9;
  int ijk[3];
  for (int d = 0; d < 3; d++) {
    const double s = (x[d] - g->min[d]) / g->h;
    if (!(s >= -tol && s <= n[d] + tol)) return MPGM_ERR_DOMAIN;
    /* truncation is floor for s >= 0; below 0 (within tol) both clamp to 0 */
    int i = (int)s;
    i = i < 0 ? 0 : i >= n[d] ? n[d] - 1 : i;
    ijk[d] = i;
    xi[d] = 2.0 * (s - i) - 1.0;
  }
  *cell = (ijk[2] * g->ny + ijk[1]) * g->nx + ijk[0];
  return 0;
}

int mpgm_grid_neighbours(const mpgm_grid *g, int c, int *out) {
  const int i0 = c % g->nx, j0 = (c / g->nx) % g->ny, k0 = c / (g->nx * g->ny);
  int n = 0;
  for (int k = k0 - 1; k <= k0 + 1; k++)
    for (int j = j0 - 1; j <= j0 + 1; j++)
      for (int i = i0 - 1; i <= i0 + 1; i++) {
        if (i < 0 || j < 0 || k < 0 || i >= g->nx || j >= g->ny || k >= g->nz) continue;
        const int cc = (k * g->ny + j) * g->nx + i;
        if (cc != c) out[n++] = cc;
      }
  return n;
}

#endif
