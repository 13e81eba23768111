/* mpgm_discretisation.h -- what the front ends share to make nodes and
 * points: bodies filled on a grid, meshes of FE cells, points on the
 * bodies' surfaces. The background grid (mpgm_grid.h) and the kd-tree
 * (mpgm_kdtree.h) have headers of their own. */
#ifndef MPGM_DISCRETISATION_H
#define MPGM_DISCRETISATION_H

#include "mpgm_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Material points of bodies filled on a grid: the rule of method mpm's
 *  particles and of method gmm's grid-filled bodies (one function, so both
 *  put their points at the same places). For each of ncell cells of kind
 *  `cell` (mpgm_cell_kind), whose node coordinates (counter-clockwise) the
 *  caller's xy(grid, c, xn) gives, the Gauss points of the rule of s->ppc
 *  are taken in order; a point belongs to the first body of s that contains
 *  it (mpgm_body_contains), or to none. Outputs, entry k = c * s->ppc + q:
 *  owner (may be NULL) the body or -1; x (may be NULL) the position, 2 per
 *  entry [m]; *count the entries that belong to a body. Returns 0, or
 *  MPGM_ERR_INPUT when the cell kind has no rule of s->ppc points. */
int mpgm_bodies_fill(const mpgm_scene *s, int cell, int ncell,
                     void (*xy)(const void *grid, int c, double *xn), const void *grid,
                     int *owner, double *x, int *count);

/** Surface tracers of the scene's bodies (contact at points; 0 without):
 *  how many, and their positions, bodies and initial velocities into the
 *  last P->nsurf points of P (after the probes). The front ends call both
 *  (mpm.c, gmm_grid.c). */
int mpgm_surface_tracers_count(const mpgm_scene *s);
void mpgm_surface_tracers_fill(mpgm_points *P, const mpgm_scene *s);
/** Points on the boundary of body b at most `spacing` apart (a disk: from
 *  its lowest point, counter-clockwise; rectangles and polygons: every
 *  vertex and equal divisions of every edge). x == NULL: only count.
 *  Returns the number of points. */
int mpgm_body_surface(const mpgm_scene_body *b, double spacing, double *x);

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

/** Each rectangle body of the scene meshed by a structured grid of Q4
 *  cells (or two T3 per square) of size <= mesh.h, and the problem built
 *  on that mesh by mpgm_fem_setup_mesh (the setup of UL-FEM, and of GMM
 *  for rectangle bodies). Errors: MPGM_ERR_INPUT (mesh too large), those
 *  of mpgm_fem_setup_mesh. */
int mpgm_mesh_rectangles(mpgm_problem *pb);

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
