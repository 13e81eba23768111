/* fe.c -- linear triangle (T3) and bilinear quadrilateral (Q4) shape
 * functions with their Gauss rules: the "fe" shape-function kind. */
#include "mpgm_shapefn.h"

#include <float.h>
#include <math.h>
#include <string.h>

#if MPGM_DIM != 2
#error "shapefn/fe.c is written for plane strain only (MPGM_DIM = 2)"
#endif

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

static int fe_eval(const mpgm_shape_query *q, double *N, double *dN) {
  int err = MPGM_ERR_SHAPE, reason = MPGM_SHAPE_BAD_INPUT;
  if (q->cell >= 0 && q->cell <= MPGM_CELL_Q4 && q->n == mpgm_fe_nnode(q->cell)) {
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
    .doc = "finite-element shape functions of the cell holding the point "
           "(T3 linear, Q4 bilinear)",
    .needs_cell = 1,
    .eval = fe_eval,
};
