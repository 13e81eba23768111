/* pt_blocks.h -- the block form of a system for PETSc's algebraic
 * multigrid (blocks.c; used by petsc.c, the PETSc module). */
#ifndef MPGM_PT_BLOCKS_H
#define MPGM_PT_BLOCKS_H

#include <petscksp.h>

#include "mpgm_solver.h"

/* The core numbers only the free components of the nodes (mpgm_csc.layout:
 * -1 for a fixed one), so its matrices are not in blocks of a node's
 * components. The block form gives every node with a free component bs
 * consecutive rows, in node order, and each fixed component of such a node
 * a row and a column of its own, zero but for the diagonal (the way
 * PETSc's elasticity examples keep their Dirichlet rows): the matrix then
 * has block size bs, which GAMG aggregates by, and the nodes' positions
 * give its rigid-body near-null space. The fixed rows' right-hand side is
 * zero, so their unknowns are zero and the free ones are the system's. */
typedef struct pt_blocks {
  int bs;           /**< components per node (0: no block form)          */
  int n, nf;        /**< equations of the matrix, rows of the block form */
  int *row;         /**< n: equation -> its row in the block form        */
  int *eq;          /**< nf: row -> equation, -1 for a fixed component   */
  double *coords;   /**< nf: the row's node position, bs per block [m]   */
  int nfix;         /**< rows of fixed components                       */
  PetscInt *fixslot; /**< nfix: their diagonal's slot in the AIJ values   */
} pt_blocks;

/* The block form of the n equations of layout L. Returns 0, or
 * MPGM_ERR_INTERNAL with the reason in why (len bytes) when L does not
 * number exactly the equations 0 .. n-1 once each. */
int pt_blocks_build(pt_blocks *B, const mpgm_dof_layout *L, int n, char *why, size_t len);
void pt_blocks_free(pt_blocks *B);

/* The AIJ pattern of A's block form: ia (nf + 1), ja (A->nnz + nfix), the
 * AIJ slot of each of A's entries (map, A->nnz), A's diagonal entry of
 * each equation (diag, n; -1 if absent), the fixed rows' diagonal slots
 * (B->fixslot); fill (nf) is scratch. ia must be zero on entry. */
void pt_blocks_rows(pt_blocks *B, const mpgm_csc *A, PetscInt *ia, PetscInt *ja, int *map,
                    int *diag, PetscInt *fill);

/* The value of the fixed rows' diagonal: the mean |A_ii| of the free
 * equations (1 when there are none), so that these rows do not spread the
 * spectrum the preconditioner sees. */
double pt_blocks_scale(const mpgm_csc *A, const int *diag);

#endif
