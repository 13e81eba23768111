/* mpgm_shapefn_impl.h -- private helpers shared by the meshfree kinds
 * (mls.c, lme.c): parameter defaults, failure reporting, small dense
 * symmetric algebra. Not installed for other folders. */
#ifndef MPGM_SHAPEFN_IMPL_H
#define MPGM_SHAPEFN_IMPL_H

#include "mpgm_shapefn.h"

/* Defaults of mpgm_shape_params (documented in mpgm_shapefn.h). */
#define MPGM_LME_GAMMA 1.8
#define MPGM_LME_TOL_SUPPORT 1e-6
#define MPGM_LME_TOL_NEWTON 1e-10
#define MPGM_LME_MAX_NEWTON 100
#define MPGM_LME_MAX_COND 1e12
#define MPGM_MLS_DILATION 2.0
#define MPGM_MLS_MAX_COND 1e10

/** The keys of cloud control (mpgm_shape_params.min_nodes, max_enlarge)
 *  in the key tables of the kinds over node clouds (mls.c, lme.c). */
#define MPGM_CLOUD_KEYS                                                                           \
  {.name = "min_nodes", .type = MPGM_KEY_INT, .offset = offsetof(mpgm_shape_params, min_nodes),  \
   .def = 0, .lo = 0, .hi = MPGM_SHAPE_MAXNODE, .unit = "-",                                     \
   .doc = "smallest cloud: the search radius grows x1.25 while it holds fewer nodes; 0: 6, or "  \
          "12 for order 2"},                                                                     \
  {.name = "max_enlarge", .type = MPGM_KEY_INT, .offset = offsetof(mpgm_shape_params, max_enlarge), \
   .def = 16, .lo = 0, .hi = MPGM_SHAPE_MAXNODE, .unit = "-",                                    \
   .doc = "cloud enlargements per point and step after failed evaluations before the step fails"}

/** The key max_cond (the same range for both kinds; its default 0 is the
 *  kind's own, MPGM_LME_MAX_COND or MPGM_MLS_MAX_COND). */
#define MPGM_MAX_COND_KEY                                                                         \
  {.name = "max_cond", .type = MPGM_KEY_REAL, .offset = offsetof(mpgm_shape_params, max_cond),   \
   .def = 0.0, .lo = 0.0, .hi = INFINITY, .unit = "-",                                           \
   .doc = "largest accepted condition number (LME Hessian, MLS moment matrix); 0: the kind's "   \
          "default"}

/** Zero N (n values) and dN (MPGM_DIM n), fill q->info, return code. Used on every
 *  failure path so that a caller never sees NaN or stale values. */
int mpgm_shape_fail(const mpgm_shape_query *q, double *N, double *dN, int code, int reason);

/** Fill q->info on success (reason OK). */
void mpgm_shape_ok(const mpgm_shape_query *q, int iterations, int nsupport, double cond,
                   double residual);

/** Check the parts of a meshfree query every kind needs: 1 <= n <=
 *  MPGM_SHAPE_MAXNODE, xn and par set. Returns 0 or the failure code (after
 *  mpgm_shape_fail when the output arrays can be zeroed safely). */
int mpgm_shape_check_cloud(const mpgm_shape_query *q, double *N, double *dN);

/** Value of a parameter or its default when it is zero (or negative). */
static inline double mpgm_shape_dflt(double v, double dflt) { return v > 0.0 ? v : dflt; }

/** Cholesky factor of the m x m symmetric positive definite A (row-major,
 *  lower triangle read), then its inverse into Ainv (full, row-major).
 *  Returns 0, or 1 if a pivot is not positive (singular / indefinite). */
int mpgm_spd_inverse(int m, const double *A, double *Ainv);

#endif
