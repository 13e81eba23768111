/* bfgs.c -- solver.newton "bfgs": modified Newton whose corrections with
 * a kept factorisation are improved by BFGS updates (Matthies and Strang
 * 1979, "The solution of nonlinear finite element equations"; Nocedal and
 * Wright 2006, algorithm 7.4 for the two-loop form).
 *
 * Modified Newton solves K0 delta = R with the factorisation of an earlier
 * tangent K0 and converges linearly, at the rate at which K0 misses the
 * current tangent. Each of its iterations shows the true tangent along
 * one direction: the change of the unknowns s_k = du_k+1 - du_k and of the
 * residual y_k = R_k - R_k+1 (R = f_ext - f_int, so y ~ K s). BFGS
 * corrects the inverse of K0 by every pair since the factorisation,
 *
 *   H_k+1 = (I - rho s y^T) H_k (I - rho y s^T) + rho s s^T,
 *   rho = 1 / (y^T s),  H_0 = K0^-1,
 *
 * applied without forming H (the two-loop recursion: one solve with K0 and
 * four vector operations per pair), so that the iteration converges
 * superlinearly with the same factorisation. H stays symmetric and
 * positive definite when K0 is and every pair has y^T s > 0; a pair
 * without that curvature (a point yielding or unloading between the
 * iterates: the residual is only piecewise smooth) is skipped. The pairs
 * are forgotten at every factorisation and at the start of every Newton
 * solve (a step, or a re-solve after a contact change: the equations or
 * the held components may differ); the newest solver.bfgs_pairs are kept.
 * H_0 includes the contact changes on the kept factorisation
 * (solver.contact_rank, lowrank.c). The pairs are updates, counted in
 * counts.bfgs_updates.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core_impl.h"

static double dot(const double *a, const double *b, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) s += a[i] * b[i];
  return s;
}

static void axpy(double a, const double *x, double *y, int n) {
  for (int i = 0; i < n; i++) y[i] += a * x[i];
}

int mpgm_bfgs_setup(mpgm_problem *pb) {
  mpgm_bfgs *b = &pb->ls->bfgs;
  if (!pb->scene->newton_bfgs) return 0;
  b->m = pb->scene->bfgs_pairs;
  const size_t n = MPGM_DIM * (size_t)pb->nodes.cap + 1, m = (size_t)b->m;
  b->S = calloc(m * n, sizeof(double));
  b->Y = calloc(m * n, sizeof(double));
  b->r_prev = calloc(n, sizeof(double));
  b->du_prev = calloc(n, sizeof(double));
  b->q = calloc(n, sizeof(double));
  MPGM_CHECK(pb->ctx, b->S && b->Y && b->r_prev && b->du_prev && b->q, MPGM_ERR_NOMEM,
             "out of memory");
  return 0;
}

void mpgm_bfgs_free(mpgm_bfgs *b) {
  void *arr[] = {b->S, b->Y, b->r_prev, b->du_prev, b->q};
  for (size_t i = 0; i < sizeof arr / sizeof arr[0]; i++) free(arr[i]);
  memset(b, 0, sizeof *b);
}

void mpgm_bfgs_reset(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  ls->bfgs.k = 0;
  ls->bfgs.first = 0;
  ls->bfgs.have_prev = 0;
}

/* du over the numbered equations into x. */
static void gather_du(const mpgm_problem *pb, double *x) {
  const mpgm_nodes *nd = &pb->nodes;
  for (int i = 0; i < MPGM_DIM * nd->n; i++)
    if (nd->dof[i] >= 0) x[nd->dof[i]] = nd->du[i];
}

/* The pair of the last iteration (s, y) from where it started to here,
 * kept when it has curvature. */
static void push_pair(mpgm_problem *pb, int n) {
  mpgm_linsys *ls = pb->ls;
  mpgm_bfgs *b = &ls->bfgs;
  const int slot = (b->first + b->k) % b->m;
  double *s = b->S + (size_t)slot * (size_t)n, *y = b->Y + (size_t)slot * (size_t)n;
  gather_du(pb, s);
  double sy = 0.0, ss = 0.0, yy = 0.0;
  for (int i = 0; i < n; i++) {
    s[i] -= b->du_prev[i];
    y[i] = b->r_prev[i] - ls->R[i];
    sy += s[i] * y[i], ss += s[i] * s[i], yy += y[i] * y[i];
  }
  if (!(sy > 1e-12 * sqrt(ss * yy))) { /* no curvature (or NaN): skip */
    if (b->k == b->m) {                /* the slot was the oldest pair's */
      b->first = (b->first + 1) % b->m;
      b->k--;
    }
    return;
  }
  b->rho[slot] = 1.0 / sy;
  if (b->k == b->m)
    b->first = (b->first + 1) % b->m; /* the oldest goes */
  else
    b->k++;
  mpgm_count(pb->ctx, MPGM_C_BFGS_UPDATES, 1);
}

int mpgm_bfgs_solve(mpgm_problem *pb, int reuse) {
  mpgm_linsys *ls = pb->ls;
  mpgm_bfgs *b = &ls->bfgs;
  mpgm_ctx *ctx = pb->ctx;
  const int n = pb->nodes.ndof, m = b->m;
  if (!reuse) mpgm_bfgs_reset(pb);
  if (reuse && b->have_prev) push_pair(pb, n);
  /* the point this correction starts from, for the next pair */
  memcpy(b->r_prev, ls->R, sizeof(double) * (size_t)n);
  gather_du(pb, b->du_prev);
  b->have_prev = 1;
  double alpha[MPGM_BFGS_PAIRS_MAX];
  memcpy(b->q, ls->R, sizeof(double) * (size_t)n);
  for (int j = b->k - 1; j >= 0; j--) {
    const int i = (b->first + j) % m;
    const double *s = b->S + (size_t)i * (size_t)n, *y = b->Y + (size_t)i * (size_t)n;
    alpha[j] = b->rho[i] * dot(s, b->q, n);
    axpy(-alpha[j], y, b->q, n);
  }
  MPGM_CALL(mpgm_solver_solve(ls->solver, ctx, b->q, ls->delta));
  if (reuse) mpgm_lowrank_apply(pb, ls->delta);
  for (int j = 0; j < b->k; j++) {
    const int i = (b->first + j) % m;
    const double *s = b->S + (size_t)i * (size_t)n, *y = b->Y + (size_t)i * (size_t)n;
    const double beta = b->rho[i] * dot(y, ls->delta, n);
    axpy(alpha[j] - beta, s, ls->delta, n);
  }
  return 0;
}
