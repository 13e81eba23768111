/* scene_reference.c -- the scene's "reference" block (a kind of the
 * reference family, references/) and the metrics it adds to summary.json. */
#include <cjson/cJSON.h>
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
  ref->x0[0] = s->probes[ref->probe].x[0]; /* 2-D only: x and y */
  ref->x0[1] = s->probes[ref->probe].x[1];
  if (ref->type->needs_component) {
    static const char *const comps[] = {"x", "y", NULL};
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
  if (nrow < 1 || !hist || !metrics_cjson || ref->probe < 0 || ncol < 4 + 2 * ref->probe)
    return MPGM_ERR_INPUT;
  mpgm_metric m[MPGM_REF_MAXMETRIC];
  const int n = ref->type->metrics(ref, nrow, ncol, hist, acc, m);
  for (int i = 0; i < n && i < MPGM_REF_MAXMETRIC; i++)
    cJSON_AddNumberToObject((cJSON *)metrics_cjson, m[i].name, m[i].value);
  return 0;
}
