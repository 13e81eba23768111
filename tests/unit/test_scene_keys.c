/* test_scene_keys.c -- every shape kind, front end and time scheme reads its own
 * keys of "shape", "mesh" and "time" from the table it declares
 * (mpgm_key_spec), and a key of another is refused by its owner's name
 * (io/scene_keys.c). Runs over the
 * lists (mpgm_shapefn_types, mpgm_frontend_types) of the build, 2-D and
 * 3-D: a kind or front end added to a list is tested here unchanged.
 *
 *   1. each table: names unique, not "kind", no name both a kind's and a
 *      front end's; the field inside its struct; the default inside the
 *      range (a name of the choices);
 *   2. for each front end and kind it takes: the resolved "shape" holds
 *      exactly "kind", the kind's keys and the front end's, each at its
 *      default;
 *   3. every key of another kind or front end that this pair does not
 *      take: refused in a scene file and in --set, with a message naming
 *      the key's owner; passed over (not resolved) in a run's own record
 *      (mpgm_scene_load_json), which earlier mpgm wrote with every
 *      meshfree key for every meshfree kind;
 *   4. the same for the explicit time schemes' own keys of "time";
 *   5. and for the front ends' keys of "mesh" (the rules for their nodes):
 *      each method resolves exactly its own, at their defaults;
 *   6. and for the solver backends' own keys of "solver" (petsc's
 *      options): refused with every other backend. */
#include "mpgm_frontends.h"
#include "mpgm_integrator.h"
#include "mpgm_scene_io.h"
#include "mpgm_solver.h"
#include "mpgm_test.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* one per build: the 2-D and 3-D tests run side by side in one folder */
#if MPGM_DIM == 2
#define FILE_NAME "test_scene_keys.json"
#else
#define FILE_NAME "test_scene_keys_3d.json"
#endif

static int declares(const mpgm_key_spec *k, int n, const char *name) {
  for (int i = 0; i < n; i++)
    if (strcmp(k[i].name, name) == 0) return 1;
  return 0;
}

/* 1: one table (of a struct of size size). */
static void check_table(const char *who, const mpgm_key_spec *k, int n, size_t size) {
  int bad = 0;
  for (int i = 0; i < n; i++) {
    const size_t width = k[i].type == MPGM_KEY_REAL     ? sizeof(double)
                         : k[i].type == MPGM_KEY_STRING ? k[i].size
                                                        : sizeof(int);
    int nch = 0;
    while (k[i].type == MPGM_KEY_CHOICE && k[i].choices && k[i].choices[nch]) nch++;
    const double d = k[i].def;
    const int in = k[i].type == MPGM_KEY_STRING   ? k[i].size > 0 && d == 0.0
                   : k[i].type == MPGM_KEY_CHOICE ? d == floor(d) && d >= k[i].lo && d < k[i].lo + nch
                   : (k[i].lo_open ? d > k[i].lo : d >= k[i].lo) &&
                         (k[i].hi_open ? d < k[i].hi : d <= k[i].hi) &&
                         (k[i].type == MPGM_KEY_REAL || d == floor(d));
    const int ok = k[i].name && strcmp(k[i].name, "kind") != 0 && k[i].offset + width <= size &&
                   (k[i].type == MPGM_KEY_STRING || k[i].offset % width == 0) && in && k[i].doc && k[i].unit &&
                   !declares(k, i, k[i].name) && (k[i].type != MPGM_KEY_CHOICE || nch >= 1);
    if (!ok) mpgm_test(0, "%s: key %d (%s): a name, not kind, once; its field inside the struct; "
                       "its default %g inside its range", who, i, k[i].name ? k[i].name : "?", d);
    bad += !ok;
  }
  mpgm_test(bad == 0, "%s: %d keys declared well", who, n);
}

/* The solver backend of the scenes scene_text writes (check_backends). */
static const char *linear = "auto";

/* The scene of a front end, a kind and a time scheme (NULL: the kind's
 * analysis), with extra members of section ("shape", "mesh", "time" or
 * "solver"). */
