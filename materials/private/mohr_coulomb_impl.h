/* mohr_coulomb_impl.h -- private to materials/ (and its unit tests): the
 * Mohr-Coulomb return mapping in principal stress space
 * (docs/theory.md, section 15).
 *
 * Sign convention: tension positive; principal stresses sorted
 * s[0] >= s[1] >= s[2]. With k = (1 + sin phi) / (1 - sin phi) the yield
 * function of the sorted sextant is
 *   f(s) = k s[0] - s[2] - sc,   sc = 2 c cos phi / (1 - sin phi),
 * the plastic potential g(s) = m s[0] - s[2], m = (1 + sin psi) /
 * (1 - sin psi), the apex s = (sa, sa, sa), sa = c cot phi.
 */
#ifndef MPGM_MOHR_COULOMB_IMPL_H
#define MPGM_MOHR_COULOMB_IMPL_H

#include "mpgm_material.h"

/** Where the trial stress lies, i.e. which return was taken. */
typedef enum {
  MPGM_MC_ELASTIC = 0, /**< f <= 0: no return                          */
  MPGM_MC_PLANE = 1,   /**< to the plane f = 0                          */
  MPGM_MC_EDGE_12 = 2, /**< to the edge s1 = s2 (triaxial compression)  */
  MPGM_MC_EDGE_23 = 3, /**< to the edge s2 = s3 (triaxial extension)    */
  MPGM_MC_APEX = 4     /**< to the apex                                 */
} mpgm_mc_region;

/** Indices of the derived constants in mpgm_material.c after setup. */
enum {
  MPGM_MC_LAMBDA = 0, /**< Lame lambda [Pa]                    */
  MPGM_MC_MU = 1,     /**< shear modulus [Pa]                  */
  MPGM_MC_K = 2,      /**< (1 + sin phi) / (1 - sin phi)       */
  MPGM_MC_M = 3,      /**< (1 + sin psi) / (1 - sin psi)       */
  MPGM_MC_SC = 4,     /**< 2 c cos phi / (1 - sin phi) [Pa]    */
  MPGM_MC_APEXS = 5   /**< c cot phi [Pa]                      */
};

/** Yield function f [Pa] of principal stresses s (any order; tension
 *  positive): the largest of the six Mohr-Coulomb planes. */
double mpgm_mc_yield_principal(const mpgm_material *m, const double s[3]);

/** Return mapping in principal (Kirchhoff) stress space with the elastic
 *  law of m (Hencky: linear in the logarithmic strains).
 *  st   : trial principal stresses [Pa], sorted st[0] >= st[1] >= st[2]
 *  s    : out, returned principal stresses [Pa], sorted the same way
 *  dsdt : out (may be NULL), 3x3 row major d s / d st, the algorithmic
 *         tangent of the map (multiply by the elastic matrix for d s / d e)
 *  Returns the region (mpgm_mc_region). */
int mpgm_mc_return(const mpgm_material *m, const double st[3], double s[3], double dsdt[9]);

/** Eigen-decomposition of the symmetric 3x3 matrix S given by its Voigt
 *  components {xx, yy, zz, xy, yz, xz} (cyclic Jacobi, sym_eigen3.c):
 *  S = V diag(l) V^T, V row major with the eigenvectors as columns
 *  (V[3 r + i] = component r of vector i), l unsorted. The eigenvalues of a
 *  positive definite S keep relative accuracy. Returns 0, or -1 when S
 *  holds a NaN or Inf or the sweeps did not converge. */
int mpgm_sym3_eigen(const double S[6], double l[3], double V[9]);

#endif
