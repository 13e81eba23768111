/* step.c -- one step of any method: the front end begins it (nodes,
 * connectivity, nodal history), the scene's time integrator solves and
 * commits it, the front end ends it (moves or forgets its nodes). */
#include "mpgm_core_impl.h"

int mpgm_begin_step(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  mpgm_fe_view v;
  mpgm_problem_view(pb, &v);
  pb->conn.tn = 0; /* the transpose and the runs of the last step's */
  pb->conn.rn = 0; /* lists are stale                                 */
  mpgm_timer_start(ctx, MPGM_T_SHAPE);
  const int err = pb->fe->begin_step(pb->fe_data, &v);
  mpgm_timer_stop(ctx, MPGM_T_SHAPE);
  pb->lambda = v.lambda;
  return err;
}

int mpgm_step(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  MPGM_CALL(mpgm_begin_step(pb));
  MPGM_CALL(pb->integ->step(pb->integ_data, pb));
  pb->t += pb->dt;
  pb->step++;
  if (!pb->fe->end_step) return 0;
  mpgm_fe_view v;
  mpgm_problem_view(pb, &v);
  mpgm_timer_start(ctx, MPGM_T_SHAPE);
  const int err = pb->fe->end_step(pb->fe_data, &v);
  mpgm_timer_stop(ctx, MPGM_T_SHAPE);
  return err;
}

int mpgm_problem_observe(mpgm_problem *pb, const mpgm_observer *obs) {
  MPGM_CHECK(pb->ctx, pb->nobs < MPGM_OBSERVERS_MAX, MPGM_ERR_INTERNAL,
             "more than %d observers of a problem", MPGM_OBSERVERS_MAX);
  pb->obs[pb->nobs++] = *obs;
  return 0;
}
