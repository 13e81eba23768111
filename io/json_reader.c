/* json_reader.c -- typed, validated reads of a cJSON tree (json_reader.h). */
#include "mpgm_json_reader.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void full_path(const jr_node *o, const char *key, char *buf, size_t n) {
  int w;
  if (!key) w = snprintf(buf, n, "%s", o->path[0] ? o->path : "(root)");
  else if (o->path[0]) w = snprintf(buf, n, "%s.%s", o->path, key);
  else w = snprintf(buf, n, "%s", key);
  if (w >= (int)n && n > 4) memcpy(buf + n - 4, "...", 4); /* truncated: say so */
}

int jr_fail(jr_node *o, const char *key, const char *fmt, ...) {
  char path[JR_PATH + 64], msg[600];
  full_path(o, key, path, sizeof path);
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  return mpgm_err_set(o->r->ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: %s: %s",
                      o->r->file, path, msg);
}

const char *jr_type(const cJSON *v) {
  if (!v) return "nothing";
  if (cJSON_IsNumber(v)) return "a number";
  if (cJSON_IsString(v)) return "a string";
  if (cJSON_IsBool(v)) return "a boolean";
  if (cJSON_IsNull(v)) return "null";
  if (cJSON_IsArray(v)) return "an array";
  if (cJSON_IsObject(v)) return "an object";
  return "an invalid value";
}

static void mark_seen(jr_node *o, const char *key) {
  for (int i = 0; i < o->nseen; i++)
    if (strcmp(o->seen[i], key) == 0) return;
  if (o->nseen < JR_MAXKEYS) o->seen[o->nseen++] = key;
}

static jr_override *find_override(jr_node *o, const char *key) {
  char path[JR_PATH + 64];
  full_path(o, key, path, sizeof path);
  jr_override *hit = NULL;
  for (int i = 0; i < o->r->nov; i++)
    if (strcmp(o->r->ov[i].path, path) == 0) {
      o->r->ov[i].used = 1;
      hit = &o->r->ov[i]; /* the last --set of a path wins */
    }
  return hit;
}

/* Keep a value made from an override alive until the reader is done. */
static const cJSON *keep(jr_reader *r, cJSON *v) {
  if (!v) return NULL;
  if (!r->tmp) r->tmp = cJSON_CreateArray();
  cJSON_AddItemToArray(r->tmp, v);
  return v;
}

enum { AS_NUMBER, AS_STRING, AS_JSON };

/* Item for key: the override (converted as `as` says) or the file's. */
static int lookup(jr_node *o, const char *key, int as, const cJSON **out) {
  mark_seen(o, key);
  jr_override *ov = find_override(o, key);
  if (!ov) {
    *out = o->j ? cJSON_GetObjectItemCaseSensitive(o->j, key) : NULL;
    return 0;
  }
  const char *s = ov->value;
  if (as == AS_NUMBER) {
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || (errno == ERANGE && isinf(v)))
      return jr_fail(o, key, "expected a number, found '%s' (from --set)", s);
    *out = keep(o->r, cJSON_CreateNumber(v));
  } else if (as == AS_STRING) {
    *out = keep(o->r, cJSON_CreateString(s));
  } else {
    cJSON *v = cJSON_Parse(s);
    if (!v) v = cJSON_CreateString(s);
    *out = keep(o->r, v);
  }
  return 0;
}

const cJSON *jr_override_json(jr_node *o, const char *key) {
  jr_override *ov = find_override(o, key);
  if (!ov) return NULL;
  cJSON *v = cJSON_Parse(ov->value);
  if (!v) v = cJSON_CreateString(ov->value);
  return keep(o->r, v);
}

