/* test_json_strict.c -- the strict JSON check (io/json_strict.c) against
 * texts RFC 8259 and RFC 3629 accept and refuse (cases in the manner of
 * JSONTestSuite's y_ and n_ files), the offset it reports, and a random
 * round trip: every tree cJSON prints passes the check. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_json_reader.h"
#include "mpgm_test.h"

typedef struct {
  const char *text;
  size_t len;   /* 0: strlen(text) */
  long at;      /* offset of the fault, -1 when the text is valid */
} json_case;

#define OK(t) {t, 0, -1}
#define BAD(t, at) {t, 0, at}
#define BADN(t, n, at) {t, n, at}

static const json_case cases[] = {
    OK("{}"), OK("[]"), OK(" \t\r\n{ } \n"), OK("0"), OK("-0"), OK("-0.0e+0"), OK("1E-7"),
    OK("123456789012345678901234567890"), OK("1e400"), OK("\"\""), OK("\"\\u00e9\\ud83d\\ude00\""),
    OK("\"\\\"\\\\\\/\\b\\f\\n\\r\\t\""), OK("\"caf\xc3\xa9 \xe2\x80\x93 \xf0\x9f\x98\x80 \xf4\x8f\xbf\xbf\""),
    OK("{\"a\": [1, 2.5, -3e2, true, false, null, {\"b\": {}}]}"), OK("\xEF\xBB\xBF{}"),
    BAD("", 0), BAD("   ", 3), BAD("{", 1), BAD("[1,]", 3), BAD("{\"a\":1,}", 7), BAD("[1 2]", 3),
    BAD("{\"a\" 1}", 5), BAD("{a: 1}", 1), BAD("{'a': 1}", 1), BAD("[1] x", 4), BAD("{} {}", 3),
    BAD("01", 0), BAD("-01", 0), BAD("1.", 0), BAD(".5", 0), BAD("+1", 0), BAD("1e", 0),
    BAD("1e+", 0), BAD("-", 0), BAD("0x10", 1), BAD("[NaN]", 1), BAD("[Infinity]", 1),
    BAD("[-Infinity]", 1), BAD("tru", 0), BAD("nul", 0), BAD("True", 0),
    BAD("\"abc", 0), BAD("\"a\tb\"", 2), BAD("\"a\nb\"", 2), BAD("\"\\x41\"", 1), BAD("\"\\u12\"", 1),
    BAD("\"\\u0000\"", 1), BAD("{\"mesh\\u0000junk\": 1}", 6), BAD("\"\\ud800\"", 1),
    BAD("\"\\udc00\"", 1), BAD("\"\\ud800\\u0041\"", 1), BAD("\"\\ude00\\ud83d\"", 1),
    BAD("\"\xe9\"", 1), BAD("\"\xc0\xaf\"", 1), BAD("\"\xe0\x80\xaf\"", 1), BAD("\"\xed\xa0\x80\"", 1),
    BAD("\"\xf4\x90\x80\x80\"", 1), BAD("\"\xf5\x80\x80\x80\"", 1), BAD("\"\xc3\"", 1),
    BAD("\"\xe2\x80\"", 1), BAD("\"\x80\"", 1), BAD("\"\xff\"", 1),
    BADN("{}\0", 3, 2), BADN("{\"a\": \"b\0c\"}", 12, 8), BADN("[\0]", 3, 1), BADN("\0", 1, 0),
};

static void check_cases(void) {
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    const json_case *c = &cases[i];
    const size_t len = c->len ? c->len : strlen(c->text);
    size_t at = 0;
    char why[160];
    const int bad = jr_strict_check(c->text, len, &at, why, sizeof why);
    if (c->at < 0) {
      mpgm_test(!bad, "case %zu: '%.40s' is valid JSON (refused at %zu: %s)", i, c->text, at, why);
    } else {
      mpgm_test(bad && (long)at == c->at && why[0],
                "case %zu: '%.40s' is refused at offset %ld (bad %d, at %zu: %s)", i, c->text, c->at,
                bad, at, why);
    }
  }
}

