/* test_hexmesh.c -- FE meshes of boxes in 3-D (discretisation/mesh.c built
 * with MPGM_DIM = 3): H8 cells for UL-FEM.
 *
 *   - two box bodies meshed with their own spacing (one not a multiple of
 *     h): node and cell counts, nodes on the boxes' faces exactly;
 *   - the Gauss points: 8 per cell, volumes summing to each box's volume,
 *     positions inside their body, masses density x volume;
 *   - the shape functions of every point (mpgm_fem_cells_shape): partition
 *     of unity, sum N_a x_a = x_p and sum grad N_a (x) x_a = I;
 *   - boundaries selected by a z plane and by a box fix the components
 *     they name on exactly the nodes they should;
 *   - a probe is placed in its cell; one outside every body is refused. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "mpgm_core_impl.h" /* mpgm_points_free, mpgm_nodes_free */
#include "mpgm_discretisation.h"
#include "mpgm_test.h"
#include "support_conn.h"

#if MPGM_DIM != 3
#error "test_hexmesh.c checks the 3-D meshes: build it with MPGM_DIM = 3"
#endif

typedef struct world {
  mpgm_ctx ctx;
  mpgm_scene s;
  mpgm_material mat;
  mpgm_scene_body bodies[2];
  mpgm_scene_boundary bcs[2];
  mpgm_scene_probe probe;
  mpgm_points pts;
  mpgm_nodes nodes;
  mpgm_conn conn;
  mpgm_effects fx;
  mpgm_fe_view v;
} world;

static void box(mpgm_scene_body *b, const double lo[3], const double hi[3]) {
  memset(b, 0, sizeof *b);
  b->geometry = MPGM_GEOM_BOX;
  memcpy(b->min, lo, sizeof b->min);
  memcpy(b->max, hi, sizeof b->max);
}

static void world_init(world *w, const double probe[3]) {
  memset(w, 0, sizeof *w);
  mpgm_ctx_init(&w->ctx);
  mpgm_scene *s = &w->s;
  snprintf(s->file, sizeof s->file, "hexmesh.json");
  s->cell = MPGM_CELL_H8;
  s->h = 0.25;
  s->ppc = 8;
  neo_hookean_of(&w->mat, 2000.0);
  s->mats = &w->mat;
  s->nmat = 1;
  const double l0[3] = {0, 0, 0}, h0[3] = {1.0, 0.5, 0.75};
  const double l1[3] = {2.0, 0.0, 0.0}, h1[3] = {2.6, 0.3, 0.4}; /* 0.6 / 0.25: 3 cells of 0.2 */
  box(&w->bodies[0], l0, h0);
  box(&w->bodies[1], l1, h1);
  s->bodies = w->bodies;
  s->nbody = 2;
  /* z = 0 held in z; the box around the second body's x = 2.6 face held in all */
  w->bcs[0] = (mpgm_scene_boundary){.select = MPGM_SELECT_Z, .value = 0.0, .tol = 1e-9, .fix = {0, 0, 1}};
  w->bcs[1] = (mpgm_scene_boundary){.select = MPGM_SELECT_BOX, .min = {2.6, -1, -1}, .max = {2.6, 1, 1},
                                    .tol = 1e-9, .fix = {1, 1, 1}};
  s->bcs = w->bcs;
  s->nbc = 2;
  memcpy(w->probe.x, probe, sizeof w->probe.x);
  s->probes = &w->probe;
  s->nprobe = 1;
  w->v = (mpgm_fe_view){.ctx = &w->ctx, .scene = s, .fx = &w->fx, .pts = &w->pts,
                        .nodes = &w->nodes, .conn = &w->conn};
}

