/* petsc.c -- PETSc's Krylov solvers and preconditioners (KSP + PC: CG or
 * GMRES with incomplete factors, hypre's BoomerAMG or GAMG; MUMPS as a
 * direct option),
 * sequential, behind the solver family's analyse / factor / solve.
 *
 * analyse converts the pattern to PETSc's compressed rows (AIJ) once and
 * keeps the map from each column entry to its row slot; the AIJ matrix is
 * built on the instance's own arrays (MatCreateSeqAIJWithArrays), so factor
 * only copies the values through the map (between MatSeqAIJGetArray and
 * its restore, which tells PETSc they changed). factor sets the
 * preconditioner up (PCSetUp: the AMG hierarchy, the incomplete or the
 * MUMPS factors), solve runs the Krylov method.
 *
 * Options: the scene's solver.petsc string, PETSc's own command-line
 * syntax, is split by mpgm (solvers/petsc_options.c, which holds every
 * option to the policy of docs/scene-format.md, "PETSc options are
 * confined", again here: no option that reads or writes a file, views,
 * monitors but to the terminal, or starts a program) and each option goes
 * into PETSc's options database by name (PetscOptionsSetValue; PETSc never
 * parses the string, so an -options_file or -prefix_push that got past
 * the scene loader is still not acted on), under a prefix of the
 * instance's own ("mpgm3_"; the KSP carries the prefix, and so do the PC,
 * the factor matrix and the multigrid levels it makes), so two instances
 * with different options do not mix, and is taken out again when the
 * instance ends. (An options object of the instance's own does not reach
 * the factor matrix: MUMPS would read the global database.) What the
 * string does not choose: CG with ICC(0) on a symmetric matrix, GMRES with
 * ILU(0) otherwise, the ILU's zero pivots shifted to non-zero (PETSc's
 * MAT_SHIFT_NONZERO; without it a Mohr-Coulomb tangent of the column
 * collapse at h = 0.025 stopped the run at 1.43 s: a pivot of ILU(0) was
 * zero, which full LU avoids by pivoting). solver.linear_tol,
 * linear_max_iterations and linear_restart give the tolerances and GMRES's
 * restart; the string may override them. Unless it sets -ksp_norm_type, a
 * Krylov method stops on the true residual |b - A x| <= tol |b|
 * (KSP_NORM_UNPRECONDITIONED; PETSc then picks the preconditioner side
 * that supports it, right for GMRES), as the other backends do. An option
 * of the string that PETSc has not read by the end of the first factor is
 * refused: a misspelt name would otherwise go unnoticed. The check
 * operation does that before a run: the KSP and PC set up once on a test
 * system (pt_check), so that `mpgm check` and `mpgm run` refuse a bad
 * option as bad input before any result is written.
 *
 * Failures: a matrix with a zero or missing diagonal entry (no stiffness
 * at a free degree of freedom; AMG, ILU and Jacobi divide by it) or a
 * preconditioner that cannot be built (a zero pivot) is MPGM_ERR_SINGULAR;
 * only LU (MUMPS) pivots past a zero diagonal and reports singularity
 * itself. A Krylov solve that stops short of its tolerance is
 * MPGM_ERR_LINEAR. Both are recoverable, with PETSc's reason in the
 * message. A PETSc error is MPGM_ERR_NOMEM (out of memory), MPGM_ERR_INPUT
 * with the scene file's name ("FILE: solver.petsc: ...") when the options
 * caused it (an unknown type or solver package, a value out of range, a
 * choice PETSc does not support, while it applies them: KSPSetFromOptions,
 * KSPSetUp, PCSetUp), else MPGM_ERR_SOLVER, each with PETSc's text.
 * PETSc never prints but for the monitors the options ask for: its error
 * handler is the one that only returns.
 *
 * PETSc (and MPI under it) is initialised the first time an instance is
 * created, once per process, without PETSc's signal handlers;
 * mpgm_solver_finalize ends it when the program ends (app/ arranges it).
 *
 * This file is a module of its own (mpgm_petsc.so, loaded by
 * solvers/plugin.c the first time a scene asks for "petsc"): PETSc, MPI
 * and the hundred libraries under them take 70 ms to load, which every
 * mpgm command would otherwise pay.
 */
#include "mpgm_petsc_options.h"
#include "mpgm_solver.h"
#include "pt_blocks.h"

#include <ctype.h>
#include <math.h>
#include <petscksp.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h> /* strcasecmp */

