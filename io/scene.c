/* scene.c -- load and validate a scene file (docs/scene-format.md). */
#include "mpgm_scene_io.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_frontends.h"
#include "mpgm_json_reader.h"
#include "scene_impl.h"

static const char *const cell_names[] = {"tri", "quad", "hex", NULL}; /* = mpgm_cell_kind */
static const char *const kin_names[] = {"finite", "small", NULL};
static const char *const analysis_names[] = {"static", "dynamic", "explicit", NULL};
static const char *const vtk_names[] = {"none", "ascii", "binary", NULL};
static const char *const format_names[] = {"vtu", "vtk", "xdmf", NULL}; /* = mpgm_format bits */
static const char *const compress_names[] = {"none", "zlib", NULL};    /* = mpgm_compress */
static const char *const field_names[] = {"displacement", "velocity", "stress", "mass",
                                          "volume", "J", "material", "acceleration", "id", "eps_p",
                                          "body", NULL};

/* Names of materials, bodies, probes: usable in dotted paths. */
int mpgm_scene_check_name(jr_node *o, const char *name) {
  size_t n = strlen(name);
  if (n == 0 || n >= MPGM_NAME_LEN)
    return jr_fail(o, NULL, "expected a name of 1 to %d characters, found \"%s\"",
                   MPGM_NAME_LEN - 1, name);
  for (size_t i = 0; i < n; i++)
    if (!(isalnum((unsigned char)name[i]) || name[i] == '_' || name[i] == '-'))
      return jr_fail(o, NULL, "expected a name of letters, digits, '_' or '-', found \"%s\"", name);
  return 0;
}

/* An object-valued key whose members are named entries (materials, probes).
 * *map is NULL when absent. */
int mpgm_scene_get_map(jr_node *o, const char *key, const cJSON **map) {
  const cJSON *v = jr_override_json(o, key);
  if (!v) v = jr_raw(o, key);
  else jr_raw(o, key);
  if (v && !cJSON_IsObject(v)) return jr_fail(o, key, "expected an object of named entries, found %s", jr_type(v));
  *map = v;
  return 0;
}

int mpgm_scene_get_array(jr_node *o, const char *key, const cJSON **arr) {
  const cJSON *v = jr_override_json(o, key);
  if (!v) v = jr_raw(o, key);
  else jr_raw(o, key);
  if (v && !cJSON_IsArray(v)) return jr_fail(o, key, "expected an array, found %s", jr_type(v));
  *arr = v;
  return 0;
}

/* Element i of an array as a node with path "key.i". */
int mpgm_scene_array_elem(jr_node *o, const char *key, const cJSON *arr, int i,
                           cJSON *out_arr, jr_node *e) {
  memset(e, 0, sizeof *e);
  e->r = o->r;
  if (snprintf(e->path, sizeof e->path, "%s%s%s.%d", o->path, o->path[0] ? "." : "", key, i) >=
      (int)sizeof e->path)
    return jr_fail(o, key, "path too long");
  e->j = cJSON_GetArrayItem(arr, i);
  if (!cJSON_IsObject(e->j)) return jr_fail(e, NULL, "expected an object, found %s", jr_type(e->j));
  e->out = cJSON_CreateObject();
  cJSON_AddItemToArray(out_arr, e->out);
  return 0;
}

/* One material entry: type, density, the type's parameters, setup. */
static int read_material(jr_node *m, mpgm_material *mat) {
  const mpgm_material_type *const *all = mpgm_material_types();
  const char *choices[16];
  int nt = 0;
  for (; all[nt] && nt < 15; nt++) choices[nt] = all[nt]->name;
  choices[nt] = NULL;
  int t;
  MPGM_CALL(jr_enum(m, "type", choices, -1, &t));
  mat->type = all[t];
  MPGM_CALL(jr_num(m, "density", NAN, 0, INFINITY, 1, 0, &mat->density));
  for (int p = 0; p < mat->type->nparam; p++) {
    const mpgm_param_spec *ps = &mat->type->params[p];
    MPGM_CALL(jr_num(m, ps->name, ps->def, ps->lo, ps->hi, ps->lo_open, ps->hi_open,
                     &mat->param[p]));
  }
  MPGM_CALL(jr_end(m));
  char msg[256] = "";
  if (mat->type->setup(mat, msg, sizeof msg)) return jr_fail(m, NULL, "%s", msg);
  return 0;
}

