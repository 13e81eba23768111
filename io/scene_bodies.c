/* scene_bodies.c -- the "bodies" of a scene, their geometries (plane:
 * rectangle, disk, polygon, ring; 3-D: box, sphere, cylinder, extruded
 * polygon), and the "probes" inside them (docs/scene-format.md). Called
 * by scene.c's read_scene. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_impl.h"

static int find_material(const mpgm_scene *s, const char *name) {
  for (int i = 0; i < s->nmat; i++)
    if (strcmp(s->mats[i].name, name) == 0) return i;
  return -1;
}

/* "points": [[x, y], ...] of a polygon (validated: simple, with area). */
static int read_polygon_points(jr_node *g, mpgm_scene_body *body) {
  const cJSON *v = jr_override_json(g, "points");
  if (!v) v = jr_raw(g, "points");
  else jr_raw(g, "points");
  if (!v) return jr_fail(g, "points", "required key is missing (expected [[x, y], ...], at least 3 points)");
  if (!cJSON_IsArray(v))
    return jr_fail(g, "points", "expected an array of points [[x, y], ...], found %s", jr_type(v));
  const int n = cJSON_GetArraySize(v);
  if (n > MPGM_POLYGON_MAX)
    return jr_fail(g, "points", "expected at most %d points, found %d", MPGM_POLYGON_MAX, n);
  int i = 0;
  for (const cJSON *c = v->child; c; c = c->next, i++) {
    if (!cJSON_IsArray(c) || cJSON_GetArraySize(c) != 2)
      return jr_fail(g, "points", "expected points [x, y], found %s%s at index %d", jr_type(c),
                     cJSON_IsArray(c) ? " of another length" : "", i);
    for (int d = 0; d < 2; d++) {
      const cJSON *e = cJSON_GetArrayItem(c, d);
      if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
        return jr_fail(g, "points", "expected points [x, y] of 2 finite numbers, found %s in point %d",
                       jr_type(e), i);
      body->points[2 * i + d] = e->valuedouble;
    }
  }
  body->npoints = n;
  char msg[256] = "";
  if (mpgm_polygon_check(body->points, n, msg, sizeof msg)) return jr_fail(g, "points", "%s", msg);
  cJSON *a = cJSON_AddArrayToObject(g->out, "points");
  for (int k = 0; k < n; k++) cJSON_AddItemToArray(a, cJSON_CreateDoubleArray(body->points + 2 * k, 2));
  return 0;
}

#if MPGM_DIM == 2
/* "ring": an annulus, or the sector of one between two angles (degrees in
 * the scene, radians in the body). */
static int read_ring(jr_node *g, mpgm_scene_body *body) {
  MPGM_CALL(jr_vec(g, "centre", NULL, body->centre));
  MPGM_CALL(jr_num(g, "inner", NAN, 0, INFINITY, 0, 0, &body->radius_in));
  MPGM_CALL(jr_num(g, "outer", NAN, 0, INFINITY, 1, 0, &body->radius));
  double a0, a1;
  MPGM_CALL(jr_num(g, "from", 0.0, -360.0, 360.0, 0, 0, &a0));
  MPGM_CALL(jr_num(g, "to", 360.0, -360.0, 720.0, 0, 0, &a1));
  MPGM_CALL(jr_end(g));
  if (!(body->radius > body->radius_in))
    return jr_fail(g, "outer", "expected outer > inner = %g m, found %g m", body->radius_in, body->radius);
  if (!(a1 > a0) || a1 - a0 > 360.0)
    return jr_fail(g, "to", "expected from < to <= from + 360 degrees, found from %g, to %g", a0, a1);
  body->angle[0] = a0 * 3.14159265358979323846 / 180.0;
  body->angle[1] = a1 * 3.14159265358979323846 / 180.0;
  return 0;
}

/* Exactly one of "rectangle", "disk", "polygon", "ring"; fills the geometry
 * and the bounding box (body->min/max). *g is the geometry's node, for
 * messages. */
