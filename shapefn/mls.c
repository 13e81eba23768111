/* mls.c -- moving least-squares shape functions (Lancaster & Salkauskas;
 * Iaconeta et al. 2017, eqs 50-58): the "mls" kind.
 *
 *   N_a(x) = p(x)^T M(x)^-1 p(x_a) w_a(x),   M(x) = sum_b w_b(x) p(x_b) p(x_b)^T
 *
 * Basis: linear (1, u, v) or quadratic (1, u, v, u^2, uv, v^2), shifted to
 * the evaluation point and scaled by the support radius R,
 * (u, v) = (x_a - x) / R, so that the entries of M are O(1) whatever the
 * coordinates and the units (conditioning). The approximant does not depend
 * on the shift (the shifted basis spans the same polynomials), so the
 * derivative is taken with the centre c frozen and then c = x:
 *
 *   g = M^-1 p(0),            N_a = w_a g . p_a
 *   dg/dx_k = M^-1 (dp(0)/dx_k - dM/dx_k g),   dp(0)/dx_k = e_{1+k} / R,
 *   dM/dx_k = sum_b dw_b/dx_k p_b p_b^T
 *   dN_a/dx_k = dw_a/dx_k g . p_a + w_a dg/dx_k . p_a
 *
 * which is the full derivative including that of M^-1 (Belytschko et al.).
 *
 * Weight: the cubic B-spline in rho = |x - x_a| / R, scaled to w(0) = 1,
 *   w = 1 - 6 rho^2 + 6 rho^3 (rho <= 1/2),  2 (1 - rho)^3 (1/2 < rho <= 1),
 *   0 beyond.
 * Chosen over the truncated exponential (Gaussian) weight because its
 * support ends exactly at R with w, w' and w'' all zero there (C2): a node
 * entering or leaving the cloud changes N and grad N continuously, with no
 * cut-off tolerance and no jump; it also costs no exp().
 *
 * Failures (recoverable MPGM_ERR_SHAPE, N = dN = 0, reason in q->info):
 * fewer nodes with w > 0 than basis terms (TOO_FEW); M not positive
 * definite or cond_1(M) > max_cond, e.g. collinear nodes (ILL_COND).
 */
#include "mpgm_shapefn_impl.h"

#include <math.h>
#include <string.h>

#if MPGM_DIM != 2
#error "shapefn/mls.c is written for plane strain only (MPGM_DIM = 2)"
#endif

#define MLS_MAXM 6

/* Weight and (dw/drho) / rho of the cubic spline (finite at rho = 0). */
static inline double spline_w(double rho, double *dw_rho) {
  if (rho <= 0.5) {
    *dw_rho = -12.0 + 18.0 * rho;
    return 1.0 + rho * rho * (-6.0 + 6.0 * rho);
  }
  const double s = 1.0 - rho;
  *dw_rho = -6.0 * s * s / rho;
  return 2.0 * s * s * s;
}

static int mls_radius(const mpgm_shape_params *par, double *R) {
  *R = 0.0;
  if (!par) return MPGM_ERR_INPUT;
  if (par->radius > 0.0) *R = par->radius;
  else if (par->h > 0.0) *R = mpgm_shape_dflt(par->dilation, MPGM_MLS_DILATION) * par->h;
  return *R > 0.0 && isfinite(*R) ? 0 : MPGM_ERR_INPUT;
}

/* Basis at scaled offset (u, v): 3 or 6 terms. */
static inline void basis(int m, double u, double v, double *p) {
  p[0] = 1.0;
  p[1] = u;
  p[2] = v;
  if (m == 6) {
    p[3] = u * u;
    p[4] = u * v;
    p[5] = v * v;
  }
}

