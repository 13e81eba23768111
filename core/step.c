/* step.c -- one updated-Lagrangian step: predictor, Newton, commit
 * (Algorithm 1/2 phase b of Iaconeta et al. 2017, shared by every front
 * end; docs/theory.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core.h"
#include "mpgm_mtx.h"
#include "mpgm_output.h"

static double norm2(const double *x, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) s += x[i] * x[i];
  return sqrt(s);
}

/* Predictor (42): du = 0. Fixed components get the increment of their
 * (ramped) prescribed value through the first Newton iteration: it solves
 * K_ff delta = R(0) - K_fc dubar, so the whole body follows the boundary
 * linearly instead of the boundary nodes jumping alone (which can invert
 * the cells next to them). Returns 1 when some increment is non-zero. */
static int predictor(mpgm_problem *pb, int warm) {
  mpgm_nodes *nd = &pb->nodes;
  int any = 0;
  for (int i = 0; i < 2 * nd->n; i++) {
    if (!warm || nd->fix[i]) nd->du[i] = 0.0;
    /* time.predictor = velocity: start from the motion at the nodal
     * velocity (the converged step is the same; on the rolling disk it
     * saves a tenth of the Newton iterations) */
    if (!warm && !nd->fix[i] && pb->fx.inertia && pb->scene->predictor_velocity)
      nd->du[i] = pb->dt * nd->v[i];
    if (warm) continue; /* a re-solve keeps the free increments it had */
    pb->dubar[i] = nd->fix[i] ? pb->lambda * nd->ubar[i] - nd->u[i] : 0.0;
    any |= pb->dubar[i] != 0.0;
  }
  return any;
}

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
  for (int p = 0; p < m; p++) {
    double d[2] = {0, 0}, v[2] = {0, 0}, a[2] = {0, 0};
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      const double N = C->N[k];
      d[0] += N * nd->du[2 * I];
      d[1] += N * nd->du[2 * I + 1];
      if (inertia) {
        v[0] += N * nd->v_new[2 * I]; v[1] += N * nd->v_new[2 * I + 1];
        a[0] += N * nd->a_new[2 * I]; a[1] += N * nd->a_new[2 * I + 1];
      }
    }
    P->u[2 * p] += d[0];
    P->u[2 * p + 1] += d[1];
    if (move) {
      P->x[2 * p] += d[0];
      P->x[2 * p + 1] += d[1];
    }
    if (inertia && newmark_pv) { /* eq (48): trapezoidal in the particle */
      P->v[2 * p] += 0.5 * pb->dt * (P->a[2 * p] + a[0]);
      P->v[2 * p + 1] += 0.5 * pb->dt * (P->a[2 * p + 1] + a[1]);
      P->a[2 * p] = a[0]; P->a[2 * p + 1] = a[1];
    } else if (inertia) {
      P->v[2 * p] = v[0]; P->v[2 * p + 1] = v[1];
      P->a[2 * p] = a[0]; P->a[2 * p + 1] = a[1];
    }
  }
  memcpy(P->F, P->F_t, sizeof(double) * 4 * (size_t)P->n);
  memcpy(P->sigma, P->sigma_t, sizeof(double) * 4 * (size_t)P->n);
  memcpy(P->vol, P->vol_t, sizeof(double) * (size_t)P->n);
  if (P->nstate) memcpy(P->state, P->state_t, sizeof(double) * (size_t)P->nstate * P->n);
  for (int i = 0; i < 2 * nd->n; i++) {
    nd->u[i] += nd->du[i];
    if (move) nd->x[i] += nd->du[i];
    if (inertia) {
      nd->v[i] = nd->v_new[i];
      nd->a[i] = nd->a_new[i];
    }
  }
  mpgm_timer_stop(ctx, MPGM_T_UPDATE);
}

static int contact_update(mpgm_problem *pb);

/* output.matrices: the system K delta = R about to be solved, as
 * DIR/matrices/stepSSSS_itII_K.mtx and _b.mtx (II counts the Newton
 * iterations of the step from 0, across contact re-solves). */
