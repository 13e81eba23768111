/* implicit.c -- the implicit Newmark integrator (Algorithms 1 and 2 of
 * Iaconeta et al. 2017, phase b, shared by every front end; static
 * analysis is the same without inertia): predictor, Newton on R and
 * K = K_mat + K_geo (+ K_dyn), the contact active set, Newmark corrector
 * and commit of points and nodes (docs/theory.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core_impl.h"


/* Commit a converged step: points (material and tracers) and nodes. */
static void commit(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  mpgm_timer_start(ctx, MPGM_T_UPDATE);
  mpgm_points *P = &pb->pts;
  mpgm_nodes *nd = &pb->nodes;
  const mpgm_conn *C = &pb->conn;
  const int move = pb->fx.geometric, inertia = pb->fx.inertia;
  const int newmark_pv = pb->fe->point_velocity == MPGM_PV_NEWMARK;
  const int m = P->n + P->nprobe + P->nsurf;
  /* work of gravity (dynamic), at its value in the middle of the step */
  const double gf = inertia ? mpgm_gravity_factor(pb, pb->t + 0.5 * pb->dt) : 0.0;
  double g[MPGM_DIM];
  for (int c = 0; c < MPGM_DIM; c++) g[c] = gf * pb->scene->gravity[c];
  double wext = 0.0;
  /* a manufactured body force's work, the same */
  const double *b = inertia ? MPGM_MMS_FORCES(pb, pb->t + 0.5 * pb->dt) : NULL;
  for (int p = 0; p < m; p++) {
    double d[MPGM_DIM] = {0}, v[MPGM_DIM] = {0}, a[MPGM_DIM] = {0};
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      const double N = C->N[k];
      const double *du = nd->du + MPGM_DIM * I;
      for (int c = 0; c < MPGM_DIM; c++) d[c] += N * du[c];
      if (inertia) {
        const double *vn = nd->v_new + MPGM_DIM * I, *an = nd->a_new + MPGM_DIM * I;
        for (int c = 0; c < MPGM_DIM; c++) v[c] += N * vn[c];
        for (int c = 0; c < MPGM_DIM; c++) a[c] += N * an[c];
      }
    }
    double gd = g[0] * d[0], bd = b && p < P->n ? b[MPGM_DIM * p] * d[0] : 0.0;
    for (int c = 1; c < MPGM_DIM; c++) {
      gd += g[c] * d[c];
      if (b && p < P->n) bd += b[MPGM_DIM * p + c] * d[c];
    }
    if (p < P->n) wext += P->mass[p] * gd;
    if (p < P->n && b) wext += P->mass[p] * bd;
    double *u = P->u + MPGM_DIM * p, *x = P->x + MPGM_DIM * p;
    double *vp = P->v + MPGM_DIM * p, *ap = P->a + MPGM_DIM * p;
    for (int c = 0; c < MPGM_DIM; c++) u[c] += d[c];
    if (move)
      for (int c = 0; c < MPGM_DIM; c++) x[c] += d[c];
    if (inertia && newmark_pv) { /* eq (48): trapezoidal in the particle */
      for (int c = 0; c < MPGM_DIM; c++) vp[c] += 0.5 * pb->dt * (ap[c] + a[c]);
      for (int c = 0; c < MPGM_DIM; c++) ap[c] = a[c];
    } else if (inertia) {
      for (int c = 0; c < MPGM_DIM; c++) vp[c] = v[c], ap[c] = a[c];
    }
  }
  if (inertia) {
    pb->work_ext += wext;
    mpgm_work_internal(pb);
  }
  memcpy(P->F, P->F_t, sizeof(double) * MPGM_TENSOR * (size_t)P->n);
  memcpy(P->sigma, P->sigma_t, sizeof(double) * MPGM_NSTRESS * (size_t)P->n);
  memcpy(P->vol, P->vol_t, sizeof(double) * (size_t)P->n);
  if (P->nstate) memcpy(P->state, P->state_t, sizeof(double) * (size_t)P->nstate * P->n);
  for (int i = 0; i < MPGM_DIM * nd->n; i++) {
    nd->u[i] += nd->du[i];
    if (move) nd->x[i] += nd->du[i];
    if (inertia) {
      nd->v[i] = nd->v_new[i];
      nd->a[i] = nd->a_new[i];
    }
  }
  mpgm_timer_stop(ctx, MPGM_T_UPDATE);
}

