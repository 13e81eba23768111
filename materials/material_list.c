/* material_list.c -- the compile-time list of material implementations.
 * Adding a material: write its .c, add one line to MPGM_MATERIAL_LIST. */
#include "mpgm_material.h"

#include <math.h>
#include <string.h>

#define MPGM_MATERIAL_LIST(X)                                                  \
  X(mpgm_material_linear_elastic)                                              \
  X(mpgm_material_neo_hookean)                                                 \
  X(mpgm_material_mohr_coulomb)

#define MPGM_DECLARE(t) extern const mpgm_material_type t;
MPGM_MATERIAL_LIST(MPGM_DECLARE)
#undef MPGM_DECLARE

#define MPGM_ADDR(t) &t,
static const mpgm_material_type *const all_types[] = {
    MPGM_MATERIAL_LIST(MPGM_ADDR) NULL};
#undef MPGM_ADDR

/** All material implementations, NULL-terminated. */
const mpgm_material_type *const *mpgm_material_types(void) {
  return all_types;
}

double mpgm_material_param(const mpgm_material *m, const char *name) {
  for (int i = 0; i < m->type->nparam; i++)
    if (strcmp(m->type->params[i].name, name) == 0) return m->param[i];
  return NAN;
}

/** The implementation with scene name `name`; NULL if none (or name NULL). */
const mpgm_material_type *mpgm_material_type_find(const char *name) {
  if (!name) return NULL;
  for (int i = 0; all_types[i]; i++)
    if (strcmp(all_types[i]->name, name) == 0) return all_types[i];
  return NULL;
}
