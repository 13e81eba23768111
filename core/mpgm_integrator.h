/* mpgm_integrator.h -- the time-integrator family: how a step is solved
 * and committed once the front end has begun it (nodes, connectivity,
 * nodal history). One .c per integrator exports a const type record; the
 * list is core/integrator_list.c. Integrators are members of the core:
 * they work on the core's problem, which no one else sees. */
#ifndef MPGM_INTEGRATOR_H
#define MPGM_INTEGRATOR_H

#include "mpgm_base.h"

#ifdef __cplusplus
extern "C" {
#endif

struct mpgm_problem;

typedef struct mpgm_integrator_type {
  const char *name; /**< "implicit", ...                                   */
  const char *doc;  /**< one line for docs                                 */
  int implicit;     /**< 1: assembles and factorises a tangent             */
  /** Optional: the integrator's own data for a problem (*self). */
  int (*create)(struct mpgm_problem *pb, void **self);
  /** Optional: release it (accepts NULL). */
  void (*destroy)(void *self);
  /** Solve the step from pb's time t to t + dt and commit points and
   *  nodes. On a recoverable failure (> 0) nothing is committed and the
   *  run loop may cut the step. */
  int (*step)(void *self, struct mpgm_problem *pb);
  /** Optional: the largest step the scheme allows from pb's present state
   *  (a stability limit, e.g. CFL); the run loop takes the smaller of it
   *  and the scene's step. Called before every step. NAN, with the
   *  reason recorded in pb->ctx, when the scene's own fixed step may not
   *  be taken from this state (an explicit time.dt above the stability
   *  limit): the run fails at that step, without a cut. */
  double (*dt_limit)(void *self, const struct mpgm_problem *pb);
  /** Its own keys of the scene's "time" block (nkeys of them), read into
   *  mpgm_scene.scheme; another scheme's scene refuses them by this
   *  scheme's name. */
  const mpgm_key_spec *keys;
  int nkeys;
} mpgm_integrator_type;

/** The integrator named `name`; NULL if none. */
const mpgm_integrator_type *mpgm_integrator_type_find(const char *name);
/** All integrators, NULL-terminated. */
const mpgm_integrator_type *const *mpgm_integrator_types(void);

#ifdef __cplusplus
}
#endif
#endif