/* Newton on the step from the predictor (42) to convergence; warm: start
 * from the current increments (a re-solve after the contact set changed).
 * Returns 0 or an error code; *again = the contact update's mask when it
 * stopped early because the contact set changed on the way (solve the step
 * again). */
/* A stop asked for (a signal, mpgm_run_control.stop): the step is
 * abandoned here, before the next assembly or factorisation, rather than
 * after its last iteration, which may be minutes away. MPGM_TEST_FAULT
 * interrupt:STEP asks for one at the first iteration of STEP (tests). */
static int stop_asked(mpgm_problem *pb, const mpgm_newton *nt) {
  if ((pb->stop && *pb->stop) || (nt->it == 1 && mpgm_fault_due(pb->ctx, MPGM_ERR_INTERRUPTED, pb->step + 1)))
    MPGM_ERROR(pb->ctx, MPGM_ERR_INTERRUPTED, "stop asked for in step %ld at its Newton iteration %d",
               pb->step + 1, nt->it);
  return 0;
}

static int newton(mpgm_problem *pb, int warm, int *again) {
  const mpgm_scene *sc = pb->scene;
  const int contact = pb->fx.contact || pb->fx.contact_points;
  mpgm_newton nt;
  MPGM_CALL(mpgm_newton_init(pb, &nt, warm));
  for (int checked = 0;;) {
    MPGM_CALL(stop_asked(pb, &nt));
    MPGM_CALL(mpgm_newton_residual(pb, &nt));
    /* contact: check the active set once, as soon as the residual is below
     * contact_check of the reference, rather than only at convergence: a
     * wrong set is then not iterated to full accuracy first. The converged
     * state is checked again by the step. */
    if (contact && !checked && nt.it > 0 && !pb->ls->lift && nt.res <= sc->contact_check * nt.ref) {
      checked = 1;
#if MPGM_DIM == 2 /* contact is plane strain (MPGM_MMS_FORCES) */
      const int changed = mpgm_contact_update(pb);
#else
      const int changed = 0;
#endif
      if (changed) {
        pb->last.iterations = nt.it;
        *again = changed;
        return 0;
      }
    }
    int done;
    MPGM_CALL(mpgm_newton_test(pb, &nt, &done));
    if (done) return 0;
    MPGM_CALL(stop_asked(pb, &nt));
    MPGM_CALL(mpgm_newton_iterate(pb, &nt));
  }
}

/* The nodal mass of the lumped (row-sum) mass matrix into mI (MPGM_DIM per
 * node, the first of each node's used) and a = R / m into delta. */
static void lumped_acceleration(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  const mpgm_nodes *nd = &pb->nodes;
  const mpgm_conn *C = &pb->conn;
  const mpgm_points *P = &pb->pts;
  double *mI = ls->react; /* scratch, MPGM_DIM per node */
  memset(mI, 0, sizeof(double) * MPGM_DIM * (size_t)nd->n);
  for (int p = 0; p < P->n; p++)
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++)
      mI[MPGM_DIM * C->node[k]] += P->mass[p] * C->N[k];
  for (int i = 0; i < MPGM_DIM * nd->n; i++)
    if (nd->dof[i] >= 0) {
      const double mi = mI[MPGM_DIM * (i / MPGM_DIM)];
      ls->delta[nd->dof[i]] = mi > 0.0 ? ls->R[nd->dof[i]] / mi : 0.0;
    }
}