static void test_counts(const world *w) {
  /* body 0: 4 x 2 x 3 cells, 5 x 3 x 4 nodes; body 1: 3 x 2 x 2 cells, 4 x 3 x 3 nodes */
  mpgm_test(w->nodes.n == 60 + 36, "nodes: 5 x 3 x 4 + 4 x 3 x 3 = 96 (%d)", w->nodes.n);
  mpgm_test(w->pts.n == (24 + 12) * 8, "points: 8 per cell of 36 cells (%d)", w->pts.n);
  int faces = 1;
  for (int k = 0; k < w->nodes.n; k++) {
    const double *X = w->nodes.X + 3 * k;
    const mpgm_scene_body *b = &w->bodies[k < 60 ? 0 : 1];
    for (int d = 0; d < 3; d++) faces &= X[d] >= b->min[d] && X[d] <= b->max[d];
  }
  mpgm_test(faces, "every node lies in its box, the last row on its far faces");
  double v[2] = {0, 0}, m = 0.0;
  int inside = 1;
  for (int p = 0; p < w->pts.n; p++) {
    v[w->pts.body[p]] += w->pts.vol[p];
    m += w->pts.mass[p];
    inside &= mpgm_body_contains(&w->bodies[w->pts.body[p]], w->pts.x + 3 * p);
  }
  mpgm_test_rel(v[0], 1.0 * 0.5 * 0.75, TEST_TOL2, "the first box's point volumes sum to its volume");
  mpgm_test_rel(v[1], 0.6 * 0.3 * 0.4, TEST_TOL2, "the second box's point volumes sum to its volume");
  mpgm_test_rel(m, 2000.0 * (v[0] + v[1]), TEST_TOL2, "masses are density x volume");
  mpgm_test(inside, "every Gauss point lies in its body");
}

static void test_shape(const world *w) {
  const conn_errors e = conn_check(&w->conn, w->nodes.X, w->pts.x, w->pts.n + w->pts.nprobe);
  mpgm_test_abs(e.unity, 0.0, TEST_TOL2, "shape: sum N = 1 at every point and the probe");
  mpgm_test_abs(e.linear, 0.0, TEST_TOL3, "shape: sum N_a x_a = x_p");
  mpgm_test_abs(e.gradient, 0.0, TEST_TOL4, "shape: sum grad N_a (x) x_a = I");
}

static void test_fixity(const world *w) {
  int ok = 1, nz = 0, nb = 0;
  for (int k = 0; k < w->nodes.n; k++) {
    const double *X = w->nodes.X + 3 * k;
    const int onz = fabs(X[2]) <= 1e-9, onb = fabs(X[0] - 2.6) <= 1e-9;
    nz += onz, nb += onb;
    const unsigned char *f = w->nodes.fix + 3 * k;
    ok &= f[0] == onb && f[1] == onb && f[2] == (onz || onb);
  }
  mpgm_test(ok && nz == 15 + 12 && nb == 9, "boundaries: z = 0 holds z on its 27 nodes, the box all "
            "three on the 9 of x = 2.6 (%d, %d)", nz, nb);
}

int main(void) {
  world w;
  const double probe[3] = {0.4, 0.3, 0.6};
  world_init(&w, probe);
  mpgm_fem_cells *cells = NULL;
  int err = mpgm_fem_rectangles(&w.v, &cells);
  mpgm_test(err == 0, "two boxes meshed with H8 cells (%s)", w.ctx.msg);
  if (err) return mpgm_test_summary();
  mpgm_test(mpgm_fem_cells_shape(cells, &w.v) == 0, "the points' shape functions");
  test_counts(&w);
  test_shape(&w);
  test_fixity(&w);
  const int q = w.pts.n;
  mpgm_test(fabs(w.pts.x[3 * q] - 0.4) + fabs(w.pts.x[3 * q + 2] - 0.6) == 0.0,
            "the probe sits at its position");
  mpgm_fem_cells_destroy(cells);
  mpgm_points_free(&w.pts);
  mpgm_nodes_free(&w.nodes);
  mpgm_conn_release(&w.conn);
  const double away[3] = {1.5, 0.2, 0.2};
  world w2;
  world_init(&w2, away);
  cells = NULL;
  err = mpgm_fem_rectangles(&w2.v, &cells);
  mpgm_test(err == MPGM_ERR_INPUT && strstr(w2.ctx.msg, "probes") && strstr(w2.ctx.msg, "(1.5, 0.2, 0.2)"),
            "a probe outside every body is refused: %s", w2.ctx.msg);
  mpgm_fem_cells_destroy(cells);
  mpgm_points_free(&w2.pts);
  mpgm_nodes_free(&w2.nodes);
  mpgm_conn_release(&w2.conn);
  return mpgm_test_summary();
}
