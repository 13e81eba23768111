/* cpdi.c -- convected particle domain interpolation (Sadeghirad, Brannon &
 * Burghardt 2011, "CPDI1"; as Tran et al. 2019 write it, eqs 21-24): the
 * "cpdi" kind.
 *
 * A particle carries a parallelogram domain, x_p + s1 r1 + s2 r2 with
 * |s1|, |s2| <= 1, whose half-axes follow the material, r_k = F_p r_k^0.
 * Its corners, numbered counter-clockwise,
 *
 *   x_1 = x_p - r1 - r2,  x_2 = x_p + r1 - r2,  x_3 = x_p + r1 + r2,
 *   x_4 = x_p - r1 + r2,
 *
 * carry the values of the grid's functions phi_I (the bilinear hats, or
 * with shape.grid_functions "quadratic_bspline" the quadratic B-splines),
 * and over the domain phi_I is replaced by the bilinear interpolant of
 * those four values. Its mean over the domain (volume V = 4 |r1 x r2|)
 * and the mean of its gradient are
 *
 *   N_Ip    = (1/4) sum_c phi_I(x_c),
 *   dN_Ip/dx = (1/V) [(phi_1 - phi_3)(r1y - r2y) + (phi_2 - phi_4)(r1y + r2y)],
 *   dN_Ip/dy = (1/V) [(phi_1 - phi_3)(r2x - r1x) - (phi_2 - phi_4)(r1x + r2x)],
 *
 * with phi_c = phi_I(x_c). The factor is 1/V with V the full domain (4
 * times the parallelogram of r1, r2): with it, sum_I dN_Ip x_I = identity,
 * the gradient of a linear field is exact (tests/unit/test_cpdi.c; the
 * derivation is in docs/theory.md, "CPDI"). Both sums use grid functions
 * that reproduce linear fields, at points the bilinear map reaches
 * linearly.
 *
 * The quadratic B-splines are C1: the error of the grid's velocity field is
 * then smooth, and its difference over a domain's corners is O(h^2) where
 * the hats' kinks make it O(h) (docs/theory.md section 21.6: on 004's
 * vortex at A = 1 rad this is what keeps second order).
 *
 * Nodes: the caller gives the grid nodes whose functions may reach a corner
 * (MPM takes every node within h, 2 h for the splines, of the domain's
 * bounding box). A corner beyond the grid's box (par->grid_lo, grid_hi; a
 * point on a support at the grid's edge has its domain's edge there, and
 * the smallest shear or rounding takes a corner past it) is pulled back
 * onto the box's edge, counted in info->clamped: the corner values still
 * sum to 1 (momentum is kept), linear reproduction is lost at that point
 * only. Each corner's functions must sum to 1; a corner where the grid has
 * no node (no box given) fails with MPGM_SHAPE_OFF_GRID, a domain with
 * r1 x r2 <= 0 (turned inside out) with MPGM_SHAPE_INVERTED. A query
 * without a domain (probes and surface tracers, which have none) gets the
 * grid functions and their gradients at x_p.
 *
 * In 3-D the domain is the parallelepiped x_p + s1 r1 + s2 r2 + s3 r3,
 * |s_k| <= 1, with 8 corners in mpgm_corner_sign's order; phi_I is
 * replaced by the trilinear interpolant of the corner values, whose means
 * are (V = 8 r1 . (r2 x r3), s_ck the signs of corner c)
 *
 *   N_Ip     = (1/8) sum_c phi_I(x_c),
 *   dN_Ip/dx = (1/V) sum_c phi_I(x_c) w_c,
 *   w_c      = s_c1 (r2 x r3) + s_c2 (r3 x r1) + s_c3 (r1 x r2)
 *
 * (the mean of d phi / d s_k over the cube is sum_c phi_c s_ck / 8, and
 * J^-T = [r2 x r3, r3 x r1, r1 x r2] / (r1 . (r2 x r3)) for J = [r1 r2
 * r3]; the 2-D formula above is the same construction with the 2-D
 * cofactors). The box, the splines and the failures are as in 2-D; a
 * domain with r1 . (r2 x r3) <= 0 is inverted. CPLS stays 2-D. */
