/* support_mesh.h -- for tests: a distorted structured mesh built into a
 * problem through the same path as the UL-FEM front end. */
#ifndef MPGM_SUPPORT_MESH_H
#define MPGM_SUPPORT_MESH_H

#include <stdint.h>

#include "mpgm_discretisation.h"
#include "mpgm_fem.h"
#include "mpgm_gmm.h"

/** In a front end's setup: nx x ny cells (Q4, or two T3 per square with
 *  alternating diagonals, as pb->scene->cell says) on [0, lx] x [0, ly],
 *  every interior node moved by up to jitter * h in x and y (PRNG seed);
 *  cells are checked strictly convex. All cells belong to body 0. Then
 *  mpgm_fem_setup_mesh builds nodes, Gauss points and connectivity. */
int support_distorted_mesh(mpgm_problem *pb, int nx, int ny, double lx, double ly,
                           double jitter, uint64_t seed);

#endif
