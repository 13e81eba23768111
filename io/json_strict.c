/* json_strict.c -- strict RFC 8259 check of a JSON text before cJSON reads it.
 *
 * cJSON is lenient where a simulation input must not be: it stops at a NUL
 * byte (the rest of the file is silently ignored), it keeps "\u0000" in a key
 * or string as a terminator ("mesh\u0000junk" reads as "mesh"), it copies
 * bytes that are not UTF-8 into strings (and so into summary.json, which is
 * then not JSON), and it takes numbers JSON forbids ("01", "1.", "-.5").
 * This recursive-descent checker walks the text once, rejects all of these
 * with the offset of the first fault, and leaves the tree building to cJSON.
 */
#include "mpgm_json_reader.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

typedef struct {
  const unsigned char *s, *end;
  size_t at;     /* offset of the fault */
  char *why;
  size_t nwhy;
  int depth;
} jv;

static int jv_fail(jv *v, const unsigned char *p, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static int jv_fail(jv *v, const unsigned char *p, const char *fmt, ...) {
  v->at = (size_t)(p - v->s);
  va_list ap;
  va_start(ap, fmt);
  if (v->nwhy) vsnprintf(v->why, v->nwhy, fmt, ap);
  va_end(ap);
  return 1;
}

/* Length of the UTF-8 sequence at p (1..4), 0 when it is not one: overlong
 * forms, UTF-16 surrogates (U+D800..DFFF) and code points above U+10FFFF are
 * refused, as RFC 3629 says. */
static int utf8_len(const unsigned char *p, const unsigned char *end) {
  const unsigned c = p[0];
  int n;
  unsigned lo = 0x80, hi = 0xBF;
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (end - p < n) return 0;
  if (p[1] < lo || p[1] > hi) return 0;
  for (int i = 2; i < n; i++)
    if (p[i] < 0x80 || p[i] > 0xBF) return 0;
  return n;
}

long jr_utf8_invalid(const char *text, size_t len) {
  const unsigned char *s = (const unsigned char *)text, *p = s, *end = s + len;
  while (p < end) {
    const int n = utf8_len(p, end);
    if (!n) return (long)(p - s);
    p += n;
  }
  return -1;
}

static void skip_ws(jv *v, const unsigned char **p) {
  while (*p < v->end && (**p == ' ' || **p == '\t' || **p == '\n' || **p == '\r')) (*p)++;
}

static int hex4(const unsigned char *p, const unsigned char *end, unsigned *u) {
  if (end - p < 4) return 1;
  *u = 0;
  for (int i = 0; i < 4; i++) {
    const unsigned c = p[i];
    unsigned d;
    if (c >= '0' && c <= '9') d = c - '0';
    else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
    else if (c >= 'A' && c <= 'F') d = c - 'A' + 10;
    else return 1;
    *u = *u << 4 | d;
  }
  return 0;
}

/* \uXXXX at p (p at the 'u'): a NUL, a lone or reversed surrogate is a fault. */
static int unicode_escape(jv *v, const unsigned char **pp) {
  const unsigned char *p = *pp, *start = p - 1;
  unsigned u, w;
  if (hex4(p + 1, v->end, &u)) return jv_fail(v, start, "\\u must be followed by 4 hex digits");
  p += 5;
  if (u == 0)
    return jv_fail(v, start, "\\u0000 (a NUL character) is not allowed in a key or string");
  if (u >= 0xDC00 && u <= 0xDFFF)
    return jv_fail(v, start, "\\u%04X is a lone low surrogate (not a character)", u);
  if (u >= 0xD800 && u <= 0xDBFF) {
    if (v->end - p < 6 || p[0] != '\\' || p[1] != 'u' || hex4(p + 2, v->end, &w) ||
        w < 0xDC00 || w > 0xDFFF)
      return jv_fail(v, start, "\\u%04X is a high surrogate without its low half", u);
    p += 6;
  }
  *pp = p;
  return 0;
}

static int string(jv *v, const unsigned char **pp) {
  const unsigned char *p = *pp + 1; /* after the opening quote */
  for (;;) {
    if (p >= v->end) return jv_fail(v, *pp, "string not closed before the end of the file");
    const unsigned c = *p;
    if (c == '"') break;
    if (c == 0) return jv_fail(v, p, "NUL byte inside a string");
    if (c < 0x20) return jv_fail(v, p, "control character 0x%02X inside a string (escape it)", c);
    if (c == '\\') {
      if (p + 1 >= v->end) return jv_fail(v, p, "string not closed before the end of the file");
      const unsigned e = p[1];
      p++;
      if (e == 'u') {
        if (unicode_escape(v, &p)) return 1;
        continue;
      }
      if (!strchr("\"\\/bfnrt", (int)e) || !e)
        return jv_fail(v, p - 1, "invalid escape '\\%c' in a string", e >= 0x20 && e < 0x7F ? e : '?');
      p++;
      continue;
    }
    const int n = utf8_len(p, v->end);
    if (!n) return jv_fail(v, p, "byte 0x%02X is not valid UTF-8 (strings must be UTF-8)", c);
    p += n;
  }
  *pp = p + 1;
  return 0;
}

static int is_digit(const unsigned char *p, const unsigned char *end) {
  return p < end && *p >= '0' && *p <= '9';
}

/* JSON's number: -? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)? */
static int number(jv *v, const unsigned char **pp) {
  const unsigned char *p = *pp, *start = p;
  if (p < v->end && *p == '-') p++;
  if (!is_digit(p, v->end)) return jv_fail(v, start, "a number must start with a digit (after an optional '-')");
  if (*p == '0' && is_digit(p + 1, v->end))
    return jv_fail(v, start, "a number may not have a leading zero");
  while (is_digit(p, v->end)) p++;
  if (p < v->end && *p == '.') {
    p++;
    if (!is_digit(p, v->end)) return jv_fail(v, start, "a digit must follow the decimal point");
    while (is_digit(p, v->end)) p++;
  }
  if (p < v->end && (*p == 'e' || *p == 'E')) {
    p++;
    if (p < v->end && (*p == '+' || *p == '-')) p++;
    if (!is_digit(p, v->end)) return jv_fail(v, start, "a digit must follow the exponent's 'e'");
    while (is_digit(p, v->end)) p++;
  }
  *pp = p;
  return 0;
}

static int value(jv *v, const unsigned char **pp);

/* Array or object at *pp; `close` is ']' or '}'. */
static int container(jv *v, const unsigned char **pp, unsigned char close) {
  const unsigned char *p = *pp + 1;
  if (++v->depth > JR_MAX_DEPTH)
    return jv_fail(v, *pp, "nested deeper than %d arrays and objects", JR_MAX_DEPTH);
  skip_ws(v, &p);
  if (p < v->end && *p == close) {
    *pp = p + 1;
    v->depth--;
    return 0;
  }
  for (;;) {
    if (close == '}') {
      if (p >= v->end || *p != '"') return jv_fail(v, p, "expected a key in double quotes");
      if (string(v, &p)) return 1;
      skip_ws(v, &p);
      if (p >= v->end || *p != ':') return jv_fail(v, p, "expected ':' after the key");
      p++;
    }
    skip_ws(v, &p);
    if (value(v, &p)) return 1;
    skip_ws(v, &p);
    if (p < v->end && *p == ',') {
      p++;
      skip_ws(v, &p);
      continue;
    }
    if (p < v->end && *p == close) break;
    return jv_fail(v, p, "expected ',' or '%c'", close);
  }
  *pp = p + 1;
  v->depth--;
  return 0;
}

static int literal(jv *v, const unsigned char **pp, const char *word) {
  const size_t n = strlen(word);
  if ((size_t)(v->end - *pp) < n || memcmp(*pp, word, n) != 0)
    return jv_fail(v, *pp, "expected a value (object, array, string, number, true, false or null)");
  *pp += n;
  return 0;
}

static int value(jv *v, const unsigned char **pp) {
  if (*pp >= v->end) return jv_fail(v, *pp, "expected a value, found the end of the file");
  switch (**pp) {
  case '{': return container(v, pp, '}');
  case '[': return container(v, pp, ']');
  case '"': return string(v, pp);
  case 't': return literal(v, pp, "true");
  case 'f': return literal(v, pp, "false");
  case 'n': return literal(v, pp, "null");
  case 0: return jv_fail(v, *pp, "NUL byte (a JSON text may not contain one)");
  default:
    if (**pp == '-' || (**pp >= '0' && **pp <= '9') || **pp == '.' || **pp == '+') return number(v, pp);
    return jv_fail(v, *pp, "expected a value (object, array, string, number, true, false or null)");
  }
}

int jr_strict_check(const char *text, size_t len, size_t *at, char *why, size_t nwhy) {
  jv v = {.s = (const unsigned char *)text, .end = (const unsigned char *)text + len,
          .why = why, .nwhy = nwhy};
  const unsigned char *p = v.s;
  if (nwhy) why[0] = '\0';
  /* a UTF-8 byte order mark is not JSON (RFC 8259 section 8.1) but harmless */
  if (len >= 3 && memcmp(p, "\xEF\xBB\xBF", 3) == 0) p += 3;
  skip_ws(&v, &p);
  int bad = value(&v, &p);
  if (!bad) {
    skip_ws(&v, &p);
    if (p < v.end)
      bad = jv_fail(&v, p, *p ? "text after the end of the JSON value"
                              : "NUL byte (a JSON text may not contain one)");
  }
  if (at) *at = bad ? v.at : len;
  return bad;
}

int jr_is_json_number(const char *s) {
  const size_t n = strlen(s);
  jv v = {.s = (const unsigned char *)s, .end = (const unsigned char *)s + n};
  const unsigned char *p = v.s;
  return n > 0 && number(&v, &p) == 0 && p == v.end;
}
