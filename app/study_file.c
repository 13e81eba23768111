/* study_file.c -- read and validate a study file, expand its runs
 * (study.h, docs/studies.md).
 *
 *   {"scene": "../cantilever.json",              required
 *    "description": "...",
 *    "axes": {"mesh.h": [0.5, 0.25], ...},        cartesian product
 *    "runs": [{"method": "fem"}, ...],            explicit list (x axes)
 *    "set": {"output.vtk": "none"},               every run
 *    "out": "DIR", "jobs": 2, "metric": "error",
 *    "reference": {"metric": "tip_uy", "value": -0.67437},
 *    "plot": {"x": "mesh.h", "series": ["method"], "title": "..."}}
 */
#define _XOPEN_SOURCE 700 /* realpath */
#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_json_reader.h"
#include "study.h"

/* A value as --set takes it: strings as they are, numbers in their
 * shortest exact form, JSON for the rest. NULL when out of memory. */
static char *value_text(const cJSON *v) {
  char buf[64];
  if (cJSON_IsString(v)) return strdup(v->valuestring);
  if (cJSON_IsNumber(v)) {
    mpgm_format_double(v->valuedouble, buf, sizeof buf);
    return strdup(buf);
  }
  if (cJSON_IsBool(v)) return strdup(cJSON_IsTrue(v) ? "true" : "false");
  return cJSON_PrintUnformatted(v);
}

/* A value an override may take: anything but null and non-finite numbers
 * ("scene" takes file names only). */
static int check_value(jr_node *o, const char *key, const cJSON *v, const char *where) {
  if (strcmp(key, "scene") == 0 && !cJSON_IsString(v))
    return jr_fail(o, key, "expected a scene file name%s, found %s", where, jr_type(v));
  if (cJSON_IsNull(v) || (cJSON_IsNumber(v) && !isfinite(v->valuedouble)) || cJSON_IsInvalid(v))
    return jr_fail(o, key, "expected a value for --set%s, found %s", where, jr_type(v));
  return 0;
}

/* A dotted scene path: letters, digits, '_', '-', dots between parts. */
static int check_key(jr_node *o, const char *key) {
  int ok = *key && *key != '.' && key[strlen(key) - 1] != '.' && !strstr(key, "..") && strlen(key) < 200;
  for (const char *c = key; ok && *c; c++)
    ok = isalnum((unsigned char)*c) || *c == '_' || *c == '-' || *c == '.';
  if (!ok) return jr_fail(o, key, "expected a dotted scene path such as mesh.h as the key");
  return 0;
}

/* dir of file (no trailing '/'), "." when it has none. */
static void dir_of(const char *file, char *buf, size_t cap) {
  const char *s = strrchr(file, '/');
  if (!s) snprintf(buf, cap, ".");
  else if (s == file) snprintf(buf, cap, "/");
  else snprintf(buf, cap, "%.*s", (int)(s - file), file);
}

/* p relative to dir (unless absolute) into buf (STUDY_PATH chars), made
 * canonical when the file exists; 0 if too long. */
static int resolve(const char *dir, const char *p, char *buf, size_t cap) {
  const size_t nd = p[0] == '/' || strcmp(dir, ".") == 0 ? 0 : strlen(dir), np = strlen(p);
  char tmp[STUDY_PATH], real[PATH_MAX];
  if (nd + np + 2 > sizeof tmp) return 0;
  memcpy(tmp, dir, nd);
  if (nd) tmp[nd] = '/';
  memcpy(tmp + nd + (nd > 0), p, np + 1);
  const char *use = realpath(tmp, real) ? real : tmp;
  if (strlen(use) >= cap) return 0;
  memcpy(buf, use, strlen(use) + 1);
  return 1;
}

static void stem_of(const char *file, char *buf, size_t cap) {
  const char *b = strrchr(file, '/');
  snprintf(buf, cap, "%s", b ? b + 1 : file);
  char *dot = strrchr(buf, '.');
  if (dot && dot != buf) *dot = '\0';
}

static uint64_t fnv1a(const char *s) {
  uint64_t h = 1469598103934665603ull;
  for (; *s; s++) h = (h ^ (unsigned char)*s) * 1099511628211ull;
  return h;
}

