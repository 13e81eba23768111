/* support_tensor.h -- DIM x DIM row-major tensors for the material tests
 * (test_materials.c, test_mohr_coulomb.c), in the build's MPGM_DIM: the
 * products and transposes may alias their inputs; det and the inverse are
 * the library's own (base/mpgm_tensor.h); symmetric tensors to and
 * from the Voigt part of the stress layout (mpgm_voigt_pair). */
#ifndef MPGM_SUPPORT_TENSOR_H
#define MPGM_SUPPORT_TENSOR_H

#include <string.h>

#include "mpgm_base.h"
#include "mpgm_tensor.h"

/* C = A B (C may be A or B). */
static inline void mul(const double A[MPGM_TENSOR], const double B[MPGM_TENSOR],
                       double C[MPGM_TENSOR]) {
  double T[MPGM_TENSOR];
  for (int i = 0; i < MPGM_DIM; i++)
    for (int j = 0; j < MPGM_DIM; j++) {
      double v = 0.0;
      for (int k = 0; k < MPGM_DIM; k++) v += A[MPGM_DIM * i + k] * B[MPGM_DIM * k + j];
      T[MPGM_DIM * i + j] = v;
    }
  memcpy(C, T, sizeof T);
}
/* T = A^T (T may be A). */
static inline void transpose(const double A[MPGM_TENSOR], double T[MPGM_TENSOR]) {
  double B[MPGM_TENSOR];
  for (int i = 0; i < MPGM_DIM; i++)
    for (int j = 0; j < MPGM_DIM; j++) B[MPGM_DIM * j + i] = A[MPGM_DIM * i + j];
  memcpy(T, B, sizeof B);
}
static inline void identity(double I[MPGM_TENSOR]) {
  for (int i = 0; i < MPGM_TENSOR; i++) I[i] = MPGM_DIAG(i) ? 1.0 : 0.0;
}
static inline double det(const double F[MPGM_TENSOR]) { return mpgm_det(F); }
static inline void inverse(const double F[MPGM_TENSOR], double inv[MPGM_TENSOR]) {
  mpgm_inv(F, mpgm_det(F), inv);
}
/* B = Q A Q^T */
static inline void rotate(const double Q[MPGM_TENSOR], const double A[MPGM_TENSOR],
                          double B[MPGM_TENSOR]) {
  double Qt[MPGM_TENSOR], T[MPGM_TENSOR];
  transpose(Q, Qt);
  mul(Q, A, T);
  mul(T, Qt, B);
}
/* The symmetric tensor S of the Voigt part of s (the stress layout's first
 * MPGM_NVOIGT components; plane strain's zz is not in it), and back. */
static inline void sym_of(const double *s, double S[MPGM_TENSOR]) {
  for (int k = 0; k < MPGM_NVOIGT; k++) {
    const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
    S[MPGM_DIM * a + b] = S[MPGM_DIM * b + a] = s[k];
  }
}
static inline void voigt_of(const double S[MPGM_TENSOR], double *v) {
  for (int k = 0; k < MPGM_NVOIGT; k++) v[k] = S[MPGM_DIM * mpgm_voigt_pair[k][0] + mpgm_voigt_pair[k][1]];
}

#endif
