/* mpgm_krylov.h -- restarted GMRES with a preconditioner given as a
 * function: the Krylov kernel of the backend `reuse` (the last
 * factorisation of a direct backend, for Newton-Krylov) and of the unit
 * tests' GMRES + ILU(0) (tests/unit/support_ilu_gmres.c).
 *
 * GMRES(m) (Saad & Schultz 1986) on A M^-1 y = b, x = M^-1 y (right
 * preconditioning: the residual GMRES minimises is the true one,
 * |b - A x|), modified Gram-Schmidt, Givens rotations, x_0 = 0. A cycle
 * ends after m Krylov vectors or when the updated residual reaches
 * tol |b|; the true residual is then computed, and the solve ends when
 * |b - A x| <= tol |b|, when the residual has stalled at round-off (a cycle
 * no longer halves it and the normwise backward error
 * |r| / (|A| |x| + |b|), infinity norms, is below 64 eps; only with
 * op->anorm > 0), or after max_iter iterations in all.
 */
#ifndef MPGM_KRYLOV_H
#define MPGM_KRYLOV_H

#include "mpgm_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The operator and the preconditioner. */
typedef struct mpgm_krylov_op {
  void *user;
  /** y = A x */
  void (*matvec)(void *user, const double *x, double *y);
  /** z = M^-1 v (z and v may alias); a non-zero return (an MPGM_ERR_
   *  code, recorded in ctx by the callee) ends the solve with it. */
  int (*precond)(void *user, mpgm_ctx *ctx, const double *v, double *z);
  double anorm; /**< |A| (infinity norm) for the round-off stop; 0: none */
} mpgm_krylov_op;

/** Workspace for systems of order n with m = min(restart, n) vectors per
 *  cycle. */
typedef struct mpgm_gmres_ws {
  int n, m;
  double *V, *H;        /**< Krylov basis (m + 1) x n, Hessenberg (m + 1) x m */
  double *cs, *sn, *g;  /**< Givens rotations and rotated residual (m + 1)    */
  double *y;            /**< least-squares solution (m + 1)                   */
  double *r, *w, *t;    /**< n-vectors: true residual, V y, M^-1 v            */
  double *bw, *xs;      /**< copy of b (b and x may alias), iterate           */
} mpgm_gmres_ws;

/** Allocate the workspace (previous arrays freed). Errors: MPGM_ERR_NOMEM. */
int mpgm_gmres_ws_alloc(mpgm_ctx *ctx, mpgm_gmres_ws *ws, int n, int restart);
/** Free the arrays (accepts a zeroed or freed workspace). */
void mpgm_gmres_ws_free(mpgm_gmres_ws *ws);
/** Bytes the workspace of order n and restart m takes. */
double mpgm_gmres_ws_bytes(int n, int m);

/** Outcome of mpgm_gmres. */
typedef struct mpgm_gmres_result {
  int iterations;  /**< Krylov iterations                                */
  double relres;   /**< |b - A x| / |b| of the last iterate (2-norms)     */
  int converged;   /**< 1: to tol or to round-off                         */
} mpgm_gmres_result;

/** x = A^-1 b (b and x may alias), x_0 = 0. Returns 0 (res says whether
 *  it converged; x holds the last iterate either way), or the
 *  preconditioner's error code. A residual that is not finite ends the
 *  solve unconverged (relres NaN). */
int mpgm_gmres(mpgm_gmres_ws *ws, mpgm_ctx *ctx, const mpgm_krylov_op *op, const double *b,
               double *x, double tol, int max_iter, mpgm_gmres_result *res);

#ifdef __cplusplus
}
#endif

#endif
