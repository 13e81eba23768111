/* scene_impl.h -- private to core: pieces of scene loading that live in
 * their own files (geometry.c, reference_list.c, scene_boundaries.c). */
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

/** The array at key (NULL when absent; an --set override replaces it);
 *  bad input when it is not an array. */
int mpgm_scene_get_array(jr_node *o, const char *key, const cJSON **arr);
/** Element i of array arr (at key) as an object node with path "key.i";
 *  its resolved copy is appended to out_arr. */
int mpgm_scene_array_elem(jr_node *o, const char *key, const cJSON *arr, int i, cJSON *out_arr,
                          jr_node *e);
/** "boundaries" and "obstacles" (scene_boundaries.c; after the bodies). */
int mpgm_scene_read_boundaries(jr_node *root, mpgm_scene *s);
int mpgm_scene_read_obstacles(jr_node *root, mpgm_scene *s);

#endif