static void scene_text(const mpgm_frontend_type *fe, const mpgm_shapefn_type *sh, const char *scheme,
                       const char *section, const char *extra, char *text, size_t len) {
  char tm[256];
  const int in_time = strcmp(section, "time") == 0, in_mesh = strcmp(section, "mesh") == 0;
  const int in_solver = strcmp(section, "solver") == 0;
  if (scheme || sh->velocity_ls)
    snprintf(tm, sizeof tm, "{\"analysis\": \"explicit\", \"scheme\": \"%s\", \"end\": 0.01%s}",
             scheme ? scheme : "usl", in_time ? extra : "");
  else
    snprintf(tm, sizeof tm, "{\"analysis\": \"static\"%s}", in_time ? extra : "");
#if MPGM_DIM == 2
  const char *dom = "\"min\": [0, 0], \"max\": [2.4, 1.6]";
  const char *body = "\"rectangle\": {\"min\": [0.0, 0.0], \"max\": [1.6, 0.8]}";
  const char *fix = "[\"x\", \"y\"]";
#else
  const char *dom = "\"min\": [0, 0, 0], \"max\": [2.4, 1.6, 0.8]";
  const char *body = "\"box\": {\"min\": [0.0, 0.0, 0.0], \"max\": [1.6, 0.8, 0.4]}";
  const char *fix = "[\"x\", \"y\", \"z\"]";
#endif
  snprintf(text, len,
           "{\"method\": \"%s\", \"shape\": {\"kind\": \"%s\"%s},"
           " \"mesh\": {\"h\": 0.2, \"layout\": \"%s\", \"domain\": {%s}%s},"
           " \"time\": %s,"
           " \"materials\": {\"m\": {\"type\": \"neo_hookean\", \"density\": 1000, \"E\": 1e6, "
           "\"nu\": 0.3}},"
           " \"bodies\": [{\"material\": \"m\", %s}],"
           " \"boundaries\": [{\"x\": 0.0, \"fix\": %s}], \"solver\": {\"linear\": \"%s\"%s},"
           " \"output\": {\"vtk\": \"none\"}}",
           fe->name, sh->name, in_time || in_mesh || in_solver ? "" : extra,
           sh->grid_only ? "centres" : "gauss", dom, in_mesh ? extra : "", tm, body, fix, linear,
           in_solver ? extra : "");
}

/* Load text from a scene file (as a user's scene), with one --set. */
static int load_file(mpgm_ctx *ctx, const char *text, const char *set, mpgm_scene **s) {
  FILE *f = fopen(FILE_NAME, "w");
  if (!f || fputs(text, f) < 0 || fclose(f) != 0)
    return mpgm_err_set(ctx, MPGM_ERR_IO, __FILE__, __LINE__, "cannot write %s", FILE_NAME);
  const char *sets[1] = {set};
  const int err = mpgm_scene_load(ctx, FILE_NAME, set ? 1 : 0, sets, s);
  remove(FILE_NAME);
  return err;
}

/* Key k of the resolved object o at its default. */
static int at_default(const cJSON *o, const mpgm_key_spec *k) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, k->name);
  return k->type == MPGM_KEY_CHOICE
             ? cJSON_IsString(v) && strcmp(v->valuestring, k->choices[(int)(k->def - k->lo)]) == 0
             : cJSON_IsNumber(v) && v->valuedouble == k->def;
}

/* 2: the resolved "shape" of a pair holds its keys at their defaults, and
 * nothing else. */
static void check_resolved(const char *what, const mpgm_frontend_type *fe,
                           const mpgm_shapefn_type *sh, const mpgm_scene *s) {
  const cJSON *o = cJSON_GetObjectItemCaseSensitive((const cJSON *)s->resolved, "shape");
  const int n = cJSON_GetArraySize(o);
  int bad = 0;
  for (int w = 0; w < 2; w++) {
    const mpgm_key_spec *k = w ? fe->shape_keys : sh->keys;
    for (int i = 0; i < (w ? fe->nshape_keys : sh->nkeys); i++) {
      const int ok = at_default(o, &k[i]);
      if (!ok) mpgm_test(0, "%s: shape.%s resolved at its default %g", what, k[i].name, k[i].def);
      bad += !ok;
    }
  }
  mpgm_test(bad == 0 && n == 1 + sh->nkeys + fe->nshape_keys,
            "%s: resolved shape holds kind and its %d + %d keys at their defaults (%d members)", what,
            sh->nkeys, fe->nshape_keys, n);
}