/* Folder name of a run: key=value,... with the scene's stem for "scene";
 * characters outside [A-Za-z0-9._+=,-] become '_'; a long name is cut and
 * ends with a hash of the whole. */
static void run_name(study_run *r) {
  char full[8192];
  size_t n = 0;
  full[0] = '\0';
  for (int k = 0; k < r->nkv && n < sizeof full; k++) {
    char stem[STUDY_NAME];
    const char *v = r->kv[k].value;
    if (strcmp(r->kv[k].key, "scene") == 0) {
      stem_of(v, stem, sizeof stem);
      v = stem;
    }
    n += (size_t)snprintf(full + n, sizeof full - n, "%s%s=%s", k ? "," : "", r->kv[k].key, v);
  }
  if (!full[0]) snprintf(full, sizeof full, "base");
  for (char *c = full; *c; c++)
    if (!isalnum((unsigned char)*c) && !strchr("._+=,-", *c)) *c = '_';
  if (strlen(full) < 200) memcpy(r->name, full, strlen(full) + 1);
  else snprintf(r->name, sizeof r->name, "%.180s~%016llx", full, (unsigned long long)fnv1a(full));
}

static int add_kv(mpgm_ctx *ctx, study_kv **kv, int *n, const char *key, const cJSON *v) {
  study_kv *a = realloc(*kv, sizeof *a * (size_t)(*n + 1));
  MPGM_CHECK(ctx, a, MPGM_ERR_NOMEM, "out of memory (study)");
  *kv = a;
  a[*n].key = strdup(key);
  a[*n].value = value_text(v);
  (*n)++;
  MPGM_CHECK(ctx, a[*n - 1].key && a[*n - 1].value, MPGM_ERR_NOMEM, "out of memory (study)");
  return 0;
}

/* "axes": {KEY: [v, ...], ...}; *nax axes into ax (borrowed items). */
static int read_axes(jr_node *root, jr_node *axes, const cJSON **ax, int *nax, long *prod) {
  MPGM_CALL(jr_child(root, "axes", 0, axes));
  *nax = 0;
  *prod = 1;
  for (const cJSON *c = axes->j ? axes->j->child : NULL; c; c = c->next) {
    MPGM_CALL(check_key(axes, c->string));
    for (int i = 0; i < *nax; i++)
      if (strcmp(ax[i]->string, c->string) == 0) return jr_fail(axes, c->string, "duplicate key");
    if (!cJSON_IsArray(c) || cJSON_GetArraySize(c) < 1)
      return jr_fail(axes, c->string, "expected a non-empty array of values, found %s%s", jr_type(c),
                     cJSON_IsArray(c) ? " (empty)" : "");
    int idx = 0;
    for (const cJSON *v = c->child; v; v = v->next, idx++) {
      char where[48];
      snprintf(where, sizeof where, " at index %d", idx);
      MPGM_CALL(check_value(axes, c->string, v, where));
      for (const cJSON *w = c->child; w != v; w = w->next)
        if (cJSON_Compare(w, v, 1)) return jr_fail(axes, c->string, "value%s appears twice", where);
    }
    if (*nax == STUDY_MAX_KEYS) return jr_fail(axes, c->string, "more than %d axes", STUDY_MAX_KEYS);
    ax[(*nax)++] = c;
    *prod *= cJSON_GetArraySize(c);
    if (*prod > STUDY_MAX_RUNS)
      return jr_fail(root, "axes", "expected at most %d runs, found more", STUDY_MAX_RUNS);
  }
  return 0;
}

