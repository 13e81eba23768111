/* blocks.c -- the block form of a system for PETSc's algebraic multigrid
 * (pt_blocks.h). */
#include "pt_blocks.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

void pt_blocks_free(pt_blocks *B) {
  free(B->row);
  free(B->eq);
  free(B->coords);
  free(B->fixslot);
  *B = (pt_blocks){0};
}

/* Nodes with a free component become blocks, in node order. */
int pt_blocks_build(pt_blocks *B, const mpgm_dof_layout *L, int n, char *why, size_t len) {
  pt_blocks_free(B);
  const int bs = L->dim;
  int nb = 0;
  for (int v = 0; v < L->nnode; v++) {
    int any = 0;
    for (int c = 0; c < bs; c++) any |= L->dof[bs * v + c] >= 0;
    nb += any;
  }
  B->bs = bs;
  B->n = n;
  B->nf = bs * nb;
  B->row = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  B->eq = malloc(sizeof(int) * (size_t)(B->nf > 0 ? B->nf : 1));
  B->coords = malloc(sizeof(double) * (size_t)(B->nf > 0 ? B->nf : 1));
  B->fixslot = malloc(sizeof(PetscInt) * (size_t)(B->nf > 0 ? B->nf : 1));
  if (!B->row || !B->eq || !B->coords || !B->fixslot) {
    pt_blocks_free(B);
    snprintf(why, len, "no memory for the block form of %d equations", n);
    return MPGM_ERR_NOMEM;
  }
  for (int e = 0; e < n; e++) B->row[e] = -1;
  int b = 0, seen = 0;
  for (int v = 0; v < L->nnode; v++) {
    int any = 0;
    for (int c = 0; c < bs; c++) any |= L->dof[bs * v + c] >= 0;
    if (!any) continue;
    for (int c = 0; c < bs; c++) {
      const int e = L->dof[bs * v + c], r = bs * b + c;
      B->eq[r] = e;
      B->coords[r] = L->x[bs * v + c];
      if (e < 0) {
        B->nfix++;
        continue;
      }
      if (e >= n || B->row[e] >= 0) {
        snprintf(why, len, "the layout numbers equation %d (node %d) %s", e, v,
                 e >= n ? "beyond the matrix's order" : "twice");
        pt_blocks_free(B);
        return MPGM_ERR_INTERNAL;
      }
      B->row[e] = r;
      seen++;
    }
    b++;
  }
  if (seen != n) {
    snprintf(why, len, "the layout numbers %d of the matrix's %d equations", seen, n);
    pt_blocks_free(B);
    return MPGM_ERR_INTERNAL;
  }
  return 0;
}

/* Rows counted, started, then filled column by column of the block form
 * (so each row's columns come sorted). */
void pt_blocks_rows(pt_blocks *B, const mpgm_csc *A, PetscInt *ia, PetscInt *ja, int *map,
                    int *diag, PetscInt *fill) {
  const int nf = B->nf;
  for (int k = 0; k < A->nnz; k++) ia[B->row[A->rowind[k]] + 1]++;
  for (int r = 0; r < nf; r++)
    if (B->eq[r] < 0) ia[r + 1]++;
  for (int r = 0; r < nf; r++) ia[r + 1] += ia[r];
  for (int r = 0; r < nf; r++) fill[r] = ia[r];
  int f = 0;
  for (int jf = 0; jf < nf; jf++) {
    const int e = B->eq[jf];
    if (e < 0) {
      const PetscInt slot = fill[jf]++;
      ja[slot] = jf;
      B->fixslot[f++] = slot;
      continue;
    }
    diag[e] = -1;
    for (int k = A->colptr[e]; k < A->colptr[e + 1]; k++) {
      const PetscInt slot = fill[B->row[A->rowind[k]]]++;
      ja[slot] = jf;
      map[k] = (int)slot;
      if (A->rowind[k] == e) diag[e] = k;
    }
  }
}

double pt_blocks_scale(const mpgm_csc *A, const int *diag) {
  double s = 0.0;
  int m = 0;
  for (int e = 0; e < A->n; e++)
    if (diag[e] >= 0) {
      s += fabs(A->val[diag[e]]);
      m++;
    }
  return m > 0 && s > 0.0 ? s / m : 1.0;
}
