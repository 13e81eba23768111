/* run.c -- a scene run to the end with its outputs: the problem, the
 * results folder (a monitor of the core's run loop), summary.json. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_run.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "mpgm_checkpoint.h"
#include "mpgm_output.h"
#include "mpgm_scene_io.h"

void *mpgm_effects_json(const mpgm_effects *fx) {
  cJSON *e = cJSON_CreateObject();
  cJSON_AddBoolToObject(e, "inertia", fx->inertia);
  cJSON_AddBoolToObject(e, "gravity", fx->gravity);
  cJSON_AddBoolToObject(e, "tangent", fx->tangent);
  cJSON_AddBoolToObject(e, "geometric_stiffness", fx->geometric && fx->tangent);
  /* explicit schemes move the points under either kinematics */
  cJSON_AddBoolToObject(e, "configuration_update", fx->geometric || !fx->tangent);
  cJSON_AddBoolToObject(e, "plasticity", fx->plasticity);
  cJSON_AddBoolToObject(e, "prescribed_displacement", fx->prescribed);
  cJSON_AddBoolToObject(e, "contact", fx->contact);
  cJSON_AddBoolToObject(e, "contact_points", fx->contact_points);
  cJSON_AddBoolToObject(e, "initial_stress", fx->prestress);
  cJSON_AddBoolToObject(e, "manufactured_source", fx->manufactured);
  return e;
}

