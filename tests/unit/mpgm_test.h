/* mpgm_test.h -- tiny unit-check helpers in the spirit of gsl_test:
 * one line per check, named tolerances in units of machine epsilon. */
#ifndef MPGM_TEST_H
#define MPGM_TEST_H

#include <float.h>
#include <stdint.h>

#define TEST_TOL0 (2.0 * DBL_EPSILON)
#define TEST_TOL1 (16.0 * DBL_EPSILON)
#define TEST_TOL2 (256.0 * DBL_EPSILON)
#define TEST_TOL3 (2048.0 * DBL_EPSILON)
#define TEST_TOL4 (16384.0 * DBL_EPSILON)
#define TEST_TOL5 (131072.0 * DBL_EPSILON)
#define TEST_TOL6 (1048576.0 * DBL_EPSILON)

/** Check |result - expected| <= tol * max(|expected|, 1e-300); prints one
 *  line (only failures unless MPGM_TEST_VERBOSE is set). */
void mpgm_test_rel(double result, double expected, double tol,
                   const char *fmt, ...);
/** Check |result - expected| <= tol. */
void mpgm_test_abs(double result, double expected, double tol,
                   const char *fmt, ...);
/** Check a condition. */
void mpgm_test(int ok, const char *fmt, ...);
/** Deterministic PRNG (xorshift64*): tests are repeatable bit for bit. */
typedef struct rng { uint64_t s; } rng;
/** Uniform double in [a, b). The state must be seeded non-zero. */
double uniform(rng *r, double a, double b);
/** Print the summary line "N passed, M failed" and return the exit status. */
int mpgm_test_summary(void);

#endif