/* "runs": [{KEY: value, ...}, ...] (checked; entries borrowed). */
static int read_runs(jr_node *root, const cJSON *runs, const cJSON *const *ax, int nax) {
  if (!runs) return 0;
  if (!cJSON_IsArray(runs) || cJSON_GetArraySize(runs) < 1)
    return jr_fail(root, "runs", "expected a non-empty array of objects {\"key\": value, ...}, found %s",
                   jr_type(runs));
  int i = 0;
  for (const cJSON *e = runs->child; e; e = e->next, i++) {
    jr_node en;
    memset(&en, 0, sizeof en);
    en.r = root->r;
    en.j = e;
    snprintf(en.path, sizeof en.path, "runs.%d", i);
    if (!cJSON_IsObject(e)) return jr_fail(&en, NULL, "expected an object {\"key\": value, ...}, found %s", jr_type(e));
    int nk = 0;
    for (const cJSON *c = e->child; c; c = c->next, nk++) {
      MPGM_CALL(check_key(&en, c->string));
      MPGM_CALL(check_value(&en, c->string, c, ""));
      for (const cJSON *d = e->child; d != c; d = d->next)
        if (strcmp(d->string, c->string) == 0) return jr_fail(&en, c->string, "duplicate key");
      for (int a = 0; a < nax; a++)
        if (strcmp(ax[a]->string, c->string) == 0)
          return jr_fail(&en, c->string, "also an axis (axes.%s): give a key in one place", c->string);
    }
    if (nk + nax > STUDY_MAX_KEYS) return jr_fail(&en, NULL, "more than %d keys with the axes", STUDY_MAX_KEYS);
    for (const cJSON *d = runs->child; d != e; d = d->next)
      if (cJSON_Compare(d, e, 1)) return jr_fail(&en, NULL, "the same run as an earlier entry");
  }
  return 0;
}

/* "set": {KEY: value} (checked against the axes and runs keys). */
static int read_set(jr_node *root, mpgm_study *st, const cJSON *const *ax, int nax, const cJSON *runs) {
  jr_node set;
  MPGM_CALL(jr_child(root, "set", 0, &set));
  for (const cJSON *c = set.j ? set.j->child : NULL; c; c = c->next) {
    MPGM_CALL(check_key(&set, c->string));
    MPGM_CALL(check_value(&set, c->string, c, ""));
    if (strcmp(c->string, "scene") == 0)
      return jr_fail(&set, c->string, "the base scene is the top-level key \"scene\"");
    for (const cJSON *d = set.j->child; d != c; d = d->next)
      if (strcmp(d->string, c->string) == 0) return jr_fail(&set, c->string, "duplicate key");
    int clash = 0;
    for (int a = 0; a < nax; a++) clash |= strcmp(ax[a]->string, c->string) == 0;
    for (const cJSON *e = runs ? runs->child : NULL; e; e = e->next)
      clash |= cJSON_GetObjectItemCaseSensitive(e, c->string) != NULL;
    if (clash) return jr_fail(&set, c->string, "also an axis or a key of runs: give a key in one place");
    if (st->nset == STUDY_MAX_KEYS) return jr_fail(&set, c->string, "more than %d keys", STUDY_MAX_KEYS);
    MPGM_CALL(add_kv(root->r->ctx, &st->set, &st->nset, c->string, c));
  }
  return 0;
}

/* The runs: entries of "runs" (or one empty entry) x the axes product,
 * the last axis varying fastest. */
static int expand(mpgm_ctx *ctx, jr_node *root, mpgm_study *st, const cJSON *runs,
                  const cJSON *const *ax, int nax, long prod) {
  const int nentry = runs ? cJSON_GetArraySize(runs) : 1;
  MPGM_CHECK(ctx, (long)nentry * prod <= STUDY_MAX_RUNS, MPGM_ERR_INPUT,
             "%s: runs x axes: expected at most %d runs, found %ld", st->file, STUDY_MAX_RUNS,
             (long)nentry * prod);
  MPGM_CHECK(ctx, runs || nax > 0, MPGM_ERR_INPUT,
             "%s: (root): no runs: give \"axes\" (a product of values) or \"runs\" (a list)", st->file);
  st->nrun = (int)(nentry * prod);
  MPGM_ALLOC(ctx, st->runs, st->nrun);
  char dir[STUDY_PATH];
  dir_of(st->file, dir, sizeof dir);
  for (int i = 0; i < st->nrun; i++) {
    study_run *r = &st->runs[i];
    r->exit_code = -1;
    const cJSON *e = runs ? cJSON_GetArrayItem(runs, i / (int)prod) : NULL;
    snprintf(r->scene, sizeof r->scene, "%s", st->scene);
    for (const cJSON *c = e ? e->child : NULL; c; c = c->next) MPGM_CALL(add_kv(ctx, &r->kv, &r->nkv, c->string, c));
    long rest = i % prod, div = prod; /* mixed radix, the last axis fastest */
    for (int a = 0; a < nax; a++) {
      const int na = cJSON_GetArraySize(ax[a]);
      div /= na;
      MPGM_CALL(add_kv(ctx, &r->kv, &r->nkv, ax[a]->string, cJSON_GetArrayItem(ax[a], (int)(rest / div))));
      rest %= div;
    }
    for (int k = 0; k < r->nkv; k++)
      if (strcmp(r->kv[k].key, "scene") == 0 && !resolve(dir, r->kv[k].value, r->scene, sizeof r->scene))
        return jr_fail(root, "runs", "scene file name too long");
    run_name(r);
    for (int j = 0; j < i; j++)
      MPGM_CHECK(ctx, strcmp(st->runs[j].name, r->name) != 0, MPGM_ERR_INPUT,
                 "%s: runs %d and %d get the same folder name %s (values that differ only in characters "
                 "outside [A-Za-z0-9._+=,-])", st->file, j + 1, i + 1, r->name);
  }
  return 0;
}

