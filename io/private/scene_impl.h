/* scene_impl.h -- private to io/: pieces of scene loading that live in
 * their own files (scene_bodies.c, scene_boundaries.c, scene_reference.c,
 * scene_solver.c, scene_time.c, scene_keys.c). */
#ifndef MPGM_SCENE_IMPL_H
#define MPGM_SCENE_IMPL_H

#include <stddef.h>

#include "mpgm_json_reader.h"
#include "mpgm_scene_io.h"
#include "mpgm_scene.h"

/** Read the optional top-level "reference" block into s->reference
 *  (after the probes and the time block were read). */
int mpgm_reference_read(jr_node *root, mpgm_scene *s);
/** Read the optional "manufactured" block into s->mms (after the
 *  materials, the bodies and the time block), checking that every body
 *  lies where the solution is defined. */
int mpgm_scene_read_manufactured(jr_node *root, mpgm_scene *s);

/** A name of a material, body or probe, usable in dotted paths: 1 to
 *  MPGM_NAME_LEN - 1 letters, digits, '_' or '-'. */
int mpgm_scene_check_name(jr_node *o, const char *name);
/** An object-valued key whose members are named entries (materials,
 *  probes); *map NULL when absent. */
int mpgm_scene_get_map(jr_node *o, const char *key, const cJSON **map);
/** "bodies" (after the materials and the mesh) and "probes" (after the
 *  bodies) (scene_bodies.c). */
int mpgm_scene_read_bodies(jr_node *root, mpgm_scene *s);
int mpgm_scene_read_probes(jr_node *root, mpgm_scene *s);
/** The array at key (NULL when absent; an --set override replaces it);
 *  bad input when it is not an array. */
int mpgm_scene_get_array(jr_node *o, const char *key, const cJSON **arr);
/** Element i of array arr (at key) as an object node with path "key.i";
 *  its resolved copy is appended to out_arr. */
int mpgm_scene_array_elem(jr_node *o, const char *key, const cJSON *arr, int i, cJSON *out_arr,
                          jr_node *e);
/** "boundaries" and "obstacles" (scene_boundaries.c; after the bodies). */
int mpgm_scene_read_boundaries(jr_node *root, mpgm_scene *s);
int mpgm_scene_read_obstacles(jr_node *root, mpgm_scene *s);
/** The side of every contact plane the bodies are on (after the front end
 *  accepted the contact boundaries): +1 for a plane on the lower end of
 *  mesh.domain, -1 on the upper end; a plane inside the domain (contact at
 *  points) by where the bodies are. Errors: MPGM_ERR_INPUT. */
int mpgm_scene_contact_sides(mpgm_ctx *ctx, mpgm_scene *s);

/** "time": the explicit schemes' keys (refused with the other analyses)
 *  and Newmark's or HHT's parameters (scene_time.c); analysis: the name of
 *  s->analysis, for messages. */
int mpgm_scene_read_explicit(jr_node *tm, mpgm_scene *s, const char *analysis);
int mpgm_scene_read_newmark(jr_node *tm, mpgm_scene *s, const char *analysis);
/** "time": time.dt, a number (s) or {"cells": k, "speed": c}, the time a
 *  wave of c m/s takes to cross k cells, k (h / c) (scene_time.c; after
 *  mesh.h). def and lo_open as jr_num takes them. */
int mpgm_scene_read_dt(jr_node *tm, mpgm_scene *s, double def, int lo_open);
/** "time", explicit analysis, after every reader of the block: a key of
 *  another explicit scheme refused by its name (scene_time.c). */
int mpgm_scene_scheme_keys_end(jr_node *tm, const mpgm_scene *s);
/** "time": time.max_steps and the fixed steps against it (scene_time.c;
 *  after dt, end and load_steps). */
int mpgm_scene_read_max_steps(jr_node *tm, mpgm_scene *s);

/** The keys of table keys (n of them) into the struct at base, each with
 *  its type, default and range (scene_keys.c). */
int mpgm_scene_read_keys(jr_node *o, const mpgm_key_spec *keys, int n, void *base);
/** A plug-in that declares keys of a section (shape kinds, front ends,
 *  time schemes), for the refusal of its keys in another's scene: what
 *  selects it ("shape.kind", "method", "time.scheme"), its name, its
 *  table. */
typedef struct mpgm_key_owner {
  const char *what, *name;
  const mpgm_key_spec *keys;
  int nkeys;
} mpgm_key_owner;
/** After o's readers: each key of o (in the file, or --set o.KEY) they did
 *  not take that one of others declares is refused, "a key of OWNERS, not
 *  of MINE (expected one of: ...)" and, for a key of the file, hint; in a
 *  run's own record (!s->from_file) it is passed over. A key nobody
 *  declares is left to jr_end and the overrides' check (scene_keys.c). */
int mpgm_scene_foreign_keys(jr_node *o, const mpgm_scene *s, const mpgm_key_owner *others, int n,
                            const char *mine, const char *hint);
/** mpgm_scene_foreign_keys for the member NAME of a family selected by
 *  WHAT ("method", "solver.linear", "time.scheme"): "not of WHAT
 *  \"NAME\"", no hint (scene_keys.c). */
int mpgm_scene_member_keys_end(jr_node *o, const mpgm_scene *s, const char *what, const char *name,
                               const mpgm_key_owner *others, int n);
/** "shape" sh beyond "kind" (after the method and the kind): the kind's
 *  keys into s->shape_par, the front end's into s->pattern; a key of
 *  another kind or front end, in the file or in --set shape.KEY, is
 *  refused naming its owners (scene_keys.c). */
int mpgm_scene_read_shape_keys(jr_node *sh, mpgm_scene *s);

/** "mesh", after every reader of the block: a key of another front end's
 *  rules for its nodes (mpgm_frontend_type.mesh_keys), in the file or in
 *  --set mesh.KEY, refused by its name (scene_keys.c). */
int mpgm_scene_mesh_keys_end(jr_node *mesh, const mpgm_scene *s);

/** "solver": the linear backend, its options and Newton's settings
 *  (scene_solver.c; after "time", whose analysis decides whether PETSc is
 *  loaded, and after "boundaries", on which contact_check's default
 *  depends). */
int mpgm_scene_read_solver(jr_node *root, mpgm_scene *s);

#endif
