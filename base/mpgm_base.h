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

#ifdef __cplusplus
extern "C" {
#endif

/** Spatial dimension of the data layouts (2-D plane strain today). */
#define MPGM_DIM 2

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

/** Short fixed description of a code ("bad input", "det F <= 0", ...). */
const char *mpgm_code_str(int code);

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

/** The run context: first error, timers, counters. One per run. */
typedef struct mpgm_ctx {
  int code;           /**< first recorded error code, 0 if none   */
  char msg[1024];     /**< its message                            */
  const char *file;   /**< source file where it was recorded      */
  int line;           /**< source line                            */
  double t[MPGM_T_COUNT];     /**< accumulated wall time per timer [s] */
  double t_start[MPGM_T_COUNT]; /**< start stamp of a running timer   */
  long n_analyses;       /**< symbolic analyses                      */
  long n_factorizations; /**< numeric factorisations                 */
  long n_solves;         /**< solves                                 */
  long n_linear_iterations; /**< iterations of iterative linear solvers */
  long n_material_calls; /**< constitutive updates (per point)       */
  long n_body_force;     /**< body-force loops                       */
  long n_mass;           /**< inertia loops                          */
  long n_point_sorts;    /**< reorderings of the points in memory    */
  long n_radius_growths; /**< meshfree clouds: x1.25 growths of a search
                              radius that held fewer than min_nodes   */
  long n_cloud_enlargements; /**< meshfree clouds: next-nearest nodes
                              added after a failed evaluation          */
  long n_nodes_merged;   /**< GMM: node-steps left out for being closer
                              than mesh.min_node_distance to another  */
  long n_cold_restarts;  /**< meshfree: failed warm-started evaluations
                              (LME multiplier) retried from zero       */
} mpgm_ctx;

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

/** Read a whole file into *text (malloc'd, NUL-terminated; the caller
 *  frees it; binary content may hold NULs), its length in *len (may be
 *  NULL). Errors: MPGM_ERR_IO (cannot
 *  open or read, with the path), MPGM_ERR_NOMEM. */
int mpgm_read_file(mpgm_ctx *ctx, const char *path, char **text, size_t *len);

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
