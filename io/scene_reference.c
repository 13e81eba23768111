/* scene_reference.c -- the scene's "reference" block (a kind of the
 * reference family, references/) and the metrics it adds to summary.json;
 * the "manufactured" block (an exact solution that drives the run). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "scene_impl.h"


int mpgm_reference_read(jr_node *root, mpgm_scene *s) {
  mpgm_reference *ref = &s->reference;
  memset(ref, 0, sizeof *ref);
  /* absent: no reference (and no empty block in the resolved scene) */
  const cJSON *v = jr_override_json(root, "reference");
  if (!v) v = jr_raw(root, "reference");
  if (!v) return 0;
  jr_node r;
  MPGM_CALL(jr_child(root, "reference", 1, &r));
  const mpgm_reference_type *const *all_types = mpgm_reference_types();
  const char *names[16];
  int nk = 0;
  for (; all_types[nk] && nk < 15; nk++) names[nk] = all_types[nk]->name;
  names[nk] = NULL;
  int k;
  MPGM_CALL(jr_enum(&r, "kind", names, -1, &k));
  ref->type = all_types[k];
  char pname[MPGM_NAME_LEN];
  MPGM_CALL(jr_str(&r, "probe", NULL, pname, sizeof pname));
  ref->probe = -1;
  for (int i = 0; i < s->nprobe; i++)
    if (strcmp(s->probes[i].name, pname) == 0) ref->probe = i;
  if (ref->probe < 0) {
    char list[512] = "";
    for (int i = 0; i < s->nprobe; i++) {
      size_t l = strlen(list);
      snprintf(list + l, sizeof list - l, "%s\"%s\"", i ? ", " : "", s->probes[i].name);
    }
    return jr_fail(&r, "probe", "expected the name of a probe defined in probes (%s), found \"%s\"",
                   s->nprobe ? list : "none defined", pname);
  }
  memcpy(ref->x0, s->probes[ref->probe].x, sizeof ref->x0);
  if (ref->type->needs_component) {
    static const char *const comps[] = {"x", "y", MPGM_DIM == 3 ? "z" : NULL, NULL};
    MPGM_CALL(jr_enum(&r, "component", comps, -1, &ref->component));
  }
  for (int p = 0; p < ref->type->nparam && p < MPGM_REF_MAXPARAM; p++) {
    const mpgm_param_spec *ps = &ref->type->params[p];
    MPGM_CALL(jr_num(&r, ps->name, ps->def, ps->lo, ps->hi, ps->lo_open, ps->hi_open, &ref->param[p]));
  }
  MPGM_CALL(jr_end(&r));
  if (ref->type->needs_dynamic && s->analysis == MPGM_ANALYSIS_STATIC)
    return jr_fail(&r, "kind", "reference \"%s\" compares a time history: expected time.analysis "
                   "\"dynamic\" or \"explicit\", found \"static\"", ref->type->name);
  return 0;
}

#if MPGM_DIM == 2
/* Where a manufactured solution holds: the vibration on the strip
 * 0 <= x <= L (it does not depend on y; rollers carry its stress on every
 * side), the ring and the vortex on the annulus ri <= R <= ro about the
 * origin, whose circles they leave free of traction (the ring for nu = 0).
 * A body must be that domain, not only lie in it: a face of a body inside
 * it would need the solution's traction, which no scene applies, and the
 * errors would mean nothing. */
static int mms_domain_check(jr_node *root, const mpgm_scene *s) {
  const mpgm_mms *m = &s->mms;
  const int strip = m->kind == MPGM_MMS_VIBRATION;
  const char *name = strip ? "vibration" : m->kind == MPGM_MMS_RING ? "ring" : "vortex";
  const double tol = 1e-9 * (strip ? m->L : m->ro);
  for (int i = 0; i < s->nbody; i++) {
    const mpgm_scene_body *b = &s->bodies[i];
    char found[160];
    if (strip) {
      if (b->geometry == MPGM_GEOM_RECTANGLE && fabs(b->min[0]) <= tol && fabs(b->max[0] - m->L) <= tol)
        continue;
      if (b->geometry == MPGM_GEOM_RECTANGLE)
        snprintf(found, sizeof found, "a rectangle from x = %.9g to %.9g m", b->min[0], b->max[0]);
      else
        snprintf(found, sizeof found, "a body that is not a rectangle");
      return jr_fail(root, "manufactured", "solution \"vibration\" holds on the strip 0 <= x <= L = %g m "
                     "(manufactured.L): expected every body to be a rectangle from x = 0 to L, found "
                     "body \"%s\", %s", m->L, b->name, found);
    }
    if (b->geometry == MPGM_GEOM_RING && hypot(b->centre[0], b->centre[1]) <= tol &&
        fabs(b->radius_in - m->ri) <= tol && fabs(b->radius - m->ro) <= tol)
      continue;
    if (b->geometry == MPGM_GEOM_RING)
      snprintf(found, sizeof found, "a ring centred at (%.9g, %.9g) m from R = %.9g to %.9g m",
               b->centre[0], b->centre[1], b->radius_in, b->radius);
    else
      snprintf(found, sizeof found, "a body that is not a ring");
    return jr_fail(root, "manufactured", "solution \"%s\" holds on the annulus %g <= R <= %g m about "
                   "the origin (manufactured.ri, ro): expected every body to be a ring centred at the "
                   "origin with inner %g and outer %g, found body \"%s\", %s", name, m->ri, m->ro,
                   m->ri, m->ro, b->name, found);
  }
  return 0;
}
#endif

