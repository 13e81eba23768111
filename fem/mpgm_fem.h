/* mpgm_fem.h -- the UL-FEM front end, the reference method: each rectangle
 * body is meshed with a structured grid of T3 or Q4 cells of size <= h;
 * material points sit at the Gauss points of the cells (mesh.ppc per
 * cell), nodes persist and move with the body, the connectivity of a point
 * is its cell. */
#ifndef MPGM_FEM_H
#define MPGM_FEM_H

#include "mpgm_core.h"

#ifdef __cplusplus
extern "C" {
#endif

extern const mpgm_frontend_type mpgm_frontend_fem;

#ifdef __cplusplus
}
#endif
#endif
