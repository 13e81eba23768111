/* elastic_impl.h -- private to materials/: the isotropic elastic pieces that
 * several laws share (E, nu validation; the plane-strain linear law). */
#ifndef MPGM_ELASTIC_IMPL_H
#define MPGM_ELASTIC_IMPL_H

#include "mpgm_material.h"

/** Check m->param[0] = E > 0 and m->param[1] = nu in (-1, 0.5), store the
 *  Lame constants in m->c[0] (lambda) and m->c[1] (mu), mark the material
 *  symmetric and elastic. MPGM_ERR_INPUT with msg ("NAME: need ...") else. */
int mpgm_elastic_setup(mpgm_material *m, const char *name, char *msg, size_t msglen);

/** Plane-strain linear law for grad u = F - I: sigma = lambda tr(eps) I +
 *  2 mu eps with s_zz = lambda (eps_xx + eps_yy); D (if not NULL) the
 *  constant Voigt matrix with engineering shear. */
void mpgm_elastic_small(double lambda, double mu, const double F[4], double sigma[4],
                        double D[9]);

#endif
