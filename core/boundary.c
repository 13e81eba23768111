/* boundary.c -- geometric node selection of scene boundaries. */
#include <math.h>

#include "mpgm_scene.h"

/* A plane x, y or z = value (the selector is the axis), or a box. */
int mpgm_boundary_selects(const mpgm_scene_boundary *bc, const double X[MPGM_DIM]) {
  const double t = bc->tol;
  if (bc->select != MPGM_SELECT_BOX) return fabs(X[bc->select] - bc->value) <= t;
  for (int d = 0; d < MPGM_DIM; d++)
    if (!(X[d] >= bc->min[d] - t && X[d] <= bc->max[d] + t)) return 0;
  return 1;
}