static int read_geometry(jr_node *b, mpgm_scene_body *body, jr_node *g) {
  const cJSON *hr = jr_raw(b, "rectangle"), *hd = jr_raw(b, "disk"), *hp = jr_raw(b, "polygon");
  const cJSON *hg = jr_raw(b, "ring");
  const int ng = !!hr + !!hd + !!hp + !!hg;
  if (ng > 1)
    return jr_fail(b, NULL, "expected exactly one geometry: \"rectangle\", \"disk\", \"polygon\" "
                   "or \"ring\", found %d", ng);
  if (ng == 0 && !jr_override_json(b, "rectangle"))
    return jr_fail(b, "rectangle", "required key is missing (expected one geometry: \"rectangle\": "
                   "{\"min\", \"max\"}, \"disk\": {\"centre\", \"radius\"}, \"polygon\": "
                   "{\"points\"} or \"ring\": {\"centre\", \"inner\", \"outer\"})");
  if (hd) {
    body->geometry = MPGM_GEOM_DISK;
    MPGM_CALL(jr_child(b, "disk", 1, g));
    MPGM_CALL(jr_vec(g, "centre", NULL, body->centre));
    MPGM_CALL(jr_num(g, "radius", NAN, 0, INFINITY, 1, 0, &body->radius));
    MPGM_CALL(jr_end(g));
  } else if (hg) {
    body->geometry = MPGM_GEOM_RING;
    MPGM_CALL(jr_child(b, "ring", 1, g));
    MPGM_CALL(read_ring(g, body));
  } else if (hp) {
    body->geometry = MPGM_GEOM_POLYGON;
    MPGM_CALL(jr_child(b, "polygon", 1, g));
    MPGM_CALL(read_polygon_points(g, body));
    MPGM_CALL(jr_end(g));
  } else {
    body->geometry = MPGM_GEOM_RECTANGLE;
    MPGM_CALL(jr_child(b, "rectangle", 1, g));
    MPGM_CALL(jr_vec_len(g, "min", NULL, body->min));
    MPGM_CALL(jr_vec_len(g, "max", NULL, body->max));
    MPGM_CALL(jr_end(g));
    if (!(body->max[0] > body->min[0]) || !(body->max[1] > body->min[1]))
      return jr_fail(g, NULL, "expected max > min in x and y (a body with area), found an empty "
                     "rectangle [%g, %g] x [%g, %g]", body->min[0], body->max[0], body->min[1], body->max[1]);
  }
  mpgm_body_bbox(body, body->min, body->max);
  return 0;
}
#else
/* "cylinder": centre (of one end), axis (to the other end's centre),
 * radius. */
static int read_cylinder(jr_node *g, mpgm_scene_body *body) {
  MPGM_CALL(jr_vec(g, "centre", NULL, body->centre));
  MPGM_CALL(jr_vec(g, "axis", NULL, body->axis));
  MPGM_CALL(jr_num(g, "radius", NAN, 0, INFINITY, 1, 0, &body->radius));
  MPGM_CALL(jr_end(g));
  const double *a = body->axis;
  if (!(sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) > 0.0))
    return jr_fail(g, "axis", "expected a non-zero axis (from the centre of one end to that of the "
                   "other), found [0, 0, 0]");
  return 0;
}

/* A 3-D scene's body: exactly one of "box", "sphere", "cylinder" or
 * "polygon" (a polygon of the x-y plane extruded from z0 to z1); fills the
 * geometry and the bounding box. The plane bodies are refused by name. */
