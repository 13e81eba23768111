/* mpgm_mpm.h -- the grid-reset front end: the implicit material point method
 * of Algorithm 1 in Iaconeta et al. (2017).
 *
 * A structured background grid of Q4 cells (or two T3 per square) covers
 * mesh.domain with cells of size mesh.h. Particles are created at the Gauss
 * points (mesh.ppc) of the grid cells that lie inside a body. Every step the
 * grid is reset to its undeformed position; only cells holding particles
 * are active, only nodes of active cells with non-zero mass carry degrees of
 * freedom; mass, momentum and inertia are projected to those nodes (eqs
 * 38-41); the core solves the step on the grid, which moves with the Newton
 * iterate; the particles are then updated (eqs 46-49) and the grid is
 * forgotten. */
#ifndef MPGM_MPM_H
#define MPGM_MPM_H

#include "mpgm_core.h"

#ifdef __cplusplus
extern "C" {
#endif

extern const mpgm_frontend_type mpgm_frontend_mpm;

#ifdef __cplusplus
}
#endif
#endif
