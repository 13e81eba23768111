/* scene_impl.h -- private to core: pieces of scene loading that live in
 * their own files (geometry.c, reference_list.c). */
#ifndef MPGM_SCENE_IMPL_H
#define MPGM_SCENE_IMPL_H

#include <stddef.h>

#include "json_reader.h"
#include "mpgm_scene.h"

/** Signed area of the polygon p (n points x0, y0, x1, y1, ...) [m^2];
 *  > 0 when counter-clockwise. */
double mpgm_polygon_area(const double *p, int n);

/** 0 when p (n points) is an admissible polygon body: 3 to
 *  MPGM_POLYGON_MAX points, no two consecutive points equal (the last one
 *  is joined to the first), non-zero area, no two edges that cross, touch
 *  or overlap. Otherwise 1, with what is wrong in msg. Tolerances are
 *  1e-12 of the bounding box (width + height). */
int mpgm_polygon_check(const double *p, int n, char *msg, size_t len);

/** 1 when body b (bounding box in b->min/max) meets the closed box
 *  [lo, hi] (touching counts), else 0. */
int mpgm_body_meets_box(const mpgm_scene_body *b, const double lo[2], const double hi[2]);

/** Read the optional top-level "reference" block into s->reference
 *  (after the probes and the time block were read). */
int mpgm_reference_read(jr_node *root, mpgm_scene *s);

#endif