static int read_materials(jr_node *root, mpgm_scene *s) {
  const cJSON *map = NULL;
  MPGM_CALL(mpgm_scene_get_map(root, "materials", &map));
  if (!map || !map->child) return jr_fail(root, "materials", "expected at least one named material, found none");
  s->nmat = cJSON_GetArraySize(map);
  MPGM_ALLOC(root->r->ctx, s->mats, s->nmat);
  cJSON *outmap = cJSON_AddObjectToObject(root->out, "materials");
  int i = 0;
  for (const cJSON *c = map->child; c; c = c->next, i++) {
    jr_node m = {.r = root->r, .j = c};
    snprintf(m.path, sizeof m.path, "materials.%s", c->string);
    MPGM_CALL(mpgm_scene_check_name(&m, c->string));
    for (const cJSON *d = map->child; d != c; d = d->next)
      if (strcmp(d->string, c->string) == 0) return jr_fail(&m, NULL, "duplicate material name");
    if (!cJSON_IsObject(c)) return jr_fail(&m, NULL, "expected an object, found %s", jr_type(c));
    m.out = cJSON_AddObjectToObject(outmap, c->string);
    mpgm_material *mat = &s->mats[i];
    snprintf(mat->name, sizeof mat->name, "%s", c->string);
    MPGM_CALL(read_material(&m, mat));
  }
  return 0;
}

int mpgm_material_load(mpgm_ctx *ctx, const char *file, const char *path, const void *json,
                       mpgm_material *mat) {
  jr_reader r = {.ctx = ctx, .file = file};
  jr_node m = {.r = &r, .j = json};
  snprintf(m.path, sizeof m.path, "%s", path);
  if (!cJSON_IsObject((const cJSON *)json)) {
    int err = jr_fail(&m, NULL, "expected a material object, found %s", jr_type(json));
    return err;
  }
  cJSON *out = cJSON_CreateObject();
  m.out = out;
  int err = read_material(&m, mat);
  cJSON_Delete(out);
  cJSON_Delete(r.tmp);
  return err;
}

/* output.matrices: a step (from 1) or an increasing array of them ([]: none). */
static int read_matrices(jr_node *o, mpgm_scene *s) {
  const cJSON *v = jr_override_json(o, "matrices");
  if (!v) v = jr_raw(o, "matrices");
  else jr_raw(o, "matrices");
  s->nmatrices = 0;
  if (v && !cJSON_IsNumber(v) && !cJSON_IsArray(v))
    return jr_fail(o, "matrices", "expected a step number or an array of step numbers, found %s", jr_type(v));
  const int n = !v ? 0 : cJSON_IsNumber(v) ? 1 : cJSON_GetArraySize(v);
  if (n > MPGM_MATRICES_MAX)
    return jr_fail(o, "matrices", "expected at most %d steps, found %d", MPGM_MATRICES_MAX, n);
  for (int i = 0; i < n; i++) {
    const cJSON *c = cJSON_IsNumber(v) ? v : cJSON_GetArrayItem(v, i);
    const long prev = s->nmatrices ? s->matrices[s->nmatrices - 1] : 0;
    if (!cJSON_IsNumber(c))
      return jr_fail(o, "matrices", "expected step numbers (integers from 1), found %s", jr_type(c));
    const double x = c->valuedouble;
    if (!(x == floor(x)) || !(x >= 1.0 && x <= 1e9))
      return jr_fail(o, "matrices", "expected step numbers, integers in [1, 1e9] (the first step is "
                     "1), found %.17g", x);
    if ((long)x <= prev)
      return jr_fail(o, "matrices", "expected increasing step numbers, found %ld after %ld", (long)x, prev);
    s->matrices[s->nmatrices++] = (long)x;
  }
  cJSON *a = cJSON_AddArrayToObject(o->out, "matrices");
  for (int i = 0; i < s->nmatrices; i++) cJSON_AddItemToArray(a, cJSON_CreateNumber((double)s->matrices[i]));
  return 0;
}

/* output.format: one format name or an array of them (each once); the
 * resolved scene holds the array. */
