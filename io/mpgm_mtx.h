/* mpgm_mtx.h -- Matrix Market files of the linear systems (output.matrices,
 * `mpgm bench-solvers`): a square sparse matrix in coordinate format and a
 * right-hand side in array format, 1-based indices, values with 17
 * significant digits (they read back to the same doubles).
 *
 * Format (https://math.nist.gov/MatrixMarket/formats.html):
 *   %%MatrixMarket matrix coordinate real general|symmetric
 *   % comments
 *   n n nnz
 *   i j value          (nnz lines; symmetric: the lower triangle, i >= j)
 *
 *   %%MatrixMarket matrix array real general
 *   n 1
 *   value              (n lines)
 */
#ifndef MPGM_MTX_H
#define MPGM_MTX_H

#include "mpgm_base.h"
#include "mpgm_solver.h"

#ifdef __cplusplus
extern "C" {
#endif

/** 1 when A's pattern and values are symmetric to the last bit (every
 *  stored entry (i, j) has a stored (j, i) of the same value), else 0.
 *  Needs sorted rows in each column (as mpgm_csc has). */
int mpgm_csc_is_symmetric(const mpgm_csc *A);

/** Write A (full pattern, stored entries including explicit zeros) to
 *  path. "symmetric" when A->symmetric is set and the pattern is
 *  symmetric, or A is symmetric to the last bit: the upper triangle is
 *  written (the one the SPD backends read; the core's symmetric tangents
 *  may differ between the triangles in the last bits), as the lower
 *  triangle the format stores. Otherwise "general". comment (may be NULL)
 *  goes on a "% " line. Written to path.tmp and renamed. Errors:
 *  MPGM_ERR_IO. */
int mpgm_mtx_write_csc(mpgm_ctx *ctx, const char *path, const mpgm_csc *A, const char *comment);

/** Write the vector b (n entries) to path as an n x 1 array. Errors:
 *  MPGM_ERR_IO. */
int mpgm_mtx_write_vec(mpgm_ctx *ctx, const char *path, const double *b, int n,
                       const char *comment);

/** Read a square real (or integer) coordinate matrix, general or
 *  symmetric, into *A: arrays allocated here (free with
 *  mpgm_mtx_free_csc), full pattern (a symmetric file is mirrored), rows
 *  sorted in each column, duplicate entries summed, A->symmetric set when
 *  mpgm_csc_is_symmetric. Errors: MPGM_ERR_IO (cannot read the file),
 *  MPGM_ERR_NOMEM, MPGM_ERR_INPUT with "FILE: line L: expected ..., found
 *  ..." (bad header, size line, entry, index out of range, too few or too
 *  many entries, a non-finite value, an entry above the diagonal of a
 *  symmetric file, a matrix that is not square). *A is zeroed on error. */
int mpgm_mtx_read_csc(mpgm_ctx *ctx, const char *path, mpgm_csc *A);

/** Read an n x 1 real (or integer) array into *b (allocated here, free
 *  with free()) and its length into *n. Errors as mpgm_mtx_read_csc. */
int mpgm_mtx_read_vec(mpgm_ctx *ctx, const char *path, double **b, int *n);

/** Free the arrays of a matrix read by mpgm_mtx_read_csc and zero it
 *  (accepts NULL and a zeroed matrix). */
void mpgm_mtx_free_csc(mpgm_csc *A);

#ifdef __cplusplus
}
#endif
#endif