int jr_num(jr_node *o, const char *key, double def, double lo, double hi,
           int lo_open, int hi_open, double *out) {
  const cJSON *v;
  MPGM_CALL(lookup(o, key, AS_NUMBER, &v));
  double x;
  if (!v) {
    if (isnan(def)) return jr_fail(o, key, "required key is missing (expected a number)");
    x = def;
  } else {
    if (!cJSON_IsNumber(v)) return jr_fail(o, key, "expected a number, found %s", jr_type(v));
    x = v->valuedouble;
    if (!isfinite(x)) return jr_fail(o, key, "expected a finite number, found %g", x);
    if ((lo_open ? !(x > lo) : !(x >= lo)) || (hi_open ? !(x < hi) : !(x <= hi))) {
      char lb[40], hb[40];
      if (isinf(lo)) snprintf(lb, sizeof lb, "(-inf");
      else snprintf(lb, sizeof lb, "%s%g", lo_open ? "(" : "[", lo);
      if (isinf(hi)) snprintf(hb, sizeof hb, "inf)");
      else snprintf(hb, sizeof hb, "%g%s", hi, hi_open ? ")" : "]");
      return jr_fail(o, key, "expected a number in %s, %s, found %g", lb, hb, x);
    }
  }
  *out = x;
  if (o->out) cJSON_AddNumberToObject(o->out, key, x);
  return 0;
}

int jr_int(jr_node *o, const char *key, int def, int lo, int hi, int *out) {
  const cJSON *v;
  MPGM_CALL(lookup(o, key, AS_NUMBER, &v));
  int x;
  if (!v) {
    if (def < lo) return jr_fail(o, key, "required key is missing (expected an integer)");
    x = def;
  } else {
    if (!cJSON_IsNumber(v)) return jr_fail(o, key, "expected an integer, found %s", jr_type(v));
    double d = v->valuedouble;
    if (!(d == floor(d)) || d < lo || d > hi)
      return jr_fail(o, key, "expected an integer in [%d, %d], found %g", lo, hi, d);
    x = (int)d;
  }
  *out = x;
  if (o->out) cJSON_AddNumberToObject(o->out, key, x);
  return 0;
}

int jr_enum(jr_node *o, const char *key, const char *const *choices, int def,
            int *out) {
  const cJSON *v;
  MPGM_CALL(lookup(o, key, AS_STRING, &v));
  char list[256] = "";
  for (int i = 0; choices[i]; i++) {
    size_t l = strlen(list);
    snprintf(list + l, sizeof list - l, "%s\"%s\"", i ? " | " : "", choices[i]);
  }
  int x = -1;
  if (!v) {
    if (def < 0) return jr_fail(o, key, "required key is missing (expected %s)", list);
    x = def;
  } else {
    if (!cJSON_IsString(v)) return jr_fail(o, key, "expected %s, found %s", list, jr_type(v));
    for (int i = 0; choices[i]; i++)
      if (strcmp(choices[i], v->valuestring) == 0) x = i;
    if (x < 0) return jr_fail(o, key, "expected %s, found \"%s\"", list, v->valuestring);
  }
  *out = x;
  if (o->out) cJSON_AddStringToObject(o->out, key, choices[x]);
  return 0;
}

int jr_str(jr_node *o, const char *key, const char *def, char *buf, size_t len) {
  const cJSON *v;
  MPGM_CALL(lookup(o, key, AS_STRING, &v));
  const char *s;
  if (!v) {
    if (!def) return jr_fail(o, key, "required key is missing (expected a string)");
    s = def;
  } else {
    if (!cJSON_IsString(v)) return jr_fail(o, key, "expected a string, found %s", jr_type(v));
    s = v->valuestring;
  }
  if (strlen(s) >= len)
    return jr_fail(o, key, "expected a string of at most %zu characters, found %zu",
                   len - 1, strlen(s));
  snprintf(buf, len, "%s", s);
  if (o->out) cJSON_AddStringToObject(o->out, key, buf);
  return 0;
}

