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
 *
 * A 3-D build checks the cube: N_I is the product of the three 1-D means,
 * partition of unity, linear reproduction and the gradient identities at
 * points next to cell faces, edges and corners, central differences, C1
 * along z, OFF_GRID next to the grid's corner, edge and face, the input
 * errors and the support radius sqrt(3) (h + lp).
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

#if MPGM_DIM == 2
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

#else
/* ---- 3-D: the particle's cube ------------------------------------------ */

/* The nodes (i h, j h, k h) of the grid with 0 <= i, j, k < lim (lim <= 0:
 * no end) within 1.65 h of x on every axis (those within h + lp and a
 * layer of zero-weight ones); returns their count. */
static int cloud3(const double x[3], int lim, double *xn) {
  int lo[3], hi[3], n = 0;
  for (int d = 0; d < 3; d++) {
    lo[d] = (int)ceil(x[d] / H - 1.65);
    hi[d] = (int)floor(x[d] / H + 1.65);
    if (lim > 0) {
      lo[d] = lo[d] < 0 ? 0 : lo[d];
      hi[d] = hi[d] > lim - 1 ? lim - 1 : hi[d];
    }
  }
  for (int k = lo[2]; k <= hi[2]; k++)
    for (int j = lo[1]; j <= hi[1]; j++)
      for (int i = lo[0]; i <= hi[0]; i++, n++) {
        xn[3 * n] = i * H;
        xn[3 * n + 1] = j * H;
        xn[3 * n + 2] = k * H;
      }
  return n;
}

static int eval3(const double x[3], int lim, double lp, double *xn, int *n, double *N, double *dN,
                 mpgm_shape_info *info) {
  *n = cloud3(x, lim, xn);
  const mpgm_shape_params par = {.h = H, .half_width = lp};
  mpgm_shape_query q = {.n = *n, .xn = xn, .xp = {x[0], x[1], x[2]}, .cell = -1, .par = &par,
                        .info = info};
  return mpgm_shapefn_type_find("ugimp")->eval(&q, N, dN);
}

/* Points in a cell and next to its faces, edges and corners: a random
 * point, then each coordinate pushed to one of the break offsets
 * (0, lp, h - lp, on the node plane) from a node. */
static void point3(rng *r, int p, double x[3]) {
  const double at[5] = {0.0, LP, H - LP, 0.5 * H, 1e-12 * H};
  for (int d = 0; d < 3; d++) {
    x[d] = uniform(r, -2.0 * H, 2.0 * H);
    if (p % 4 > d) x[d] = H * round(x[d] / H) + at[(p + d) % 5]; /* near a face / edge / corner */
  }
}

/* N_I = product of the 1-D means over the three axes (the trilinear hat
 * over the cube separates), partition of unity, linear reproduction and
 * the gradient identities, gradients against central differences. */
static void check_grid3(void) {
  double xn[3 * 128], N[128], dN[3 * 128], Np[128], Nm[128], g[3 * 128];
  rng r = {0x2545F4914F6CDD1DULL};
  double wN = 0, wsum = 0, wx = 0, wI = 0, wfd = 0;
  int fails = 0, np = 0, nq = 0;
  for (int p = 0; p < 200; p++) {
    double x[3];
    point3(&r, p, x);
    int n;
    if (eval3(x, 0, LP, xn, &n, N, dN, NULL)) {
      fails++;
      continue;
    }
    double s = 0, rx[3] = {0, 0, 0}, G[9] = {0};
    for (int a = 0; a < n; a++) {
      const double m = mean_hat(x[0] - xn[3 * a], LP) * mean_hat(x[1] - xn[3 * a + 1], LP) *
                       mean_hat(x[2] - xn[3 * a + 2], LP);
      wN = fmax(wN, fabs(N[a] - m));
      s += N[a];
      for (int i = 0; i < 3; i++) {
        rx[i] += N[a] * xn[3 * a + i];
        for (int j = 0; j < 3; j++) G[3 * i + j] += xn[3 * a + i] * dN[3 * a + j];
      }
    }
    wsum = fmax(wsum, fabs(s - 1.0));
    for (int i = 0; i < 3; i++) {
      wx = fmax(wx, fabs(rx[i] - x[i]) / H);
      for (int j = 0; j < 3; j++) wI = fmax(wI, fabs(G[3 * i + j] - (i == j)));
    }
    const double e = 1e-6 * H;
    for (int c = 0; c < 3; c++) { /* the same cloud for both sides */
      const mpgm_shape_params par = {.h = H, .half_width = LP};
      mpgm_shape_query q = {.n = n, .xn = xn, .xp = {x[0], x[1], x[2]}, .cell = -1, .par = &par};
      q.xp[c] += e;
      fails += mpgm_shapefn_type_find("ugimp")->eval(&q, Np, g) != 0;
      q.xp[c] -= 2 * e;
      fails += mpgm_shapefn_type_find("ugimp")->eval(&q, Nm, g) != 0;
      for (int a = 0; a < n; a++) wfd = fmax(wfd, fabs((Np[a] - Nm[a]) / (2 * e) - dN[3 * a + c]) * H);
    }
    np++;
    nq = n > nq ? n : nq;
  }
  mpgm_test(fails == 0, "ugimp 3-D: %d points near faces, edges and corners evaluate (%d failed; "
            "up to %d nodes)", np, fails, nq);
  mpgm_test(wN < 1e-14, "ugimp 3-D: N_I = the product of the 1-D means of the hat (%.1e)", wN);
  mpgm_test(wsum < 1e-14 && wx < 1e-13 && wI < 1e-12,
            "ugimp 3-D: sum N = 1 (%.1e), sum N x_I = x (%.1e h), sum x_I (x) grad N = I (%.1e)",
            wsum, wx, wI);
  mpgm_test(wfd < 1e-6, "ugimp 3-D: grad N against central differences (x h: %.2g)", wfd);
}

