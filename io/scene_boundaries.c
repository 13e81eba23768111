/* scene_boundaries.c -- the "boundaries" and "obstacles" of a scene:
 * node selectors, conditions (stick, slip, contact at grid nodes or at
 * surface points), prescribed displacements, and the rigid
 * obstacles (docs/scene-format.md). Called by scene.c's read_scene. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_json_reader.h"
#include "scene_impl.h"

static const char *const condition_names[] = {"stick", "slip", "contact", NULL}; /* = mpgm_condition - 1 */

/* the components' names, and the forms of "fix" for messages */
static const char *const comp_names[] = {"x", "y", "z"};
#if MPGM_DIM == 2
#define FIX_FORMS "[\"x\"], [\"y\"] or [\"x\", \"y\"]"
#define COMP_FORMS "\"x\" or \"y\""
#else
#define FIX_FORMS "1 to 3 of \"x\", \"y\", \"z\" (e.g. [\"z\"] or [\"x\", \"y\", \"z\"])"
#define COMP_FORMS "\"x\", \"y\" or \"z\""
#endif

static int read_fix(jr_node *o, const char *key, int fix[MPGM_DIM]) {
  const cJSON *v = jr_override_json(o, key);
  if (!v) v = jr_raw(o, key);
  else jr_raw(o, key);
  if (!v)
    return jr_fail(o, key, "required key is missing (expected \"fix\": " FIX_FORMS ", "
                   "or \"condition\": \"stick\" | \"slip\")");
  for (int d = 0; d < MPGM_DIM; d++) fix[d] = 0;
  if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) < 1 || cJSON_GetArraySize(v) > MPGM_DIM)
    return jr_fail(o, key, "expected " FIX_FORMS ", found %s%s", jr_type(v),
                   cJSON_IsArray(v) ? " of another length" : "");
  for (const cJSON *c = v->child; c; c = c->next) {
    int d = -1;
    for (int k = 0; k < MPGM_DIM && cJSON_IsString(c); k++)
      if (strcmp(c->valuestring, comp_names[k]) == 0) d = k;
    if (d < 0) return jr_fail(o, key, "expected components " COMP_FORMS ", found %s%s%s%s", jr_type(c),
                              cJSON_IsString(c) ? " \"" : "", cJSON_IsString(c) ? c->valuestring : "",
                              cJSON_IsString(c) ? "\"" : "");
    if (fix[d]) return jr_fail(o, key, "component \"%s\" listed twice", c->valuestring);
    fix[d] = 1;
  }
  cJSON *a = cJSON_AddArrayToObject(o->out, key);
  for (int d = 0; d < MPGM_DIM; d++)
    if (fix[d]) cJSON_AddItemToArray(a, cJSON_CreateString(comp_names[d]));
  return 0;
}

/* The selector of bc meets body bd within bc->tol: lines against the body's
 * extent across them (exact for any connected body), boxes against the
 * body itself. */
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
  double E = 0.0; /* fmax ignores the NAN of a material without E */
  for (int i = 0; i < s->nmat; i++) E = fmax(E, mpgm_material_param(&s->mats[i], "E"));
  if (!(E > 0.0))
    return jr_fail(b, "penalty", "expected a material with a Young's modulus \"E\" (the penalty is "
                   "a multiple of the largest), found none");
  /* the springs, spread over the plane (k / spacing per unit area), are
   * `factor` times as stiff as a layer of one cell of the body (E / h) */
  bc->penalty = factor * E * bc->spacing / s->h;
  return 0;
}

/* The node selector of a boundary: exactly one of a plane "x", "y" (or
 * "z" in 3-D) = value, or a "box" {min, max}. */
static int read_selector(jr_node *b, mpgm_scene_boundary *bc) {
  const cJSON *hp[MPGM_DIM], *hb = jr_raw(b, "box");
  int nsel = !!hb, plane = -1;
  for (int d = 0; d < MPGM_DIM; d++) {
    hp[d] = jr_raw(b, comp_names[d]);
    nsel += !!hp[d];
    if (hp[d]) plane = d;
  }
  if (nsel != 1)
    return jr_fail(b, NULL, "expected exactly one node selector: %s or \"box\": {\"min\", \"max\"}, "
                   "found %d", MPGM_DIM == 2 ? "\"x\": value, \"y\": value" :
                   "\"x\": value, \"y\": value, \"z\": value", nsel);
  if (plane >= 0) {
    bc->select = plane; /* = MPGM_SELECT_X, _Y, _Z */
    return jr_len(b, comp_names[plane], NAN, -INFINITY, INFINITY, &bc->value);
  }
  jr_node box;
  bc->select = MPGM_SELECT_BOX;
  MPGM_CALL(jr_child(b, "box", 1, &box));
  MPGM_CALL(jr_vec_len(&box, "min", NULL, bc->min));
  MPGM_CALL(jr_vec_len(&box, "max", NULL, bc->max));
  MPGM_CALL(jr_end(&box));
  for (int d = 0; d < MPGM_DIM; d++)
    if (bc->max[d] < bc->min[d])
      return jr_fail(&box, NULL, "expected max >= min in %s, found an inverted box",
                     MPGM_DIM == 2 ? "x and y" : "x, y and z");
  return 0;
}