static int read_formats(jr_node *o, mpgm_scene *s) {
  const cJSON *v = jr_override_json(o, "format");
  if (!v) v = jr_raw(o, "format");
  else jr_raw(o, "format");
  s->formats = MPGM_FORMAT_VTU;
  if (v) {
    if (!cJSON_IsString(v) && !(cJSON_IsArray(v) && v->child))
      return jr_fail(o, "format", "expected \"vtu\", \"vtk\" or \"xdmf\", or a non-empty array "
                     "of them, found %s", jr_type(v));
    s->formats = 0;
    for (const cJSON *c = cJSON_IsArray(v) ? v->child : v; c; c = cJSON_IsArray(v) ? c->next : NULL) {
      int k = -1;
      for (int i = 0; format_names[i] && cJSON_IsString(c); i++)
        if (strcmp(format_names[i], c->valuestring) == 0) k = i;
      if (k < 0)
        return jr_fail(o, "format", "expected the formats vtu, vtk or xdmf, found %s%s%s%s", jr_type(c),
                       cJSON_IsString(c) ? " \"" : "", cJSON_IsString(c) ? c->valuestring : "",
                       cJSON_IsString(c) ? "\"" : "");
      if (s->formats & (1u << k))
        return jr_fail(o, "format", "expected each format once, found \"%s\" twice", format_names[k]);
      s->formats |= 1u << k;
    }
  }
  cJSON *a = cJSON_AddArrayToObject(o->out, "format");
  for (int i = 0; format_names[i]; i++)
    if (s->formats & (1u << i)) cJSON_AddItemToArray(a, cJSON_CreateString(format_names[i]));
  return 0;
}

static int read_output(jr_node *root, mpgm_scene *s) {
  jr_node o;
  MPGM_CALL(jr_child(root, "output", 0, &o));
  char def[MPGM_PATH_LEN];
  snprintf(def, sizeof def, "results/%s", s->stem);
  const int from_scene = s->from_file && jr_raw(&o, "dir") && !jr_override_json(&o, "dir");
  MPGM_CALL(jr_str(&o, "dir", def, s->out_dir, sizeof s->out_dir));
  if (!s->out_dir[0]) return jr_fail(&o, "dir", "expected a folder path, found an empty string");
  if (from_scene && !mpgm_path_below(s->out_dir))
    return jr_fail(&o, "dir", "a scene names its results folder below the current folder (a scene "
                   "from elsewhere must not write outside it): expected a relative path without "
                   "'..', found \"%s\"; give that folder with --out DIR or --set output.dir=DIR",
                   s->out_dir);
  MPGM_CALL(jr_int(&o, "every", 1, 1, 1 << 30, &s->every));
  MPGM_CALL(jr_int(&o, "checkpoint_every", 0, 0, 1 << 30, &s->checkpoint_every));
  MPGM_CALL(jr_enum(&o, "vtk", vtk_names, MPGM_VTK_OUT_BINARY, &s->vtk));
  MPGM_CALL(read_formats(&o, s));
  MPGM_CALL(jr_enum(&o, "compress", compress_names, MPGM_COMPRESS_NONE, &s->compress));
  MPGM_CALL(jr_bool(&o, "grid", 0, &s->grid));
  const cJSON *f = jr_override_json(&o, "fields");
  if (!f) f = jr_raw(&o, "fields");
  else jr_raw(&o, "fields");
  s->fields = MPGM_FIELD_ALL;
  if (f) {
    if (!cJSON_IsArray(f)) return jr_fail(&o, "fields", "expected an array of field names, found %s", jr_type(f));
    s->fields = 0;
    for (const cJSON *c = f->child; c; c = c->next) {
      int k = -1;
      for (int i = 0; field_names[i] && cJSON_IsString(c); i++)
        if (strcmp(field_names[i], c->valuestring) == 0) k = i;
      if (k < 0)
        return jr_fail(&o, "fields", "expected field names (displacement, velocity, stress, mass, "
                       "volume, J, material, acceleration, id, eps_p, body), found %s%s%s%s", jr_type(c),
                       cJSON_IsString(c) ? " \"" : "", cJSON_IsString(c) ? c->valuestring : "",
                       cJSON_IsString(c) ? "\"" : "");
      s->fields |= 1u << k;
    }
  }
  cJSON *a = cJSON_AddArrayToObject(o.out, "fields");
  for (int i = 0; field_names[i]; i++)
    if (s->fields & (1u << i)) cJSON_AddItemToArray(a, cJSON_CreateString(field_names[i]));
  /* times: steps end on them and VTK is written there */
  const cJSON *t = NULL;
  MPGM_CALL(mpgm_scene_get_array(&o, "times", &t));
  s->ntimes = 0;
  if (t && cJSON_GetArraySize(t) > 64)
    return jr_fail(&o, "times", "expected at most 64 times, found %d", cJSON_GetArraySize(t));
  for (const cJSON *c = t ? t->child : NULL; c; c = c->next) {
    if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble))
      return jr_fail(&o, "times", "expected numbers, found %s", jr_type(c));
    const double v = c->valuedouble, prev = s->ntimes ? s->times[s->ntimes - 1] : 0.0;
    if (!(v > prev))
      return jr_fail(&o, "times", "expected increasing times above 0 (%s), found %g after %g",
                     s->analysis != MPGM_ANALYSIS_STATIC ? "s" : "load factors", v, prev);
    s->times[s->ntimes++] = v;
  }
  cJSON_AddItemToObject(o.out, "times", cJSON_CreateDoubleArray(s->times, s->ntimes));
  MPGM_CALL(read_matrices(&o, s));
  return jr_end(&o);
}

