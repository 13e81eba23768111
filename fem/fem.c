/* fem.c -- the UL-FEM front end: each rectangle body meshed by a structured
 * grid of Q4 cells (or two T3 per square) of size <= mesh.h, the problem
 * built on it by mpgm_fem_setup_mesh (discretisation/mesh.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_discretisation.h"
#include "mpgm_fem.h"

const mpgm_frontend_ops mpgm_frontend_fem = {
    .name = "fem",
    .point_velocity = MPGM_PV_INTERPOLATE,
    .setup = mpgm_mesh_rectangles,
    .begin_step = mpgm_fem_begin_step,
    .end_step = mpgm_fem_end_step,
    .cells = mpgm_fem_cells,
    .destroy = mpgm_fem_destroy,
};