typedef struct pt_data {
  mpgm_solver_opts opts; /**< tol, restart, max_iter, petsc                 */
  char prefix[32];       /**< the instance's options prefix ("mpgm3_")       */
  int nopt;              /**< options of solver.petsc in the database       */
  char **optname;        /**< their names, with the prefix (nopt)           */
  int n, nnz;            /**< order and entries of the analysed pattern     */
  int nf;                /**< order of PETSc's matrix: n, or the block form's */
  pt_blocks blk;         /**< GAMG with a layout: the block form (bs > 0)   */
  double *xw;            /**< the block form's solution (nf)                 */
  PetscInt *ia, *ja;     /**< AIJ pattern (n + 1, nnz), sorted per row       */
  PetscScalar *a;        /**< AIJ values (nnz)                               */
  int *map;              /**< column entry k -> its AIJ slot (nnz)           */
  int *diag;             /**< column entry of A_jj, -1 if absent (n)         */
  PetscInt *fill;        /**< scratch of analyse (n)                         */
  double *bw;            /**< copy of b (b and x may alias; nf)              */
  Mat A;                 /**< AIJ on ia, ja, a                               */
  Vec b, x;              /**< vectors without arrays of their own            */
  Vec r;                 /**< the true residual b - A x                      */
  KSP ksp;
  int direct;            /**< the KSP is PREONLY (a factorisation, MUMPS)    */
  int gmres;             /**< the KSP is GMRES (its breakdowns explained)    */
  int ready;             /**< 1 after a successful factor                    */
  int checked;           /**< 1 once the options were checked for use        */
  int trial;             /**< 1: the instance of pt_check, on a test system  */
  int iterations;        /**< iterations of the last solve                   */
  double nnz_factor;     /**< entries the preconditioner holds (0: unknown)  */
  double mem_peak;       /**< its largest memory as PETSc or MUMPS counts it */
  double anorm;          /**< |A| (infinity norm) of the values factorised  */
} pt_data;

/* ---- PETSc as a process-wide library ------------------------------------ */

static pthread_once_t init_once = PTHREAD_ONCE_INIT;
static PetscErrorCode init_code = 0;

/* The arguments this module starts PETSc with. PETSc keeps the pointer
 * (PetscGetArgs), so whether PETSc is this module's to end is PETSc's own
 * record, not a flag of ours: a host program's PETSc has other arguments. */
static char **module_args(void) {
  static char a0[] = "mpgm", a1[] = "-no_signal_handler";
  static char *argv[] = {a0, a1, NULL};
  return argv;
}

static void petsc_init(void) {
  PetscBool done = PETSC_FALSE;
  PetscInitialized(&done);
  if (done) return; /* a host program's own PETSc */
  int argc = 2;
  char **pargv = module_args();
  init_code = PetscInitialize(&argc, &pargv, NULL, NULL);
  if (init_code) return;
  /* errors come back as codes and reach the user through mpgm_ctx */
  PetscPushErrorHandler(PetscReturnErrorHandler, NULL);
}

/** Ends PETSc (and MPI) if this module started it and it is running;
 *  called by the loader's mpgm_solver_finalize, which app/ runs when the
 *  program ends (the library never ends the process). */
void mpgm_solver_petsc_module_finalize(void) {
  if (!PetscInitializeCalled || PetscFinalizeCalled) return;
  int argc = 0;
  char **args = NULL;
  if (PetscGetArgs(&argc, &args) == 0 && args == module_args()) PetscFinalize();
}

/* Record PETSc's error ierr of `what` (its message text) as code. */
static int fail(mpgm_ctx *ctx, PetscErrorCode ierr, int code, const char *what) {
  const char *text = NULL;
  char *specific = NULL;
  PetscErrorMessage((int)ierr, &text, &specific);
  if (ierr == PETSC_ERR_MEM) code = MPGM_ERR_NOMEM;
  MPGM_ERROR(ctx, code, "petsc: %s failed (error %d: %s%s%s)", what, (int)ierr,
             text ? text : "unknown", specific && *specific ? ": " : "",
             specific ? specific : "");
}

#define PT_TRY(ctx, call, code, what)                                                     \
  do {                                                                                    \
    PetscErrorCode ierr_ = (call);                                                        \
    if (ierr_) return fail((ctx), ierr_, (code), (what));                                 \
  } while (0)

/* The scene file and ": " before "solver.petsc" in the messages of bad
 * options ("" without a file: bench-solvers' presets). */
#define WHERE(d) (d)->opts.file ? (d)->opts.file : "", (d)->opts.file ? ": " : ""

/* PETSc's errors that options cause while PETSc applies them: a type or a
 * solver package that does not exist, a value out of range or of the wrong
 * kind, a choice PETSc or this build does not support, a preconditioner
 * that needs what only a program can give (PCSHELL's functions, AMS's
 * coordinates). */
static int options_error(PetscErrorCode e) {
  return e == PETSC_ERR_SUP || e == PETSC_ERR_SUP_SYS || e == PETSC_ERR_ARG_WRONG ||
         e == PETSC_ERR_ARG_OUTOFRANGE || e == PETSC_ERR_ARG_INCOMP ||
         e == PETSC_ERR_ARG_TYPENOTSET || e == PETSC_ERR_ARG_UNKNOWN_TYPE ||
         e == PETSC_ERR_USER || e == PETSC_ERR_MISSING_FACTOR || e == PETSC_ERR_USER_INPUT;
}

/* A failure of a call that applies the options: bad input with the scene
 * file's name when options were given and the error is of their kind (or
 * code says any error is: KSPSetFromOptions); else as fail. */
static int fail_options(mpgm_ctx *ctx, const pt_data *d, PetscErrorCode ierr, int code,
                        const char *what) {
  if (ierr == PETSC_ERR_MEM || !d->opts.petsc[0] || (code != MPGM_ERR_INPUT && !options_error(ierr)))
    return fail(ctx, ierr, code, what);
  const char *text = NULL;
  char *specific = NULL;
  PetscErrorMessage((int)ierr, &text, &specific);
  MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s%ssolver.petsc: PETSc refused the options \"%s\" (%s: "
             "error %d: %s%s%s)", WHERE(d), d->opts.petsc, what, (int)ierr, text ? text : "unknown",
             specific && *specific ? ": " : "", specific ? specific : "");
}