#include "mpgm_shapefn_impl.h"

#include <math.h>

#if MPGM_DIM == 2
/* The bilinear hat of the node at offset (dx, dy) = x - x_I on a grid of
 * spacing h, and (grad) its gradient (the one-sided value at a kink,
 * consistently from the side of the lower node). */
static inline double hat(double dx, double dy, double h, double *gx, double *gy) {
  const double ax = fabs(dx), ay = fabs(dy);
  if (ax >= h || ay >= h) {
    if (gx) *gx = *gy = 0.0;
    return 0.0;
  }
  const double wx = 1.0 - ax / h, wy = 1.0 - ay / h;
  if (gx) {
    *gx = (dx >= 0.0 ? -1.0 : 1.0) / h * wy;
    *gy = (dy >= 0.0 ? -1.0 : 1.0) / h * wx;
  }
  return wx * wy;
}

#endif

/* The node-centred quadratic B-spline of a grid of spacing h at offset
 * d = x - x_I (support |d| < 1.5 h), and (g) its derivative. */
static inline double bspline2(double d, double h, double *g) {
  const double r = fabs(d) / h, sg = d >= 0.0 ? 1.0 : -1.0;
  if (r >= 1.5) {
    *g = 0.0;
    return 0.0;
  }
  if (r < 0.5) {
    *g = -2.0 * r * sg / h;
    return 0.75 - r * r;
  }
  *g = -(1.5 - r) * sg / h;
  return 0.5 * (1.5 - r) * (1.5 - r);
}

/* One direction of the quadratic functions at x of the node at xn on the
 * grid [lo, hi] (no edge when hi <= lo). Past an edge the node that would
 * sit a cell outside is a ghost whose value is extrapolated linearly,
 * v_ghost = 2 v_edge - v_next: its spline goes to the edge node twice and
 * to the next one negated. The functions then still sum to 1 and
 * reproduce linear fields up to the edge, and at the edge itself only the
 * edge node's is non-zero (1), so a support there fixes the value. */
static double bspline2_edge(double x, double xn, double h, double lo, double hi, double *g) {
  double w = bspline2(x - xn, h, g);
  if (!(hi > lo)) return w;
  const double tol = 1e-9 * h;
  double gg;
  for (int side = 0; side < 2; side++) {
    const double edge = side ? hi : lo, ghost = side ? hi + h : lo - h;
    const double next = side ? hi - h : lo + h;
    const double c = fabs(xn - edge) <= tol ? 2.0 : fabs(xn - next) <= tol ? -1.0 : 0.0;
    if (c == 0.0) continue;
    w += c * bspline2(x - ghost, h, &gg);
    *g += c * gg;
  }
  return w;
}

#if MPGM_DIM == 2
/* The grid function of node xn at x (par->grid_order: 1 the hats, 2 the
 * quadratic B-splines with the ghost rule at the grid box's edges), and
 * (gx, gy; optional) its gradient. */
static double gridfn(const mpgm_shape_params *par, const double *x, const double *xn,
                     double *gx, double *gy) {
  if (par->grid_order != 2) return hat(x[0] - xn[0], x[1] - xn[1], par->h, gx, gy);
  double g0, g1;
  const double w0 = bspline2_edge(x[0], xn[0], par->h, par->grid_lo[0], par->grid_hi[0], &g0);
  const double w1 = bspline2_edge(x[1], xn[1], par->h, par->grid_lo[1], par->grid_hi[1], &g1);
  if (gx) {
    *gx = g0 * w1;
    *gy = w0 * g1;
  }
  return w0 * w1;
}

#endif

static int cpdi_radius(const mpgm_shape_params *par, double *R) {
  *R = 0.0;
  if (!par || !(par->h > 0.0)) return MPGM_ERR_INPUT;
  /* a point's own functions; a domain reaches farther */
  *R = (par->grid_order == 2 ? 1.5 : 1.0) * sqrt((double)MPGM_DIM) * par->h;
  return 0;
}

