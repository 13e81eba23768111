/* test_mpm3.c -- the MPM front end in 3-D (mpm/mpm.c built with MPGM_DIM =
 * 3) through its own interface, with each grid shape kind of a 3-D build
 * (fe on H8 cells, ugimp, cpdi):
 *
 *   - create: a box on whole cells and a ball filled with 2 x 2 x 2 points
 *     per cell, a probe; the points' mass is the bodies';
 *   - begin_step (locate, shape functions, the light-node rule, the
 *     projection): at every point and the probe sum N = 1, sum N_a x_a =
 *     x_p and sum grad N_a (x) x_a = I (all three kinds reproduce linear
 *     fields); the nodes' mass is the points' and their momentum the
 *     points' (a rigid motion v0 + W x given to the points); the nodes of
 *     the step on z = 0 have their z fixed by the boundary and no other;
 *   - the same again after the points moved (a second step's begin_step):
 *     the lists follow them;
 *   - with the light-node rule of the default mesh.min_node_mass, which
 *     renormalises the functions of the points that lost a node: the
 *     partition of unity, the mass and the momentum. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "mpgm_core_impl.h"
#include "mpgm_discretisation.h"
#include "mpgm_mpm.h"
#include "mpgm_test.h"
#include "support_conn.h"

#if MPGM_DIM != 3
#error "test_mpm3.c checks the 3-D MPM front end: build it with MPGM_DIM = 3"
#endif

typedef struct world {
  mpgm_ctx ctx;
  mpgm_scene s;
  mpgm_material mat;
  mpgm_scene_body bodies[2];
  mpgm_scene_boundary bc;
  mpgm_scene_probe probe;
  mpgm_points pts;
  mpgm_nodes nodes;
  mpgm_conn conn;
  mpgm_effects fx;
  mpgm_pool *pool;
  mpgm_fe_view v;
} world;

static void world_init(world *w, const char *kind, double min_node_mass) {
  memset(w, 0, sizeof *w);
  mpgm_ctx_init(&w->ctx);
  mpgm_scene *s = &w->s;
  snprintf(s->file, sizeof s->file, "mpm3.json");
  s->shape = mpgm_shapefn_type_find(kind);
  s->cell = MPGM_CELL_H8;
  s->h = 0.25;
  s->ppc = 8;
  s->mesh_par.min_node_mass = min_node_mass;
  if (s->shape->grid_only) s->shape_par.half_width = s->h / (2.0 * cbrt((double)s->ppc));
  const double lo[3] = {-0.5, -0.5, -0.5}, hi[3] = {2.5, 1.5, 1.5};
  memcpy(s->dom_min, lo, sizeof lo);
  memcpy(s->dom_max, hi, sizeof hi);
  neo_hookean_of(&w->mat, 1500.0);
  s->mats = &w->mat;
  s->nmat = 1;
  mpgm_scene_body *b = w->bodies;
  b[0].geometry = MPGM_GEOM_BOX;
  const double bl[3] = {0.0, 0.0, 0.0}, bh[3] = {1.0, 0.5, 0.75};
  memcpy(b[0].min, bl, sizeof bl);
  memcpy(b[0].max, bh, sizeof bh);
  b[1].geometry = MPGM_GEOM_SPHERE;
  const double c[3] = {1.75, 0.5, 0.6};
  memcpy(b[1].centre, c, sizeof c);
  b[1].radius = 0.45;
  mpgm_body_bbox(&b[1], b[1].min, b[1].max);
  s->bodies = b;
  s->nbody = 2;
  w->bc = (mpgm_scene_boundary){.select = MPGM_SELECT_Z, .value = 0.0, .tol = 1e-9, .fix = {0, 0, 1}};
  s->bcs = &w->bc;
  s->nbc = 1;
  /* off the grid's planes: a tracer's grid functions (cpdi, ugimp: no
   * domain) are the hats at the point, whose gradient on a plane of nodes
   * is not the one-sided one (a tracer's gradient is never used) */
  const double px[3] = {0.4, 0.3, 0.55};
  memcpy(w->probe.x, px, sizeof px);
  s->probes = &w->probe;
  s->nprobe = 1;
  w->fx.inertia = 1;
  mpgm_pool_create(&w->ctx, 1, &w->pool);
  w->v = (mpgm_fe_view){.ctx = &w->ctx, .scene = s, .fx = &w->fx, .pts = &w->pts,
                        .nodes = &w->nodes, .conn = &w->conn, .pool = w->pool};
}

/* A rigid motion v = v0 + W x on the points. */
static void rigid_velocity(mpgm_points *P) {
  const double v0[3] = {0.3, -0.2, 0.1}, W[3] = {0.5, -0.25, 0.75};
  for (int p = 0; p < P->n + P->nprobe; p++) {
    const double *x = P->x + 3 * p;
    double *v = P->v + 3 * p;
    v[0] = v0[0] + W[1] * x[2] - W[2] * x[1];
    v[1] = v0[1] + W[2] * x[0] - W[0] * x[2];
    v[2] = v0[2] + W[0] * x[1] - W[1] * x[0];
  }
}

