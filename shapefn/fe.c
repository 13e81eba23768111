/* fe.c -- linear triangle (T3) and bilinear quadrilateral (Q4) shape
 * functions with their Gauss rules (2-D builds), the trilinear hexahedron
 * (H8; 3-D builds): the "fe" shape-function kind. */
#include "mpgm_shapefn.h"

#include <float.h>
#include <math.h>
#include <string.h>

#if MPGM_DIM == 2

int mpgm_fe_nnode(int cell) { return cell == MPGM_CELL_T3 ? 3 : 4; }

void mpgm_fe_ref(int cell, const double xi[2], double *N, double *dNdxi) {
  if (cell == MPGM_CELL_T3) {
    N[0] = 1.0 - xi[0] - xi[1];
    N[1] = xi[0];
    N[2] = xi[1];
    if (dNdxi) {
      dNdxi[0] = -1.0; dNdxi[1] = -1.0;
      dNdxi[2] = 1.0;  dNdxi[3] = 0.0;
      dNdxi[4] = 0.0;  dNdxi[5] = 1.0;
    }
    return;
  }
  static const double s[4] = {-1.0, 1.0, 1.0, -1.0};
  static const double t[4] = {-1.0, -1.0, 1.0, 1.0};
  for (int a = 0; a < 4; a++) {
    double fs = 1.0 + s[a] * xi[0], ft = 1.0 + t[a] * xi[1];
    N[a] = 0.25 * fs * ft;
    if (dNdxi) {
      dNdxi[2 * a] = 0.25 * s[a] * ft;
      dNdxi[2 * a + 1] = 0.25 * t[a] * fs;
    }
  }
}

int mpgm_fe_gauss(int cell, int npts, double *xi, double *w) {
  if (cell == MPGM_CELL_T3) {
    if (npts == 1) {
      xi[0] = xi[1] = 1.0 / 3.0;
      w[0] = 0.5;
      return 0;
    }
    if (npts == 3) { /* interior rule, degree 2 */
      const double a = 1.0 / 6.0, b = 2.0 / 3.0;
      const double p[3][2] = {{a, a}, {b, a}, {a, b}};
      for (int i = 0; i < 3; i++) {
        xi[2 * i] = p[i][0];
        xi[2 * i + 1] = p[i][1];
        w[i] = 1.0 / 6.0;
      }
      return 0;
    }
    return MPGM_ERR_INPUT;
  }
  int n;
  double g[3], gw[3];
  switch (npts) {
  case 1: n = 1; g[0] = 0.0; gw[0] = 2.0; break;
  case 4: n = 2; g[0] = -1.0 / sqrt(3.0); g[1] = -g[0]; gw[0] = gw[1] = 1.0; break;
  case 9:
    n = 3;
    g[0] = -sqrt(0.6); g[1] = 0.0; g[2] = sqrt(0.6);
    gw[0] = gw[2] = 5.0 / 9.0; gw[1] = 8.0 / 9.0;
    break;
  default: return MPGM_ERR_INPUT;
  }
  /* eta-major order: rows of points from the bottom of the cell up */
  for (int j = 0, k = 0; j < n; j++)
    for (int i = 0; i < n; i++, k++) {
      xi[2 * k] = g[i];
      xi[2 * k + 1] = g[j];
      w[k] = gw[i] * gw[j];
    }
  return 0;
}

int mpgm_fe_centres(int npts, double *xi, double *w) {
  const int n = npts == 1 ? 1 : npts == 4 ? 2 : npts == 9 ? 3 : 0;
  if (!n) return MPGM_ERR_INPUT;
  /* eta-major order, as the Gauss rule */
  for (int j = 0, k = 0; j < n; j++)
    for (int i = 0; i < n; i++, k++) {
      xi[2 * k] = -1.0 + (2.0 * i + 1.0) / n;
      xi[2 * k + 1] = -1.0 + (2.0 * j + 1.0) / n;
      w[k] = 4.0 / npts;
    }
  return 0;
}