/* "mesh": cell size, cell kind, points per cell, the light-node and
 * close-node rules, the domain. */
static int read_mesh(jr_node *root, mpgm_scene *s) {
  jr_node mesh, dom;
  MPGM_CALL(jr_child(root, "mesh", 1, &mesh));
  MPGM_CALL(jr_num(&mesh, "h", NAN, 0, INFINITY, 1, 0, &s->h));
  root->r->h = s->h; /* the cell of the lengths given in cells from here on */
  MPGM_CALL(jr_enum(&mesh, "cell", cell_names, MPGM_DIM == 2 ? MPGM_CELL_Q4 : MPGM_CELL_H8, &s->cell));
  if (MPGM_DIM == 2 && s->cell == MPGM_CELL_H8)
    return jr_fail(&mesh, "cell", "a hexahedron is a 3-D cell: expected \"quad\" or \"tri\" in a "
                   "plane-strain scene, found \"hex\"");
  if (MPGM_DIM == 3 && s->cell != MPGM_CELL_H8)
    return jr_fail(&mesh, "cell", "a 3-D scene's cells are hexahedra: expected \"hex\", found \"%s\"",
                   cell_names[s->cell]);
  const int ppc0 = s->cell == MPGM_CELL_H8 ? 8 : s->cell == MPGM_CELL_Q4 ? 4 : 3;
  MPGM_CALL(jr_int(&mesh, "ppc", ppc0, 1, MPGM_MAXRULE, &s->ppc));
  memset(&s->mesh_par, 0, sizeof s->mesh_par); /* the method's rules for its nodes */
  MPGM_CALL(mpgm_scene_read_keys(&mesh, s->frontend->mesh_keys, s->frontend->nmesh_keys, &s->mesh_par));
  static const char *const layout_names[] = {"gauss", "centres", NULL};
  /* a kind with particle domains (CPDI) tiles the body with them: the
   * sub-cell squares of quads (cubes of hexahedra) */
  const int centres = s->shape->domain && s->cell != MPGM_CELL_T3;
  MPGM_CALL(jr_enum(&mesh, "layout", layout_names, centres, &s->layout_centres));
  if (s->layout_centres && s->cell == MPGM_CELL_T3)
    return jr_fail(&mesh, "layout", "\"centres\" splits a square cell into ppc equal squares: "
                   "expected cell \"quad\", found \"tri\"");
  {
    double xi[MPGM_DIM * MPGM_MAXRULE], w[MPGM_MAXRULE];
    if (mpgm_fe_gauss(s->cell, s->ppc, xi, w))
      return jr_fail(&mesh, "ppc", "expected %s, found %d",
                     s->cell == MPGM_CELL_H8   ? "1, 8 or 27 points per hexahedron"
                     : s->cell == MPGM_CELL_Q4 ? "1, 4 or 9 points per quad"
                                               : "1 or 3 points per triangle", s->ppc);
  }
  /* the scene's dimension (the domain's coordinates) was matched to this
   * build's before (scene_dimension) */
  MPGM_CALL(jr_child(&mesh, "domain", 1, &dom));
  MPGM_CALL(jr_vec_len(&dom, "min", NULL, s->dom_min));
  MPGM_CALL(jr_vec_len(&dom, "max", NULL, s->dom_max));
  MPGM_CALL(jr_end(&dom));
  for (int d = 0; d < MPGM_DIM; d++)
    if (!(s->dom_max[d] > s->dom_min[d]))
      return jr_fail(&dom, NULL, "expected max > min in %s, found an empty domain",
                     MPGM_DIM == 2 ? "x and y" : "x, y and z");
  MPGM_CALL(mpgm_scene_mesh_keys_end(&mesh, s));
  MPGM_CALL(jr_end(&mesh));

  return 0;
}

