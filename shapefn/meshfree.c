/* meshfree.c -- helpers shared by the meshfree shape-function kinds:
 * failure reporting, query checks, the small SPD inverse. See
 * mpgm_shapefn_impl.h. */
#include "mpgm_shapefn_impl.h"

#include <math.h>
#include <string.h>

int mpgm_shape_fail(const mpgm_shape_query *q, double *N, double *dN, int code, int reason) {
  if (q->n > 0 && q->n <= MPGM_SHAPE_MAXNODE) {
    if (N) memset(N, 0, sizeof(double) * (size_t)q->n);
    if (dN) memset(dN, 0, sizeof(double) * MPGM_DIM * (size_t)q->n);
  }
  if (q->info) {
    q->info->reason = reason;
    q->info->msg = mpgm_shape_reason_str(reason);
  }
  return code;
}

void mpgm_shape_ok(const mpgm_shape_query *q, int iterations, int nsupport, double cond,
                   double residual) {
  mpgm_shape_info *in = q->info;
  if (!in) return;
  in->reason = MPGM_SHAPE_OK;
  in->msg = mpgm_shape_reason_str(MPGM_SHAPE_OK);
  in->iterations = iterations;
  in->nsupport = nsupport;
  in->cond = cond;
  in->residual = residual;
}

int mpgm_shape_check_cloud(const mpgm_shape_query *q, double *N, double *dN) {
  if (q->info) memset(q->info, 0, sizeof *q->info);
  if (q->n < 1 || q->n > MPGM_SHAPE_MAXNODE || !q->xn || !q->par || !N || !dN)
    return mpgm_shape_fail(q, N, dN, MPGM_ERR_INPUT, MPGM_SHAPE_BAD_INPUT);
  for (int d = 0; d < MPGM_DIM; d++)
    if (!isfinite(q->xp[d])) return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_BAD_INPUT);
  return 0;
}

int mpgm_spd_inverse(int m, const double *A, double *Ainv) {
  double L[36], Y[36];
  /* A = L L^T */
  for (int j = 0; j < m; j++) {
    double d = A[j * m + j];
    for (int k = 0; k < j; k++) d -= L[j * m + k] * L[j * m + k];
    if (!(d > 0.0)) return 1;
    const double ljj = sqrt(d);
    L[j * m + j] = ljj;
    for (int i = j + 1; i < m; i++) {
      double s = A[i * m + j];
      for (int k = 0; k < j; k++) s -= L[i * m + k] * L[j * m + k];
      L[i * m + j] = s / ljj;
    }
  }
  /* Y = L^-1 (lower triangular), then Ainv = Y^T Y */
  for (int j = 0; j < m; j++) {
    for (int i = 0; i < j; i++) Y[i * m + j] = 0.0;
    Y[j * m + j] = 1.0 / L[j * m + j];
    for (int i = j + 1; i < m; i++) {
      double s = 0.0;
      for (int k = j; k < i; k++) s -= L[i * m + k] * Y[k * m + j];
      Y[i * m + j] = s / L[i * m + i];
    }
  }
  for (int i = 0; i < m; i++)
    for (int j = i; j < m; j++) {
      double s = 0.0;
      for (int k = j; k < m; k++) s += Y[k * m + i] * Y[k * m + j];
      Ainv[i * m + j] = Ainv[j * m + i] = s;
    }
  return 0;
}

void mpgm_shape_params_for_radius(const mpgm_shape_params *base, double r0, double r,
                                  mpgm_shape_params *out) {
  *out = *base;
  if (!(r > r0) || !(base->h > 0.0)) return;
  const double gamma = mpgm_shape_dflt(base->gamma, MPGM_LME_GAMMA);
  const double rr = r * (1.0 + 1e-12) / base->h; /* round-off must not cut the farthest node */
  out->radius = r * (1.0 + 1e-12);
  out->tol_support = fmax(exp(-gamma * rr * rr), 1e-300);
}

int mpgm_shape_eval_retry(const mpgm_shapefn_type *t, const mpgm_shape_query *q, double *N,
                          double *dN, long *cold) {
  int err = t->eval(q, N, dN);
  double *lam = q->lambda;
  int warm = 0;
  for (int d = 0; lam && d < MPGM_DIM; d++) warm |= lam[d] != 0.0;
  if (err == MPGM_ERR_SHAPE && warm) {
    for (int d = 0; d < MPGM_DIM; d++) lam[d] = 0.0;
    if (cold) (*cold)++;
    err = t->eval(q, N, dN);
  }
  return err;
}
