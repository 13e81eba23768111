/* scene.c -- load and validate a scene file (docs/scene-format.md). */
#include "mpgm_scene.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json_reader.h"
#include "scene_impl.h"

static const char *const method_names[] = {"fem", "mpm", "gmm", NULL}; /* = mpgm_method */
static const char *const cell_names[] = {"tri", "quad", NULL}; /* = mpgm_cell_kind */
static const char *const kin_names[] = {"finite", "small", NULL};
static const char *const analysis_names[] = {"static", "dynamic", NULL};
static const char *const vtk_names[] = {"none", "ascii", "binary", NULL};
static const char *const field_names[] = {"displacement", "velocity", "stress", "mass",
                                          "volume", "J", "material", "acceleration", "id", "eps_p",
                                          NULL};
static const char *const future_methods[] = {NULL}; /* named methods of later issues */
static const char *const condition_names[] = {"stick", "slip", "contact", NULL}; /* = mpgm_condition - 1 */

const char *mpgm_method_name(int method) {
  return (method >= 0 && method <= MPGM_METHOD_GMM) ? method_names[method] : "?";
}

/* Names of materials, bodies, probes: usable in dotted paths. */
static int check_name(jr_node *o, const char *name) {
  size_t n = strlen(name);
  if (n == 0 || n >= MPGM_NAME_LEN)
    return jr_fail(o, NULL, "expected a name of 1 to %d characters, found \"%s\"",
                   MPGM_NAME_LEN - 1, name);
  for (size_t i = 0; i < n; i++)
    if (!(isalnum((unsigned char)name[i]) || name[i] == '_' || name[i] == '-'))
      return jr_fail(o, NULL, "expected a name of letters, digits, '_' or '-', found \"%s\"", name);
  return 0;
}

/* An object-valued key whose members are named entries (materials, probes).
 * *map is NULL when absent. */
static int get_map(jr_node *o, const char *key, const cJSON **map) {
  const cJSON *v = jr_override_json(o, key);
  if (!v) v = jr_raw(o, key);
  else jr_raw(o, key);
  if (v && !cJSON_IsObject(v)) return jr_fail(o, key, "expected an object of named entries, found %s", jr_type(v));
  *map = v;
  return 0;
}

static int get_array(jr_node *o, const char *key, const cJSON **arr) {
  const cJSON *v = jr_override_json(o, key);
  if (!v) v = jr_raw(o, key);
  else jr_raw(o, key);
  if (v && !cJSON_IsArray(v)) return jr_fail(o, key, "expected an array, found %s", jr_type(v));
  *arr = v;
  return 0;
}

/* Element i of an array as a node with path "key.i". */
static int array_elem(jr_node *o, const char *key, const cJSON *arr, int i,
                      cJSON *out_arr, jr_node *e) {
  memset(e, 0, sizeof *e);
  e->r = o->r;
  if (snprintf(e->path, sizeof e->path, "%s%s%s.%d", o->path, o->path[0] ? "." : "", key, i) >=
      (int)sizeof e->path)
    return jr_fail(o, key, "path too long");
  e->j = cJSON_GetArrayItem(arr, i);
  if (!cJSON_IsObject(e->j)) return jr_fail(e, NULL, "expected an object, found %s", jr_type(e->j));
  e->out = cJSON_CreateObject();
  cJSON_AddItemToArray(out_arr, e->out);
  return 0;
}

/* One material entry: type, density, the type's parameters, setup. */
static int read_material(jr_node *m, mpgm_material *mat) {
  const mpgm_material_type *const *all = mpgm_material_types();
  const char *choices[16];
  int nt = 0;
  for (; all[nt] && nt < 15; nt++) choices[nt] = all[nt]->name;
  choices[nt] = NULL;
  int t;
  MPGM_CALL(jr_enum(m, "type", choices, -1, &t));
  mat->type = all[t];
  MPGM_CALL(jr_num(m, "density", NAN, 0, INFINITY, 1, 0, &mat->density));
  for (int p = 0; p < mat->type->nparam; p++) {
    const mpgm_param_spec *ps = &mat->type->params[p];
    MPGM_CALL(jr_num(m, ps->name, ps->def, ps->lo, ps->hi, ps->lo_open, ps->hi_open,
                     &mat->param[p]));
  }
  MPGM_CALL(jr_end(m));
  char msg[256] = "";
  if (mat->type->setup(mat, msg, sizeof msg)) return jr_fail(m, NULL, "%s", msg);
  return 0;
}

static int read_materials(jr_node *root, mpgm_scene *s) {
  const cJSON *map = NULL;
  MPGM_CALL(get_map(root, "materials", &map));
  if (!map || !map->child) return jr_fail(root, "materials", "expected at least one named material, found none");
  s->nmat = cJSON_GetArraySize(map);
  MPGM_ALLOC(root->r->ctx, s->mats, s->nmat);
  cJSON *outmap = cJSON_AddObjectToObject(root->out, "materials");
  int i = 0;
  for (const cJSON *c = map->child; c; c = c->next, i++) {
    jr_node m = {.r = root->r, .j = c};
    snprintf(m.path, sizeof m.path, "materials.%s", c->string);
    MPGM_CALL(check_name(&m, c->string));
    for (const cJSON *d = map->child; d != c; d = d->next)
      if (strcmp(d->string, c->string) == 0) return jr_fail(&m, NULL, "duplicate material name");
    if (!cJSON_IsObject(c)) return jr_fail(&m, NULL, "expected an object, found %s", jr_type(c));
    m.out = cJSON_AddObjectToObject(outmap, c->string);
    mpgm_material *mat = &s->mats[i];
    snprintf(mat->name, sizeof mat->name, "%s", c->string);
    MPGM_CALL(read_material(&m, mat));
  }
  return 0;
}

