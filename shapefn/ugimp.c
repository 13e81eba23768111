/* ugimp.c -- uniform GIMP shape functions (Bardenhagen & Kober 2004, the
 * "uniform" variant: the particle's domain keeps its initial size; as
 * Molinos et al. 2021 and Tran et al. 2019 compare them): the "ugimp" kind.
 *
 * On a regular grid of spacing h, the weight of node I at a particle of
 * half-width lp (a square of side 2 lp) is the mean of the node's bilinear
 * hat function over that square, a tensor product S_I = S(dx) S(dy) of the
 * 1-D weight in the offset d = x_p - x_I:
 *
 *   (h + lp + d)^2 / (4 h lp)      -h - lp < d <= -h + lp
 *   1 + d / h                      -h + lp < d <= -lp
 *   1 - (d^2 + lp^2) / (2 h lp)    -lp < d <= lp
 *   1 - d / h                       lp < d <= h - lp
 *   (h + lp - d)^2 / (4 h lp)       h - lp < d <= h + lp
 *   0                               |d| >= h + lp
 *
 * (the integral of the hat over [d - lp, d + lp] divided by 2 lp, which is
 * C1 in d: no jump of the gradient when a particle crosses a cell edge,
 * unlike the hat itself). Its derivative dS/dx_p, piece by piece:
 * (h + lp + d) / (2 h lp), 1/h, -d / (h lp), -1/h, -(h + lp - d) / (2 h lp).
 * The weights sum to 1 and reproduce linear fields wherever all the nodes
 * within h + lp of the particle exist (a grid covering the body does).
 *
 * In 3-D the particle is a cube of half-width lp and the weight the
 * product of three such factors, S_I = S(dx) S(dy) S(dz), its gradient
 * component k the factor k's derivative times the other two (the mean of
 * the trilinear hat over the cube, for the same reason: the hat and the
 * cube are both products over the axes).
 *
 * The kind takes its cloud like the meshfree kinds: the caller searches the
 * nodes within sqrt(DIM) (h + lp) (the corner of the square or cube
 * support); nodes outside it get N = 0. h = par->h, lp = par->half_width (MPM sets
 * h / (2 sqrt(ppc)), the half side of a particle's share of its cell).
 * Weights that do not sum to 1 (a node within h + lp missing: the grid
 * ends there) fail with MPGM_SHAPE_OFF_GRID rather than give forces that do
 * not balance (a one-cell-high bar with points at the Gauss points loses
 * its momentum in a few steps that way; at the sub-cell centres, the
 * particles' squares stay inside their cell and need no node beyond).
 */
#include "mpgm_shapefn_impl.h"

#include <math.h>


/* The 1-D weight at offset d and its derivative in d. */
static inline double weight(double d, double h, double lp, double *dS) {
  const double a = fabs(d), s = d < 0.0 ? -1.0 : 1.0;
  if (a >= h + lp) {
    *dS = 0.0;
    return 0.0;
  }
  if (a > h - lp) {
    const double e = h + lp - a;
    *dS = -s * e / (2.0 * h * lp);
    return e * e / (4.0 * h * lp);
  }
  if (a > lp) {
    *dS = -s / h;
    return 1.0 - a / h;
  }
  *dS = -d / (h * lp);
  return 1.0 - (d * d + lp * lp) / (2.0 * h * lp);
}

static int ugimp_radius(const mpgm_shape_params *par, double *R) {
  *R = 0.0;
  if (!par || !(par->h > 0.0) || !(par->half_width > 0.0) || !(par->half_width <= 0.5 * par->h))
    return MPGM_ERR_INPUT;
  *R = sqrt((double)MPGM_DIM) * (par->h + par->half_width);
  return 0;
}

static int ugimp_eval(const mpgm_shape_query *q, double *N, double *dN) {
  MPGM_CALL(mpgm_shape_check_cloud(q, N, dN));
  double R;
  if (ugimp_radius(q->par, &R)) return mpgm_shape_fail(q, N, dN, MPGM_ERR_INPUT, MPGM_SHAPE_BAD_INPUT);
  const double h = q->par->h, lp = q->par->half_width;
  int nsup = 0;
  double sum = 0.0;
  for (int a = 0; a < q->n; a++) {
#if MPGM_DIM == 2
    double gx, gy;
    const double sx = weight(q->xp[0] - q->xn[2 * a], h, lp, &gx);
    const double sy = weight(q->xp[1] - q->xn[2 * a + 1], h, lp, &gy);
    N[a] = sx * sy;
    dN[2 * a] = gx * sy;
    dN[2 * a + 1] = sx * gy;
#else
    double g[3], w[3];
    for (int d = 0; d < 3; d++) w[d] = weight(q->xp[d] - q->xn[3 * a + d], h, lp, g + d);
    N[a] = w[0] * w[1] * w[2];
    dN[3 * a] = g[0] * w[1] * w[2];
    dN[3 * a + 1] = w[0] * g[1] * w[2];
    dN[3 * a + 2] = w[0] * w[1] * g[2];
#endif
    nsup += N[a] > 0.0;
    sum += N[a];
  }
  if (nsup == 0) return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_TOO_FEW);
  /* a node the grid lacks leaves the weights short of 1 and their
   * gradients short of summing to 0: forces that do not balance */
  if (!(fabs(sum - 1.0) <= 1e-9)) return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_OFF_GRID);
  mpgm_shape_ok(q, 0, nsup, 0.0, 0.0);
  return 0;
}

const mpgm_shapefn_type mpgm_shapefn_ugimp = {
    .name = "ugimp",
#if MPGM_DIM == 2
    .doc = "uniform GIMP (Bardenhagen & Kober 2004): bilinear hats averaged over the particle's "
           "square of half-width h / (2 sqrt(ppc)); regular grids only (method mpm)",
#else
    .doc = "uniform GIMP (Bardenhagen & Kober 2004): trilinear hats averaged over the "
           "particle's cube of half-width lp; regular grids only (method mpm)",
#endif
    .needs_cell = 0,
    .grid_only = 1,
    .eval = ugimp_eval,
    .support_radius = ugimp_radius,
};