int mpgm_fe_eval(int cell, const double *xn, const double xi[2], double *N,
                 double *dN, double *detJ) {
  const int nn = mpgm_fe_nnode(cell);
  double dr[2 * MPGM_FE_MAXNODE];
  mpgm_fe_ref(cell, xi, N, dr);
  /* J = dx/dxi: J[i][j] = sum_a x_a,i dN_a/dxi_j */
  double J00 = 0, J01 = 0, J10 = 0, J11 = 0;
  for (int a = 0; a < nn; a++) {
    J00 += xn[2 * a] * dr[2 * a];
    J01 += xn[2 * a] * dr[2 * a + 1];
    J10 += xn[2 * a + 1] * dr[2 * a];
    J11 += xn[2 * a + 1] * dr[2 * a + 1];
  }
  const double det = J00 * J11 - J01 * J10;
  if (detJ) *detJ = det;
  if (!(det > 0.0)) return MPGM_ERR_JACOBIAN;
  /* grad N = J^-T dN/dxi */
  const double i00 = J11 / det, i01 = -J01 / det, i10 = -J10 / det, i11 = J00 / det;
  for (int a = 0; a < nn; a++) {
    const double r = dr[2 * a], s = dr[2 * a + 1];
    dN[2 * a] = r * i00 + s * i10;
    dN[2 * a + 1] = r * i01 + s * i11;
  }
  return 0;
}

int mpgm_fe_local(int cell, const double *xn, const double x[2], double xi[2]) {
  const int nn = mpgm_fe_nnode(cell);
  xi[0] = cell == MPGM_CELL_T3 ? 1.0 / 3.0 : 0.0;
  xi[1] = xi[0];
  /* Newton on x(xi) = x; exact in one iteration for T3 */
  for (int it = 0; it < 30; it++) {
    double N[MPGM_FE_MAXNODE], dr[2 * MPGM_FE_MAXNODE];
    mpgm_fe_ref(cell, xi, N, dr);
    double r0 = -x[0], r1 = -x[1], J00 = 0, J01 = 0, J10 = 0, J11 = 0;
    for (int a = 0; a < nn; a++) {
      r0 += N[a] * xn[2 * a];
      r1 += N[a] * xn[2 * a + 1];
      J00 += xn[2 * a] * dr[2 * a];
      J01 += xn[2 * a] * dr[2 * a + 1];
      J10 += xn[2 * a + 1] * dr[2 * a];
      J11 += xn[2 * a + 1] * dr[2 * a + 1];
    }
    const double det = J00 * J11 - J01 * J10;
    if (!(fabs(det) > 0.0)) return MPGM_ERR_SHAPE;
    const double d0 = (J11 * r0 - J01 * r1) / det;
    const double d1 = (-J10 * r0 + J00 * r1) / det;
    xi[0] -= d0;
    xi[1] -= d1;
    /* xi is O(1), but the correction stalls at the round-off of x(xi),
     * about eps |x| over the cell size: stop there (a fixed 1e-14 could
     * never be met by a small cell far from the origin) */
    const double xmag = fabs(x[0]) + fabs(x[1]) + fabs(xn[0]) + fabs(xn[1]);
    const double tol = 1e-12 + 64.0 * DBL_EPSILON * xmag / sqrt(fabs(det));
    if (fabs(d0) + fabs(d1) < tol) return 0;
  }
  return MPGM_ERR_SHAPE;
}

int mpgm_fe_inside(int cell, const double xi[2], double tol) {
  if (cell == MPGM_CELL_T3)
    return xi[0] >= -tol && xi[1] >= -tol && xi[0] + xi[1] <= 1.0 + tol;
  return fabs(xi[0]) <= 1.0 + tol && fabs(xi[1]) <= 1.0 + tol;
}

#else /* MPGM_DIM == 3: the trilinear hexahedron H8 */

/* Signs of the H8 nodes: the Q4's four around the face zeta = -1, then
 * the same four at zeta = +1 (mpgm_corner_sign's order). */
static const double hs[8] = {-1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0, -1.0};
static const double ht[8] = {-1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0};
static const double hu[8] = {-1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0};

int mpgm_fe_nnode(int cell) { return cell == MPGM_CELL_H8 ? 8 : 0; }

void mpgm_fe_ref(int cell, const double xi[3], double *N, double *dNdxi) {
  if (cell != MPGM_CELL_H8) return;
  for (int a = 0; a < 8; a++) {
    const double fs = 1.0 + hs[a] * xi[0], ft = 1.0 + ht[a] * xi[1], fu = 1.0 + hu[a] * xi[2];
    N[a] = 0.125 * fs * ft * fu;
    if (dNdxi) {
      dNdxi[3 * a] = 0.125 * hs[a] * ft * fu;
      dNdxi[3 * a + 1] = 0.125 * ht[a] * fs * fu;
      dNdxi[3 * a + 2] = 0.125 * hu[a] * fs * ft;
    }
  }
}

