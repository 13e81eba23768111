/* run.c -- the load/time loop of a scene, its output and summary.json. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_run.h"
#include "mpgm_scene_io.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "mpgm_output.h"

void *mpgm_effects_json(const mpgm_effects *fx) {
  cJSON *e = cJSON_CreateObject();
  cJSON_AddBoolToObject(e, "inertia", fx->inertia);
  cJSON_AddBoolToObject(e, "gravity", fx->gravity);
  cJSON_AddBoolToObject(e, "geometric_stiffness", fx->geometric);
  cJSON_AddBoolToObject(e, "configuration_update", fx->geometric);
  cJSON_AddBoolToObject(e, "plasticity", fx->plasticity);
  cJSON_AddBoolToObject(e, "prescribed_displacement", fx->prescribed);
  cJSON_AddBoolToObject(e, "contact", fx->contact);
  cJSON_AddBoolToObject(e, "contact_points", fx->contact_points);
  cJSON_AddBoolToObject(e, "initial_stress", fx->prestress);
  return e;
}

/* Processor time of this process so far (every thread, user + system). */
static double process_cpu(void) {
  struct rusage u;
  if (getrusage(RUSAGE_SELF, &u)) return NAN;
  return (double)(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * (double)(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

typedef struct run_state {
  const char *status;   /**< "completed" or "failed"            */
  const char *message;  /**< failure message or ""              */
  long failed_step;     /**< step that failed, -1 if none        */
  double wall;          /**< wall time of the run [s]            */
  double cpu;           /**< processor time of the run, every thread,
                             user + system [s]                   */
  cJSON *cuts;          /**< the first MAX_CUT_LOG step cuts     */
} run_state;

#define MAX_CUT_LOG 100

/* One rejected step for summary.json: step, end time (or load factor) and
 * step size tried, error code and message. */
static void cut_record(run_state *rs, long step, double t, double dt, int code, const char *why) {
  if (!rs->cuts) rs->cuts = cJSON_CreateArray();
  if (!rs->cuts || cJSON_GetArraySize(rs->cuts) >= MAX_CUT_LOG) return;
  cJSON *c = cJSON_CreateObject();
  if (!c) return;
  cJSON_AddNumberToObject(c, "step", (double)step);
  cJSON_AddNumberToObject(c, "t", t);
  cJSON_AddNumberToObject(c, "dt", dt);
  cJSON_AddNumberToObject(c, "code", code);
  cJSON_AddStringToObject(c, "reason", why);
  cJSON_AddItemToArray(rs->cuts, c);
}

static cJSON *summary_json(const mpgm_problem *pb, const mpgm_output *o, const run_state *rs) {
  const mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *s = pb->scene;
  cJSON *j = cJSON_CreateObject();
  cJSON_AddStringToObject(j, "status", rs->status);
  cJSON_AddStringToObject(j, "message", rs->message);
  if (rs->failed_step >= 0) cJSON_AddNumberToObject(j, "failed_step", (double)rs->failed_step);
  cJSON_AddStringToObject(j, "scene_file", s->file);
  cJSON_AddItemToObject(j, "scene", cJSON_Duplicate((const cJSON *)s->resolved, 1));
  cJSON_AddStringToObject(j, "method", mpgm_method_name(s->method));
  cJSON_AddStringToObject(j, "shape", s->shape->name);
  /* "auto" on its LU fallback still reports the backend it chose */
  cJSON_AddStringToObject(j, "solver", mpgm_solver_name(pb->solver));
  cJSON_AddNumberToObject(j, "solver_threads", s->threads);
  cJSON_AddNumberToObject(j, "threads", mpgm_pool_size(pb->pool));
  cJSON_AddItemToObject(j, "effects", (cJSON *)mpgm_effects_json(&pb->fx));
  cJSON *c = cJSON_AddObjectToObject(j, "counts");
  int ncells = 0;
  const int *cp, *cc, *ct;
  if (pb->fe->cells) pb->fe->cells((mpgm_problem *)pb, &ncells, &cp, &cc, &ct);
  cJSON_AddNumberToObject(c, "points", pb->pts.n);
  cJSON_AddNumberToObject(c, "probes", pb->pts.nprobe);
  cJSON_AddNumberToObject(c, "nodes", pb->nodes.n);
  cJSON_AddNumberToObject(c, "cells", ncells);
  cJSON_AddNumberToObject(c, "dofs", pb->nodes.ndof);
  cJSON_AddNumberToObject(c, "nnz", pb->K.nnz);
  cJSON_AddNumberToObject(c, "steps", (double)pb->step);
  cJSON_AddNumberToObject(c, "newton_iterations", (double)pb->newton_total);
  cJSON_AddNumberToObject(c, "analyses", (double)ctx->count[MPGM_C_ANALYSES]);
  cJSON_AddNumberToObject(c, "factorizations", (double)ctx->count[MPGM_C_FACTORIZATIONS]);
  cJSON_AddNumberToObject(c, "solves", (double)ctx->count[MPGM_C_SOLVES]);
  cJSON_AddNumberToObject(c, "material_updates", (double)ctx->count[MPGM_C_MATERIAL_CALLS]);
  cJSON_AddNumberToObject(c, "body_force_loops", (double)ctx->count[MPGM_C_BODY_FORCE]);
  cJSON_AddNumberToObject(c, "inertia_loops", (double)ctx->count[MPGM_C_MASS]);
  cJSON_AddNumberToObject(c, "point_sorts", (double)ctx->count[MPGM_C_POINT_SORTS]);
  cJSON_AddNumberToObject(c, "radius_growths", (double)ctx->count[MPGM_C_RADIUS_GROWTHS]);
  cJSON_AddNumberToObject(c, "cloud_enlargements", (double)ctx->count[MPGM_C_CLOUD_ENLARGEMENTS]);
  cJSON_AddNumberToObject(c, "shape_cold_restarts", (double)ctx->count[MPGM_C_COLD_RESTARTS]);
  cJSON_AddNumberToObject(c, "nodes_merged", (double)ctx->count[MPGM_C_NODES_MERGED]);
  cJSON_AddNumberToObject(c, "step_cuts", (double)pb->step_cuts);
  mpgm_solver_stats st = {0};
  const int have_stats = mpgm_solver_get_stats(pb->solver, &st) == 0;
  cJSON_AddNumberToObject(c, "solver_switches", (double)st.switches);
  cJSON_AddNumberToObject(c, "lu_fallback_steps", (double)st.fallback_steps);
  cJSON_AddNumberToObject(c, "contact_resolves", (double)pb->contact_rounds);
  if (pb->fx.contact_points) {
    cJSON_AddNumberToObject(c, "contact_points", pb->cp.n);
    cJSON_AddNumberToObject(c, "contact_points_held", pb->cp.held);
    cJSON_AddNumberToObject(c, "contact_point_holds", (double)pb->cp.holds);
    cJSON_AddNumberToObject(c, "contact_point_releases", (double)pb->cp.releases);
    cJSON_AddNumberToObject(c, "contact_points_unenforced", (double)pb->cp.unenforced);
  }
  cJSON_AddNumberToObject(c, "vtk_files", o->files);
  cJSON_AddNumberToObject(c, "clock_reads", (double)mpgm_wtime_reads());
  if (have_stats && ctx->count[MPGM_C_FACTORIZATIONS]) {
    cJSON_AddNumberToObject(c, "nnz_factor", st.nnz_factor);
    if (st.flops > 0) cJSON_AddNumberToObject(c, "factor_flops", st.flops);
    if (st.mem_peak > 0) cJSON_AddNumberToObject(c, "solver_memory_peak", st.mem_peak);
  }
  if (pb->solver && pb->solver->type->iterative)
    cJSON_AddNumberToObject(c, "linear_iterations", (double)ctx->count[MPGM_C_LINEAR_ITERATIONS]);
  if (o->matrices_dir[0]) cJSON_AddNumberToObject(c, "matrices_written", (double)o->mtx_written);
  cJSON *t = cJSON_AddObjectToObject(j, "time_s");
  for (int i = 0; i < MPGM_T_COUNT; i++)
    cJSON_AddNumberToObject(t, mpgm_timer_name(i), i == MPGM_T_TOTAL ? rs->wall : ctx->t[i]);
  /* processor time beside the wall time: below threads x wall, the run
   * waited for cores other jobs held, and its wall times are inflated */
  if (isfinite(rs->cpu)) cJSON_AddNumberToObject(j, "cpu_s", rs->cpu);
  cJSON *nw = cJSON_AddObjectToObject(j, "newton_last_step");
  cJSON_AddNumberToObject(nw, "iterations", pb->last.iterations);
  cJSON_AddNumberToObject(nw, "residual_initial", pb->last.res0);
  cJSON_AddNumberToObject(nw, "residual", pb->last.res);
  cJSON_AddNumberToObject(nw, "residual_relative", pb->last.res_rel);
  cJSON_AddNumberToObject(nw, "increment_relative", pb->last.du_rel);
  cJSON_AddItemToObject(nw, "residuals", cJSON_CreateDoubleArray(pb->last.hist, pb->last.nhist));
  /* metrics: final probe displacements and conservation checks */
  cJSON *m = cJSON_AddObjectToObject(j, "metrics");
  cJSON *pr = cJSON_AddObjectToObject(j, "probes");
  for (int k = 0; k < pb->pts.nprobe; k++) {
    const int p = pb->pts.n + k;
    char key[MPGM_NAME_LEN + 8];
    snprintf(key, sizeof key, "%s_ux", s->probes[k].name);
    cJSON_AddNumberToObject(m, key, pb->pts.u[2 * p]);
    snprintf(key, sizeof key, "%s_uy", s->probes[k].name);
    cJSON_AddNumberToObject(m, key, pb->pts.u[2 * p + 1]);
    cJSON *q = cJSON_AddObjectToObject(pr, s->probes[k].name);
    cJSON_AddItemToObject(q, "x", cJSON_CreateDoubleArray(s->probes[k].x, 2));
    cJSON_AddItemToObject(q, "u", cJSON_CreateDoubleArray(pb->pts.u + 2 * p, 2));
  }
  double mass = 0.0, vol = 0.0, xmax = -INFINITY, ymax = -INFINITY;
  for (int p = 0; p < pb->pts.n; p++) {
    mass += pb->pts.mass[p];
    vol += pb->pts.vol[p];
    xmax = fmax(xmax, pb->pts.x[2 * p]);
    ymax = fmax(ymax, pb->pts.x[2 * p + 1]);
  }
  cJSON_AddNumberToObject(m, "mass_total", mass);
  cJSON_AddNumberToObject(m, "volume_total", vol);
  if (pb->pts.n > 0) { /* the reach of the bodies: a collapse's runout and height */
    cJSON_AddNumberToObject(m, "runout", xmax);
    cJSON_AddNumberToObject(m, "height", ymax);
  }
  if (pb->fx.plasticity)
    cJSON_AddNumberToObject(m, "eps_p_max", mpgm_points_plastic_strain(&pb->pts, s->mats, NULL));
  (void)mpgm_reference_metrics(s, o->nrow, 2 + o->ncol, o->hist, m);
  if (rs->cuts) cJSON_AddItemReferenceToObject(j, "step_cuts", rs->cuts);
  cJSON *out = cJSON_AddObjectToObject(j, "output");
  cJSON_AddStringToObject(out, "dir", o->dir);
  return j;
}

static int write_summary(mpgm_problem *pb, mpgm_output *o, const run_state *rs) {
  cJSON *j = summary_json(pb, o, rs);
  char path[MPGM_PATH_LEN + 64];
  snprintf(path, sizeof path, "%s/summary.json", o->dir);
  int err = mpgm_write_json(pb->ctx, path, j);
  cJSON_Delete(j);
  return err;
}

/* One line on the state of the run (mpgm_log level PROGRESS). */
static void progress(const mpgm_problem *pb, double end, double t0) {
  if (!mpgm_log_wanted(pb->ctx, MPGM_LOG_PROGRESS)) return;
  const double el = mpgm_wtime() - t0, done = pb->t / end;
  const double eta = done > 0.0 ? el / done * (1.0 - done) : 0.0;
  const int st = pb->scene->analysis == MPGM_ANALYSIS_STATIC;
  mpgm_log(pb->ctx, MPGM_LOG_PROGRESS, "step %ld  %s = %.6g of %g  newton %d  |R|/ref = %.2e  cuts %ld  "
           "elapsed %.1fs  ETA %.1fs", pb->step, st ? "load" : "t", pb->t, end, pb->last.iterations,
           pb->last.res_rel, pb->step_cuts, el, eta);
}

/* Time split of the last step, for benchmarks (level INFO). */
static void log_split(const mpgm_problem *pb, const double *before) {
  mpgm_ctx *ctx = pb->ctx;
  const int it = pb->last.iterations > 0 ? pb->last.iterations : 1;
  char line[1024];
  int n = snprintf(line, sizeof line, "step %ld: %d Newton iterations; per iteration [ms]:", pb->step,
                   pb->last.iterations);
  for (int i = 0; i < MPGM_T_TOTAL && n > 0 && (size_t)n < sizeof line; i++)
    n += snprintf(line + n, sizeof line - (size_t)n, " %s %.3f", mpgm_timer_name(i),
                  1e3 * (ctx->t[i] - before[i]) / it);
  mpgm_log(ctx, MPGM_LOG_INFO, "%s", line);
}

int mpgm_run(mpgm_ctx *ctx, const mpgm_scene *s, const mpgm_frontend_ops *fe,
             const mpgm_run_opts *opts) {
  const double t0 = mpgm_wtime(), cpu0 = process_cpu();
  mpgm_problem *pb = NULL;
  MPGM_CALL(mpgm_problem_create(ctx, s, fe, &pb));
  mpgm_output o;
  int err = mpgm_output_open(ctx, &o, pb, opts && opts->out_dir ? opts->out_dir : s->out_dir);
  if (!err) err = mpgm_output_observe(ctx, &o, pb);
  if (err) {
    mpgm_output_close(&o);
    mpgm_problem_destroy(&pb);
    return err;
  }
  const int dyn = s->analysis == MPGM_ANALYSIS_DYNAMIC;
  /* the step: time step, or load increment (t then counts load, 0 to 1) */
  const double end = dyn ? s->t_end : 1.0, dt0 = dyn ? s->dt : 1.0 / s->load_steps;
  double dt_now = dt0; /* halved by a cut, doubled back after easy steps */
  int level = 0, easy = 0, nout = 0; /* nout: output.times passed */
  pb->dt = dt0;
  run_state rs = {.status = "completed", .message = "", .failed_step = -1};
  mpgm_timer_start(ctx, MPGM_T_OUTPUT);
  err = mpgm_output_probes_record(ctx, &o, pb);
  if (!err) err = mpgm_output_vtk(ctx, &o, pb);
  mpgm_timer_stop(ctx, MPGM_T_OUTPUT);
  char msg[sizeof ctx->msg + 192] = "";
  while (!err && pb->t < end - 1e-9 * dt0) {
    pb->dt = fmin(dt_now, end - pb->t);
    /* output.times: the step that reaches the next one ends on it (a step
     * within 1e-6 of it is stretched to it, not followed by a sliver) */
    while (nout < s->ntimes && s->times[nout] <= pb->t + 1e-9 * dt0) nout++;
    int on_time = 0;
    if (nout < s->ntimes && s->times[nout] - pb->t <= pb->dt * (1.0 + 1e-6)) {
      pb->dt = s->times[nout] - pb->t;
      on_time = 1;
    }
    double before[MPGM_T_COUNT];
    memcpy(before, ctx->t, sizeof before);
    const long k = pb->step + 1;
    const double ts = mpgm_wtime();
    err = mpgm_step(pb);
    if (err > 0 && level < s->max_cuts) {
      /* step control: a recoverable failure rejects the step (nothing was
       * committed) and retries it with half the step */
      mpgm_log(ctx, MPGM_LOG_WARNING, "step %ld (%s %.9g, %s %.3g) rejected: %s; retrying with %.3g "
               "(halving %d of at most %d, time.max_cuts)", k, dyn ? "t =" : "load factor", pb->t + pb->dt,
              dyn ? "dt" : "increment", pb->dt, ctx->msg, 0.5 * pb->dt, level + 1, s->max_cuts);
      cut_record(&rs, k, pb->t + pb->dt, pb->dt, err, ctx->msg);
      mpgm_err_clear(ctx);
      err = 0;
      dt_now = 0.5 * pb->dt;
      level++;
      easy = 0;
      pb->step_cuts++;
      pb->factor_valid = 0; /* the tangent of another step size */
      continue;
    }
    if (err) {
      snprintf(msg, sizeof msg, "step %ld (%s %.9g) failed: %s%s", k, dyn ? "t =" : "load factor",
               pb->t + pb->dt, ctx->msg,
               err > 0 && s->max_cuts > 0 ? " (at the smallest step allowed, the scene's halved "
                                            "time.max_cuts times)" : "");
      rs.status = "failed";
      rs.message = msg;
      rs.failed_step = k;
      break;
    }
    /* grow_after steps in a row that converged at the cut size double the
     * step back towards the scene's */
    if (level > 0 && ++easy >= s->grow_after) {
      dt_now = fmin(dt0, 2.0 * dt_now);
      level--;
      easy = 0;
    }
    if (opts && opts->per_iteration) log_split(pb, before);
    mpgm_timer_start(ctx, MPGM_T_OUTPUT);
    err = mpgm_output_probes_record(ctx, &o, pb);
    if (!err) err = mpgm_output_step_record(ctx, &o, pb, mpgm_wtime() - ts);
    if (!err && (pb->step % s->every == 0 || on_time || pb->t >= end - 1e-9 * dt0)) {
      err = mpgm_output_vtk(ctx, &o, pb);
      if (!err) err = mpgm_output_probes_write(ctx, &o, pb);
      if (!err) err = mpgm_output_steps_write(ctx, &o, pb);
    }
    mpgm_timer_stop(ctx, MPGM_T_OUTPUT);
    progress(pb, end, t0);
  }
  /* on failure keep the message of the failing step; still write what we have */
  mpgm_ctx keep = *ctx;
  mpgm_err_clear(ctx);
  rs.wall = mpgm_wtime() - t0;
  rs.cpu = process_cpu() - cpu0;
  int werr = mpgm_output_probes_write(ctx, &o, pb);
  if (!werr) werr = mpgm_output_steps_write(ctx, &o, pb);
  if (!werr) werr = write_summary(pb, &o, &rs);
  if (err) {
    const int code = keep.code ? keep.code : err;
    *ctx = keep;
    ctx->code = 0;
    mpgm_err_set(ctx, code, keep.file, keep.line, "%s", rs.failed_step >= 0 ? msg : keep.msg);
    err = code;
  } else {
    err = werr;
  }
  cJSON_Delete(rs.cuts);
  mpgm_output_close(&o);
  mpgm_problem_destroy(&pb);
  return err;
}
