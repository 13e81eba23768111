/* mpgm_frontends.h -- front ends with persistent nodes (gmm/).
 *
 * mpgm_frontend_fem: UL-FEM, the reference method: each rectangle body is
 * meshed with a structured grid of T3 or Q4 cells of size <= h; material
 * points sit at the Gauss points of the cells (mesh.ppc per cell), nodes
 * persist and move with the body, the connectivity of a point is its cell.
 * mpgm_frontend_gmm: the same nodes and points, connected by node clouds.
 */
#ifndef MPGM_FRONTENDS_H
#define MPGM_FRONTENDS_H

#include "mpgm_core.h"

#ifdef __cplusplus
extern "C" {
#endif

extern const mpgm_frontend_ops mpgm_frontend_fem;

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
extern const mpgm_frontend_ops mpgm_frontend_gmm;

/** A conforming mesh of FE cells, as a mesher (or a test) makes it. */
typedef struct mpgm_fem_mesh {
  int cell;         /**< mpgm_cell_kind of every cell                     */
  int nnode;        /**< nodes                                            */
  const double *X;  /**< initial node positions, 2 per node [m]           */
  int ncell;        /**< cells                                            */
  const int *cnode; /**< mpgm_fe_nnode(cell) node ids per cell, counter-
                         clockwise                                        */
  const int *cbody; /**< scene body of every cell (material, velocity)     */
} mpgm_fem_mesh;

/** The persistent-node FE problem of a mesh (arrays are copied): nodes with
 *  the initial velocity of their body, material points at the Gauss points
 *  of every cell (scene mesh.ppc; volume w det J, mass density * volume),
 *  probes located in the cell holding them, scene boundaries applied to
 *  the nodes, and the connectivity (point -> its cell's nodes). Sets
 *  pb->fe_data; for the setup operation of a front end. Errors:
 *  MPGM_ERR_INPUT (probe outside the mesh, boundary selecting no node),
 *  MPGM_ERR_JACOBIAN (inverted cell), MPGM_ERR_NOMEM. */
int mpgm_fem_setup_mesh(mpgm_problem *pb, const mpgm_fem_mesh *m);

/** The operations shared by every front end built on mpgm_fem_setup_mesh
 *  (begin_step: N and grad N at the start-of-step node positions). */
int mpgm_fem_begin_step(mpgm_problem *pb);
int mpgm_fem_end_step(mpgm_problem *pb);
int mpgm_fem_cells(mpgm_problem *pb, int *ncells, const int **ptr, const int **conn,
                   const int **type);
void mpgm_fem_destroy(mpgm_problem *pb);


#ifdef __cplusplus
}
#endif
#endif