/* Processor time of this process so far (every thread, user + system). */
static double process_cpu(void) {
  struct rusage u;
  if (getrusage(RUSAGE_SELF, &u)) return NAN;
  return (double)(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * (double)(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/* How the run went, for summary.json. */
typedef struct run_state {
  const mpgm_run_result *res; /**< status, failure, cuts                */
  const char *status;   /**< "completed", "failed" (a step failed) or
                             "io_error" (the outputs could not be
                             written: the run stopped there)            */
  const char *message;  /**< why, "" when completed                    */
  long failed_step;     /**< the step that failed, or whose outputs
                             could not be written; -1 if none          */
  double wall;          /**< wall time of the run [s]                   */
  double cpu;           /**< processor time of the run, every thread,
                             user + system [s]                          */
} run_state;

/* The numbers of summary.json that are sums (or extremes) over the
 * material points and the work of every process: on one process its own.
 * A counter of work done per point or node counts every process's; one of
 * steps, loops and solves (each process does the same) is counted once. */
typedef struct run_totals {
  long points, nodes, dofs, points_min, points_max; /* the nodes and dofs
                  of every process (a shared node once per process) */
  long count[MPGM_C_COUNT];
  double mass, vol, xmax, ymax, eps_p, cpu;
} run_totals;

static int per_point(int c) {
  static const int sums[] = {MPGM_C_MATERIAL_CALLS, MPGM_C_POINT_SORTS, MPGM_C_RADIUS_GROWTHS,
                             MPGM_C_CLOUD_ENLARGEMENTS, MPGM_C_COLD_RESTARTS, MPGM_C_NODES_MERGED,
                             MPGM_C_SURFACE_CARRIED, MPGM_C_PROBES_CARRIED,
                             MPGM_C_NODE_MOTION_FALLBACKS, MPGM_C_DOMAIN_CLAMPS, MPGM_C_CPLS_LINEAR,
                             MPGM_C_CPLS_PROJECTED, MPGM_C_PATTERNS_KEPT};
  for (size_t i = 0; i < sizeof sums / sizeof *sums; i++)
    if (sums[i] == c) return 1;
  return 0;
}

/* Collective: every process calls it at the run's end. */
static int totals(mpgm_ctx *ctx, const mpgm_problem *pb, double cpu, run_totals *t) {
  const mpgm_scene *s = mpgm_problem_scene(pb);
  const mpgm_points *P = mpgm_problem_points(pb);
  mpgm_report r;
  mpgm_problem_report(pb, &r);
  memset(t, 0, sizeof *t);
  t->xmax = t->ymax = -INFINITY;
  /* height along the vertical of gravity in 3-D (a slab stands in y); y in plane strain */
  const int up = MPGM_DIM == 2 ? 1 : mpgm_scene_vertical(s);
  for (int p = 0; p < P->n; p++) {
    t->mass += P->mass[p];
    t->vol += P->vol[p];
    t->xmax = fmax(t->xmax, P->x[MPGM_DIM * p]);
    t->ymax = fmax(t->ymax, P->x[MPGM_DIM * p + up]);
  }
  t->eps_p = mpgm_problem_effects(pb)->plasticity ? mpgm_points_plastic_strain(P, s->mats, NULL) : 0.0;
  t->cpu = cpu;
  t->points = t->points_min = t->points_max = P->n;
  t->nodes = r.nodes, t->dofs = r.ndof;
  memcpy(t->count, ctx->count, sizeof t->count);
  if (mpgm_ctx_size(ctx) == 1) return 0;
  double sum[3] = {t->mass, t->vol, t->cpu}, max[4] = {t->xmax, t->ymax, t->eps_p, -(double)P->n};
  long lsum[3] = {t->points, t->nodes, t->dofs}, lmax[MPGM_C_COUNT + 1], lcount[MPGM_C_COUNT];
  for (int i = 0; i < MPGM_C_COUNT; i++) {
    lmax[i] = per_point(i) ? 0 : ctx->count[i];
    lcount[i] = per_point(i) ? ctx->count[i] : 0;
  }
  lmax[MPGM_C_COUNT] = P->n;
  MPGM_CALL(mpgm_allreduce(ctx, MPGM_REDUCE_SUM, sum, 3));
  MPGM_CALL(mpgm_allreduce(ctx, MPGM_REDUCE_MAX, max, 4));
  MPGM_CALL(mpgm_allreduce_long(ctx, MPGM_REDUCE_SUM, lsum, 3));
  MPGM_CALL(mpgm_allreduce_long(ctx, MPGM_REDUCE_SUM, lcount, MPGM_C_COUNT));
  MPGM_CALL(mpgm_allreduce_long(ctx, MPGM_REDUCE_MAX, lmax, MPGM_C_COUNT + 1));
  t->mass = sum[0], t->vol = sum[1], t->cpu = sum[2];
  t->xmax = max[0], t->ymax = max[1], t->eps_p = max[2];
  t->points_min = -(long)max[3], t->points_max = lmax[MPGM_C_COUNT];
  t->points = lsum[0], t->nodes = lsum[1], t->dofs = lsum[2];
  for (int i = 0; i < MPGM_C_COUNT; i++) t->count[i] = per_point(i) ? lcount[i] : lmax[i];
  return 0;
}

/* summary.json "counts": the run's sizes and the work it did. */
static void counts_json(cJSON *c, const mpgm_problem *pb, const mpgm_report *r, const mpgm_output *o,
                        const mpgm_ctx *ctx, const run_totals *t) {
  const mpgm_points *P = mpgm_problem_points(pb);
  cJSON_AddNumberToObject(c, "points", (double)t->points);
  cJSON_AddNumberToObject(c, "probes", P->nprobe);
  cJSON_AddNumberToObject(c, "nodes", (double)t->nodes);
  cJSON_AddNumberToObject(c, "cells", r->ncells);
  cJSON_AddNumberToObject(c, "dofs", (double)t->dofs);
  cJSON_AddNumberToObject(c, "nnz", r->nnz);
  cJSON_AddNumberToObject(c, "steps", (double)r->step);
  cJSON_AddNumberToObject(c, "newton_iterations", (double)r->newton_total);
  /* the work counters of the context, linear iterations apart (below) */
  for (int i = 0; i < MPGM_C_COUNT; i++)
    if (i != MPGM_C_LINEAR_ITERATIONS)
      cJSON_AddNumberToObject(c, mpgm_counter_name(i), (double)t->count[i]);
  cJSON_AddNumberToObject(c, "step_cuts", (double)r->step_cuts);
  cJSON_AddNumberToObject(c, "solver_switches", (double)r->solver_stats.switches);
  cJSON_AddNumberToObject(c, "lu_fallback_steps", (double)r->solver_stats.fallback_steps);
  cJSON_AddNumberToObject(c, "contact_resolves", (double)r->contact_resolves);
  if (mpgm_problem_effects(pb)->contact_points) {
    cJSON_AddNumberToObject(c, "contact_points", r->contact_points);
    cJSON_AddNumberToObject(c, "contact_points_held", r->contact_points_held);
    cJSON_AddNumberToObject(c, "contact_point_holds", (double)r->contact_point_holds);
    cJSON_AddNumberToObject(c, "contact_point_releases", (double)r->contact_point_releases);
    cJSON_AddNumberToObject(c, "contact_points_unenforced", (double)r->contact_points_unenforced);
  }
  cJSON_AddNumberToObject(c, "vtk_files", o->files);
  cJSON_AddNumberToObject(c, "clock_reads", (double)mpgm_wtime_reads());
  if (r->have_solver_stats && ctx->count[MPGM_C_FACTORIZATIONS]) {
    cJSON_AddNumberToObject(c, "nnz_factor", r->solver_stats.nnz_factor);
    if (r->solver_stats.flops > 0) cJSON_AddNumberToObject(c, "factor_flops", r->solver_stats.flops);
    if (r->solver_stats.mem_peak > 0)
      cJSON_AddNumberToObject(c, "solver_memory_peak", r->solver_stats.mem_peak);
    if (r->solver_stats.block_size > 0)
      cJSON_AddNumberToObject(c, "solver_block_size", r->solver_stats.block_size);
  }
  if (r->solver_iterative)
    cJSON_AddNumberToObject(c, "linear_iterations", (double)ctx->count[MPGM_C_LINEAR_ITERATIONS]);
  if (o->matrices_dir[0]) cJSON_AddNumberToObject(c, "matrices_written", (double)o->mtx_written);
  if (o->nproc > 1) { /* the balance of a run on many processes */
    cJSON *q = cJSON_AddObjectToObject(c, "processes");
    cJSON_AddNumberToObject(q, "count", o->nproc);
    cJSON_AddNumberToObject(q, "points_min", (double)t->points_min);
    cJSON_AddNumberToObject(q, "points_max", (double)t->points_max);
    cJSON_AddNumberToObject(q, "imbalance", t->points > 0 ? (double)t->points_max * o->nproc /
                                                                (double)t->points : 1.0);
  }
}

/* summary.json "metrics" and "probes": the final probe displacements, the
 * reach of the bodies, conservation checks, the reference's errors. A run
 * that did not complete (failed, interrupted, io_error) has them as
 * "metrics_at_stop" and "probes_at_stop" instead, with the time (or load
 * factor) "t" and the "step" of the last converged step they were taken
 * at (in the metrics, and in each probe): they are not a finished run's
 * numbers, and studies and plots, which read "metrics", do not take them
 * for one. */
static void metrics_json(cJSON *j, const mpgm_problem *pb, const mpgm_output *o, int complete,
                         const run_totals *t) {
  const mpgm_scene *s = mpgm_problem_scene(pb);
  const mpgm_points *P = mpgm_problem_points(pb);
  cJSON *m = cJSON_AddObjectToObject(j, complete ? "metrics" : "metrics_at_stop");
  cJSON *pr = cJSON_AddObjectToObject(j, complete ? "probes" : "probes_at_stop");
  if (!complete) {
    mpgm_report r;
    mpgm_problem_report(pb, &r);
    cJSON_AddNumberToObject(m, "t", r.t);
    cJSON_AddNumberToObject(m, "step", (double)r.step);
  }
  for (int k = 0; k < P->nprobe; k++) {
    const int p = P->n + k;
    char key[MPGM_NAME_LEN + 8];
    for (int c = 0; c < MPGM_DIM; c++) { /* NAME_ux, NAME_uy (, NAME_uz) */
      snprintf(key, sizeof key, "%s_u%c", s->probes[k].name, "xyz"[c]);
      cJSON_AddNumberToObject(m, key, P->u[MPGM_DIM * p + c]);
    }
    cJSON *q = cJSON_AddObjectToObject(pr, s->probes[k].name);
    cJSON_AddItemToObject(q, "x", cJSON_CreateDoubleArray(s->probes[k].x, MPGM_DIM));
    cJSON_AddItemToObject(q, "u", cJSON_CreateDoubleArray(P->u + MPGM_DIM * p, MPGM_DIM));
    if (!complete) {
      cJSON_AddItemToObject(q, "t", cJSON_Duplicate(cJSON_GetObjectItemCaseSensitive(m, "t"), 0));
      cJSON_AddItemToObject(q, "step", cJSON_Duplicate(cJSON_GetObjectItemCaseSensitive(m, "step"), 0));
    }
  }
  const double mass = t->mass;
  cJSON_AddNumberToObject(m, "mass_total", mass);
  cJSON_AddNumberToObject(m, "volume_total", t->vol);
  if (t->points > 0) { /* the reach of the bodies: a collapse's runout and height */
    cJSON_AddNumberToObject(m, "runout", t->xmax);
    cJSON_AddNumberToObject(m, "height", t->ymax);
  }
  if (mpgm_problem_effects(pb)->plasticity) cJSON_AddNumberToObject(m, "eps_p_max", t->eps_p);
#if MPGM_DIM == 2 /* the manufactured solutions are plane strain */
  double e[3];
  if (mpgm_problem_mms_errors(pb, e)) { /* eq 47 of Tran et al. 2019 */
    cJSON_AddNumberToObject(m, "mms_u_rms", e[0]);
    cJSON_AddNumberToObject(m, "mms_v_rms", e[1]);
    cJSON_AddNumberToObject(m, "mms_sigma_rms", e[2]);
    /* the points' against the grid's momentum, relative to sqrt(2 M K):
     * the momentum of the whole mass M at the points' RMS speed (a
     * vibration's net momentum is near zero) */
    double gap, kmax;
    mpgm_output_momentum_gap(o, &gap, &kmax);
    const double scale = sqrt(2.0 * mass * kmax);
    cJSON_AddNumberToObject(m, "momentum_gap", scale > 0.0 ? gap / scale : gap);
  }
#endif
  (void)mpgm_reference_metrics(s, o->nrow, 2 + o->ncol, o->hist, o->ref_acc, m);
}

/* summary.json "newton_last_step". */
static void newton_json(cJSON *j, const mpgm_newton_info *n) {
  cJSON *nw = cJSON_AddObjectToObject(j, "newton_last_step");
  cJSON_AddNumberToObject(nw, "iterations", n->iterations);
  cJSON_AddNumberToObject(nw, "residual_initial", n->res0);
  cJSON_AddNumberToObject(nw, "residual", n->res);
  cJSON_AddNumberToObject(nw, "residual_relative", n->res_rel);
  cJSON_AddNumberToObject(nw, "increment_relative", n->du_rel);
  cJSON_AddItemToObject(nw, "residuals", cJSON_CreateDoubleArray(n->hist, n->nhist));
}

/* summary.json "step_cuts": step, end time (or load factor) and step size
 * tried, error code and message of each rejected step recorded. */
static void cuts_json(cJSON *j, const mpgm_run_result *res) {
  if (!res->ncuts) return;
  cJSON *a = cJSON_AddArrayToObject(j, "step_cuts");
  for (int i = 0; a && i < res->ncuts; i++) {
    const mpgm_cut *c = &res->cuts[i];
    cJSON *e = cJSON_CreateObject();
    if (!e) return;
    cJSON_AddNumberToObject(e, "step", (double)c->step);
    cJSON_AddNumberToObject(e, "t", c->t);
    cJSON_AddNumberToObject(e, "dt", c->dt);
    cJSON_AddNumberToObject(e, "code", c->code);
    cJSON_AddStringToObject(e, "reason", c->reason);
    cJSON_AddItemToArray(a, e);
  }
}

static cJSON *summary_json(const mpgm_problem *pb, const mpgm_output *o, const run_state *rs,
                           const mpgm_ctx *ctx, const run_totals *tot) {
  const mpgm_scene *s = mpgm_problem_scene(pb);
  const mpgm_run_result *res = rs->res;
  mpgm_report r;
  mpgm_problem_report(pb, &r);
  cJSON *j = cJSON_CreateObject();
  cJSON_AddStringToObject(j, "status", rs->status);
  cJSON_AddStringToObject(j, "message", rs->message);
  if (rs->failed_step >= 0) cJSON_AddNumberToObject(j, "failed_step", (double)rs->failed_step);
  cJSON_AddStringToObject(j, "version", mpgm_version()); /* the code that made the results */
  cJSON_AddNumberToObject(j, "dimension", MPGM_DIM); /* 2: plane strain; 3: mpgm-3d's run */
  cJSON_AddStringToObject(j, "scene_file", s->file);
  cJSON_AddItemToObject(j, "scene", cJSON_Duplicate((const cJSON *)s->resolved, 1));
  cJSON_AddStringToObject(j, "method", s->frontend->name);
  cJSON_AddStringToObject(j, "shape", s->shape->name);
  /* "auto" on its LU fallback still reports the backend it chose */
  cJSON_AddStringToObject(j, "solver", r.solver);
  cJSON_AddNumberToObject(j, "solver_threads", s->threads);
  cJSON_AddNumberToObject(j, "threads", r.threads);
  cJSON_AddItemToObject(j, "effects", (cJSON *)mpgm_effects_json(mpgm_problem_effects(pb)));
  counts_json(cJSON_AddObjectToObject(j, "counts"), pb, &r, o, ctx, tot);
  cJSON *t = cJSON_AddObjectToObject(j, "time_s");
  for (int i = 0; i < MPGM_T_COUNT; i++)
    cJSON_AddNumberToObject(t, mpgm_timer_name(i), i == MPGM_T_TOTAL ? rs->wall : ctx->t[i]);
  /* processor time beside the wall time: below threads x wall, the run
   * waited for cores other jobs held, and its wall times are inflated */
  if (isfinite(tot->cpu)) cJSON_AddNumberToObject(j, "cpu_s", tot->cpu); /* every process's */
  newton_json(j, &r.last);
  metrics_json(j, pb, o, strcmp(rs->status, "completed") == 0, tot);
  cuts_json(j, res);
  cJSON *out = cJSON_AddObjectToObject(j, "output");
  cJSON_AddStringToObject(out, "dir", o->dir);
  return j;
}

/* Metric NAME of the metrics object m into the outcome, when m has it. */
static void outcome_metric(mpgm_run_outcome *oc, const cJSON *m, const char *name) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(m, name);
  if (!cJSON_IsNumber(v) || oc->nmetric >= MPGM_OUTCOME_METRICS) return;
  snprintf(oc->metric[oc->nmetric].name, sizeof oc->metric[0].name, "%.63s", name);
  oc->metric[oc->nmetric++].value = v->valuedouble;
}

/* The run's outcome from its summary j (mpgm_run_outcome says which
 * metrics are the main ones). */
static void outcome_fill(mpgm_run_outcome *oc, const mpgm_problem *pb, const mpgm_output *o,
                         const run_state *rs, const cJSON *j) {
  const mpgm_scene *s = mpgm_problem_scene(pb);
  mpgm_report r;
  mpgm_problem_report(pb, &r);
  memset(oc, 0, sizeof *oc);
  oc->set = 1;
  snprintf(oc->status, sizeof oc->status, "%s", rs->status);
  oc->steps = r.step;
  oc->step_cuts = r.step_cuts;
  oc->t = r.t;
  oc->wall = rs->wall;
  const cJSON *m = cJSON_GetObjectItemCaseSensitive(j, "metrics");
  if (!m) m = cJSON_GetObjectItemCaseSensitive(j, "metrics_at_stop");
  cJSON *ref = cJSON_CreateObject(); /* the reference's own metrics, by name */
  if (ref && mpgm_reference_metrics(s, o->nrow, 2 + o->ncol, o->hist, o->ref_acc, ref) == 0 && ref->child) {
    for (const cJSON *c = ref->child; c; c = c->next)
      if (strstr(c->string, "error")) outcome_metric(oc, m, c->string);
    for (const cJSON *c = ref->child; c && !oc->nmetric; c = c->next) outcome_metric(oc, m, c->string);
  }
  cJSON_Delete(ref);
  if (!oc->nmetric) {
    outcome_metric(oc, m, "mms_u_rms");
    outcome_metric(oc, m, "mms_sigma_rms");
  }
  const int probes = !oc->nmetric; /* no reference: the probes' final displacement */
  for (int k = 0; probes && k < s->nprobe && k < 2; k++) {
    char key[MPGM_NAME_LEN + 8];
    for (int c = 0; c < MPGM_DIM; c++) {
      snprintf(key, sizeof key, "%s_u%c", s->probes[k].name, "xyz"[c]);
      outcome_metric(oc, m, key);
    }
  }
  if (!oc->nmetric) {
    outcome_metric(oc, m, "runout");
    outcome_metric(oc, m, "height");
  }
  outcome_metric(oc, m, "eps_p_max");
}

/* summary.json, written by the first process of many (every process
 * calls it: the totals are collective). */
static int write_summary(mpgm_ctx *ctx, const mpgm_problem *pb, mpgm_output *o, const run_state *rs,
                         mpgm_run_outcome *oc) {
  run_totals tot;
  MPGM_CALL(totals(ctx, pb, rs->cpu, &tot));
  if (o->rank > 0) return 0;
  cJSON *j = summary_json(pb, o, rs, ctx, &tot);
  if (oc && j) outcome_fill(oc, pb, o, rs, j);
  char path[MPGM_PATH_LEN + 64];
  snprintf(path, sizeof path, "%s/summary.json", o->dir);
  int err = mpgm_write_json(ctx, path, j);
  cJSON_Delete(j);
  return err;
}

/* The output monitor: every converged step's probe and Newton records; VTK,
 * probes.csv and steps.csv when fields are due. */
typedef struct out_monitor {
  mpgm_ctx *ctx;
  mpgm_output *o;
  const mpgm_run_result *res; /**< the run's result so far (its cuts)    */
  double t_hist;              /**< wall clock of the last rewrite of the
                                   histories (probes.csv, steps.csv)     */
  const volatile sig_atomic_t *stop; /**< mpgm_run_opts.stop             */
  int last_fields;            /**< the last converged step (or the initial
                                   state) has its fields written          */
  int stopped;                /**< stop_here wrote the stop's records    */
} out_monitor;

/* The histories are rewritten whole (atomically) with a VTK output, but at
 * most once in this many seconds: rewriting them at every step of a long
 * run (output.every 1) costs a time that grows with the square of the
 * steps (an explicit run of 24,000 steps spent 40 ms a step on it). The
 * run's end writes them in any case. */
#define HIST_PERIOD 1.0

/* The stop asked for after this step (mpgm_run_opts.stop): its fields when
 * they were not due anyway, and a checkpoint to continue from; finish()
 * writes the histories and summary.json. After the last step the run is
 * complete and is not stopped. */
static int stop_here(out_monitor *m, const mpgm_problem *pb, int fields) {
  mpgm_ctx *ctx = m->ctx;
  const mpgm_scene *s = mpgm_problem_scene(pb);
  const int dyn = s->analysis != MPGM_ANALYSIS_STATIC;
  mpgm_report r;
  mpgm_problem_report(pb, &r);
  if (r.t >= (dyn ? s->t_end : 1.0) * (1.0 - 1e-9)) return 0;
  mpgm_timer_start(ctx, MPGM_T_OUTPUT);
  int err = fields ? 0 : mpgm_output_vtk(ctx, m->o, pb);
  const int many = mpgm_ctx_size(ctx) > 1; /* (no checkpoints on many processes yet) */
  if (!err && !many) err = mpgm_checkpoint_write(ctx, m->o->dir, pb, m->o, m->res);
  mpgm_timer_stop(ctx, MPGM_T_OUTPUT);
  if (err) return err;
  m->stopped = 1;
  if (many)
    MPGM_ERROR(ctx, MPGM_ERR_INTERRUPTED, "interrupted after step %ld (%s %.9g): its results are "
               "written; a run on many processes writes no checkpoint to continue from so far",
               r.step, dyn ? "t =" : "load factor", r.t);
  MPGM_ERROR(ctx, MPGM_ERR_INTERRUPTED, "interrupted after step %ld (%s %.9g): its results and a "
             "checkpoint are written; continue with: mpgm run --restart %s", r.step,
             dyn ? "t =" : "load factor", r.t, m->o->dir);
}

static int output_step(void *user, const mpgm_problem *pb, int fields, double wall) {
  out_monitor *m = user;
  mpgm_ctx *ctx = m->ctx;
  mpgm_timer_start(ctx, MPGM_T_OUTPUT);
  /* (each write on many processes agrees: the histories are the first's) */
  int err = mpgm_output_probes_record(ctx, m->o, pb);
  if (!err) err = mpgm_output_step_record(ctx, m->o, pb, wall);
  if (!err && fields) {
    err = mpgm_output_vtk(ctx, m->o, pb);
    const double now = mpgm_wtime();
    if (!err && now - m->t_hist >= HIST_PERIOD) {
      m->t_hist = now;
      err = mpgm_output_probes_write(ctx, m->o);
      if (!err) err = mpgm_output_steps_write(ctx, m->o);
      err = mpgm_agree(ctx, err);
    }
  }
  mpgm_timer_stop(ctx, MPGM_T_OUTPUT);
  if (!err) m->last_fields = fields;
  if (!err && m->stop && *m->stop) err = stop_here(m, pb, fields);
  return err;
}

/* A checkpoint into the results folder (output.checkpoint_every). */
static int output_checkpoint(void *user, const mpgm_problem *pb) {
  out_monitor *m = user;
  mpgm_timer_start(m->ctx, MPGM_T_OUTPUT);
  const int err = mpgm_checkpoint_write(m->ctx, m->o->dir, pb, m->o, m->res);
  mpgm_timer_stop(m->ctx, MPGM_T_OUTPUT);
  return err;
}

/* The run's end: probes.csv, steps.csv and summary.json are written
 * whatever happened; on failure the failing step's message is kept in ctx
 * (as "step K (t = T) failed: why" when a step failed) and its code
 * returned, else the code of the writes. A run whose outputs could not be
 * written says so in summary.json ("io_error", the step and the message),
 * when summary.json itself can still be written. */
static int finish(mpgm_ctx *ctx, mpgm_problem *pb, mpgm_output *o, run_state *rs, int err,
                  mpgm_run_outcome *oc) {
  const mpgm_run_result *res = rs->res;
  char io_msg[sizeof ctx->msg + 64] = "";
  rs->status = "completed";
  rs->message = "";
  rs->failed_step = -1;
  if (res->failed) {
    rs->status = "failed";
    rs->message = res->message;
    rs->failed_step = res->failed_step;
  } else if (err == MPGM_ERR_INTERRUPTED) { /* stopped between steps */
    snprintf(io_msg, sizeof io_msg, "%s", ctx->msg);
    rs->status = "interrupted";
    rs->message = io_msg;
  } else if (err) { /* the outputs of a converged step, or the start's */
    mpgm_report r;
    mpgm_problem_report(pb, &r);
    snprintf(io_msg, sizeof io_msg, "outputs of step %ld: %s", r.step, ctx->msg);
    rs->status = err == MPGM_ERR_IO ? "io_error" : "failed";
    rs->message = io_msg;
    rs->failed_step = r.step;
  }
  mpgm_ctx keep = *ctx;
  mpgm_err_clear(ctx);
  int werr = mpgm_output_probes_write(ctx, o);
  if (!werr) werr = mpgm_output_steps_write(ctx, o);
  /* summary.json even when the tables could not be written */
  const int serr = write_summary(ctx, pb, o, rs, oc);
  if (!werr) werr = serr;
  werr = mpgm_agree(ctx, werr); /* many processes: the first's writes */
  if (!err) return werr;
  const int code = keep.code ? keep.code : err;
  *ctx = keep;
  ctx->code = 0;
  mpgm_err_set(ctx, code, keep.file, keep.line, "%s", res->failed ? res->message : keep.msg);
  return code;
}

/* The results folder of a run: a new one, or, for a restart, the
 * checkpoint's state restored into pb, o and res, all of it read and
 * checked before the folder is touched (a checkpoint refused leaves every
 * file of the folder as it was). */
static int start(mpgm_ctx *ctx, mpgm_problem *pb, mpgm_output *o, const char *dir,
                 const mpgm_run_opts *opts, mpgm_run_result *res) {
  memset(o, 0, sizeof *o);
  MPGM_CHECK(ctx, !(opts && opts->restart) || mpgm_ctx_size(ctx) == 1, MPGM_ERR_INPUT,
             "--restart: a run on many processes continues from no checkpoint so far; run it "
             "without mpiexec, or with -n 1");
  if (opts && opts->restart) {
    MPGM_CALL(mpgm_checkpoint_restore(ctx, opts->restart, pb, o, dir, res));
    MPGM_CALL(mpgm_output_resume(ctx, o));
  } else {
    MPGM_CALL(mpgm_output_open(ctx, o, pb, dir));
  }
  return mpgm_output_observe(ctx, o, pb);
}

int mpgm_run(mpgm_ctx *ctx, const mpgm_scene *s, const mpgm_run_opts *opts) {
  const double t0 = mpgm_wtime(), cpu0 = process_cpu();
  mpgm_problem *pb = NULL;
  /* solver.petsc judged by PETSc before anything is written */
  MPGM_CALL(mpgm_scene_check_solver(ctx, s));
  MPGM_CALL(mpgm_problem_create(ctx, s, NULL, &pb));
  /* the set-up is done: from here a stop asked for leaves records */
  if (opts && opts->running) *opts->running = 1;
  mpgm_output o;
  mpgm_run_result res = {.failed_step = -1};
  int err = start(ctx, pb, &o, opts && opts->out_dir ? opts->out_dir : s->out_dir, opts, &res);
  if (err) { /* no results folder, or a checkpoint refused: nothing written */
    mpgm_run_result_free(&res);
    mpgm_output_close(&o);
    mpgm_problem_destroy(&pb);
    return err;
  }
  if (!(opts && opts->restart)) { /* the initial state */
    mpgm_timer_start(ctx, MPGM_T_OUTPUT);
    err = mpgm_output_probes_record(ctx, &o, pb);
    if (!err) err = mpgm_output_vtk(ctx, &o, pb);
    mpgm_timer_stop(ctx, MPGM_T_OUTPUT);
  }
  if (!err) {
    out_monitor m = {ctx, &o, &res, -HIST_PERIOD, opts ? opts->stop : NULL, 1, 0};
    const mpgm_monitor mon = {.user = &m, .step = output_step, .checkpoint = output_checkpoint};
    const mpgm_run_control rc = {.monitor = &mon, .time_split = opts && opts->per_iteration, .t0 = t0,
                                 .stop = m.stop};
    err = mpgm_problem_run(pb, &rc, &res);
    /* stopped before a step or in one (not by stop_here after a step): the
     * last converged step's fields, if not written, and a checkpoint */
    if (err == MPGM_ERR_INTERRUPTED && !m.stopped) {
      mpgm_err_clear(ctx);
      err = stop_here(&m, pb, m.last_fields);
    }
  }
  run_state rs = {.res = &res, .wall = mpgm_wtime() - t0, .cpu = process_cpu() - cpu0};
  err = finish(ctx, pb, &o, &rs, err, opts ? opts->outcome : NULL);
  mpgm_run_result_free(&res);
  mpgm_output_close(&o);
  mpgm_problem_destroy(&pb);
  return err;
}