#define PT_OPT(ctx, d, call, code, what)                                                  \
  do {                                                                                    \
    PetscErrorCode ierr_ = (call);                                                        \
    if (ierr_) return fail_options((ctx), (d), ierr_, (code), (what));                    \
  } while (0)

/* ---- instance ----------------------------------------------------------- */

/* solver.petsc into the options database under the instance's prefix,
 * split and held to the policy here (solvers/petsc_options.c) whatever the
 * caller checked, each option set by name: PetscOptionsInsertString would
 * itself read the file of an -options_file. The names are kept (once each,
 * as PETSc keeps a name given twice once, with its last value) to take
 * them out again. */
static int insert_options(mpgm_ctx *ctx, pt_data *d) {
  static int serial = 0; /* instances so far: the prefixes */
  snprintf(d->prefix, sizeof d->prefix, "mpgm%d_", __atomic_fetch_add(&serial, 1, __ATOMIC_RELAXED));
  mpgm_petsc_options po;
  char why[400];
  if (mpgm_petsc_options_parse(d->opts.petsc, &po, why, sizeof why))
    MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s%ssolver.petsc: %s", WHERE(d), why);
  if (po.n > 0) MPGM_ALLOC(ctx, d->optname, po.n);
  const size_t lp = strlen(d->prefix);
  for (int i = 0; i < po.n; i++) {
    char *name = NULL;
    for (int k = 0; k < d->nopt && !name; k++)
      if (strcasecmp(d->optname[k] + 1 + lp, po.name[i]) == 0) name = d->optname[k];
    if (!name) {
      const size_t l = lp + strlen(po.name[i]) + 2;
      MPGM_ALLOC(ctx, name, l);
      snprintf(name, l, "-%s%s", d->prefix, po.name[i]);
      d->optname[d->nopt++] = name;
    }
    PT_TRY(ctx, PetscOptionsSetValue(NULL, name, po.value[i]), MPGM_ERR_SOLVER,
           "PetscOptionsSetValue (solver.petsc)");
  }
  return MPGM_OK;
}

static int pt_create(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data) {
  pthread_once(&init_once, petsc_init);
  MPGM_CHECK(ctx, init_code == 0, MPGM_ERR_SOLVER,
             "petsc: PetscInitialize failed (error %d): PETSc and MPI could not start",
             (int)init_code);
  pt_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *data = d;
  d->opts = *opts;
  return insert_options(ctx, d);
}

/* Release the PETSc objects and the pattern-sized arrays. */
static void release(pt_data *d) {
  if (d->ksp) KSPDestroy(&d->ksp);
  if (d->A) MatDestroy(&d->A);
  if (d->b) VecDestroy(&d->b);
  if (d->x) VecDestroy(&d->x);
  if (d->r) VecDestroy(&d->r);
  free(d->ia); free(d->ja); free(d->a); free(d->map); free(d->diag); free(d->fill);
  free(d->bw);
  free(d->xw);
  pt_blocks_free(&d->blk);
  d->ia = d->ja = d->fill = NULL;
  d->a = NULL;
  d->map = d->diag = NULL;
  d->bw = d->xw = NULL;
  d->n = d->nnz = d->nf = 0;
  d->ready = 0;
}

static void pt_destroy(void *data) {
  pt_data *d = data;
  if (!d) return;
  release(d);
  for (int i = 0; i < d->nopt; i++) PetscOptionsClearValue(NULL, d->optname[i]);
  for (int i = 0; d->optname && i < d->nopt; i++) free(d->optname[i]);
  free(d->optname);
  free(d);
}

/* AIJ pattern of A from its columns: row counts, row starts, then the
 * columns in increasing order (each row's entries come sorted), the map
 * from column entries to row slots and the diagonal's entries. */
static void to_rows(pt_data *d, const mpgm_csc *A) {
  const int n = A->n;
  for (int k = 0; k < A->nnz; k++) d->ia[A->rowind[k] + 1]++;
  for (int i = 0; i < n; i++) d->ia[i + 1] += d->ia[i];
  for (int i = 0; i < n; i++) d->fill[i] = d->ia[i];
  for (int j = 0; j < n; j++) {
    d->diag[j] = -1;
    for (int k = A->colptr[j]; k < A->colptr[j + 1]; k++) {
      const PetscInt slot = d->fill[A->rowind[k]]++;
      d->ja[slot] = j;
      d->map[k] = (int)slot;
      if (A->rowind[k] == j) d->diag[j] = k;
    }
  }
}

/* The KSP: CG with ICC(0) (symmetric A) or GMRES with ILU(0), its zero
 * pivots shifted, unless the options choose, the tolerances, then the
 * options, GMRES's restart and the true residual's norm unless they set
 * them. */
