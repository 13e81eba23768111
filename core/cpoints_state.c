/* cpoints_state.c -- which surface points of contact at points the front
 * end can serve this step (mpgm_frontend.h): bookkeeping without a
 * dimension of its own, so that the front ends and the light-node rule
 * call it in both builds (a 3-D scene has no surface points yet; the
 * springs themselves are contact_points.c's, plane strain). */
#include <string.h>

#include "mpgm_core_impl.h"

void mpgm_cpoints_enforce_all(mpgm_cpoints *cp) { memset(cp->off, 0, (size_t)cp->n); }

void mpgm_cpoints_unenforce(mpgm_cpoints *cp, int i) {
  cp->unenforced += !cp->off[i];
  cp->off[i] = 1;
}

int mpgm_cpoints_unenforced(const mpgm_cpoints *cp, int i) { return cp->off[i]; }
