/* mpgm_solver.h -- the sparse linear solver plug-in family.
 *
 * Contract: the core owns a compressed-column matrix whose pattern is fixed
 * while the connectivity is unchanged; each Newton iteration refills its
 * values. A backend analyses the pattern once (analyse), factorises the
 * values (factor) and solves (solve). analyse is called again only when the
 * pattern changes. The matrix always holds the full pattern (both
 * triangles), sorted row indices per column, no duplicates; a symmetric
 * backend may read one triangle only.
 */
#ifndef MPGM_SOLVER_H
#define MPGM_SOLVER_H

#include "mpgm_base.h"
#include "mpgm_blob.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Where the equations of a matrix are (optional, with mpgm_csc.layout):
 *  the node and component of each, the nodes' positions. Backends whose
 *  preconditioners use it read it at analyse: PETSc's GAMG takes the
 *  block size (dim) and the rigid-body modes as its near-null space. */
typedef struct mpgm_dof_layout {
  int dim;          /**< components per node: the block size (2 or 3)   */
  int nnode;        /**< nodes                                          */
  const int *dof;   /**< dim per node: the equation of each component,
                         -1 when it is fixed (no equation)              */
  const double *x;  /**< dim per node: the nodes' positions [m]         */
} mpgm_dof_layout;

/** Compressed sparse column matrix (0-based), borrowed by the backends. */
typedef struct mpgm_csc {
  int n;          /**< rows = columns                          */
  int nnz;        /**< stored entries = colptr[n]              */
  int *colptr;    /**< n + 1 column starts                     */
  int *rowind;    /**< nnz row indices, sorted in each column  */
  double *val;    /**< nnz values                              */
  int symmetric;  /**< 1 when the values are symmetric         */
  const mpgm_dof_layout *layout; /**< NULL, or the equations' nodes and
                     components (the core's tangents and masses)  */
} mpgm_csc;

/** Statistics a backend reports after factor (and solve). */
typedef struct mpgm_solver_stats {
  double nnz_factor; /**< entries in the factors (L, or L + U; the
                          incomplete factors of an iterative backend)   */
  double flops;      /**< flop count of the factorisation, if known (else 0) */
  double mem_peak;   /**< peak memory of the instance since it was
                          created [bytes]: the library's own count plus
                          the copies the backend keeps (0 if unknown)    */
  int iterations;    /**< iterative backends: iterations of the last
                          solve (0 for direct backends)                  */
  long switches;     /**< composite "auto": falls from Cholesky to LU    */
  long fallback_steps; /**< composite "auto": steps solved with LU       */
  int block_size;    /**< the block size the preconditioner was given
                          (PETSc's GAMG with the matrix's layout: its
                          components per node, with the rigid-body near-
                          null space); 0: none                          */
} mpgm_solver_stats;

/** Options of the backends (the scene's solver block). A backend reads
 *  the fields that concern it and ignores the others;
 *  mpgm_solver_opts_default gives the defaults. */
typedef struct mpgm_solver_opts {
  double tol;   /**< iterative: relative residual |b - A x| / |b| a solve
                     must reach (default 1e-10)                          */
  int restart;  /**< GMRES: Krylov vectors per cycle (default 100)       */
  int max_iter; /**< iterative: iterations per solve before it fails with
                     MPGM_ERR_LINEAR (default 5000)                      */
  int symmetric; /**< "auto": 1 when the matrices will be symmetric
                     (Cholesky first), 0 when not (LU); "petsc": picks
                     the defaults (CG or GMRES); default 1               */
  char petsc[512]; /**< petsc: options in PETSc's command-line syntax
                     ("-ksp_type gmres -pc_type gamg"); default ""     */
  const struct mpgm_solver_type *part; /**< reuse: the direct backend
                     whose factorisation preconditions GMRES; NULL     */
  int refactor_iterations; /**< reuse: refactorise after a solve of more
                     Krylov iterations than this (default 20)          */
  const struct mpgm_solver_type *fallback; /**< fallback: the direct
                     backend that factorises a matrix the iterative
                     opts.part could not solve or precondition; NULL   */
  const char *file; /**< the scene file the options come from, named in
                     the messages of options that are bad input
                     ("FILE: solver.petsc: ..."); borrowed; NULL: none */
} mpgm_solver_opts;

