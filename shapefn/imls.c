/* imls.c -- improved moving least squares coefficients (Tran, Solowski,
 * Berzins & Guilkey 2019, eqs 8-20); see mpgm_imls.h for the contract and
 * docs/theory.md for the derivation.
 *
 * Layout: the workspace P holds one column of n values per monomial. It is
 * filled with the monomials q_j(x_k) (0 where w_k = 0, so that the sums run
 * over all k without a branch and far points never enter as inf * 0) and
 * orthonormalised in place: column j ends as p_j / |p_j| when direction j
 * is kept. The weights w_k live in phi until the last loop turns them into
 * the coefficients. The value of each p_j at x_e is carried alongside
 * (pe[j]); the centred monomials vanish at x_e except the constant.
 */
#include "mpgm_imls.h"

#include <math.h>
#include <string.h>

#if MPGM_DIM != 2
#error "shapefn/imls.c is written for plane strain only (MPGM_DIM = 2)"
#endif

double mpgm_imls_bspline(double r) {
  r = fabs(r);
  if (r <= 1.0) return 2.0 / 3.0 + r * r * (0.5 * r - 1.0);
  if (r < 2.0) {
    const double s = 2.0 - r;
    return s * s * s / 6.0;
  }
  return 0.0; /* also NaN */
}

/* Number of monomials of the basis. */
static int nbasis(int dim, int order) {
  return dim == 1 ? order + 1 : (order == 1 ? 3 : 6);
}

/* Weights into w and monomials into the columns of P (stride n). Returns
 * the number of data points with w > 0. */
static int fill(const mpgm_imls_params *p, const double *xe, int n, const double *xd, int m,
                double *w, double *P) {
  const double ih = 1.0 / p->h;
  int ns = 0;
  for (int k = 0; k < n; k++) {
    const double u = (xd[p->dim * k] - xe[0]) * ih;
    const double v = p->dim == 2 ? (xd[2 * k + 1] - xe[1]) * ih : 0.0;
    double wk = mpgm_imls_bspline(u);
    if (p->dim == 2 && wk > 0.0) wk *= mpgm_imls_bspline(v);
    w[k] = wk;
    if (!(wk > 0.0)) {
      w[k] = 0.0;
      for (int j = 0; j < m; j++) P[(size_t)j * n + k] = 0.0;
      continue;
    }
    ns++;
    double q[MPGM_IMLS_MAXBASIS];
    q[0] = 1.0;
    q[1] = u;
    if (p->dim == 1) {
      q[2] = u * u; /* used only when m == 3 */
    } else {
      q[2] = v;
      q[3] = u * u;
      q[4] = u * v;
      q[5] = v * v;
    }
    for (int j = 0; j < m; j++) P[(size_t)j * n + k] = q[j];
  }
  return ns;
}

/* Weighted inner product sum_k w_k a_k b_k (eq 9). */
static double wdot(int n, const double *w, const double *a, const double *b) {
  double s = 0.0;
  for (int k = 0; k < n; k++) s += w[k] * a[k] * b[k];
  return s;
}

/* Modified Gram-Schmidt of the columns of P in <., .>_w (eq 19), each
 * column projected twice ("twice is enough": the kept columns stay
 * orthonormal to round-off however close to dependent they are), with the
 * relative drop test (eq 20). pe[j] receives p_j(x_e) / |p_j|. */
static void gram_schmidt(int n, int m, const double *w, double tol, double *P, double *pe,
                         mpgm_imls_info *out) {
  out->rank = 0;
  out->kept = 0u;
  out->min_kept = 1.0;
  out->max_dropped = 0.0;
  for (int j = 0; j < m; j++) {
    double *v = P + (size_t)j * n;
    double ve = j == 0 ? 1.0 : 0.0; /* q_j(x_e) */
    const double nq = wdot(n, w, v, v);
    for (int pass = 0; pass < 2; pass++)
      for (int i = 0; i < j; i++) {
        if (!(out->kept & (1u << i))) continue;
        const double *pi = P + (size_t)i * n;
        const double r = wdot(n, w, v, pi);
        for (int k = 0; k < n; k++) v[k] -= r * pi[k];
        ve -= r * pe[i];
      }
    const double np = wdot(n, w, v, v);
    /* nq = 0 (a monomial vanishing on all data) gives 0 > 0: dropped */
    const double ratio = nq > 0.0 ? sqrt(np / nq) : 0.0;
    if (np > tol * tol * nq) {
      const double s = 1.0 / sqrt(np);
      for (int k = 0; k < n; k++) v[k] *= s;
      pe[j] = ve * s;
      out->kept |= 1u << j;
      out->rank++;
      out->min_kept = fmin(out->min_kept, ratio);
    } else {
      pe[j] = 0.0;
      out->max_dropped = fmax(out->max_dropped, ratio);
    }
  }
}

/* Zero phi, report rank 0, return code. */
static int fail(int n, double *phi, mpgm_imls_info *info, int code) {
  if (phi && n > 0) memset(phi, 0, sizeof(double) * (size_t)n);
  if (info) info->rank = 0;
  return code;
}

int mpgm_imls_coeffs(const mpgm_imls_params *p, const double *x_eval, int n, const double *xdata,
                     double *phi, mpgm_imls_info *info, double *work) {
  mpgm_imls_info loc = {0};
  if (info) *info = loc;
  if (!p || !x_eval || n < 0 || (n > 0 && (!xdata || !phi)))
    return fail(n, phi, info, MPGM_ERR_INPUT);
  if ((p->dim != 1 && p->dim != 2) || (p->order != 1 && p->order != 2) || !(p->h > 0.0) ||
      !isfinite(p->h) || !(p->tol_rel >= 0.0 && p->tol_rel < 1.0) || !isfinite(x_eval[0]) ||
      (p->dim == 2 && !isfinite(x_eval[1])))
    return fail(n, phi, info, MPGM_ERR_INPUT);
  double stack[MPGM_IMLS_MAXBASIS * MPGM_IMLS_STACK_NDATA];
  double *P = work;
  if (!P) {
    if (n > MPGM_IMLS_STACK_NDATA) return fail(n, phi, info, MPGM_ERR_INPUT);
    P = stack;
  }
  const int m = nbasis(p->dim, p->order);
  const double tol = p->tol_rel > 0.0 ? p->tol_rel : MPGM_IMLS_TOL_REL;
  loc.nbasis = m;
  loc.nsupport = n > 0 ? fill(p, x_eval, n, xdata, m, phi, P) : 0;
  if (loc.nsupport == 0) {
    if (info) *info = loc;
    return fail(n, phi, info, MPGM_ERR_SHAPE);
  }

  double pe[MPGM_IMLS_MAXBASIS];
  gram_schmidt(n, m, phi, tol, P, pe, &loc);
  /* eq 17 with normalised p_j: phi_k = w_k sum_j p_j(x_e) p_j(x_k) */
  for (int k = 0; k < n; k++) {
    if (phi[k] == 0.0) continue;
    double s = 0.0;
    for (int j = 0; j < m; j++) s += pe[j] * P[(size_t)j * n + k];
    phi[k] *= s;
  }
  if (info) *info = loc;
  return 0;
}