static int write_system(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  char path[MPGM_PATH_LEN + 64], what[MPGM_PATH_LEN + 128];
  const int len = snprintf(path, sizeof path, "%s/step%04ld_it%02d_", pb->matrices_dir, pb->step + 1,
                           pb->matrices_step);
  MPGM_CHECK(ctx, len > 0 && (size_t)len + 6 < sizeof path, MPGM_ERR_IO, "%s: path too long",
             pb->matrices_dir);
  mpgm_timer_start(ctx, MPGM_T_OUTPUT);
  snprintf(what, sizeof what, "mpgm: tangent K of step %ld, system %d (K delta = b), scene %s",
           pb->step + 1, pb->matrices_step, pb->scene->file);
  strcat(path, "K.mtx");
  int err = mpgm_mtx_write_csc(ctx, path, &pb->K, what);
  snprintf(what, sizeof what, "mpgm: right-hand side b (residual R) of step %ld, system %d, scene %s",
           pb->step + 1, pb->matrices_step, pb->scene->file);
  strcpy(path + len, "b.mtx");
  if (!err) err = mpgm_mtx_write_vec(ctx, path, pb->R, pb->K.n, what);
  mpgm_timer_stop(ctx, MPGM_T_OUTPUT);
  MPGM_CALL(err);
  pb->matrices_step++;
  pb->matrices_written++;
  return MPGM_OK;
}

/* Newton on the step from the predictor (42) to convergence; warm: start
 * from the current increments (a re-solve after the contact set changed).
 * Returns 0 or an error code; *again = contact_update's mask when it
 * stopped early because the contact set changed on the way (solve the step
 * again). */
static int newton(mpgm_problem *pb, int warm, int *again) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *sc = pb->scene;
  mpgm_nodes *nd = &pb->nodes;
  mpgm_newton_info *info = &pb->last;
  int err;
  memset(info, 0, sizeof *info);
  if (!warm) MPGM_CALL(mpgm_body_force(pb));
  const int lifted = predictor(pb, warm);
  pb->lift = lifted ? pb->dubar : NULL;
  const int n = nd->ndof;
  /* |f_ext| over the free equations (held contact components have
   * numbered, constrained equations) */
  double fnorm = 0.0;
  for (int i = 0; i < 2 * nd->n; i++)
    if (nd->dof[i] >= 0 && !nd->fix[i]) fnorm += pb->fext[nd->dof[i]] * pb->fext[nd->dof[i]];
  fnorm = sqrt(fnorm);
  double ref = 0.0, res_prev = INFINITY;
  /* a factorisation of this pattern exists (modified Newton may start from
   * the one of an earlier step) */
  int factored = sc->newton_modified && pb->factor_valid &&
                 memcmp(pb->fix_factored, nd->fix, 2 * (size_t)nd->n) == 0;
  int checked = 0;
  for (int it = 0;; it++) {
    MPGM_CALL(mpgm_eval_points(pb));
    /* modified Newton assembles K only when it refactorises */
    const int want_K = !sc->newton_modified || !factored || pb->lift;
    MPGM_CALL(mpgm_assemble(pb, want_K));
    const double res = norm2(pb->R, n);
    if (!isfinite(res))
      MPGM_ERROR(ctx, MPGM_ERR_NAN, "Newton iteration %d: residual is not finite", it);
    if (it == 0) {
      info->res0 = res;
      ref = fmax(res, fnorm);
    }
    info->res = res;
    info->res_rel = ref > 0.0 ? res / ref : 0.0;
    if (it < 64) info->hist[info->nhist++] = res;
    /* contact: check the active set once, as soon as the residual is below
     * contact_check of the reference, rather than only at convergence: a
     * wrong set is then not iterated to full accuracy first. The converged
     * state is checked again by mpgm_step. */
    if ((pb->fx.contact || pb->fx.contact_points) && !checked && it > 0 && !pb->lift &&
        res <= sc->contact_check * ref) {
      checked = 1;
      const int changed = contact_update(pb);
      if (changed) {
        info->iterations = it;
        *again = changed;
        return 0;
      }
    }
    /* converged: residual small (absolute or relative to the step's load),
     * or the last correction negligible against the step's increment (the
     * residual then sits at its round-off floor, which grows with the
     * problem's size and stiffness) */
    const int res_ok = res <= sc->atol || res <= sc->rtol * ref;
    if (!pb->lift && (res_ok || (it > 0 && info->du_rel <= sc->dtol))) break;
    if (it == sc->max_iter)
      MPGM_ERROR(ctx, MPGM_ERR_NOT_CONVERGED,
                 "Newton did not converge in %d iterations (|R| = %.3e, |R|/ref = %.3e, "
                 "|du|/|Du| = %.3e)", it, res, info->res_rel, info->du_rel);
    if (it > 2 && res > 1e8 * ref)
      MPGM_ERROR(ctx, MPGM_ERR_DIVERGED, "Newton diverged at iteration %d (|R|/ref = %.3e)", it,
                 info->res_rel);
    /* modified Newton: keep the last factorisation while the residual
     * drops by reuse_ratio per iteration; else refactorise */
    const int reuse = sc->newton_modified && factored && !pb->lift &&
                      (it == 0 || res <= sc->reuse_ratio * res_prev);
    res_prev = res;
    if (!reuse && !want_K) MPGM_CALL(mpgm_assemble(pb, 1));
    if (!pb->solver->analysed) {
      MPGM_CALL(mpgm_solver_analyse(pb->solver, ctx, &pb->K, pb->perm));
      pb->solver->analysed = 1;
    }
    /* output.matrices: the system this iteration solves (modified Newton
     * reusing a factorisation: K holds the factorised values still, as K
     * is assembled only to be factorised) */
    if (pb->matrices_on) MPGM_CALL(write_system(pb));
    err = reuse ? 0 : mpgm_solver_factor(pb->solver, ctx, &pb->K);
    factored = 1;
    pb->factor_valid = !err;
    MPGM_CALL(err);
    /* the held contact components the factorisation was made with */
    if (!reuse) memcpy(pb->fix_factored, nd->fix, 2 * (size_t)nd->n);
    MPGM_CALL(mpgm_solver_solve(pb->solver, ctx, pb->R, pb->delta));
    double dd = 0.0, uu = 0.0;
    for (int i = 0; i < 2 * nd->n; i++) {
      if (pb->lift && nd->dof[i] < 0) {
        nd->du[i] = pb->dubar[i];
        dd += nd->du[i] * nd->du[i];
      }
      if (nd->dof[i] >= 0) {
        const double d = pb->delta[nd->dof[i]];
        nd->du[i] += d;
        dd += d * d;
      }
      uu += nd->du[i] * nd->du[i];
    }
    if (!isfinite(dd)) MPGM_ERROR(ctx, MPGM_ERR_NAN, "Newton iteration %d: solution is not finite", it);
    info->du_rel = uu > 0.0 ? sqrt(dd / uu) : 0.0;
    pb->lift = NULL;
    info->iterations = it + 1;
  }
  return 0;
}

