/* newton.c -- Newton's method on the equations of one step, split as GSL
 * splits its iterative solvers: init (predictor, reference norms),
 * residual (R and, when the next correction needs it, K at the current
 * iterate), test (converged, diverged, out of iterations) and iterate (one
 * correction: factorise or reuse, solve, update). The integrator runs the
 * loop and may act between the calls (the contact active set). */
#include <math.h>
#include <string.h>

#include "mpgm_core_impl.h"

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
  mpgm_linsys *ls = pb->ls;
  mpgm_nodes *nd = &pb->nodes;
  int any = 0;
  for (int i = 0; i < MPGM_DIM * nd->n; i++) {
    if (!warm || nd->fix[i]) nd->du[i] = 0.0;
    /* time.predictor = velocity: start from the motion at the nodal
     * velocity (the converged step is the same; on the rolling disk it
     * saves a tenth of the Newton iterations) */
    if (!warm && !nd->fix[i] && pb->fx.inertia && pb->scene->predictor_velocity)
      nd->du[i] = pb->dt * nd->v[i];
    if (warm) continue; /* a re-solve keeps the free increments it had */
    ls->dubar[i] = nd->fix[i] ? pb->lambda * nd->ubar[i] - nd->u[i] : 0.0;
    any |= ls->dubar[i] != 0.0;
  }
  return any;
}

/* time.hht_alpha: the internal force of t_n on this step's nodes, f_ext -
 * R at du = 0 (the stresses of t_n in the configuration of t_n): one more
 * constitutive update and residual per step. */
static int hht_start(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  mpgm_nodes *nd = &pb->nodes;
  memset(nd->du, 0, sizeof(double) * MPGM_DIM * (size_t)nd->n);
  MPGM_CALL(mpgm_eval_points(pb, 0));
  MPGM_CALL(mpgm_assemble_static(pb));
  for (int i = 0; i < nd->ndof; i++) ls->fint_n[i] = ls->fext[i] - ls->R[i];
  return 0;
}

int mpgm_newton_init(mpgm_problem *pb, mpgm_newton *nt, int warm) {
  mpgm_linsys *ls = pb->ls;
  const mpgm_nodes *nd = &pb->nodes;
  memset(nt, 0, sizeof *nt);
  memset(&pb->last, 0, sizeof pb->last);
  nt->warm = warm;
  nt->res_prev = INFINITY;
  nt->omega = 1.0;
  if (!warm) MPGM_CALL(mpgm_body_force(pb, pb->t + pb->dt));
  if (!warm && ls->fint_n) MPGM_CALL(hht_start(pb));
  ls->lift = predictor(pb, warm) ? ls->dubar : NULL;
  /* |f_ext| over the free equations (held contact components have
   * numbered, constrained equations) */
  double fnorm = 0.0;
  for (int i = 0; i < MPGM_DIM * nd->n; i++)
    if (nd->dof[i] >= 0 && !nd->fix[i]) fnorm += ls->fext[nd->dof[i]] * ls->fext[nd->dof[i]];
  nt->fnorm = sqrt(fnorm);
  /* a factorisation of this pattern exists (modified Newton may start from
   * the one of an earlier step) */
  nt->factored = pb->scene->newton_modified && ls->factor_valid &&
                 memcmp(ls->fix_factored, nd->fix, MPGM_DIM * (size_t)nd->n) == 0;
  mpgm_bfgs_reset(pb);
  return 0;
}

/* The points' update and R (and K) at the current increments; |R| into
 * *res. Returns the update's error code (0: none). */
static int evaluate(mpgm_problem *pb, int want_K, double *res) {
  int err = mpgm_eval_points(pb, want_K);
  if (!err) err = mpgm_assemble(pb, want_K);
  *res = err ? INFINITY : norm2(pb->ls->R, pb->nodes.ndof);
  return err;
}

/* du += s delta over the numbered components (as update_increments does
 * for an iteration that lifts nothing). */
static void shift_increments(mpgm_problem *pb, double s) {
  mpgm_nodes *nd = &pb->nodes;
  for (int i = 0; i < MPGM_DIM * nd->n; i++)
    if (nd->dof[i] >= 0) nd->du[i] += s * pb->ls->delta[nd->dof[i]];
}

