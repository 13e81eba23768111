/* mpgm_tensor.h -- small dense MPGM_DIM x MPGM_DIM
 * matrices, row major (F, dF, H and their inverses). In 2-D each is the
 * expression the plane-strain kernels wrote out by hand, in the same
 * floating-point order, so that moving a kernel onto them changes no bit;
 * the 3-D forms are the cofactor ones. */
#ifndef MPGM_TENSOR_H
#define MPGM_TENSOR_H

#include "mpgm_base.h"

/** det a. */
static inline double mpgm_det(const double *a) {
#if MPGM_DIM == 2
  return a[0] * a[3] - a[1] * a[2];
#else
  return a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) +
         a[2] * (a[3] * a[7] - a[4] * a[6]);
#endif
}

/** ia = a^-1, J = det a (given, not checked). */
static inline void mpgm_inv(const double *a, double J, double *ia) {
#if MPGM_DIM == 2
  ia[0] = a[3] / J; ia[1] = -a[1] / J; ia[2] = -a[2] / J; ia[3] = a[0] / J;
#else
  ia[0] = (a[4] * a[8] - a[5] * a[7]) / J;
  ia[1] = (a[2] * a[7] - a[1] * a[8]) / J;
  ia[2] = (a[1] * a[5] - a[2] * a[4]) / J;
  ia[3] = (a[5] * a[6] - a[3] * a[8]) / J;
  ia[4] = (a[0] * a[8] - a[2] * a[6]) / J;
  ia[5] = (a[2] * a[3] - a[0] * a[5]) / J;
  ia[6] = (a[3] * a[7] - a[4] * a[6]) / J;
  ia[7] = (a[1] * a[6] - a[0] * a[7]) / J;
  ia[8] = (a[0] * a[4] - a[1] * a[3]) / J;
#endif
}

/** c = a b (c must not alias a or b). */
static inline void mpgm_mul(const double *a, const double *b, double *c) {
  for (int i = 0; i < MPGM_DIM; i++)
    for (int j = 0; j < MPGM_DIM; j++) {
      double s = a[MPGM_DIM * i] * b[j];
      for (int k = 1; k < MPGM_DIM; k++) s += a[MPGM_DIM * i + k] * b[MPGM_DIM * k + j];
      c[MPGM_DIM * i + j] = s;
    }
}

/** s : sym(h) for a stress s in the Voigt layout (its first MPGM_NVOIGT
 *  components; plane strain's zz does no in-plane work): the diagonal
 *  terms, then each shear times h_ij + h_ji. */
static inline double mpgm_stress_work(const double *s, const double *h) {
  double w = s[0] * h[0];
  for (int k = 1; k < MPGM_NVOIGT; k++) {
    const int i = mpgm_voigt_pair[k][0], j = mpgm_voigt_pair[k][1];
    w += s[k] * (i == j ? h[MPGM_DIM * i + i] : h[MPGM_DIM * i + j] + h[MPGM_DIM * j + i]);
  }
  return w;
}

#endif