int mpgm_material_load(mpgm_ctx *ctx, const char *file, const char *path, const void *json,
                       mpgm_material *mat) {
  jr_reader r = {.ctx = ctx, .file = file};
  jr_node m = {.r = &r, .j = json};
  snprintf(m.path, sizeof m.path, "%s", path);
  if (!cJSON_IsObject((const cJSON *)json)) {
    int err = jr_fail(&m, NULL, "expected a material object, found %s", jr_type(json));
    return err;
  }
  cJSON *out = cJSON_CreateObject();
  m.out = out;
  int err = read_material(&m, mat);
  cJSON_Delete(out);
  cJSON_Delete(r.tmp);
  return err;
}

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

/* Exactly one of "rectangle", "disk", "polygon"; fills the geometry and the
 * bounding box (body->min/max). *g is the geometry's node, for messages. */
static int read_geometry(jr_node *b, mpgm_scene_body *body, jr_node *g) {
  const cJSON *hr = jr_raw(b, "rectangle"), *hd = jr_raw(b, "disk"), *hp = jr_raw(b, "polygon");
  const int ng = !!hr + !!hd + !!hp;
  if (ng > 1)
    return jr_fail(b, NULL, "expected exactly one geometry: \"rectangle\", \"disk\" or \"polygon\", "
                   "found %d", ng);
  if (ng == 0 && !jr_override_json(b, "rectangle"))
    return jr_fail(b, "rectangle", "required key is missing (expected one geometry: \"rectangle\": "
                   "{\"min\", \"max\"}, \"disk\": {\"centre\", \"radius\"} or \"polygon\": "
                   "{\"points\"})");
  if (hd) {
    body->geometry = MPGM_GEOM_DISK;
    MPGM_CALL(jr_child(b, "disk", 1, g));
    MPGM_CALL(jr_vec2(g, "centre", NULL, body->centre));
    MPGM_CALL(jr_num(g, "radius", NAN, 0, INFINITY, 1, 0, &body->radius));
    MPGM_CALL(jr_end(g));
  } else if (hp) {
    body->geometry = MPGM_GEOM_POLYGON;
    MPGM_CALL(jr_child(b, "polygon", 1, g));
    MPGM_CALL(read_polygon_points(g, body));
    MPGM_CALL(jr_end(g));
  } else {
    body->geometry = MPGM_GEOM_RECTANGLE;
    MPGM_CALL(jr_child(b, "rectangle", 1, g));
    MPGM_CALL(jr_vec2(g, "min", NULL, body->min));
    MPGM_CALL(jr_vec2(g, "max", NULL, body->max));
    MPGM_CALL(jr_end(g));
    if (!(body->max[0] > body->min[0]) || !(body->max[1] > body->min[1]))
      return jr_fail(g, NULL, "expected max > min in x and y (a body with area), found an empty "
                     "rectangle [%g, %g] x [%g, %g]", body->min[0], body->max[0], body->min[1], body->max[1]);
  }
  mpgm_body_bbox(body, body->min, body->max);
  return 0;
}

static int read_bodies(jr_node *root, mpgm_scene *s) {
  const cJSON *arr = NULL;
  MPGM_CALL(get_array(root, "bodies", &arr));
  if (!arr || cJSON_GetArraySize(arr) == 0)
    return jr_fail(root, "bodies", "expected at least one body, found none");
  s->nbody = cJSON_GetArraySize(arr);
  MPGM_ALLOC(root->r->ctx, s->bodies, s->nbody);
  cJSON *out = cJSON_AddArrayToObject(root->out, "bodies");
  for (int i = 0; i < s->nbody; i++) {
    jr_node b;
    MPGM_CALL(array_elem(root, "bodies", arr, i, out, &b));
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
    if (s->method == MPGM_METHOD_FEM && body->geometry != MPGM_GEOM_RECTANGLE)
      return jr_fail(&b, NULL, "method fem meshes rectangle bodies only; use method mpm or gmm for "
                     "disk and polygon bodies");
    const double zero[2] = {0, 0};
    MPGM_CALL(jr_vec2(&b, "velocity", zero, body->velocity));
    jr_node geo;
    MPGM_CALL(jr_child(&b, "geostatic", 0, &geo));
    if (geo.j) { /* sigma_yy = rho g_y (surface - y), sigma_xx = sigma_zz = k0 sigma_yy */
      body->geostatic = 1;
      MPGM_CALL(jr_num(&geo, "surface", NAN, -INFINITY, INFINITY, 0, 0, &body->surface));
      MPGM_CALL(jr_num(&geo, "k0", NAN, 0.0, 10.0, 0, 0, &body->k0));
      MPGM_CALL(jr_end(&geo));
    }
    MPGM_CALL(jr_end(&b));
    const double tol[2] = {1e-12 * (s->dom_max[0] - s->dom_min[0]), 1e-12 * (s->dom_max[1] - s->dom_min[1])};
    for (int d = 0; d < 2; d++)
      if (body->min[d] < s->dom_min[d] - tol[d] || body->max[d] > s->dom_max[d] + tol[d])
        return jr_fail(&g, NULL, "expected a body inside the domain [%g, %g] x [%g, %g] (mesh.domain), "
                       "found [%g, %g] x [%g, %g]", s->dom_min[0], s->dom_max[0], s->dom_min[1],
                       s->dom_max[1], body->min[0], body->max[0], body->min[1], body->max[1]);
  }
  return 0;
}