/* solver.line_search (m > 0): backtracking along the last correction d,
 * with f = |R|^2 / 2 as the merit function (Dennis and Schnabel 1996,
 * section 6.3; PETSc's "bt" line search). The correction is kept whole
 * when |R(du)| <= (1 - 1e-4 a) |R0| at a = 1 (R0 at the iterate it was
 * computed from, d from the tangent there, so f'(0) = -omega |R0|^2 along
 * the relaxed d). Otherwise du goes back to du0 + a' d with a' the
 * minimiser of the quadratic through f(0), f'(0) and f(a), kept within
 * [0.1 a, 0.5 a]; a trial whose points fail (det F <= 0, the return
 * mapping, NaN: a recoverable code) halves a. At most m trials; the last
 * is kept either way (the stagnation test and max_iterations judge what
 * follows), and a trial that still fails returns its error (the step is
 * cut). A point flipping between plastic and elastic makes full
 * corrections overshoot the kink and |R| wander (docs/theory.md section
 * 6): the search keeps |R| falling instead. err: the full correction's
 * evaluation; returns the accepted trial's. */
static int line_search(mpgm_problem *pb, mpgm_newton *nt, int err, double *res) {
  const double r0 = nt->res_prev, g0 = -nt->omega * r0 * r0, f0 = 0.5 * r0 * r0;
  double a = 1.0;
  for (int k = 0; k < pb->scene->line_search; k++) {
    if (err < 0) return err; /* not a failure of the iterate: no search */
    if (!err && *res <= (1.0 - 1e-4 * a) * r0) break; /* also false for NaN */
    double next = 0.5 * a;
    if (!err && isfinite(*res)) {
      const double fa = 0.5 * *res * *res, q = -g0 * a * a / (2.0 * (fa - f0 - g0 * a));
      next = fmin(0.5 * a, fmax(0.1 * a, q));
    }
    if (k == 0) mpgm_count(pb->ctx, MPGM_C_LINE_SEARCHES, 1);
    shift_increments(pb, next - a);
    a = next;
    mpgm_err_clear(pb->ctx);
    err = evaluate(pb, nt->want_K, res);
  }
  return err;
}

int mpgm_newton_residual(mpgm_problem *pb, mpgm_newton *nt) {
  mpgm_linsys *ls = pb->ls;
  mpgm_newton_info *info = &pb->last;
  /* modified Newton assembles K only when it refactorises, and then the
   * points' tangents D are needed; else the material update skips them */
  nt->want_K = !pb->scene->newton_modified || !nt->factored || ls->lift;
  double res;
  int err = evaluate(pb, nt->want_K, &res);
  if (pb->scene->line_search > 0 && nt->it > 0 && nt->searchable && isfinite(nt->res_prev))
    err = line_search(pb, nt, err, &res);
  MPGM_CALL(err);
  if (mpgm_fault_due(pb->ctx, MPGM_ERR_NAN, pb->step + 1)) res = NAN; /* tests */
  if (!isfinite(res))
    MPGM_ERROR(pb->ctx, MPGM_ERR_NAN, "Newton iteration %d: residual is not finite", nt->it);
  if (nt->it == 0) {
    info->res0 = res;
    /* the step's reference: a re-solve after a contact change keeps it
     * (or its own start, if larger). Taken afresh from the re-solve's
     * start, ref tightened the tolerance by the factor the first solve
     * had already gained when the contact set changed (10 to 30 on the
     * rolling disk, where keeping it saves 7 to 10 % of the iterations;
     * docs/benchmarks.md, "Table 1 on an Intel Xeon") */
    nt->ref = fmax(res, nt->fnorm);
    if (nt->warm) nt->ref = fmax(nt->ref, ls->step_ref);
    ls->step_ref = nt->ref;
  }
  nt->res = res;
  memmove(nt->rh + 1, nt->rh, sizeof nt->rh - sizeof nt->rh[0]);
  nt->rh[0] = res;
  info->res = res;
  info->res_rel = nt->ref > 0.0 ? res / nt->ref : 0.0;
  if (nt->it < 64) info->hist[info->nhist++] = res;
  return 0;
}