static int read_geometry(jr_node *b, mpgm_scene_body *body, jr_node *g) {
  static const char *const plane[] = {"rectangle", "disk", "ring"};
  for (int k = 0; k < 3; k++)
    if (b->j && cJSON_GetObjectItemCaseSensitive(b->j, plane[k]))
      return jr_fail(b, plane[k], "a plane-strain body: a 3-D scene's bodies are \"box\", "
                     "\"sphere\", \"cylinder\" or \"polygon\" (extruded from z0 to z1)");
  const cJSON *hb = jr_raw(b, "box"), *hs = jr_raw(b, "sphere"), *hc = jr_raw(b, "cylinder");
  const cJSON *hp = jr_raw(b, "polygon");
  const int ng = !!hb + !!hs + !!hc + !!hp;
  if (ng > 1)
    return jr_fail(b, NULL, "expected exactly one geometry: \"box\", \"sphere\", \"cylinder\" "
                   "or \"polygon\", found %d", ng);
  if (ng == 0 && !jr_override_json(b, "box"))
    return jr_fail(b, "box", "required key is missing (expected one geometry: \"box\": {\"min\", "
                   "\"max\"}, \"sphere\": {\"centre\", \"radius\"}, \"cylinder\": {\"centre\", "
                   "\"axis\", \"radius\"} or \"polygon\": {\"points\", \"z0\", \"z1\"})");
  if (hs) {
    body->geometry = MPGM_GEOM_SPHERE;
    MPGM_CALL(jr_child(b, "sphere", 1, g));
    MPGM_CALL(jr_vec(g, "centre", NULL, body->centre));
    MPGM_CALL(jr_num(g, "radius", NAN, 0, INFINITY, 1, 0, &body->radius));
    MPGM_CALL(jr_end(g));
  } else if (hc) {
    body->geometry = MPGM_GEOM_CYLINDER;
    MPGM_CALL(jr_child(b, "cylinder", 1, g));
    MPGM_CALL(read_cylinder(g, body));
  } else if (hp) {
    body->geometry = MPGM_GEOM_POLYGON;
    MPGM_CALL(jr_child(b, "polygon", 1, g));
    MPGM_CALL(read_polygon_points(g, body));
    MPGM_CALL(jr_len(g, "z0", NAN, -INFINITY, INFINITY, &body->z[0]));
    MPGM_CALL(jr_len(g, "z1", NAN, -INFINITY, INFINITY, &body->z[1]));
    MPGM_CALL(jr_end(g));
    if (!(body->z[1] > body->z[0]))
      return jr_fail(g, "z1", "expected z1 > z0 = %g m (a prism with volume), found %g m", body->z[0],
                     body->z[1]);
  } else {
    body->geometry = MPGM_GEOM_BOX;
    MPGM_CALL(jr_child(b, "box", 1, g));
    MPGM_CALL(jr_vec_len(g, "min", NULL, body->min));
    MPGM_CALL(jr_vec_len(g, "max", NULL, body->max));
    MPGM_CALL(jr_end(g));
    char box[MPGM_BOX_STR];
    for (int d = 0; d < MPGM_DIM; d++)
      if (!(body->max[d] > body->min[d]))
        return jr_fail(g, NULL, "expected max > min in x, y and z (a body with volume), found an "
                       "empty box %s", mpgm_box_str(body->min, body->max, box));
  }
  mpgm_body_bbox(body, body->min, body->max);
  return 0;
}
#endif