static int read_fix(jr_node *o, const char *key, int fix[2]) {
  const cJSON *v = jr_override_json(o, key);
  if (!v) v = jr_raw(o, key);
  else jr_raw(o, key);
  if (!v)
    return jr_fail(o, key, "required key is missing (expected \"fix\": [\"x\"], [\"y\"] or [\"x\", \"y\"], "
                   "or \"condition\": \"stick\" | \"slip\")");
  fix[0] = fix[1] = 0;
  if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) < 1 || cJSON_GetArraySize(v) > 2)
    return jr_fail(o, key, "expected [\"x\"], [\"y\"] or [\"x\", \"y\"], found %s%s", jr_type(v),
                   cJSON_IsArray(v) ? " of another length" : "");
  for (const cJSON *c = v->child; c; c = c->next) {
    int d = cJSON_IsString(c) ? (strcmp(c->valuestring, "x") == 0 ? 0 : strcmp(c->valuestring, "y") == 0 ? 1 : -1) : -1;
    if (d < 0) return jr_fail(o, key, "expected components \"x\" or \"y\", found %s%s%s%s", jr_type(c),
                              cJSON_IsString(c) ? " \"" : "", cJSON_IsString(c) ? c->valuestring : "",
                              cJSON_IsString(c) ? "\"" : "");
    if (fix[d]) return jr_fail(o, key, "component \"%s\" listed twice", c->valuestring);
    fix[d] = 1;
  }
  cJSON *a = cJSON_AddArrayToObject(o->out, key);
  if (fix[0]) cJSON_AddItemToArray(a, cJSON_CreateString("x"));
  if (fix[1]) cJSON_AddItemToArray(a, cJSON_CreateString("y"));
  return 0;
}

/* The selector of bc meets body bd within bc->tol: lines against the body's
 * extent across them (exact for any connected body), boxes against the
 * body itself. */
static int selector_meets_body(const mpgm_scene_boundary *bc, const mpgm_scene_body *bd) {
  const double t = bc->tol;
  if (bc->select != MPGM_SELECT_BOX)
    return bc->value >= bd->min[bc->select] - t && bc->value <= bd->max[bc->select] + t;
  const double lo[2] = {bc->min[0] - t, bc->min[1] - t}, hi[2] = {bc->max[0] + t, bc->max[1] + t};
  return mpgm_body_meets_box(bd, lo, hi);
}

/* "enforce", "penalty", "spacing" of a contact boundary: contact at the
 * grid nodes on the plane (default) or at points on the bodies' surfaces
 * held by a penalty (docs/theory.md, "Contact at surface points"). */
static int read_contact_points(jr_node *b, const mpgm_scene *s, mpgm_scene_boundary *bc) {
  static const char *const enforce_names[] = {"nodes", "points", NULL};
  MPGM_CALL(jr_enum(b, "enforce", enforce_names, MPGM_ENFORCE_NODES, &bc->enforce));
  if (bc->enforce != MPGM_ENFORCE_POINTS) {
    if (jr_raw(b, "penalty") || jr_raw(b, "spacing"))
      return jr_fail(b, jr_raw(b, "penalty") ? "penalty" : "spacing",
                     "expected no penalty or spacing with \"enforce\": \"nodes\" (they belong to "
                     "\"enforce\": \"points\")");
    return 0;
  }
  double factor;
  MPGM_CALL(jr_num(b, "penalty", 2.0, 0.0, 1e12, 1, 0, &factor));
  MPGM_CALL(jr_num(b, "spacing", 0.5 * s->h, 0.0, INFINITY, 1, 0, &bc->spacing));
  /* the penalty scales with the stiffest material */
  double E = 0.0;
  for (int i = 0; i < s->nmat; i++)
    for (int k = 0; k < s->mats[i].type->nparam; k++)
      if (strcmp(s->mats[i].type->params[k].name, "E") == 0) E = fmax(E, s->mats[i].param[k]);
  if (!(E > 0.0))
    return jr_fail(b, "penalty", "expected a material with a Young's modulus \"E\" (the penalty is "
                   "a multiple of the largest), found none");
  /* the springs, spread over the plane (k / spacing per unit area), are
   * `factor` times as stiff as a layer of one cell of the body (E / h) */
  bc->penalty = factor * E * bc->spacing / s->h;
  return 0;
}

