/* mpgm_grid.h -- structured background grid over a box, with O(1) point
 * location and local coordinates.
 * 2-D: Q4 cells, or two T3 per square (the diagonal from the lower-left to
 * the upper-right corner). Square (i, j) is j * nx + i; node (i, j) is
 * j * (nx + 1) + i; a Q4 cell is its square; T3 cells 2 sq (lower-right)
 * and 2 sq + 1 (upper-left).
 * 3-D: H8 cells, one per cube. Cube (i, j, k) is (k ny + j) nx + i; node
 * (i, j, k) is (k (ny + 1) + j) (nx + 1) + i; a cell's nodes are its
 * bottom face's (counter-clockwise from (i, j)), then its top face's. */
#ifndef MPGM_GRID_H
#define MPGM_GRID_H

#include <math.h>

#include "mpgm_core.h"

typedef struct mpgm_grid {
  int cell;           /**< mpgm_cell_kind                                */
  int nn;             /**< nodes per cell                                */
  double h;           /**< cell size [m]                                 */
  double min[MPGM_DIM], max[MPGM_DIM]; /**< covered box: min + (nx, ny
                                            (, nz)) h [m]                */
  int nx, ny;         /**< squares (cubes) in x and y                    */
  int nz;             /**< 3-D: cubes in z (2-D: 0)                      */
  int nnode, ncell;   /**< grid nodes and cells                          */
} mpgm_grid;

/** Grid over mesh.domain with cells of exactly mesh.h (the box is extended
 *  up to a whole number of cells). MPGM_ERR_INPUT if it is too large. */
int mpgm_grid_init(mpgm_ctx *ctx, mpgm_grid *g, const mpgm_scene *s);
/** Position of grid node id. */
void mpgm_grid_node(const mpgm_grid *g, int id, double X[MPGM_DIM]);
/** Node ids (2-D counter-clockwise; 3-D in H8 order) and, if xn is not
 *  NULL, their coordinates. */
void mpgm_grid_cell(const mpgm_grid *g, int c, int *nodes, double *xn);
/** Cell holding x and x's local coordinates in it; MPGM_ERR_DOMAIN if x is
 *  outside the grid. Points on a shared edge (face) go to the cell above /
 *  right (/ in front). */
int mpgm_grid_locate(const mpgm_grid *g, const double x[MPGM_DIM], int *cell,
                     double xi[MPGM_DIM]);
/** The grid column (or row) of coordinate x along axis a, floor((x -
 *  min) / h), as an int however far from the grid x is (a position read
 *  from a checkpoint, or of a run gone astray, can be any double): clamped
 *  to +-2^30, NaN to -2^30, so that spans of such lines do not overflow
 *  when taken as long. */
static inline int mpgm_grid_line(const mpgm_grid *g, int a, double x) {
  const double f = floor((x - g->min[a]) / g->h), lim = 1073741824.0;
  return f >= lim ? (int)lim : f >= -lim ? (int)f : -(int)lim;
}
/** Cells sharing a node with cell c (c excluded); returns their count (2-D
 *  <= 17: 8 neighbouring squares and the other triangle of its own square;
 *  3-D <= 26 cubes). */
int mpgm_grid_neighbours(const mpgm_grid *g, int c, int *out);

#endif
