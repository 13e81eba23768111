/* shapefn_list.c -- the compile-time list of shape-function kinds.
 * Adding a kind: write its .c, add one line to MPGM_SHAPEFN_LIST. */
#include "mpgm_shapefn.h"

#include <string.h>

#define MPGM_SHAPEFN_LIST(X) X(mpgm_shapefn_fe)

#define MPGM_DECLARE(t) extern const mpgm_shapefn_type t;
MPGM_SHAPEFN_LIST(MPGM_DECLARE)
#undef MPGM_DECLARE

#define MPGM_ADDR(t) &t,
static const mpgm_shapefn_type *const all_types[] = {
    MPGM_SHAPEFN_LIST(MPGM_ADDR) NULL};
#undef MPGM_ADDR

const mpgm_shapefn_type *const *mpgm_shapefn_types(void) { return all_types; }

const mpgm_shapefn_type *mpgm_shapefn_type_find(const char *name) {
  for (int i = 0; all_types[i]; i++)
    if (strcmp(all_types[i]->name, name) == 0) return all_types[i];
  return NULL;
}
