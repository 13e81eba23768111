/* integrator_list.c -- the time integrators. Adding one: write its .c with
 * a const mpgm_integrator_type, add one line to MPGM_INTEGRATOR_LIST. */
#include <string.h>

#include "mpgm_integrator.h"

#define MPGM_INTEGRATOR_LIST(X) \
  X(mpgm_integrator_implicit) X(mpgm_integrator_npc) X(mpgm_integrator_fe) X(mpgm_integrator_usl)

#define MPGM_DECLARE(t) extern const mpgm_integrator_type t;
MPGM_INTEGRATOR_LIST(MPGM_DECLARE)
#undef MPGM_DECLARE

#define MPGM_ADDR(t) &t,
static const mpgm_integrator_type *const all_types[] = {MPGM_INTEGRATOR_LIST(MPGM_ADDR) NULL};
#undef MPGM_ADDR

const mpgm_integrator_type *const *mpgm_integrator_types(void) { return all_types; }

const mpgm_integrator_type *mpgm_integrator_type_find(const char *name) {
  for (int i = 0; name && all_types[i]; i++)
    if (strcmp(all_types[i]->name, name) == 0) return all_types[i];
  return NULL;
}