static int make_ksp(mpgm_ctx *ctx, pt_data *d, int symmetric) {
  PC pc;
  PT_TRY(ctx, KSPCreate(PETSC_COMM_SELF, &d->ksp), MPGM_ERR_SOLVER, "KSPCreate");
  PT_TRY(ctx, KSPSetOptionsPrefix(d->ksp, d->prefix), MPGM_ERR_SOLVER, "KSPSetOptionsPrefix");
  PT_TRY(ctx, KSPSetOperators(d->ksp, d->A, d->A), MPGM_ERR_SOLVER, "KSPSetOperators");
  PT_TRY(ctx, KSPSetType(d->ksp, symmetric ? KSPCG : KSPGMRES), MPGM_ERR_SOLVER, "KSPSetType");
  PT_TRY(ctx, KSPGetPC(d->ksp, &pc), MPGM_ERR_SOLVER, "KSPGetPC");
  PT_TRY(ctx, PCSetType(pc, symmetric ? PCICC : PCILU), MPGM_ERR_SOLVER, "PCSetType");
  if (!symmetric)
    PT_TRY(ctx, PCFactorSetShiftType(pc, MAT_SHIFT_NONZERO), MPGM_ERR_SOLVER,
           "PCFactorSetShiftType");
  PT_TRY(ctx, KSPSetTolerances(d->ksp, d->opts.tol, 0.0, PETSC_DEFAULT, d->opts.max_iter),
         MPGM_ERR_SOLVER, "KSPSetTolerances");
  PT_OPT(ctx, d, KSPSetFromOptions(d->ksp), MPGM_ERR_INPUT, "KSPSetFromOptions");
  PetscBool set = PETSC_FALSE;
  PT_TRY(ctx, PetscOptionsHasName(NULL, d->prefix, "-ksp_gmres_restart", &set), MPGM_ERR_SOLVER,
         "PetscOptionsHasName");
  if (!set) /* a no-op unless the KSP is GMRES */
    PT_TRY(ctx, KSPGMRESSetRestart(d->ksp, d->opts.restart), MPGM_ERR_SOLVER,
           "KSPGMRESSetRestart");
  PT_TRY(ctx, PetscOptionsHasName(NULL, d->prefix, "-ksp_norm_type", &set), MPGM_ERR_SOLVER,
         "PetscOptionsHasName");
  KSPType kt;
  PT_TRY(ctx, KSPGetType(d->ksp, &kt), MPGM_ERR_SOLVER, "KSPGetType");
  d->direct = strcmp(kt, KSPPREONLY) == 0;
  d->gmres = strcmp(kt, KSPGMRES) == 0;
  if (!set && !d->direct)
    PT_TRY(ctx, KSPSetNormType(d->ksp, KSP_NORM_UNPRECONDITIONED), MPGM_ERR_SOLVER,
           "KSPSetNormType");
  return MPGM_OK;
}

/* 1 when the options choose GAMG as the preconditioner (then a matrix
 * with a layout goes to PETSc in its block form, pt_blocks.h). */
static int wants_blocks(mpgm_ctx *ctx, const pt_data *d, int *yes) {
  char pc[64] = "";
  PetscBool set = PETSC_FALSE;
  PT_TRY(ctx, PetscOptionsGetString(NULL, d->prefix, "-pc_type", pc, sizeof pc, &set),
         MPGM_ERR_SOLVER, "PetscOptionsGetString");
  *yes = set && strcasecmp(pc, PCGAMG) == 0;
  return MPGM_OK;
}

/* The block form's block size and near-null space: the rigid-body modes
 * of the rows' node positions (3 in 2-D, 6 in 3-D). */
static int block_setup(mpgm_ctx *ctx, pt_data *d) {
  Vec xy;
  MatNullSpace nsp;
  PT_TRY(ctx, MatSetBlockSize(d->A, d->blk.bs), MPGM_ERR_SOLVER, "MatSetBlockSize");
  PT_TRY(ctx, VecCreateSeqWithArray(PETSC_COMM_SELF, d->blk.bs, d->nf, d->blk.coords, &xy),
         MPGM_ERR_SOLVER, "VecCreateSeqWithArray (coordinates)");
  PetscErrorCode e = MatNullSpaceCreateRigidBody(xy, &nsp);
  VecDestroy(&xy);
  if (e) return fail(ctx, e, MPGM_ERR_SOLVER, "MatNullSpaceCreateRigidBody");
  e = MatSetNearNullSpace(d->A, nsp);
  MatNullSpaceDestroy(&nsp);
  if (e) return fail(ctx, e, MPGM_ERR_SOLVER, "MatSetNearNullSpace");
  return MPGM_OK;
}

/* The AIJ pattern of A (or of its block form: GAMG chosen and A's layout
 * given) and its KSP (perm is not used: PETSc's preconditioners order for
 * themselves). */