/* The key columns: every run's keys, in order of first appearance. */
static int key_columns(mpgm_ctx *ctx, mpgm_study *st) {
  int cap = 0;
  for (int i = 0; i < st->nrun; i++) cap += st->runs[i].nkv;
  MPGM_ALLOC(ctx, st->keys, cap);
  for (int i = 0; i < st->nrun; i++)
    for (int k = 0; k < st->runs[i].nkv; k++) {
      int seen = 0;
      for (int c = 0; c < st->nkey && !seen; c++) seen = strcmp(st->keys[c], st->runs[i].kv[k].key) == 0;
      if (!seen) st->keys[st->nkey++] = st->runs[i].kv[k].key;
    }
  return 0;
}

/* "reference", "plot" and "metric". */
static int read_plot_keys(jr_node *root, mpgm_study *st) {
  jr_node ref, plot;
  MPGM_CALL(jr_child(root, "reference", 0, &ref));
  if (ref.j) {
    MPGM_CALL(jr_str(&ref, "metric", NULL, st->ref_metric, sizeof st->ref_metric));
    MPGM_CALL(jr_num(&ref, "value", NAN, -INFINITY, INFINITY, 0, 0, &st->ref_value));
    MPGM_CALL(jr_end(&ref));
    st->has_ref = 1;
  }
  MPGM_CALL(jr_str(root, "metric", st->has_ref ? "reference.error" : "error", st->metric, sizeof st->metric));
  MPGM_CALL(jr_child(root, "plot", 0, &plot));
  if (plot.j) {
    char buf[STUDY_NAME];
    MPGM_CALL(jr_str(&plot, "x", "mesh.h", buf, sizeof buf));
    MPGM_CALL(jr_str(&plot, "title", "", buf, sizeof buf));
    const cJSON *s = jr_raw(&plot, "series");
    if (s) {
      int ok = cJSON_IsArray(s);
      for (const cJSON *c = ok ? s->child : NULL; c; c = c->next) ok &= cJSON_IsString(c) && c->valuestring[0];
      if (!ok) return jr_fail(&plot, "series", "expected an array of key names, found %s", jr_type(s));
    }
    MPGM_CALL(jr_end(&plot));
  }
  return 0;
}

/* study.json: the study as resolved (paths as the runs use them). */
static int make_record(mpgm_ctx *ctx, mpgm_study *st, const cJSON *doc) {
  cJSON *j = st->record = cJSON_CreateObject();
  MPGM_CHECK(ctx, j, MPGM_ERR_NOMEM, "out of memory (study)");
  cJSON_AddStringToObject(j, "study_file", st->file);
  const cJSON *d = cJSON_GetObjectItemCaseSensitive(doc, "description");
  cJSON_AddStringToObject(j, "description", cJSON_IsString(d) ? d->valuestring : "");
  cJSON_AddStringToObject(j, "name", st->stem);
  cJSON_AddStringToObject(j, "scene", st->scene);
  cJSON_AddStringToObject(j, "out", st->out);
  cJSON_AddNumberToObject(j, "jobs", st->jobs);
  cJSON_AddStringToObject(j, "metric", st->metric);
  static const char *const copy[] = {"axes", "runs", "set", "reference", "plot"};
  for (size_t k = 0; k < sizeof copy / sizeof *copy; k++) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(doc, copy[k]);
    if (v) cJSON_AddItemToObject(j, copy[k], cJSON_Duplicate(v, 1));
  }
  cJSON *keys = cJSON_AddArrayToObject(j, "keys");
  for (int k = 0; k < st->nkey; k++) cJSON_AddItemToArray(keys, cJSON_CreateString(st->keys[k]));
  cJSON *list = cJSON_AddArrayToObject(j, "run_list");
  for (int i = 0; i < st->nrun; i++) {
    cJSON *r = cJSON_CreateObject();
    cJSON_AddStringToObject(r, "dir", st->runs[i].name);
    cJSON_AddStringToObject(r, "scene", st->runs[i].scene);
    cJSON *o = cJSON_AddObjectToObject(r, "set");
    for (int k = 0; k < st->runs[i].nkv; k++)
      if (strcmp(st->runs[i].kv[k].key, "scene") != 0)
        cJSON_AddStringToObject(o, st->runs[i].kv[k].key, st->runs[i].kv[k].value);
    cJSON_AddItemToArray(list, r);
  }
  return 0;
}

