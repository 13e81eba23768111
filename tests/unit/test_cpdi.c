/* test_cpdi.c -- the "cpdi" shape-function kind (shapefn/cpdi.c):
 *
 *   - partition of unity and linear reproduction under a general F (the
 *     domain stretched, sheared and turned): sum N = 1, sum N x_I = x_p,
 *     sum grad N = 0 and sum grad N (x) x_I = identity, so the gradient of
 *     a linear field is exact: the factor 1/V of the gradient (V = 4 |r1 x
 *     r2|) is the right one, and a factor of 1/(2V) or 2/V (printed forms
 *     of the formula differ) would give a gradient off by that factor;
 *   - N and grad N equal the domain averages of the bilinear interpolant
 *     of the corner values and of its gradient, by Gauss quadrature over
 *     the parallelogram (an independent construction of the closed form);
 *   - inside one cell, where the hats are bilinear, CPDI's average is
 *     exact: an axis-aligned square gives uGIMP's weights;
 *   - without a domain (tracers) the kind gives the hats at x_p;
 *   - a corner off the grid fails with MPGM_SHAPE_OFF_GRID, a domain
 *     turned inside out with MPGM_SHAPE_INVERTED (N = dN = 0, no NaN);
 *     with the grid's box given, a corner beyond it is pulled back onto
 *     its edge and counted, and N, grad N still sum to 1 and 0;
 *   - the quadratic B-splines (shape.grid_functions "quadratic_bspline"):
 *     the same reproduction under a general F, also where domains reach
 *     the grid box's edges (the ghost rule), only the edge nodes non-zero
 *     on the edge, and a quadratic field's gradient exact at the particle
 *     (the spline through its nodal values is off by a constant, h^2 / 8
 *     times its second derivative in each direction), which the hats miss
 *     by O(h): why the splines keep the rate on the vortex.
 *
 * A 3-D build checks the parallelepiped the same way (its own node clouds:
 * the nodes within reach of the domain's bounding box, as MPM gives them):
 * reproduction under three F (with stretch, shear and turns), N and grad
 * N against quadrature of the trilinear interpolant with V from the
 * determinant, the cube inside a cell against uGIMP, tracers, OFF_GRID,
 * inverted and flat domains, the box clamp at a face and at a corner, and
 * the quadratic B-splines inside and near the box's faces, edges and
 * corner.
 */
#include "mpgm_shapefn.h"
#include "mpgm_test.h"

#include <math.h>
#include <stdio.h>

static const double H = 0.25;
enum { R = 4, NG = (2 * R + 1) * (2 * R + 1) }; /* nodes (i h, j h), |i|, |j| <= R */


static double hat1(double d) { return fmax(0.0, 1.0 - fabs(d) / H); }

#if MPGM_DIM == 2
static void grid(double *xn) {
  for (int j = -R, n = 0; j <= R; j++)
    for (int i = -R; i <= R; i++, n++) {
      xn[2 * n] = i * H;
      xn[2 * n + 1] = j * H;
    }
}

static int eval(const char *kind, const double xp[2], const double *dom, double lp, double *N,
                double *dN, int *reason) {
  static double xn[2 * NG];
  grid(xn);
  const mpgm_shape_params par = {.h = H, .half_width = lp};
  mpgm_shape_info info = {0};
  const mpgm_shape_query q = {.n = NG, .xn = xn, .xp = {xp[0], xp[1]}, .cell = -1, .par = &par,
                              .info = &info, .domain = dom};
  const int err = mpgm_shapefn_type_find(kind)->eval(&q, N, dN);
  if (reason) *reason = info.reason;
  return err;
}

/* r = F r0 for r0 = (a, 0), (0, b) */
static void domain(const double F[4], double a, double b, double r[4]) {
  r[0] = F[0] * a;
  r[1] = F[2] * a;
  r[2] = F[1] * b;
  r[3] = F[3] * b;
}


/* the hat of node a at x */
static double hatn(int a, const double x[2]) {
  const double xi = (a % (2 * R + 1) - R) * H, yi = (a / (2 * R + 1) - R) * H;
  return hat1(x[0] - xi) * hat1(x[1] - yi);
}

/* Sums over the nodes of cpdi's functions with parameters par at (xp,
 * domain r): |sum N - 1|, |sum N x_I - x_p|, |sum grad N| H,
 * |sum x_I (x) grad N - 1| and, for f = x^2 + 3 x y - 2 y^2, |sum f_I grad
 * N - grad f(x_p)| H. Returns the evaluation's error. */
