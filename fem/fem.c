/* fem.c -- the UL-FEM front end, the reference method on the shared core:
 * each rectangle body meshed by a structured grid of Q4 cells (or two T3
 * per square) of size <= mesh.h (discretisation/mesh.c); nodes persist and
 * move with the body, and a point's connectivity is its cell. */
#include "mpgm_discretisation.h"
#include "mpgm_fem.h"

static int fem_create(const mpgm_fe_view *v, void **self) {
  return mpgm_fem_rectangles(v, (mpgm_fem_cells **)self);
}

static void fem_destroy(void *self) { mpgm_fem_cells_destroy(self); }

/* N and grad N in the cells at the start-of-step node positions. */
static int fem_begin_step(void *self, const mpgm_fe_view *v) { return mpgm_fem_cells_shape(self, v); }

static int fem_cells(const void *self, mpgm_cells *out) { return mpgm_fem_cells_output(self, out); }

const mpgm_frontend_type mpgm_frontend_fem = {
    .name = "fem",
    .doc = "UL-FEM: rectangle bodies meshed by T3 or Q4 cells, nodes that persist and move "
           "with the body, the cell as connectivity",
    .persistent_nodes = 1,
    .point_velocity = MPGM_PV_INTERPOLATE,
    .shapes = MPGM_FE_SHAPE_CELL,
    .geometries = 1u << MPGM_GEOM_RECTANGLE,
    .conditions = MPGM_FE_COND_FIX | MPGM_FE_COND_DISPLACEMENT,
    .obstacles = 0,
    .create = fem_create,
    .destroy = fem_destroy,
    .begin_step = fem_begin_step,
    .cells = fem_cells,
};