static int read_boundaries(jr_node *root, mpgm_scene *s) {
  const cJSON *arr = NULL;
  MPGM_CALL(get_array(root, "boundaries", &arr));
  s->nbc = arr ? cJSON_GetArraySize(arr) : 0;
  MPGM_ALLOC(root->r->ctx, s->bcs, s->nbc);
  cJSON *out = cJSON_AddArrayToObject(root->out, "boundaries");
  for (int i = 0; i < s->nbc; i++) {
    jr_node b;
    MPGM_CALL(array_elem(root, "boundaries", arr, i, out, &b));
    mpgm_scene_boundary *bc = &s->bcs[i];
    char def[32];
    snprintf(def, sizeof def, "boundary%d", i);
    MPGM_CALL(jr_str(&b, "name", def, bc->name, sizeof bc->name));
    const cJSON *hx = jr_raw(&b, "x"), *hy = jr_raw(&b, "y"), *hb = jr_raw(&b, "box");
    int nsel = !!hx + !!hy + !!hb;
    if (nsel != 1)
      return jr_fail(&b, NULL, "expected exactly one node selector: \"x\": value, \"y\": value or "
                     "\"box\": {\"min\", \"max\"}, found %d", nsel);
    if (hx || hy) {
      bc->select = hx ? MPGM_SELECT_X : MPGM_SELECT_Y;
      MPGM_CALL(jr_num(&b, hx ? "x" : "y", NAN, -INFINITY, INFINITY, 0, 0, &bc->value));
    } else {
      jr_node box;
      bc->select = MPGM_SELECT_BOX;
      MPGM_CALL(jr_child(&b, "box", 1, &box));
      MPGM_CALL(jr_vec2(&box, "min", NULL, bc->min));
      MPGM_CALL(jr_vec2(&box, "max", NULL, bc->max));
      MPGM_CALL(jr_end(&box));
      if (bc->max[0] < bc->min[0] || bc->max[1] < bc->min[1])
        return jr_fail(&box, NULL, "expected max >= min in x and y, found an inverted box");
    }
    MPGM_CALL(jr_num(&b, "tol", 1e-6 * s->h, 0, INFINITY, 0, 0, &bc->tol));
    /* fem nodes lie on the bodies: a selector that misses every body picks no
     * node (the front end checks the exact node selection when it meshes).
     * mpm grid nodes cover mesh.domain: the selector must meet the domain. */
    const char *selkey = bc->select == MPGM_SELECT_X ? "x" : bc->select == MPGM_SELECT_Y ? "y" : "box";
    if (s->method != MPGM_METHOD_MPM) { /* fem, gmm: persistent nodes of the bodies */
      int meets = 0;
      for (int k = 0; k < s->nbody && !meets; k++)
        meets = selector_meets_body(bc, &s->bodies[k]);
      if (!meets)
        return jr_fail(&b, selkey, "expected a selector that meets a body (only bodies carry nodes), "
                       "found none within tol = %g of it", bc->tol);
    } else {
      mpgm_scene_body dom = {.geometry = MPGM_GEOM_RECTANGLE};
      memcpy(dom.min, s->dom_min, sizeof dom.min);
      memcpy(dom.max, s->dom_max, sizeof dom.max);
      if (!selector_meets_body(bc, &dom))
        return jr_fail(&b, selkey, "expected a selector that meets mesh.domain (the background grid "
                       "covers the domain), found none within tol = %g of it", bc->tol);
    }
    const cJSON *hf = jr_raw(&b, "fix"), *hc = jr_raw(&b, "condition");
    if (hf && hc)
      return jr_fail(&b, NULL, "expected either \"fix\": [...] or \"condition\": \"stick\" | \"slip\", "
                     "found both");
    if (hc) {
      int c;
      MPGM_CALL(jr_enum(&b, "condition", condition_names, -1, &c));
      bc->condition = c + 1;
      if (bc->condition == MPGM_COND_SLIP && bc->select == MPGM_SELECT_BOX)
        return jr_fail(&b, "condition", "\"slip\" fixes the normal component of a plane selector "
                       "(\"x\" or \"y\"); a box selector has no normal (use \"stick\" or \"fix\")");
      if (bc->condition == MPGM_COND_CONTACT) {
        if (bc->select == MPGM_SELECT_BOX)
          return jr_fail(&b, "condition", "\"contact\" needs a plane selector (\"x\" or \"y\"), "
                         "found a box");
        MPGM_CALL(read_contact_points(&b, s, bc));
        if (s->method == MPGM_METHOD_FEM ||
            (s->method == MPGM_METHOD_GMM && bc->enforce != MPGM_ENFORCE_POINTS))
          return jr_fail(&b, "condition", "\"contact\" at grid nodes is a condition of method mpm "
                         "(grid nodes stay on the plane); found method %s%s", mpgm_method_name(s->method),
                         s->method == MPGM_METHOD_GMM ? " (method gmm: \"enforce\": \"points\", or a "
                         "rigid obstacle, top-level \"obstacles\", as in cases/rolling_disk_gmm.json)" : "");
        const int ax = bc->select == MPGM_SELECT_X ? 0 : 1;
        const double tol = 1e-9 * (s->dom_max[ax] - s->dom_min[ax]) + bc->tol;
        if (fabs(bc->value - s->dom_min[ax]) <= tol) bc->side = 1;
        else if (fabs(bc->value - s->dom_max[ax]) <= tol) bc->side = -1;
        else if (bc->enforce == MPGM_ENFORCE_POINTS) {
          /* a plane inside the grid (room for the material to dip into
           * it by the springs' give): the bodies say which side */
          int above = 1, below = 1;
          for (int k = 0; k < s->nbody; k++) {
            above &= s->bodies[k].min[ax] >= bc->value - tol;
            below &= s->bodies[k].max[ax] <= bc->value + tol;
          }
          if (above == below)
            return jr_fail(&b, ax ? "y" : "x", "expected every body on one side of the contact plane "
                           "%c = %g, found bodies on both sides", "xy"[ax], bc->value);
          bc->side = above ? 1 : -1;
        } else
          return jr_fail(&b, ax ? "y" : "x", "expected a contact plane on the boundary of mesh.domain "
                         "(%c = %g or %g, so the body is on one side; a plane inside the domain needs "
                         "\"enforce\": \"points\"), found %g", "xy"[ax],
                         s->dom_min[ax], s->dom_max[ax], bc->value);
      }
      /* the resolved scene keeps "condition" only, so it loads again as is */
      bc->fix[0] = bc->condition != MPGM_COND_SLIP || bc->select == MPGM_SELECT_X;
      bc->fix[1] = bc->condition != MPGM_COND_SLIP || bc->select == MPGM_SELECT_Y;
    } else {
      bc->condition = MPGM_COND_FIX;
      MPGM_CALL(read_fix(&b, "fix", bc->fix));
    }
    const double zero[2] = {0, 0};
    MPGM_CALL(jr_vec2(&b, "displacement", zero, bc->displacement));
    if (s->method == MPGM_METHOD_MPM && (bc->displacement[0] != 0.0 || bc->displacement[1] != 0.0))
      return jr_fail(&b, "displacement", "expected [0, 0] with method mpm (the background grid is reset "
                     "every step; prescribed displacements need persistent nodes: method fem), found "
                     "[%g, %g]", bc->displacement[0], bc->displacement[1]);
    MPGM_CALL(jr_end(&b));
  }
  return 0;
}

