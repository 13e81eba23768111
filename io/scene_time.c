/* scene_time.c -- the time integrator's keys of the "time" block: the
 * explicit schemes, Newmark's or HHT's parameters of the implicit dynamic
 * one, and the bound on the number of steps (time.max_steps). */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

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

/* With an implicit analysis: the keys of the explicit schemes, theirs in
 * common and each scheme's own, refused. */
static int refuse_explicit(jr_node *tm, const char *analysis) {
  static const char *const keys[] = {"scheme", "cfl", "local_damping", "kinetic_damping",
                                     "allow_unstable_dt"};
  char why[96];
  snprintf(why, sizeof why, "only with time.analysis \"explicit\", found \"%s\"", analysis);
  MPGM_CALL(refuse_keys(tm, keys, 5, why));
  for (const mpgm_integrator_type *const *it = mpgm_integrator_types(); *it; it++)
    for (int k = 0; !(*it)->implicit && k < (*it)->nkeys; k++) {
      const char *key = (*it)->keys[k].name;
      if (jr_raw(tm, key) || jr_override_json(tm, key))
        return jr_fail(tm, key, "%s (a key of time.scheme \"%s\")", why, (*it)->name);
    }
  return 0;
}

/* "time", explicit analysis: the scheme (an explicit member of the
 * integrator family), the CFL number, the damping, and the scheme's own
 * keys (its table: npc's gamma and position). The keys are refused with
 * the other analyses, whose integrator ignores them. */
int mpgm_scene_read_explicit(jr_node *tm, mpgm_scene *s, const char *analysis) {
  memset(&s->scheme, 0, sizeof s->scheme);
  if (s->analysis != MPGM_ANALYSIS_EXPLICIT) return refuse_explicit(tm, analysis);
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
  /* below MPGM_CFL_MIN a step only multiplies the run's steps (a cfl of
   * 1e-300 made steps of 1e-150 s, a run that never ends) */
  MPGM_CALL(jr_num(tm, "cfl", 0.1, MPGM_CFL_MIN, 1.0, 0, 0, &s->cfl));
  MPGM_CALL(mpgm_scene_read_keys(tm, s->integrator->keys, s->integrator->nkeys, &s->scheme));
  MPGM_CALL(jr_num(tm, "local_damping", 0.0, 0.0, 1.0, 0, 1, &s->local_damping));
  MPGM_CALL(jr_bool(tm, "kinetic_damping", 0, &s->kinetic_damping));
  /* a fixed step above the stability limit fails the run (core/explicit.c)
   * unless the scene asks for it; with CFL steps there is no such step */
  if (s->dt > 0.0) return jr_bool(tm, "allow_unstable_dt", 0, &s->allow_unstable_dt);
  static const char *const fixed[] = {"allow_unstable_dt"};
  MPGM_CALL(refuse_keys(tm, fixed, 1, "only with a fixed time.dt (steps from time.cfl are "
                        "within the stability limit), found none"));
  return 0;
}

/* "time", explicit analysis, after its readers: a key of another explicit
 * scheme refused by that scheme's name. */
int mpgm_scene_scheme_keys_end(jr_node *tm, const mpgm_scene *s) {
  if (s->analysis != MPGM_ANALYSIS_EXPLICIT) return 0;
  mpgm_key_owner others[16];
  int n = 0;
  for (const mpgm_integrator_type *const *it = mpgm_integrator_types(); *it && n < 16; it++)
    if (*it != s->integrator && !(*it)->implicit)
      others[n++] = (mpgm_key_owner){"time.scheme", (*it)->name, (*it)->keys, (*it)->nkeys};
  return mpgm_scene_member_keys_end(tm, s, "time.scheme", s->integrator->name, others, n);
}

/* "time": time.max_steps, the most steps of the run, and the fixed steps
 * (end / dt, or load_steps) against it, so that a run that could not end
 * within it is refused before it starts (steps from the CFL condition and
 * cut steps are counted as the run goes, core/run.c). */
int mpgm_scene_read_max_steps(jr_node *tm, mpgm_scene *s) {
  MPGM_CALL(jr_int(tm, "max_steps", MPGM_MAX_STEPS_DEFAULT, 1, INT_MAX, &s->max_steps));
  if (s->analysis == MPGM_ANALYSIS_STATIC && s->load_steps > s->max_steps)
    return jr_fail(tm, "load_steps", "expected at most time.max_steps = %d steps, found %d: fewer "
                   "load steps or a larger time.max_steps", s->max_steps, s->load_steps);
  if (s->analysis == MPGM_ANALYSIS_STATIC || !(s->dt > 0.0)) return 0;
  /* the steps of a run without cuts, but for those output.times adds */
  const double n = ceil(s->t_end / s->dt * (1.0 - 1e-9));
  if (n > (double)s->max_steps)
    return jr_fail(tm, "dt", "expected at most time.max_steps = %d steps, found end / dt = %.4g "
                   "steps (end %g s, dt %g s): a larger time.dt or time.max_steps", s->max_steps,
                   n, s->t_end, s->dt);
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

/* "time.dt": seconds, or {"cells": k, "speed": c}: the time a wave of
 * c m/s takes to cross k cells of mesh.h, k (h / c), so that a fixed step
 * said as a fraction of h / c (the manufactured solutions' 0.4 h / c)
 * follows a finer mesh.h. h / c is divided first: for the cases' h and c
 * the product then is the double of the step written in seconds (0.4 (0.025
 * / 100) is 1e-4; (0.4 0.025) / 100 is not). */
int mpgm_scene_read_dt(jr_node *tm, mpgm_scene *s, double def, int lo_open) {
  const cJSON *v = jr_override_json(tm, "dt");
  if (!v) v = jr_raw(tm, "dt");
  else jr_raw(tm, "dt");
  if (!cJSON_IsObject(v)) return jr_num(tm, "dt", def, 0, INFINITY, lo_open, 0, &s->dt);
  if (s->analysis == MPGM_ANALYSIS_STATIC)
    return jr_fail(tm, "dt", "a step in cells, {\"cells\": k, \"speed\": c}, is a time step: "
                   "expected time.analysis \"dynamic\" or \"explicit\", found \"static\"");
  jr_node d = {.r = tm->r, .j = v}; /* no mirror: the resolved scene holds the step in seconds */
  snprintf(d.path, sizeof d.path, "time.dt");
  double k, c;
  MPGM_CALL(jr_num(&d, "cells", NAN, 0.0, INFINITY, 1, 0, &k));
  MPGM_CALL(jr_num(&d, "speed", NAN, 0.0, INFINITY, 1, 0, &c));
  MPGM_CALL(jr_end(&d));
  s->dt = k * (s->h / c);
  if (!(s->dt > 0.0 && isfinite(s->dt)))
    return jr_fail(tm, "dt", "expected a positive finite step, found k (h / c) = %g s", s->dt);
  if (tm->out) cJSON_AddNumberToObject(tm->out, "dt", s->dt);
  return 0;
}