/* "time": analysis, step and end (dynamic) or load steps (static),
 * Newmark parameters, predictor, step control, initial acceleration. */
static int read_time(jr_node *root, mpgm_scene *s) {
  jr_node tm;
  MPGM_CALL(jr_child(root, "time", 0, &tm));
  MPGM_CALL(jr_enum(&tm, "analysis", analysis_names, MPGM_ANALYSIS_STATIC, &s->analysis));
  const int dyn = s->analysis != MPGM_ANALYSIS_STATIC;
  const int expl = s->analysis == MPGM_ANALYSIS_EXPLICIT;
  /* explicit: dt 0 (the default) takes each step from the CFL condition */
  MPGM_CALL(mpgm_scene_read_dt(&tm, s, expl ? 0.0 : dyn ? NAN : 1.0, !expl));
  MPGM_CALL(jr_num(&tm, "end", dyn ? NAN : 1.0, 0, INFINITY, 1, 0, &s->t_end));
  MPGM_CALL(jr_int(&tm, "load_steps", 1, 1, 1 << 24, &s->load_steps));
  MPGM_CALL(mpgm_scene_read_newmark(&tm, s, analysis_names[s->analysis]));
  static const char *const predictor_names[] = {"zero", "velocity", NULL};
  MPGM_CALL(jr_enum(&tm, "predictor", predictor_names, 0, &s->predictor_velocity));
  MPGM_CALL(jr_int(&tm, "max_cuts", 0, 0, 30, &s->max_cuts));
  MPGM_CALL(jr_int(&tm, "grow_after", 4, 1, 1000000, &s->grow_after));
  MPGM_CALL(jr_bool(&tm, "grow_backoff", 0, &s->grow_backoff));
  static const char *const mass_names[] = {"consistent", "lumped", NULL};
  if (s->analysis != MPGM_ANALYSIS_DYNAMIC && (jr_raw(&tm, "mass") || jr_override_json(&tm, "mass")))
    return jr_fail(&tm, "mass", "only with time.analysis \"dynamic\" (explicit schemes always "
                   "lump the mass), found \"%s\"", analysis_names[s->analysis]);
  if (s->analysis == MPGM_ANALYSIS_DYNAMIC)
    MPGM_CALL(jr_enum(&tm, "mass", mass_names, 0, &s->lumped_mass));
  static const char *const accel_names[] = {"zero", "equilibrium", NULL};
  MPGM_CALL(jr_enum(&tm, "initial_acceleration", accel_names, 1, &s->initial_accel));
  MPGM_CALL(mpgm_scene_read_explicit(&tm, s, analysis_names[s->analysis]));
  MPGM_CALL(mpgm_scene_read_max_steps(&tm, s));
  MPGM_CALL(mpgm_scene_scheme_keys_end(&tm, s));
  MPGM_CALL(jr_end(&tm));
  if (dyn && s->dt > s->t_end)
    return jr_fail(&tm, "dt", "expected dt <= end (%g s), found %g s", s->t_end, s->dt);
  if (dyn && s->dt > 0.0 && s->t_end / s->dt > 1e8)
    return jr_fail(&tm, "dt", "expected at most 1e8 steps, found end/dt = %g", s->t_end / s->dt);
  return 0;
}