/* "obstacles": rigid node layers of method gmm (docs/scene-format.md). */
static int read_obstacles(jr_node *root, mpgm_scene *s) {
  const cJSON *arr = NULL;
  MPGM_CALL(get_array(root, "obstacles", &arr));
  s->nobstacle = arr ? cJSON_GetArraySize(arr) : 0;
  if (!arr) return 0;
  if (s->method != MPGM_METHOD_GMM)
    return jr_fail(root, "obstacles", "obstacles are layers of fixed nodes of method gmm; found method "
                   "%s (method mpm: a \"contact\" boundary on the grid)", mpgm_method_name(s->method));
  if (s->nobstacle > 16) return jr_fail(root, "obstacles", "expected at most 16 obstacles, found %d", s->nobstacle);
  MPGM_ALLOC(root->r->ctx, s->obstacles, s->nobstacle);
  cJSON *out = cJSON_AddArrayToObject(root->out, "obstacles");
  static const char *const sides[2][3] = {{"left", "right", NULL}, {"below", "above", NULL}};
  for (int i = 0; i < s->nobstacle; i++) {
    jr_node o;
    MPGM_CALL(array_elem(root, "obstacles", arr, i, out, &o));
    mpgm_scene_obstacle *ob = &s->obstacles[i];
    char def[32];
    snprintf(def, sizeof def, "obstacle%d", i);
    MPGM_CALL(jr_str(&o, "name", def, ob->name, sizeof ob->name));
    const cJSON *hx = jr_raw(&o, "x"), *hy = jr_raw(&o, "y");
    if (!!hx + !!hy != 1)
      return jr_fail(&o, NULL, "expected exactly one plane: \"x\": value or \"y\": value, found %d",
                     !!hx + !!hy);
    const int ax = hy ? 1 : 0;
    const char *key = ax ? "y" : "x";
    ob->axis = ax;
    MPGM_CALL(jr_num(&o, key, NAN, -INFINITY, INFINITY, 0, 0, &ob->value));
    int sd;
    MPGM_CALL(jr_enum(&o, "side", sides[ax], -1, &sd));
    ob->side = sd ? 1 : -1;
    MPGM_CALL(jr_int(&o, "gap", 1, 1, 16, &ob->gap));
    MPGM_CALL(jr_int(&o, "layers", 2, 1, 16, &ob->layers));
    MPGM_CALL(jr_end(&o));
    /* on a grid line: the layers are aligned with the grid of mesh.domain */
    const double k = (ob->value - s->dom_min[ax]) / s->h;
    if (fabs(k - nearbyint(k)) > 1e-6)
      return jr_fail(&o, key, "expected a plane on a grid line (%c = %g + k h, h = mesh.h = %g), "
                     "found %g", "xy"[ax], s->dom_min[ax], s->h, ob->value);
    /* every body on the free side of the plane (touching it is allowed) */
    const double tol = 1e-9 * s->h;
    for (int b = 0; b < s->nbody; b++) {
      const mpgm_scene_body *bd = &s->bodies[b];
      if (ob->side < 0 ? bd->min[ax] < ob->value - tol : bd->max[ax] > ob->value + tol)
        return jr_fail(&o, key, "expected every body on the free side of the plane (%s %c = %g), "
                       "found body \"%s\" reaching %c = %g", ob->side < 0 ? (ax ? "above" : "right of")
                       : (ax ? "below" : "left of"), "xy"[ax], ob->value, bd->name, "xy"[ax],
                       ob->side < 0 ? bd->min[ax] : bd->max[ax]);
    }
  }
  return 0;
}

static int read_probes(jr_node *root, mpgm_scene *s) {
  const cJSON *map = NULL;
  MPGM_CALL(get_map(root, "probes", &map));
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
    MPGM_CALL(check_name(&q, c->string));
    snprintf(s->probes[i].name, MPGM_NAME_LEN, "%s", c->string);
    MPGM_CALL(jr_vec2(&p, c->string, NULL, s->probes[i].x));
    const double *x = s->probes[i].x;
    int in = 0;
    for (int b = 0; b < s->nbody && !in; b++) in = mpgm_body_contains(&s->bodies[b], x);
    if (!in) return jr_fail(&q, NULL, "expected a position inside a body, found (%g, %g)", x[0], x[1]);
  }
  MPGM_CALL(jr_end(&p));
  return 0;
}

/* output.matrices: a step number (from 1) or an increasing array of them;
 * [] or absent: none. */
static int read_matrices(jr_node *o, mpgm_scene *s) {
  const cJSON *v = jr_override_json(o, "matrices");
  if (!v) v = jr_raw(o, "matrices");
  else jr_raw(o, "matrices");
  s->nmatrices = 0;
  if (v && !cJSON_IsNumber(v) && !cJSON_IsArray(v))
    return jr_fail(o, "matrices", "expected a step number or an array of step numbers, found %s", jr_type(v));
  const int n = !v ? 0 : cJSON_IsNumber(v) ? 1 : cJSON_GetArraySize(v);
  if (n > MPGM_MATRICES_MAX)
    return jr_fail(o, "matrices", "expected at most %d steps, found %d", MPGM_MATRICES_MAX, n);
  for (int i = 0; i < n; i++) {
    const cJSON *c = cJSON_IsNumber(v) ? v : cJSON_GetArrayItem(v, i);
    const long prev = s->nmatrices ? s->matrices[s->nmatrices - 1] : 0;
    if (!cJSON_IsNumber(c))
      return jr_fail(o, "matrices", "expected step numbers (integers from 1), found %s", jr_type(c));
    const double x = c->valuedouble;
    if (!(x == floor(x)) || !(x >= 1.0 && x <= 1e9))
      return jr_fail(o, "matrices", "expected step numbers, integers in [1, 1e9] (the first step is "
                     "1), found %.17g", x);
    if ((long)x <= prev)
      return jr_fail(o, "matrices", "expected increasing step numbers, found %ld after %ld", (long)x, prev);
    s->matrices[s->nmatrices++] = (long)x;
  }
  cJSON *a = cJSON_AddArrayToObject(o->out, "matrices");
  for (int i = 0; i < s->nmatrices; i++) cJSON_AddItemToArray(a, cJSON_CreateNumber((double)s->matrices[i]));
  return 0;
}

