/* mpgm_test.c -- see mpgm_test.h. The counters are the test program's own
 * state (tests are executables, not library code). */
#include "mpgm_test.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

static int n_pass, n_fail;

static void report(int ok, const char *detail, const char *fmt, va_list ap) {
  if (ok) n_pass++; else n_fail++;
  if (ok && !getenv("MPGM_TEST_VERBOSE")) return;
  printf("%s: ", ok ? "PASS" : "FAIL");
  vprintf(fmt, ap);
  if (detail) printf(" %s", detail);
  printf("\n");
}

void mpgm_test_rel(double r, double e, double tol, const char *fmt, ...) {
  double scale = fabs(e) > 1e-300 ? fabs(e) : 1e-300;
  double err = fabs(r - e) / scale;
  int ok = isfinite(r) && err <= tol;
  char buf[160];
  snprintf(buf, sizeof buf, "(got %.17g, expected %.17g, rel err %.3g > tol %.3g)",
           r, e, err, tol);
  va_list ap; va_start(ap, fmt); report(ok, ok ? NULL : buf, fmt, ap); va_end(ap);
}

void mpgm_test_abs(double r, double e, double tol, const char *fmt, ...) {
  double err = fabs(r - e);
  int ok = isfinite(r) && err <= tol;
  char buf[160];
  snprintf(buf, sizeof buf, "(got %.17g, expected %.17g, abs err %.3g > tol %.3g)",
           r, e, err, tol);
  va_list ap; va_start(ap, fmt); report(ok, ok ? NULL : buf, fmt, ap); va_end(ap);
}

void mpgm_test(int ok, const char *fmt, ...) {
  va_list ap; va_start(ap, fmt); report(ok, NULL, fmt, ap); va_end(ap);
}

int mpgm_test_summary(void) {
  printf("%d passed, %d failed\n", n_pass, n_fail);
  return n_fail ? EXIT_FAILURE : EXIT_SUCCESS;
}

double uniform(rng *r, double a, double b) {
  r->s ^= r->s >> 12;
  r->s ^= r->s << 25;
  r->s ^= r->s >> 27;
  const uint64_t x = r->s * 0x2545F4914F6CDD1DULL;
  return a + (b - a) * ((double)(x >> 11) * 0x1.0p-53);
}
