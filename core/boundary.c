/* boundary.c -- geometric node selection of scene boundaries. */
#include <math.h>

#include "mpgm_scene.h"

#if MPGM_DIM != 2
#error "core/boundary.c is written for plane strain only (MPGM_DIM = 2)"
#endif

/* 2-D only: the selectors x = value, y = value and a box, in x and y. */
int mpgm_boundary_selects(const mpgm_scene_boundary *bc, const double X[MPGM_DIM]) {
  const double x = X[0], y = X[1], t = bc->tol;
  if (bc->select == MPGM_SELECT_X) return fabs(x - bc->value) <= t;
  if (bc->select == MPGM_SELECT_Y) return fabs(y - bc->value) <= t;
  return x >= bc->min[0] - t && x <= bc->max[0] + t && y >= bc->min[1] - t && y <= bc->max[1] + t;
}