static int pt_analyse(void *data, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm) {
  (void)perm;
  pt_data *d = data;
  const int n = A->n, nnz = A->nnz;
  release(d);
  int blocks = 0;
  if (A->layout && A->layout->dim > 1) MPGM_CALL(wants_blocks(ctx, d, &blocks));
  if (blocks) {
    char why[160];
    const int err = pt_blocks_build(&d->blk, A->layout, n, why, sizeof why);
    if (err) MPGM_ERROR(ctx, err, "petsc: %s", why);
  }
  const int nf = blocks ? d->blk.nf : n, nfix = blocks ? d->blk.nfix : 0;
  MPGM_ALLOC(ctx, d->ia, nf + 1);
  MPGM_ALLOC(ctx, d->ja, nnz + nfix > 0 ? nnz + nfix : 1);
  MPGM_ALLOC(ctx, d->a, nnz + nfix > 0 ? nnz + nfix : 1);
  MPGM_ALLOC(ctx, d->map, nnz > 0 ? nnz : 1);
  MPGM_ALLOC(ctx, d->diag, n);
  MPGM_ALLOC(ctx, d->fill, nf);
  MPGM_ALLOC(ctx, d->bw, nf);
  if (blocks) {
    MPGM_ALLOC(ctx, d->xw, nf);
    pt_blocks_rows(&d->blk, A, d->ia, d->ja, d->map, d->diag, d->fill);
  } else {
    to_rows(d, A);
  }
  d->n = n;
  d->nf = nf;
  d->nnz = nnz;
  PT_TRY(ctx, MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, nf, nf, d->ia, d->ja, d->a, &d->A),
         MPGM_ERR_SOLVER, "MatCreateSeqAIJWithArrays");
  if (blocks) MPGM_CALL(block_setup(ctx, d));
  if (A->symmetric)
    PT_TRY(ctx, MatSetOption(d->A, MAT_SYMMETRIC, PETSC_TRUE), MPGM_ERR_SOLVER, "MatSetOption");
  PT_TRY(ctx, VecCreateSeqWithArray(PETSC_COMM_SELF, 1, nf, NULL, &d->b), MPGM_ERR_SOLVER,
         "VecCreateSeqWithArray");
  PT_TRY(ctx, VecCreateSeqWithArray(PETSC_COMM_SELF, 1, nf, NULL, &d->x), MPGM_ERR_SOLVER,
         "VecCreateSeqWithArray");
  PT_TRY(ctx, VecCreateSeq(PETSC_COMM_SELF, nf, &d->r), MPGM_ERR_SOLVER, "VecCreateSeq");
  return make_ksp(ctx, d, A->symmetric);
}

/* The multigrid level an option names ("...mg_levels_K_..."), -1 if none. */
static int option_level(const char *name) {
  char low[256];
  size_t l = 0;
  for (; name[l] && l + 1 < sizeof low; l++) low[l] = (char)tolower((unsigned char)name[l]);
  low[l] = '\0';
  const char *p = strstr(low, "mg_levels_");
  if (!p || !isdigit((unsigned char)p[10])) return -1;
  char *end;
  const long k = strtol(p + 10, &end, 10);
  return *end == '_' && k < 1000000 ? (int)k : -1;
}

/* The levels of the instance's multigrid (0 when the PC is none). */
static int mg_levels(pt_data *d) {
  PC pc;
  PetscBool mg = PETSC_FALSE;
  PetscInt nl = 0;
  if (KSPGetPC(d->ksp, &pc) || PetscObjectTypeCompareAny((PetscObject)pc, &mg, PCGAMG, PCMG, "") ||
      !mg || PCMGGetLevels(pc, &nl))
    return 0;
  return (int)nl;
}

/* Every option of solver.petsc must have been read by the KSP, the PC or
 * the factorisation they chose. On the test system of pt_check an option
 * of a multigrid level its hierarchy does not have (-mg_levels_3_... on
 * three levels, 0 to 2) is left to the run's first factorisation, on the
 * run's own hierarchy: how many levels GAMG makes depends on the matrix. */
static int check_options_used(mpgm_ctx *ctx, pt_data *d) {
  PetscInt n = 0;
  char **names = NULL, **values = NULL;
  PT_TRY(ctx, PetscOptionsLeftGet(NULL, &n, &names, &values), MPGM_ERR_SOLVER,
         "PetscOptionsLeftGet");
  char list[256] = "";
  const size_t lp = strlen(d->prefix);
  const int levels = d->trial ? mg_levels(d) : 0;
  int left = 0;
  for (PetscInt i = 0; i < n; i++) {
    if (strncmp(names[i], d->prefix, lp) != 0) continue; /* another instance's */
    if (d->trial && option_level(names[i] + lp) >= levels) continue;
    const size_t l = strlen(list);
    snprintf(list + l, sizeof list - l, "%s-%s", left++ ? ", " : "", names[i] + lp);
  }
  PetscOptionsLeftRestore(NULL, &n, &names, &values);
  MPGM_CHECK(ctx, left == 0, MPGM_ERR_INPUT,
             "%s%ssolver.petsc: PETSc did not use %s (misspelt, or not an option of the KSP and PC "
             "chosen: \"%s\")", WHERE(d), list, d->opts.petsc);
  d->checked = 1;
  return MPGM_OK;
}

/* What the preconditioner holds: the entries and memory of its factors
 * (ILU, ICC, LU, Cholesky; MUMPS's INFOG(20) and (22)), or of the
 * operators of every level of a multigrid (GAMG, the fine one included);
 * hypre does not say (0). */