/* 3: key of section, of owner (another kind, front end or scheme),
 * refused in the file and in --set naming owner, passed over in a
 * record. */
static void check_foreign(const char *what, const mpgm_frontend_type *fe, const mpgm_shapefn_type *sh,
                          const char *scheme, const char *section, const mpgm_key_spec *key,
                          const char *owner) {
  char extra[128], text[2048], set[128];
  const char *value = key->type == MPGM_KEY_CHOICE ? key->choices[0] : "1";
  snprintf(extra, sizeof extra, ", \"%s\": %s%s%s", key->name, key->type == MPGM_KEY_CHOICE ? "\"" : "",
           value, key->type == MPGM_KEY_CHOICE ? "\"" : "");
  mpgm_ctx ctx;
  mpgm_scene *s = NULL;
  for (int by_set = 0; by_set < 2; by_set++) {
    mpgm_ctx_init(&ctx);
    scene_text(fe, sh, scheme, section, by_set ? "" : extra, text, sizeof text);
    snprintf(set, sizeof set, "%s.%s=%s", section, key->name, value);
    const int err = load_file(&ctx, text, by_set ? set : NULL, &s);
    char want[160];
    snprintf(want, sizeof want, "%s.%s: a key of ", section, key->name);
    mpgm_test(err == MPGM_ERR_INPUT && strstr(ctx.msg, want) && strstr(ctx.msg, owner),
              "%s: %s.%s (%s's) refused %s: %s", what, section, key->name, owner,
              by_set ? "in --set" : "in the file", ctx.msg);
    mpgm_scene_destroy(&s);
  }
  mpgm_ctx_init(&ctx);
  scene_text(fe, sh, scheme, section, extra, text, sizeof text);
  cJSON *j = cJSON_Parse(text);
  const int err = j ? mpgm_scene_load_json(&ctx, "record", j, &s) : MPGM_ERR_INTERNAL;
  cJSON_Delete(j);
  const cJSON *o = s ? cJSON_GetObjectItemCaseSensitive((const cJSON *)s->resolved, section) : NULL;
  mpgm_test(err == 0 && o && !cJSON_GetObjectItemCaseSensitive(o, key->name),
            "%s: %s.%s in a run's record passed over, not resolved (%s)", what, section, key->name,
            err ? ctx.msg : "loaded");
  mpgm_scene_destroy(&s);
}

/* 3 for every key of owner's table (name, n keys) that the pair lacks. */
static int check_table_foreign(const char *what, const mpgm_frontend_type *fe,
                               const mpgm_shapefn_type *sh, const char *owner,
                               const mpgm_key_spec *keys, int nkeys) {
  int n = 0;
  for (int k = 0; k < nkeys; k++) {
    if (declares(sh->keys, sh->nkeys, keys[k].name) ||
        declares(fe->shape_keys, fe->nshape_keys, keys[k].name))
      continue;
    check_foreign(what, fe, sh, NULL, "shape", &keys[k], owner);
    n++;
  }
  return n;
}

/* 3 for every key of the other kinds and front ends this pair lacks. */
static int check_foreign_all(const char *what, const mpgm_frontend_type *fe,
                             const mpgm_shapefn_type *sh) {
  const mpgm_shapefn_type *const *st = mpgm_shapefn_types();
  const mpgm_frontend_type *const *ft = mpgm_frontend_types();
  int n = 0;
  for (int i = 0; st[i]; i++) n += check_table_foreign(what, fe, sh, st[i]->name, st[i]->keys, st[i]->nkeys);
  for (int i = 0; ft[i]; i++)
    n += check_table_foreign(what, fe, sh, ft[i]->name, ft[i]->shape_keys, ft[i]->nshape_keys);
  return n;
}

/* 1-3 for the explicit schemes' own keys of "time" (MPM, fe): each
 * resolves its keys at their defaults; a key of another is refused. */
