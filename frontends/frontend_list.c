/* frontend_list.c -- the front ends. Adding one: its own folder with a
 * const mpgm_frontend_type, one line in MPGM_FRONTEND_LIST (the first is
 * the default method). */
#include <string.h>

#include "mpgm_fem.h"
#include "mpgm_frontends.h"
#if MPGM_DIM == 2
#include "mpgm_gmm.h"
#endif
#include "mpgm_mpm.h"

/* 3-D: UL-FEM and MPM (GMM comes with the 3-D meshfree kinds) */
#if MPGM_DIM == 2
#define MPGM_FRONTEND_LIST(X) X(mpgm_frontend_fem) X(mpgm_frontend_mpm) X(mpgm_frontend_gmm)
#else
#define MPGM_FRONTEND_LIST(X) X(mpgm_frontend_fem) X(mpgm_frontend_mpm)
#endif

#define MPGM_ADDR(t) &t,
static const mpgm_frontend_type *const all_types[] = {MPGM_FRONTEND_LIST(MPGM_ADDR) NULL};
#undef MPGM_ADDR

const mpgm_frontend_type *const *mpgm_frontend_types(void) { return all_types; }

const mpgm_frontend_type *mpgm_frontend_type_find(const char *name) {
  for (int i = 0; name && all_types[i]; i++)
    if (strcmp(all_types[i]->name, name) == 0) return all_types[i];
  return NULL;
}
