/* mpgm_gmm.h -- the Galerkin Meshfree Method front end: the nodes and
 * points of UL-FEM (or of bodies filled on a grid), connected by node
 * clouds. */
#ifndef MPGM_GMM_H
#define MPGM_GMM_H

#include "mpgm_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** mpgm_frontend_gmm: the Galerkin Meshfree Method (gmm/gmm.c; Iaconeta et
 *  al. 2017, section 4.2): nodes, points, probes and boundaries as
 *  mpgm_frontend_fem (rectangle bodies), or, for scenes with disk or
 *  polygon bodies or obstacles, those of the grid fill (gmm_grid.c: MPM's
 *  points, nodes at the grid nodes of their cells, obstacle node layers);
 *  every step each point is connected
 *  to the cloud of nodes within the support radius of the scene's meshfree
 *  kind (kd-tree search; radius growth to shape.min_nodes, enlargement on a
 *  failed evaluation up to shape.max_enlarge; counted in mpgm_ctx). The
 *  mesh cells are written for visualisation only. docs/theory.md,
 *  section 13. */
extern const mpgm_frontend_type mpgm_frontend_gmm;

#ifdef __cplusplus
}
#endif
#endif