static int sums(const mpgm_shape_params *par, const double xp[2], const double *r, double err[5]) {
  static double xn[2 * NG];
  grid(xn);
  double N[NG], dN[2 * NG];
  const mpgm_shape_query q = {.n = NG, .xn = xn, .xp = {xp[0], xp[1]}, .cell = -1, .par = par,
                              .domain = r};
  if (mpgm_shapefn_type_find("cpdi")->eval(&q, N, dN)) return 1;
  double s = 0, x[2] = {0, 0}, g[2] = {0, 0}, G[4] = {0, 0, 0, 0}, gf[2] = {0, 0};
  for (int a = 0; a < NG; a++) {
    const double X = xn[2 * a], Y = xn[2 * a + 1], f = X * X + 3 * X * Y - 2 * Y * Y;
    s += N[a];
    for (int i = 0; i < 2; i++) {
      x[i] += N[a] * xn[2 * a + i];
      g[i] += dN[2 * a + i];
      gf[i] += f * dN[2 * a + i];
      for (int j = 0; j < 2; j++) G[2 * i + j] += xn[2 * a + i] * dN[2 * a + j];
    }
  }
  err[0] = fabs(s - 1.0);
  err[1] = fmax(fabs(x[0] - xp[0]), fabs(x[1] - xp[1]));
  err[2] = fmax(fabs(g[0]), fabs(g[1])) * H;
  err[3] = fmax(fmax(fabs(G[0] - 1), fabs(G[3] - 1)), fmax(fabs(G[1]), fabs(G[2])));
  err[4] = fmax(fabs(gf[0] - (2 * xp[0] + 3 * xp[1])), fabs(gf[1] - (3 * xp[0] - 4 * xp[1]))) * H;
  return 0;
}

/* sums() on the grid's box [-R H, R H]^2 (order: 1 hats, 2 splines) */
static int spline_sums(int order, const double xp[2], const double *r, double err[5]) {
  const mpgm_shape_params par = {.h = H, .grid_order = order, .grid_lo = {-R * H, -R * H},
                                 .grid_hi = {R * H, R * H}};
  return sums(&par, xp, r, err);
}

static void check_reproduction(void) {
  const double Fs[3][4] = {{1.3, 0.4, -0.2, 0.8}, {0.6, -0.5, 0.7, 1.1}, {1.0, 0.0, 0.0, 1.0}};
  const double xps[3][2] = {{0.013, -0.071}, {0.2, 0.25}, {-0.31, 0.17}};
  const mpgm_shape_params par = {.h = H};
  double worst[4] = {0, 0, 0, 0};
  for (int f = 0; f < 3; f++)
    for (int k = 0; k < 3; k++) {
      double r[4], e[5];
      domain(Fs[f], 0.11, 0.07, r);
      if (sums(&par, xps[k], r, e)) {
        mpgm_test(0, "cpdi: F %d, point %d evaluates", f, k);
        continue;
      }
      for (int i = 0; i < 4; i++) worst[i] = fmax(worst[i], e[i]);
    }
  mpgm_test(worst[0] < 1e-13, "cpdi: sum N = 1 under stretch, shear and turn (%.1e)", worst[0]);
  mpgm_test(worst[1] < 1e-13, "cpdi: sum N x_I = x_p (%.1e m)", worst[1]);
  mpgm_test(worst[2] < 1e-13, "cpdi: sum grad N = 0 (%.1e, times h)", worst[2]);
  mpgm_test(worst[3] < 1e-13, "cpdi: sum x_I (x) grad N = identity: a linear field's gradient "
            "exact with the factor 1/V, V = 4 |r1 x r2| (%.1e)", worst[3]);
}

/* N and grad N against Gauss quadrature (5 x 5 per cell of a 16 x 16
 * subdivision of the parallelogram) of the corner values' bilinear
 * interpolant and of its gradient. */
