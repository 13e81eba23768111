/* krylov.c -- restarted GMRES, right-preconditioned, with the operator and
 * the preconditioner as functions (mpgm_krylov.h; docs/theory.md section
 * 18, "Iterative linear solvers"). */
#include "mpgm_krylov.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* the round-off floor of the normwise backward error (mpgm_krylov.h): a
 * direct solver reaches 1e-16 to 1e-15 there; on the cantilever's
 * tangents GMRES stalls at about 1e-16 */
#define ROUNDOFF (64.0 * DBL_EPSILON)

void mpgm_gmres_ws_free(mpgm_gmres_ws *ws) {
  free(ws->V); free(ws->H); free(ws->cs); free(ws->sn); free(ws->g); free(ws->y);
  free(ws->r); free(ws->w); free(ws->t); free(ws->bw); free(ws->xs);
  memset(ws, 0, sizeof *ws);
}

double mpgm_gmres_ws_bytes(int n, int m) {
  return ((double)(m + 1) * n + (double)(m + 1) * m + 4.0 * (m + 1) + 5.0 * n) * sizeof(double);
}

int mpgm_gmres_ws_alloc(mpgm_ctx *ctx, mpgm_gmres_ws *ws, int n, int restart) {
  mpgm_gmres_ws_free(ws);
  const int m = restart < n ? restart : n;
  MPGM_ALLOC(ctx, ws->V, (size_t)(m + 1) * n);
  MPGM_ALLOC(ctx, ws->H, (size_t)(m + 1) * m);
  MPGM_ALLOC(ctx, ws->cs, m + 1);
  MPGM_ALLOC(ctx, ws->sn, m + 1);
  MPGM_ALLOC(ctx, ws->g, m + 1);
  MPGM_ALLOC(ctx, ws->y, m + 1);
  MPGM_ALLOC(ctx, ws->r, n);
  MPGM_ALLOC(ctx, ws->w, n);
  MPGM_ALLOC(ctx, ws->t, n);
  MPGM_ALLOC(ctx, ws->bw, n);
  MPGM_ALLOC(ctx, ws->xs, n);
  ws->n = n;
  ws->m = m;
  return MPGM_OK;
}

static double dot(const double *a, const double *b, int n) {
  double s = 0.0;
  for (int i = 0; i < n; i++) s += a[i] * b[i];
  return s;
}

/* One GMRES cycle from the iterate xs with true residual r (norm beta):
 * at most m iterations (and no more than `left`); xs is updated. The
 * iterations done go to *its; returns the preconditioner's error code. */
