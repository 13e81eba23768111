/* mpgm_material.h -- the material plug-in family.
 *
 * A material turns a deformation (F, or I + grad u in small-strain analysis)
 * and the committed state of a point into the Cauchy stress and the spatial
 * tangent the core assembles (K_mat = sum_p B^T D B v_p).
 *
 * Layouts (mpgm_base.h), in the build's dimension:
 *   F, dF : MPGM_TENSOR entries, DIM x DIM row major; plane strain (DIM 2)
 *           {F11, F12, F21, F22} with F33 = 1; 3-D {F11, F12, F13, F21, ...}.
 *   sigma : MPGM_NSTRESS entries, Cauchy stress [Pa]: plane strain
 *           {s_xx, s_yy, s_xy, s_zz} (s_zz out of plane); 3-D the six
 *           Voigt components {xx, yy, zz, xy, yz, xz}.
 *   D     : MPGM_NVOIGT x MPGM_NVOIGT row major (3x3 or 6x6), Voigt order
 *           of mpgm_voigt_pair with engineering shear (2-D B = [dN/dx 0;
 *           0 dN/dy; dN/dy dN/dx]); Pa. For finite kinematics D is the
 *           spatial tangent of the Cauchy stress (c = J^-1 c_tau, c_tau the
 *           tangent of the Lie derivative of Kirchhoff stress), so the
 *           geometric stiffness is added separately by the core.
 * A material's nstate may depend on the dimension (it is the type's, and a
 * build has one dimension).
 *
 * Each implementation is one .c exporting a `const mpgm_material_type`;
 * the list of all of them is MPGM_MATERIAL_LIST in material_list.c.
 */
#ifndef MPGM_MATERIAL_H
#define MPGM_MATERIAL_H

#include "mpgm_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Kinematics of the analysis. */
typedef enum {
  MPGM_KIN_FINITE = 0, /**< updated Lagrangian, large deformation   */
  MPGM_KIN_SMALL = 1   /**< linear small-strain analysis           */
} mpgm_kinematics;


#define MPGM_MAT_MAXPARAM 8
#define MPGM_MAT_MAXCONST 8

typedef struct mpgm_material_type mpgm_material_type;

/** A material instance (one per named material in the scene). */
typedef struct mpgm_material {
  const mpgm_material_type *type;      /**< implementation               */
  char name[64];                       /**< name in the scene            */
  double density;                      /**< reference density [kg/m^3]   */
  double param[MPGM_MAT_MAXPARAM];     /**< in type->params order        */
  double c[MPGM_MAT_MAXCONST];         /**< derived constants (setup)    */
  int symmetric;   /**< 1 when the tangent D has major symmetry          */
  int plastic;     /**< 1 when the material runs a return mapping        */
} mpgm_material;

struct mpgm_material_type {
  const char *name;   /**< scene name, e.g. "neo_hookean"             */
  const char *doc;    /**< one line for docs                          */
  int nparam;         /**< entries of params                          */
  const mpgm_param_spec *params; /**< parameter table (not incl. density) */
  int nstate;         /**< state doubles per point (0 for elastic)    */
  int finite;         /**< 1 when usable with MPGM_KIN_FINITE          */
  /** Derive constants from m->param; set m->symmetric, m->plastic.
   *  Returns 0, or MPGM_ERR_INPUT with msg filled (bad combination). */
  int (*setup)(mpgm_material *m, char *msg, size_t msglen);
  /** Initial state of a point (may be NULL when nstate == 0). */
  void (*init_state)(const mpgm_material *m, double *state);
  /** Stress and tangent.
   *  kin     : MPGM_KIN_FINITE or MPGM_KIN_SMALL
   *  F       : total deformation gradient (finite), or I + grad u (small)
   *  dF      : increment over the step, F = dF F_n (finite; may be ignored)
   *  state_n : committed state (nstate doubles; NULL if nstate == 0)
   *  state   : out, trial state (may alias nothing; NULL if nstate == 0)
   *  sigma   : out, Cauchy stress (MPGM_NSTRESS: 2-D {xx, yy, xy, zz})
   *  D       : out, tangent, MPGM_NTANGENT entries (may be NULL: stress
   *            only)
   *  Returns 0, MPGM_ERR_JACOBIAN (det F <= 0) or another recoverable code. */
  int (*update)(const mpgm_material *m, int kin, const double F[MPGM_TENSOR],
                const double dF[MPGM_TENSOR], const double *state_n, double *state,
                double sigma[MPGM_NSTRESS], double D[MPGM_NTANGENT]);
  /* Optional operations (NULL when the material has no such notion). */
  /** Equivalent plastic strain [-] held in a state (output field eps_p). */
  double (*plastic_strain)(const mpgm_material *m, const double *state);
  /** Yield function [Pa] at the Kirchhoff stress tau (MPGM_NSTRESS, the
   *  layout of sigma; tau = J sigma; small kinematics: sigma); <= 0 inside
   *  the surface. */
  double (*yield)(const mpgm_material *m, const double tau[MPGM_NSTRESS]);
  /** Initial state of a point that carries the initial Cauchy stress s0
   *  (MPGM_NSTRESS) [Pa] at F = I: update() at F = I then returns s0, so
   *  the core does not add s0 as a separate prestress. Returns 0, or
   *  MPGM_ERR_INPUT with msg filled when s0 is not admissible (outside the
   *  yield surface). */
  int (*init_stress)(const mpgm_material *m, int kin, const double s0[MPGM_NSTRESS],
                     double *state, char *msg, size_t msglen);
};

/** Find an implementation by scene name; NULL if none. */
const mpgm_material_type *mpgm_material_type_find(const char *name);

/** The value of m's parameter `name` (its type's params table, e.g. "E"),
 *  NAN when the type has no such parameter. */
double mpgm_material_param(const mpgm_material *m, const char *name);

/** All implementations, NULL-terminated (for docs and error messages). */
const mpgm_material_type *const *mpgm_material_types(void);

/** Lame constants from E [Pa] and nu. */
static inline void mpgm_lame(double E, double nu, double *lambda, double *mu) {
  *lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  *mu = E / (2.0 * (1.0 + nu));
}

#ifdef __cplusplus
}
#endif
#endif