static int read_output(jr_node *root, mpgm_scene *s) {
  jr_node o;
  MPGM_CALL(jr_child(root, "output", 0, &o));
  char def[MPGM_PATH_LEN];
  snprintf(def, sizeof def, "results/%s", s->stem);
  MPGM_CALL(jr_str(&o, "dir", def, s->out_dir, sizeof s->out_dir));
  MPGM_CALL(jr_int(&o, "every", 1, 1, 1 << 30, &s->every));
  MPGM_CALL(jr_enum(&o, "vtk", vtk_names, MPGM_VTK_OUT_BINARY, &s->vtk));
  const cJSON *f = jr_override_json(&o, "fields");
  if (!f) f = jr_raw(&o, "fields");
  else jr_raw(&o, "fields");
  s->fields = MPGM_FIELD_ALL;
  if (f) {
    if (!cJSON_IsArray(f)) return jr_fail(&o, "fields", "expected an array of field names, found %s", jr_type(f));
    s->fields = 0;
    for (const cJSON *c = f->child; c; c = c->next) {
      int k = -1;
      for (int i = 0; field_names[i] && cJSON_IsString(c); i++)
        if (strcmp(field_names[i], c->valuestring) == 0) k = i;
      if (k < 0)
        return jr_fail(&o, "fields", "expected field names (displacement, velocity, stress, mass, "
                       "volume, J, material, acceleration, id, eps_p), found %s%s%s%s", jr_type(c),
                       cJSON_IsString(c) ? " \"" : "", cJSON_IsString(c) ? c->valuestring : "",
                       cJSON_IsString(c) ? "\"" : "");
      s->fields |= 1u << k;
    }
  }
  cJSON *a = cJSON_AddArrayToObject(o.out, "fields");
  for (int i = 0; field_names[i]; i++)
    if (s->fields & (1u << i)) cJSON_AddItemToArray(a, cJSON_CreateString(field_names[i]));
  /* times: steps end on them and VTK is written there */
  const cJSON *t = NULL;
  MPGM_CALL(get_array(&o, "times", &t));
  s->ntimes = 0;
  if (t && cJSON_GetArraySize(t) > 64)
    return jr_fail(&o, "times", "expected at most 64 times, found %d", cJSON_GetArraySize(t));
  for (const cJSON *c = t ? t->child : NULL; c; c = c->next) {
    if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble))
      return jr_fail(&o, "times", "expected numbers, found %s", jr_type(c));
    const double v = c->valuedouble, prev = s->ntimes ? s->times[s->ntimes - 1] : 0.0;
    if (!(v > prev))
      return jr_fail(&o, "times", "expected increasing times above 0 (%s), found %g after %g",
                     s->analysis == MPGM_ANALYSIS_DYNAMIC ? "s" : "load factors", v, prev);
    s->times[s->ntimes++] = v;
  }
  cJSON_AddItemToObject(o.out, "times", cJSON_CreateDoubleArray(s->times, s->ntimes));
  MPGM_CALL(read_matrices(&o, s));
  return jr_end(&o);
}

/* Parameters of the meshfree kinds (shape.*; docs/scene-format.md, "shape").
 * The cell-based kind "fe" takes none, so its only key is "kind". The length
 * scale h = mesh.h is set once the mesh is read. */
static int read_shape_params(jr_node *sh, mpgm_scene *s) {
  mpgm_shape_params *p = &s->shape_par;
  memset(p, 0, sizeof *p);
  s->min_nodes = 0;
  s->max_enlarge = 0;
  /* which kinds a method takes: cells for fem, node clouds for gmm, either
   * for mpm (clouds of grid nodes) */
  if (s->shape->needs_cell && s->method == MPGM_METHOD_GMM)
    return jr_fail(sh, "kind", "method gmm needs a meshfree shape kind (\"mls\" or \"lme\"), found "
                   "\"%s\" (\"fe\" is the default; it needs the cells of method fem or mpm)",
                   s->shape->name);
  if (!s->shape->needs_cell && s->method == MPGM_METHOD_FEM)
    return jr_fail(sh, "kind", "method fem takes shape kind \"fe\" only (its connectivity is the "
                   "cells), found the meshfree kind \"%s\" (use method gmm)", s->shape->name);
  if (s->shape->needs_cell) return 0;
  MPGM_CALL(jr_num(sh, "gamma", 1.8, 0.0, INFINITY, 1, 0, &p->gamma));
  MPGM_CALL(jr_num(sh, "tol_support", 1e-6, 0.0, 1.0, 1, 1, &p->tol_support));
  MPGM_CALL(jr_num(sh, "radius", 0.0, 0.0, INFINITY, 0, 0, &p->radius));
  MPGM_CALL(jr_num(sh, "dilation", 2.0, 0.0, INFINITY, 1, 0, &p->dilation));
  MPGM_CALL(jr_int(sh, "order", 1, 1, 2, &p->order));
  MPGM_CALL(jr_num(sh, "max_cond", 0.0, 0.0, INFINITY, 0, 0, &p->max_cond));
  MPGM_CALL(jr_int(sh, "min_nodes", 0, 0, MPGM_SHAPE_MAXNODE, &s->min_nodes));
  MPGM_CALL(jr_int(sh, "max_enlarge", 16, 0, MPGM_SHAPE_MAXNODE, &s->max_enlarge));
  return 0;
}

