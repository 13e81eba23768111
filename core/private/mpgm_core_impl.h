/* mpgm_core_impl.h -- private to core/: the pieces the step is made of
 * (Newton, contact at nodes). */
#ifndef MPGM_CORE_IMPL_H
#define MPGM_CORE_IMPL_H

#include "mpgm_core.h"

/** State of Newton's method on one step (newton.c). */
typedef struct mpgm_newton {
  int warm;        /**< started from the current increments (a re-solve) */
  int it;          /**< the current iterate: corrections made so far       */
  double fnorm;    /**< |f_ext| over the free equations                   */
  double ref;      /**< reference norm of the residual: max(|R_0|, fnorm) */
  double res;      /**< |R| at the current iterate                        */
  double res_prev; /**< |R| at the previous one                           */
  int factored;    /**< a factorisation for this pattern and fixity exists */
  int want_K;      /**< the last residual call assembled K too            */
} mpgm_newton;

/** Body force, predictor (du = 0, or dt v with time.predictor velocity;
 *  prescribed increments lifted into the first iteration) and reference
 *  norms; warm: keep the free increments (a re-solve). Resets pb->last. */
int mpgm_newton_init(mpgm_problem *pb, mpgm_newton *nt, int warm);
/** Constitutive update and R (and K when the next correction needs it) at
 *  the current increments; |R| into nt->res and pb->last. Errors:
 *  MPGM_ERR_NAN, the point update's. */
int mpgm_newton_residual(mpgm_problem *pb, mpgm_newton *nt);
/** *done = 1 when the iterate is converged (rtol, atol or dtol). Errors:
 *  MPGM_ERR_NOT_CONVERGED (max_iterations reached), MPGM_ERR_DIVERGED. */
int mpgm_newton_test(mpgm_problem *pb, const mpgm_newton *nt, int *done);
/** One correction: the observers see K delta = R; factorise (or reuse the
 *  factorisation, modified Newton), solve, du += delta. */
int mpgm_newton_iterate(mpgm_problem *pb, mpgm_newton *nt);

/** Active-set update of unilateral contact at the current increments
 *  (contact_nodes.c). Returns a mask of what changed: 1 contact nodes,
 *  2 surface points. */
int mpgm_contact_update(mpgm_problem *pb);

#endif
