/* sym_eigen3.c -- eigen-decomposition of a symmetric 3x3 matrix by cyclic
 * Jacobi rotations (mohr_coulomb_impl.h). Used by the 3-D Mohr-Coulomb
 * update for b_e and the stresses; no allocation, no library calls beyond
 * sqrt, so it may run per point and per Newton iterate.
 *
 * Each rotation zeroes one off-diagonal entry a_pq; the diagonal is updated
 * with the rotation's tangent t (a_pp -= t a_pq, a_qq += t a_pq), which
 * keeps the small eigenvalues of a positive definite matrix to relative
 * accuracy (the logarithms of b_e need that). A rotation is skipped once
 * |a_pq| is below half an ulp of sqrt(|a_pp a_qq|): further rotations
 * would not change the diagonal in floating point.
 */
#include <float.h>
#include <math.h>

#include "mohr_coulomb_impl.h"

/* Row-major index of (i, j) in a 3x3 matrix. */
#define IX(i, j) (3 * (i) + (j))

/* One rotation in the (p, q) plane: a_pq -> 0, V <- V G. */
static void rotate(double A[9], double V[9], int p, int q) {
  const double apq = A[IX(p, q)];
  const double theta = (A[IX(q, q)] - A[IX(p, p)]) / (2.0 * apq);
  /* the smaller root of t^2 + 2 theta t - 1 = 0 (rotation angle <= pi/4) */
  const double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
  const double c = 1.0 / sqrt(t * t + 1.0), s = t * c, tau = s / (1.0 + c);
  A[IX(p, p)] -= t * apq;
  A[IX(q, q)] += t * apq;
  A[IX(p, q)] = A[IX(q, p)] = 0.0;
  const int r = 3 - p - q; /* the third index */
  const double arp = A[IX(r, p)], arq = A[IX(r, q)];
  A[IX(r, p)] = A[IX(p, r)] = arp - s * (arq + tau * arp);
  A[IX(r, q)] = A[IX(q, r)] = arq + s * (arp - tau * arq);
  for (int k = 0; k < 3; k++) {
    const double vp = V[IX(k, p)], vq = V[IX(k, q)];
    V[IX(k, p)] = vp - s * (vq + tau * vp);
    V[IX(k, q)] = vq + s * (vp - tau * vq);
  }
}

int mpgm_sym3_eigen(const double S[6], double l[3], double V[9]) {
  double A[9] = {S[0], S[3], S[5], S[3], S[1], S[4], S[5], S[4], S[2]};
  for (int i = 0; i < 9; i++) {
    if (!isfinite(A[i])) return -1;
    V[i] = (i % 4 == 0) ? 1.0 : 0.0;
  }
  static const int pq[3][2] = {{0, 1}, {1, 2}, {0, 2}};
  int converged = 0;
  for (int sweep = 0; sweep < 32 && !converged; sweep++) {
    converged = 1;
    for (int k = 0; k < 3; k++) {
      const int p = pq[k][0], q = pq[k][1];
      const double apq = fabs(A[IX(p, q)]);
      if (apq == 0.0) continue;
      if (apq <= 0.5 * DBL_EPSILON * sqrt(fabs(A[IX(p, p)] * A[IX(q, q)]))) {
        A[IX(p, q)] = A[IX(q, p)] = 0.0;
        continue;
      }
      rotate(A, V, p, q);
      converged = 0;
    }
  }
  for (int i = 0; i < 3; i++) l[i] = A[IX(i, i)];
  return converged ? 0 : -1;
}