/** The default options (tol 1e-10, restart 100, max_iter 5000,
 *  symmetric 1, petsc "", part NULL, refactor_iterations 20, fallback
 *  NULL, file NULL). */
mpgm_solver_opts mpgm_solver_opts_default(void);

/** 1 when the backend `name` can be used; 0 with the reason in msg (of
 *  len bytes; may be NULL) when not: "petsc" is a module loaded here, on
 *  first use, and absent when mpgm was built without PETSc. */
int mpgm_solver_usable(const char *name, char *msg, size_t len);

/** End the libraries that backends started for the process (PETSc and the
 *  MPI under it); call once, at exit, after every instance is destroyed. */
void mpgm_solver_finalize(void);

/** A named configuration of a backend with options (PETSc's KSP and PC
 *  choices): `mpgm bench-solvers` and the conformance tests run each as
 *  "backend:name". */
typedef struct mpgm_solver_preset {
  const char *name;    /**< short name: "cg-gamg"                           */
  const char *options; /**< mpgm_solver_opts.petsc: "-ksp_type cg -pc_type gamg" */
  int spd_only;        /**< 1: only for symmetric positive definite matrices
                            (CG, Cholesky); the benchmark skips others     */
  int direct;          /**< 1: a direct method (MUMPS): solved to round-off,
                            in one application of the factors            */
} mpgm_solver_preset;