static void pc_stats(pt_data *d, PC pc) {
  d->nnz_factor = 0.0;
  MatSolverType st = NULL;
  Mat F = NULL;
  MatInfo info;
  PetscBool mg = PETSC_FALSE;
  PetscObjectTypeCompareAny((PetscObject)pc, &mg, PCGAMG, PCMG, "");
  if (mg) {
    PetscInt nl = 0;
    double mem = 0.0;
    if (PCMGGetLevels(pc, &nl)) return;
    for (PetscInt l = 0; l < nl; l++) {
      KSP k;
      Mat Al;
      if (PCMGGetSmoother(pc, l, &k) || KSPGetOperators(k, &Al, NULL) ||
          MatGetInfo(Al, MAT_LOCAL, &info))
        return;
      d->nnz_factor += info.nz_used;
      mem += info.memory;
    }
    d->mem_peak = fmax(d->mem_peak, mem);
    return;
  }
  PetscBool factor = PETSC_FALSE;
  PetscObjectTypeCompareAny((PetscObject)pc, &factor, PCLU, PCILU, PCICC, PCCHOLESKY, "");
  if (!factor || PCFactorGetMatrix(pc, &F)) return;
  if (!PCFactorGetMatSolverType(pc, &st) && st && strcmp(st, MATSOLVERMUMPS) == 0) {
    PetscInt nz = 0, mem = 0;
    if (!MatMumpsGetInfog(F, 20, &nz)) /* negative: millions of entries */
      d->nnz_factor = nz >= 0 ? (double)nz : -1e6 * (double)nz;
    /* INFOG(22) counts whole megabytes: at least the factors' values */
    if (!MatMumpsGetInfog(F, 22, &mem))
      d->mem_peak = fmax(d->mem_peak, fmax(1048576.0 * mem, 8.0 * d->nnz_factor));
    return;
  }
  if (MatGetInfo(F, MAT_LOCAL, &info)) return;
  d->nnz_factor = info.nz_used;
  if (info.memory > d->mem_peak) d->mem_peak = info.memory;
}

/* A zero or missing diagonal entry: singular for every preconditioner but
 * a pivoting LU. */
static int check_diagonal(mpgm_ctx *ctx, const pt_data *d, const mpgm_csc *A, PC pc) {
  PetscBool lu = PETSC_FALSE;
  PetscObjectTypeCompare((PetscObject)pc, PCLU, &lu);
  if (lu) return MPGM_OK;
  for (int j = 0; j < d->n; j++)
    if (d->diag[j] < 0 || A->val[d->diag[j]] == 0.0) {
      PCType pt = NULL;
      PCGetType(pc, &pt);
      MPGM_ERROR(ctx, MPGM_ERR_SINGULAR, "petsc: equation %d of %d has a %s diagonal entry: "
                 "singular for the preconditioner %s", j, d->n, d->diag[j] < 0 ? "missing" : "zero",
                 pt ? pt : "?");
    }
  return MPGM_OK;
}

/* The values of A into the AIJ matrix; the preconditioner built on them.
 * A zero diagonal or a failed build (a zero pivot): MPGM_ERR_SINGULAR. */
static int pt_factor(void *data, mpgm_ctx *ctx, const mpgm_csc *A) {
  pt_data *d = data;
  MPGM_CHECK(ctx, d->ksp && A->n == d->n && A->nnz == d->nnz, MPGM_ERR_INTERNAL,
             "petsc: factor of order %d (%d entries), analysed %d (%d)", A->n, A->nnz, d->n,
             d->nnz);
  d->ready = 0;
  PC pc;
  PT_TRY(ctx, KSPGetPC(d->ksp, &pc), MPGM_ERR_SOLVER, "KSPGetPC");
  MPGM_CALL(check_diagonal(ctx, d, A, pc));
  PetscScalar *a; /* d->a itself; the restore tells PETSc the values changed */
  PT_TRY(ctx, MatSeqAIJGetArray(d->A, &a), MPGM_ERR_SOLVER, "MatSeqAIJGetArray");
  for (int k = 0; k < d->nnz; k++) a[d->map[k]] = A->val[k];
  if (d->blk.bs) { /* the fixed components' rows */
    const double s = pt_blocks_scale(A, d->diag);
    for (int f = 0; f < d->blk.nfix; f++) a[d->blk.fixslot[f]] = s;
  }
  PT_TRY(ctx, MatSeqAIJRestoreArray(d->A, &a), MPGM_ERR_SOLVER, "MatSeqAIJRestoreArray");
  PetscReal an = 0.0;
  PT_TRY(ctx, MatNorm(d->A, NORM_INFINITY, &an), MPGM_ERR_SOLVER, "MatNorm");
  d->anorm = an;
  PT_OPT(ctx, d, KSPSetUp(d->ksp), MPGM_ERR_SOLVER, "KSPSetUp");
  /* after the KSP's first solve KSPSetUp returns at once, and PCApply
   * would set the preconditioner up for the new values inside the next
   * solve (timed as a solve, its failure found there); PCSetUp does it
   * here, where it belongs */
  PT_OPT(ctx, d, PCSetUp(pc), MPGM_ERR_SOLVER, "PCSetUp (the preconditioner)");
  PCFailedReason why = PC_NOERROR;
  PT_TRY(ctx, PCGetFailedReason(pc, &why), MPGM_ERR_SOLVER, "PCGetFailedReason");
  if (why != PC_NOERROR)
    MPGM_ERROR(ctx, MPGM_ERR_SINGULAR, "petsc: the preconditioner could not be built (%s, order %d)",
               PCFailedReasons[why], d->n);
  if (!d->checked) MPGM_CALL(check_options_used(ctx, d));
  pc_stats(d, pc);
  d->ready = 1;
  return MPGM_OK;
}

/* |b - A x| / |b| (2-norms) of the vectors d->b, d->x into *rel, and
 * whether x is as good as round-off allows: the normwise backward error
 * |r| / (|A| |x| + |b|) (infinity norms) at most ROUNDOFF. In double
 * precision the residual of A x cannot fall much below eps |A| |x|; on a
 * stiff tangent (the static cantilever: a direct solve leaves |r| / |b| =
 * 5e-10 at h = 0.0625) that floor lies above 1e-10 |b|, and a Krylov solve
 * that has reached it has done what a direct one does. */