void mpgm_fe_cube(const double xi[3], double h, double *N, double *dN) {
  const double c = 0.25 / h; /* 1/8 of the reference functions, times d xi / dx = 2 / h */
  for (int a = 0; a < 8; a++) {
    const double fs = 1.0 + hs[a] * xi[0], ft = 1.0 + ht[a] * xi[1], fu = 1.0 + hu[a] * xi[2];
    N[a] = 0.125 * fs * ft * fu;
    dN[3 * a] = c * hs[a] * ft * fu;
    dN[3 * a + 1] = c * ht[a] * fs * fu;
    dN[3 * a + 2] = c * hu[a] * fs * ft;
  }
}

/* The n-point Gauss-Legendre rule on [-1, 1] (n = 1, 2, 3). */
static int gauss_1d(int n, double *g, double *gw) {
  switch (n) {
  case 1: g[0] = 0.0; gw[0] = 2.0; return 0;
  case 2: g[0] = -1.0 / sqrt(3.0); g[1] = -g[0]; gw[0] = gw[1] = 1.0; return 0;
  case 3:
    g[0] = -sqrt(0.6); g[1] = 0.0; g[2] = sqrt(0.6);
    gw[0] = gw[2] = 5.0 / 9.0; gw[1] = 8.0 / 9.0;
    return 0;
  default: return MPGM_ERR_INPUT;
  }
}

/* n from npts = n^3 (n = 1, 2, 3), else 0. */
static int cube_root(int npts) { return npts == 1 ? 1 : npts == 8 ? 2 : npts == 27 ? 3 : 0; }

int mpgm_fe_gauss(int cell, int npts, double *xi, double *w) {
  const int n = cube_root(npts);
  double g[3], gw[3];
  if (cell != MPGM_CELL_H8 || !n) return MPGM_ERR_INPUT;
  gauss_1d(n, g, gw);
  /* zeta-major, then eta: layers of the Q4's rows from the bottom up */
  for (int l = 0, k = 0; l < n; l++)
    for (int j = 0; j < n; j++)
      for (int i = 0; i < n; i++, k++) {
        xi[3 * k] = g[i];
        xi[3 * k + 1] = g[j];
        xi[3 * k + 2] = g[l];
        w[k] = gw[i] * gw[j] * gw[l];
      }
  return 0;
}

int mpgm_fe_centres(int npts, double *xi, double *w) {
  const int n = cube_root(npts);
  if (!n) return MPGM_ERR_INPUT;
  for (int l = 0, k = 0; l < n; l++)
    for (int j = 0; j < n; j++)
      for (int i = 0; i < n; i++, k++) {
        xi[3 * k] = -1.0 + (2.0 * i + 1.0) / n;
        xi[3 * k + 1] = -1.0 + (2.0 * j + 1.0) / n;
        xi[3 * k + 2] = -1.0 + (2.0 * l + 1.0) / n;
        w[k] = 8.0 / npts;
      }
  return 0;
}

/* J = dx/dxi of the H8 with nodes xn from the reference derivatives dr:
 * J[i][j] = sum_a x_a,i dN_a/dxi_j; returns det J. */
static double jacobian(const double *xn, const double *dr, double J[3][3]) {
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double s = 0.0;
      for (int a = 0; a < 8; a++) s += xn[3 * a + i] * dr[3 * a + j];
      J[i][j] = s;
    }
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
         J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

/* The cofactor matrix C of J (C = det J J^-T). */
static void cofactor(const double J[3][3], double C[3][3]) {
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      C[i][j] = J[i1][j1] * J[i2][j2] - J[i1][j2] * J[i2][j1];
    }
}

