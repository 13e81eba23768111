/* elastic_common.c -- shared isotropic elastic pieces (elastic_impl.h). */
#include <math.h>
#include <stdio.h>

#include "elastic_impl.h"

#if MPGM_DIM != 2
#error "materials/elastic_common.c is written for plane strain only (MPGM_DIM = 2)"
#endif

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

void mpgm_elastic_small(double lam, double mu, const double F[4], double sigma[4], double D[9]) {
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
