/* support_csc.h -- for the tangent tests (test_assembly.c in 2-D,
 * test_assembly3.c in 3-D): a CSC matrix checked and spread into a dense
 * one. */
#ifndef MPGM_SUPPORT_CSC_H
#define MPGM_SUPPORT_CSC_H

#include <string.h>

#include "mpgm_core_impl.h"
#include "mpgm_test.h"

/* The CSC as a dense ndof x ndof matrix (row major) and a mask of its
 * pattern; checks the structure. Returns 0 when the structure is valid. */
static inline int csc_dense(const mpgm_csc *A, double *Kd, unsigned char *in, const char *name) {
  const int n = A->n;
  int ok = A->colptr[0] == 0 && A->colptr[n] == A->nnz;
  int sorted = 1;
  for (int j = 0; j < n && ok; j++) {
    ok &= A->colptr[j + 1] >= A->colptr[j];
    for (int t = A->colptr[j]; t < A->colptr[j + 1] && ok; t++) {
      const int i = A->rowind[t];
      ok &= i >= 0 && i < n;
      if (t > A->colptr[j]) sorted &= i > A->rowind[t - 1];
    }
  }
  mpgm_test(ok, "%s: CSC column pointers and row indices in range", name);
  mpgm_test(sorted, "%s: CSC rows sorted and unique in every column", name);
  if (!ok || !sorted) return 1;
  memset(Kd, 0, sizeof(double) * (size_t)n * n);
  memset(in, 0, (size_t)n * n);
  for (int j = 0; j < n; j++)
    for (int t = A->colptr[j]; t < A->colptr[j + 1]; t++) {
      Kd[(size_t)A->rowind[t] * n + j] = A->val[t];
      in[(size_t)A->rowind[t] * n + j] = 1;
    }
  return 0;
}

#endif