int mpgm_fe_eval(int cell, const double *xn, const double xi[3], double *N, double *dN,
                 double *detJ) {
  if (cell != MPGM_CELL_H8) {
    if (detJ) *detJ = 0.0;
    return MPGM_ERR_INPUT;
  }
  double dr[24], J[3][3], C[3][3];
  mpgm_fe_ref(cell, xi, N, dr);
  const double det = jacobian(xn, dr, J);
  if (detJ) *detJ = det;
  if (!(det > 0.0)) return MPGM_ERR_JACOBIAN;
  /* grad N = J^-T dN/dxi = C dN/dxi / det J */
  cofactor(J, C);
  for (int a = 0; a < 8; a++)
    for (int i = 0; i < 3; i++)
      dN[3 * a + i] =
          (C[i][0] * dr[3 * a] + C[i][1] * dr[3 * a + 1] + C[i][2] * dr[3 * a + 2]) / det;
  return 0;
}

int mpgm_fe_local(int cell, const double *xn, const double x[3], double xi[3]) {
  if (cell != MPGM_CELL_H8) return MPGM_ERR_INPUT;
  xi[0] = xi[1] = xi[2] = 0.0;
  double xmag = 0.0, dprev = HUGE_VAL;
  for (int d = 0; d < 3; d++) xmag += fabs(x[d]) + fabs(xn[d]);
  /* Newton on x(xi) = x from the centre. On a strongly distorted hex a
   * full step can overshoot where J varies: a correction larger than the
   * one before it is taken at half length, so a diverging sequence is
   * pulled back instead of leaving the region where the map is one-to-one
   * (converging sequences, where the corrections shrink, are plain Newton). */
  for (int it = 0; it < 50; it++) {
    double N[8], dr[24], J[3][3], C[3][3], r[3];
    mpgm_fe_ref(cell, xi, N, dr);
    for (int d = 0; d < 3; d++) {
      r[d] = -x[d];
      for (int a = 0; a < 8; a++) r[d] += N[a] * xn[3 * a + d];
    }
    const double det = jacobian(xn, dr, J);
    if (!(fabs(det) > 0.0)) return MPGM_ERR_SHAPE;
    cofactor(J, C);
    double dx[3], step = 0.0; /* dx = J^-1 r = C^T r / det */
    for (int j = 0; j < 3; j++) {
      dx[j] = (C[0][j] * r[0] + C[1][j] * r[1] + C[2][j] * r[2]) / det;
      step += fabs(dx[j]);
    }
    /* the correction stalls at the round-off of x(xi), about eps |x|
     * over the cell size (as in 2-D) */
    const double tol = 1e-12 + 64.0 * DBL_EPSILON * xmag / cbrt(fabs(det));
    double lam = 1.0;
    if (step > dprev && step > tol) lam = 0.5; /* diverging: damp */
    for (int j = 0; j < 3; j++) xi[j] -= lam * dx[j];
    if (step < tol) return 0;
    dprev = step;
  }
  return MPGM_ERR_SHAPE;
}

int mpgm_fe_inside(int cell, const double xi[3], double tol) {
  if (cell != MPGM_CELL_H8) return 0;
  return fabs(xi[0]) <= 1.0 + tol && fabs(xi[1]) <= 1.0 + tol && fabs(xi[2]) <= 1.0 + tol;
}

#endif

/* The cell kind of the build: T3 or Q4 in 2-D, H8 in 3-D. */
static int build_cell(int cell) {
#if MPGM_DIM == 2
  return cell >= 0 && cell <= MPGM_CELL_Q4;
#else
  return cell == MPGM_CELL_H8;
#endif
}

static int fe_eval(const mpgm_shape_query *q, double *N, double *dN) {
  int err = MPGM_ERR_SHAPE, reason = MPGM_SHAPE_BAD_INPUT;
  if (build_cell(q->cell) && q->n == mpgm_fe_nnode(q->cell)) {
    err = mpgm_fe_eval(q->cell, q->xn, q->xi, N, dN, NULL);
    reason = err ? MPGM_SHAPE_INVERTED : MPGM_SHAPE_OK;
  }
  if (q->info) {
    memset(q->info, 0, sizeof *q->info);
    q->info->reason = reason;
    q->info->msg = mpgm_shape_reason_str(reason);
    q->info->nsupport = err ? 0 : q->n;
  }
  return err;
}

const mpgm_shapefn_type mpgm_shapefn_fe = {
    .name = "fe",
#if MPGM_DIM == 2
    .doc = "finite-element shape functions of the cell holding the point "
           "(T3 linear, Q4 bilinear)",
#else
    .doc = "finite-element shape functions of the cell holding the point "
           "(H8 trilinear)",
#endif
    .needs_cell = 1,
    .eval = fe_eval,
};
