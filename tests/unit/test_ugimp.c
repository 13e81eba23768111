/* test_ugimp.c -- the "ugimp" shape-function kind (shapefn/ugimp.c):
 *
 *   - its 1-D weight equals the mean of the node's hat function over the
 *     particle's interval, computed here by Simpson's rule on each linear
 *     piece (an independent construction of the closed form);
 *   - weight and gradient are continuous (C1) across the five break
 *     points d = +-lp, +-(h - lp), +-(h + lp), where the pieces meet;
 *   - the 2-D weights are the tensor product, their gradient matches
 *     central differences;
 *   - a cloud missing a node within h + lp fails recoverably with reason
 *     MPGM_SHAPE_OFF_GRID (N = dN = 0); no length scale or lp > h/2 is
 *     MPGM_ERR_INPUT; the support radius is sqrt(2) (h + lp).
 * (Partition of unity, linear reproduction and the gradient identities on
 * a grid: test_shapefn_meshfree.c.)
 */
#include "mpgm_shapefn.h"
#include "mpgm_test.h"

#include <math.h>
#include <stdio.h>

static const double H = 0.37, LP = 0.37 / 4.0;

/* the hat of a node at 0, half-width H */
static double hat(double x) { return fmax(0.0, 1.0 - fabs(x) / H); }

/* mean of the hat over [d - lp, d + lp]: exact Simpson on each piece where
 * the hat is linear (breaks at -H, 0, H) */
static double mean_hat(double d, double lp) {
  double brk[5] = {d - lp, -H, 0.0, H, d + lp}, sum = 0.0;
  double a = d - lp;
  for (int i = 1; i < 5; i++) {
    const double b = i == 4 ? d + lp : fmin(fmax(brk[i], d - lp), d + lp);
    if (b > a) sum += (b - a) / 6.0 * (hat(a) + 4.0 * hat(0.5 * (a + b)) + hat(b));
    a = fmax(a, b);
  }
  return sum / (2.0 * lp);
}

/* the 7 x 7 grid nodes (i h, j h), |i|, |j| <= 3: every node within h + lp
 * of a point with |x|, |y| <= h + lp; node (0, 0) is number 24 */
enum { NP = 49, ORIGIN = 24 };
static void patch(double *xn) {
  for (int j = -3, n = 0; j <= 3; j++)
    for (int i = -3; i <= 3; i++, n++) {
      xn[2 * n] = i * H;
      xn[2 * n + 1] = j * H;
    }
}

/* N and dN of the node at the origin seen from (x, y); 0 or the error */
static int origin_node(double x, double y, double *N, double *dN) {
  double xn[2 * NP], Na[NP], dNa[2 * NP];
  patch(xn);
  const mpgm_shape_params par = {.h = H, .half_width = LP};
  mpgm_shape_query q = {.n = NP, .xn = xn, .xp = {x, y}, .cell = -1, .par = &par};
  const int err = mpgm_shapefn_type_find("ugimp")->eval(&q, Na, dNa);
  *N = Na[ORIGIN];
  dN[0] = dNa[2 * ORIGIN];
  dN[1] = dNa[2 * ORIGIN + 1];
  return err;
}

/* S(d) = N_origin(d, y0) / S(y0) over the whole support and past it */
static void check_closed_form(void) {
  const double y0 = 0.31 * H, Sy = mean_hat(y0, LP);
  double worst = 0.0;
  int errs = 0;
  for (int k = -130; k <= 130; k++) {
    const double d = k * (H + LP) / 120.0;
    double N, dN[2];
    errs += origin_node(d, y0, &N, dN) != 0;
    worst = fmax(worst, fabs(N / Sy - mean_hat(d, LP)));
  }
  mpgm_test(errs == 0 && worst < 1e-14, "1-D weight = the mean of the hat over the particle "
            "(261 offsets to 1.08 (h + lp); largest difference %.2g)", worst);
}

/* weight and slope on both sides of each break point */
static void check_c1(void) {
  const double brk[6] = {LP, H - LP, H + LP, -LP, -(H - LP), -(H + LP)};
  const double y0 = 0.31 * H, e = 1e-9 * H;
  for (int b = 0; b < 6; b++) {
    double N1, N2, g1[2], g2[2];
    const int err = origin_node(brk[b] - e, y0, &N1, g1) | origin_node(brk[b] + e, y0, &N2, g2);
    mpgm_test(!err && fabs(N1 - N2) < 1e-8 && fabs(g1[0] - g2[0]) < 1e-7 / H,
              "C1 at d = %+.3f h: weight jumps %.2g, slope %.2g", brk[b] / H, fabs(N1 - N2),
              fabs(g1[0] - g2[0]));
  }
}

