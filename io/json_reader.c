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

/* An override's value as JSON when it is JSON (arrays, objects, numbers,
 * ...), as a string otherwise (jr_check_override has refused a value that
 * starts like an array or object and is not JSON). */
static const cJSON *override_json(jr_node *o, const jr_override *ov) {
  const char *s = ov->value;
  const int json = !jr_strict_check(s, strlen(s), NULL, NULL, 0);
  return keep(o->r, json ? cJSON_Parse(s) : cJSON_CreateString(s));
}

int jr_check_override(mpgm_ctx *ctx, const char *file, const jr_override *ov) {
  const char *s = ov->value;
  char why[160];
  size_t at;
  const long bad = jr_utf8_invalid(s, strlen(s));
  MPGM_CHECK(ctx, bad < 0, MPGM_ERR_INPUT, "%s: %s: --set value is not UTF-8 (byte 0x%02X at "
             "character %ld)", file, ov->path, (unsigned)(unsigned char)s[bad < 0 ? 0 : bad], bad + 1);
  const char *p = s + strspn(s, " \t\r\n");
  if ((*p == '[' || *p == '{') && jr_strict_check(s, strlen(s), &at, why, sizeof why))
    MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: %s: --set value '%s' is not JSON: %s at character %zu",
               file, ov->path, s, why, at + 1);
  return 0;
}

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
    double v = strtod(s, NULL);
    if (!jr_is_json_number(s))
      return jr_fail(o, key, "expected a number in JSON's form (e.g. 0.05, -2, 1e-6), found '%s' "
                     "(from --set)", s);
    if (!isfinite(v)) return jr_fail(o, key, "expected a finite number, found '%s' (from --set)", s);
    *out = keep(o->r, cJSON_CreateNumber(v));
  } else if (as == AS_STRING) {
    *out = keep(o->r, cJSON_CreateString(s));
  } else {
    *out = override_json(o, ov);
  }
  return 0;
}

const cJSON *jr_override_json(jr_node *o, const char *key) {
  const jr_override *ov = find_override(o, key);
  return ov ? override_json(o, ov) : NULL;
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

int jr_bool(jr_node *o, const char *key, int def, int *out) {
  const cJSON *v;
  MPGM_CALL(lookup(o, key, AS_JSON, &v));
  if (v && !cJSON_IsBool(v)) return jr_fail(o, key, "expected true or false, found %s", jr_type(v));
  *out = v ? cJSON_IsTrue(v) : def;
  if (o->out) cJSON_AddBoolToObject(o->out, key, *out);
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

/* 1-based line and column (in bytes) of offset at of text. */
static void line_col(const char *text, size_t at, int *line, int *col) {
  *line = 1;
  *col = 1;
  for (size_t i = 0; i < at; i++) {
    if (text[i] == '\n') {
      (*line)++;
      *col = 1;
    } else {
      (*col)++;
    }
  }
}

/* Up to 20 bytes of text from at, printable ASCII only (others as '?'). */
static void excerpt(const char *text, size_t len, size_t at, char near[24]) {
  size_t k = 0;
  for (size_t i = at; i < len && k < 20; i++, k++) {
    const unsigned char c = (unsigned char)text[i];
    near[k] = c == '\n' || c == '\r' || c == '\t' ? ' ' : c >= 0x20 && c < 0x7F ? (char)c : '?';
  }
  near[k] = '\0';
}

int jr_parse_text(mpgm_ctx *ctx, const char *file, const char *text, size_t len, cJSON **doc) {
  *doc = NULL;
  char why[160], near[24];
  size_t at;
  int line, col;
  if (jr_strict_check(text, len, &at, why, sizeof why)) {
    line_col(text, at, &line, &col);
    excerpt(text, len, at, near);
    /* a text that does not even begin as a JSON document (any file may be
     * named where a scene is expected: /etc/shadow) is not repeated */
    size_t k = 0;
    while (k < len && strchr(" \t\r\n", text[k]) && text[k]) k++;
    if (k >= len || (text[k] != '{' && text[k] != '['))
      MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: line %d, column %d: JSON syntax error: not a JSON document (it "
                 "does not begin with '{' or '['; its content is not repeated here)", file, line, col);
    MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: line %d, column %d: JSON syntax error: %s (near '%s'%s)",
               file, line, col, why, near, near[0] ? "" : ", the end of the file");
  }
  const char *end = NULL;
  cJSON *d = cJSON_ParseWithLengthOpts(text, len, &end, 0);
  if (!d) { /* the strict check passed: cJSON fails only when memory runs out */
    at = end ? (size_t)(end - text) : 0;
    line_col(text, at < len ? at : len, &line, &col);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "%s: line %d, column %d: cJSON could not build the tree "
               "(out of memory?)", file, line, col);
  }
  if (!cJSON_IsObject(d)) {
    const char *type = jr_type(d);
    cJSON_Delete(d);
    MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: (root): expected an object, found %s", file, type);
  }
  *doc = d;
  return 0;
}

int jr_parse_file(mpgm_ctx *ctx, const char *file, cJSON **doc) {
  *doc = NULL;
  char *text;
  size_t len;
  MPGM_CALL(mpgm_read_file(ctx, file, JR_MAX_FILE, &text, &len));
  const int err = jr_parse_text(ctx, file, text, len, doc);
  free(text);
  return err;
}

