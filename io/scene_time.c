/* scene_time.c -- the time integrator's keys of the "time" block: the
 * explicit schemes, and Newmark's or HHT's parameters of the implicit
 * dynamic one. */
#include <stdio.h>

#include "mpgm_integrator.h"
#include "mpgm_json_reader.h"
#include "scene_impl.h"

/* Bad input at the first of keys[0..n) that the scene (or an --set)
 * gives: "why" says why it may not be given here. */
static int refuse_keys(jr_node *tm, const char *const *keys, int n, const char *why) {
  for (int i = 0; i < n; i++)
    if (jr_raw(tm, keys[i]) || jr_override_json(tm, keys[i])) return jr_fail(tm, keys[i], "%s", why);
  return 0;
}

/* "time", explicit analysis: the scheme (an explicit member of the
 * integrator family), the CFL number, the predictor's gamma. The keys are
 * refused with the other analyses, whose integrator ignores them. */
int mpgm_scene_read_explicit(jr_node *tm, mpgm_scene *s, const char *analysis) {
  static const char *const keys[] = {"scheme", "cfl", "npc_gamma", "npc_position",
                                     "local_damping", "kinetic_damping"};
  if (s->analysis != MPGM_ANALYSIS_EXPLICIT) {
    char why[96];
    snprintf(why, sizeof why, "only with time.analysis \"explicit\", found \"%s\"", analysis);
    return refuse_keys(tm, keys, 6, why);
  }
  const mpgm_integrator_type *const *it = mpgm_integrator_types();
  const mpgm_integrator_type *ex[16];
  const char *names[16];
  int n = 0;
  for (int i = 0; it[i] && n < 15; i++)
    if (!it[i]->implicit) {
      ex[n] = it[i];
      names[n++] = it[i]->name;
    }
  names[n] = NULL;
  MPGM_CHECK(tm->r->ctx, n > 0, MPGM_ERR_INTERNAL, "no explicit integrator in this build");
  int k; /* the first explicit integrator of the list is the default */
  MPGM_CALL(jr_enum(tm, "scheme", names, 0, &k));
  s->integrator = ex[k];
  MPGM_CALL(jr_num(tm, "cfl", 0.1, 0.0, 1.0, 1, 0, &s->cfl));
  MPGM_CALL(jr_num(tm, "npc_gamma", 0.5, 0.0, 1.0, 0, 0, &s->npc_gamma));
  static const char *const position_names[] = {"newmark", "eq34", NULL};
  MPGM_CALL(jr_enum(tm, "npc_position", position_names, 0, &s->npc_eq34));
  MPGM_CALL(jr_num(tm, "local_damping", 0.0, 0.0, 1.0, 0, 1, &s->local_damping));
  MPGM_CALL(jr_bool(tm, "kinetic_damping", 0, &s->kinetic_damping));
  return 0;
}

/* "time": Newmark's beta and gamma, or the alpha of Hilber, Hughes and
 * Taylor (1977) in [-1/3, 0], which sets them (beta = (1 - alpha)^2 / 4,
 * gamma = 1/2 - alpha) and weights the forces (docs/theory.md section 5).
 * alpha 0, the default: Newmark with beta and gamma as given. */
int mpgm_scene_read_newmark(jr_node *tm, mpgm_scene *s, const char *analysis) {
  MPGM_CALL(jr_num(tm, "hht_alpha", 0.0, -1.0 / 3.0, 0.0, 0, 0, &s->hht_alpha));
  if (s->hht_alpha == 0.0) {
    MPGM_CALL(jr_num(tm, "newmark_beta", 0.25, 0, 0.5, 1, 0, &s->beta));
    return jr_num(tm, "newmark_gamma", 0.5, 0.5, 1, 0, 0, &s->gamma);
  }
  if (s->analysis != MPGM_ANALYSIS_DYNAMIC)
    return jr_fail(tm, "hht_alpha", "only with time.analysis \"dynamic\", found \"%s\"", analysis);
  static const char *const keys[] = {"newmark_beta", "newmark_gamma"};
  char why[128];
  snprintf(why, sizeof why, "set by time.hht_alpha (%g): beta = (1 - alpha)^2 / 4, gamma = "
           "1/2 - alpha; give one or the other", s->hht_alpha);
  MPGM_CALL(refuse_keys(tm, keys, 2, why));
  s->beta = 0.25 * (1.0 - s->hht_alpha) * (1.0 - s->hht_alpha);
  s->gamma = 0.5 - s->hht_alpha;
  return 0;
}
