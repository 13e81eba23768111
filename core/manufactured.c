/* manufactured.c -- a run driven by a manufactured solution (scene
 * "manufactured"; Tran et al. 2019, section 4; docs/theory.md section 21):
 * the points start with the solution's velocity (and acceleration), every
 * force evaluation adds the body force m_p b(X_p, t) that makes the
 * solution exact, and the errors of eq 47 measure the run against it.
 *
 * The body force is a function of the material coordinate X_p (the
 * point's initial position) and of t, evaluated per point by
 * references/mms.c; it is what an effect costs when the scene calls for it
 * (pb->fx.manufactured) and nothing otherwise. */
#include <math.h>
#include <stdlib.h>

#include "mpgm_core_impl.h"

#if MPGM_DIM != 2
#error "core/manufactured.c is written for plane strain only (MPGM_DIM = 2)"
#endif

int mpgm_mms_setup(mpgm_problem *pb) {
  mpgm_points *P = &pb->pts;
  const mpgm_mms *m = &pb->scene->mms;
  MPGM_ALLOC(pb->ctx, pb->mms_b, MPGM_DIM * (size_t)P->n + 1);
  const int all = P->n + P->nprobe + P->nsurf;
  for (int p = 0; p < all; p++) { /* the solution's state at t = 0 */
    double u[MPGM_DIM], v[MPGM_DIM], a[MPGM_DIM], F[MPGM_TENSOR];
    mpgm_mms_motion(m, P->x0 + MPGM_DIM * p, 0.0, u, v, a, F);
    for (int c = 0; c < MPGM_DIM; c++) {
      P->v[MPGM_DIM * p + c] = v[c];
      P->a[MPGM_DIM * p + c] = a[c];
    }
    /* the velocity gradient dF/dt at t = 0 (F = I there), by a central
     * difference of the solution's F: CPLS's corner velocities */
    const double e = 1e-6 / mpgm_mms_omega(m);
    double Fp[MPGM_TENSOR], Fm[MPGM_TENSOR];
    mpgm_mms_motion(m, P->x0 + MPGM_DIM * p, e, NULL, NULL, NULL, Fp);
    mpgm_mms_motion(m, P->x0 + MPGM_DIM * p, -e, NULL, NULL, NULL, Fm);
    for (int i = 0; i < MPGM_TENSOR; i++) P->L[MPGM_TENSOR * p + i] = (Fp[i] - Fm[i]) / (2.0 * e);
  }
  return 0;
}

const double *mpgm_mms_forces(mpgm_problem *pb, double t) {
  const mpgm_points *P = &pb->pts;
  for (int p = 0; p < P->n; p++) mpgm_mms_body_force(&pb->scene->mms, P->x0 + MPGM_DIM * p, t, pb->mms_b + MPGM_DIM * p);
  return pb->mms_b;
}

int mpgm_problem_mms_errors(const mpgm_problem *pb, double err[3]) {
  err[0] = err[1] = err[2] = NAN;
  if (!pb->fx.manufactured) return 0;
  const mpgm_points *P = &pb->pts;
  const mpgm_mms *m = &pb->scene->mms;
  double su = 0.0, sv = 0.0, ss = 0.0;
  for (int p = 0; p < P->n; p++) { /* 2-D only: the in-plane stress {xx, yy, xy} */
    double u[MPGM_DIM], v[MPGM_DIM], s[4];
    mpgm_mms_motion(m, P->x0 + MPGM_DIM * p, pb->t, u, v, NULL, NULL);
    mpgm_mms_cauchy(m, P->x0 + MPGM_DIM * p, pb->t, s);
    const double *x = P->x + MPGM_DIM * p, *X = P->x0 + MPGM_DIM * p, *vp = P->v + MPGM_DIM * p;
    const double *sp = P->sigma + MPGM_NSTRESS * p;
    for (int c = 0; c < MPGM_DIM; c++) {
      su += pow(x[c] - X[c] - u[c], 2);
      sv += pow(vp[c] - v[c], 2);
    }
    ss += pow(sp[0] - s[0], 2) + pow(sp[1] - s[1], 2) + 2.0 * pow(sp[2] - s[2], 2);
  }
  if (P->n == 0) return 1;
  err[0] = sqrt(su / P->n);
  err[1] = sqrt(sv / P->n);
  err[2] = sqrt(ss / P->n);
  return 1;
}
