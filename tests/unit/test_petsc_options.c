/* test_petsc_options.c -- the policy of solver.petsc (solvers/petsc_options.c,
 * docs/scene-format.md "PETSc options are confined"): strings it accepts
 * (every preset of solvers/plugin.c and every string cases/, tests/,
 * bench/ and docs/ hand to solver.petsc among them) with the options they
 * split into, and strings it refuses with the token and the reason it
 * names. No PETSc here: the split is mpgm's own. */
#include <stdio.h>
#include <string.h>

#include "mpgm_petsc_options.h"
#include "mpgm_solver.h"
#include "mpgm_test.h"

typedef struct {
  const char *text;
  int n;              /* options it splits into */
  const char *first;  /* the first one, "name=value" or "name" */
} ok_case;

static const ok_case accepted[] = {
    {"", 0, NULL},
    {"   ", 0, NULL},
    /* bench/cost_growth, tests/scripts/petsc.sh, the cases' descriptions, docs */
    {"-ksp_type gmres -pc_type ilu", 2, "ksp_type=gmres"},
    {"-pc_type gamg", 1, "pc_type=gamg"},
    {"-pc_type hypre", 1, "pc_type=hypre"},
    {"-pc_type sor", 1, "pc_type=sor"},
    {"-ksp_type gmres -pc_type hypre", 2, "ksp_type=gmres"},
    {"-ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps", 3, "ksp_type=preonly"},
    {"-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps", 3, "ksp_type=preonly"},
    {"-ksp_max_it 2", 1, "ksp_max_it=2"},
    {"-ksp_max_it 1", 1, "ksp_max_it=1"},
    {"-ksp_gmres_breakdown_tolerance 1e-300", 1, "ksp_gmres_breakdown_tolerance=1e-300"},
    {"-ksp_gmres_cgs_refinement_type refine_ifneeded", 1, "ksp_gmres_cgs_refinement_type=refine_ifneeded"},
    /* a misspelt name passes the policy: PETSc's own check finds it */
    {"-pc_typo gamg", 1, "pc_typo=gamg"},
    /* -2 is a value, not a name (PetscOptionsValidKey), and so are -inf and -nan */
    {"-mat_mumps_icntl_10 -2", 1, "mat_mumps_icntl_10=-2"},
    {"-ksp_divtol -inf -ksp_rtol 1e-8", 2, "ksp_divtol=-inf"},
    {"-pc_hypre_boomeramg_relax_type_all symmetric-SOR/Jacobi", 1,
     "pc_hypre_boomeramg_relax_type_all=symmetric-SOR/Jacobi"},
    {"-pc_hypre_boomeramg_agg_num_paths 2", 1, "pc_hypre_boomeramg_agg_num_paths=2"},
    {"-ksp_type lgmres -ksp_lgmres_augment 3", 2, "ksp_type=lgmres"},
    {"-ksp_monitor -ksp_type cg", 2, "ksp_monitor"},
    {"-ksp_type cg -ksp_monitor_true_residual", 2, "ksp_type=cg"},
    {"-mg_levels_ksp_monitor -pc_type gamg", 2, "mg_levels_ksp_monitor"},
    {"-mat_mumps_icntl_4 2 -mat_mumps_icntl_1 6 -mat_mumps_icntl_2 0 -mat_mumps_icntl_22 0", 4,
     "mat_mumps_icntl_4=2"},
    {"  -ksp_rtol   1e-8  -ksp_norm_type unpreconditioned ", 2, "ksp_rtol=1e-8"},
    {"\"-ksp_type\" \"cg\" -pc_type jacobi", 2, "ksp_type=cg"},
    {"-KSP_Type CG", 1, "KSP_Type=CG"},
    {"-sub_pc_type ilu -pc_type bjacobi -pc_composite_pcs ilu,jacobi", 3, "sub_pc_type=ilu"},
    {"-pc_factor_levels 1 -pc_factor_shift_type nonzero -pc_factor_shift_amount 1.5e-12", 3,
     "pc_factor_levels=1"},
    {"-ksp_initial_guess_nonzero -pc_type none", 2, "ksp_initial_guess_nonzero"},
};

typedef struct {
  const char *text;
  const char *token; /* the refused token as the message shows it */
  const char *word;  /* a word of the reason */
} bad_case;

