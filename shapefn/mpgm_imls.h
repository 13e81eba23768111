/* mpgm_imls.h -- improved moving least squares (IMLS) reconstruction
 * (Tran, Solowski, Berzins & Guilkey 2019, "CPLS", eqs 8-20; seed 004).
 *
 * Given data points x_k (k = 0 .. n-1) and an evaluation point x_e, return
 * the coefficients phi_k(x_e) of the weighted least-squares fit, so that
 *
 *   f(x_e) ~ sum_k phi_k f_k        for any data values f_k
 *
 * (the reconstruction is linear in the data; eqs 16-17). CPLS uses it to
 * map velocities from particle centres and particle-domain corners to a
 * grid node x_I (004 eqs 25, 31, 41): x_e = x_I, one call per node, and
 * the same phi for every velocity component.
 *
 * Method (docs/theory.md, "Improved moving least squares"):
 *   - weight w_k = N((x_k - x_e) / h) N((y_k - y_e) / h), N the cubic
 *     B-spline of eq 10 (support |r| < 2): the data points that count lie
 *     in the open square |x_k - x_e|_inf < 2 h;
 *   - monomials centred at x_e and scaled by h, u = (x - x_e) / h,
 *     v = (y - y_e) / h, in the order
 *       1-D: 1, u [, u^2]       2-D: 1, u, v [, u^2, u v, v^2];
 *   - Gram-Schmidt in the weighted inner product <f, g> = sum_k w_k f_k g_k
 *     (eqs 9, 19), modified, with one re-orthogonalisation pass; monomial j
 *     is dropped (eq 20) when what is left of it after the projections is
 *     small relative to the monomial itself:
 *       |p_j| <= tol_rel |q_j|,   |f| = <f, f>^(1/2);
 *   - phi_k = w_k sum_{j kept} p_j(x_e) p_j(x_k) / <p_j, p_j>   (eq 17).
 *
 * Properties: the constant is never dropped (when some weight is
 * positive), so sum_k phi_k = 1; every polynomial in the span of the kept
 * directions is reproduced to round-off (all linear / quadratic
 * polynomials when nothing is dropped). Degenerate data keep what they
 * determine:
 *   - one data point (or all coincident): rank 1, phi = w_k / sum w
 *     (the weighted mean);
 *   - 1-D quadratic with two distinct points: u^2 dropped, rank 2, phi are
 *     the weights of the straight line through the two points;
 *   - 2-D data on one straight line: the second of u, v in the order above
 *     that the line makes affine in the first (v for a line that is not
 *     vertical, u for a vertical one) is dropped, and with it the quadratic
 *     monomials that are not new along the line: rank 2 (linear) or 3
 *     (quadratic). The fit is exact for data that are linear (quadratic)
 *     along the line; off the line, x_e is read at the point of the line
 *     with the same kept coordinate (same x for a non-vertical line);
 *   - nearly degenerate data: a direction survives only when the data
 *     spread along it by more than tol_rel times its extent |q_j| (for the
 *     normal of a thin strip, its width over the distance of x_e from it).
 *     A kept direction amplifies the data by ~1/ratio (|phi| below ~1 /
 *     tol_rel) and loses ~log10(1/ratio) digits; a dropped one loses the
 *     reproduction of that direction only. Nothing is ever NaN.
 *
 * The library never prints; no allocation (workspace from the caller, or
 * on the stack for small n).
 */
#ifndef MPGM_IMLS_H
#define MPGM_IMLS_H

#include <stddef.h>

#include "mpgm_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest number of monomials (2-D quadratic). */
#define MPGM_IMLS_MAXBASIS 6
/** Up to this many data points, work may be NULL (a stack array of
 *  MPGM_IMLS_MAXBASIS x this many doubles, 12 kB, is used). */
#define MPGM_IMLS_STACK_NDATA 256
/** Default of mpgm_imls_params.tol_rel (see there). */
#define MPGM_IMLS_TOL_REL 1e-6

