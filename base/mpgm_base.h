/* mpgm_base.h -- error codes, the run context (errors, timers, counters),
 * and the CALL/CHECK macros shared by every mpgm library.
 *
 * Conventions (see docs/architecture.md):
 *   - every function that can fail returns int: 0 success, < 0 fatal,
 *     > 0 recoverable (the time loop may cut the step);
 *   - the message of the first failure is recorded in an mpgm_ctx together
 *     with file and line; callers add nothing but propagate the code;
 *   - no global mutable state: the context is passed explicitly.
 */
#ifndef MPGM_BASE_H
#define MPGM_BASE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MPGM_NAME_LEN 64   /**< names of scene items (materials, bodies) */
#define MPGM_PATH_LEN 1024 /**< file and folder paths                    */

/** Spatial dimension of the data layouts: the components of a vector per
 *  point or node (x, u, v, a, grad N), the degrees of freedom per node.
 *  Every library is built once per dimension from the same sources
 *  (CMake: the _3d targets compile with -DMPGM_DIM=3; docs/architecture.md,
 *  "How the dimension is chosen"); 2 is plane strain. Code still written
 *  out per component (x and y apart) is marked "2-D only" where it stands,
 *  and a file holding such code stops a 3-D build with an #error. */
#ifndef MPGM_DIM
#define MPGM_DIM 2
#endif
#if MPGM_DIM != 2 && MPGM_DIM != 3
#error "MPGM_DIM must be 2 (plane strain) or 3"
#endif
/** Entries of a full second-order tensor, MPGM_DIM x MPGM_DIM row major:
 *  the deformation gradient F and its increment dF, {xx, xy, yx, yy} in
 *  2-D, {xx, xy, xz, yx, ..., zz} in 3-D. */
#define MPGM_TENSOR (MPGM_DIM * MPGM_DIM)
/** Entries of one node pair's block of the tangent K (the rows of node a's
 *  components, the columns of node b's), MPGM_DIM x MPGM_DIM row major. */
#define MPGM_BLOCK (MPGM_DIM * MPGM_DIM)
/** Components of a symmetric tensor in Voigt notation that the tangent
 *  couples: 2-D the in-plane {xx, yy, xy}; 3-D {xx, yy, zz, xy, yz, xz}
 *  (mpgm_voigt_pair). */
#define MPGM_NVOIGT (MPGM_DIM * (MPGM_DIM + 1) / 2)
/** Entries of the material tangent D per point: MPGM_NVOIGT x MPGM_NVOIGT,
 *  row major, engineering shear (mpgm_material.h). */
#define MPGM_NTANGENT (MPGM_NVOIGT * MPGM_NVOIGT)
/** Stored components of a stress per point (sigma, S0, the materials'
 *  tau): 2-D {xx, yy, xy, zz}: plane strain keeps the out-of-plane zz,
 *  which is not zero, after the in-plane Voigt components; 3-D the six
 *  Voigt components {xx, yy, zz, xy, yz, xz}, the full tensor. */
#if MPGM_DIM == 2
#define MPGM_NSTRESS (MPGM_NVOIGT + 1)
#else
#define MPGM_NSTRESS MPGM_NVOIGT
#endif
/** The tensor indices (i, j), i <= j, of Voigt component k < MPGM_NVOIGT:
 *  the diagonal first, then the shears; 2-D xx, yy, xy; 3-D xx, yy, zz,
 *  xy, yz, xz. */
static const int mpgm_voigt_pair[MPGM_NVOIGT][2] =
#if MPGM_DIM == 2
    {{0, 0}, {1, 1}, {0, 1}};