/* time.initial_acceleration = equilibrium: before the first step of a
 * dynamic run, the nodal acceleration that satisfies the equation of
 * motion at t = 0, M a_0 = f_ext - f_int(sigma_0), with the consistent mass
 * M of the material points (Newmark's a_n of the first step; starting from
 * a_0 = 0 instead makes the velocity lag a_0 dt / 2 for the whole run).
 * Held contact and fixed components get a_0 = 0. Should M be singular
 * (nodes on too few points), the row-sum (lumped) mass is used. MPM's
 * particles take a_p = sum N_I a_0I, the a_p^n of their update (48). */
static int initial_acceleration(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  mpgm_nodes *nd = &pb->nodes;
  const mpgm_conn *C = &pb->conn;
  mpgm_points *P = &pb->pts;
  memset(nd->du, 0, sizeof(double) * MPGM_DIM * (size_t)nd->n);
  MPGM_CALL(mpgm_body_force(pb, 0.0)); /* the first step starts at t = 0 */
  MPGM_CALL(mpgm_eval_points(pb, 1));
  MPGM_CALL(mpgm_assemble_mass(pb));
  MPGM_CALL(mpgm_problem_analyse(pb));
  ls->factor_valid = 0; /* the factorisation is M's, not the tangent's */
  /* a composite's part in use, without its fallback: Cholesky refusing M
   * means M is singular, and the lumped mass is used */
  mpgm_solver *ms = mpgm_solver_part(ls->solver);
  const int err = mpgm_solver_factor(ms, ctx, &ls->K);
  if (!err) {
    MPGM_CALL(mpgm_solver_solve(ms, ctx, ls->R, ls->delta));
  } else if (err == MPGM_ERR_SINGULAR) {
    mpgm_err_clear(ctx);
    lumped_acceleration(pb);
  } else {
    return err;
  }
  for (int i = 0; i < MPGM_DIM * nd->n; i++) {
    const int e = nd->dof[i];
    nd->a[i] = e >= 0 && !nd->fix[i] ? ls->delta[e] : 0.0;
    if (!isfinite(nd->a[i]))
      MPGM_ERROR(ctx, MPGM_ERR_NAN, "initial acceleration: not finite at node %d", i / MPGM_DIM);
  }
  if (pb->fe->point_velocity == MPGM_PV_NEWMARK)
    for (int p = 0; p < P->n + P->nprobe + P->nsurf; p++) {
      double a[MPGM_DIM] = {0};
      for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++)
        for (int c = 0; c < MPGM_DIM; c++) a[c] += C->N[k] * nd->a[MPGM_DIM * C->node[k] + c];
      for (int c = 0; c < MPGM_DIM; c++) P->a[MPGM_DIM * p + c] = a[c];
    }
  return MPGM_OK;
}

/* The start of the step's solve: new maps or pattern when the front end
 * changed the connectivity, contact flips cleared, the solver and the
 * observers told. *rebuild: the pattern must be rebuilt. */
static int begin_solve(mpgm_problem *pb, int *rebuild) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  *rebuild = pb->conn.version != ls->pattern_version;
  if (!*rebuild && pb->conn.map_version != ls->map_version) MPGM_CALL(mpgm_scatter_build(pb));
  if (pb->fx.contact) memset(ls->cflip, 0, (size_t)pb->nodes.n);
  if (pb->fx.contact_points) memset(pb->cp.flip, 0, (size_t)pb->cp.n);
  int kept; /* a composite solver may change its part at a new step */
  MPGM_CALL(mpgm_solver_step(ls->solver, ctx, &kept));
  if (!kept) ls->factor_valid = 0;
  for (int i = 0; i < pb->nobs; i++) /* a retried (cut) step starts afresh */
    if (pb->obs[i].step_begin) MPGM_CALL(pb->obs[i].step_begin(pb->obs[i].user, ctx, pb->step + 1));
  return 0;
}