/* The end of an evaluation over a domain's nc corners (a point without
 * domain: one): no node in the support, or a corner whose functions do not
 * sum to 1 (it lies where the grid has no node), fails; else the info. */
static int domain_done(const mpgm_shape_query *q, double *N, double *dN, int nsup,
                       const double *sum, int nc, int clamped) {
  if (nsup == 0) return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_TOO_FEW);
  for (int c = 0; c < nc; c++)
    if (!(fabs(sum[c] - 1.0) <= 1e-9)) return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_OFF_GRID);
  mpgm_shape_ok(q, 0, nsup, 0.0, 0.0);
  if (q->info) q->info->clamped = clamped;
  return 0;
}

#if MPGM_DIM == 2
/* Without a domain: the grid functions at x_p. */
static int point_eval(const mpgm_shape_query *q, double *N, double *dN) {
  double sum = 0.0;
  int nsup = 0;
  for (int a = 0; a < q->n; a++) {
    N[a] = gridfn(q->par, q->xp, q->xn + 2 * a, dN + 2 * a, dN + 2 * a + 1);
    sum += N[a];
    nsup += N[a] > 0.0;
  }
  return domain_done(q, N, dN, nsup, &sum, 1, 0); /* the point as a domain of one corner */
}

static int cpdi_eval(const mpgm_shape_query *q, double *N, double *dN) {
  MPGM_CALL(mpgm_shape_check_cloud(q, N, dN));
  if (!q->par || !(q->par->h > 0.0))
    return mpgm_shape_fail(q, N, dN, MPGM_ERR_INPUT, MPGM_SHAPE_BAD_INPUT);
  if (!q->domain) return point_eval(q, N, dN);
  const double *r = q->domain; /* r1 = (r[0], r[1]), r2 = (r[2], r[3]) */
  const double cross = r[0] * r[3] - r[1] * r[2];
  if (!(cross > 0.0)) return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_INVERTED);
  const double V = 4.0 * cross;
  const double *lo = q->par->grid_lo, *hi = q->par->grid_hi;
  const int box = hi[0] > lo[0] && hi[1] > lo[1];
  double xc[4][2];
  mpgm_domain_corners(r, xc);
  int clamped = 0;
  for (int c = 0; c < 4; c++) {
    xc[c][0] += q->xp[0];
    xc[c][1] += q->xp[1];
    for (int i = 0; i < 2 && box; i++) {
      const double v = fmin(fmax(xc[c][i], lo[i]), hi[i]);
      clamped += v != xc[c][i];
      xc[c][i] = v;
    }
  }
  double sum[4] = {0.0, 0.0, 0.0, 0.0};
  int nsup = 0;
  for (int a = 0; a < q->n; a++) {
    double phi[4];
    for (int c = 0; c < 4; c++) {
      phi[c] = gridfn(q->par, xc[c], q->xn + 2 * a, NULL, NULL);
      sum[c] += phi[c];
    }
    const double d13 = phi[0] - phi[2], d24 = phi[1] - phi[3];
    N[a] = 0.25 * (phi[0] + phi[1] + phi[2] + phi[3]);
    dN[2 * a] = (d13 * (r[1] - r[3]) + d24 * (r[1] + r[3])) / V;
    dN[2 * a + 1] = (d13 * (r[2] - r[0]) - d24 * (r[0] + r[2])) / V;
    nsup += N[a] > 0.0;
  }
  return domain_done(q, N, dN, nsup, sum, 4, clamped);
}

#else /* MPGM_DIM == 3 */

/* The trilinear hat of the node at offset d = x - x_I on a grid of spacing
 * h and (g, optional) its gradient, one-sided at a kink as in 2-D. */