/* In a 3-D scene, the value of o.key (after --set) when it names one of
 * the plane-strain-only names: an error saying so, not an unknown name. */
static int refuse_plane_only(jr_node *o, const char *key, const char *const *names, const char *what) {
  if (MPGM_DIM == 2) return 0;
  const cJSON *v = jr_override_json(o, key);
  if (!v && o->j) v = cJSON_GetObjectItemCaseSensitive(o->j, key);
  for (int k = 0; cJSON_IsString(v) && names[k]; k++)
    if (strcmp(v->valuestring, names[k]) == 0)
      return jr_fail(o, key, "%s \"%s\" is plane strain for now: not in a 3-D scene", what, names[k]);
  return 0;
}

static int read_scene(jr_node *root, mpgm_scene *s) {
  static const char *const plane_methods[] = {"gmm", NULL};
  static const char *const plane_kinds[] = {"mls", "lme", "cpls", NULL};
  char desc[2048];
  MPGM_CALL(jr_str(root, "description", "", desc, sizeof desc));
  /* method: a front end of the list (the first is the default) */
  const mpgm_frontend_type *const *ft = mpgm_frontend_types();
  const char *fnames[16];
  int nf = 0;
  for (; ft[nf] && nf < 15; nf++) fnames[nf] = ft[nf]->name;
  fnames[nf] = NULL;
  int fi;
  MPGM_CALL(refuse_plane_only(root, "method", plane_methods, "method"));
  MPGM_CALL(jr_enum(root, "method", fnames, 0, &fi));
  s->frontend = ft[fi];

  jr_node sh;
  MPGM_CALL(jr_child(root, "shape", 0, &sh));
  const mpgm_shapefn_type *const *st = mpgm_shapefn_types();
  const char *snames[16];
  int ns = 0;
  for (; st[ns] && ns < 15; ns++) snames[ns] = st[ns]->name;
  snames[ns] = NULL;
  int sk;
  MPGM_CALL(refuse_plane_only(&sh, "kind", plane_kinds, "shape function"));
  MPGM_CALL(jr_enum(&sh, "kind", snames, 0, &sk));
  s->shape = st[sk];
  MPGM_CALL(mpgm_scene_read_shape_keys(&sh, s));
  MPGM_CALL(jr_end(&sh));

  MPGM_CALL(read_mesh(root, s));
  /* uGIMP: a particle's square is its share of its cell, ppc to a cell */
  if (s->shape->grid_only) /* (a cube's in 3-D) */
    s->shape_par.half_width = s->h / (2.0 * (MPGM_DIM == 2 ? sqrt((double)s->ppc) : cbrt((double)s->ppc)));
  MPGM_CALL(jr_enum(root, "kinematics", kin_names, MPGM_KIN_FINITE, &s->kinematics));
  MPGM_CALL(jr_int(root, "threads", 0, 0, 256, &s->loop_threads));

  MPGM_CALL(read_time(root, s));
  /* static and dynamic analyses: the implicit Newmark integrator (explicit:
   * time.scheme, read_explicit) */
  if (s->analysis != MPGM_ANALYSIS_EXPLICIT) s->integrator = mpgm_integrator_type_find("implicit");
  MPGM_CHECK(root->r->ctx, s->integrator, MPGM_ERR_INTERNAL, "no implicit integrator in this build");
  if (s->shape->velocity_ls && strcmp(s->integrator->name, "usl") != 0) {
    jr_node shn = {.r = root->r};
    snprintf(shn.path, sizeof shn.path, "shape");
    return jr_fail(&shn, "kind", "\"%s\" reconstructs the nodal velocity of an update-stress-last "
                   "step: expected time.analysis \"explicit\" with time.scheme \"usl\", found %s",
                   s->shape->name, s->analysis == MPGM_ANALYSIS_EXPLICIT ? s->integrator->name
                                                                       : "an implicit analysis");
  }

  MPGM_CALL(read_materials(root, s));
  MPGM_CALL(mpgm_scene_read_bodies(root, s));
  MPGM_CALL(mpgm_scene_read_boundaries(root, s));
  MPGM_CALL(mpgm_scene_read_obstacles(root, s));
  /* after the boundaries: a default follows them (solver.contact_check) */
  MPGM_CALL(mpgm_scene_read_solver(root, s));
  for (int i = 0; i < s->nmat; i++) {
    jr_node m = {.r = root->r};
    snprintf(m.path, sizeof m.path, "materials.%s", s->mats[i].name);
    if (s->kinematics == MPGM_KIN_FINITE && !s->mats[i].type->finite)
      return jr_fail(&m, "type", "\"%s\" is a small-strain law: expected kinematics \"small\" or a "
                     "finite-strain material (neo_hookean), found kinematics \"finite\"",
                     s->mats[i].type->name);
    /* the backends that may factorise its tangent */
    const mpgm_solver_type *const by[2] = {s->solver, s->solver_opts.fallback};
    static const char *const key[2] = {"linear", "linear_fallback"};
    for (int k = 0; k < 2; k++)
      if (by[k] && by[k]->needs_spd && !s->mats[i].symmetric)
        return jr_fail(&m, "type", "material has an unsymmetric tangent: solver.%s \"%s\" needs a "
                       "symmetric matrix (use \"umfpack\" or \"auto\")", key[k], by[k]->name);
  }
  const double g0[MPGM_DIM] = {0};
  MPGM_CALL(jr_vec(root, "gravity", g0, s->gravity));
  MPGM_CALL(jr_num(root, "gravity_ramp", 0.0, 0.0, INFINITY, 0, 0, &s->gravity_ramp));
  if (s->gravity_ramp > 0.0 && s->analysis == MPGM_ANALYSIS_STATIC)
    return jr_fail(root, "gravity_ramp", "ramps gravity in time: expected time.analysis \"dynamic\" "
                   "or \"explicit\" (static runs ramp it with the load factor), found \"static\"");
  MPGM_CALL(mpgm_scene_read_probes(root, s));
  MPGM_CALL(mpgm_scene_read_manufactured(root, s));
  MPGM_CALL(mpgm_reference_read(root, s));
  MPGM_CALL(read_output(root, s));
  MPGM_CALL(jr_end(root));
  s->shape_par.h = s->h; /* the meshfree kinds' length scale: mesh.h */
  return 0;
}