/* Solve the step (the front end has begun it) and commit it: rounds of
 * Newton until the contact active set settles. On a recoverable failure
 * nothing is committed. */
static int implicit_step(void *self, mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  (void)self;
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *sc = pb->scene;
  mpgm_nodes *nd = &pb->nodes;
  int rebuild, its = 0, ndof_step = nd->ndof;
  MPGM_CALL(begin_solve(pb, &rebuild));
  for (int round = 0;; round++) {
    if (rebuild) {
      mpgm_nodes_number(nd);
      MPGM_CHECK(ctx, nd->ndof > 0, MPGM_ERR_INPUT,
                 "%s: boundaries: every degree of freedom of the step is fixed; nothing to solve",
                 sc->file);
      MPGM_CALL(mpgm_pattern_build(pb));
      rebuild = 0;
    }
    /* the step's numbering is fixed once it starts: f_ext (computed once
     * per step) and the increments of a re-solve are indexed by it */
    if (round == 0) ndof_step = nd->ndof;
    if (round == 0 && pb->step == 0 && pb->fx.inertia && sc->initial_accel)
      MPGM_CALL(initial_acceleration(pb));
    MPGM_CHECK(ctx, nd->ndof == ndof_step, MPGM_ERR_INTERNAL,
               "step %ld: equations renumbered within the step (%d -> %d)", pb->step + 1, ndof_step,
               nd->ndof);
    /* a recoverable failure of Newton is the step's failure (the run loop
     * may cut the step); only a contact change solves the step again */
    int early = 0;
    MPGM_CALL(newton(pb, round > 0, &early));
    its += pb->last.iterations;
#if MPGM_DIM == 2
    const int changed = early ? early : pb->fx.contact || pb->fx.contact_points ? mpgm_contact_update(pb) : 0;
#else /* contact is plane strain (MPGM_MMS_FORCES) */
    const int changed = early;
#endif
    if (!changed) break;
    MPGM_CHECK(ctx, round < 50, MPGM_ERR_NOT_CONVERGED,
               "the contact active set did not settle in %d solves of the step", round + 1);
    pb->contact_rounds++;
    /* contact nodes keep their equations whatever their state: the
     * pattern and its analysis stand, only the maps (which leave out held
     * components) and the factorisation change. Surface points change
     * values only, but the factorisation without a new spring is a poor
     * start (measured on the rolling disk at dt = 0.004 s: 45 % more
     * Newton iterations and 3 more step cuts than refactorising): with
     * modified Newton on a direct solver the springs' change goes onto
     * the kept factorisation (lowrank.c), else it is factorised again */
    if (changed & 1) MPGM_CALL(mpgm_scatter_maps(pb));
    int kept = 0;
    if (changed == 2 && ls->factor_valid && sc->newton_modified && !ls->solver->type->iterative)
      MPGM_CALL(mpgm_lowrank_update(pb, &kept));
    if (kept) mpgm_count(ctx, MPGM_C_CONTACT_LOW_RANK, 1);
    else ls->factor_valid = 0;
  }
  pb->last.iterations = its;
  commit(pb);
  pb->newton_total += its;
  return 0;
}

/* The integrator's data is the run's linear system (pb->ls), handed to
 * the problem's destroy even when its creation failed half-way. */
static int implicit_create(mpgm_problem *pb, void **self) {
  const int err = mpgm_linsys_create(pb);
  *self = pb->ls;
  return err;
}

static void implicit_destroy(void *self) { mpgm_linsys_destroy(self); }

const mpgm_integrator_type mpgm_integrator_implicit = {
    .name = "implicit",
    .doc = "implicit Newmark (static: without inertia): Newton on R and K = K_mat + K_geo "
           "(+ K_dyn), with the contact active set",
    .implicit = 1,
    .create = implicit_create,
    .destroy = implicit_destroy,
    .step = implicit_step,
};