int jr_vec2(jr_node *o, const char *key, const double *def, double out[2]) {
  const cJSON *v;
  MPGM_CALL(lookup(o, key, AS_JSON, &v));
  if (!v) {
    if (!def) return jr_fail(o, key, "required key is missing (expected [x, y])");
    out[0] = def[0];
    out[1] = def[1];
  } else {
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2)
      return jr_fail(o, key, "expected an array of 2 numbers [x, y], found %s%s",
                     jr_type(v), cJSON_IsArray(v) ? " of another length" : "");
    for (int i = 0; i < 2; i++) {
      const cJSON *e = cJSON_GetArrayItem(v, i);
      if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
        return jr_fail(o, key, "expected an array of 2 numbers [x, y], found %s at index %d",
                       jr_type(e), i);
      out[i] = e->valuedouble;
    }
  }
  if (o->out) cJSON_AddItemToObject(o->out, key, cJSON_CreateDoubleArray(out, 2));
  return 0;
}

int jr_child(jr_node *o, const char *key, int required, jr_node *child) {
  const cJSON *v;
  MPGM_CALL(lookup(o, key, AS_JSON, &v));
  memset(child, 0, sizeof *child);
  child->r = o->r;
  full_path(o, key, child->path, sizeof child->path);
  if (!v && required) return jr_fail(o, key, "required key is missing (expected an object)");
  if (v && !cJSON_IsObject(v)) return jr_fail(o, key, "expected an object, found %s", jr_type(v));
  child->j = v;
  if (o->out) {
    child->out = cJSON_CreateObject();
    cJSON_AddItemToObject(o->out, key, child->out);
  }
  return 0;
}

const cJSON *jr_raw(jr_node *o, const char *key) {
  mark_seen(o, key);
  return o->j ? cJSON_GetObjectItemCaseSensitive(o->j, key) : NULL;
}

int jr_end(jr_node *o) {
  if (!o->j) return 0;
  for (const cJSON *c = o->j->child; c; c = c->next) {
    int known = 0;
    for (int i = 0; i < o->nseen; i++)
      if (strcmp(o->seen[i], c->string) == 0) known = 1;
    if (!known) {
      char list[512] = "";
      for (int i = 0; i < o->nseen; i++) {
        size_t l = strlen(list);
        snprintf(list + l, sizeof list - l, "%s%s", i ? ", " : "", o->seen[i]);
      }
      return jr_fail(o, c->string, "unknown key (expected one of: %s)", list);
    }
    for (const cJSON *d = o->j->child; d != c; d = d->next)
      if (strcmp(d->string, c->string) == 0)
        return jr_fail(o, c->string, "duplicate key");
  }
  return 0;
}

int jr_unused_overrides(jr_reader *r) {
  for (int i = 0; i < r->nov; i++)
    if (!r->ov[i].used)
      return mpgm_err_set(r->ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                          "%s: %s: unknown path in --set %s=%s (no such key in the "
                          "scene schema, or no such array element / named entry)",
                          r->file, r->ov[i].path, r->ov[i].path, r->ov[i].value);
  return 0;
}

/* 1-based line and column of `at` in text. */
static void line_col(const char *text, const char *at, int *line, int *col) {
  *line = 1;
  *col = 1;
  for (const char *p = text; p < at && *p; p++) {
    if (*p == '\n') {
      (*line)++;
      *col = 1;
    } else {
      (*col)++;
    }
  }
}

int jr_parse_file(mpgm_ctx *ctx, const char *file, cJSON **doc) {
  *doc = NULL;
  char *text;
  MPGM_CALL(mpgm_read_file(ctx, file, &text, NULL));
  const char *end = NULL;
  cJSON *d = cJSON_ParseWithOpts(text, &end, 1);
  if (!d) {
    int line, col;
    const char *at = end ? end : cJSON_GetErrorPtr();
    if (!at) at = text;
    line_col(text, at, &line, &col);
    char near[24] = "";
    snprintf(near, sizeof near, "%.20s", at);
    for (char *p = near; *p; p++)
      if (*p == '\n' || *p == '\r') *p = ' ';
    free(text);
    MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: line %d, column %d: JSON syntax error near '%s'%s", file,
               line, col, near, near[0] ? "" : " (end of file)");
  }
  free(text);
  if (!cJSON_IsObject(d)) {
    const char *type = jr_type(d);
    cJSON_Delete(d);
    MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: (root): expected an object, found %s", file, type);
  }
  *doc = d;
  return 0;
}