static int mls_eval(const mpgm_shape_query *q, double *N, double *dN) {
  int err = mpgm_shape_check_cloud(q, N, dN);
  if (err) return err;
  const mpgm_shape_params *par = q->par;
  double R;
  if (mls_radius(par, &R)) return mpgm_shape_fail(q, N, dN, MPGM_ERR_INPUT, MPGM_SHAPE_BAD_INPUT);
  if (par->order < 0 || par->order > 2)
    return mpgm_shape_fail(q, N, dN, MPGM_ERR_INPUT, MPGM_SHAPE_BAD_INPUT);
  const int m = par->order == 2 ? 6 : 3;
  const double max_cond = mpgm_shape_dflt(par->max_cond, MPGM_MLS_MAX_COND);
  const double x = q->xp[0], y = q->xp[1], iR = 1.0 / R;

  /* weights, their gradients and the basis of the nodes in the support;
   * M and dM/dx, dM/dy (upper triangles) */
  int idx[MPGM_SHAPE_MAXNODE];
  double w[MPGM_SHAPE_MAXNODE], gw[2 * MPGM_SHAPE_MAXNODE], P[MLS_MAXM * MPGM_SHAPE_MAXNODE];
  double M[MLS_MAXM * MLS_MAXM] = {0}, Mx[MLS_MAXM * MLS_MAXM] = {0},
         My[MLS_MAXM * MLS_MAXM] = {0};
  int ns = 0;
  memset(N, 0, sizeof(double) * (size_t)q->n);
  memset(dN, 0, sizeof(double) * 2 * (size_t)q->n);
  for (int a = 0; a < q->n; a++) {
    const double u = (q->xn[2 * a] - x) * iR, v = (q->xn[2 * a + 1] - y) * iR;
    const double rho = sqrt(u * u + v * v);
    if (!(rho < 1.0)) continue; /* also drops NaN coordinates */
    double dw_rho;
    const double wa = spline_w(rho, &dw_rho);
    /* d rho / dx = (x - x_a) / (R |x - x_a|) = -u / (R rho) */
    double *pa = P + m * ns;
    basis(m, u, v, pa);
    idx[ns] = a;
    w[ns] = wa;
    gw[2 * ns] = -dw_rho * u * iR;
    gw[2 * ns + 1] = -dw_rho * v * iR;
    for (int i = 0; i < m; i++)
      for (int j = i; j < m; j++) {
        const double pp = pa[i] * pa[j];
        M[i * m + j] += wa * pp;
        Mx[i * m + j] += gw[2 * ns] * pp;
        My[i * m + j] += gw[2 * ns + 1] * pp;
      }
    ns++;
  }
  if (ns < m) return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_TOO_FEW);
  for (int i = 0; i < m; i++)
    for (int j = 0; j < i; j++) {
      M[i * m + j] = M[j * m + i];
      Mx[i * m + j] = Mx[j * m + i];
      My[i * m + j] = My[j * m + i];
    }

  double Mi[MLS_MAXM * MLS_MAXM];
  if (mpgm_spd_inverse(m, M, Mi)) {
    if (q->info) q->info->cond = INFINITY;
    return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_ILL_COND);
  }
  /* cond_1(M) = |M|_1 |M^-1|_1 (both symmetric: max row sums) */
  double n1 = 0.0, ni1 = 0.0;
  for (int i = 0; i < m; i++) {
    double s = 0.0, si = 0.0;
    for (int j = 0; j < m; j++) {
      s += fabs(M[i * m + j]);
      si += fabs(Mi[i * m + j]);
    }
    n1 = fmax(n1, s);
    ni1 = fmax(ni1, si);
  }
  const double cond = n1 * ni1;
  if (q->info) q->info->cond = cond;
  if (!(cond <= max_cond)) return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_ILL_COND);

  /* g = M^-1 e0; dg_k = M^-1 (e_{1+k} / R - dM_k g) */
  double g[MLS_MAXM], gx[MLS_MAXM], gy[MLS_MAXM], tx[MLS_MAXM], ty[MLS_MAXM];
  for (int i = 0; i < m; i++) g[i] = Mi[i * m];
  for (int i = 0; i < m; i++) {
    double sx = 0.0, sy = 0.0;
    for (int j = 0; j < m; j++) {
      sx += Mx[i * m + j] * g[j];
      sy += My[i * m + j] * g[j];
    }
    tx[i] = (i == 1 ? iR : 0.0) - sx;
    ty[i] = (i == 2 ? iR : 0.0) - sy;
  }
  for (int i = 0; i < m; i++) {
    double sx = 0.0, sy = 0.0;
    for (int j = 0; j < m; j++) {
      sx += Mi[i * m + j] * tx[j];
      sy += Mi[i * m + j] * ty[j];
    }
    gx[i] = sx;
    gy[i] = sy;
  }
  for (int k = 0; k < ns; k++) {
    const double *pa = P + m * k;
    double gp = 0.0, gxp = 0.0, gyp = 0.0;
    for (int i = 0; i < m; i++) {
      gp += g[i] * pa[i];
      gxp += gx[i] * pa[i];
      gyp += gy[i] * pa[i];
    }
    const int a = idx[k];
    N[a] = w[k] * gp;
    dN[2 * a] = gw[2 * k] * gp + w[k] * gxp;
    dN[2 * a + 1] = gw[2 * k + 1] * gp + w[k] * gyp;
  }
  mpgm_shape_ok(q, 0, ns, cond, 0.0);
  return 0;
}

/* shape.* of "mls" (docs/scene-format.md, "shape") */
static const mpgm_key_spec mls_keys[] = {
    {.name = "radius", .type = MPGM_KEY_REAL, .offset = offsetof(mpgm_shape_params, radius),
     .def = 0.0, .lo = 0.0, .hi = INFINITY, .unit = "m",
     .doc = "support radius R of the weight; 0: dilation h"},
    {.name = "dilation", .type = MPGM_KEY_REAL, .offset = offsetof(mpgm_shape_params, dilation),
     .def = MPGM_MLS_DILATION, .lo = 0.0, .hi = INFINITY, .lo_open = 1, .unit = "-",
     .doc = "R / h when radius is 0"},
    {.name = "order", .type = MPGM_KEY_INT, .offset = offsetof(mpgm_shape_params, order),
     .def = 1, .lo = 1, .hi = 2, .unit = "-", .doc = "basis: 1 linear (3 terms), 2 quadratic (6)"},
    MPGM_MAX_COND_KEY,
    MPGM_CLOUD_KEYS,
};

const mpgm_shapefn_type mpgm_shapefn_mls = {
    .name = "mls",
    .doc = "moving least squares, linear or quadratic basis, cubic-spline weight of radius "
           "R = radius or dilation * h",
    .needs_cell = 0,
    .eval = mls_eval,
    .support_radius = mls_radius,
    .keys = mls_keys,
    .nkeys = sizeof mls_keys / sizeof *mls_keys,
};