static const bad_case refused[] = {
    /* files of options, prefixes */
    {"-options_file /etc/passwd", "-options_file", "file"},
    {"-ksp_type cg -options_file /etc/passwd", "-options_file", "file"},
    {"\"-options_file\" /etc/passwd", "-options_file", "file"},
    {"-OPTIONS_FILE /etc/passwd", "-OPTIONS_FILE", "file"},
    {"-options_file_yaml x.yaml", "-options_file_yaml", "file"},
    {"-options_string_yaml a", "-options_string_yaml", "YAML"},
    {"-options_left", "-options_left", "database"},
    {"-prefix_push mpgm0_ -ksp_type cg -prefix_pop", "-prefix_push", "prefix"},
    {"-prefix_pop", "-prefix_pop", "prefix"},
    /* viewers, monitors and the like */
    {"-ksp_monitor :/tmp/owned", ":/tmp/owned", "no value"},
    {"-ksp_monitor ascii", "ascii", "no value"},
    {"-ksp_monitor_true_residual draw", "draw", "no value"},
    {"-ksp_view_mat binary:/tmp/A.bin", "-ksp_view_mat", "results folder"},
    {"-ksp_view", "-ksp_view", "views"},
    {"-mat_view ::ascii_matlab", "-mat_view", "views"},
    {"-pc_gamg_view", "-pc_gamg_view", "views"},
    {"-ksp_monitor_lg_residualnorm", "-ksp_monitor_lg_residualnorm", "monitors"},
    {"-ksp_monitor_short", "-ksp_monitor_short", "monitors"},
    {"-ksp_gmres_krylov_monitor", "-ksp_gmres_krylov_monitor", "monitors"},
    {"-ksp_plot_eigenvalues", "-ksp_plot_eigenvalues", "draws"},
    {"-ksp_converged_reason", "-ksp_converged_reason", "viewer"},
    {"-ksp_converged_reason ascii:/tmp/r.txt", "-ksp_converged_reason", "viewer"},
    {"-ksp_converged_rate", "-ksp_converged_rate", "viewer"},
    {"-ksp_compute_eigenvalues", "-ksp_compute_eigenvalues", "viewer"},
    {"-ksp_final_residual", "-ksp_final_residual", "viewer"},
    {"-log_view", "-log_view", "logs"},
    {"-log_trace /tmp/trace", "-log_trace", "logs"},
    {"-pc_mg_log", "-pc_mg_log", "logs"},
    {"-viewer_binary_filename /tmp/x", "-viewer_binary_filename", "views"},
    {"-history /tmp/h", "-history", "results folder"},
    {"-malloc_dump", "-malloc_dump", "results folder"},
    {"-malloc_debug", "-malloc_debug", "results folder"},
    {"-info", "-info", "results folder"},
    {"-info /tmp/info.txt", "-info", "results folder"},
    {"-start_in_debugger", "-start_in_debugger", "debugs"},
    {"-on_error_attach_debugger gdb", "-on_error_attach_debugger", "debugs"},
    {"-debug_terminal xterm", "-debug_terminal", "debugs"},
    {"-on_error_emacs host", "-on_error_emacs", "results folder"},
    {"-dll_append /tmp/libx.so", "-dll_append", "results folder"},
    {"-display :0", "-display", "results folder"},
    {"-pc_hypre_boomeramg_print_statistics 1", "-pc_hypre_boomeramg_print_statistics", "prints"},
    {"-mat_superlu_dist_statprint", "-mat_superlu_dist_statprint", "prints"},
    {"-objects_dump", "-objects_dump", "results folder"},
    {"-mat_mumps_ooc_tmpdir /tmp", "-mat_mumps_ooc_tmpdir", "folder"},
    {"-ksp_monitor_python mod.fn", "-ksp_monitor_python", "Python"},
    /* MUMPS's streams, print level, out-of-core factors */
    {"-mat_mumps_icntl_1 7", "-mat_mumps_icntl_1", "fort.N"},
    {"-mat_mumps_icntl_2 12", "-mat_mumps_icntl_2", "fort.N"},
    {"-mat_mumps_icntl_3 5", "-mat_mumps_icntl_3", "fort.N"},
    {"-mat_mumps_icntl_3", "-mat_mumps_icntl_3", "fort.N"},
    {"-sub_mat_mumps_icntl_1 9", "-sub_mat_mumps_icntl_1", "fort.N"},
    {"-mat_mumps_icntl_4 9", "-mat_mumps_icntl_4", "print level"},
    {"-mat_mumps_icntl_22 1", "-mat_mumps_icntl_22", "out-of-core"},
    /* values that could name files, viewers or code */
    {"-pc_type python", "python", "Python"},
    {"-ksp_type PYTHON", "PYTHON", "Python"},
    {"-pc_factor_mat_ordering_type /tmp/x", "/tmp/x", "file"},
    {"-ksp_type ~/x", "~/x", "file"},
    {"-pc_type a:b", "a:b", "viewer"},
    {"-ksp_type $HOME", "$HOME", "file"},
    {"-pc_type ../up", "../up", "file"},
    {"-pc_type \"a b\"", "a b", "file"},
    {"-pc_hypre_boomeramg_relax_type_all /SOR/Jacobi", "/SOR/Jacobi", "file"},
    /* what PETSc would read differently from what it looks like */
    {"ksp_type cg", "ksp_type", "no option before it"},
    {"-ksp_type cg gmres", "gmres", "no option before it"},
    {"-ksp_type\tcg", NULL, "control character"},
    {"-ksp_type cg\n-pc_type ilu", NULL, "control character"},
    {"--ksp_type cg", "--ksp_type", "one '-'"},
    {"-ksp_type \"cg", "\"cg", "without its end"},
    {"-ksp_type \"cg\"x", "\"cg\"x", "followed by a space"},
    {"-ksp_type \"\"", "\"\"", "empty"},
    {"-ksp.type cg", "-ksp.type", "letters, digits"},
    {"-ksp_type cg -", "-", "no option before it"},
};