/** Parameters of a reconstruction. */
typedef struct mpgm_imls_params {
  int dim;        /**< 1 or 2: coordinates per point                          */
  int order;      /**< 1 linear, 2 quadratic basis                            */
  double h;       /**< cell size l_e [m] (> 0): the B-spline weight of eq 10
                       has support 2 h on each side of x_e, per axis         */
  double tol_rel; /**< relative Gram-Schmidt threshold in [0, 1): monomial j
                       is dropped when |p_j| <= tol_rel |q_j| (norm ratio,
                       the sine of the angle between q_j and the kept span).
                       0 means MPGM_IMLS_TOL_REL = 1e-6. Why: after the
                       two Gram-Schmidt passes an exactly dependent
                       monomial leaves a ratio at round-off (<= 2e-16 in
                       test_imls), while data rounded far from the origin
                       leave ~1e-12 (an exact zero test keeps those, and
                       phi reaches 1e12); 1e-6 sits well above both. A kept
                       direction with ratio s gives |phi| of order 1 / s (a
                       thin strip read 1/s of its width away) and so loses
                       log10(1/s) digits of |f|: at most 6, fields in the
                       span stay exact to ~1e-10. A direction is dropped
                       only when the data spread along it by less than a
                       millionth of its extent: geometrically degenerate
                       for any MPM cloud. A larger value (1e-3) caps |phi|
                       near 1 / tol_rel where data noise must not be
                       amplified, dropping thin clouds' directions sooner.  */
} mpgm_imls_params;

/** Optional detail of one reconstruction (filled on success and failure). */
typedef struct mpgm_imls_info {
  int nbasis;         /**< monomials tried: dim + 1 (linear), 3 or 6 (quad.) */
  int rank;           /**< directions kept, 1 .. nbasis; 0 on failure        */
  unsigned kept;      /**< bit j set: monomial j kept (order in the header) */
  int nsupport;       /**< data points with positive weight                 */
  double min_kept;    /**< smallest ratio |p_j| / |q_j| of a kept direction  */
  double max_dropped; /**< largest ratio of a dropped direction; 0 if none   */
} mpgm_imls_info;

/** Doubles of workspace mpgm_imls_coeffs needs for n data points. */
static inline size_t mpgm_imls_work_len(int n) {
  return n > 0 ? (size_t)MPGM_IMLS_MAXBASIS * (size_t)n : 0;
}

/** IMLS coefficients phi_k(x_e) of n data points (eqs 9-20).
 *  p       parameters (borrowed)
 *  x_eval  evaluation point, dim values [m]
 *  n       number of data points (>= 0)
 *  xdata   their coordinates, dim per point [m]; a point with a non-finite
 *          coordinate gets weight 0 (ignored), as does one outside the
 *          square |x_k - x_e|_inf < 2 h
 *  phi     out, n values: f(x_e) ~ sum_k phi_k f_k; 0 where w_k = 0
 *  info    optional out (may be NULL): rank, kept directions, ratios
 *  work    mpgm_imls_work_len(n) doubles, or NULL when
 *          n <= MPGM_IMLS_STACK_NDATA
 *  Returns 0; MPGM_ERR_SHAPE (recoverable) when no data point has positive
 *  weight (the only way for no direction to survive: the constant always
 *  does otherwise); MPGM_ERR_INPUT for dim or order not 1 or 2, h not
 *  positive and finite, tol_rel outside [0, 1), a non-finite x_eval, n < 0,
 *  NULL arrays, or work NULL with n > MPGM_IMLS_STACK_NDATA. On any error
 *  phi is zeroed (when it is not NULL) and info->rank = 0: never NaN. */
int mpgm_imls_coeffs(const mpgm_imls_params *p, const double *x_eval, int n, const double *xdata,
                     double *phi, mpgm_imls_info *info, double *work);

/** The 1-D cubic B-spline weight of eq 10 in r = (x - x_e) / h:
 *  2/3 - r^2 + |r|^3 / 2 (|r| <= 1), (2 - |r|)^3 / 6 (1 <= |r| <= 2), 0
 *  beyond (and for NaN). C2, support |r| < 2, integral 1. */
double mpgm_imls_bspline(double r);

#ifdef __cplusplus
}
#endif
#endif