static void check_quadrature(void) {
  const double F[4] = {1.2, 0.5, -0.3, 0.9}, xp[2] = {0.04, -0.09};
  double r[4], N[NG], dN[2 * NG];
  domain(F, 0.13, 0.09, r);
  if (eval("cpdi", xp, r, 0.0, N, dN, NULL)) {
    mpgm_test(0, "cpdi: quadrature point evaluates");
    return;
  }
  const double det = r[0] * r[3] - r[1] * r[2];
  const double gs[5] = {-0.906179845938664, -0.538469310105683, 0.0, 0.538469310105683,
                        0.906179845938664};
  const double gw[5] = {0.236926885056189, 0.478628670499366, 0.568888888888889,
                        0.478628670499366, 0.236926885056189};
  const double sc[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  double worstN = 0, worstG = 0;
  for (int a = 0; a < NG; a++) {
    double phi[4];
    for (int c = 0; c < 4; c++) {
      const double x[2] = {xp[0] + sc[c][0] * r[0] + sc[c][1] * r[2],
                           xp[1] + sc[c][0] * r[1] + sc[c][1] * r[3]};
      phi[c] = hatn(a, x);
    }
    double m = 0, g1 = 0, g2 = 0, w = 0; /* over s in [-1, 1]^2 */
    for (int i = 0; i < 5; i++)
      for (int j = 0; j < 5; j++) {
        const double s1 = gs[i], s2 = gs[j], wt = gw[i] * gw[j];
        double v = 0, d1 = 0, d2 = 0;
        for (int c = 0; c < 4; c++) {
          v += phi[c] * (1 + sc[c][0] * s1) * (1 + sc[c][1] * s2) / 4;
          d1 += phi[c] * sc[c][0] * (1 + sc[c][1] * s2) / 4;
          d2 += phi[c] * (1 + sc[c][0] * s1) * sc[c][1] / 4;
        }
        m += wt * v;
        g1 += wt * d1;
        g2 += wt * d2;
        w += wt;
      }
    m /= w;
    g1 /= w;
    g2 /= w;
    /* grad_x = J^-T grad_s, J = [r1 r2] (columns) */
    const double gx = (r[3] * g1 - r[1] * g2) / det, gy = (-r[2] * g1 + r[0] * g2) / det;
    worstN = fmax(worstN, fabs(m - N[a]));
    worstG = fmax(worstG, fmax(fabs(gx - dN[2 * a]), fabs(gy - dN[2 * a + 1])) * H);
  }
  mpgm_test(worstN < 1e-14, "cpdi: N = the domain mean of the corners' interpolant (%.1e)", worstN);
  mpgm_test(worstG < 1e-13, "cpdi: grad N = its mean gradient (%.1e, times h)", worstG);
}

/* an axis-aligned square inside one cell: uGIMP's weights */
static void check_ugimp(void) {
  const double lp = H / 4, xp[2] = {0.1, 0.12}, r[4] = {lp, 0, 0, lp};
  double N1[NG], d1[2 * NG], N2[NG], d2[2 * NG];
  const int e1 = eval("cpdi", xp, r, 0.0, N1, d1, NULL), e2 = eval("ugimp", xp, NULL, lp, N2, d2, NULL);
  double w = 0;
  for (int a = 0; a < NG; a++) w = fmax(w, fmax(fabs(N1[a] - N2[a]), H * fmax(fabs(d1[2 * a] - d2[2 * a]), fabs(d1[2 * a + 1] - d2[2 * a + 1]))));
  mpgm_test(!e1 && !e2 && w < 1e-14, "cpdi: a square inside a cell gives uGIMP's N and grad N (%.1e)", w);
}

static void check_point_and_failures(void) {
  const double xp[2] = {0.03, 0.11};
  double N[NG], dN[2 * NG];
  int reason = 0, err = eval("cpdi", xp, NULL, 0.0, N, dN, &reason);
  double w = 0;
  for (int a = 0; a < NG; a++) w = fmax(w, fabs(N[a] - hatn(a, xp)));
  mpgm_test(!err && w < 1e-15, "cpdi: no domain: the hats at x_p (%.1e)", w);
  /* a corner beyond the last node (R h = 1 m) */
  const double far[2] = {0.95, 0.0}, r[4] = {0.1, 0, 0, 0.1};
  err = eval("cpdi", far, r, 0.0, N, dN, &reason);
  int finite = 1;
  for (int a = 0; a < NG; a++) finite = finite && N[a] == 0.0 && dN[2 * a] == 0.0;
  mpgm_test(err == MPGM_ERR_SHAPE && reason == MPGM_SHAPE_OFF_GRID && finite,
            "cpdi: a corner off the grid fails with OFF_GRID (err %d, reason %d), N = 0", err, reason);
  const double inv[4] = {0.1, 0, 0, -0.1}, mid[2] = {0, 0};
  err = eval("cpdi", mid, inv, 0.0, N, dN, &reason);
  mpgm_test(err == MPGM_ERR_SHAPE && reason == MPGM_SHAPE_INVERTED,
            "cpdi: an inverted domain fails with INVERTED (err %d, reason %d)", err, reason);
  /* the grid's box: the corner at x = 1.05 is pulled back to 1 */
  static double xn[2 * NG];
  grid(xn);
  const mpgm_shape_params bp = {.h = H, .grid_lo = {-R * H, -R * H}, .grid_hi = {R * H, R * H}};
  mpgm_shape_info info = {0};
  const mpgm_shape_query qb = {.n = NG, .xn = xn, .xp = {far[0], far[1]}, .cell = -1, .par = &bp,
                               .info = &info, .domain = r};
  err = mpgm_shapefn_type_find("cpdi")->eval(&qb, N, dN);
  double sN = 0, sg = 0;
  for (int a = 0; a < NG; a++) {
    sN += N[a];
    sg += dN[2 * a] + dN[2 * a + 1];
  }
  mpgm_test(!err && info.clamped == 2 && fabs(sN - 1) < 1e-14 && fabs(sg) * H < 1e-13,
            "cpdi: with the grid's box, 2 corners pulled back (%d), sum N - 1 = %.1e, sum grad N = "
            "%.1e", info.clamped, sN - 1, sg);
  const mpgm_shape_query q = {.n = 1, .xn = mid, .xp = {0, 0}, .cell = -1, .par = NULL};
  mpgm_test(mpgm_shapefn_type_find("cpdi")->eval(&q, N, dN) == MPGM_ERR_INPUT,
            "cpdi: no length scale is MPGM_ERR_INPUT");
}

static void check_quadratic(void) {
  const double Fs[3][4] = {{1.3, 0.4, -0.2, 0.8}, {0.6, -0.5, 0.7, 1.1}, {1.0, 0.0, 0.0, 1.0}};
  /* inside (corners 2 h or more from the box), then near its edges: the
   * box is [-1, 1]^2, corners within 0.5 h and 1.5 h of an edge */
  const double in[3][2] = {{0.013, -0.071}, {0.2, 0.25}, {-0.31, 0.17}};
  const double edge[3][2] = {{-0.93, 0.11}, {0.87, 0.91}, {0.05, -0.81}};
  double worst_in[5] = {0, 0, 0, 0, 0}, worst_edge[4] = {0, 0, 0, 0}, hats = 0.0;
  int fails = 0;
  for (int f = 0; f < 3; f++)
    for (int k = 0; k < 3; k++) {
      double r[4], e[5];
      domain(Fs[f], 0.11, 0.07, r);
      fails += spline_sums(2, in[k], r, e);
      for (int i = 0; i < 5; i++) worst_in[i] = fmax(worst_in[i], e[i]);
      fails += spline_sums(1, in[k], r, e);
      hats = fmax(hats, e[4]);
      domain(Fs[f], 0.03, 0.02, r);
      fails += spline_sums(2, edge[k], r, e);
      for (int i = 0; i < 4; i++) worst_edge[i] = fmax(worst_edge[i], e[i]);
    }
  mpgm_test(fails == 0, "cpdi quadratic: every domain evaluates (%d failed)", fails);
  mpgm_test(fmax(worst_in[0], worst_in[2]) < 1e-13 && worst_in[1] < 1e-13 && worst_in[3] < 1e-13,
            "cpdi quadratic: sum N = 1, sum N x_I = x_p, sum grad N = 0, sum x_I (x) grad N = "
            "identity under stretch, shear and turn (%.1e %.1e %.1e %.1e)",
            worst_in[0], worst_in[1], worst_in[2], worst_in[3]);
  mpgm_test(fmax(worst_edge[0], worst_edge[2]) < 1e-13 && worst_edge[1] < 1e-13 &&
            worst_edge[3] < 1e-13, "cpdi quadratic: the same with corners within 1.5 h of the "
            "box's edges, by the ghost rule (%.1e %.1e %.1e %.1e)",
            worst_edge[0], worst_edge[1], worst_edge[2], worst_edge[3]);
  mpgm_test(worst_in[4] < 1e-12 && hats > 1e-3,
            "cpdi quadratic: a quadratic field's gradient exact at the particle (%.1e, times h); "
            "the hats miss it by %.1e", worst_in[4], hats);
  /* on the edge x = -1 (no domain: a tracer) only the edge column carries
   * a value, so a support there holds the field */
  static double xn[2 * NG];
  grid(xn);
  const mpgm_shape_params par = {.h = H, .grid_order = 2, .grid_lo = {-R * H, -R * H},
                                 .grid_hi = {R * H, R * H}};
  double N[NG], dN[2 * NG], off = 0.0, on = 0.0;
  const mpgm_shape_query q = {.n = NG, .xn = xn, .xp = {-R * H, 0.07}, .cell = -1, .par = &par};
  const int err = mpgm_shapefn_type_find("cpdi")->eval(&q, N, dN);
  for (int a = 0; a < NG; a++) {
    if (xn[2 * a] == -R * H) on += N[a];
    else off = fmax(off, fabs(N[a]));
  }
  mpgm_test(!err && off == 0.0 && fabs(on - 1.0) < 1e-14,
            "cpdi quadratic: on the box's edge only the edge nodes are non-zero (%.1e; sum %.15g)",
            off, on);
}

#else
/* ---- 3-D: the parallelepiped -------------------------------------------- */

enum { MAXN = MPGM_SHAPE_MAXNODE };

/* The nodes (i h, j h, k h) within reach of the bounding box of the
 * corners of (xp, r) (of xp when r is NULL), on the grid |i|, |j|, |k| <=
 * R when fin (else without end): what MPM gives the kind. Returns the
 * count (-1 when more than MAXN). */
static int cloud3(const double xp[3], const double *r, double reach, int fin, double *xn) {
  double lo[3], hi[3], off[8][3];
  for (int d = 0; d < 3; d++) lo[d] = hi[d] = xp[d];
  if (r) {
    mpgm_domain_corners(r, off);
    for (int c = 0; c < 8; c++)
      for (int d = 0; d < 3; d++) {
        lo[d] = fmin(lo[d], xp[d] + off[c][d]);
        hi[d] = fmax(hi[d], xp[d] + off[c][d]);
      }
  }
  int i0[3], i1[3], n = 0;
  for (int d = 0; d < 3; d++) {
    i0[d] = (int)floor((lo[d] - reach) / H);
    i1[d] = (int)ceil((hi[d] + reach) / H);
    if (fin) {
      i0[d] = i0[d] < -R ? -R : i0[d];
      i1[d] = i1[d] > R ? R : i1[d];
    }
  }
  for (int k = i0[2]; k <= i1[2]; k++)
    for (int j = i0[1]; j <= i1[1]; j++)
      for (int i = i0[0]; i <= i1[0]; i++) {
        const double x[3] = {i * H, j * H, k * H};
        int in = 1;
        for (int d = 0; d < 3; d++) in &= x[d] > lo[d] - reach && x[d] < hi[d] + reach;
        if (!in) continue;
        if (n == MAXN) return -1;
        for (int d = 0; d < 3; d++) xn[3 * n + d] = x[d];
        n++;
      }
  return n;
}

/* r_k = F (len_k e_k): column k of F scaled */
static void domain3(const double F[9], const double len[3], double r[9]) {
  for (int k = 0; k < 3; k++)
    for (int d = 0; d < 3; d++) r[3 * k + d] = F[3 * d + k] * len[k];
}

/* det of the 3 x 3 [r1 r2 r3] by the rule of Sarrus */
static double det3(const double *r) {
  return r[0] * r[4] * r[8] + r[3] * r[7] * r[2] + r[6] * r[1] * r[5] - r[6] * r[4] * r[2] -
         r[3] * r[1] * r[8] - r[0] * r[7] * r[5];
}

static double hat3n(const double *xn, const double x[3]) {
  return hat1(x[0] - xn[0]) * hat1(x[1] - xn[1]) * hat1(x[2] - xn[2]);
}

typedef struct {
  int err, n, reason, clamped;
  double xn[3 * MAXN], N[MAXN], dN[3 * MAXN];
} res3;

/* Evaluate cpdi (or ugimp with half-width lp) on the cloud of (xp, r). */
static void run3(const char *kind, const mpgm_shape_params *par, const double xp[3],
                 const double *r, int fin, res3 *o) {
  const double reach = (par->grid_order == 2 ? 1.5 : 1.0) * H + par->half_width + 0.01 * H;
  o->n = cloud3(xp, r, reach, fin, o->xn);
  mpgm_shape_info info = {0};
  const mpgm_shape_query q = {.n = o->n, .xn = o->xn, .xp = {xp[0], xp[1], xp[2]}, .cell = -1,
                              .par = par, .info = &info, .domain = r};
  o->err = o->n < 0 ? -1 : mpgm_shapefn_type_find(kind)->eval(&q, o->N, o->dN);
  o->reason = info.reason;
  o->clamped = info.clamped;
}

/* The sums of sums() in 3-D, f = x^2 + 3 x y - 2 y^2 + z^2 - x z + 2 y z. */
static int sums3(const mpgm_shape_params *par, const double xp[3], const double *r, int fin,
                 double err[5]) {
  static res3 o;
  for (int i = 0; i < 5; i++) err[i] = 0.0;
  run3("cpdi", par, xp, r, fin, &o);
  if (o.err) return 1;
  double s = 0, x[3] = {0}, g[3] = {0}, G[9] = {0}, gf[3] = {0};
  for (int a = 0; a < o.n; a++) {
    const double *p = o.xn + 3 * a;
    const double f = p[0] * p[0] + 3 * p[0] * p[1] - 2 * p[1] * p[1] + p[2] * p[2] - p[0] * p[2] +
                     2 * p[1] * p[2];
    s += o.N[a];
    for (int i = 0; i < 3; i++) {
      x[i] += o.N[a] * p[i];
      g[i] += o.dN[3 * a + i];
      gf[i] += f * o.dN[3 * a + i];
      for (int j = 0; j < 3; j++) G[3 * i + j] += p[i] * o.dN[3 * a + j];
    }
  }
  const double gx[3] = {2 * xp[0] + 3 * xp[1] - xp[2], 3 * xp[0] - 4 * xp[1] + 2 * xp[2],
                        2 * xp[2] - xp[0] + 2 * xp[1]};
  err[0] = fabs(s - 1.0);
  for (int i = 0; i < 3; i++) {
    err[1] = fmax(err[1], fabs(x[i] - xp[i]));
    err[2] = fmax(err[2], fabs(g[i]) * H);
    err[4] = fmax(err[4], fabs(gf[i] - gx[i]) * H);
    for (int j = 0; j < 3; j++) err[3] = fmax(err[3], fabs(G[3 * i + j] - (i == j)));
  }
  return 0;
}

/* stretched, sheared and turned; turned about a skew axis; identity */
static const double F3[3][9] = {{1.3, 0.4, -0.2, -0.1, 0.8, 0.3, 0.25, -0.15, 1.1},
                                {0.36, -0.48, 0.8, 0.8, 0.6, 0.0, -0.48, 0.64, 0.6},
                                {1, 0, 0, 0, 1, 0, 0, 0, 1}};
static const double XP3[3][3] = {{0.013, -0.071, 0.044}, {0.2, 0.25, -0.125}, {-0.31, 0.17, 0.26}};
static const double LEN3[3] = {0.06, 0.05, 0.04};

static void check_reproduction3(void) {
  const mpgm_shape_params par = {.h = H};
  double worst[4] = {0, 0, 0, 0};
  int fails = 0;
  for (int f = 0; f < 3; f++) {
    mpgm_test(det3(F3[f]) > 0.2, "cpdi 3-D: F %d has det %.3f > 0", f, det3(F3[f]));
    for (int k = 0; k < 3; k++) {
      double r[9], e[5];
      domain3(F3[f], LEN3, r);
      fails += sums3(&par, XP3[k], r, 0, e);
      for (int i = 0; i < 4; i++) worst[i] = fmax(worst[i], e[i]);
    }
  }
  mpgm_test(fails == 0, "cpdi 3-D: every domain evaluates (%d failed)", fails);
  mpgm_test(worst[0] < 1e-13 && worst[1] < 1e-13 && worst[2] < 1e-13,
            "cpdi 3-D: sum N = 1, sum N x_I = x_p, sum grad N = 0 under stretch, shear and turn "
            "(%.1e %.1e %.1e)", worst[0], worst[1], worst[2]);
  mpgm_test(worst[3] < 1e-13, "cpdi 3-D: sum x_I (x) grad N = identity: the factor 1/V, V = 8 "
            "r1 . (r2 x r3) (%.1e)", worst[3]);
}

/* N and grad N against 3 x 3 x 3 Gauss quadrature over s in [-1, 1]^3 of
 * the trilinear interpolant of the corner values and of its gradient,
 * grad_x = J^-T grad_s (J = [r1 r2 r3]) solved by Cramer's rule with the
 * Sarrus determinant. */
static void check_quadrature3(void) {
  const double xp[3] = {0.04, -0.09, 0.07};
  double r[9];
  domain3(F3[0], LEN3, r);
  static res3 o;
  const mpgm_shape_params par = {.h = H};
  run3("cpdi", &par, xp, r, 0, &o);
  if (o.err) {
    mpgm_test(0, "cpdi 3-D: quadrature point evaluates");
    return;
  }
  const double det = det3(r), g = sqrt(0.6), gs[3] = {-g, 0.0, g};
  const double gw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  double worstN = 0, worstG = 0;
  for (int a = 0; a < o.n; a++) {
    double phi[8], sc[8][3];
    for (int c = 0; c < 8; c++) {
      double x[3];
      for (int k = 0; k < 3; k++) sc[c][k] = mpgm_corner_sign(c, k);
      for (int d = 0; d < 3; d++) x[d] = xp[d] + sc[c][0] * r[d] + sc[c][1] * r[3 + d] + sc[c][2] * r[6 + d];
      phi[c] = hat3n(o.xn + 3 * a, x);
    }
    double m = 0, gsum[3] = {0, 0, 0};
    for (int i = 0; i < 27; i++) {
      const double s[3] = {gs[i % 3], gs[i / 3 % 3], gs[i / 9]};
      const double wt = gw[i % 3] * gw[i / 3 % 3] * gw[i / 9] / 8.0;
      for (int c = 0; c < 8; c++) {
        double f[3], d[3];
        for (int k = 0; k < 3; k++) f[k] = (1 + sc[c][k] * s[k]) / 2;
        for (int k = 0; k < 3; k++) d[k] = sc[c][k] / 2 * f[(k + 1) % 3] * f[(k + 2) % 3];
        m += wt * phi[c] * f[0] * f[1] * f[2];
        for (int k = 0; k < 3; k++) gsum[k] += wt * phi[c] * d[k];
      }
    }
    /* J^T gx = g_s: row k of J^T is r_k; Cramer: replace column j */
    double gx[3];
    for (int j = 0; j < 3; j++) {
      double M[9];
      for (int k = 0; k < 3; k++)
        for (int d = 0; d < 3; d++) M[3 * d + k] = d == j ? gsum[k] : r[3 * k + d];
      gx[j] = det3(M) / det;
    }
    worstN = fmax(worstN, fabs(m - o.N[a]));
    for (int d = 0; d < 3; d++) worstG = fmax(worstG, fabs(gx[d] - o.dN[3 * a + d]) * H);
  }
  mpgm_test(worstN < 1e-14, "cpdi 3-D: N = the domain mean of the corners' trilinear "
            "interpolant (%.1e)", worstN);
  mpgm_test(worstG < 1e-13, "cpdi 3-D: grad N = its mean gradient, with V = 8 det [r1 r2 r3] "
            "(%.1e, times h)", worstG);
}

/* an axis-aligned cube inside one cell: uGIMP's weights */
static void check_ugimp3(void) {
  const double lp = H / 4, xp[3] = {0.1, 0.12, 0.09}, r[9] = {lp, 0, 0, 0, lp, 0, 0, 0, lp};
  static res3 a, b;
  const mpgm_shape_params par = {.h = H, .half_width = lp};
  run3("cpdi", &par, xp, r, 0, &a);
  run3("ugimp", &par, xp, r, 0, &b); /* the same cloud: ugimp ignores the domain */
  double w = 0;
  for (int k = 0; k < a.n && a.n == b.n; k++) {
    w = fmax(w, fabs(a.N[k] - b.N[k]));
    for (int d = 0; d < 3; d++) w = fmax(w, H * fabs(a.dN[3 * k + d] - b.dN[3 * k + d]));
  }
  mpgm_test(!a.err && !b.err && a.n == b.n && w < 1e-14,
            "cpdi 3-D: a cube inside a cell gives uGIMP's N and grad N (%.1e)", w);
}

static void check_point_and_failures3(void) {
  static res3 o;
  const mpgm_shape_params par = {.h = H};
  const double xp[3] = {0.03, 0.11, -0.07};
  run3("cpdi", &par, xp, NULL, 0, &o);
  double w = 0, wg = 0;
  for (int a = 0; a < o.n; a++) {
    w = fmax(w, fabs(o.N[a] - hat3n(o.xn + 3 * a, xp)));
    const double *p = o.xn + 3 * a; /* the hat's gradient, x inside a cell */
    for (int d = 0; d < 3; d++) {
      const double s = (xp[d] >= p[d] ? -1.0 : 1.0) / H;
      const double o1 = hat1(xp[(d + 1) % 3] - p[(d + 1) % 3]) * hat1(xp[(d + 2) % 3] - p[(d + 2) % 3]);
      const double gd = hat1(xp[d] - p[d]) > 0 ? s * o1 : 0.0;
      wg = fmax(wg, fabs(gd - o.dN[3 * a + d]) * H);
    }
  }
  mpgm_test(!o.err && w < 1e-15 && wg < 1e-14, "cpdi 3-D: no domain: the hats and their gradients "
            "at x_p (%.1e, %.1e)", w, wg);
  /* corners beyond the last node (R h = 1 m) of a grid that ends there */
  const double far[3] = {0.95, 0.0, 0.1}, r[9] = {0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.1};
  run3("cpdi", &par, far, r, 1, &o);
  int zero = 1;
  for (int a = 0; a < o.n; a++) zero = zero && o.N[a] == 0.0 && o.dN[3 * a] == 0.0 && o.dN[3 * a + 2] == 0.0;
  mpgm_test(o.err == MPGM_ERR_SHAPE && o.reason == MPGM_SHAPE_OFF_GRID && zero,
            "cpdi 3-D: corners off the grid fail with OFF_GRID (err %d, reason %d), N = 0", o.err,
            o.reason);
  const double inv[9] = {0.1, 0, 0, 0, 0.1, 0, 0, 0, -0.1}, mid[3] = {0, 0, 0};
  const double flat[9] = {0.1, 0, 0, 0, 0.1, 0, 0.05, 0.05, 0}; /* r3 in the plane of r1, r2 */
  run3("cpdi", &par, mid, inv, 0, &o);
  const int e1 = o.err, r1 = o.reason;
  run3("cpdi", &par, mid, flat, 0, &o);
  mpgm_test(e1 == MPGM_ERR_SHAPE && r1 == MPGM_SHAPE_INVERTED && o.err == MPGM_ERR_SHAPE &&
                o.reason == MPGM_SHAPE_INVERTED,
            "cpdi 3-D: inverted and flat domains fail with INVERTED (%d, %d)", r1, o.reason);
  /* the grid's box: the 4 corners at x = 1.05 are pulled back to 1, then
   * a domain by the box's corner, 4 corners beyond each of 3 faces */
  const mpgm_shape_params bp = {.h = H, .grid_lo = {-R * H, -R * H, -R * H},
                                .grid_hi = {R * H, R * H, R * H}};
  const double corner[3] = {0.95, -0.95, 0.95};
  int ok = 1;
  for (int k = 0; k < 2; k++) {
    run3("cpdi", &bp, k ? corner : far, r, 1, &o);
    double sN = 0, sg[3] = {0, 0, 0};
    for (int a = 0; a < o.n; a++) {
      sN += o.N[a];
      for (int d = 0; d < 3; d++) sg[d] += o.dN[3 * a + d];
    }
    const double g = fmax(fmax(fabs(sg[0]), fabs(sg[1])), fabs(sg[2])) * H;
    ok = !o.err && o.clamped == (k ? 12 : 4) && fabs(sN - 1) < 1e-14 && g < 1e-13;
    mpgm_test(ok, "cpdi 3-D: with the grid's box, %d corner coordinates pulled back (%d), sum N - "
              "1 = %.1e, sum grad N = %.1e", k ? 12 : 4, o.clamped, sN - 1, g);
  }
  const mpgm_shape_query q = {.n = 1, .xn = mid, .xp = {0, 0, 0}, .cell = -1, .par = NULL};
  double N[1], dN[3];
  mpgm_test(mpgm_shapefn_type_find("cpdi")->eval(&q, N, dN) == MPGM_ERR_INPUT,
            "cpdi 3-D: no length scale is MPGM_ERR_INPUT");
}

static void check_quadratic3(void) {
  const mpgm_shape_params sp = {.h = H, .grid_order = 2, .grid_lo = {-R * H, -R * H, -R * H},
                                .grid_hi = {R * H, R * H, R * H}};
  const mpgm_shape_params hp = {.h = H, .grid_lo = {-R * H, -R * H, -R * H},
                                .grid_hi = {R * H, R * H, R * H}};
  /* corners within 0.5 h and 1.5 h of one, two and three faces */
  const double edge[3][3] = {{-0.93, 0.11, 0.02}, {0.87, 0.91, -0.2}, {0.05, -0.81, 0.93}};
  const double small[3] = {0.03, 0.02, 0.02};
  double wi[5] = {0}, we[4] = {0}, hats = 0.0;
  int fails = 0;
  for (int f = 0; f < 3; f++)
    for (int k = 0; k < 3; k++) {
      double r[9], e[5];
      domain3(F3[f], LEN3, r);
      fails += sums3(&sp, XP3[k], r, 1, e);
      for (int i = 0; i < 5; i++) wi[i] = fmax(wi[i], e[i]);
      fails += sums3(&hp, XP3[k], r, 1, e);
      hats = fmax(hats, e[4]);
      domain3(F3[f], small, r);
      fails += sums3(&sp, edge[k], r, 1, e);
      for (int i = 0; i < 4; i++) we[i] = fmax(we[i], e[i]);
    }
  mpgm_test(fails == 0, "cpdi 3-D quadratic: every domain evaluates (%d failed)", fails);
  mpgm_test(fmax(wi[0], wi[2]) < 1e-13 && wi[1] < 1e-13 && wi[3] < 1e-13,
            "cpdi 3-D quadratic: sum N = 1, sum N x_I = x_p, sum grad N = 0, sum x_I (x) grad N "
            "= identity (%.1e %.1e %.1e %.1e)", wi[0], wi[1], wi[2], wi[3]);
  mpgm_test(fmax(we[0], we[2]) < 1e-13 && we[1] < 1e-13 && we[3] < 1e-13,
            "cpdi 3-D quadratic: the same within 1.5 h of the box's faces, edges and corner, by "
            "the ghost rule (%.1e %.1e %.1e %.1e)", we[0], we[1], we[2], we[3]);
  mpgm_test(wi[4] < 1e-12 && hats > 1e-3, "cpdi 3-D quadratic: a quadratic field's gradient exact "
            "at the particle (%.1e, times h); the hats miss it by %.1e", wi[4], hats);
  /* on the face x = -1 (a tracer) only the face's nodes carry a value */
  static res3 o;
  const double xp[3] = {-R * H, 0.07, -0.12};
  run3("cpdi", &sp, xp, NULL, 1, &o);
  double off = 0.0, on = 0.0;
  for (int a = 0; a < o.n; a++) {
    if (o.xn[3 * a] == -R * H) on += o.N[a];
    else off = fmax(off, fabs(o.N[a]));
  }
  mpgm_test(!o.err && off == 0.0 && fabs(on - 1.0) < 1e-14,
            "cpdi 3-D quadratic: on the box's face only the face's nodes are non-zero (%.1e; sum "
            "%.15g)", off, on);
}
#endif

int main(void) {
  mpgm_test(mpgm_shapefn_type_find("cpdi") != NULL, "cpdi registered");
  if (!mpgm_shapefn_type_find("cpdi")) return mpgm_test_summary();
#if MPGM_DIM == 2
  check_reproduction();
  check_quadrature();
  check_ugimp();
  check_point_and_failures();
  check_quadratic();
#else
  check_reproduction3();
  check_quadrature3();
  check_ugimp3();
  check_point_and_failures3();
  check_quadratic3();
#endif
  return mpgm_test_summary();
}