/* JR_MAX_DEPTH nested arrays pass, one more is refused at its '['. */
static void check_depth(void) {
  char text[2 * JR_MAX_DEPTH + 8];
  for (int extra = 0; extra < 2; extra++) {
    const int d = JR_MAX_DEPTH + extra;
    memset(text, '[', (size_t)d);
    memset(text + d, ']', (size_t)d);
    size_t at;
    const int bad = jr_strict_check(text, (size_t)(2 * d), &at, NULL, 0);
    if (extra) mpgm_test(bad && at == (size_t)JR_MAX_DEPTH, "%d nested arrays are refused at the last '['", d);
    else mpgm_test(!bad, "%d nested arrays pass", d);
  }
}

static void check_numbers(void) {
  const char *yes[] = {"0", "-0", "0.5", "-12.25e-3", "1E+2", "1e999"};
  const char *no[] = {"", "01", "1.", ".5", "+1", "0x10", "1e", "nan", "inf", " 1", "1 ", "1,5"};
  for (size_t i = 0; i < sizeof yes / sizeof yes[0]; i++)
    mpgm_test(jr_is_json_number(yes[i]), "'%s' is a JSON number", yes[i]);
  for (size_t i = 0; i < sizeof no / sizeof no[0]; i++)
    mpgm_test(!jr_is_json_number(no[i]), "'%s' is not a JSON number", no[i]);
  mpgm_test(jr_utf8_invalid("ab\xc3\xa9", 4) == -1, "valid UTF-8 has no invalid byte");
  mpgm_test(jr_utf8_invalid("ab\xc3", 3) == 2, "a cut sequence is invalid at its start");
}

/* A random tree of objects, arrays, strings (with escapes and UTF-8),
 * numbers, literals: what cJSON prints is strict JSON, and reads back. */
static cJSON *random_tree(rng *r, int depth) {
  const int kind = depth > 4 ? (int)uniform(r, 2, 6) : (int)uniform(r, 0, 6);
  static const char *words[] = {"mesh", "a\"b", "tab\there", "\xc3\xa9t\xc3\xa9", "\x01ctl", "/\\"};
  if (kind == 0 || kind == 1) {
    cJSON *c = kind ? cJSON_CreateArray() : cJSON_CreateObject();
    const int n = (int)uniform(r, 0, 5);
    for (int i = 0; i < n; i++) {
      cJSON *v = random_tree(r, depth + 1);
      if (kind) cJSON_AddItemToArray(c, v);
      else cJSON_AddItemToObject(c, words[(int)uniform(r, 0, 6)], v);
    }
    return c;
  }
  if (kind == 2) return cJSON_CreateString(words[(int)uniform(r, 0, 6)]);
  if (kind == 3) return cJSON_CreateNumber(uniform(r, -1, 1) * 1e-300 * (1 + uniform(r, 0, 1e8)));
  if (kind == 4) return cJSON_CreateNumber(uniform(r, -1e12, 1e12));
  return uniform(r, 0, 1) < 0.5 ? cJSON_CreateNull() : cJSON_CreateBool(uniform(r, 0, 1) < 0.5);
}

static void check_round_trip(void) {
  rng r = {0x9E3779B97F4A7C15ull};
  int nbad = 0;
  for (int t = 0; t < 500; t++) {
    cJSON *tree = random_tree(&r, 0);
    char *text = t % 2 ? cJSON_Print(tree) : cJSON_PrintUnformatted(tree);
    size_t at;
    char why[160];
    if (jr_strict_check(text, strlen(text), &at, why, sizeof why)) {
      if (!nbad++) fprintf(stderr, "tree %d: '%.60s' refused at %zu: %s\n", t, text, at, why);
    }
    free(text);
    cJSON_Delete(tree);
  }
  mpgm_test(nbad == 0, "500 random trees printed by cJSON pass the check (%d refused)", nbad);
}

int main(void) {
  check_cases();
  check_depth();
  check_numbers();
  check_round_trip();
  return mpgm_test_summary();
}
