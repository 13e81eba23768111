/* gmm_impl.h -- private to gmm/: method gmm's discretisation of bodies
 * filled on a grid (gmm_grid.c), used by the front end (gmm.c). */
#ifndef MPGM_GMM_IMPL_H
#define MPGM_GMM_IMPL_H

#include "mpgm_core.h"
#include "mpgm_kdtree.h"

/** The cells of a grid-filled GMM problem, for output only (the cells take
 *  no part in the interpolation). */
typedef struct gmm_grid {
  int ncell;  /**< output cells: grid cells holding material points       */
  int *cptr;  /**< ncell + 1 offsets into cnode                           */
  int *cnode; /**< node ids of every cell, counter-clockwise              */
  int *ctype; /**< VTK cell type of every cell (9 quad, 5 triangle)        */
  /* light nodes (mesh.min_node_mass): parked for a step */
  unsigned char *fix0;   /**< MPGM_DIM per node: fixity of obstacles and
                              boundaries                                   */
  double *ubar0;         /**< MPGM_DIM per node: their prescribed values [m] */
  unsigned char *parked; /**< per node: parked in this step                */
  unsigned char *eligible; /**< per node: free (no fixed component), so it
                              may be parked                                */
  double *xs, *us;       /**< MPGM_DIM per node: position, displacement at the
                              start of the step (restored for parked nodes)
                              [m]                                            */
  double *mass;          /**< per node: sum_p N_Ip m_p of the step [kg]      */
  int nparked;           /**< nodes parked in this step                       */
  unsigned char *obst;   /**< per node: an obstacle node                      */
  int *wptr, *widx;      /**< per parked node (in node order): the free body
                              nodes it follows (CSR)                          */
  double *ww;            /**< their inverse-distance weights (sum 1)         */
  int wcap;
} gmm_grid;

/** 1 when method gmm discretises the scene on the grid (a disk or polygon
 *  body, or an obstacle), 0 when it meshes its rectangle bodies as UL-FEM. */
int mpgm_gmm_uses_grid(const mpgm_scene *s);

/** Nodes, material points, probes, obstacle nodes and boundaries of a
 *  grid-filled GMM problem (docs/theory.md, section 13): material points at
 *  the Gauss points (mesh.ppc) of the cells of the grid of mesh.h over
 *  mesh.domain that lie inside a body (mpgm_bodies_fill, method mpm's
 *  rule); nodes are the grid nodes of the cells holding points that some
 *  material point has within r0 [m] (the support radius), then the
 *  obstacles' fixed nodes (a grid node of the bodies on an obstacle layer
 *  is that obstacle's node: fixed). *out receives the output cells.
 *  Errors: MPGM_ERR_INPUT (grid too large, no point in any body, boundary
 *  selecting no node), MPGM_ERR_NOMEM. */
int mpgm_gmm_grid_setup(const mpgm_fe_view *v, double r0, gmm_grid **out);

/** Light nodes (docs/theory.md, section 13; mpgm_light_nodes): a free node
 *  whose mass sum_p N_Ip m_p over the connectivity c (of every point;
 *  compacted in place) is at most mesh.min_node_mass times the heaviest
 *  node's, or that lies beyond an obstacle's plane, is parked for the step:
 *  fixed where it is, left out of every list, and the functions of the
 *  points that used it are renormalised over their other nodes
 *  (mpgm_light_drop). Restores the fixity of the last step first. Errors:
 *  MPGM_ERR_SHAPE (a point lost every node). */
int mpgm_gmm_grid_park(const mpgm_fe_view *v, gmm_grid *g, const mpgm_kdtree *tree, double r0,
                       mpgm_conn *c);
/** After the step: a parked node moves with the body, by the
 *  inverse-distance average of the increments (and takes the average
 *  velocity and acceleration) of the free body nodes within r0 of it
 *  (tree: over the start-of-step node positions; chosen in
 *  mpgm_gmm_grid_park). */
void mpgm_gmm_grid_unpark(const mpgm_fe_view *v, gmm_grid *g);

/** Free (accepts NULL, nulls the pointer). */
void mpgm_gmm_grid_destroy(gmm_grid **g);

#endif
