/* fem.c -- UL-FEM front end: each rectangle body meshed by a structured
 * grid of Q4 cells (or two T3 per square) of size <= mesh.h; the problem is
 * then built by mpgm_fem_setup_mesh (fem_mesh.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_frontends.h"

/* Cells of a body meshed nx x ny over [min, max]; count (if not NULL)
 * accumulates its nodes and cells, unclamped, in double. */
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

static int fem_setup(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *s = pb->scene;
  const int per_sq = s->cell == MPGM_CELL_Q4 ? 1 : 2, nn = mpgm_fe_nnode(s->cell);
  /* count: in double first, so a tiny h cannot overflow the integers */
  double count[2] = {0.0, 0.0};
  int nx, ny;
  for (int b = 0; b < s->nbody; b++) body_grid(s, &s->bodies[b], &nx, &ny, count);
  MPGM_CHECK(ctx, count[0] < 5e7 && count[1] * per_sq * s->ppc < 1e8, MPGM_ERR_INPUT,
             "%s: mesh.h: expected a mesh of at most 5e7 nodes and 1e8 points, found %.4g nodes "
             "and %.4g points (h = %g)", s->file, count[0], count[1] * per_sq * s->ppc, s->h);
  const int nnode = (int)count[0], ncell = (int)count[1] * per_sq;
  double *X = malloc(sizeof(double) * 2 * (size_t)nnode);
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
        X[2 * k] = i == nx ? bd->max[0] : bd->min[0] + i * hx;
        X[2 * k + 1] = j == ny ? bd->max[1] : bd->min[1] + j * hy;
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
  int err = mpgm_fem_setup_mesh(pb, &mesh);
  free(X);
  free(cnode);
  free(cbody);
  return err;
}

const mpgm_frontend_ops mpgm_frontend_fem = {
    .name = "fem",
    .point_velocity = MPGM_PV_INTERPOLATE,
    .setup = fem_setup,
    .begin_step = mpgm_fem_begin_step,
    .end_step = mpgm_fem_end_step,
    .cells = mpgm_fem_cells,
    .destroy = mpgm_fem_destroy,
};
