/* shapefn_list.c -- the compile-time list of shape-function kinds and the
 * generic wrappers of the family.
 * Adding a kind: write its .c, add one line to MPGM_SHAPEFN_LIST. */
#include "mpgm_shapefn.h"

#include <string.h>

/* The kinds of the build's dimension: the meshfree ones (mls, lme) and
 * CPLS (its least squares are imls.c's, written for plane strain) are
 * 2-D only for now. */
#if MPGM_DIM == 2
#define MPGM_SHAPEFN_LIST(X) \
  X(mpgm_shapefn_fe) X(mpgm_shapefn_mls) X(mpgm_shapefn_lme) X(mpgm_shapefn_ugimp) \
  X(mpgm_shapefn_cpdi) X(mpgm_shapefn_cpls)
#else
#define MPGM_SHAPEFN_LIST(X) X(mpgm_shapefn_fe) X(mpgm_shapefn_ugimp) X(mpgm_shapefn_cpdi)
#endif

#define MPGM_DECLARE(t) extern const mpgm_shapefn_type t;
MPGM_SHAPEFN_LIST(MPGM_DECLARE)
#undef MPGM_DECLARE

#define MPGM_ADDR(t) &t,
static const mpgm_shapefn_type *const all_types[] = {
    MPGM_SHAPEFN_LIST(MPGM_ADDR) NULL};
#undef MPGM_ADDR

const mpgm_shapefn_type *const *mpgm_shapefn_types(void) { return all_types; }

const mpgm_shapefn_type *mpgm_shapefn_type_find(const char *name) {
  for (int i = 0; all_types[i]; i++)
    if (strcmp(all_types[i]->name, name) == 0) return all_types[i];
  return NULL;
}

int mpgm_shape_support_radius(const mpgm_shapefn_type *t, const mpgm_shape_params *par,
                              double *radius) {
  *radius = 0.0;
  if (!t || !t->support_radius) return MPGM_ERR_UNSUPPORTED;
  return t->support_radius(par, radius);
}

const char *mpgm_shape_reason_str(int reason) {
  switch (reason) {
  case MPGM_SHAPE_OK: return "ok";
  case MPGM_SHAPE_BAD_INPUT: return "bad query (node count, missing length scale or cell)";
  case MPGM_SHAPE_INVERTED: return "inverted cell or particle domain (det J <= 0)";
  case MPGM_SHAPE_TOO_FEW: return "too few nodes in the support for the basis";
  case MPGM_SHAPE_ILL_COND: return "moment matrix or Hessian singular or ill-conditioned";
  case MPGM_SHAPE_OUTSIDE_HULL: return "point outside the convex hull of its cloud";
  case MPGM_SHAPE_NOT_CONVERGED: return "Newton on the LME multiplier did not converge";
  case MPGM_SHAPE_OFF_GRID:
    return "uGIMP, CPDI: the point's square (domain) reaches nodes the grid does not have (widen "
           "mesh.domain by a cell; uGIMP: or use mesh.layout \"centres\")";
  default: return "unknown shape-function failure";
  }
}