/* light: the light-node rule drops nodes and renormalises (Shepard), which
 * keeps the partition of unity and the mass, not linear fields. */
static void check_step(const world *w, const char *kind, int step, int light) {
  const mpgm_points *P = &w->pts;
  const mpgm_nodes *nd = &w->nodes;
  const mpgm_conn *C = &w->conn;
  const conn_errors e = conn_check(C, nd->X, P->x, P->n + P->nprobe);
  mpgm_test_abs(e.unity, 0.0, TEST_TOL3, "%s step %d: sum N = 1 at every point and the probe", kind, step);
  if (!light) {
    mpgm_test_abs(e.linear, 0.0, TEST_TOL4, "%s step %d: sum N_a x_a = x_p", kind, step);
    mpgm_test_abs(e.gradient, 0.0, TEST_TOL5, "%s step %d: sum grad N_a (x) x_a = I", kind, step);
  }
  double mp = 0.0, mn = 0.0, qp[3] = {0}, qn[3] = {0};
  for (int p = 0; p < P->n; p++) {
    mp += P->mass[p];
    for (int d = 0; d < 3; d++) qp[d] += P->mass[p] * P->v[3 * p + d];
  }
  int fix = 1;
  for (int i = 0; i < nd->n; i++) {
    mn += nd->mass[i];
    for (int d = 0; d < 3; d++) qn[d] += nd->mass[i] * nd->v[3 * i + d];
    const int onz = fabs(nd->X[3 * i + 2]) <= 1e-9;
    fix &= nd->fix[3 * i] == 0 && nd->fix[3 * i + 1] == 0 && nd->fix[3 * i + 2] == onz;
  }
  mpgm_test_rel(mn, mp, TEST_TOL3, "%s step %d: the nodes' mass is the points'", kind, step);
  double dq = 0.0, q = 0.0;
  for (int d = 0; d < 3; d++) dq = fmax(dq, fabs(qn[d] - qp[d])), q = fmax(q, fabs(qp[d]));
  mpgm_test_abs(dq / q, 0.0, TEST_TOL4, "%s step %d: the nodes' momentum is the points'", kind, step);
  mpgm_test(fix, "%s step %d: the step's nodes on z = 0 have z fixed, no other component", kind, step);
}

static void run_kind(const char *kind, double min_node_mass) {
  world w;
  world_init(&w, kind, min_node_mass);
  const int light = min_node_mass > 0.0;
  void *self = NULL;
  int err = mpgm_frontend_mpm.create(&w.v, &self);
  mpgm_test(err == 0, "%s: created (%s)", kind, w.ctx.msg);
  if (err) return;
  /* the box on 4 x 2 x 3 cells: 192 points of h^3 / 8 each; the ball's
   * points each h^3 / 8 too */
  double mb = 0.0, mball = 0.0;
  int nball = 0;
  for (int p = 0; p < w.pts.n; p++) {
    *(w.pts.body[p] ? &mball : &mb) += w.pts.mass[p];
    nball += w.pts.body[p] == 1;
  }
  mpgm_test(w.pts.n - nball == 192, "%s: the box on 24 cells has 192 points", kind);
  mpgm_test_rel(mb, 1500.0 * 0.375, TEST_TOL2, "%s: the box's points carry its mass", kind);
  mpgm_test_rel(mball, 1500.0 * nball * pow(0.25, 3) / 8, TEST_TOL2,
                "%s: each of the ball's %d points carries rho h^3 / 8", kind, nball);
  rigid_velocity(&w.pts);
  for (int step = 1; step <= 2; step++) {
    err = mpgm_frontend_mpm.begin_step(self, &w.v);
    mpgm_test(err == 0, "%s step %d: begin_step (%s)", kind, step, w.ctx.msg);
    if (err) break;
    check_step(&w, kind, step, light);
    mpgm_frontend_mpm.end_step(self, &w.v);
    for (int p = 0; p < w.pts.n + w.pts.nprobe; p++) /* move by a fraction of a cell */
      for (int d = 0; d < 3; d++) w.pts.x[3 * p + d] += 0.4 * 0.25 * w.pts.v[3 * p + d];
  }
  mpgm_frontend_mpm.destroy(self);
  mpgm_points_free(&w.pts);
  mpgm_nodes_free(&w.nodes);
  mpgm_conn_release(&w.conn);
  mpgm_pool_destroy(&w.pool);
}

int main(void) {
  /* no light nodes: linear fields are reproduced exactly */
  run_kind("fe", 0.0);
  run_kind("ugimp", 0.0);
  run_kind("cpdi", 0.0);
  /* the default rule (1 % of the heaviest node) */
  run_kind("fe", 1e-2);
  run_kind("cpdi", 1e-2);
  return mpgm_test_summary();
}
