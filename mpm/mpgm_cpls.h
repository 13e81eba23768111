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

/** Largest sum_k |phi_k| a node's reconstruction may have (docs/theory.md
 *  section 20.3): interior nodes have 1.0-1.5; nodes a cell outside a body
 *  or inside a hole, reached by data from one side, up to 20 with the
 *  quadratic basis, and their extrapolated velocities break the run (the
 *  vortex at h = 0.0625 stops at t = 0.94 s with det F <= 0 at its outer
 *  edge). 2 gave the smallest errors of 2, 3 and 5 there. */
#define MPGM_CPLS_MAX_GAIN 2.0

/** Workspace (data points binned by cell, gathers), created on first use. */
typedef struct mpgm_cpls mpgm_cpls;
void mpgm_cpls_destroy(mpgm_cpls *c);

/** The velocity of each of the nnode nodes of the step (lglob: its grid
 *  node) reconstructed by IMLS of `order` (1 or 2) over the cell size from
 *  the material points' centres and domain corners, written into v
 *  (MPGM_DIM per node). A node whose quadratic coefficients exceed
 *  MPGM_CPLS_MAX_GAIN takes the linear basis (counted in *lower); a node
 *  whose linear ones do too, or that no data point reaches, keeps its entry
 *  of v (the caller's projection), counted in *kept. Returns 0 or an
 *  allocation error. */
int mpgm_cpls_velocities(mpgm_ctx *ctx, mpgm_cpls **c, const mpgm_grid *g, const mpgm_points *P,
                         int order, int nnode, const int *lglob, double *v, long *lower,
                         long *kept);

#ifdef __cplusplus
}
#endif
#endif