static void check_fd(void) {
  double xn[2 * NP], N[NP], dN[2 * NP], Np[NP], Nm[NP], g[2 * NP];
  const int n = NP;
  patch(xn);
  const mpgm_shape_params par = {.h = H, .half_width = LP};
  const mpgm_shapefn_type *t = mpgm_shapefn_type_find("ugimp");
  rng r = {0x2545F4914F6CDD1DULL};
  double worst = 0.0;
  for (int p = 0; p < 50; p++) {
    const double x[2] = {uniform(&r, 0.0, H), uniform(&r, 0.0, H)};
    mpgm_shape_query q = {.n = n, .xn = xn, .xp = {x[0], x[1]}, .cell = -1, .par = &par};
    if (t->eval(&q, N, dN)) {
      mpgm_test(0, "ugimp at (%g, %g) in a full patch failed", x[0], x[1]);
      continue;
    }
    const double e = 1e-6 * H;
    for (int c = 0; c < 2; c++) {
      mpgm_shape_query qp = q, qm = q;
      qp.xp[c] += e;
      qm.xp[c] -= e;
      t->eval(&qp, Np, g);
      t->eval(&qm, Nm, g);
      for (int a = 0; a < n; a++) worst = fmax(worst, fabs((Np[a] - Nm[a]) / (2 * e) - dN[2 * a + c]) * H);
    }
  }
  mpgm_test(worst < 1e-6, "grad N against central differences (largest difference x h: %.2g)", worst);
}

static void check_failures(void) {
  const mpgm_shapefn_type *t = mpgm_shapefn_type_find("ugimp");
  double xn[2 * NP], N[NP], dN[2 * NP];
  const int n = NP;
  patch(xn);
  /* drop the node at (-h, 0): a point at (0.1 h, 0.5 h) needs it */
  double xm[2 * NP];
  int k = 0;
  for (int a = 0; a < n; a++)
    if (a != ORIGIN - 1) {
      xm[2 * k] = xn[2 * a];
      xm[2 * k + 1] = xn[2 * a + 1];
      k++;
    }
  const mpgm_shape_params par = {.h = H, .half_width = LP};
  mpgm_shape_info info = {0};
  mpgm_shape_query q = {.n = k, .xn = xm, .xp = {0.1 * H, 0.5 * H}, .cell = -1, .par = &par,
                        .info = &info};
  int err = t->eval(&q, N, dN);
  double nz = 0.0;
  for (int a = 0; a < k; a++) nz += fabs(N[a]) + fabs(dN[2 * a]) + fabs(dN[2 * a + 1]);
  mpgm_test(err == MPGM_ERR_SHAPE && info.reason == MPGM_SHAPE_OFF_GRID && nz == 0.0,
            "a missing node within h + lp: MPGM_ERR_SHAPE, OFF_GRID, N = dN = 0 (%s)",
            info.msg ? info.msg : "?");
  /* the same point at the centre of its sub-square needs no node beyond */
  q.xp[0] = 0.25 * H;
  mpgm_test(t->eval(&q, N, dN) == 0, "at a sub-cell centre (0.25 h) the node at -h is not needed");
  const mpgm_shape_params bad = {.h = H, .half_width = 0.6 * H}, none = {.h = H};
  q.par = &bad;
  mpgm_test(t->eval(&q, N, dN) == MPGM_ERR_INPUT, "lp > h/2: MPGM_ERR_INPUT");
  q.par = &none;
  mpgm_test(t->eval(&q, N, dN) == MPGM_ERR_INPUT, "no half-width: MPGM_ERR_INPUT");
  double R = 0.0;
  mpgm_test(mpgm_shape_support_radius(t, &par, &R) == 0, "support radius defined");
  mpgm_test_rel(R, sqrt(2.0) * (H + LP), TEST_TOL1, "support radius sqrt(2) (h + lp)");
}

int main(void) {
  mpgm_test(mpgm_shapefn_type_find("ugimp") != NULL, "ugimp registered");
  if (!mpgm_shapefn_type_find("ugimp")) return mpgm_test_summary();
  check_closed_form();
  check_c1();
  check_fd();
  check_failures();
  return mpgm_test_summary();
}
