/* mpgm_base.c -- error table, context, clock (the readers of files: read.c). */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_base.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

const char *mpgm_point_str(const double x[MPGM_DIM], char buf[MPGM_POINT_STR]) {
#if MPGM_DIM == 2
  snprintf(buf, MPGM_POINT_STR, "(%g, %g)", x[0], x[1]);
#else
  snprintf(buf, MPGM_POINT_STR, "(%g, %g, %g)", x[0], x[1], x[2]);
#endif
  return buf;
}

const char *mpgm_code_str(int code) {
  switch (code) {
  case MPGM_OK: return "success";
  case MPGM_ERR_INPUT: return "bad input";
  case MPGM_ERR_IO: return "I/O error";
  case MPGM_ERR_NOMEM: return "out of memory";
  case MPGM_ERR_UNSUPPORTED: return "operation not supported";
  case MPGM_ERR_SOLVER: return "linear solver failure";
  case MPGM_ERR_INTERNAL: return "internal error";
  case MPGM_ERR_DOMAIN: return "point left the background grid";
  case MPGM_ERR_INTERRUPTED: return "interrupted";
  case MPGM_ERR_DIMENSION: return "a scene of the other dimension";
  case MPGM_ERR_JACOBIAN: return "det F <= 0 (inverted point or cell)";
  case MPGM_ERR_NOT_CONVERGED: return "Newton did not converge";
  case MPGM_ERR_DIVERGED: return "Newton diverged";
  case MPGM_ERR_NAN: return "NaN or Inf in residual or solution";
  case MPGM_ERR_SINGULAR: return "singular or indefinite matrix";
  case MPGM_ERR_RETURN_MAP: return "return mapping did not converge";
  case MPGM_ERR_SHAPE: return "shape function failure";
  case MPGM_ERR_LINEAR: return "iterative linear solver did not converge";
  default: return "unknown error";
  }
}

static const char *const timer_names[MPGM_T_COUNT] = {
    "shape", "search", "assembly", "analyse", "factor", "solve",
    "material", "body_force", "mass", "update", "output", "total"};

const char *mpgm_timer_name(int id) {
  return (id >= 0 && id < MPGM_T_COUNT) ? timer_names[id] : "?";
}

static const char *const counter_names[MPGM_C_COUNT] = {
    "analyses", "factorizations", "solves", "linear_iterations", "material_updates",
    "body_force_loops", "inertia_loops", "point_sorts", "radius_growths", "cloud_enlargements",
    "shape_cold_restarts", "nodes_merged", "surface_points_carried",
    "probes_carried", "node_motion_fallbacks", "domain_corners_clamped",
    "cpls_linear_nodes", "cpls_projected_nodes", "linear_not_converged",
    "factor_reuses", "patterns_kept", "kinetic_resets", "newton_relaxations",
    "newton_stagnations", "contact_low_rank", "line_searches", "bfgs_updates",
    "linear_fallbacks", "factor_renewals"};

const char *mpgm_counter_name(int id) {
  return (id >= 0 && id < MPGM_C_COUNT) ? counter_names[id] : "?";
}

void mpgm_ctx_init(mpgm_ctx *ctx) { memset(ctx, 0, sizeof(*ctx)); }

void mpgm_ctx_set_logger(mpgm_ctx *ctx, mpgm_log_fn fn, void *user, int level) {
  ctx->log = fn;
  ctx->log_user = user;
  ctx->log_level = level;
}

void mpgm_log(mpgm_ctx *ctx, int level, const char *fmt, ...) {
  if (!ctx || !mpgm_log_wanted(ctx, level)) return;
  char msg[2048];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  ctx->log(ctx->log_user, level, msg);
}

int mpgm_err_set(mpgm_ctx *ctx, int code, const char *file, int line,
                 const char *fmt, ...) {
  if (!ctx || ctx->code) return code;
  ctx->code = code;
  ctx->file = file;
  ctx->line = line;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(ctx->msg, sizeof(ctx->msg), fmt, ap);
  va_end(ap);
  return code;
}

void mpgm_err_clear(mpgm_ctx *ctx) {
  ctx->code = 0;
  ctx->msg[0] = '\0';
  ctx->file = NULL;
  ctx->line = 0;
}

/* clock reads of the process (every timer start and stop is one), for the
 * cost of the timers themselves (bench/timers) */
static long clock_reads;

long mpgm_wtime_reads(void) { return __atomic_load_n(&clock_reads, __ATOMIC_RELAXED); }

double mpgm_wtime(void) {
  struct timespec ts;
  __atomic_fetch_add(&clock_reads, 1, __ATOMIC_RELAXED);
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

const char *mpgm_version(void) {
#ifdef MPGM_VERSION_STRING
  return MPGM_VERSION_STRING;
#else
  return "unknown";
#endif
}

const char *mpgm_box_str(const double lo[MPGM_DIM], const double hi[MPGM_DIM], char buf[MPGM_BOX_STR]) {
#if MPGM_DIM == 2
  snprintf(buf, MPGM_BOX_STR, "[%g, %g] x [%g, %g]", lo[0], hi[0], lo[1], hi[1]);
#else
  snprintf(buf, MPGM_BOX_STR, "[%g, %g] x [%g, %g] x [%g, %g]", lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]);
#endif
  return buf;
}
