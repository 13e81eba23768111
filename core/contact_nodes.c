/* contact_nodes.c -- the active set of unilateral contact at nodes (and,
 * through mpgm_cpoints_update, at surface points) after a Newton solve. */
#include <stdlib.h>

#include "mpgm_core_impl.h"

#if MPGM_DIM != 2
#error "core/contact_nodes.c is written for plane strain only (MPGM_DIM = 2)"
#endif

/* Unilateral contact (the contact codes of the nodes): a contact node is
 * held (no slip) while the plane pushes on the body, released where it
 * would pull, and held again where a released node moves into the plane.
 * A node changes state at most once per step (pb->ls->cflip), so the active set
 * cannot chatter and settles in a few solves; the front end starts each
 * step from the set the last one ended with. Contact at surface points
 * follows the same rules (mpgm_cpoints_update). Returns a mask of what
 * changed: 1 contact nodes, 2 surface points. */
int mpgm_contact_update(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  mpgm_nodes *nd = &pb->nodes;
  double *r = ls->react;
  int changed = pb->fx.contact_points && mpgm_cpoints_update(pb) ? 2 : 0;
  if (!pb->fx.contact) return changed;
  mpgm_reactions(pb, r);
  for (int i = 0; i < nd->n; i++) {
    const int code = nd->contact[i];
    if (!code || ls->cflip[i]) continue;
    const int axis = abs(code) - 1, side = code > 0 ? 1 : -1;
    const int held = nd->fix[MPGM_DIM * i + axis];
    if ((held && side * r[MPGM_DIM * i + axis] < 0.0) ||
        (!held && side * nd->du[MPGM_DIM * i + axis] < 0.0)) {
      /* 2-D only: both components (no slip) written out */
      nd->fix[MPGM_DIM * i] = nd->fix[MPGM_DIM * i + 1] = (unsigned char)!held;
      nd->ubar[MPGM_DIM * i] = nd->ubar[MPGM_DIM * i + 1] = 0.0;
      ls->cflip[i] = 1;
      changed |= 1;
    }
  }
  return changed;
}

