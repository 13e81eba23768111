/* mpgm_shapefn.h -- the shape-function plug-in family.
 *
 * Contract shared by every kind: given a material point and its candidate
 * nodes, return N_I and grad N_I (with respect to the configuration the node
 * coordinates are given in), or a recoverable error (MPGM_ERR_SHAPE,
 * MPGM_ERR_JACOBIAN). Cell-based kinds (FE) also take the cell kind and the
 * point's local coordinates in that cell; meshfree kinds (MLS, LME: next
 * issues) take only the cloud.
 */
#ifndef MPGM_SHAPEFN_H
#define MPGM_SHAPEFN_H

#include "mpgm_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Cell kinds of finite-element connectivity. */
typedef enum {
  MPGM_CELL_T3 = 0, /**< linear triangle, nodes counter-clockwise      */
  MPGM_CELL_Q4 = 1  /**< bilinear quadrilateral, nodes counter-clockwise */
} mpgm_cell_kind;

/** Largest number of nodes a point may be connected to (FE: 4). */
#define MPGM_FE_MAXNODE 4

/** One evaluation request. */
typedef struct mpgm_shape_query {
  int n;            /**< number of candidate nodes                       */
  const double *xn; /**< their coordinates, 2 per node [m]               */
  double xp[2];     /**< point position [m]                              */
  int cell;         /**< mpgm_cell_kind for cell-based kinds, else -1    */
  double xi[2];     /**< local coordinates of the point in the cell      */
} mpgm_shape_query;

/** A shape-function kind. */
typedef struct mpgm_shapefn_type {
  const char *name; /**< scene name: "fe"                                 */
  const char *doc;  /**< one line for docs                                */
  int needs_cell;   /**< 1: connectivity comes from cells (FEM, MPM only) */
  /** N (q->n values) and dN (2 per node: d/dx, d/dy) at the point.
   *  Returns 0, MPGM_ERR_JACOBIAN (inverted cell) or MPGM_ERR_SHAPE. */
  int (*eval)(const mpgm_shape_query *q, double *N, double *dN);
} mpgm_shapefn_type;

/** Find a kind by scene name; NULL if none. */
const mpgm_shapefn_type *mpgm_shapefn_type_find(const char *name);
/** All kinds, NULL-terminated. */
const mpgm_shapefn_type *const *mpgm_shapefn_types(void);

/* ---- finite-element reference elements (used by the "fe" kind and by the
 *      front ends to place points and probes) ---------------------------- */

/** Nodes of a cell kind (3 or 4). */
int mpgm_fe_nnode(int cell);
/** Reference shape functions and their derivatives d/dxi, d/deta at xi.
 *  T3: xi in the unit triangle (N = 1 - xi - eta, xi, eta);
 *  Q4: xi in [-1, 1]^2, nodes (-1,-1), (1,-1), (1,1), (-1,1). */
void mpgm_fe_ref(int cell, const double xi[2], double *N, double *dNdxi);
/** Gauss rule with npts points: T3: 1 or 3; Q4: 1, 4 or 9 (n x n).
 *  xi: 2 per point; w: weights (sum = reference area: 1/2 or 4).
 *  Returns 0 or MPGM_ERR_INPUT for an unsupported count. */
int mpgm_fe_gauss(int cell, int npts, double *xi, double *w);
/** N and spatial gradients at local xi of a cell with node coordinates xn;
 *  detJ (may be NULL) receives det(dx/dxi). MPGM_ERR_JACOBIAN if detJ <= 0. */
int mpgm_fe_eval(int cell, const double *xn, const double xi[2], double *N,
                 double *dN, double *detJ);
/** Local coordinates of point x in a cell (Newton for Q4, exact for T3).
 *  Returns 0, or MPGM_ERR_SHAPE if the inversion does not converge. */
int mpgm_fe_local(int cell, const double *xn, const double x[2], double xi[2]);
/** 1 when local coordinates xi lie in the reference cell (with slack tol). */
int mpgm_fe_inside(int cell, const double xi[2], double tol);

#ifdef __cplusplus
}
#endif
#endif