/* solver.stagnation (w > 0): the smallest |R| of the last w iterates is
 * not half the smallest before them. Hard steps of the column collapse
 * (a point flipping between plastic and elastic) reach |R|/ref ~ 1e-2 by
 * the fourth iterate and then wander there until max_iterations: the
 * step is cut either way, and ending it once |R| has stopped falling
 * saves those iterations. A Newton solve that converges, even linearly
 * (modified Newton refactorises unless |R| falls by reuse_ratio), halves
 * |R| within a few iterates. The window starts again where a stall was
 * relaxed (solver.relaxation), so relaxation has its iterations. */
static int stagnated(const mpgm_newton *nt, const mpgm_newton_info *info, int w, double *recent,
                     double *before) {
  const int it = nt->it, base = nt->it_stall;
  if (w <= 0 || it >= info->nhist || it - w < base) return 0;
  *before = *recent = INFINITY;
  for (int k = base; k <= it - w; k++) *before = fmin(*before, info->hist[k]);
  for (int k = it - w + 1; k <= it; k++) *recent = fmin(*recent, info->hist[k]);
  return *recent > 0.5 * *before;
}

/* Newton's residual tolerance: |R| <= max(atol, rtol ref) converges. */
static double res_tolerance(const mpgm_scene *sc, const mpgm_newton *nt) {
  return fmax(sc->atol, sc->rtol * nt->ref);
}

int mpgm_newton_test(mpgm_problem *pb, const mpgm_newton *nt, int *done) {
  const mpgm_scene *sc = pb->scene;
  const mpgm_newton_info *info = &pb->last;
  const int it = nt->it;
  const double res = nt->res;
  /* converged: residual small (absolute or relative to the step's load),
   * or the last correction negligible against the step's increment (the
   * residual then sits at its round-off floor, which grows with the
   * problem's size and stiffness) */
  const int res_ok = res <= res_tolerance(sc, nt);
  /* tests: a stall made on purpose ends Newton as its iteration limit does */
  const int stall = it > 0 && mpgm_fault_due(pb->ctx, MPGM_ERR_NOT_CONVERGED, pb->step + 1);
  *done = !stall && !pb->ls->lift && (res_ok || (it > 0 && info->du_rel <= sc->dtol));
  if (*done) return 0;
  if (it == sc->max_iter || stall)
    MPGM_ERROR(pb->ctx, MPGM_ERR_NOT_CONVERGED,
               "Newton did not converge in %d iterations (|R| = %.3e, |R|/ref = %.3e, "
               "|du|/|Du| = %.3e)", it, res, info->res_rel, info->du_rel);
  /* stagnated: ended, but where the scene relaxes stalls, only once a
   * stall was relaxed (relax(): |R| repeating), from where it was */
  double recent, before;
  const int may_relax = sc->relaxation < 1.0 && nt->it_stall == 0;
  if (!may_relax && stagnated(nt, info, sc->stagnation, &recent, &before)) {
    mpgm_count(pb->ctx, MPGM_C_NEWTON_STAGNATIONS, 1);
    MPGM_ERROR(pb->ctx, MPGM_ERR_NOT_CONVERGED,
               "Newton stagnated at iteration %d: the smallest |R|/ref of the last %d iterates, "
               "%.3e, is not half the smallest before them, %.3e (solver.stagnation)", it,
               sc->stagnation, recent / nt->ref, before / nt->ref);
  }
  if (it > 2 && res > 1e8 * nt->ref)
    MPGM_ERROR(pb->ctx, MPGM_ERR_DIVERGED, "Newton diverged at iteration %d (|R|/ref = %.3e)", it,
               info->res_rel);
  return 0;
}

/* The system K delta = R about to be solved, to every observer. */
static int observe_system(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  for (int i = 0; i < pb->nobs; i++)
    if (pb->obs[i].system)
      MPGM_CALL(pb->obs[i].system(pb->obs[i].user, pb->ctx, pb->step + 1, &ls->K, ls->R));
  return 0;
}

/* du += delta (free components); with a lift, the fixed components take
 * their prescribed increments. Returns |delta|^2 + |lift|^2 in *dd and
 * |du|^2 in *uu. */
static void update_increments(mpgm_problem *pb, double *dd, double *uu) {
  mpgm_linsys *ls = pb->ls;
  mpgm_nodes *nd = &pb->nodes;
  *dd = *uu = 0.0;
  for (int i = 0; i < MPGM_DIM * nd->n; i++) {
    if (ls->lift && nd->dof[i] < 0) {
      nd->du[i] = ls->dubar[i];
      *dd += nd->du[i] * nd->du[i];
    }
    if (nd->dof[i] >= 0) {
      const double d = ls->delta[nd->dof[i]];
      nd->du[i] += d;
      *dd += d * d;
    }
    *uu += nd->du[i] * nd->du[i];
  }
}

