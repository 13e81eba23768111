/* neo_hookean.c -- compressible neo-Hookean hyperelasticity.
 *
 * Stored energy (Simo & Pister form)
 *   W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2,
 * Cauchy stress (plane strain: F33 = 1, b = F F^T, b33 = 1)
 *   sigma = (lambda ln J / J) I + (mu / J) (b - I),  s_zz = lambda ln J / J,
 * spatial tangent of the Cauchy stress, c = J^-1 c_tau with
 *   c_tau = lambda I (x) I + 2 (mu - lambda ln J) I_sym,
 * i.e. in Voigt {xx, yy, xy} with engineering shear
 *   D = [[l + 2 m, l, 0], [l, l + 2 m, 0], [0, 0, m]],
 *   l = lambda / J,  m = (mu - lambda ln J) / J.
 *
 * In 3-D b is the full 3x3 F F^T, sigma has its six Voigt components and
 * D is the 6x6 form of the same c: l + 2 m, l in the normal block, m on
 * the shear diagonal.
 *
 * Small-strain analysis uses the linear-elastic limit (identical to
 * linear_elastic). Constants after setup: c[0] = lambda, c[1] = mu [Pa].
 */
#include "elastic_impl.h"

#include <math.h>
#include <stdio.h>


enum { P_E = 0, P_NU = 1 };
enum { C_LAMBDA = 0, C_MU = 1 };

static const mpgm_param_spec params[] = {
    {"E", "Pa", NAN, 0.0, INFINITY, 1, 1,
     "Young's modulus of the linearised law (required)"},
    {"nu", "-", NAN, -1.0, 0.5, 1, 1,
     "Poisson's ratio of the linearised law (required)"},
};

/* Check E and nu and store the Lame constants. */
static int setup(mpgm_material *m, char *msg, size_t msglen) {
  return mpgm_elastic_setup(m, "neo_hookean", msg, msglen);
}

/* Cauchy stress and spatial tangent for the total deformation gradient F
 * (finite) or the linear limit (small). det F <= 0 (or not finite):
 * MPGM_ERR_JACOBIAN, outputs left untouched. */
static int update(const mpgm_material *m, int kin, const double F[MPGM_TENSOR],
                  const double dF[MPGM_TENSOR], const double *state_n, double *state,
                  double sigma[MPGM_NSTRESS], double D[MPGM_NTANGENT]) {
  (void)dF;
  (void)state_n;
  (void)state;
  const double lam = m->c[C_LAMBDA], mu = m->c[C_MU];
  if (kin == MPGM_KIN_SMALL) {
    mpgm_elastic_small(lam, mu, F, sigma, D);
    return MPGM_OK;
  }
  if (kin != MPGM_KIN_FINITE) return MPGM_ERR_UNSUPPORTED;

#if MPGM_DIM == 2
  const double J = F[0] * F[3] - F[1] * F[2];
  if (!(J > 0.0) || !isfinite(J)) return MPGM_ERR_JACOBIAN;
  const double lnJ = log(J), iJ = 1.0 / J;
  /* b - I, in-plane; (b - I)_zz = 0 */
  const double bxx = F[0] * F[0] + F[1] * F[1] - 1.0;
  const double byy = F[2] * F[2] + F[3] * F[3] - 1.0;
  const double bxy = F[0] * F[2] + F[1] * F[3];
  const double p = lam * lnJ * iJ, g = mu * iJ;
  sigma[0] = p + g * bxx;
  sigma[1] = p + g * byy;
  sigma[2] = g * bxy;
  sigma[3] = p;
  if (D) {
    const double l = lam * iJ, s = (mu - lam * lnJ) * iJ;
    D[0] = l + 2.0 * s; D[1] = l;           D[2] = 0.0;
    D[3] = l;           D[4] = l + 2.0 * s; D[5] = 0.0;
    D[6] = 0.0;         D[7] = 0.0;         D[8] = s;
  }
#else
  const double J = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
                   F[2] * (F[3] * F[7] - F[4] * F[6]);
  if (!(J > 0.0) || !isfinite(J)) return MPGM_ERR_JACOBIAN;
  const double lnJ = log(J), iJ = 1.0 / J;
  const double p = lam * lnJ * iJ, g = mu * iJ;
  for (int k = 0; k < MPGM_NVOIGT; k++) {
    const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
    /* (b - I)_ab, b = F F^T */
    const double bab = F[3 * a] * F[3 * b] + F[3 * a + 1] * F[3 * b + 1] +
                       F[3 * a + 2] * F[3 * b + 2] - (a == b ? 1.0 : 0.0);
    sigma[k] = (a == b ? p : 0.0) + g * bab;
  }
  if (D) mpgm_elastic_tangent(lam * iJ, (mu - lam * lnJ) * iJ, D);
#endif
  return MPGM_OK;
}

/** Compressible neo-Hookean solid (plane strain or 3-D); params E [Pa], nu [-] of
 *  the linearised law. Finite and small kinematics; det F <= 0 returns
 *  MPGM_ERR_JACOBIAN. */
const mpgm_material_type mpgm_material_neo_hookean = {
    .name = "neo_hookean",
    .doc = "compressible neo-Hookean hyperelasticity (linear limit in small "
           "strain)",
    .nparam = (int)(sizeof(params) / sizeof(params[0])),
    .params = params,
    .nstate = 0,
    .finite = 1,
    .setup = setup,
    .init_state = NULL,
    .update = update,
};