static int read_scene(jr_node *root, mpgm_scene *s) {
  char desc[2048];
  MPGM_CALL(jr_str(root, "description", "", desc, sizeof desc));
  /* method: the front ends of later issues are named, so the message helps */
  const cJSON *mv = jr_override_json(root, "method");
  if (!mv) mv = jr_raw(root, "method");
  for (int i = 0; mv && cJSON_IsString(mv) && future_methods[i]; i++)
    if (strcmp(mv->valuestring, future_methods[i]) == 0)
      return jr_fail(root, "method", "method \"%s\" is not available in this build yet (expected \"fem\", \"mpm\" or \"gmm\")",
                     mv->valuestring);
  /* re-read through the typed path (consumes the override again: harmless) */
  MPGM_CALL(jr_enum(root, "method", method_names, MPGM_METHOD_FEM, &s->method));

  jr_node sh;
  MPGM_CALL(jr_child(root, "shape", 0, &sh));
  const mpgm_shapefn_type *const *st = mpgm_shapefn_types();
  const char *snames[16];
  int ns = 0;
  for (; st[ns] && ns < 15; ns++) snames[ns] = st[ns]->name;
  snames[ns] = NULL;
  int sk;
  MPGM_CALL(jr_enum(&sh, "kind", snames, 0, &sk));
  s->shape = st[sk];
  MPGM_CALL(read_shape_params(&sh, s));
  MPGM_CALL(jr_end(&sh));

  jr_node mesh, dom;
  MPGM_CALL(jr_child(root, "mesh", 1, &mesh));
  MPGM_CALL(jr_num(&mesh, "h", NAN, 0, INFINITY, 1, 0, &s->h));
  MPGM_CALL(jr_enum(&mesh, "cell", cell_names, MPGM_CELL_Q4, &s->cell));
  MPGM_CALL(jr_int(&mesh, "ppc", s->cell == MPGM_CELL_Q4 ? 4 : 3, 1, 9, &s->ppc));
  MPGM_CALL(jr_num(&mesh, "min_node_mass", 1e-2, 0.0, 0.5, 0, 1, &s->min_node_mass));
  {
    double xi[18], w[9];
    if (mpgm_fe_gauss(s->cell, s->ppc, xi, w))
      return jr_fail(&mesh, "ppc", "expected %s, found %d",
                     s->cell == MPGM_CELL_Q4 ? "1, 4 or 9 points per quad" : "1 or 3 points per triangle", s->ppc);
  }
  MPGM_CALL(jr_child(&mesh, "domain", 1, &dom));
  MPGM_CALL(jr_vec2(&dom, "min", NULL, s->dom_min));
  MPGM_CALL(jr_vec2(&dom, "max", NULL, s->dom_max));
  MPGM_CALL(jr_end(&dom));
  if (!(s->dom_max[0] > s->dom_min[0]) || !(s->dom_max[1] > s->dom_min[1]))
    return jr_fail(&dom, NULL, "expected max > min in x and y, found an empty domain");
  MPGM_CALL(jr_end(&mesh));

  MPGM_CALL(jr_enum(root, "kinematics", kin_names, MPGM_KIN_FINITE, &s->kinematics));
  MPGM_CALL(jr_int(root, "threads", 0, 0, 256, &s->loop_threads));

  jr_node tm;
  MPGM_CALL(jr_child(root, "time", 0, &tm));
  MPGM_CALL(jr_enum(&tm, "analysis", analysis_names, MPGM_ANALYSIS_STATIC, &s->analysis));
  const int dyn = s->analysis == MPGM_ANALYSIS_DYNAMIC;
  MPGM_CALL(jr_num(&tm, "dt", dyn ? NAN : 1.0, 0, INFINITY, 1, 0, &s->dt));
  MPGM_CALL(jr_num(&tm, "end", dyn ? NAN : 1.0, 0, INFINITY, 1, 0, &s->t_end));
  MPGM_CALL(jr_int(&tm, "load_steps", 1, 1, 1 << 24, &s->load_steps));
  MPGM_CALL(jr_num(&tm, "newmark_beta", 0.25, 0, 0.5, 1, 0, &s->beta));
  MPGM_CALL(jr_num(&tm, "newmark_gamma", 0.5, 0.5, 1, 0, 0, &s->gamma));
  static const char *const predictor_names[] = {"zero", "velocity", NULL};
  MPGM_CALL(jr_enum(&tm, "predictor", predictor_names, 0, &s->predictor_velocity));
  MPGM_CALL(jr_int(&tm, "max_cuts", 0, 0, 30, &s->max_cuts));
  MPGM_CALL(jr_int(&tm, "grow_after", 4, 1, 1000000, &s->grow_after));
  static const char *const accel_names[] = {"zero", "equilibrium", NULL};
  MPGM_CALL(jr_enum(&tm, "initial_acceleration", accel_names, 1, &s->initial_accel));
  MPGM_CALL(jr_end(&tm));
  if (dyn && s->dt > s->t_end)
    return jr_fail(&tm, "dt", "expected dt <= end (%g s), found %g s", s->t_end, s->dt);
  if (dyn && s->t_end / s->dt > 1e8)
    return jr_fail(&tm, "dt", "expected at most 1e8 steps, found end/dt = %g", s->t_end / s->dt);

  jr_node so;
  MPGM_CALL(jr_child(root, "solver", 0, &so));
  const mpgm_solver_type *const *svt = mpgm_solver_types();
  const char *svn[16] = {"auto"};
  int nsv = 1;
  for (; svt[nsv - 1] && nsv < 15; nsv++) svn[nsv] = svt[nsv - 1]->name;
  svn[nsv] = NULL;
  int si;
  MPGM_CALL(jr_enum(&so, "linear", svn, 0, &si));
  s->solver = si ? svt[si - 1] : NULL;
  MPGM_CALL(jr_num(&so, "rtol", 1e-9, 0, 1, 1, 1, &s->rtol));
  MPGM_CALL(jr_num(&so, "atol", 1e-10, 0, INFINITY, 0, 0, &s->atol));
  MPGM_CALL(jr_num(&so, "dtol", 1e-10, 0, 1, 1, 1, &s->dtol));
  MPGM_CALL(jr_int(&so, "max_iterations", 25, 1, 1000, &s->max_iter));
  static const char *const newton_names[] = {"full", "modified", NULL};
  MPGM_CALL(jr_enum(&so, "newton", newton_names, 0, &s->newton_modified));
  MPGM_CALL(jr_num(&so, "reuse_ratio", 0.1, 0.0, 1.0, 1, 1, &s->reuse_ratio));
  MPGM_CALL(jr_num(&so, "contact_check", 1e-3, 0.0, 1.0, 0, 1, &s->contact_check));
  static const char *const ordering_names[] = {"backend", "geometric", NULL};
  MPGM_CALL(jr_enum(&so, "ordering", ordering_names, 0, &s->ordering_nd));
  MPGM_CALL(jr_int(&so, "threads", 1, 0, 256, &s->threads));
  /* iterative backends (gmres); the direct ones ignore them */
  s->solver_opts = mpgm_solver_opts_default();
  MPGM_CALL(jr_num(&so, "linear_tol", s->solver_opts.tol, 0, 1, 1, 1, &s->solver_opts.tol));
  MPGM_CALL(jr_int(&so, "linear_restart", s->solver_opts.restart, 1, 1000, &s->solver_opts.restart));
  MPGM_CALL(jr_int(&so, "linear_max_iterations", s->solver_opts.max_iter, 1, 10000000,
                   &s->solver_opts.max_iter));
  MPGM_CALL(jr_end(&so));

  MPGM_CALL(read_materials(root, s));
  for (int i = 0; i < s->nmat; i++) {
    jr_node m = {.r = root->r};
    snprintf(m.path, sizeof m.path, "materials.%s", s->mats[i].name);
    if (s->kinematics == MPGM_KIN_FINITE && !s->mats[i].type->finite)
      return jr_fail(&m, "type", "\"%s\" is a small-strain law: expected kinematics \"small\" or a "
                     "finite-strain material (neo_hookean), found kinematics \"finite\"",
                     s->mats[i].type->name);
    if (s->solver && s->solver->needs_spd && !s->mats[i].symmetric)
      return jr_fail(&m, "type", "material has an unsymmetric tangent: solver.linear \"%s\" needs a "
                     "symmetric matrix (use \"umfpack\" or \"auto\")", s->solver->name);
  }
  MPGM_CALL(read_bodies(root, s));
  MPGM_CALL(read_boundaries(root, s));
  MPGM_CALL(read_obstacles(root, s));
  const double g0[2] = {0, 0};
  MPGM_CALL(jr_vec2(root, "gravity", g0, s->gravity));
  MPGM_CALL(read_probes(root, s));
  MPGM_CALL(mpgm_reference_read(root, s));
  MPGM_CALL(read_output(root, s));
  MPGM_CALL(jr_end(root));
  s->shape_par.h = s->h; /* the meshfree kinds' length scale: mesh.h */
  return 0;
}

