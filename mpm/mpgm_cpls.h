/* mpgm_cpls.h -- CPLS nodal velocities for the MPM front end (cpls.c):
 * improved moving least squares from the particles' centres and domain
 * corners (Tran et al. 2019, eqs 25, 31, 41). */
#ifndef MPGM_CPLS_H
#define MPGM_CPLS_H

#include "mpgm_data.h"
#include "mpgm_grid.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Workspace (data points binned by cell, gathers), created on first use. */
typedef struct mpgm_cpls mpgm_cpls;
void mpgm_cpls_destroy(mpgm_cpls *c);

/** The velocity of each of the nnode nodes of the step (lglob: its grid
 *  node) reconstructed by IMLS of `order` (1 or 2) over the cell size from
 *  the material points' centres and domain corners, written into v
 *  (MPGM_DIM per node); a node no data point reaches keeps its entry of v
 *  (the caller's projection), counted in *kept. Returns 0 or an
 *  allocation error. */
int mpgm_cpls_velocities(mpgm_ctx *ctx, mpgm_cpls **c, const mpgm_grid *g, const mpgm_points *P,
                         int order, int nnode, const int *lglob, double *v, long *kept);

#ifdef __cplusplus
}
#endif
#endif
