/* elastic_common.c -- shared isotropic elastic pieces (elastic_impl.h). */
#include <math.h>
#include <stdio.h>

#include "elastic_impl.h"


int mpgm_elastic_setup(mpgm_material *m, const char *name, char *msg, size_t msglen) {
  const double E = m->param[0], nu = m->param[1];
  if (!(E > 0.0 && isfinite(E)) || !(nu > -1.0 && nu < 0.5)) {
    if (msg && msglen)
      snprintf(msg, msglen, "%s: need E > 0 and -1 < nu < 0.5 (E = %g, nu = %g)", name, E, nu);
    return MPGM_ERR_INPUT;
  }
  mpgm_lame(E, nu, &m->c[0], &m->c[1]);
  m->symmetric = 1;
  m->plastic = 0;
  return MPGM_OK;
}

#if MPGM_DIM == 2
void mpgm_elastic_small(double lam, double mu, const double F[MPGM_TENSOR],
                        double sigma[MPGM_NSTRESS], double D[MPGM_NTANGENT]) {
  const double exx = F[0] - 1.0, eyy = F[3] - 1.0;
  const double exy = 0.5 * (F[1] + F[2]); /* tensor shear strain */
  const double ltr = lam * (exx + eyy);
  sigma[0] = ltr + 2.0 * mu * exx;
  sigma[1] = ltr + 2.0 * mu * eyy;
  sigma[2] = 2.0 * mu * exy;
  sigma[3] = ltr;
  if (D) {
    D[0] = lam + 2.0 * mu; D[1] = lam;            D[2] = 0.0;
    D[3] = lam;            D[4] = lam + 2.0 * mu; D[5] = 0.0;
    D[6] = 0.0;            D[7] = 0.0;            D[8] = mu;
  }
}
#else
void mpgm_elastic_small(double lam, double mu, const double F[MPGM_TENSOR],
                        double sigma[MPGM_NSTRESS], double D[MPGM_NTANGENT]) {
  const double ltr = lam * (F[0] + F[4] + F[8] - 3.0);
  for (int k = 0; k < MPGM_NVOIGT; k++) {
    const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
    /* tensor strain component (a, b) of sym(F - I) */
    const double e = a == b ? F[4 * a] - 1.0 : 0.5 * (F[3 * a + b] + F[3 * b + a]);
    sigma[k] = (a == b ? ltr : 0.0) + 2.0 * mu * e;
  }
  if (D) mpgm_elastic_tangent(lam, mu, D);
}
#endif

void mpgm_elastic_tangent(double l, double s, double D[MPGM_NTANGENT]) {
  for (int i = 0; i < MPGM_NTANGENT; i++) D[i] = 0.0;
  for (int i = 0; i < MPGM_DIM; i++) {
    for (int j = 0; j < MPGM_DIM; j++) D[MPGM_NVOIGT * i + j] = l;
    D[(MPGM_NVOIGT + 1) * i] = l + 2.0 * s;
  }
  for (int k = MPGM_DIM; k < MPGM_NVOIGT; k++) D[(MPGM_NVOIGT + 1) * k] = s;
}