static double hat3(const double d[3], double h, double *g) {
  double w[3], s[3];
  for (int k = 0; k < 3; k++) {
    const double a = fabs(d[k]);
    if (a >= h) {
      if (g) g[0] = g[1] = g[2] = 0.0;
      return 0.0;
    }
    w[k] = 1.0 - a / h;
    s[k] = (d[k] >= 0.0 ? -1.0 : 1.0) / h;
  }
  if (g) {
    g[0] = s[0] * w[1] * w[2];
    g[1] = w[0] * s[1] * w[2];
    g[2] = w[0] * w[1] * s[2];
  }
  return w[0] * w[1] * w[2];
}

/* The grid function of node xn at x (the hats, or the quadratic
 * B-splines with the ghost rule on each axis) and (g, optional) its
 * gradient. */
static double gridfn3(const mpgm_shape_params *par, const double *x, const double *xn,
                      double *g) {
  if (par->grid_order != 2) {
    const double d[3] = {x[0] - xn[0], x[1] - xn[1], x[2] - xn[2]};
    return hat3(d, par->h, g);
  }
  double w[3], dw[3];
  for (int k = 0; k < 3; k++)
    w[k] = bspline2_edge(x[k], xn[k], par->h, par->grid_lo[k], par->grid_hi[k], dw + k);
  if (g) {
    g[0] = dw[0] * w[1] * w[2];
    g[1] = w[0] * dw[1] * w[2];
    g[2] = w[0] * w[1] * dw[2];
  }
  return w[0] * w[1] * w[2];
}

/* Without a domain: the grid functions at x_p. */
static int point_eval(const mpgm_shape_query *q, double *N, double *dN) {
  double sum = 0.0;
  int nsup = 0;
  for (int a = 0; a < q->n; a++) {
    N[a] = gridfn3(q->par, q->xp, q->xn + 3 * a, dN + 3 * a);
    sum += N[a];
    nsup += N[a] > 0.0;
  }
  return domain_done(q, N, dN, nsup, &sum, 1, 0); /* the point as a domain of one corner */
}

static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

/* The parallelepiped xp + sum_k s_k r_k: its 8 corners x_c, pulled back
 * onto the grid's box when one is given (returns how many coordinates
 * were), and the corners' gradient weights w_c = s1 (r2 x r3) + s2 (r3 x
 * r1) + s3 (r1 x r2). *V = 8 r1 . (r2 x r3). */
static int corners3(const mpgm_shape_query *q, double xc[8][3], double wc[8][3], double *V) {
  const double *r = q->domain, *lo = q->par->grid_lo, *hi = q->par->grid_hi;
  double c23[3], c31[3], c12[3];
  cross3(r + 3, r + 6, c23);
  cross3(r + 6, r, c31);
  cross3(r, r + 3, c12);
  *V = 8.0 * (r[0] * c23[0] + r[1] * c23[1] + r[2] * c23[2]);
  const int box = hi[0] > lo[0] && hi[1] > lo[1] && hi[2] > lo[2];
  int clamped = 0;
  mpgm_domain_corners(r, xc);
  for (int c = 0; c < 8; c++) {
    const double s1 = mpgm_corner_sign(c, 0), s2 = mpgm_corner_sign(c, 1);
    const double s3 = mpgm_corner_sign(c, 2);
    for (int i = 0; i < 3; i++) {
      wc[c][i] = s1 * c23[i] + s2 * c31[i] + s3 * c12[i];
      xc[c][i] += q->xp[i];
      if (!box) continue;
      const double v = fmin(fmax(xc[c][i], lo[i]), hi[i]);
      clamped += v != xc[c][i];
      xc[c][i] = v;
    }
  }
  return clamped;
}

