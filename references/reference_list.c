/* reference_list.c -- the compile-time list of reference kinds (the scene's
 * "reference" block is read in io/scene_reference.c).
 * Adding a kind: write its .c, add one line to MPGM_REFERENCE_LIST. */
#include <string.h>

#include "mpgm_reference.h"

#define MPGM_REFERENCE_LIST(X)                                                 \
  X(mpgm_reference_probe_value)                                                \
  X(mpgm_reference_rolling_disk)                                               \
  X(mpgm_reference_column_wave)                                                \
  X(mpgm_reference_dyka_bar)                                                   \
  X(mpgm_reference_rigid_block)

#define MPGM_DECLARE(t) extern const mpgm_reference_type t;
MPGM_REFERENCE_LIST(MPGM_DECLARE)
#undef MPGM_DECLARE

#define MPGM_ADDR(t) &t,
static const mpgm_reference_type *const all_types[] = {MPGM_REFERENCE_LIST(MPGM_ADDR) NULL};
#undef MPGM_ADDR

const mpgm_reference_type *const *mpgm_reference_types(void) { return all_types; }

const mpgm_reference_type *mpgm_reference_type_find(const char *name) {
  if (!name) return NULL;
  for (int i = 0; all_types[i]; i++)
    if (strcmp(all_types[i]->name, name) == 0) return all_types[i];
  return NULL;
}
