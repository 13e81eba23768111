/* support_mesh.c -- see support_mesh.h. */
#include "support_mesh.h"

#include <stdlib.h>
#include <string.h>

#include "mpgm_test.h"
#include "mpgm_scene_io.h"

/* Strictly convex, counter-clockwise polygon. */
static int convex(int nn, const double *xn) {
  for (int i = 0; i < nn; i++) {
    const int j = (i + 1) % nn, k = (i + 2) % nn;
    const double ex = xn[2 * j] - xn[2 * i], ey = xn[2 * j + 1] - xn[2 * i + 1];
    const double fx = xn[2 * k] - xn[2 * j], fy = xn[2 * k + 1] - xn[2 * j + 1];
    if (!(ex * fy - ey * fx > 0.0)) return 0;
  }
  return 1;
}

int support_distorted_mesh(const mpgm_fe_view *v, int nx, int ny, double lx, double ly,
                           double jitter, uint64_t seed, mpgm_fem_cells **out) {
  mpgm_ctx *ctx = v->ctx;
  const int cell = v->scene->cell, per = cell == MPGM_CELL_Q4 ? 1 : 2, nn = mpgm_fe_nnode(cell);
  const int nnode = (nx + 1) * (ny + 1), ncell = nx * ny * per;
  double *X = calloc(2 * (size_t)nnode, sizeof(double));
  int *cnode = calloc((size_t)nn * ncell, sizeof(int)), *cbody = calloc(ncell, sizeof(int));
  int err = (!X || !cnode || !cbody) ? mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "oom") : 0;
  const double hx = lx / nx, hy = ly / ny;
  rng r = {seed};
  for (int j = 0; j <= ny && !err; j++)
    for (int i = 0; i <= nx; i++) {
      const int k = j * (nx + 1) + i;
      double x = i * hx, y = j * hy;
      if (i > 0 && i < nx && j > 0 && j < ny) {
        x += uniform(&r, -jitter, jitter) * hx;
        y += uniform(&r, -jitter, jitter) * hy;
      }
      X[2 * k] = i == nx ? lx : x;
      X[2 * k + 1] = j == ny ? ly : y;
    }
  for (int j = 0, c = 0; j < ny && !err; j++)
    for (int i = 0; i < nx && !err; i++) {
      const int q[4] = {j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1,
                        (j + 1) * (nx + 1) + i};
      const int alt = (i + j) % 2; /* T3: both diagonal orientations occur */
      const int tri[2][3] = {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
      const int tra[2][3] = {{q[0], q[1], q[3]}, {q[1], q[2], q[3]}};
      for (int t = 0; t < per && !err; t++, c++) {
        int *cn = cnode + (size_t)nn * c;
        memcpy(cn, per == 1 ? q : alt ? tra[t] : tri[t], sizeof(int) * nn);
        double xn[2 * MPGM_FE_MAXNODE];
        for (int a = 0; a < nn; a++) {
          xn[2 * a] = X[2 * cn[a]];
          xn[2 * a + 1] = X[2 * cn[a] + 1];
        }
        if (!convex(nn, xn))
          err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "test mesh: cell %d not convex", c);
      }
    }
  if (!err) {
    const mpgm_fem_mesh m = {cell, nnode, X, ncell, cnode, cbody};
    err = mpgm_fem_cells_create(v, &m, out);
  }
  free(X);
  free(cnode);
  free(cbody);
  return err;
}

void support_fem_destroy(void *self) { mpgm_fem_cells_destroy(self); }

int support_fem_begin_step(void *self, const mpgm_fe_view *v) { return mpgm_fem_cells_shape(self, v); }

int support_fem_cells(const void *self, mpgm_cells *out) { return mpgm_fem_cells_output(self, out); }
