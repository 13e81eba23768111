/* mpgm_petsc_options.h -- what solver.petsc may hold: PETSc's options split
 * as PETSc 3.18 splits an options string, each held to mpgm's policy.
 *
 * A scene file may come from someone else, and PETSc's options reach
 * beyond the solver: -options_file reads a file (and PETSc's error echoes
 * its first line), viewers and monitors (-ksp_view_mat binary:PATH,
 * -ksp_monitor :PATH) write files anywhere, MUMPS writes to Fortran units
 * and out-of-core files, debugger options start programs. The policy keeps
 * the options that choose and tune a KSP, a PC and a factorisation, and
 * refuses the rest (docs/scene-format.md, "PETSc options are confined"):
 *
 *   - -options_file, -options_file_yaml, -options_string_yaml, any other
 *     -options_*, -prefix_push, -prefix_pop;
 *   - every name that views, monitors, draws, plots, prints, dumps, logs,
 *     debugs or names a file or folder (a word of the name: view, monitor,
 *     draw, plot, print, dump, log..., debug, trace, history, malloc,
 *     python, dll, socket, saws, matlab, emacs, display, sleep, file,
 *     filename, dir, tmpdir, path, lg, info; and the viewers without such a
 *     word: *_converged_reason, *_converged_rate, *_final_residual,
 *     *_compute_eigenvalues[_explicitly], *_compute_singularvalues), but
 *     *ksp_monitor and *ksp_monitor_true_residual without a value: those
 *     print each Krylov iteration to the terminal;
 *   - MUMPS's output streams -mat_mumps_icntl_1 .. _3 other than 0 (none)
 *     or 6 (the terminal), its print level _4 outside 0 .. 4, and its
 *     out-of-core factorisation -mat_mumps_icntl_22 other than 0;
 *   - values that could name a file or a viewer or load code: a value may
 *     hold letters, digits and _ . , + - only (a '/' only in hypre's
 *     relaxation types "...SOR/Jacobi"), and is not "python";
 *   - what PETSc would read differently from what it looks like: a quote
 *     without its end, a closing quote not followed by a space, an empty
 *     quoted value, a tab or newline (PETSc splits on spaces only), a value
 *     with no option before it (PETSc would skip it), "--name", a name with
 *     characters other than letters, digits and '_'.
 *
 * Pure string work (no PETSc): the scene loader calls it, and so does the
 * PETSc module before it sets a single option (solvers/petsc/petsc.c).
 */
#ifndef MPGM_PETSC_OPTIONS_H
#define MPGM_PETSC_OPTIONS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** The longest options string (mpgm_solver_opts.petsc holds 512 bytes). */
#define MPGM_PETSC_OPTIONS_MAX 511
/** At most this many options: two characters and a space each. */
#define MPGM_PETSC_OPTIONS_N ((MPGM_PETSC_OPTIONS_MAX + 1) / 3 + 1)

/** The options of a string, in order (a name given twice: PETSc keeps the
 *  last value). Names and values point into text. */
typedef struct mpgm_petsc_options {
  int n;                                /**< options                      */
  const char *name[MPGM_PETSC_OPTIONS_N];  /**< without the leading '-'   */
  const char *value[MPGM_PETSC_OPTIONS_N]; /**< NULL: the option has none */
  char text[MPGM_PETSC_OPTIONS_MAX + 1];   /**< the tokens, NUL-ended     */
} mpgm_petsc_options;

/** Split text (NUL-terminated) into PETSc's options as PETSc 3.18's
 *  PetscOptionsInsertString would (tokens separated by spaces; a token
 *  that starts with '"' runs to the next '"'; a token is an option name
 *  when PetscOptionsValidKey says so, and the token after a name is its
 *  value unless it is a name itself) and hold each to the policy above.
 *  Returns 0 with the options in *out, or -1 with the first refused token
 *  and the reason in why (len bytes; the token's unprintable bytes shown
 *  as '?'). out and why may be NULL. */
int mpgm_petsc_options_parse(const char *text, mpgm_petsc_options *out, char *why, size_t len);

#ifdef __cplusplus
}
#endif
#endif