/* C1 across the break points along z, the axis 2-D never has. */
static void check_c1_z(void) {
  const double brk[6] = {LP, H - LP, H + LP, -LP, -(H - LP), -(H + LP)}, e = 1e-9 * H;
  double xn[3 * 128], N1[128], N2[128], g1[3 * 128], g2[3 * 128];
  for (int b = 0; b < 6; b++) {
    const double x1[3] = {0.31 * H, -0.17 * H, brk[b] - e}, x2[3] = {x1[0], x1[1], brk[b] + e};
    int n1, n2;
    double jN = 0, jg = 0;
    int err = eval3(x1, 0, LP, xn, &n1, N1, g1, NULL);
    double o1 = 0, o2 = 0, s1 = 0, s2 = 0; /* the node at the origin */
    for (int a = 0; a < n1; a++)
      if (xn[3 * a] == 0 && xn[3 * a + 1] == 0 && xn[3 * a + 2] == 0) { o1 = N1[a]; s1 = g1[3 * a + 2]; }
    err |= eval3(x2, 0, LP, xn, &n2, N2, g2, NULL);
    for (int a = 0; a < n2; a++)
      if (xn[3 * a] == 0 && xn[3 * a + 1] == 0 && xn[3 * a + 2] == 0) { o2 = N2[a]; s2 = g2[3 * a + 2]; }
    jN = fabs(o1 - o2);
    jg = fabs(s1 - s2);
    mpgm_test(!err && jN < 1e-8 && jg < 1e-7 / H && (fabs(brk[b]) >= H + LP || o1 > 0.0),
              "ugimp 3-D: C1 at dz = %+.3f h: weight jumps %.2g, slope %.2g", brk[b] / H, jN, jg);
  }
}

static void check_failures3(void) {
  double xn[3 * 128], N[128], dN[3 * 128];
  mpgm_shape_info info = {0};
  int n;
  /* the grid [0, 3h]^3: a point 0.1 h from its corner reaches past it */
  const double cx[3] = {0.1 * H, 0.1 * H, 0.1 * H};
  int err = eval3(cx, 4, LP, xn, &n, N, dN, &info);
  double nz = 0.0;
  for (int a = 0; a < n; a++) nz += fabs(N[a]) + fabs(dN[3 * a]) + fabs(dN[3 * a + 1]) + fabs(dN[3 * a + 2]);
  mpgm_test(err == MPGM_ERR_SHAPE && info.reason == MPGM_SHAPE_OFF_GRID && nz == 0.0,
            "ugimp 3-D: at a grid corner, nodes missing: MPGM_ERR_SHAPE, OFF_GRID, N = dN = 0 (%s)",
            info.msg ? info.msg : "?");
  /* at the centre of its sub-cube the cube stays in the cell */
  const double cc[3] = {0.25 * H, 0.25 * H, 0.25 * H};
  err = eval3(cc, 4, 0.25 * H, xn, &n, N, dN, &info);
  mpgm_test(err == 0, "ugimp 3-D: at a sub-cube centre by the grid's corner no node beyond is "
            "needed (%d)", err);
  /* next to an edge of the grid (two faces), and next to one face */
  const double ex[3] = {0.1 * H, 0.1 * H, 1.5 * H}, fx[3] = {1.5 * H, 1.5 * H, 0.1 * H};
  const int e1 = eval3(ex, 4, LP, xn, &n, N, dN, &info), r1 = info.reason;
  const int e2 = eval3(fx, 4, LP, xn, &n, N, dN, &info), r2 = info.reason;
  mpgm_test(e1 == MPGM_ERR_SHAPE && r1 == MPGM_SHAPE_OFF_GRID && e2 == MPGM_ERR_SHAPE &&
                r2 == MPGM_SHAPE_OFF_GRID,
            "ugimp 3-D: next to the grid's edge and face: OFF_GRID (%d, %d)", r1, r2);
  const double in[3] = {1.5 * H, 1.5 * H, 1.5 * H};
  mpgm_test(eval3(in, 4, LP, xn, &n, N, dN, &info) == 0, "ugimp 3-D: inside the grid: ok");
  mpgm_test(eval3(in, 4, 0.6 * H, xn, &n, N, dN, &info) == MPGM_ERR_INPUT &&
                eval3(in, 4, 0.0, xn, &n, N, dN, &info) == MPGM_ERR_INPUT,
            "ugimp 3-D: lp > h/2 or no half-width: MPGM_ERR_INPUT");
  const mpgm_shape_params par = {.h = H, .half_width = LP};
  double R = 0.0;
  mpgm_test(mpgm_shape_support_radius(mpgm_shapefn_type_find("ugimp"), &par, &R) == 0,
            "support radius defined");
  mpgm_test_rel(R, sqrt(3.0) * (H + LP), TEST_TOL1, "ugimp 3-D: support radius sqrt(3) (h + lp)");
}
#endif

int main(void) {
  mpgm_test(mpgm_shapefn_type_find("ugimp") != NULL, "ugimp registered");
  if (!mpgm_shapefn_type_find("ugimp")) return mpgm_test_summary();
#if MPGM_DIM == 2
  check_closed_form();
  check_c1();
  check_fd();
  check_failures();
#else
  check_grid3();
  check_c1_z();
  check_failures3();
#endif
  return mpgm_test_summary();
}
