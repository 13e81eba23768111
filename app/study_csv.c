/* study_csv.c -- gather the runs' summary.json into study.csv (study.h). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_json_reader.h"
#include "study.h"

void mpgm_study_run_dir(const mpgm_study *st, const study_run *r, const char *leaf, char *buf,
                        size_t cap) {
  snprintf(buf, cap, "%s/runs/%s%s%s", st->out, r->name, leaf ? "/" : "", leaf ? leaf : "");
}

cJSON *mpgm_study_summary(const mpgm_study *st, const study_run *r) {
  char path[STUDY_PATH + STUDY_NAME + 32];
  mpgm_study_run_dir(st, r, "summary.json", path, sizeof path);
  mpgm_ctx quiet;
  mpgm_ctx_init(&quiet);
  cJSON *doc = NULL;
  if (jr_parse_file(&quiet, path, &doc)) return NULL;
  if (!cJSON_IsString(cJSON_GetObjectItemCaseSensitive(doc, "status"))) {
    cJSON_Delete(doc);
    return NULL;
  }
  return doc;
}

/* The item at a dotted path of j (NULL when absent). */
static const cJSON *at_path(const cJSON *j, const char *path) {
  char part[256];
  while (j && *path) {
    const size_t n = strcspn(path, ".");
    if (n >= sizeof part) return NULL;
    memcpy(part, path, n);
    part[n] = '\0';
    j = cJSON_GetObjectItemCaseSensitive(j, part);
    path += n + (path[n] == '.');
  }
  return j;
}

/* The reference block's columns: value, error, relative_error. */
static int reference_error(const mpgm_study *st, const cJSON *summary, double *err, double *rel) {
  const cJSON *m = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(summary, "metrics"),
                                                    st->ref_metric);
  if (!st->has_ref || !cJSON_IsNumber(m)) return 0;
  *err = fabs(m->valuedouble - st->ref_value);
  *rel = st->ref_value != 0.0 ? *err / fabs(st->ref_value) : NAN;
  return 1;
}

double mpgm_study_metric(const mpgm_study *st, const cJSON *summary) {
  double e, rel;
  if (strncmp(st->metric, "reference.", 10) == 0) {
    if (!reference_error(st, summary, &e, &rel)) return NAN;
    return strcmp(st->metric + 10, "relative_error") == 0 ? rel : e;
  }
  char path[160];
  snprintf(path, sizeof path, "metrics.%s", st->metric);
  const cJSON *v = strchr(st->metric, '.') ? at_path(summary, st->metric) : at_path(summary, path);
  return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* 1 when name is a key column of the study (a run key or a "set" key). */
static int is_key(const mpgm_study *st, const char *name) {
  for (int k = 0; k < st->nkey; k++)
    if (strcmp(st->keys[k], name) == 0) return 1;
  for (int k = 0; k < st->nset; k++)
    if (strcmp(st->set[k].key, name) == 0) return 1;
  return 0;
}

/* Every scalar of j under prefix into the row (arrays are left out); a
 * name that is also a key column (say "method") gets "summary." before. */
static int flatten(const mpgm_study *st, mpgm_table *t, int row, const char *prefix, const cJSON *j) {
  static const char *const skip[] = {"status", "message", "scene_file", "scene", "effects",
                                     "probes", "output", "step_cuts"};
  for (const cJSON *c = j->child; c; c = c->next) {
    int skipped = 0;
    for (size_t k = 0; !prefix[0] && k < sizeof skip / sizeof *skip; k++) skipped |= !strcmp(c->string, skip[k]);
    if (skipped || cJSON_IsArray(c) || cJSON_IsNull(c)) continue;
    char name[512], val[64];
    snprintf(name, sizeof name, "%s%s", prefix, c->string);
    if (cJSON_IsObject(c)) {
      strncat(name, ".", sizeof name - strlen(name) - 1);
      MPGM_CALL(flatten(st, t, row, name, c));
      continue;
    }
    const char *v = val;
    if (cJSON_IsString(c)) v = c->valuestring;
    else if (cJSON_IsBool(c)) v = cJSON_IsTrue(c) ? "true" : "false";
    else mpgm_format_double(c->valuedouble, val, sizeof val);
    if (is_key(st, name)) {
      char alt[520];
      snprintf(alt, sizeof alt, "summary.%s", name);
      MPGM_CALL(mpgm_table_set_named(t, row, alt, v));
    } else {
      MPGM_CALL(mpgm_table_set_named(t, row, name, v));
    }
  }
  return 0;
}

static int fill_row(mpgm_table *t, const mpgm_study *st, const study_run *r) {
  const int row = mpgm_table_add_row(t);
  if (row < 0) return MPGM_ERR_NOMEM;
  for (int k = 0; k < r->nkv; k++) MPGM_CALL(mpgm_table_set_named(t, row, r->kv[k].key, r->kv[k].value));
  for (int k = 0; k < st->nset; k++) MPGM_CALL(mpgm_table_set_named(t, row, st->set[k].key, st->set[k].value));
  static const char *const state[] = {"pending", "running", "", ""};
  MPGM_CALL(mpgm_table_set_named(t, row, "status", r->status[0] ? r->status : state[r->state]));
  MPGM_CALL(mpgm_table_set_named(t, row, "message", r->message));
  char buf[STUDY_NAME + 8];
  snprintf(buf, sizeof buf, "%d", r->exit_code);
  MPGM_CALL(mpgm_table_set_named(t, row, "exit_code", r->exit_code >= 0 ? buf : ""));
  snprintf(buf, sizeof buf, "runs/%s", r->name);
  MPGM_CALL(mpgm_table_set_named(t, row, "dir", buf));
  const cJSON *s = r->summary;
  if (!s) return 0;
  int err = flatten(st, t, row, "", s);
  double e, rel;
  if (!err && reference_error(st, s, &e, &rel)) {
    mpgm_format_double(st->ref_value, buf, sizeof buf);
    err = mpgm_table_set_named(t, row, "reference.value", buf);
    mpgm_format_double(e, buf, sizeof buf);
    if (!err) err = mpgm_table_set_named(t, row, "reference.error", buf);
    mpgm_format_double(rel, buf, sizeof buf);
    if (!err && isfinite(rel)) err = mpgm_table_set_named(t, row, "reference.relative_error", buf);
  }
  return err;
}

int mpgm_study_write_csv(mpgm_ctx *ctx, const mpgm_study *st) {
  mpgm_table t;
  memset(&t, 0, sizeof t);
  int err = 0;
  /* the leading columns, whatever the runs hold */
  for (int k = 0; k < st->nkey && !err; k++) err = mpgm_table_col(&t, st->keys[k], 1) < 0;
  for (int k = 0; k < st->nset && !err; k++) err = mpgm_table_col(&t, st->set[k].key, 1) < 0;
  static const char *const lead[] = {"status", "message", "exit_code", "dir"};
  for (size_t k = 0; k < sizeof lead / sizeof *lead && !err; k++) err = mpgm_table_col(&t, lead[k], 1) < 0;
  for (int i = 0; i < st->nrun && !err; i++) err = fill_row(&t, st, &st->runs[i]);
  if (err) {
    mpgm_table_free(&t);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (study.csv)");
  }
  char path[STUDY_PATH + 16];
  snprintf(path, sizeof path, "%s/study.csv", st->out);
  err = mpgm_table_write(ctx, &t, path);
  mpgm_table_free(&t);
  return err;
}