/* Lengths in cells (docs/scene-format.md, "Lengths in cells"): a number is
 * metres; {"cells": k} is k h and {"at": x, "cells": k} is x + k h, so that a
 * case says "one cell high" or "a quarter cell from the end" once and a
 * finer mesh.h keeps it. k h is one product (exact when k is a power of two,
 * so that k = 1, 0.5, -1 give the very double a scene would write in
 * metres); x + k h adds it to x once. */
static int len_of(jr_node *o, const char *key, const cJSON *v, const char *where, double *x) {
  static const char form[] = "a length: a number (metres), {\"cells\": k} (k mesh.h) or "
                             "{\"at\": x, \"cells\": k} (x + k mesh.h)";
  if (cJSON_IsNumber(v)) {
    if (!isfinite(v->valuedouble)) return jr_fail(o, key, "expected a finite number%s", where);
    *x = v->valuedouble;
    return 0;
  }
  if (!cJSON_IsObject(v)) return jr_fail(o, key, "expected %s%s, found %s", form, where, jr_type(v));
  const cJSON *k = NULL, *at = NULL;
  for (const cJSON *c = v->child; c; c = c->next) {
    const int is_k = strcmp(c->string, "cells") == 0, is_at = strcmp(c->string, "at") == 0;
    if (!is_k && !is_at)
      return jr_fail(o, key, "expected %s%s, found the key \"%s\"", form, where, c->string);
    if ((is_k && k) || (is_at && at))
      return jr_fail(o, key, "expected %s%s, found \"%s\" twice", form, where, c->string);
    if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble))
      return jr_fail(o, key, "expected %s%s, found %s for \"%s\"", form, where, jr_type(c), c->string);
    if (is_k) k = c;
    else at = c;
  }
  if (!k) return jr_fail(o, key, "expected %s%s, found no \"cells\"", form, where);
  if (!(o->r->h > 0.0))
    return jr_fail(o, key, "a length in cells needs mesh.h, which is not known here");
  const double kh = k->valuedouble * o->r->h;
  *x = at ? at->valuedouble + kh : kh;
  if (!isfinite(*x)) return jr_fail(o, key, "expected a finite length%s, found %g", where, *x);
  return 0;
}

int jr_len(jr_node *o, const char *key, double def, double lo, double hi, double *out) {
  const cJSON *v;
  MPGM_CALL(lookup(o, key, AS_JSON, &v));
  double x = def;
  if (!v && isnan(def)) return jr_fail(o, key, "required key is missing (expected a length)");
  if (v) MPGM_CALL(len_of(o, key, v, "", &x));
  if (!(x >= lo && x <= hi)) {
    char lb[40], hb[40];
    if (isinf(lo)) snprintf(lb, sizeof lb, "(-inf");
    else snprintf(lb, sizeof lb, "[%g", lo);
    if (isinf(hi)) snprintf(hb, sizeof hb, "inf)");
    else snprintf(hb, sizeof hb, "%g]", hi);
    return jr_fail(o, key, "expected a length in %s, %s m, found %g m", lb, hb, x);
  }
  *out = x;
  if (o->out) cJSON_AddNumberToObject(o->out, key, x);
  return 0;
}

/* [x, y] ([x, y, z] in 3-D): MPGM_DIM finite numbers, or (lengths)
 * MPGM_DIM lengths as len_of reads them; def NULL: required. */
static int vec_read(jr_node *o, const char *key, const double *def, int lengths,
                    double out[MPGM_DIM]) {
  const char *what = lengths ? "lengths" : "numbers", *form = MPGM_DIM == 2 ? "[x, y]" : "[x, y, z]";
  const cJSON *v;
  MPGM_CALL(lookup(o, key, AS_JSON, &v));
  if (!v) {
    if (!def) return jr_fail(o, key, "required key is missing (expected %s)", form);
    for (int i = 0; i < MPGM_DIM; i++) out[i] = def[i];
  } else {
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != MPGM_DIM)
      return jr_fail(o, key, "expected an array of %d %s %s, found %s%s", MPGM_DIM, what, form,
                     jr_type(v), cJSON_IsArray(v) ? " of another length" : "");
    for (int i = 0; i < MPGM_DIM; i++) {
      const cJSON *e = cJSON_GetArrayItem(v, i);
      if (lengths) {
        char at[16];
        snprintf(at, sizeof at, " at index %d", i);
        MPGM_CALL(len_of(o, key, e, at, &out[i]));
        continue;
      }
      if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
        return jr_fail(o, key, "expected an array of %d numbers %s, found %s at index %d", MPGM_DIM,
                       form, jr_type(e), i);
      out[i] = e->valuedouble;
    }
  }
  if (o->out) cJSON_AddItemToObject(o->out, key, cJSON_CreateDoubleArray(out, MPGM_DIM));
  return 0;
}

int jr_vec(jr_node *o, const char *key, const double *def, double out[MPGM_DIM]) {
  return vec_read(o, key, def, 0, out);
}

int jr_vec_len(jr_node *o, const char *key, const double *def, double out[MPGM_DIM]) {
  return vec_read(o, key, def, 1, out);
}
