/* test_hexgrid.c -- the structured background grid in 3-D (discretisation/
 * grid.c built with MPGM_DIM = 3): H8 cells over a box.
 *
 *   - sizes: the box extended to whole cells, node and cell counts;
 *   - every cell's eight nodes are the corners of its cube in H8 order
 *     (bottom face counter-clockwise seen from +z, then the top face), and
 *     the ids of neighbouring cells' shared corners agree;
 *   - locate: random points (and points on faces, edges, corners and the
 *     box's far faces) land in the cube that holds them, and the trilinear
 *     map of their local coordinates (written here, not fe.c's) gives the
 *     point back; points beyond the box are MPGM_ERR_DOMAIN;
 *   - neighbours: 26 inside, 7 at a corner, each sharing a node;
 *   - filling (discretisation/fill.c) with 2 x 2 x 2 points per cell in
 *     the gauss and centres layouts: a box on whole cells gets 8 points
 *     per cell at the rule's positions, volumes summing to its own; a
 *     ball's points lie in it and their volumes approach 4/3 pi r^3;
 *   - a scene with another cell kind or too many nodes is refused. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "mpgm_discretisation.h"
#include "mpgm_grid.h"
#include "mpgm_test.h"

#if MPGM_DIM != 3
#error "test_hexgrid.c checks the 3-D grid: build it with MPGM_DIM = 3"
#endif

static void scene_box(mpgm_scene *s, const double lo[3], const double hi[3], double h) {
  memset(s, 0, sizeof *s);
  snprintf(s->file, sizeof s->file, "hexgrid.json");
  s->cell = MPGM_CELL_H8;
  s->h = h;
  s->ppc = 8;
  memcpy(s->dom_min, lo, sizeof s->dom_min);
  memcpy(s->dom_max, hi, sizeof s->dom_max);
}

/* The H8 corner signs of node a (as mpgm_shapefn.h orders them). */
static void corner(int a, int s[3]) {
  static const int q[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  s[0] = q[a % 4][0];
  s[1] = q[a % 4][1];
  s[2] = a < 4 ? -1 : 1;
}

static void test_cells(const mpgm_grid *g) {
  int ok = 1, shared = 1;
  for (int c = 0; c < g->ncell; c++) {
    int nodes[8];
    double xn[24];
    mpgm_grid_cell(g, c, nodes, xn);
    const int i = c % g->nx, j = (c / g->nx) % g->ny, k = c / (g->nx * g->ny);
    for (int a = 0; a < 8; a++) {
      int s[3];
      corner(a, s);
      const int ijk[3] = {i + (s[0] > 0), j + (s[1] > 0), k + (s[2] > 0)};
      for (int d = 0; d < 3; d++) ok &= xn[3 * a + d] == g->min[d] + ijk[d] * g->h;
      double X[3];
      mpgm_grid_node(g, nodes[a], X);
      for (int d = 0; d < 3; d++) ok &= X[d] == xn[3 * a + d];
      ok &= nodes[a] >= 0 && nodes[a] < g->nnode;
    }
    if (i + 1 < g->nx) { /* the right neighbour's left face is this cell's right face */
      int right[8];
      mpgm_grid_cell(g, c + 1, right, NULL);
      shared &= right[0] == nodes[1] && right[3] == nodes[2] && right[4] == nodes[5] && right[7] == nodes[6];
    }
    if (k + 1 < g->nz) { /* the cell above's bottom face is this cell's top */
      int up[8];
      mpgm_grid_cell(g, c + g->nx * g->ny, up, NULL);
      for (int a = 0; a < 4; a++) shared &= up[a] == nodes[a + 4];
    }
  }
  mpgm_test(ok, "every cell's nodes are its cube's corners in H8 order (%d cells)", g->ncell);
  mpgm_test(shared, "neighbouring cells share their face's node ids");
}

/* x = sum_a N_a(xi) x_a with the trilinear N written out. */
static void trilinear(const double *xn, const double xi[3], double x[3]) {
  for (int d = 0; d < 3; d++) x[d] = 0.0;
  for (int a = 0; a < 8; a++) {
    int s[3];
    corner(a, s);
    const double N = 0.125 * (1 + s[0] * xi[0]) * (1 + s[1] * xi[1]) * (1 + s[2] * xi[2]);
    for (int d = 0; d < 3; d++) x[d] += N * xn[3 * a + d];
  }
}

static int locate_back(const mpgm_grid *g, const double x[3], double *err) {
  int c;
  double xi[3], xn[24], y[3];
  int nodes[8];
  if (mpgm_grid_locate(g, x, &c, xi)) return 0;
  mpgm_grid_cell(g, c, nodes, xn);
  trilinear(xn, xi, y);
  int in = 1;
  for (int d = 0; d < 3; d++) {
    in &= xi[d] >= -1.0 - 1e-9 && xi[d] <= 1.0 + 1e-9;
    *err = fmax(*err, fabs(y[d] - x[d]));
  }
  return in;
}

static void test_locate(const mpgm_grid *g) {
  rng r = {0x9e3779b97f4a7c15ull};
  double err = 0.0;
  int ok = 1;
  for (int k = 0; k < 2000; k++) {
    double x[3];
    for (int d = 0; d < 3; d++) x[d] = uniform(&r, g->min[d], g->max[d]);
    ok &= locate_back(g, x, &err);
  }
  /* on grid lines: faces, edges, corners, and the far faces of the box */
  for (int k = 0; k < 200; k++) {
    double x[3];
    for (int d = 0; d < 3; d++) {
      const int n = d == 0 ? g->nx : d == 1 ? g->ny : g->nz;
      x[d] = uniform(&r, 0, 1) < 0.5 ? g->min[d] + (int)uniform(&r, 0, n + 1) * g->h
                                     : uniform(&r, g->min[d], g->max[d]);
    }
    ok &= locate_back(g, x, &err);
  }
  mpgm_test(ok, "locate: 2200 points land in their cube (local coordinates in [-1, 1]^3)");
  mpgm_test_abs(err, 0.0, 1e-12, "locate: the trilinear map of the local coordinates gives the point back");
  const double out[3][3] = {{g->min[0] - 1e-6, g->min[1], g->min[2]},
                            {g->min[0], g->max[1] + 1e-6, g->min[2]},
                            {g->min[0], g->min[1], g->max[2] + 1e-6}};
  int dom = 1;
  for (int k = 0; k < 3; k++) {
    int c;
    double xi[3];
    dom &= mpgm_grid_locate(g, out[k], &c, xi) == MPGM_ERR_DOMAIN;
  }
  mpgm_test(dom, "locate: points beyond the box's faces are MPGM_ERR_DOMAIN");
}

static void test_neighbours(const mpgm_grid *g) {
  int out[32];
  const int inner = (1 * g->ny + 1) * g->nx + 1;
  mpgm_test(mpgm_grid_neighbours(g, inner, out) == 26, "neighbours: 26 around an inner cell");
  const int n0 = mpgm_grid_neighbours(g, 0, out);
  int share = n0 == 7, mine[8];
  mpgm_grid_cell(g, 0, mine, NULL);
  for (int k = 0; k < n0; k++) {
    int other[8], common = 0;
    mpgm_grid_cell(g, out[k], other, NULL);
    for (int a = 0; a < 8; a++)
      for (int b = 0; b < 8; b++) common |= mine[a] == other[b];
    share &= common;
  }
  mpgm_test(share, "neighbours: 7 at the corner cell, each sharing a node with it");
}

/* A box on whole cells and a ball, filled in the layout given. */
static void test_fill(int centres) {
  const char *name = centres ? "centres" : "gauss";
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene s;
  const double lo[3] = {0, 0, 0}, hi[3] = {3, 2, 2};
  scene_box(&s, lo, hi, 0.25);
  s.layout_centres = centres;
  mpgm_scene_body bodies[2];
  memset(bodies, 0, sizeof bodies);
  bodies[0].geometry = MPGM_GEOM_BOX;
  const double bl[3] = {0.25, 0.5, 0.0}, bh[3] = {1.25, 1.0, 0.75};
  memcpy(bodies[0].min, bl, sizeof bl);
  memcpy(bodies[0].max, bh, sizeof bh);
  bodies[1].geometry = MPGM_GEOM_SPHERE;
  const double c[3] = {2.2, 1.0, 1.0}, r = 0.7;
  memcpy(bodies[1].centre, c, sizeof c);
  bodies[1].radius = r;
  mpgm_body_bbox(&bodies[1], bodies[1].min, bodies[1].max);
  s.bodies = bodies;
  s.nbody = 2;
  mpgm_grid g;
  mpgm_fill f;
  mpgm_test(mpgm_grid_init(&ctx, &g, &s) == 0 && mpgm_grid_fill(&ctx, &g, &s, &f) == 0,
            "%s: a box and a ball filled (%s)", name, ctx.msg);
  int nbox = 0, at_rule = 1, in_ball = 1;
  double vbox = 0.0, vball = 0.0;
  /* the rule's offsets from a cell's lower corner, in cells: gauss
   * (1 -+ 1/sqrt 3) / 2, centres 1/4 and 3/4 */
  const double o = centres ? 0.25 : 0.5 * (1.0 - 1.0 / sqrt(3.0));
  for (size_t k = 0; k < f.ngauss; k++) {
    const double *x = f.x + 3 * k;
    if (f.owner[k] == 0) {
      nbox++;
      vbox += f.vol[k % 8];
      for (int d = 0; d < 3; d++) {
        const double t = x[d] / 0.25 - floor(x[d] / 0.25);
        at_rule &= fabs(t - o) < 1e-12 || fabs(t - (1.0 - o)) < 1e-12;
      }
    } else if (f.owner[k] == 1) {
      vball += f.vol[k % 8];
      in_ball &= mpgm_body_contains(&bodies[1], x);
    }
  }
  mpgm_test(nbox == 4 * 2 * 3 * 8, "%s: the box on 24 cells has 192 points (%d)", name, nbox);
  mpgm_test(at_rule, "%s: the box's points sit at the rule's positions in their cells", name);
  mpgm_test_rel(vbox, 1.0 * 0.5 * 0.75, TEST_TOL2, "%s: the box's point volumes sum to its volume", name);
  mpgm_test(in_ball, "%s: the ball's points lie in it", name);
  mpgm_test_rel(vball, 4.0 / 3.0 * 3.14159265358979323846 * r * r * r, 0.03,
                "%s: the ball's point volumes approach 4/3 pi r^3 (3 %%, h = r / 2.8)", name);
  mpgm_fill_free(&f);
}

int main(void) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene s;
  const double lo[3] = {-0.5, 0.25, 1.0}, hi[3] = {1.3, 1.0, 1.9};
  scene_box(&s, lo, hi, 0.25);
  mpgm_grid g;
  mpgm_test(mpgm_grid_init(&ctx, &g, &s) == 0, "init over a box 1.8 x 0.75 x 0.9, h = 0.25");
  mpgm_test(g.nx == 8 && g.ny == 3 && g.nz == 4 && g.nn == 8, "the box extended to whole cells: 8 x 3 x 4");
  mpgm_test(g.nnode == 9 * 4 * 5 && g.ncell == 96, "nodes 180, cells 96");
  mpgm_test_rel(g.max[0], -0.5 + 8 * 0.25, TEST_TOL0, "covered box: max = min + n h");
  test_cells(&g);
  test_locate(&g);
  test_neighbours(&g);
  test_fill(0);
  test_fill(1);
  scene_box(&s, lo, hi, 0.25);
  s.cell = MPGM_CELL_H8 + 1;
  mpgm_test(mpgm_grid_init(&ctx, &g, &s) == MPGM_ERR_INPUT, "another cell kind is refused");
  mpgm_ctx_init(&ctx);
  const double big[3] = {1000, 1000, 1000}, zero[3] = {0, 0, 0};
  scene_box(&s, zero, big, 1.0);
  mpgm_test(mpgm_grid_init(&ctx, &g, &s) == MPGM_ERR_INPUT, "a grid of 1e9 nodes is refused");
  return mpgm_test_summary();
}