static int check_schemes(void) {
  const mpgm_frontend_type *mpm = mpgm_frontend_type_find("mpm");
  const mpgm_shapefn_type *fe = mpgm_shapefn_type_find("fe");
  const mpgm_integrator_type *const *it = mpgm_integrator_types();
  int n = 0;
  for (int i = 0; it[i]; i++) {
    check_table(it[i]->name, it[i]->keys, it[i]->nkeys, sizeof(mpgm_scheme_params));
    if (it[i]->implicit || !mpm || !fe) continue;
    char what[64], text[2048];
    snprintf(what, sizeof what, "time.scheme %s", it[i]->name);
    scene_text(mpm, fe, it[i]->name, "time", "", text, sizeof text);
    mpgm_ctx ctx;
    mpgm_ctx_init(&ctx);
    mpgm_scene *s = NULL;
    int err = load_file(&ctx, text, NULL, &s);
    const cJSON *o = s ? cJSON_GetObjectItemCaseSensitive((const cJSON *)s->resolved, "time") : NULL;
    int bad = err != 0;
    for (int k = 0; !err && k < it[i]->nkeys; k++) bad += !cJSON_GetObjectItemCaseSensitive(o, it[i]->keys[k].name);
    mpgm_test(!bad && s->integrator == it[i], "%s: loads, its %d keys resolved (%s)", what, it[i]->nkeys,
              err ? ctx.msg : "ok");
    mpgm_scene_destroy(&s);
    for (int j = 0; it[j]; j++)
      for (int k = 0; j != i && !it[j]->implicit && k < it[j]->nkeys; k++, n++)
        if (!declares(it[i]->keys, it[i]->nkeys, it[j]->keys[k].name))
          check_foreign(what, mpm, fe, it[i]->name, "time", &it[j]->keys[k], it[j]->name);
  }
  return n;
}

/* 5: each front end (with a kind it takes) resolves "mesh" as h, cell,
 * ppc, layout, domain and exactly its own keys at their defaults; a key of
 * another front end's is refused. */
static int check_mesh(void) {
  const mpgm_frontend_type *const *ft = mpgm_frontend_types();
  const mpgm_shapefn_type *const *st = mpgm_shapefn_types();
  int n = 0;
  for (int f = 0; ft[f]; f++) {
    check_table(ft[f]->name, ft[f]->mesh_keys, ft[f]->nmesh_keys, sizeof(mpgm_mesh_params));
    const mpgm_shapefn_type *sh = NULL;
    for (int k = 0; st[k] && !sh; k++)
      if (ft[f]->shapes & (st[k]->needs_cell ? MPGM_FE_SHAPE_CELL : MPGM_FE_SHAPE_CLOUD) &&
          !(st[k]->grid_only && ft[f]->persistent_nodes) && !st[k]->velocity_ls)
        sh = st[k];
    if (!sh) continue;
    char what[64], text[2048];
    snprintf(what, sizeof what, "%s-%s mesh", ft[f]->name, sh->name);
    scene_text(ft[f], sh, NULL, "mesh", "", text, sizeof text);
    mpgm_ctx ctx;
    mpgm_ctx_init(&ctx);
    mpgm_scene *s = NULL;
    const int err = load_file(&ctx, text, NULL, &s);
    const cJSON *o = s ? cJSON_GetObjectItemCaseSensitive((const cJSON *)s->resolved, "mesh") : NULL;
    int bad = err != 0;
    for (int i = 0; !err && i < ft[f]->nmesh_keys; i++) bad += !at_default(o, &ft[f]->mesh_keys[i]);
    mpgm_test(!bad && cJSON_GetArraySize(o) == 5 + ft[f]->nmesh_keys,
              "%s: resolved mesh holds its %d keys at their defaults and 5 others (%s)", what,
              ft[f]->nmesh_keys, err ? ctx.msg : "ok");
    mpgm_scene_destroy(&s);
    for (int g = 0; !err && ft[g]; g++)
      for (int k = 0; g != f && k < ft[g]->nmesh_keys; k++)
        if (!declares(ft[f]->mesh_keys, ft[f]->nmesh_keys, ft[g]->mesh_keys[k].name)) {
          check_foreign(what, ft[f], sh, NULL, "mesh", &ft[g]->mesh_keys[k], ft[g]->name);
          n++;
        }
  }
  return n;
}

