/* run.c -- the load/time loop of a problem with step control: a step that
 * fails recoverably is cut (retried with half the step), the step grows
 * back after easy steps, steps end on output.times; a monitor sees every
 * converged step, the logger hears cuts and progress. The run stops as
 * failed at time.max_steps, at a step its integrator refuses (an explicit
 * time.dt above the stability limit) and when an explicit run's energy
 * grows without work (energy.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core_impl.h"

void mpgm_run_result_free(mpgm_run_result *r) {
  free(r->cuts);
  r->cuts = NULL;
  r->ncuts = 0;
}

/* One rejected step for the record: step, end time (or load factor) and
 * step size tried, error code and message. */
static void cut_record(mpgm_run_result *r, long step, double t, double dt, int code, const char *why) {
  if (r->ncuts >= MPGM_CUTS_MAX) return;
  if (!r->cuts && !(r->cuts = calloc(MPGM_CUTS_MAX, sizeof *r->cuts))) return;
  mpgm_cut *c = &r->cuts[r->ncuts++];
  c->step = step;
  c->t = t;
  c->dt = dt;
  c->code = code;
  snprintf(c->reason, sizeof c->reason, "%s", why);
}

/* Where this call of the run loop started, for the progress line's ETA. */
typedef struct span_start {
  double wall, t; /* wall clock at the first step, time (or load) then */
  long step;
} span_start;

/* The steps and seconds of the loop before the first ETA: the first steps
 * (a factorisation, a contact search, a cold cache) are not the rest's. */
#define ETA_STEPS 5
#define ETA_SECONDS 2.0

/* One line on the state of the run (mpgm_log level PROGRESS). The ETA is
 * the loop's wall time per fraction of the span done since its start (a
 * restart's included), taken after ETA_STEPS steps or ETA_SECONDS seconds;
 * "ETA --" before. */