static int cpdi_eval(const mpgm_shape_query *q, double *N, double *dN) {
  MPGM_CALL(mpgm_shape_check_cloud(q, N, dN));
  if (!q->par || !(q->par->h > 0.0))
    return mpgm_shape_fail(q, N, dN, MPGM_ERR_INPUT, MPGM_SHAPE_BAD_INPUT);
  if (!q->domain) return point_eval(q, N, dN);
  double xc[8][3], wc[8][3], V;
  const int clamped = corners3(q, xc, wc, &V);
  if (!(V > 0.0)) return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_INVERTED);
  double sum[8] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  int nsup = 0;
  for (int a = 0; a < q->n; a++) {
    double n = 0.0, g[3] = {0.0, 0.0, 0.0};
    for (int c = 0; c < 8; c++) {
      const double phi = gridfn3(q->par, xc[c], q->xn + 3 * a, NULL);
      sum[c] += phi;
      n += phi;
      for (int i = 0; i < 3; i++) g[i] += phi * wc[c][i];
    }
    N[a] = 0.125 * n;
    for (int i = 0; i < 3; i++) dN[3 * a + i] = g[i] / V;
    nsup += N[a] > 0.0;
  }
  return domain_done(q, N, dN, nsup, sum, 8, clamped);
}
#endif

/* shape.grid_functions of the kinds with particle domains: the grid
 * functions a domain's corners carry, into grid_order 1 or 2 */
static const char *const grid_fn_names[] = {"bilinear", "quadratic_bspline", NULL};
#define GRID_FUNCTIONS_KEY                                                                        \
  {.name = "grid_functions", .type = MPGM_KEY_CHOICE,                                             \
   .offset = offsetof(mpgm_shape_params, grid_order), .def = 1, .lo = 1, .hi = 2,                \
   .choices = grid_fn_names, .unit = "-",                                                         \
   .doc = "the grid functions of the domains' corners: the hats or the quadratic B-splines"}

static const mpgm_key_spec cpdi_keys[] = {GRID_FUNCTIONS_KEY};

#if MPGM_DIM == 2
/* CPLS's keys: the grid functions, and the basis of its velocity
 * reconstruction (second order by default: kept at large deformation) */
static const mpgm_key_spec cpls_keys[] = {
    GRID_FUNCTIONS_KEY,
    {.name = "order", .type = MPGM_KEY_INT, .offset = offsetof(mpgm_shape_params, order),
     .def = 2, .lo = 1, .hi = 2, .unit = "-",
     .doc = "basis of the velocity reconstruction: 1 linear, 2 quadratic"},
};

/* CPLS (Tran et al. 2019): CPDI's N and grad N, the nodal velocities by
 * least squares from the points' centres and corners (mpm/cpls.c). */
const mpgm_shapefn_type mpgm_shapefn_cpls = {
    .name = "cpls",
    .doc = "convected particle least squares (Tran et al. 2019): CPDI's functions, nodal "
           "velocities by improved moving least squares from the particles' centres and domain "
           "corners; explicit usl on method mpm",
    .needs_cell = 0,
    .grid_only = 1,
    .domain = 1,
    .velocity_ls = 1,
    .eval = cpdi_eval,
    .support_radius = cpdi_radius,
    .keys = cpls_keys,
    .nkeys = sizeof cpls_keys / sizeof *cpls_keys,
};
#endif

const mpgm_shapefn_type mpgm_shapefn_cpdi = {
    .name = "cpdi",
#if MPGM_DIM == 2
    .doc = "convected particle domain interpolation (CPDI1, Sadeghirad et al. 2011): bilinear "
           "hats (or quadratic B-splines, shape.grid_functions) averaged over the particle's "
           "parallelogram r_k = F r_k^0 from its corners; regular grids only (method mpm)",
#else
    .doc = "convected particle domain interpolation (CPDI1, Sadeghirad et al. 2011): trilinear "
           "hats (or quadratic B-splines, shape.grid_functions) averaged over the particle's "
           "parallelepiped r_k = F r_k^0 from its 8 corners; regular grids only (method mpm)",
#endif
    .needs_cell = 0,
    .grid_only = 1,
    .domain = 1,
    .eval = cpdi_eval,
    .support_radius = cpdi_radius,
    .keys = cpdi_keys,
    .nkeys = sizeof cpdi_keys / sizeof *cpdi_keys,
};
