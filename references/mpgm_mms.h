/* mpgm_mms.h -- the three manufactured solutions of Tran, Solowski, Berzins
 * & Guilkey (2019), CPLS MPM, section 4 (seed 004): axis-aligned vibration
 * (4.2), ring expansion (4.3) and generalized vortex (4.4). Derivation and
 * the misprints of the paper: docs/theory.md, section 21.
 *
 * Pure functions of the material point X [m] and the time t [s]; 2-D plane
 * strain (F_zz = 1), the compressible neo-Hookean law of
 * materials/neo_hookean.c (and 004 eq 46),
 *   sigma = (lambda ln J / J) 1 + (mu / J) (F F^T - 1),
 *   P = lambda ln J F^-T + mu (F - F^-T),
 * lambda, mu from E, nu as mpgm_lame has them. The body force b (per
 * unit mass, a function of X and t) makes the motion exact:
 *   rho0 a = Div_X P + rho0 b,  a = d2x/dt2 at fixed X.
 * Every motion starts from x = X, free of stress, with the initial velocity
 * v(X, 0) given below; omega is its angular frequency (mpgm_mms_omega),
 * c = sqrt(E / rho0).
 *
 * VIBRATION (4.2, eq 48; 1-D motion in the square 0 <= X, Y <= L):
 *   u = (A sin(2 pi X / L) sin(omega t), 0),  omega = pi c / L,
 *   F = diag(1 + (2 pi A / L) cos(2 pi X / L) sin(omega t), 1), J = F_xx.
 *   v(X, 0) = (A omega sin(2 pi X / L), 0).
 *   Boundaries: rollers on all four sides (u_x = 0 at X = 0, L; u_y = 0
 *   everywhere). None is traction-free: sigma_xx != 0 on X = 0, L and
 *   sigma_yy = lambda ln J / J != 0 on Y = 0, L (zero only for nu = 0);
 *   sigma_xy = 0 everywhere, so frictionless rollers carry exactly that.
 *   b = (b_x, 0), b_x = u_x [ k^2 (mu + (mu + lambda (1 - ln J)) / J^2) / rho0
 *   - omega^2 ], k = 2 pi / L. Period 2 L / c (0.02 s in the paper).
 *
 * RING (4.3, eqs 57-59; quarter ring ri <= R <= ro, 0 <= Theta <= pi/2):
 *   purely radial, u = U(R, t) E_R, U = A sin(omega t) g(R),
 *   omega = pi c / (ri + ro), g = c3 R^3 + c2 R^2 + c1 R with eq 59's
 *   c1 = -6 ri / (ro (ro - 3 ri)), c2 = 3 (ri + ro) / (ro^2 (ro - 3 ri)),
 *   c3 = -2 / (ro^2 (ro - 3 ri)): g'(ri) = g'(ro) = 0, g(ro) = 1.
 *   F = l1 E_R (x) E_R + l2 E_Th (x) E_Th, l1 = 1 + U', l2 = 1 + U / R.
 *   v(X, 0) = A omega g(R) E_R.
 *   Boundaries: rollers on the symmetry lines Y = 0 (u_y = 0) and X = 0
 *   (u_x = 0), where sigma_rt = 0. The curved faces have l1 = 1, so their
 *   traction is sigma_rr = lambda ln J / J: traction-free only for nu = 0
 *   (the paper's case); otherwise that normal traction must be applied.
 *   b = (-omega^2 U - D / rho0) E_R, D = (Div P)_R =
 *     [mu + (mu + lambda (1 - ln J)) / l1^2] A sin(omega t) g''(R)
 *     + (l1 - l2) / R [mu + (mu + lambda (1 - ln J)) / J].
 *   Period 2 (ri + ro) / c.
 *
 * VORTEX (4.4, eqs 60-64; full ring ri <= R <= ro):
 *   each circle R turns rigidly by alpha = A h(R) sin(omega t),
 *   omega = pi c / L (L = 1 m: 004's sin(c pi t)),
 *   h = (1 - q^2)^2, q = (R - (ri + ro)/2) / ((ro - ri)/2)
 *   (004 eq 62 for ri = 0.75, ro = 1.25), x = R (cos beta, sin beta),
 *   beta = Theta + alpha. F = Q(alpha) (1 + gamma E_Th (x) E_R),
 *   gamma = R dalpha/dR; J = 1; sigma = mu gamma (e_r (x) e_b + e_b (x) e_r)
 *   + mu gamma^2 e_b (x) e_b (current polar basis at beta).
 *   v(X, 0) = A omega h(R) (-Y, X).
 *   Boundaries: h = h' = 0 at ri and ro, so u = 0 and sigma = 0 there:
 *   both circles traction-free (holding them fixed is equally exact).
 *   b = b_r e_r + b_b e_b, s = sin(omega t),
 *     b_r = R A^2 [(mu / rho0) h'^2 s^2 - omega^2 h^2 cos^2(omega t)],
 *     b_b = -A s [R omega^2 h + (mu / rho0) (R h'' + 3 h')].
 *   Period 2 L / c.
 *
 * Parameters left 0 in mpgm_mms take the paper's values (below); nu is
 * used as given (0 is a valid value). X must lie in the body (R > 0 for
 * the ring and the vortex) and the motion must keep J > 0 (vibration:
 * 2 pi A < L; the paper's cases do).
 */