static void split_str(const mpgm_petsc_options *o, int k, char *buf, size_t len) {
  if (o->value[k]) snprintf(buf, len, "%s=%s", o->name[k], o->value[k]);
  else snprintf(buf, len, "%s", o->name[k]);
}

static void check_accepted(void) {
  for (size_t i = 0; i < sizeof accepted / sizeof *accepted; i++) {
    const ok_case *c = &accepted[i];
    mpgm_petsc_options o;
    char why[256], first[600] = "";
    const int err = mpgm_petsc_options_parse(c->text, &o, why, sizeof why);
    if (!err && o.n > 0) split_str(&o, 0, first, sizeof first);
    mpgm_test(!err && o.n == c->n && (c->n == 0 || strcmp(first, c->first) == 0),
              "accepted \"%s\": %d options, the first %s (err %d: %s; %d, %s)", c->text, c->n,
              c->first ? c->first : "-", err, err ? why : "", o.n, first);
  }
}

/* The presets `mpgm bench-solvers` runs (solvers/plugin.c) pass too. */
static void check_presets(void) {
  const mpgm_solver_type *pt = mpgm_solver_type_find("petsc");
  mpgm_test(pt && pt->presets, "the petsc backend has presets");
  int n = 0;
  for (const mpgm_solver_preset *p = pt ? pt->presets : NULL; p && p->name; p++, n++) {
    char why[256];
    const int err = mpgm_petsc_options_parse(p->options, NULL, why, sizeof why);
    mpgm_test(!err, "preset %s (\"%s\") accepted (%s)", p->name, p->options, err ? why : "");
  }
  mpgm_test(n >= 8, "%d presets checked", n);
}

static void check_refused(void) {
  for (size_t i = 0; i < sizeof refused / sizeof *refused; i++) {
    const bad_case *c = &refused[i];
    char why[256] = "", tok[128] = "";
    mpgm_petsc_options o;
    const int err = mpgm_petsc_options_parse(c->text, &o, why, sizeof why);
    if (c->token) snprintf(tok, sizeof tok, "\"%s\"", c->token);
    mpgm_test(err == -1 && strncmp(why, "refused", 7) == 0 && (!c->token || strstr(why, tok)) &&
                  strstr(why, c->word),
              "refused \"%s\": names %s and \"%s\" (%s)", c->text, c->token ? tok : "its offset",
              c->word, why);
  }
}

/* The limits: 511 characters pass, 512 do not; the most options that fit
 * in 511 characters all split; the message fits any buffer. */
static void check_limits(void) {
  char s[MPGM_PETSC_OPTIONS_MAX + 2];
  memset(s, ' ', sizeof s);
  memcpy(s, "-ksp_rtol 1e-8", 14);
  s[MPGM_PETSC_OPTIONS_MAX] = '\0';
  mpgm_test(mpgm_petsc_options_parse(s, NULL, NULL, 0) == 0, "511 characters accepted");
  s[MPGM_PETSC_OPTIONS_MAX] = ' ';
  s[MPGM_PETSC_OPTIONS_MAX + 1] = '\0';
  char why[64];
  mpgm_test(mpgm_petsc_options_parse(s, NULL, why, sizeof why) == -1 && strstr(why, "longer"),
            "512 characters refused (%s)", why);
  size_t l = 0;
  while (l + 3 <= MPGM_PETSC_OPTIONS_MAX) memcpy(s + l, "-a ", 3), l += 3;
  s[l] = '\0';
  mpgm_petsc_options o;
  mpgm_test(mpgm_petsc_options_parse(s, &o, NULL, 0) == 0 && o.n == (int)(l / 3) &&
                o.n <= MPGM_PETSC_OPTIONS_N,
            "%d one-letter options split (at most %d)", o.n, MPGM_PETSC_OPTIONS_N);
  char tiny[8];
  mpgm_test(mpgm_petsc_options_parse("-ksp_view", NULL, tiny, sizeof tiny) == -1 &&
                strlen(tiny) == sizeof tiny - 1,
            "a short message buffer is filled, not overrun");
}

int main(void) {
  check_accepted();
  check_presets();
  check_refused();
  check_limits();
  printf("%zu accepted and %zu refused strings\n", sizeof accepted / sizeof *accepted,
         sizeof refused / sizeof *refused);
  return mpgm_test_summary();
}