typedef struct mpgm_solver_type {
  const char *name;  /**< scene name: "cholmod", "umfpack", "klu", ...    */
  const char *doc;   /**< one line for docs                               */
  int needs_spd;     /**< 1: only for symmetric positive definite matrices */
  int iterative;     /**< 1: the solution meets opts.tol only (solve may
                          fail with MPGM_ERR_LINEAR); 0: a direct solver  */
  int composite;     /**< 1: made of other instances, which the wrappers
                          time and count; the composite itself is not   */
  /** Optional: configurations worth comparing, ended by a {NULL} entry
   *  (the default options are the backend's own row). */
  const mpgm_solver_preset *presets;
  /** Optional: its own keys of the scene's "solver" section (petsc: its
   *  options string), read into mpgm_solver_opts (nkeys of them); a scene
   *  with another backend refuses them by this backend's name. */
  const mpgm_key_spec *keys;
  int nkeys;
  /** Resident bytes of the library the backend loads on first use (the
   *  scene's memory estimate, io/scene_size.c); 0: none beyond mpgm's. */
  double library_bytes;
  /** Allocate the instance with options opts (never NULL; copied). */
  int (*create)(mpgm_ctx *ctx, const mpgm_solver_opts *opts, void **data);
  void (*destroy)(void *data); /**< accepts NULL and half-built data       */
  /** Symbolic analysis of A's pattern: fill-reducing ordering (perm,
   *  when not NULL: the n equations in the order to eliminate them, used
   *  as given; NULL: the backend's own ordering) and symbolic factor. */
  int (*analyse)(void *data, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm);
  /** Numeric factorisation of A (same pattern as analysed).
   *  Not positive definite / singular: MPGM_ERR_SINGULAR (recoverable). */
  int (*factor)(void *data, mpgm_ctx *ctx, const mpgm_csc *A);
  /** x = A^-1 b with the last factorisation (b, x of length n; may alias).
   *  Iterative backends: not converged within opts.max_iter iterations:
   *  MPGM_ERR_LINEAR (recoverable). */
  int (*solve)(void *data, mpgm_ctx *ctx, const double *b, double *x);
  /** Optional: X = A^-1 B for nrhs columns at once (column-major, n
   *  apart; B and X may alias), where the backend does several right-hand
   *  sides faster than one by one (a supernodal solve through BLAS 3);
   *  NULL: mpgm_solver_solve_many solves column by column. */
  int (*solve_many)(void *data, mpgm_ctx *ctx, int nrhs, const double *B, double *X);
  /** Optional (may be NULL). */
  int (*stats)(void *data, mpgm_solver_stats *st);
  /** Optional: a new time (or load) step begins; *kept = 0 when the
   *  factorisation held is no longer the one solve would use. */
  int (*step)(void *data, mpgm_ctx *ctx, int *kept);
  /** Optional (iterative backends): the relative residual the next solves
   *  must reach, |b - A x| <= tol |b| (Newton's forcing term), in place
   *  of opts.tol. */
  int (*tolerance)(void *data, double tol);
  /** Optional: the backend that stands for the instance in reports (a
   *  composite's first choice); NULL op: the type's name. */
  const char *(*backend)(const void *data);
  /** Optional: the instance that factorises now (a composite's part in
   *  use), for a matrix that must not go through its fallback; NULL op:
   *  the instance itself. */
  struct mpgm_solver *(*part)(void *data);
  /** Optional: the instance's state that outlives a step and decides what
   *  later steps do (a composite's part in use and holds), appended to a
   *  checkpoint / read back into a fresh instance (mpgm_blob.h); NULL ops:
   *  nothing to keep (factorisations are rebuilt, not saved). */
  int (*save)(const void *data, mpgm_ctx *ctx, struct mpgm_blob *b);
  int (*restore)(void *data, mpgm_ctx *ctx, struct mpgm_blob *b);
  /** Optional: judge the options before a run (a backend with options of
   *  its own, solver.petsc): an instance with opts set up on a small test
   *  system whose symmetry is opts->symmetric, then destroyed; an option
   *  refused or not used is MPGM_ERR_INPUT. NULL: nothing to judge. */
  int (*check)(mpgm_ctx *ctx, const mpgm_solver_opts *opts);
} mpgm_solver_type;

/** A solver instance. */
typedef struct mpgm_solver {
  const mpgm_solver_type *type;
  void *data;
  int analysed; /**< 1 after analyse for the current pattern */
} mpgm_solver;

/** Newton-Krylov's composite (solver.newton "krylov"; not in the list:
 *  it needs opts.part): GMRES on the current matrix preconditioned by the
 *  last factorisation of the direct backend opts.part (solvers/reuse.c). */
extern const mpgm_solver_type mpgm_solver_reuse;

/** solver.linear_fallback's composite (not in the list: it needs
 *  opts.part, iterative, and opts.fallback, direct): the iterative part's
 *  solves, and a matrix it cannot solve or precondition (MPGM_ERR_LINEAR,
 *  MPGM_ERR_SINGULAR) factorised and solved by the direct part, counted in
 *  ctx->count[MPGM_C_LINEAR_FALLBACKS] (solvers/fallback.c). */
extern const mpgm_solver_type mpgm_solver_fallback;

/** Find a backend by name; NULL if none. */
const mpgm_solver_type *mpgm_solver_type_find(const char *name);
/** All backends, NULL-terminated. */
const mpgm_solver_type *const *mpgm_solver_types(void);

/** The options of `type` judged before a run, as its first factorisation
 *  would judge them (type->check: PETSc's KSP and PC set up once on a test
 *  system of a few hundred equations with opts->symmetric's symmetry,
 *  which loads and starts PETSc); 0 at once for a backend without options
 *  of its own. Errors: MPGM_ERR_INPUT with "FILE: solver.petsc: ..." (an
 *  option refused by mpgm's policy, refused by PETSc, or not used), or the
 *  backend's code when it cannot start (MPGM_ERR_UNSUPPORTED, _SOLVER,
 *  _NOMEM). Leaves ctx's timers and counters as they were. */
