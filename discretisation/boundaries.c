/* boundaries.c -- the scene's boundaries applied to persistent nodes. */
#include "mpgm_discretisation.h"

int mpgm_nodes_apply_boundaries(mpgm_ctx *ctx, const mpgm_scene *s, mpgm_nodes *nd) {
  for (int i = 0; i < s->nbc; i++) {
    const mpgm_scene_boundary *bc = &s->bcs[i];
    /* contact at points acts on the bodies' surface points, not nodes */
    if (mpgm_bc_at_points(bc)) continue;
    int hits = 0;
    for (int k = 0; k < nd->n; k++) {
      if (!mpgm_boundary_selects(bc, nd->X + MPGM_DIM * k)) continue;
      hits++;
      for (int d = 0; d < MPGM_DIM; d++)
        if (bc->fix[d]) {
          nd->fix[MPGM_DIM * k + d] = 1;
          nd->ubar[MPGM_DIM * k + d] = bc->displacement[d];
        }
    }
    MPGM_CHECK(ctx, hits > 0, MPGM_ERR_INPUT,
               "%s: boundaries.%d.%s (\"%s\"): expected a selector that picks nodes, found none "
               "within tol = %g of it", s->file, i,
               mpgm_select_key(bc->select),
               bc->name, bc->tol);
  }
  return 0;
}
