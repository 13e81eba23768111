/* linear_elastic.c -- isotropic linear elasticity, small strain only.
 *
 *   eps   = sym(F - I)            (F = I + grad u in small-strain analysis)
 *   sigma = lambda tr(eps) I + 2 mu eps,   plane strain: eps_zz = 0, so
 *   s_zz  = lambda (eps_xx + eps_yy)
 *   D     = [[lambda + 2 mu, lambda, 0], [lambda, lambda + 2 mu, 0],
 *            [0, 0, mu]]      (Voigt {xx, yy, xy}, engineering shear)
 * In 3-D eps has all six components and D is the 6x6 matrix with
 * lambda + 2 mu, lambda in the normal block and mu on the shear diagonal.
 *
 * Constants after setup: c[0] = lambda [Pa], c[1] = mu [Pa].
 */
#include "elastic_impl.h"

#include <math.h>
#include <stdio.h>


enum { P_E = 0, P_NU = 1 };
enum { C_LAMBDA = 0, C_MU = 1 };

static const mpgm_param_spec params[] = {
    {"E", "Pa", NAN, 0.0, INFINITY, 1, 1, "Young's modulus (required)"},
    {"nu", "-", NAN, -1.0, 0.5, 1, 1, "Poisson's ratio (required)"},
};

/* Check E and nu (the scene loader checks ranges too; a direct caller may
 * not) and store the Lame constants. */
static int setup(mpgm_material *m, char *msg, size_t msglen) {
  return mpgm_elastic_setup(m, "linear_elastic", msg, msglen);
}

/* Stress and constant tangent of the linear law for grad u = F - I.
 * Finite kinematics is not provided: MPGM_ERR_UNSUPPORTED. */
static int update(const mpgm_material *m, int kin, const double F[MPGM_TENSOR],
                  const double dF[MPGM_TENSOR], const double *state_n, double *state,
                  double sigma[MPGM_NSTRESS], double D[MPGM_NTANGENT]) {
  (void)dF;
  (void)state_n;
  (void)state;
  if (kin != MPGM_KIN_SMALL) return MPGM_ERR_UNSUPPORTED;
  mpgm_elastic_small(m->c[C_LAMBDA], m->c[C_MU], F, sigma, D);
  return MPGM_OK;
}

/** Isotropic linear elasticity (small strain; plane strain or 3-D); params E [Pa],
 *  nu [-]. update() returns MPGM_ERR_UNSUPPORTED for MPGM_KIN_FINITE. */
const mpgm_material_type mpgm_material_linear_elastic = {
    .name = "linear_elastic",
    .doc = "isotropic linear elasticity, small strain only",
    .nparam = (int)(sizeof(params) / sizeof(params[0])),
    .params = params,
    .nstate = 0,
    .finite = 0,
    .setup = setup,
    .init_state = NULL,
    .update = update,
};