static int cycle(mpgm_gmres_ws *ws, mpgm_ctx *ctx, const mpgm_krylov_op *op, double beta,
                 double target, int left, int *its) {
  const int n = ws->n, m = ws->m, ld = m + 1;
  double *V = ws->V, *H = ws->H, *g = ws->g;
  for (int i = 0; i < n; i++) V[i] = ws->r[i] / beta;
  memset(g, 0, (size_t)(m + 1) * sizeof(double));
  g[0] = beta;
  int k = 0;
  while (k < m && k < left) {
    const int j = k;
    double *vj1 = V + (size_t)(j + 1) * n, *h = H + (size_t)j * ld;
    MPGM_CALL(op->precond(op->user, ctx, V + (size_t)j * n, ws->t));
    op->matvec(op->user, ws->t, vj1);
    for (int i = 0; i <= j; i++) { /* modified Gram-Schmidt */
      const double *vi = V + (size_t)i * n;
      h[i] = dot(vj1, vi, n);
      for (int l = 0; l < n; l++) vj1[l] -= h[i] * vi[l];
    }
    const double hn = sqrt(dot(vj1, vj1, n));
    h[j + 1] = hn;
    for (int i = 0; i < j; i++) { /* the earlier rotations on the new column */
      const double a = h[i], b = h[i + 1];
      h[i] = ws->cs[i] * a + ws->sn[i] * b;
      h[i + 1] = -ws->sn[i] * a + ws->cs[i] * b;
    }
    const double a = h[j], b = h[j + 1], rho = hypot(a, b);
    ws->cs[j] = rho > 0.0 ? a / rho : 1.0;
    ws->sn[j] = rho > 0.0 ? b / rho : 0.0;
    h[j] = rho;
    h[j + 1] = 0.0;
    g[j + 1] = -ws->sn[j] * g[j];
    g[j] = ws->cs[j] * g[j];
    k = j + 1;
    if (!(fabs(g[k]) > target) || !(hn > 0.0)) break; /* converged, or the space is invariant */
    for (int l = 0; l < n; l++) vj1[l] /= hn;
  }
  /* y = R^-1 g (R: the rotated Hessenberg, upper triangular k x k) */
  for (int i = k - 1; i >= 0; i--) {
    double s = g[i];
    for (int l = i + 1; l < k; l++) s -= H[(size_t)l * ld + i] * ws->y[l];
    const double rii = H[(size_t)i * ld + i];
    ws->y[i] = rii != 0.0 ? s / rii : 0.0;
  }
  /* xs += M^-1 (V y) */
  memset(ws->w, 0, (size_t)n * sizeof(double));
  for (int i = 0; i < k; i++) {
    const double *vi = V + (size_t)i * n;
    for (int l = 0; l < n; l++) ws->w[l] += ws->y[i] * vi[l];
  }
  MPGM_CALL(op->precond(op->user, ctx, ws->w, ws->w));
  for (int l = 0; l < n; l++) ws->xs[l] += ws->w[l];
  *its = k;
  return MPGM_OK;
}

/* Normwise backward error of the iterate xs with true residual r:
 * |r| / (|A| |xs| + |b|) in infinity norms. */
static double backward_error(const mpgm_gmres_ws *ws, double anorm) {
  double rn = 0.0, xn = 0.0, bn = 0.0;
  for (int i = 0; i < ws->n; i++) {
    rn = fmax(rn, fabs(ws->r[i]));
    xn = fmax(xn, fabs(ws->xs[i]));
    bn = fmax(bn, fabs(ws->bw[i]));
  }
  const double den = anorm * xn + bn;
  return den > 0.0 ? rn / den : 0.0;
}

int mpgm_gmres(mpgm_gmres_ws *ws, mpgm_ctx *ctx, const mpgm_krylov_op *op, const double *b,
               double *x, double tol, int max_iter, mpgm_gmres_result *res) {
  const int n = ws->n;
  memcpy(ws->bw, b, (size_t)n * sizeof(double));
  memset(ws->xs, 0, (size_t)n * sizeof(double));
  *res = (mpgm_gmres_result){0};
  const double bnorm = sqrt(dot(ws->bw, ws->bw, n)), target = tol * bnorm;
  double beta = bnorm;
  int done = !(bnorm > 0.0), err = MPGM_OK;
  if (!isfinite(bnorm)) {
    res->relres = NAN;
  } else if (!done) {
    memcpy(ws->r, ws->bw, (size_t)n * sizeof(double));
    while (!done && res->iterations < max_iter) {
      int k = 0;
      err = cycle(ws, ctx, op, beta, target, max_iter - res->iterations, &k);
      res->iterations += k;
      if (err) break;
      const double prev = beta;
      op->matvec(op->user, ws->xs, ws->r); /* the true residual */
      for (int i = 0; i < n; i++) ws->r[i] = ws->bw[i] - ws->r[i];
      beta = sqrt(dot(ws->r, ws->r, n));
      if (!isfinite(beta)) break;
      done = beta <= target ||
             (op->anorm > 0.0 && beta > 0.5 * prev && backward_error(ws, op->anorm) <= ROUNDOFF);
    }
    res->relres = beta / bnorm;
  }
  res->converged = done && !err;
  memcpy(x, ws->xs, (size_t)n * sizeof(double));
  return err;
}