#else
    {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
#endif
/** The Voigt component of tensor entry (i, j) (the inverse of
 *  mpgm_voigt_pair): 2-D {{xx, xy}, {xy, yy}} = {{0, 2}, {2, 1}}. */
static const int mpgm_voigt_of[MPGM_DIM][MPGM_DIM] =
#if MPGM_DIM == 2
    {{0, 2}, {2, 1}};
#else
    {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};
#endif
/** 1 on the diagonal of a DIM x DIM tensor stored row major (entry c). */
#define MPGM_DIAG(c) ((c) % (MPGM_DIM + 1) == 0)

/** Error codes. Negative: fatal. Positive: recoverable (cut the step). */
typedef enum {
  MPGM_OK = 0,
  /* fatal */
  MPGM_ERR_INPUT = -1,       /**< bad input (scene, arguments)          */
  MPGM_ERR_IO = -2,          /**< file could not be read or written     */
  MPGM_ERR_NOMEM = -3,       /**< allocation failed                     */
  MPGM_ERR_UNSUPPORTED = -4, /**< operation not provided by a plug-in   */
  MPGM_ERR_SOLVER = -5,      /**< linear solver failed (not recoverable) */
  MPGM_ERR_INTERNAL = -6,    /**< broken invariant: a bug               */
  MPGM_ERR_DOMAIN = -7,      /**< a point left the background grid      */
  MPGM_ERR_INTERRUPTED = -8, /**< the caller asked the run to stop       */
  MPGM_ERR_DIMENSION = -9,   /**< a scene (checkpoint) of the other
                                  dimension's build: bad input to this one,
                                  which the command hands to the other   */
  /* recoverable */
  MPGM_ERR_JACOBIAN = 1,     /**< det F <= 0 or inverted cell            */
  MPGM_ERR_NOT_CONVERGED = 2,/**< Newton exceeded its iteration limit     */
  MPGM_ERR_DIVERGED = 3,     /**< Newton diverged                         */
  MPGM_ERR_NAN = 4,          /**< NaN or Inf in residual or solution      */
  MPGM_ERR_SINGULAR = 5,     /**< matrix singular / not positive definite */
  MPGM_ERR_RETURN_MAP = 6,   /**< return mapping did not converge         */
  MPGM_ERR_SHAPE = 7,        /**< shape function ill-conditioned/outside  */
  MPGM_ERR_LINEAR = 8        /**< iterative linear solver did not reach its
                                  tolerance                               */
} mpgm_code;

/** One scalar parameter of a plug-in (a material, a reference solution),
 *  as the scene declares it. */
typedef struct mpgm_param_spec {
  const char *name; /**< JSON key, e.g. "E"                              */
  const char *unit; /**< unit for docs and messages, e.g. "Pa"           */
  double def;       /**< default value; NAN when the key is required      */
  double lo, hi;    /**< admissible range                                */
  int lo_open;      /**< 1: value must be > lo; 0: >= lo                 */
  int hi_open;      /**< 1: value must be < hi; 0: <= hi                 */
  const char *doc;  /**< one line for docs/scene-format.md               */
} mpgm_param_spec;

/** What a key of a plug-in's own part of the scene holds
 *  (mpgm_key_spec.type). */
typedef enum {
  MPGM_KEY_REAL = 0, /**< a number, into a double                       */
  MPGM_KEY_INT,      /**< an integer in [lo, hi], into an int            */
  MPGM_KEY_CHOICE,   /**< one of `choices`, into an int: lo + the index
                          of the name (so a field may count from 1)      */
  MPGM_KEY_STRING    /**< a string, into a char array of `size` bytes
                          (default ""); its rule is `valid`'s            */
} mpgm_key_type;

/** One key a plug-in declares in its part of the scene, read into a field
 *  of the plug-in's parameter struct (a shape kind's mpgm_shape_params, a
 *  front end's keys of "shape"). The plug-in lists its keys; the scene
 *  reader (io/scene_keys.c) reads, checks, resolves and documents them,
 *  so a new parameter is one line in the plug-in's own file. Written
 *  with designated initialisers. */
typedef struct mpgm_key_spec {
  const char *name;           /**< JSON key, e.g. "gamma"                */
  int type;                   /**< mpgm_key_type                         */
  size_t offset;              /**< offsetof the field in the struct      */
  double def;                 /**< default value (CHOICE: lo + index);
                                   NAN (REAL) or below lo (INT, CHOICE):
                                   required                              */
  double lo, hi;              /**< admissible range (CHOICE: lo is the
                                   value of the first name)              */
  int lo_open, hi_open;       /**< REAL: 1 for > lo, < hi                */
  const char *const *choices; /**< CHOICE: the names, NULL-terminated    */
  const char *unit;           /**< for docs, e.g. "m" or "-"             */
  const char *doc;            /**< one line for docs/scene-format.md     */
  size_t size;                /**< STRING: the bytes of the field        */
  /** Optional: the value's own rule beyond its type and range (the field
   *  as read); 0, or nonzero with the reason in why (len bytes). */
  int (*valid)(const void *field, char *why, size_t len);
} mpgm_key_spec;

/** Short fixed description of a code ("bad input", "det F <= 0", ...). */
const char *mpgm_code_str(int code);

/** Room for mpgm_point_str's text. */
#define MPGM_POINT_STR 96
/** A position for messages, "(x, y)" or "(x, y, z)" (%g each), in buf;
 *  returns buf. */
const char *mpgm_point_str(const double x[MPGM_DIM], char buf[MPGM_POINT_STR]);
/** Room for mpgm_box_str's text. */
#define MPGM_BOX_STR 160
/** A box "[x0, x1] x [y0, y1]" (" x [z0, z1]" in 3-D), %g each, into buf;
 *  returns buf (for messages). */
const char *mpgm_box_str(const double lo[MPGM_DIM], const double hi[MPGM_DIM], char buf[MPGM_BOX_STR]);

/** Timers of the time split reported in summary.json. */
typedef enum {
  MPGM_T_SHAPE = 0, /**< shape functions and connectivity       */
  MPGM_T_SEARCH,    /**< neighbour search                        */
  MPGM_T_ASSEMBLY,  /**< residual and tangent assembly           */
  MPGM_T_ANALYSE,   /**< symbolic analysis of the sparse matrix  */
  MPGM_T_FACTOR,    /**< numeric factorisation                   */
  MPGM_T_SOLVE,     /**< triangular solves                       */
  MPGM_T_MATERIAL,  /**< constitutive update                     */
  MPGM_T_BODYFORCE, /**< external (body) force vector            */
  MPGM_T_MASS,      /**< inertia: mass, Newmark, dynamic tangent */
  MPGM_T_UPDATE,    /**< commit of points and nodes              */
  MPGM_T_OUTPUT,    /**< VTK, probes, summary                    */
  MPGM_T_TOTAL,     /**< whole run                               */
  MPGM_T_COUNT
} mpgm_timer_id;

/** Name of a timer as written in summary.json ("assembly", ...). */
const char *mpgm_timer_name(int id);

/** Counters of the work a run did, reported in summary.json's "counts"
 *  under the names of mpgm_counter_name. */
typedef enum {
  MPGM_C_ANALYSES = 0,      /**< symbolic analyses                        */
  MPGM_C_FACTORIZATIONS,    /**< numeric factorisations                   */
  MPGM_C_SOLVES,            /**< solves                                   */
  MPGM_C_LINEAR_ITERATIONS, /**< iterations of iterative linear solvers   */
  MPGM_C_MATERIAL_CALLS,    /**< constitutive updates (per point)         */
  MPGM_C_BODY_FORCE,        /**< body-force loops                         */
  MPGM_C_MASS,              /**< inertia loops                            */
  MPGM_C_POINT_SORTS,       /**< reorderings of the points in memory      */
  MPGM_C_RADIUS_GROWTHS,    /**< node clouds: x1.25 growths of a search
                                 radius that held fewer than min_nodes   */
  MPGM_C_CLOUD_ENLARGEMENTS,/**< node clouds: next-nearest nodes added
                                 after a failed evaluation               */
  MPGM_C_COLD_RESTARTS,     /**< meshfree: failed warm-started evaluations
                                 (LME multiplier) retried from zero      */
  MPGM_C_NODES_MERGED,      /**< GMM: node-steps left out for being closer
                                 than mesh.min_node_distance to another  */
  MPGM_C_SURFACE_CARRIED,   /**< surface-point steps without functions of
                                 their own, moved with their nearest
                                 material point (mpgm_tracers_carry)     */
  MPGM_C_PROBES_CARRIED,    /**< probe-steps the same (a probe the
                                 material has left, e.g. on a free
                                 surface that sinks below it)            */
  MPGM_C_NODE_MOTION_FALLBACKS, /**< GMM, mesh.node_motion interpolated:
                                 node-steps whose functions at the node
                                 failed; the node moved with its own
                                 coefficient                             */
  MPGM_C_DOMAIN_CLAMPS,     /**< CPDI: domain corners beyond the grid
                                 pulled back onto its edge (corner-steps) */
  MPGM_C_CPLS_LINEAR,       /**< CPLS: node-steps reconstructed with the
                                 linear basis (the quadratic amplified)   */
  MPGM_C_CPLS_PROJECTED,    /**< CPLS: node-steps left with the projected
                                 velocity                                */
  MPGM_C_LINEAR_NOT_CONVERGED, /**< iterative linear solves that stopped
                                 short of their tolerance (recoverable)  */
  MPGM_C_FACTOR_REUSES,     /**< Newton-Krylov: iterations that kept the
                                 last factorisation as the preconditioner */
  MPGM_C_PATTERNS_KEPT,     /**< node clouds with shape.skin: steps whose
                                 clouds changed and kept the pattern and
                                 its analysis                            */
  MPGM_C_KINETIC_RESETS,    /**< explicit with time.kinetic_damping: the
                                 points' velocities set to zero at a peak
                                 of the kinetic energy                   */
  MPGM_C_NEWTON_RELAXATIONS, /**< solver.relaxation: Newton iterations
                                 found stalled (|R| repeating every other
                                 iteration) after which the corrections
                                 were scaled down                        */
  MPGM_C_NEWTON_STAGNATIONS, /**< solver.stagnation: Newton solves ended
                                 early because |R| had stopped falling
                                 (each a step cut, or the run's end)     */
  MPGM_C_CONTACT_LOW_RANK,  /**< solver.contact_rank: changes of the
                                 contact set at surface points applied to
                                 the kept factorisation (no refactoring) */
  MPGM_C_LINE_SEARCHES,     /**< solver.line_search: Newton corrections
                                 shortened because |R| did not fall     */
  MPGM_C_BFGS_UPDATES,      /**< solver.newton "bfgs": pairs of iterates
                                 that corrected the kept factorisation  */
  MPGM_C_LINEAR_FALLBACKS,  /**< solver.linear_fallback: matrices the
                                 iterative backend could not solve (or
                                 precondition), factorised by the direct
                                 fallback                               */
  MPGM_C_FACTOR_RENEWALS,   /**< solver.newton "modified" / "bfgs": kept
                                 factorisations renewed in a solve's last
                                 iterations because their rate could not
                                 reach the tolerance in those left       */
  MPGM_C_COUNT
} mpgm_counter_id;

/** Name of a counter as written in summary.json ("analyses", ...). */
const char *mpgm_counter_name(int id);

/** Messages of the library, by importance: the logger (mpgm_ctx_set_logger)
 *  decides what reaches the user; the library itself never prints. */
typedef enum {
  MPGM_LOG_ERROR = 0, /**< a failure (also recorded as the context's error) */
  MPGM_LOG_WARNING,   /**< a recovered problem: a step cut, a fallback      */
  MPGM_LOG_INFO,      /**< results worth a line: a step's time split        */
  MPGM_LOG_PROGRESS,  /**< the state of a running job, once per step        */
  MPGM_LOG_DEBUG      /**< details for developers                          */
} mpgm_log_level;

/** A logger: receives every message at or below the context's level, one
 *  whole message without a trailing newline. */
typedef void (*mpgm_log_fn)(void *user, int level, const char *msg);

/** A failure made on purpose, for the tests of step control
 *  (tests/scripts/failure_kinds.sh): the check of one recoverable kind
 *  (code: MPGM_ERR_RETURN_MAP, _JACOBIAN, _SHAPE, _NOT_CONVERGED, _NAN)
 *  reports a failure at its own place in the first `times` attempts of step
 *  `step` (the step and its retries after cuts). The mpgm command sets it
 *  from the environment variable MPGM_TEST_FAULT=KIND:STEP:TIMES; code 0
 *  (the default) is off. */
typedef struct mpgm_fault {
  int code;   /**< failure kind to make, 0: none                       */
  long step;  /**< the step it is made at                              */
  int times;  /**< attempts of that step it is made in                 */
  int fired;  /**< attempts so far (the step control counts its cuts)  */
} mpgm_fault;

/** The run context: first error, timers, counters, logger. One per run. */
/** A reduction over the processes of a run (mpgm_comm). */
typedef enum mpgm_reduce { MPGM_REDUCE_SUM, MPGM_REDUCE_MIN, MPGM_REDUCE_MAX } mpgm_reduce;

/** The processes a run is one of (as SUNDIALS' SUNContext_Create(comm)):
 *  this one's rank and their number, with the collectives the library
 *  uses, given by the module that started MPI (parallel/, mpgm_par.so,
 *  over a duplicate of MPI_COMM_WORLD). A context without one (comm
 *  NULL) is one process: each collective below is then the identity and
 *  no MPI is called, nor loaded. Every operation returns 0, or -1 when
 *  MPI failed. */
typedef struct mpgm_comm {
  int rank;       /**< this process, 0 .. size - 1                     */
  int size;       /**< processes of the run                            */
  int local;      /**< of them, those on this machine (sharing its cores) */
  void *impl;     /**< the module's communicator                       */
  int (*allreduce)(void *impl, mpgm_reduce op, double *v, int n); /**< in place */
  int (*allreduce_long)(void *impl, mpgm_reduce op, long *v, int n); /**< in place */
  int (*bcast)(void *impl, void *buf, size_t bytes, int root);
  int (*barrier)(void *impl);
} mpgm_comm;

typedef struct mpgm_ctx {
  int code;           /**< first recorded error code, 0 if none   */
  char msg[1024];     /**< its message                            */
  const char *file;   /**< source file where it was recorded      */
  int line;           /**< source line                            */
  double t[MPGM_T_COUNT];     /**< accumulated wall time per timer [s] */
  double t_start[MPGM_T_COUNT]; /**< start stamp of a running timer   */
  long count[MPGM_C_COUNT];   /**< work counters (mpgm_counter_id)     */
  mpgm_log_fn log;    /**< logger (NULL: messages are dropped)     */
  void *log_user;     /**< its first argument                      */
  int log_level;      /**< most detailed level passed on            */
  mpgm_fault fault;   /**< a failure made on purpose (tests); off    */
  const mpgm_comm *comm; /**< the run's processes; NULL: one process  */
} mpgm_ctx;

/** The number of processes of the context's run (1 without a comm). */
static inline int mpgm_ctx_size(const mpgm_ctx *ctx) { return ctx->comm ? ctx->comm->size : 1; }
/** This process's rank in it (0 without a comm). */
static inline int mpgm_ctx_rank(const mpgm_ctx *ctx) { return ctx->comm ? ctx->comm->rank : 0; }

/** v[0..n) reduced over the run's processes, in place, on every one
 *  (MPI_Allreduce); nothing on one process. 0, or the recorded error. */
int mpgm_allreduce(mpgm_ctx *ctx, mpgm_reduce op, double *v, int n);
/** The same for integers. */
int mpgm_allreduce_long(mpgm_ctx *ctx, mpgm_reduce op, long *v, int n);
/** bytes of buf from process root to all (MPI_Bcast); nothing on one. */
int mpgm_bcast(mpgm_ctx *ctx, void *buf, size_t bytes, int root);
/** The outcome of a part each process did on its own, the same on every
 *  process (collective): each gives its err (0, or the code with its
 *  message in ctx) and gets back 0 when every process succeeded, else the
 *  code of the first process (lowest rank) that failed; the others then
 *  hold its message as "process R of P: ...". Before the next collective
 *  after such a part, so that no process waits there for one that left.
 *  One process: err. */
int mpgm_agree(mpgm_ctx *ctx, int err);
/** The imbalance of a count over the processes (collective): the largest
 *  of every process's n over their mean, 1 when none has any (and on one
 *  process). */
int mpgm_imbalance(mpgm_ctx *ctx, long n, double *imb);

/** 1 when the failure `code` is to be made now, in an attempt of `step`
 *  (mpgm_fault); 0 otherwise, always when no fault is set. */
static inline int mpgm_fault_due(const mpgm_ctx *ctx, int code, long step) {
  return ctx->fault.code == code && code != 0 && ctx->fault.step == step &&
         ctx->fault.fired < ctx->fault.times;
}

/** Reset a context to "no error", zero timers and counters. */
void mpgm_ctx_init(mpgm_ctx *ctx);

/** Record an error (the first one wins; later calls keep the first message
 *  but return their own code). Returns code, so it can be returned. */
int mpgm_err_set(mpgm_ctx *ctx, int code, const char *file, int line,
                 const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/** Forget a recorded (recoverable) error, e.g. after a step cut. */
void mpgm_err_clear(mpgm_ctx *ctx);

/** The most any file mpgm reads may have: every reader's own bound is at
 *  most this (16 GiB; checkpoints are held to it, the other inputs to far
 *  less: docs/scene-format.md, "Files a run reads and writes"). */
#define MPGM_READ_MAX ((size_t)16 << 30)

/** What a file of this st_mode is, for messages: "a regular file", "a
 *  folder", "a pipe or FIFO", "a socket", "a character device", "a block
 *  device". */
const char *mpgm_file_kind(unsigned mode);

/** Open path for reading, a regular file only (read.c). The name is
 *  checked first (stat, which follows symbolic links: a link to a regular
 *  file is fine), so a FIFO, a pipe, a socket, a device or a folder is
 *  refused without being opened; the file is then opened non-blocking and
 *  what was opened checked again (fstat) before O_NONBLOCK is cleared, so
 *  no read can block for a writer. *fd receives the descriptor (the caller
 *  closes it), *size (may be NULL) the file's size now. Errors:
 *  MPGM_ERR_INPUT ("PATH: is a pipe or FIFO, not a regular file"; larger
 *  than max bytes, which is clamped to MPGM_READ_MAX), MPGM_ERR_IO (cannot
 *  open: "PATH: cannot open: REASON"). */
int mpgm_open_regular(mpgm_ctx *ctx, const char *path, size_t max, int *fd, size_t *size);
/** mpgm_open_regular as a stdio stream for reading; *f (the caller
 *  fcloses it). A line reader still counts the bytes it reads against max:
 *  a file may grow while it is read. */
int mpgm_fopen_regular(mpgm_ctx *ctx, const char *path, size_t max, FILE **f, size_t *size);
/** Record "PATH: larger than MAX, the most this file may have"
 *  (MPGM_ERR_INPUT) and return the code. */
int mpgm_err_too_large(mpgm_ctx *ctx, const char *path, size_t max);

/** Read a whole regular file (mpgm_open_regular) of at most max bytes into
 *  *text (malloc'd, NUL-terminated; the caller frees it; binary content may
 *  hold NULs), its length in *len (may be NULL). A file that grows past max
 *  while it is read is refused too. Errors: as mpgm_open_regular;
 *  MPGM_ERR_IO (read error), MPGM_ERR_NOMEM. */
int mpgm_read_file(mpgm_ctx *ctx, const char *path, size_t max, char **text, size_t *len);
/** 1 when path names a place below the folder it is taken from: not
 *  empty, relative (no leading '/' or '~') and without a ".." part. A path
 *  read from a file (a scene's output.dir, a .pvd's frames) must be one,
 *  so that a file from elsewhere cannot reach outside that folder. */
int mpgm_path_below(const char *path);
/** 1 when name ends with suffix and has something before it (a file's
 *  kind by its name: ".vtu", ".series", "_K.mtx"). */
int mpgm_ends_with(const char *name, const char *suffix);

/** mpgm's version and the commit it was built from, e.g. "0.1.0
 *  (1a2b3c4d5e6f)": what a checkpoint records. */
const char *mpgm_version(void);

/** Monotonic wall clock in seconds. */
double mpgm_wtime(void);
/** Calls of mpgm_wtime so far in this process (all threads): the timers'
 *  own cost is this count times the cost of one call (bench/timers). */
long mpgm_wtime_reads(void);

static inline void mpgm_timer_start(mpgm_ctx *ctx, int id) {
  ctx->t_start[id] = mpgm_wtime();
}
static inline void mpgm_timer_stop(mpgm_ctx *ctx, int id) {
  ctx->t[id] += mpgm_wtime() - ctx->t_start[id];
}
/** Move s seconds from timer `from` to timer `to` (work measured inside
 *  another timer's span, e.g. the searches of a front end's begin_step,
 *  which the core times as "shape"). */
static inline void mpgm_timer_move(mpgm_ctx *ctx, int from, int to, double s) {
  ctx->t[from] -= s;
  ctx->t[to] += s;
}
/** Add n to counter id. */
static inline void mpgm_count(mpgm_ctx *ctx, int id, long n) { ctx->count[id] += n; }

/** Pass messages up to `level` (mpgm_log_level) to fn(user, level, msg). */
void mpgm_ctx_set_logger(mpgm_ctx *ctx, mpgm_log_fn fn, void *user, int level);
/** 1 when a message of this level would reach the logger (to skip
 *  composing one nobody reads). */
static inline int mpgm_log_wanted(const mpgm_ctx *ctx, int level) {
  return ctx->log && level <= ctx->log_level;
}
/** Send a printf-style message to the context's logger (nothing when it
 *  has none, or the level is above its level). */
void mpgm_log(mpgm_ctx *ctx, int level, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/** Propagate a non-zero code. */
#define MPGM_CALL(expr)                                                        \
  do {                                                                         \
    int mpgm_call_ierr_ = (expr);                                              \
    if (mpgm_call_ierr_) return mpgm_call_ierr_;                               \
  } while (0)

/** Record and return code if cond does not hold. */
#define MPGM_CHECK(ctx, cond, code, ...)                                       \
  do {                                                                         \
    if (!(cond))                                                               \
      return mpgm_err_set((ctx), (code), __FILE__, __LINE__, __VA_ARGS__);     \
  } while (0)

/** Record and return code unconditionally. */
#define MPGM_ERROR(ctx, code, ...)                                             \
  return mpgm_err_set((ctx), (code), __FILE__, __LINE__, __VA_ARGS__)

/** calloc that records MPGM_ERR_NOMEM; use as MPGM_ALLOC(ctx, p, n). */
#define MPGM_ALLOC(ctx, p, n)                                                  \
  do {                                                                         \
    size_t mpgm_alloc_n_ = (size_t)(n);                                        \
    (p) = calloc(mpgm_alloc_n_ ? mpgm_alloc_n_ : 1, sizeof(*(p)));             \
    MPGM_CHECK(ctx, (p) != NULL, MPGM_ERR_NOMEM, "out of memory (%zu x %zu B)", \
               mpgm_alloc_n_, sizeof(*(p)));                                   \
  } while (0)

#ifdef __cplusplus
}
#endif
#endif