/* Eisenstat and Walker's forcing term (1996, choice 2, gamma 0.9, alpha 2:
 * Newton stays quadratic), the relative tolerance of this iteration's
 * linear solve: eta_max at the first iteration, gamma (|R_k| / |R_k-1|)^2
 * after, not below gamma eta_k-1^2 when that exceeds 0.1 (a sudden fall of
 * |R| does not tighten the solve at once), at most eta_max and at most
 * |R_k| / ref (eta_k = O(|R_k|) keeps Newton q-quadratic, Dembo, Eisenstat
 * and Steihaug 1982: without it the column collapse's last plastic step
 * converged at the rates 1.4 to 1.7, |R| / ref falling 3e-4, 1.4e-6,
 * 3e-10), not below what Newton's own test needs (half of its tolerance
 * over |R_k|: no oversolving at the end) and not below
 * solver.linear_tol. eta_max 1e-3, not the customary 0.1 to 0.9: far
 * from its solution (the cantilever in one load step) Newton needs as many
 * iterations as with exact solves only when its first solves are tight
 * (9 iterations at 0.1, 5 at 0.01, 4 at 1e-3 and exact, measured before
 * the |R_k| / ref bound), and the savings stay: the column collapse (0.3 s,
 * h = 0.05, GMRES + ILU(0)) takes 1353 Krylov iterations at 1e-3 against
 * 4000 solved to 1e-10, in 308 Newton iterations against 303. */
static double forcing(const mpgm_problem *pb, mpgm_newton *nt) {
  const mpgm_scene *sc = pb->scene;
  const double eta_max = 1e-3, gamma = 0.9;
  double eta = eta_max;
  if (nt->it > 0 && nt->res_prev > 0.0 && isfinite(nt->res_prev)) {
    const double q = nt->res / nt->res_prev, safe = gamma * nt->eta * nt->eta;
    eta = gamma * q * q;
    if (safe > 0.1) eta = fmax(eta, safe);
  }
  if (nt->ref > 0.0) eta = fmin(eta, nt->res / nt->ref);
  const double tau = res_tolerance(sc, nt);
  if (nt->res > 0.0) eta = fmax(eta, 0.5 * tau / nt->res);
  eta = fmax(fmin(eta, eta_max), sc->solver_opts.tol);
  nt->eta = eta;
  return eta;
}

/* solver.relaxation. Newton on a piecewise smooth residual (a material
 * point that is plastic at one iterate and elastic at the next, a
 * Mohr-Coulomb return that changes region) can fall into a cycle: every
 * correction is right for the state it was computed in and carries the
 * iterate across the kink, and |R| repeats every other iteration until
 * max_iterations (the column collapse: 25 iterations, then a step cut).
 * Once |R| repeats (the last four iterates: |R_k| within 5 % of |R_k-2|
 * and |R_k-1| of |R_k-3|) the corrections are scaled by the factor, which
 * breaks the cycle (|R| then falls by about 1 - factor per iteration),
 * and full corrections return once |R| is ten times below where the
 * stall was found, for Newton's quadratic end. A converged iterate is
 * judged by the same tests. */
static void relax(mpgm_problem *pb, mpgm_newton *nt) {
  const double w = pb->scene->relaxation, *r = nt->rh, tol = 0.05;
  if (nt->omega < 1.0 && nt->res < 0.1 * nt->res_stall) nt->omega = 1.0;
  if (w < 1.0 && nt->omega == 1.0 && nt->it >= 4 && fabs(r[0] - r[2]) <= tol * r[0] &&
      fabs(r[1] - r[3]) <= tol * r[1]) {
    nt->omega = w;
    nt->res_stall = nt->res;
    nt->it_stall = nt->it;
    mpgm_count(pb->ctx, MPGM_C_NEWTON_RELAXATIONS, 1);
  }
  if (nt->omega < 1.0)
    for (int i = 0; i < pb->nodes.ndof; i++) pb->ls->delta[i] *= nt->omega;
}