static int load(mpgm_ctx *ctx, const char *file, const char *out_dir, int jobs, mpgm_study *st, cJSON *doc) {
  jr_reader rd = {.ctx = ctx, .file = st->file};
  jr_node root;
  memset(&root, 0, sizeof root);
  root.r = &rd;
  root.j = doc;
  char buf[STUDY_PATH], dir[STUDY_PATH];
  dir_of(file, dir, sizeof dir);
  stem_of(file, st->stem, sizeof st->stem);
  MPGM_CALL(jr_str(&root, "description", "", buf, sizeof buf));
  MPGM_CALL(jr_str(&root, "scene", NULL, buf, sizeof buf));
  MPGM_CHECK(ctx, buf[0] && resolve(dir, buf, st->scene, sizeof st->scene), MPGM_ERR_INPUT,
             "%s: scene: expected a scene file name, found \"%s\"", file, buf);
  MPGM_CALL(jr_str(&root, "out", "", buf, sizeof buf));
  if (out_dir) snprintf(st->out, sizeof st->out, "%s", out_dir);
  else if (buf[0]) resolve(dir, buf, st->out, sizeof st->out);
  else snprintf(st->out, sizeof st->out, "results/%s", st->stem);
  MPGM_CALL(jr_int(&root, "jobs", 2, 1, 64, &st->jobs));
  if (jobs > 0) st->jobs = jobs;
  const cJSON *ax[STUDY_MAX_KEYS];
  int nax;
  long prod;
  jr_node axes;
  MPGM_CALL(read_axes(&root, &axes, ax, &nax, &prod));
  const cJSON *runs = jr_raw(&root, "runs");
  MPGM_CALL(read_runs(&root, runs, ax, nax));
  MPGM_CALL(read_set(&root, st, ax, nax, runs));
  MPGM_CALL(read_plot_keys(&root, st));
  MPGM_CALL(jr_end(&root));
  MPGM_CALL(expand(ctx, &root, st, runs, ax, nax, prod));
  MPGM_CALL(key_columns(ctx, st));
  return make_record(ctx, st, doc);
}

int mpgm_study_load(mpgm_ctx *ctx, const char *file, const char *out_dir, int jobs, mpgm_study *st) {
  memset(st, 0, sizeof *st);
  snprintf(st->file, sizeof st->file, "%s", file);
  cJSON *doc = NULL;
  MPGM_CALL(jr_parse_file(ctx, file, &doc));
  int err = load(ctx, file, out_dir, jobs, st, doc);
  cJSON_Delete(doc);
  if (err) mpgm_study_free(st);
  return err;
}

static void free_kv(study_kv *kv, int n) {
  for (int k = 0; k < n; k++) {
    free(kv[k].key);
    free(kv[k].value);
  }
  free(kv);
}

void mpgm_study_free(mpgm_study *st) {
  for (int i = 0; i < st->nrun; i++) {
    free_kv(st->runs[i].kv, st->runs[i].nkv);
    cJSON_Delete(st->runs[i].resolved);
    cJSON_Delete(st->runs[i].summary);
  }
  free(st->runs);
  free_kv(st->set, st->nset);
  free(st->keys);
  cJSON_Delete(st->record);
  memset(st, 0, sizeof *st);
}