/* Unilateral contact (the contact codes of the nodes): a contact node is
 * held (no slip) while the plane pushes on the body, released where it
 * would pull, and held again where a released node moves into the plane.
 * A node changes state at most once per step (pb->cflip), so the active set
 * cannot chatter and settles in a few solves; the front end starts each
 * step from the set the last one ended with. Contact at surface points
 * follows the same rules (mpgm_cpoints_update). Returns a mask of what
 * changed: 1 contact nodes, 2 surface points. */
static int contact_update(mpgm_problem *pb) {
  mpgm_nodes *nd = &pb->nodes;
  double *r = pb->react;
  int changed = pb->fx.contact_points && mpgm_cpoints_update(pb) ? 2 : 0;
  if (!pb->fx.contact) return changed;
  mpgm_reactions(pb, r);
  for (int i = 0; i < nd->n; i++) {
    const int code = nd->contact[i];
    if (!code || pb->cflip[i]) continue;
    const int axis = abs(code) - 1, side = code > 0 ? 1 : -1;
    const int held = nd->fix[2 * i + axis];
    if ((held && side * r[2 * i + axis] < 0.0) || (!held && side * nd->du[2 * i + axis] < 0.0)) {
      nd->fix[2 * i] = nd->fix[2 * i + 1] = (unsigned char)!held;
      nd->ubar[2 * i] = nd->ubar[2 * i + 1] = 0.0;
      pb->cflip[i] = 1;
      changed |= 1;
    }
  }
  return changed;
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
  mpgm_ctx *ctx = pb->ctx;
  mpgm_nodes *nd = &pb->nodes;
  const mpgm_conn *C = &pb->conn;
  mpgm_points *P = &pb->pts;
  memset(nd->du, 0, sizeof(double) * 2 * (size_t)nd->n);
  MPGM_CALL(mpgm_body_force(pb));
  MPGM_CALL(mpgm_eval_points(pb));
  MPGM_CALL(mpgm_assemble_mass(pb));
  if (!pb->solver->analysed) {
    MPGM_CALL(mpgm_solver_analyse(pb->solver, ctx, &pb->K, pb->perm));
    pb->solver->analysed = 1;
  }
  pb->factor_valid = 0; /* the factorisation is M's, not the tangent's */
  /* a composite's part in use, without its fallback: Cholesky refusing M
   * means M is singular, and the lumped mass is used */
  mpgm_solver *ms = mpgm_solver_part(pb->solver);
  int err = mpgm_solver_factor(ms, ctx, &pb->K);
  if (!err) {
    MPGM_CALL(mpgm_solver_solve(ms, ctx, pb->R, pb->delta));
  } else if (err == MPGM_ERR_SINGULAR) {
    mpgm_err_clear(ctx);
    double *mI = pb->react; /* scratch, 2 per node */
    memset(mI, 0, sizeof(double) * 2 * (size_t)nd->n);
    for (int p = 0; p < P->n; p++)
      for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) mI[2 * C->node[k]] += P->mass[p] * C->N[k];
    for (int i = 0; i < 2 * nd->n; i++)
      if (nd->dof[i] >= 0) pb->delta[nd->dof[i]] = mI[2 * (i / 2)] > 0.0 ? pb->R[nd->dof[i]] / mI[2 * (i / 2)] : 0.0;
  } else {
    return err;
  }
  for (int i = 0; i < 2 * nd->n; i++) {
    const int e = nd->dof[i];
    nd->a[i] = e >= 0 && !nd->fix[i] ? pb->delta[e] : 0.0;
    if (!isfinite(nd->a[i]))
      MPGM_ERROR(ctx, MPGM_ERR_NAN, "initial acceleration: not finite at node %d", i / 2);
  }
  if (pb->fe->point_velocity == MPGM_PV_NEWMARK)
    for (int p = 0; p < P->n + P->nprobe + P->nsurf; p++) {
      double a[2] = {0, 0};
      for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
        a[0] += C->N[k] * nd->a[2 * C->node[k]];
        a[1] += C->N[k] * nd->a[2 * C->node[k] + 1];
      }
      P->a[2 * p] = a[0];
      P->a[2 * p + 1] = a[1];
    }
  return MPGM_OK;
}