int mpgm_scene_read_bodies(jr_node *root, mpgm_scene *s) {
  const cJSON *arr = NULL;
  MPGM_CALL(mpgm_scene_get_array(root, "bodies", &arr));
  if (!arr || cJSON_GetArraySize(arr) == 0)
    return jr_fail(root, "bodies", "expected at least one body, found none");
  s->nbody = cJSON_GetArraySize(arr);
  MPGM_ALLOC(root->r->ctx, s->bodies, s->nbody);
  cJSON *out = cJSON_AddArrayToObject(root->out, "bodies");
  for (int i = 0; i < s->nbody; i++) {
    jr_node b;
    MPGM_CALL(mpgm_scene_array_elem(root, "bodies", arr, i, out, &b));
    mpgm_scene_body *body = &s->bodies[i];
    char def[32], mname[MPGM_NAME_LEN];
    snprintf(def, sizeof def, "body%d", i);
    MPGM_CALL(jr_str(&b, "name", def, body->name, sizeof body->name));
    MPGM_CALL(jr_str(&b, "material", NULL, mname, sizeof mname));
    body->material = find_material(s, mname);
    if (body->material < 0) {
      char list[512] = "";
      for (int k = 0; k < s->nmat; k++) {
        size_t l = strlen(list);
        snprintf(list + l, sizeof list - l, "%s\"%s\"", k ? ", " : "", s->mats[k].name);
      }
      return jr_fail(&b, "material", "expected the name of a material defined in materials (%s), found \"%s\"",
                     list, mname);
    }
    jr_node g;
    MPGM_CALL(read_geometry(&b, body, &g));
    const double zero[MPGM_DIM] = {0};
    MPGM_CALL(jr_vec(&b, "velocity", zero, body->velocity));
    jr_node geo;
    MPGM_CALL(jr_child(&b, "geostatic", 0, &geo));
    if (geo.j) { /* sigma_yy = rho g_y (surface - y), sigma_xx = sigma_zz = k0 sigma_yy */
      body->geostatic = 1;
      MPGM_CALL(jr_num(&geo, "surface", NAN, -INFINITY, INFINITY, 0, 0, &body->surface));
      MPGM_CALL(jr_num(&geo, "k0", NAN, 0.0, 10.0, 0, 0, &body->k0));
      MPGM_CALL(jr_end(&geo));
    } else if (b.out) { /* absent: no empty object in the resolved scene, which must load again */
      cJSON_DeleteItemFromObjectCaseSensitive(b.out, "geostatic");
    }
    MPGM_CALL(jr_end(&b));
    for (int d = 0; d < MPGM_DIM; d++) {
      const double tol = 1e-12 * (s->dom_max[d] - s->dom_min[d]);
      char dom[MPGM_BOX_STR], box[MPGM_BOX_STR];
      if (body->min[d] < s->dom_min[d] - tol || body->max[d] > s->dom_max[d] + tol)
        return jr_fail(&g, NULL, "expected a body inside the domain %s (mesh.domain), found %s",
                       mpgm_box_str(s->dom_min, s->dom_max, dom), mpgm_box_str(body->min, body->max, box));
    }
  }
  return 0;
}

int mpgm_scene_read_probes(jr_node *root, mpgm_scene *s) {
  const cJSON *map = NULL;
  MPGM_CALL(mpgm_scene_get_map(root, "probes", &map));
  s->nprobe = map ? cJSON_GetArraySize(map) : 0;
  if (s->nprobe > 32) return jr_fail(root, "probes", "expected at most 32 probes, found %d", s->nprobe);
  MPGM_ALLOC(root->r->ctx, s->probes, s->nprobe);
  jr_node p = {.r = root->r, .j = map};
  snprintf(p.path, sizeof p.path, "probes");
  p.out = cJSON_AddObjectToObject(root->out, "probes");
  int i = 0;
  for (const cJSON *c = map ? map->child : NULL; c; c = c->next, i++) {
    jr_node q = {.r = root->r};
    snprintf(q.path, sizeof q.path, "probes.%s", c->string);
    MPGM_CALL(mpgm_scene_check_name(&q, c->string));
    snprintf(s->probes[i].name, MPGM_NAME_LEN, "%s", c->string);
    MPGM_CALL(jr_vec_len(&p, c->string, NULL, s->probes[i].x));
    const double *x = s->probes[i].x;
    int in = 0;
    for (int b = 0; b < s->nbody && !in; b++) in = mpgm_body_contains(&s->bodies[b], x);
    char at[MPGM_POINT_STR];
    if (!in) return jr_fail(&q, NULL, "expected a position inside a body, found %s", mpgm_point_str(x, at));
  }
  MPGM_CALL(jr_end(&p));
  return 0;
}