int mpgm_scene_read_boundaries(jr_node *root, mpgm_scene *s) {
  const cJSON *arr = NULL;
  MPGM_CALL(mpgm_scene_get_array(root, "boundaries", &arr));
  s->nbc = arr ? cJSON_GetArraySize(arr) : 0;
  MPGM_ALLOC(root->r->ctx, s->bcs, s->nbc);
  cJSON *out = cJSON_AddArrayToObject(root->out, "boundaries");
  for (int i = 0; i < s->nbc; i++) {
    jr_node b;
    MPGM_CALL(mpgm_scene_array_elem(root, "boundaries", arr, i, out, &b));
    mpgm_scene_boundary *bc = &s->bcs[i];
    char def[32];
    snprintf(def, sizeof def, "boundary%d", i);
    MPGM_CALL(jr_str(&b, "name", def, bc->name, sizeof bc->name));
    MPGM_CALL(read_selector(&b, bc));
    MPGM_CALL(jr_len(&b, "tol", 1e-6 * s->h, 0, INFINITY, &bc->tol));
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
                       "(" COMP_FORMS "); a box selector has no normal (use \"stick\" or \"fix\")");
      if (MPGM_DIM == 3 && bc->condition == MPGM_COND_CONTACT)
        return jr_fail(&b, "condition", "contact is plane strain for now: expected \"stick\" or "
                       "\"slip\" in a 3-D scene, found \"contact\"");
      if (bc->condition == MPGM_COND_CONTACT) {
        if (bc->select == MPGM_SELECT_BOX)
          return jr_fail(&b, "condition", "\"contact\" needs a plane selector (\"x\" or \"y\"), "
                         "found a box");
        MPGM_CALL(read_contact_points(&b, s, bc));
      }
      /* the resolved scene keeps "condition" only, so it loads again as is */
      for (int d = 0; d < MPGM_DIM; d++) /* slip: the plane's normal, x, y or z */
        bc->fix[d] = bc->condition != MPGM_COND_SLIP || (int)bc->select == d;
    } else {
      bc->condition = MPGM_COND_FIX;
      MPGM_CALL(read_fix(&b, "fix", bc->fix));
    }
    const double zero[MPGM_DIM] = {0};
    MPGM_CALL(jr_vec(&b, "displacement", zero, bc->displacement));
    MPGM_CALL(jr_end(&b));
  }
  return 0;
}

int mpgm_scene_contact_sides(mpgm_ctx *ctx, mpgm_scene *s) {
  for (int i = 0; i < s->nbc; i++) {
    mpgm_scene_boundary *bc = &s->bcs[i];
    if (bc->condition != MPGM_COND_CONTACT) continue;
    const int ax = bc->select == MPGM_SELECT_X ? 0 : 1;
    const double tol = 1e-9 * (s->dom_max[ax] - s->dom_min[ax]) + bc->tol;
    if (fabs(bc->value - s->dom_min[ax]) <= tol) {
      bc->side = 1;
    } else if (fabs(bc->value - s->dom_max[ax]) <= tol) {
      bc->side = -1;
    } else if (bc->enforce == MPGM_ENFORCE_POINTS) {
      /* a plane inside the grid (room for the material to dip into it by
       * the springs' give): the bodies say which side */
      int above = 1, below = 1;
      for (int k = 0; k < s->nbody; k++) {
        above &= s->bodies[k].min[ax] >= bc->value - tol;
        below &= s->bodies[k].max[ax] <= bc->value + tol;
      }
      MPGM_CHECK(ctx, above != below, MPGM_ERR_INPUT, "%s: boundaries.%d.%c: expected every body on "
                 "one side of the contact plane %c = %g, found bodies on both sides", s->file, i,
                 "xy"[ax], "xy"[ax], bc->value);
      bc->side = above ? 1 : -1;
    } else {
      MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: boundaries.%d.%c: expected a contact plane on the "
                 "boundary of mesh.domain (%c = %g or %g, so the body is on one side; a plane inside "
                 "the domain needs \"enforce\": \"points\"), found %g", s->file, i, "xy"[ax],
                 "xy"[ax], s->dom_min[ax], s->dom_max[ax], bc->value);
    }
  }
  return 0;
}

/* "obstacles": rigid node layers (the front ends that take them:
 * mpgm_frontend_type.obstacles; docs/scene-format.md). */
int mpgm_scene_read_obstacles(jr_node *root, mpgm_scene *s) {
  const cJSON *arr = NULL;
  MPGM_CALL(mpgm_scene_get_array(root, "obstacles", &arr));
  s->nobstacle = arr ? cJSON_GetArraySize(arr) : 0;
  if (!arr) return 0;
  if (MPGM_DIM == 3)
    return jr_fail(root, "obstacles", "the rigid node layers are plane strain for now: expected no "
                   "\"obstacles\" in a 3-D scene");
  if (s->nobstacle > 16) return jr_fail(root, "obstacles", "expected at most 16 obstacles, found %d", s->nobstacle);
  MPGM_ALLOC(root->r->ctx, s->obstacles, s->nobstacle);
  cJSON *out = cJSON_AddArrayToObject(root->out, "obstacles");
  static const char *const sides[2][3] = {{"left", "right", NULL}, {"below", "above", NULL}};
  for (int i = 0; i < s->nobstacle; i++) {
    jr_node o;
    MPGM_CALL(mpgm_scene_array_elem(root, "obstacles", arr, i, out, &o));
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

