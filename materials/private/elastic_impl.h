/* elastic_impl.h -- private to materials/: the isotropic elastic pieces that
 * several laws share (E, nu validation; the small-strain linear law). */
#ifndef MPGM_ELASTIC_IMPL_H
#define MPGM_ELASTIC_IMPL_H

#include "mpgm_material.h"

/** Check m->param[0] = E > 0 and m->param[1] = nu in (-1, 0.5), store the
 *  Lame constants in m->c[0] (lambda) and m->c[1] (mu), mark the material
 *  symmetric and elastic. MPGM_ERR_INPUT with msg ("NAME: need ...") else. */
int mpgm_elastic_setup(mpgm_material *m, const char *name, char *msg, size_t msglen);

/** Linear law for grad u = F - I: sigma = lambda tr(eps) I + 2 mu eps,
 *  eps = sym(F - I); plane strain adds s_zz = lambda (eps_xx + eps_yy).
 *  D (if not NULL) the constant Voigt matrix with engineering shear. */
void mpgm_elastic_small(double lambda, double mu, const double F[MPGM_TENSOR],
                        double sigma[MPGM_NSTRESS], double D[MPGM_NTANGENT]);

/** The isotropic tangent l I (x) I + 2 s I_sym as the MPGM_NVOIGT Voigt
 *  matrix with engineering shear: l + 2 s and l in the normal block, s on
 *  the shear diagonal, 0 elsewhere. */
void mpgm_elastic_tangent(double l, double s, double D[MPGM_NTANGENT]);

#endif