/* Split "a.b=value" overrides. */
static int parse_sets(mpgm_ctx *ctx, const char *file, int nset, const char *const *sets,
                      jr_override *ov) {
  for (int i = 0; i < nset; i++) {
    const char *eq = strchr(sets[i], '=');
    MPGM_CHECK(ctx, eq && eq != sets[i], MPGM_ERR_INPUT,
               "%s: %s: expected --set KEY=VALUE with a dotted KEY (e.g. mesh.h=0.125), found "
               "\"%s\"", file, eq ? "(empty key)" : sets[i], sets[i]);
    size_t n = (size_t)(eq - sets[i]);
    MPGM_CHECK(ctx, n < JR_PATH, MPGM_ERR_INPUT, "%s: --set %.40s...: key too long", file, sets[i]);
    memcpy(ov[i].path, sets[i], n);
    ov[i].path[n] = '\0';
    ov[i].value = eq + 1;
  }
  return 0;
}

int mpgm_scene_load(mpgm_ctx *ctx, const char *file, int nset,
                    const char *const *sets, mpgm_scene **out) {
  *out = NULL;
  cJSON *doc = NULL;
  MPGM_CALL(jr_parse_file(ctx, file, &doc));
  mpgm_scene *s = calloc(1, sizeof *s);
  jr_override *ov = calloc(nset ? nset : 1, sizeof *ov);
  int err = (!s || !ov) ? mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory") : 0;
  jr_reader r = {.ctx = ctx, .file = file, .ov = ov, .nov = nset};
  cJSON *resolved = cJSON_CreateObject();
  if (!err) err = parse_sets(ctx, file, nset, sets, ov);
  if (!err) {
    snprintf(s->file, sizeof s->file, "%s", file);
    const char *base = strrchr(file, '/');
    base = base ? base + 1 : file;
    snprintf(s->stem, sizeof s->stem, "%s", base);
    char *dot = strrchr(s->stem, '.');
    if (dot && dot != s->stem) *dot = '\0';
    jr_node root = {.r = &r, .j = doc, .out = resolved};
    err = read_scene(&root, s);
  }
  if (!err) err = jr_unused_overrides(&r);
  cJSON_Delete(r.tmp);
  cJSON_Delete(doc);
  free(ov);
  s ? (void)(s->resolved = resolved) : cJSON_Delete(resolved);
  if (err) {
    mpgm_scene_destroy(&s);
    return err;
  }
  *out = s;
  return 0;
}

void mpgm_scene_destroy(mpgm_scene **sp) {
  if (!sp || !*sp) return;
  mpgm_scene *s = *sp;
  free(s->mats);
  free(s->bodies);
  free(s->bcs);
  free(s->probes);
  free(s->obstacles);
  cJSON_Delete((cJSON *)s->resolved);
  free(s);
  *sp = NULL;
}

char *mpgm_scene_resolved_json(const mpgm_scene *s) {
  return cJSON_Print((const cJSON *)s->resolved);
}