/* "manufactured" (optional): a manufactured solution of Tran et al. 2019
 * section 4 drives the run (docs/theory.md section 21). Its law is the
 * neo-Hookean one: the scene has one material of that type, finite
 * kinematics and a dynamic or explicit analysis; E, nu and the density
 * are the material's. */
int mpgm_scene_read_manufactured(jr_node *root, mpgm_scene *s) {
  if (!jr_raw(root, "manufactured") && !jr_override_json(root, "manufactured")) return 0;
#if MPGM_DIM != 2 /* their fields and domains are plane (references/mms.c) */
  (void)s;
  return jr_fail(root, "manufactured", "the manufactured solutions are plane strain: expected no "
                 "\"manufactured\" in a 3-D scene");
#else
  jr_node mn;
  MPGM_CALL(jr_child(root, "manufactured", 1, &mn));
  static const char *const names[] = {"vibration", "ring", "vortex", NULL};
  int k;
  MPGM_CALL(jr_enum(&mn, "solution", names, -1, &k));
  mpgm_mms *m = &s->mms;
  memset(m, 0, sizeof *m);
  MPGM_CALL(mpgm_mms_parse_kind(names[k], &m->kind) ? MPGM_ERR_INTERNAL : 0);
  MPGM_CALL(jr_num(&mn, "A", NAN, 0.0, INFINITY, 1, 0, &m->A));
  if (m->kind != MPGM_MMS_RING) MPGM_CALL(jr_num(&mn, "L", 1.0, 0.0, INFINITY, 1, 0, &m->L));
  if (m->kind != MPGM_MMS_VIBRATION) {
    const int ring = m->kind == MPGM_MMS_RING;
    MPGM_CALL(jr_num(&mn, "ri", ring ? 0.4 : 0.75, 0.0, INFINITY, 1, 0, &m->ri));
    MPGM_CALL(jr_num(&mn, "ro", ring ? 0.6 : 1.25, 0.0, INFINITY, 1, 0, &m->ro));
    if (!(m->ro > m->ri)) return jr_fail(&mn, "ro", "expected ro > ri = %g, found %g", m->ri, m->ro);
  }
  MPGM_CALL(jr_end(&mn));
  if (s->analysis == MPGM_ANALYSIS_STATIC)
    return jr_fail(root, "manufactured", "a motion in time: expected time.analysis \"dynamic\" or "
                   "\"explicit\", found \"static\"");
  if (s->nmat != 1 || strcmp(s->mats[0].type->name, "neo_hookean") != 0 ||
      s->kinematics != MPGM_KIN_FINITE)
    return jr_fail(root, "manufactured", "the solutions are derived for the neo-Hookean law: expected "
                   "one material of type \"neo_hookean\" and kinematics \"finite\", found %d "
                   "material(s)%s%s", s->nmat, s->nmat ? ", the first " : "",
                   s->nmat ? s->mats[0].type->name : "");
  m->E = mpgm_material_param(&s->mats[0], "E");
  m->nu = mpgm_material_param(&s->mats[0], "nu");
  m->rho0 = s->mats[0].density;
  s->manufactured = 1;
  return mms_domain_check(root, s);
#endif
}

void mpgm_reference_observe(const mpgm_scene *s, double t, double dt, const mpgm_points *P,
                            double *acc) {
  const mpgm_reference *ref = &s->reference;
  if (!ref->type || !ref->type->observe) return;
  const mpgm_ref_points pts = {.n = P->n, .x0 = P->x0, .x = P->x, .v = P->v, .sigma = P->sigma};
  ref->type->observe(ref, t, dt, &pts, acc);
}

int mpgm_reference_metrics(const mpgm_scene *s, int nrow, int ncol, const double *hist,
                           const double *acc, void *metrics_cjson) {
  const mpgm_reference *ref = &s->reference;
  if (!ref->type) return 0;
  if (nrow < 1 || !hist || !metrics_cjson || ref->probe < 0 || ncol < mpgm_ref_column(ref->probe + 1, 0))
    return MPGM_ERR_INPUT;
  mpgm_metric m[MPGM_REF_MAXMETRIC];
  const int n = ref->type->metrics(ref, nrow, ncol, hist, acc, m);
  for (int i = 0; i < n && i < MPGM_REF_MAXMETRIC; i++)
    cJSON_AddNumberToObject((cJSON *)metrics_cjson, m[i].name, m[i].value);
  return 0;
}