static void progress(const mpgm_problem *pb, double end, double t0, const span_start *st) {
  if (!mpgm_log_wanted(pb->ctx, MPGM_LOG_PROGRESS)) return;
  const double now = mpgm_wtime(), el = now - t0, loop = now - st->wall;
  const double done = end > st->t ? (pb->t - st->t) / (end - st->t) : 1.0;
  const int ready = done > 0.0 && (pb->step - st->step >= ETA_STEPS || loop >= ETA_SECONDS);
  char eta[32] = "ETA --";
  if (ready) snprintf(eta, sizeof eta, "ETA %.1fs", loop / done * (1.0 - done));
  const int stat = pb->scene->analysis == MPGM_ANALYSIS_STATIC;
  mpgm_log(pb->ctx, MPGM_LOG_PROGRESS, "step %ld  %s = %.6g of %g  newton %d  |R|/ref = %.2e  cuts %ld  "
           "elapsed %.1fs  %s", pb->step, stat ? "load" : "t", pb->t, end, pb->last.iterations,
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

void mpgm_run_span(const mpgm_scene *s, double *end, double *dt0) {
  const int dyn = s->analysis != MPGM_ANALYSIS_STATIC;
  *end = dyn ? s->t_end : 1.0;
  /* the step: time step, or load increment (t then counts load, 0 to 1);
   * an explicit run without time.dt takes each step from the CFL limit */
  *dt0 = !dyn ? 1.0 / s->load_steps : s->dt > 0.0 ? s->dt : s->t_end;
}

/* The next step's size; 1 when it ends on an output time, -1 when the
 * integrator refuses the step (its dt_limit NAN: the reason in the
 * context); the integrator's limit in *limit. */
static int next_dt(mpgm_problem *pb, mpgm_stepper *sp, double *limit) {
  const mpgm_scene *s = pb->scene;
  *limit = pb->integ->dt_limit ? pb->integ->dt_limit(pb->integ_data, pb) : INFINITY;
  if (isnan(*limit)) return -1;
  pb->dt = fmin(fmin(sp->dt_now, *limit), sp->end - pb->t);
  /* output.times: the step that reaches the next one ends on it (a step
   * within 1e-6 of it is stretched to it, not followed by a sliver) */
  while (sp->nout < s->ntimes && s->times[sp->nout] <= pb->t + 1e-9 * sp->dt0) sp->nout++;
  if (sp->nout < s->ntimes && s->times[sp->nout] - pb->t <= pb->dt * (1.0 + 1e-6)) {
    pb->dt = s->times[sp->nout] - pb->t;
    return 1;
  }
  return 0;
}

/* The mark of a failure made on purpose (mpgm_fault), "" otherwise. */
static const char *made(const mpgm_ctx *ctx, long k, int err) {
  return mpgm_fault_due(ctx, err, k) ? " [made on purpose: MPGM_TEST_FAULT]" : "";
}

/* A recoverable failure of step k rejects it (nothing was committed): cut
 * the step in half, log and record it. */
static void cut(mpgm_problem *pb, mpgm_stepper *sp, long k, int err, mpgm_run_result *res) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *s = pb->scene;
  const int dyn = s->analysis != MPGM_ANALYSIS_STATIC;
  mpgm_log(ctx, MPGM_LOG_WARNING, "step %ld (%s %.9g, %s %.3g) rejected: %s%s; retrying with %.3g "
           "(halving %d of at most %d, time.max_cuts)", k, dyn ? "t =" : "load factor", pb->t + pb->dt,
           dyn ? "dt" : "increment", pb->dt, ctx->msg, made(ctx, k, err), 0.5 * pb->dt, sp->level + 1,
           s->max_cuts);
  cut_record(res, k, pb->t + pb->dt, pb->dt, err, ctx->msg);
  if (k == ctx->fault.step && err == ctx->fault.code) ctx->fault.fired++; /* tests */
  mpgm_err_clear(ctx);
  sp->dt_now = 0.5 * pb->dt;
  sp->level++;
  sp->easy = 0;
  /* time.grow_backoff: the size it grew to failed at once, so wait twice
   * as long before the next try (capped: a wait of 2^20 steps is never) */
  if (sp->grown && s->grow_backoff) sp->wait = sp->wait < (1 << 20) ? 2 * sp->wait : sp->wait;
  sp->grown = 0;
  pb->step_cuts++;
  if (pb->ls) pb->ls->factor_valid = 0; /* the tangent of another step size */
}

/* The run failed for good at step k, at t, for the reason in the context
 * and the note after it: the run's failure message. */
static void fail_at(mpgm_problem *pb, long k, double t, const char *note, mpgm_run_result *res) {
  snprintf(res->message, sizeof res->message, "step %ld (%s %.9g) failed: %s%s", k,
           pb->scene->analysis != MPGM_ANALYSIS_STATIC ? "t =" : "load factor", t, pb->ctx->msg, note);
  res->failed = 1;
  res->failed_step = k;
}

/* Step k failed for good (its step cut as far as the scene allows). */
static void failed(mpgm_problem *pb, long k, int err, mpgm_run_result *res) {
  char note[160];
  snprintf(note, sizeof note, "%s%s", made(pb->ctx, k, err),
           err > 0 && pb->scene->max_cuts > 0 ? " (at the smallest step allowed, the scene's halved "
                                                "time.max_cuts times)" : "");
  fail_at(pb, k, pb->t + pb->dt, note, res);
}

/* The run stopped at step k for good by one of its bounds (the reason in
 * the context) at t: the step was not taken (t its start), or was taken
 * and is not kept (t its end: the energy balance). */
static void stopped(mpgm_problem *pb, long k, double t, mpgm_run_result *res) {
  fail_at(pb, k, t, "", res);
}

/* Before step k: time.max_steps, which it may not pass before the end,
 * and, at the first step taken from the CFL condition, the steps its
 * limit predicts to the end (a run of 1e150 steps stops at once rather
 * than at step time.max_steps). 0, or MPGM_ERR_NOT_CONVERGED with the
 * reason in the context. */
static int bounds(mpgm_problem *pb, const mpgm_stepper *sp, long k, double limit) {
  const mpgm_scene *s = pb->scene;
  const int dyn = s->analysis != MPGM_ANALYSIS_STATIC;
  const char *end = dyn ? "time.end" : "the full load";
  if (pb->step >= s->max_steps)
    MPGM_ERROR(pb->ctx, MPGM_ERR_NOT_CONVERGED, "time.max_steps = %d steps done before %s (%s %.9g "
               "of %g, the step now %.3g): a larger time.max_steps, or larger steps%s",
               s->max_steps, end, dyn ? "t =" : "load factor", pb->t, sp->end, pb->dt,
               dyn ? " (time.dt, time.cfl)" : " (fewer time.load_steps, fewer cuts)");
  const double left = (sp->end - pb->t) / limit;
  if (k == 1 && s->analysis == MPGM_ANALYSIS_EXPLICIT && !(s->dt > 0.0) && left > s->max_steps)
    MPGM_ERROR(pb->ctx, MPGM_ERR_NOT_CONVERGED, "the first step's CFL limit dt = %.3g s (time.cfl "
               "%g, the fastest wave or point of the start) makes about %.3g steps to time.end = "
               "%g s, above time.max_steps = %d: a coarser mesh.h, a larger time.cfl or time."
               "max_steps, or a material with slower waves", limit, s->cfl, left, s->t_end,
               s->max_steps);
  return 0;
}

/* After a converged step: the monitor's outputs, and a checkpoint every
 * output.checkpoint_every steps (then what a step rebuilds is dropped, as
 * a restart from it must: the runs with and without a stop continue
 * alike). */
static int after_step(mpgm_problem *pb, const mpgm_run_control *rc, int on_time, double wall) {
  const mpgm_scene *s = pb->scene;
  const mpgm_stepper *sp = &pb->sp;
  const int last = pb->t >= sp->end - 1e-9 * sp->dt0;
  const int fields = pb->step % s->every == 0 || on_time || last;
  if (rc->monitor && rc->monitor->step) MPGM_CALL(rc->monitor->step(rc->monitor->user, pb, fields, wall));
  if (s->checkpoint_every > 0 && pb->step % s->checkpoint_every == 0 && !last && rc->monitor &&
      rc->monitor->checkpoint) {
    MPGM_CALL(rc->monitor->checkpoint(rc->monitor->user, pb));
    mpgm_problem_drop_rebuilt(pb);
  }
  return 0;
}

/* A stop asked for (rc->stop), on many processes by any of them: all
 * stop before the same step. */
static int stop_asked(mpgm_problem *pb, const mpgm_run_control *rc) {
  long stop = rc->stop && *rc->stop;
  if (mpgm_ctx_size(pb->ctx) > 1 && mpgm_allreduce_long(pb->ctx, MPGM_REDUCE_MAX, &stop, 1)) return 1;
  return stop != 0;
}

int mpgm_problem_run(mpgm_problem *pb, const mpgm_run_control *rc, mpgm_run_result *res) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *s = pb->scene;
  mpgm_stepper *sp = &pb->sp;
  if (!pb->resumed) { /* a restored problem continues its result and steps */
    memset(res, 0, sizeof *res);
    res->failed_step = -1;
    double end, dt0;
    mpgm_run_span(s, &end, &dt0);
    *sp = (mpgm_stepper){.end = end, .dt0 = dt0, .wait = s->grow_after};
    sp->dt_now = sp->dt0;
    pb->dt = sp->dt0;
  }
  int err = 0;
  pb->stop = rc->stop;
  const span_start st = {mpgm_log_wanted(ctx, MPGM_LOG_PROGRESS) ? mpgm_wtime() : 0.0, pb->t, pb->step};
  while (!err && pb->t < sp->end - 1e-9 * sp->dt0) {
    if (stop_asked(pb, rc)) { /* asked for before this step */
      err = mpgm_err_set(ctx, MPGM_ERR_INTERRUPTED, __FILE__, __LINE__, "stop asked for before step %ld",
                         pb->step + 1);
      break;
    }
    const long k = pb->step + 1;
    double limit;
    const int on_time = next_dt(pb, sp, &limit);
    if (on_time < 0 || (err = bounds(pb, sp, k, limit))) { /* the step is not taken */
      err = err ? err : ctx->code ? ctx->code : MPGM_ERR_INTERNAL;
      stopped(pb, k, pb->t, res);
      break;
    }
    double before[MPGM_T_COUNT];
    memcpy(before, ctx->t, sizeof before);
    long count[MPGM_C_COUNT];
    memcpy(count, ctx->count, sizeof count);
    const long rounds = pb->contact_rounds;
    const mpgm_newton_info last = pb->last;
    const double ts = mpgm_wtime();
    err = mpgm_agree(ctx, mpgm_step(pb)); /* many processes: cut or stop on every one */
    if (err == MPGM_ERR_INTERRUPTED) { /* abandoned: its work is not counted */
      memcpy(ctx->count, count, sizeof count);
      pb->contact_rounds = rounds;
      pb->last = last;
      break;
    }
    if (err > 0 && sp->level < s->max_cuts) {
      cut(pb, sp, k, err, res);
      err = 0;
      continue;
    }
    if (err) {
      failed(pb, k, err, res);
      break;
    }
    /* grow_after steps in a row that converged at the cut size (more
     * after grown steps that failed, time.grow_backoff) double the step
     * back towards the scene's; a grown step that converges resets the
     * wait */
    if (sp->grown) sp->wait = s->grow_after;
    sp->grown = 0;
    if (sp->level > 0 && ++sp->easy >= sp->wait) {
      sp->dt_now = fmin(sp->dt0, 2.0 * sp->dt_now);
      sp->level--;
      sp->easy = 0;
      sp->grown = 1;
    }
    /* an explicit run whose energy grew without work: diverged, stopped */
    if (!pb->integ->implicit && (err = mpgm_energy_guard(pb))) {
      stopped(pb, k, pb->t, res);
      break;
    }
    if (rc->time_split) log_split(pb, before);
    err = after_step(pb, rc, on_time, mpgm_wtime() - ts);
    progress(pb, sp->end, rc->t0, &st);
  }
  pb->stop = NULL;
  return err;
}