int mpgm_step(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *sc = pb->scene;
  mpgm_nodes *nd = &pb->nodes;

  mpgm_timer_start(ctx, MPGM_T_SHAPE);
  int err = pb->fe->begin_step(pb);
  mpgm_timer_stop(ctx, MPGM_T_SHAPE);
  MPGM_CALL(err);
  pb->lambda = mpgm_load_factor(pb);
  int rebuild = pb->conn.version != pb->pattern_version, its = 0;
  if (!rebuild && pb->conn.map_version != pb->map_version) MPGM_CALL(mpgm_scatter_build(pb));
  if (pb->fx.contact) memset(pb->cflip, 0, (size_t)nd->n);
  if (pb->fx.contact_points) memset(pb->cp.flip, 0, (size_t)pb->cp.n);
  int ndof_step = nd->ndof;
  int kept; /* a composite solver may change its part at a new step */
  MPGM_CALL(mpgm_solver_step(pb->solver, ctx, &kept));
  if (!kept) pb->factor_valid = 0;
  /* output.matrices: a retried (cut) step writes its systems afresh */
  pb->matrices_on = 0;
  pb->matrices_step = 0;
  for (int i = 0; pb->matrices_dir && i < sc->nmatrices; i++)
    pb->matrices_on |= sc->matrices[i] == pb->step + 1;
  if (pb->matrices_on) {
    char prefix[32];
    snprintf(prefix, sizeof prefix, "step%04ld_", pb->step + 1);
    MPGM_CALL(mpgm_remove_files(ctx, pb->matrices_dir, prefix, ".mtx"));
  }
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
               "step %ld: equations renumbered within the step (%d -> %d)", pb->step + 1, ndof_step, nd->ndof);
    /* a recoverable failure of Newton is the step's failure (the run loop
     * may cut the step); only a contact change solves the step again */
    int early = 0;
    MPGM_CALL(newton(pb, round > 0, &early));
    its += pb->last.iterations;
    const int changed = early ? early : pb->fx.contact || pb->fx.contact_points ? contact_update(pb) : 0;
    if (!changed) break;
    MPGM_CHECK(ctx, round < 50, MPGM_ERR_NOT_CONVERGED,
               "the contact active set did not settle in %d solves of the step", round + 1);
    pb->contact_rounds++;
    /* contact nodes keep their equations whatever their state: the
     * pattern and its analysis stand, only the maps (which leave out held
     * components) and the factorisation change. Surface points change
     * values only, but the factorisation without a new spring is a poor
     * start (measured on the rolling disk at dt = 0.004 s: 45 % more
     * Newton iterations and 3 more step cuts than refactorising) */
    if (changed & 1) MPGM_CALL(mpgm_scatter_maps(pb));
    pb->factor_valid = 0;
  }
  pb->last.iterations = its;
  const mpgm_newton_info *info = &pb->last;
  commit(pb);
  pb->t += pb->dt;
  pb->step++;
  pb->newton_total += info->iterations;
  mpgm_timer_start(ctx, MPGM_T_SHAPE);
  err = pb->fe->end_step(pb);
  mpgm_timer_stop(ctx, MPGM_T_SHAPE);
  return err;
}
