/* fill.c -- the material points of bodies filled on a grid: the rule of
 * method mpm's particles and of method gmm's grid-filled bodies. */
#include "mpgm_discretisation.h"

int mpgm_bodies_fill(const mpgm_scene *s, int cell, int ncell,
                     void (*xy)(const void *grid, int c, double *xn), const void *grid,
                     int *owner, double *x, int *count) {
  double gxi[18], gw[9];
  *count = 0;
  if (mpgm_fe_gauss(cell, s->ppc, gxi, gw)) return MPGM_ERR_INPUT;
  const int nn = mpgm_fe_nnode(cell);
  double N[MPGM_FE_MAXNODE * 9];
  for (int q = 0; q < s->ppc; q++) mpgm_fe_ref(cell, gxi + 2 * q, N + nn * q, NULL);
  int n = 0;
  for (int c = 0; c < ncell; c++) {
    double xn[2 * MPGM_FE_MAXNODE];
    xy(grid, c, xn);
    for (int q = 0; q < s->ppc; q++) {
      double p[2] = {0, 0};
      for (int a = 0; a < nn; a++) {
        p[0] += N[nn * q + a] * xn[2 * a];
        p[1] += N[nn * q + a] * xn[2 * a + 1];
      }
      int b = 0;
      while (b < s->nbody && !mpgm_body_contains(&s->bodies[b], p)) b++;
      const size_t k = (size_t)c * s->ppc + q;
      if (owner) owner[k] = b < s->nbody ? b : -1;
      if (x) {
        x[2 * k] = p[0];
        x[2 * k + 1] = p[1];
      }
      n += b < s->nbody;
    }
  }
  *count = n;
  return 0;
}
