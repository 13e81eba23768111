/* mpgm_frontends.h -- the list of front ends (frontend_list.c) and the
 * check of a scene against its front end's traits (frontend_check.c).
 * Adding a front end: its own folder and type record (mpgm_frontend.h),
 * one line in MPGM_FRONTEND_LIST, one library in CMakeLists.txt. */
#ifndef MPGM_FRONTENDS_H
#define MPGM_FRONTENDS_H

#include "mpgm_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** All front ends, NULL-terminated; the first is the scene's default
 *  "method". */
const mpgm_frontend_type *const *mpgm_frontend_types(void);
/** The front end named `name`; NULL if none (or name NULL). */
const mpgm_frontend_type *mpgm_frontend_type_find(const char *name);

/** Check a loaded scene against its front end (s->frontend): the shape
 *  kind, the bodies' geometries, every boundary (its selector meets what
 *  carries the front end's nodes: a body, or mesh.domain for a grid; its
 *  condition; its prescribed displacement) and the obstacles against the
 *  front end's traits, then the front end's own check. Errors:
 *  MPGM_ERR_INPUT with "FILE: json.path: expected ..., found ...", naming
 *  the methods that would take what was refused. */
int mpgm_frontend_check(mpgm_ctx *ctx, const mpgm_scene *s);

#ifdef __cplusplus
}
#endif
#endif
