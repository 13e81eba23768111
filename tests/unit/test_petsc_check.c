/* test_petsc_check.c -- the "petsc" backend's options judged before a run
 * (mpgm_solver_check: the KSP and PC set up once on a test system) and
 * the module's own hold on mpgm's policy (an instance created with an
 * option the scene loader would refuse):
 *   - -options_file /etc/passwd is refused as bad input by the module
 *     itself, and no line of the file reaches the message;
 *   - a misspelt option, an unknown type or solver package is bad input
 *     naming the scene file and solver.petsc; sound options pass;
 *   - the check uses the run's symmetry: an option of GMRES passes with an
 *     unsymmetric tangent (GMRES by default) and is unused with a
 *     symmetric one (CG by default);
 *   - an option of a multigrid level the test hierarchy lacks is left to
 *     the run; one of a level it has is checked;
 *   - the check leaves the caller's timers and counters alone, and a
 *     backend without options of its own passes without loading anything.
 * Skipped (one PASS line saying so) when mpgm was built without PETSc. */
#include <stdio.h>
#include <string.h>

#include "mpgm_solver.h"
#include "mpgm_test.h"

static const mpgm_solver_type *petsc;

/* mpgm_solver_check of options text with the given symmetry, the scene
 * file "scene.json"; the code, the message in msg. */
static int check(const char *text, int symmetric, char *msg, size_t len) {
  mpgm_ctx c;
  mpgm_ctx_init(&c);
  mpgm_solver_opts o = mpgm_solver_opts_default();
  snprintf(o.petsc, sizeof o.petsc, "%s", text);
  o.symmetric = symmetric;
  o.file = "scene.json";
  const int err = mpgm_solver_check(&c, petsc, &o);
  snprintf(msg, len, "%s", c.msg);
  int untouched = 1;
  for (int i = 0; i < MPGM_C_COUNT; i++) untouched &= c.count[i] == 0;
  for (int i = 0; i < MPGM_T_COUNT; i++) untouched &= c.t[i] == 0.0;
  mpgm_test(untouched, "check \"%s\": the context's counters and timers untouched", text);
  return err;
}

static void expect_ok(const char *text, int symmetric) {
  char msg[1024];
  const int err = check(text, symmetric, msg, sizeof msg);
  mpgm_test(err == 0, "\"%s\" (%ssymmetric) passes (%d: %s)", text, symmetric ? "" : "un", err, msg);
}

static void expect_bad(const char *text, int symmetric, const char *word) {
  char msg[1024];
  const int err = check(text, symmetric, msg, sizeof msg);
  mpgm_test(err == MPGM_ERR_INPUT && strncmp(msg, "scene.json: solver.petsc: ", 26) == 0 &&
                strstr(msg, word),
            "\"%s\" (%ssymmetric) refused as bad input naming the file and \"%s\" (%d: %s)", text,
            symmetric ? "" : "un", word, err, msg);
}

/* The module's own policy: an instance created with -options_file. */
static void module_refuses(void) {
  mpgm_ctx c;
  mpgm_ctx_init(&c);
  mpgm_solver_opts o = mpgm_solver_opts_default();
  snprintf(o.petsc, sizeof o.petsc, "-ksp_type cg -options_file /etc/passwd");
  o.file = "scene.json";
  mpgm_solver *s = NULL;
  const int err = mpgm_solver_create(&c, petsc, &o, &s);
  mpgm_test(err == MPGM_ERR_INPUT && !s && strstr(c.msg, "scene.json: solver.petsc: refused") &&
                strstr(c.msg, "-options_file") && !strstr(c.msg, "root:"),
            "an instance with -options_file /etc/passwd is refused by the module, the file unread "
            "(%d: %s)", err, c.msg);
  mpgm_solver_destroy(&s);
  mpgm_ctx_init(&c);
  snprintf(o.petsc, sizeof o.petsc, "-ksp_monitor binary:/tmp/mpgm_test_petsc_check.bin");
  o.file = NULL;
  const int err2 = mpgm_solver_create(&c, petsc, &o, &s);
  mpgm_test(err2 == MPGM_ERR_INPUT && !s && strncmp(c.msg, "solver.petsc: refused", 21) == 0,
            "an instance with a monitor to a file is refused, no file named without one (%d: %s)",
            err2, c.msg);
  mpgm_solver_destroy(&s);
}

int main(void) {
  char why[512];
  if (!mpgm_solver_usable("petsc", why, sizeof why)) {
    mpgm_test(1, "skipped: %s", why);
    return mpgm_test_summary();
  }
  petsc = mpgm_solver_type_find("petsc");
  /* without options of its own a backend passes at once */
  mpgm_ctx c;
  mpgm_ctx_init(&c);
  mpgm_solver_opts o = mpgm_solver_opts_default();
  mpgm_test(mpgm_solver_check(&c, mpgm_solver_type_find("umfpack"), &o) == 0 && !c.code,
            "umfpack: nothing to check");
  module_refuses();
  expect_ok("", 1);
  expect_ok("", 0);
  for (const mpgm_solver_preset *p = petsc->presets; p && p->name; p++) {
    expect_ok(p->options, 1);
    if (!p->spd_only) expect_ok(p->options, 0);
  }
  expect_ok("-pc_type sor", 0);
  expect_ok("-ksp_monitor -ksp_monitor_true_residual", 1);
  expect_bad("-pc_typo gamg", 1, "PETSc did not use -pc_typo");
  expect_bad("-ksp_type nosuchkrylov", 0, "Unable to find requested KSP type nosuchkrylov");
  expect_bad("-pc_type lu -pc_factor_mat_solver_type nosuchpackage", 0, "nosuchpackage");
  expect_bad("-ksp_rtol abc", 1, "abc");
  expect_bad("-pc_type fieldsplit", 1, "test system of 800 equations");
  /* the run's symmetry decides PETSc's defaults, and so which options it reads */
  expect_ok("-ksp_gmres_cgs_refinement_type refine_ifneeded", 0);
  expect_bad("-ksp_gmres_cgs_refinement_type refine_ifneeded", 1, "did not use");
  /* multigrid levels: the test hierarchy's are checked, others left to the run */
  expect_ok("-pc_type gamg -mg_levels_9_ksp_type richardson", 1);
  expect_bad("-pc_type gamg -mg_levels_1_ksp_typo richardson", 1, "-mg_levels_1_ksp_typo");
  expect_bad("-options_file /etc/passwd", 1, "refused \"-options_file\"");
  return mpgm_test_summary();
}