/* Split "a.b=value" overrides. */
static int parse_sets(mpgm_ctx *ctx, const char *file, int nset, const char *const *sets,
                      jr_override *ov) {
  for (int i = 0; i < nset; i++) {
    const char *eq = strchr(sets[i], '=');
    MPGM_CHECK(ctx, eq && eq != sets[i], MPGM_ERR_INPUT,
               "%s: %s: expected --set KEY=VALUE with a dotted KEY (e.g. mesh.h=0.125), found "
               "\"%s\"", file, eq ? "(empty key)" : sets[i], sets[i]);
    size_t n = (size_t)(eq - sets[i]);
    MPGM_CHECK(ctx, n < JR_PATH, MPGM_ERR_INPUT, "%s: --set %.40s...: key too long", file, sets[i]);
    memcpy(ov[i].path, sets[i], n);
    ov[i].path[n] = '\0';
    ov[i].value = eq + 1;
    MPGM_CHECK(ctx, jr_utf8_invalid(ov[i].path, n) < 0, MPGM_ERR_INPUT,
               "%s: --set key %d is not UTF-8", file, i + 1);
    MPGM_CALL(jr_check_override(ctx, file, &ov[i]));
  }
  return 0;
}

/* A scene is 3-D when mesh.domain.min (after --set) has three
 * coordinates: MPGM_ERR_DIMENSION when this build is the other
 * dimension's, before anything else is read (whatever else the scene
 * holds is the other build's to judge). Anything but an array of 2 or 3
 * is left to the reader's own messages. */
static int scene_dimension(jr_reader *r, const cJSON *doc) {
  const cJSON *mesh = cJSON_IsObject(doc) ? cJSON_GetObjectItemCaseSensitive(doc, "mesh") : NULL;
  jr_node dom = {.r = r, .j = cJSON_IsObject(mesh) ? cJSON_GetObjectItemCaseSensitive(mesh, "domain") : NULL};
  snprintf(dom.path, sizeof dom.path, "mesh.domain");
  const cJSON *min = jr_override_json(&dom, "min");
  if (!min && cJSON_IsObject(dom.j)) min = cJSON_GetObjectItemCaseSensitive(dom.j, "min");
  const int n = cJSON_IsArray(min) ? cJSON_GetArraySize(min) : 0;
  if ((n != 2 && n != 3) || n == MPGM_DIM) return 0;
  MPGM_ERROR(r->ctx, MPGM_ERR_DIMENSION, "%s: mesh.domain.min: found %s coordinates, a %s scene: "
             "run it with %s", r->file, n == 3 ? "three" : "two", n == 3 ? "3-D" : "plane-strain",
             n == 3 ? "mpgm-3d (which mpgm calls for a 3-D scene)" : "mpgm");
}

