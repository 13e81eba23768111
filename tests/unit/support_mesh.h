/* support_mesh.h -- for tests: a distorted structured mesh built into a
 * problem through the same path as the UL-FEM front end. */
#ifndef MPGM_SUPPORT_MESH_H
#define MPGM_SUPPORT_MESH_H

#include <stdint.h>

#include "mpgm_core_impl.h"
#include "mpgm_discretisation.h"
#include "mpgm_fem.h"
#include "mpgm_gmm.h"
#include "mpgm_mpm.h"

/** In a front end's create: nx x ny cells (Q4, or two T3 per square with
 *  alternating diagonals, as v->scene->cell says) on [0, lx] x [0, ly],
 *  every interior node moved by up to jitter * h in x and y (PRNG seed);
 *  cells are checked strictly convex. All cells belong to body 0. Then
 *  mpgm_fem_cells_create builds nodes, Gauss points and connectivity into
 *  the view, the cells into *out. */
int support_distorted_mesh(const mpgm_fe_view *v, int nx, int ny, double lx, double ly,
                           double jitter, uint64_t seed, mpgm_fem_cells **out);

/** The operations of a test front end built on mpgm_fem_cells (its create
 *  is the test's own): UL-FEM's. */
void support_fem_destroy(void *self);
int support_fem_begin_step(void *self, const mpgm_fe_view *v);
int support_fem_cells(const void *self, mpgm_cells *out);

#endif