/* Modified Newton keeps the last factorisation while the residual drops
 * by reuse_ratio per iteration; else it refactorises. It also renews one
 * that cannot finish: when at most RENEW_RESERVE iterations are left and,
 * at the rate |R| now falls, reaching the tolerance would take more. On
 * the rolling disk (GMM-LME gamma 0.8, dt 0.002, step 27) a re-solve after
 * a contact change fell by 0.49 per iteration, inside reuse_ratio 0.5,
 * from |R|/ref 0.5, and stopped at max_iterations with |R|/ref 3.6e-9
 * against rtol 1e-9: the step was cut. Renewing only for the last
 * iterations, not as soon as the rate first falls short, leaves every
 * solve that finishes in time on its path: renewing at once also renewed
 * in solves whose rate then improved, and moved which steps an inverted
 * iterate cuts (docs/theory.md section 6). By then |R| has fallen by at
 * least reuse_ratio per iteration, and full Newton needs one to three
 * more. */
#define RENEW_RESERVE 4
static int keep_factor(const mpgm_problem *pb, const mpgm_newton *nt) {
  const mpgm_scene *sc = pb->scene;
  if (!sc->newton_modified || !nt->factored || pb->ls->lift) return 0;
  if (nt->it == 0) return 1;
  if (!(nt->res <= sc->reuse_ratio * nt->res_prev)) return 0;
  const int left = sc->max_iter - nt->it;
  const double tau = res_tolerance(sc, nt);
  if (left > RENEW_RESERVE || nt->res <= tau) return 1;
  const double rate = nt->res / nt->res_prev; /* in (0, reuse_ratio] */
  if (log(tau / nt->res) / log(rate) <= (double)left) return 1;
  mpgm_count(pb->ctx, MPGM_C_FACTOR_RENEWALS, 1);
  return 0;
}

int mpgm_problem_analyse(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  if (ls->solver->analysed) return 0;
  const mpgm_nodes *nd = &pb->nodes;
  ls->K_layout = (mpgm_dof_layout){MPGM_DIM, nd->n, nd->dof, nd->x};
  ls->K.layout = &ls->K_layout;
  return mpgm_solver_analyse(ls->solver, pb->ctx, &ls->K, ls->perm);
}

int mpgm_newton_iterate(mpgm_problem *pb, mpgm_newton *nt) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *sc = pb->scene;
  mpgm_nodes *nd = &pb->nodes;
  const int reuse = keep_factor(pb, nt);
  if (sc->forcing_ew) MPGM_CALL(mpgm_solver_tolerance(ls->solver, forcing(pb, nt)));
  nt->res_prev = nt->res;
  if (!reuse && !nt->want_K) { /* the tangents D skipped at this iterate */
    MPGM_CALL(mpgm_eval_points(pb, 1));
    MPGM_CALL(mpgm_assemble(pb, 1));
  }
  MPGM_CALL(mpgm_problem_analyse(pb));
  /* observers (output.matrices): the system this iteration solves
   * (modified Newton reusing a factorisation: K holds the factorised
   * values still, as K is assembled only to be factorised) */
  MPGM_CALL(observe_system(pb));
  const int err = reuse ? 0 : mpgm_solver_factor(ls->solver, ctx, &ls->K);
  nt->factored = 1;
  ls->factor_valid = !err;
  MPGM_CALL(err);
  /* the held contact components (and springs) the factorisation was
   * made with */
  if (!reuse) {
    memcpy(ls->fix_factored, nd->fix, MPGM_DIM * (size_t)nd->n);
    MPGM_CALL(mpgm_lowrank_reset(pb));
  }
  if (sc->newton_bfgs) {
    MPGM_CALL(mpgm_bfgs_solve(pb, reuse));
  } else {
    MPGM_CALL(mpgm_solver_solve(ls->solver, ctx, ls->R, ls->delta));
    if (reuse) mpgm_lowrank_apply(pb, ls->delta);
  }
  relax(pb, nt);
  double dd, uu;
  update_increments(pb, &dd, &uu);
  if (!isfinite(dd))
    MPGM_ERROR(ctx, MPGM_ERR_NAN, "Newton iteration %d: solution is not finite", nt->it);
  pb->last.du_rel = uu > 0.0 ? sqrt(dd / uu) : 0.0;
  nt->searchable = !reuse && !ls->lift;
  ls->lift = NULL;
  pb->last.iterations = ++nt->it;
  return 0;
}