#define ROUNDOFF (64.0 * PETSC_MACHINE_EPSILON)
static PetscErrorCode true_residual(pt_data *d, double *rel, int *floor) {
  PetscReal rn, bn, ri, xi, bi;
  PetscCall(MatMult(d->A, d->x, d->r));
  PetscCall(VecAYPX(d->r, -1.0, d->b));
  PetscCall(VecNorm(d->r, NORM_2, &rn));
  PetscCall(VecNorm(d->b, NORM_2, &bn));
  PetscCall(VecNorm(d->r, NORM_INFINITY, &ri));
  PetscCall(VecNorm(d->x, NORM_INFINITY, &xi));
  PetscCall(VecNorm(d->b, NORM_INFINITY, &bi));
  *rel = bn > 0.0 ? rn / bn : rn;
  const double den = d->anorm * xi + bi;
  *floor = den > 0.0 && ri / den <= ROUNDOFF;
  return 0;
}

/* KSPSolve until the true residual meets the tolerance or round-off: a
 * Krylov method's own residual (CG's recurrence, GMRES's least-squares
 * estimate) drifts from |b - A x| near round-off of the preconditioned
 * system (1.2e-9 against 1e-10 for GMRES + BoomerAMG on the cantilever),
 * so a solve that says it converged and did not is continued from where it
 * stopped, at most ROUNDS times. *why: PETSc's reason of the last solve;
 * *ok: the true residual is within the tolerance or at round-off. */
#define ROUNDS 4
static PetscErrorCode krylov(pt_data *d, int *its, KSPConvergedReason *why, double *rel, int *ok) {
  const int direct = d->direct;
  int floor = 0;
  *its = 0;
  PetscCall(KSPSetInitialGuessNonzero(d->ksp, PETSC_FALSE));
  for (int round = 0; round < ROUNDS; round++) {
    PetscInt k = 0;
    PetscCall(KSPSolve(d->ksp, d->b, d->x));
    PetscCall(KSPGetIterationNumber(d->ksp, &k));
    PetscCall(KSPGetConvergedReason(d->ksp, why));
    *its += (int)k;
    PetscCall(true_residual(d, rel, &floor));
    if (*why < 0 || direct || *rel <= d->opts.tol || floor || *its >= d->opts.max_iter) break;
    PetscCall(KSPSetInitialGuessNonzero(d->ksp, PETSC_TRUE));
  }
  *ok = (direct && *why >= 0) || *rel <= d->opts.tol || floor;
  return 0;
}

/* x = A^-1 b to the tolerance, |b - A x| <= tol |b| (b and x may alias).
 * Not converged: MPGM_ERR_LINEAR with PETSc's reason; the last iterate is
 * left in x. */
static int pt_solve(void *data, mpgm_ctx *ctx, const double *b, double *x) {
  pt_data *d = data;
  MPGM_CHECK(ctx, d->ready, MPGM_ERR_INTERNAL, "petsc: solve without a preconditioner");
  const pt_blocks *B = &d->blk;
  if (B->bs) { /* the block form: zero at the fixed components */
    memset(d->bw, 0, (size_t)d->nf * sizeof(double));
    for (int e = 0; e < d->n; e++) d->bw[B->row[e]] = b[e];
  } else {
    memcpy(d->bw, b, (size_t)d->n * sizeof(double));
  }
  PT_TRY(ctx, VecPlaceArray(d->b, d->bw), MPGM_ERR_SOLVER, "VecPlaceArray");
  int its = 0, ok = 0;
  KSPConvergedReason why = KSP_CONVERGED_ITERATING;
  double rel = 0.0;
  PetscErrorCode ierr = VecPlaceArray(d->x, B->bs ? d->xw : x);
  if (!ierr) ierr = krylov(d, &its, &why, &rel, &ok);
  VecResetArray(d->x);
  VecResetArray(d->b);
  if (B->bs)
    for (int e = 0; e < d->n; e++) x[e] = d->xw[B->row[e]];
  d->iterations = its;
  if (ierr) return fail(ctx, ierr, MPGM_ERR_SOLVER, "KSPSolve");
  if (why == KSP_DIVERGED_PC_FAILED)
    MPGM_ERROR(ctx, MPGM_ERR_SINGULAR, "petsc: the preconditioner failed in the solve (%s)",
               KSPConvergedReasons[why]);
  /* GMRES's DIVERGED_BREAKDOWN on mpgm's tangents is PETSc's restart check:
   * the recursion's residual far from the true one (docs/theory.md, 18) */
  const char *hint = d->gmres && why == KSP_DIVERGED_BREAKDOWN
                         ? " (PETSc's check at a GMRES restart: the residual of the "
                           "recursion was far from the true one, the Krylov basis having lost "
                           "its orthogonality; -ksp_gmres_cgs_refinement_type refine_ifneeded "
                           "in solver.petsc re-orthogonalises)"
                         : "";
  if (!ok)
    MPGM_ERROR(ctx, MPGM_ERR_LINEAR, "petsc: the Krylov solve did not converge: %s after %d "
               "iterations, |b - A x| / |b| = %.3g (tolerance %g)%s",
               why < 0 ? KSPConvergedReasons[why] : "its residual stalled above the tolerance and "
                                                     "above round-off",
               its, rel, d->opts.tol, hint);
  return MPGM_OK;
}