/* 6: each backend's keys refused in the scene of every other backend
 * (MPM, fe, static). */
static int check_backends(void) {
  const mpgm_frontend_type *mpm = mpgm_frontend_type_find("mpm");
  const mpgm_shapefn_type *fe = mpgm_shapefn_type_find("fe");
  const mpgm_solver_type *const *bt = mpgm_solver_types();
  int n = 0;
  for (int b = 0; bt[b]; b++) check_table(bt[b]->name, bt[b]->keys, bt[b]->nkeys, sizeof(mpgm_solver_opts));
  for (int b = 0; bt[b] && mpm && fe; b++)
    for (int a = 0; bt[a]; a++)
      for (int k = 0; a != b && k < bt[a]->nkeys; k++)
        if (!declares(bt[b]->keys, bt[b]->nkeys, bt[a]->keys[k].name)) {
          char what[64];
          snprintf(what, sizeof what, "solver.linear %s", bt[b]->name);
          linear = bt[b]->name;
          check_foreign(what, mpm, fe, NULL, "solver", &bt[a]->keys[k], bt[a]->name);
          linear = "auto";
          n++;
        }
  return n;
}

int main(void) {
  const mpgm_frontend_type *const *ft = mpgm_frontend_types();
  const mpgm_shapefn_type *const *st = mpgm_shapefn_types();
  for (int k = 0; st[k]; k++) check_table(st[k]->name, st[k]->keys, st[k]->nkeys, sizeof(mpgm_shape_params));
  for (int f = 0; ft[f]; f++) {
    check_table(ft[f]->name, ft[f]->shape_keys, ft[f]->nshape_keys, sizeof(mpgm_pattern_opts));
    for (int k = 0; st[k]; k++) /* a name both read would be read twice */
      for (int i = 0; i < ft[f]->nshape_keys; i++)
        mpgm_test(!declares(st[k]->keys, st[k]->nkeys, ft[f]->shape_keys[i].name),
                  "%s's shape.%s is not also a key of kind %s", ft[f]->name,
                  ft[f]->shape_keys[i].name, st[k]->name);
  }
  int npair = 0, nforeign = 0;
  for (int f = 0; ft[f]; f++)
    for (int k = 0; st[k]; k++) {
      const unsigned need = st[k]->needs_cell ? MPGM_FE_SHAPE_CELL : MPGM_FE_SHAPE_CLOUD;
      if (!(ft[f]->shapes & need) || (st[k]->grid_only && ft[f]->persistent_nodes)) continue;
      char what[64], text[2048];
      snprintf(what, sizeof what, "%s-%s", ft[f]->name, st[k]->name);
      scene_text(ft[f], st[k], NULL, "shape", "", text, sizeof text);
      mpgm_ctx ctx;
      mpgm_ctx_init(&ctx);
      mpgm_scene *s = NULL;
      const int err = load_file(&ctx, text, NULL, &s);
      mpgm_test(err == 0, "%s: the scene loads (%s)", what, err ? ctx.msg : "ok");
      if (!err) check_resolved(what, ft[f], st[k], s);
      mpgm_scene_destroy(&s);
      if (!err) nforeign += check_foreign_all(what, ft[f], st[k]);
      npair++;
    }
  mpgm_test(npair >= (MPGM_DIM == 2 ? 6 : 3) && nforeign >= (MPGM_DIM == 2 ? 20 : 1),
            "%d pairs of front end and kind, %d foreign keys refused", npair, nforeign);
  const int nscheme = check_schemes();
  mpgm_test(nscheme >= 2, "%d keys of other time schemes refused", nscheme);
  const int nmesh = check_mesh();
  mpgm_test(nmesh >= (MPGM_DIM == 2 ? 4 : 1), "%d keys of other front ends' mesh refused", nmesh);
  const int nbackend = check_backends();
  mpgm_test(nbackend >= 4, "%d keys of other solver backends refused", nbackend);
  return mpgm_test_summary();
}