/* Read the scene doc (owned, freed here) named file, with overrides. */
static int scene_read(mpgm_ctx *ctx, const char *file, cJSON *doc, int from_file, int nset,
                      const char *const *sets, mpgm_scene **out) {
  mpgm_scene *s = calloc(1, sizeof *s);
  if (s) s->from_file = from_file;
  jr_override *ov = calloc(nset ? nset : 1, sizeof *ov);
  int err = (!s || !ov) ? mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory") : 0;
  jr_reader r = {.ctx = ctx, .file = file, .ov = ov, .nov = nset};
  cJSON *resolved = cJSON_CreateObject();
  if (!err) err = parse_sets(ctx, file, nset, sets, ov);
  if (!err) err = scene_dimension(&r, doc);
  if (!err) {
    snprintf(s->file, sizeof s->file, "%s", file);
    const char *base = strrchr(file, '/');
    base = base ? base + 1 : file;
    snprintf(s->stem, sizeof s->stem, "%s", base);
    char *dot = strrchr(s->stem, '.');
    if (dot && dot != s->stem) *dot = '\0';
    jr_node root = {.r = &r, .j = doc, .out = resolved};
    err = read_scene(&root, s);
  }
  /* the scene against its front end's traits; then what depends on them */
  if (!err) err = mpgm_frontend_check(ctx, s);
  if (!err) err = mpgm_scene_contact_sides(ctx, s);
  if (!err) err = jr_unused_overrides(&r);
  if (!err) err = mpgm_scene_size_check(ctx, s); /* before any large allocation */
  cJSON_Delete(r.tmp);
  cJSON_Delete(doc);
  free(ov);
  s ? (void)(s->resolved = resolved) : cJSON_Delete(resolved);
  if (err) {
    mpgm_scene_destroy(&s);
    return err;
  }
  *out = s;
  return 0;
}

int mpgm_scene_load(mpgm_ctx *ctx, const char *file, int nset,
                    const char *const *sets, mpgm_scene **out) {
  *out = NULL;
  cJSON *doc = NULL;
  MPGM_CALL(jr_parse_file(ctx, file, &doc));
  return scene_read(ctx, file, doc, 1, nset, sets, out);
}

int mpgm_scene_load_text(mpgm_ctx *ctx, const char *name, const char *text, size_t len, int nset,
                         const char *const *sets, mpgm_scene **out) {
  *out = NULL;
  cJSON *doc = NULL;
  MPGM_CALL(jr_parse_text(ctx, name, text, len, &doc));
  return scene_read(ctx, name, doc, 0, nset, sets, out);
}

int mpgm_scene_load_json(mpgm_ctx *ctx, const char *name, const void *json, mpgm_scene **out) {
  *out = NULL;
  MPGM_CHECK(ctx, cJSON_IsObject((const cJSON *)json), MPGM_ERR_INPUT, "%s: expected a JSON object (a scene)", name);
  cJSON *doc = cJSON_Duplicate((const cJSON *)json, 1);
  MPGM_CHECK(ctx, doc, MPGM_ERR_NOMEM, "out of memory (scene %s)", name);
  return scene_read(ctx, name, doc, 0, 0, NULL, out);
}

void mpgm_scene_destroy(mpgm_scene **sp) {
  if (!sp || !*sp) return;
  mpgm_scene *s = *sp;
  free(s->mats);
  free(s->bodies);
  free(s->bcs);
  free(s->probes);
  free(s->obstacles);
  cJSON_Delete((cJSON *)s->resolved);
  free(s);
  *sp = NULL;
}

char *mpgm_scene_resolved_json(const mpgm_scene *s) {
  return cJSON_Print((const cJSON *)s->resolved);
}