/* Newton's forcing term: the next solves' relative tolerance. */
static int pt_tolerance(void *data, double tol) {
  pt_data *d = data;
  d->opts.tol = tol;
  if (d->ksp && KSPSetTolerances(d->ksp, tol, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT))
    return MPGM_ERR_SOLVER;
  return MPGM_OK;
}

static int pt_stats(void *data, mpgm_solver_stats *st) {
  pt_data *d = data;
  st->iterations = d->iterations;
  st->nnz_factor = d->nnz_factor;
  st->block_size = d->blk.bs;
  const double n = d->n, nf = d->nf, nnz = d->nnz, nfix = d->blk.nfix;
  st->mem_peak = d->mem_peak + (2 * nf + 1 + nnz + nfix + nfix) * sizeof(PetscInt) +
                 (nnz + nfix + nf + (d->blk.bs ? 2 * nf : 0)) * sizeof(double) +
                 (nnz + n + (d->blk.bs ? n + nf : 0)) * sizeof(int);
  return MPGM_OK;
}

/* ---- the options judged before a run ------------------------------------ */

/* The test system's grid: TEST_M x TEST_M nodes of two unknowns each, 800
 * equations, on which GAMG coarsens to several levels (at 50 equations it
 * makes one, and every -mg_levels_1_... option would look unused). */
#define TEST_M 20

/* A of the test system: the nodes of a square grid coupled to their four
 * neighbours and between their two unknowns, as a plane elasticity
 * tangent couples them, strictly diagonally dominant (every preconditioner
 * builds on it, every factorisation succeeds), symmetric, or not: then
 * each pair of off-diagonal entries differs, as a Mohr-Coulomb tangent's
 * do. Sorted rows per column, the diagonal present. */
static int test_matrix(mpgm_ctx *ctx, int symmetric, mpgm_csc *A) {
  const int m = TEST_M, n = 2 * m * m;
  *A = (mpgm_csc){.n = n, .symmetric = symmetric};
  MPGM_ALLOC(ctx, A->colptr, n + 1);
  MPGM_ALLOC(ctx, A->rowind, 10 * n);
  MPGM_ALLOC(ctx, A->val, 10 * n);
  int e = 0;
  for (int col = 0; col < n; col++) {
    const int node = col / 2, i = node / m, j = node % m;
    const int nb[5] = {i > 0 ? node - m : -1, j > 0 ? node - 1 : -1, node,
                       j < m - 1 ? node + 1 : -1, i < m - 1 ? node + m : -1};
    for (int k = 0; k < 5; k++) {
      if (nb[k] < 0) continue;
      for (int c = 0; c < 2; c++) {
        const int row = 2 * nb[k] + c;
        double v = row == col ? 12.0 : nb[k] == node || row % 2 != col % 2 ? 0.3 : -1.0;
        if (!symmetric && row != col) v += row < col ? 0.1 : -0.05;
        A->rowind[e] = row;
        A->val[e++] = v;
      }
    }
    A->colptr[col + 1] = e;
  }
  A->nnz = e;
  return MPGM_OK;
}

/* The options of opts judged as a run's first factorisation judges them:
 * an instance with them (mpgm's policy, then PETSc's options database),
 * its KSP and PC made for the test system's pattern with the run's
 * symmetry (CG + ICC(0) or GMRES + ILU(0) unless the options choose) and
 * set up on its values, every option used, then destroyed. An instance
 * that cannot start (PETSc, MPI) fails as it would in a run; any other
 * failure on this system, where every sound configuration succeeds, is
 * the options': bad input, with the scene file's name. */
static int pt_check(mpgm_ctx *ctx, const mpgm_solver_opts *opts) {
  mpgm_csc A = {0};
  mpgm_ctx c; /* the trial's own: the caller's timers and counters stay */
  mpgm_ctx_init(&c);
  void *data = NULL;
  int err = test_matrix(&c, opts->symmetric, &A), started = 0;
  if (!err) err = pt_create(&c, opts, &data);
  if (!err) {
    started = 1;
    ((pt_data *)data)->trial = 1;
    err = pt_analyse(data, &c, &A, NULL);
  }
  if (!err) err = pt_factor(data, &c, &A);
  pt_destroy(data);
  free(A.colptr);
  free(A.rowind);
  free(A.val);
  if (!err) return MPGM_OK;
  if (!started || err == MPGM_ERR_INPUT || err == MPGM_ERR_NOMEM)
    return mpgm_err_set(ctx, err, c.file, c.line, "%s", c.msg);
  const char *f = opts->file;
  return mpgm_err_set(ctx, MPGM_ERR_INPUT, c.file, c.line,
                      "%s%ssolver.petsc: the KSP and PC of \"%s\" could not be set up on a test "
                      "system of %d equations (diagonally dominant, %ssymmetric), as the first "
                      "factorisation would set them up: %s", f ? f : "", f ? ": " : "", opts->petsc,
                      A.n, opts->symmetric ? "" : "not ", c.msg);
}

/** PETSc KSP + PC (sequential): solver.petsc selects them. The loader
 *  (solvers/plugin.c) finds this record by name in the module. */
const mpgm_solver_type mpgm_solver_petsc_module = {
    .name = "petsc",
    .iterative = 1,
    .create = pt_create,
    .destroy = pt_destroy,
    .analyse = pt_analyse,
    .factor = pt_factor,
    .solve = pt_solve,
    .stats = pt_stats,
    .tolerance = pt_tolerance,
    .check = pt_check,
};