int mpgm_solver_check(mpgm_ctx *ctx, const mpgm_solver_type *type, const mpgm_solver_opts *opts);

/** Create/destroy an instance (opts NULL: the defaults; destroy accepts
 *  NULL, nulls the pointer). */
int mpgm_solver_create(mpgm_ctx *ctx, const mpgm_solver_type *type,
                       const mpgm_solver_opts *opts, mpgm_solver **out);
void mpgm_solver_destroy(mpgm_solver **s);
/** Generic wrappers: time into ctx (MPGM_T_ANALYSE/FACTOR/SOLVE) and count
 *  analyses, factorisations and solves in ctx (and, for iterative
 *  backends, their iterations in ctx->count[MPGM_C_LINEAR_ITERATIONS]). */
int mpgm_solver_analyse(mpgm_solver *s, mpgm_ctx *ctx, const mpgm_csc *A, const int *perm);
int mpgm_solver_factor(mpgm_solver *s, mpgm_ctx *ctx, const mpgm_csc *A);
int mpgm_solver_solve(mpgm_solver *s, mpgm_ctx *ctx, const double *b,
                      double *x);
/** X = A^-1 B for nrhs right-hand sides of the order n of A (column-
 *  major, n apart; may alias), counted as nrhs solves: the backend's
 *  solve_many, else one solve per column. */
int mpgm_solver_solve_many(mpgm_solver *s, mpgm_ctx *ctx, int n, int nrhs, const double *B,
                           double *X);
/** Threads of the libraries under the backends (process-wide): n >= 1
 *  sets the BLAS threads to n and serialises the OpenMP regions of
 *  SuiteSparse (CHOLMOD 3 asks for 4 OpenMP threads whatever the machine
 *  has: on 2 cores that made its factorisation 2.2x slower, see
 *  docs/benchmarks.md); n = 0 leaves the libraries' defaults. Found at run
 *  time (dlsym), so any BLAS and OpenMP runtime works; returns a bit set of
 *  what was applied: 1 BLAS threads, 2 OpenMP. */
int mpgm_solver_threads(int n);
/** A new time (or load) step begins (composites count their holds in
 *  steps); *kept = 0 when a factorisation held before is no longer valid.
 *  Backends without the operation: *kept = 1. */
int mpgm_solver_step(mpgm_solver *s, mpgm_ctx *ctx, int *kept);
/** The next solves' relative tolerance, tol in (0, 1) (an inexact Newton
 *  method's forcing term); backends without the operation (the direct
 *  ones) ignore it. */
int mpgm_solver_tolerance(mpgm_solver *s, double tol);
/** Checkpoints: the backend's name and its own state (type->save) into b /
 *  read back into a fresh instance of the same backend (another backend:
 *  MPGM_ERR_INPUT). The instance then analyses and factorises anew. */
int mpgm_solver_save(const mpgm_solver *s, mpgm_ctx *ctx, struct mpgm_blob *b);
int mpgm_solver_restore(mpgm_solver *s, mpgm_ctx *ctx, struct mpgm_blob *b);
/** The name of the backend a report should name (a composite's first
 *  choice: "cholmod" for "auto" on symmetric matrices). */
const char *mpgm_solver_name(const mpgm_solver *s);
/** The instance that factorises now: a composite's part in use, else s
 *  itself. Analyse s first. For a matrix whose failure means something
 *  (a singular mass matrix) rather than a reason to fall back. */
mpgm_solver *mpgm_solver_part(mpgm_solver *s);
/** Statistics of the last factorisation. (Named _get_ because
 *  mpgm_solver_stats is the struct's typedef.) */
int mpgm_solver_get_stats(mpgm_solver *s, mpgm_solver_stats *st);

#ifdef __cplusplus
}
#endif
#endif