#ifndef MPGM_MMS_H
#define MPGM_MMS_H

#ifdef __cplusplus
extern "C" {
#endif

/** The manufactured solution. */
typedef enum {
  MPGM_MMS_VIBRATION = 0, /**< axis-aligned vibration, 004 section 4.2 */
  MPGM_MMS_RING = 1,      /**< ring expansion, 004 section 4.3         */
  MPGM_MMS_VORTEX = 2     /**< generalized vortex, 004 section 4.4      */
} mpgm_mms_kind;

/** One manufactured solution and its parameters (0: the paper's value). */
typedef struct mpgm_mms {
  mpgm_mms_kind kind;
  double A;    /**< amplitude: m (vibration, ring), rad (vortex);
                    0: the paper's large case 0.1 m, 0.1 m, 1 rad       */
  double E;    /**< Young's modulus [Pa]; 0: 1e7 (vibration, ring),
                    1e3 (vortex)                                       */
  double nu;   /**< Poisson's ratio [-], used as given; the issue's
                    cases: 0.3 (vibration, vortex), 0 (ring)           */
  double rho0; /**< reference density [kg/m^3]; 0: 1000                */
  double L;    /**< length [m]; vibration: side of the square and
                    wavelength; vortex: the length of omega = pi c / L;
                    unused by the ring; 0: 1                           */
  double ri;   /**< inner radius [m]; ring, vortex; 0: 0.4, 0.75         */
  double ro;   /**< outer radius [m]; ring, vortex; 0: 0.6, 1.25         */
} mpgm_mms;

/** Kind from its name: "vibration" | "ring" | "vortex". Returns 0, or
 *  MPGM_ERR_INPUT (unknown name or NULL; *kind untouched). */
int mpgm_mms_parse_kind(const char *name, mpgm_mms_kind *kind);

/** Fill *m with the case of `kind` (004 Tables 2-4, corrected):
 *  all fields explicit, A the large amplitude, nu 0.3 / 0 / 0.3. */
void mpgm_mms_init(mpgm_mms *m, mpgm_mms_kind kind);

/** Angular frequency omega [rad/s] of the motion (see above). */
double mpgm_mms_omega(const mpgm_mms *m);

/** Motion at material point X [m] and time t [s]: displacement u [m],
 *  velocity v [m/s], acceleration a [m/s^2] (d/dt at fixed X) and
 *  deformation gradient F (row major dx_i/dX_j, in-plane; F_zz = 1).
 *  Any output may be NULL. A kind outside mpgm_mms_kind gives NaN (so do
 *  mpgm_mms_cauchy and mpgm_mms_body_force). */
void mpgm_mms_motion(const mpgm_mms *m, const double X[2], double t, double u[2], double v[2],
                     double a[2], double F[4]);

/** Cauchy stress [Pa] {xx, yy, xy, zz} at X [m], t [s] (the neo-Hookean
 *  law at the F of mpgm_mms_motion, in closed form). */
void mpgm_mms_cauchy(const mpgm_mms *m, const double X[2], double t, double sig[4]);

/** Body force per unit mass [m/s^2] at X [m], t [s]: b = a - Div_X P /
 *  rho0, in closed form. Per unit mass, it is the same on the reference
 *  (rho0 dV) and the current configuration (rho dv): a material point p
 *  gets m_p b(X_p, t). */
void mpgm_mms_body_force(const mpgm_mms *m, const double X[2], double t, double b[2]);

#ifdef __cplusplus
}
#endif
#endif
