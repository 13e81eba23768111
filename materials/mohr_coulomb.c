/* mohr_coulomb.c -- Mohr-Coulomb elastoplasticity at finite strain
 * (docs/theory.md, section 15).
 *
 * Multiplicative split F = F_e F_p; the elastic law is Hencky's: the
 * Kirchhoff stress is linear in the logarithmic elastic strain
 * e = 1/2 ln b_e, tau = lambda tr(e) I + 2 mu e. A step starts from the
 * trial b_e = dF b_e,n dF^T (plastic flow frozen), returns the principal
 * trial Kirchhoff stresses to the Mohr-Coulomb surface (mohr_coulomb_return.c)
 * and sets b_e from the returned logarithmic strains (exponential map:
 * b_e = exp(2 e_e), coaxial with the trial). Small kinematics uses the same
 * return on e_tr = eps - eps_p.
 *
 * State (MPGM_NSTRESS + 1 doubles per point: 5 in plane strain, 7 in 3-D):
 *   [0..NSTRESS-1] finite: b_e in the stress layout (2-D {xx, yy, xy, zz},
 *          3-D {xx, yy, zz, xy, yz, xz}, tensor components);
 *          small : its linearisation at F = I, I - 2 eps_p, same layout
 *          (so init_state = I serves both kinematics);
 *   [NSTRESS] equivalent plastic strain, the sum over steps of
 *          sqrt(2/3 |d eps_p|^2) (d eps_p: principal plastic log strains).
 *
 * Plane strain decomposes the in-plane 2x2 block in closed form (z is a
 * principal direction); 3-D decomposes the full 3x3 b_e by Jacobi
 * rotations (sym_eigen3.c) and rotates the principal tangent with the 6x6
 * Voigt transformation of its eigenvectors. The principal part (predictor,
 * return, elastic strains of the result) is the same code in both.
 *
 * Parameters: E, nu, c [Pa], phi, psi [degrees]; 0 < phi < 90, 0 <= psi <=
 * phi. The tangent is unsymmetric unless psi = phi.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "elastic_impl.h"
#include "mohr_coulomb_impl.h"

enum { P_E = 0, P_NU = 1, P_C = 2, P_PHI = 3, P_PSI = 4 };
/* state: b_e (or I - 2 eps_p) in the stress layout, then eps_p */
enum { S_B = 0, S_EPSP = MPGM_NSTRESS, NSTATE = MPGM_NSTRESS + 1 };

static const double DEG = 3.14159265358979323846 / 180.0;

static const mpgm_param_spec params[] = {
    {"E", "Pa", NAN, 0.0, INFINITY, 1, 1, "Young's modulus of the Hencky law (required)"},
    {"nu", "-", NAN, -1.0, 0.5, 1, 1, "Poisson's ratio (required)"},
    {"c", "Pa", NAN, 0.0, INFINITY, 0, 1, "cohesion (required; 0 allowed)"},
    {"phi", "deg", NAN, 0.0, 90.0, 1, 1, "friction angle, 0 < phi < 90 (required)"},
    {"psi", "deg", 0.0, 0.0, 90.0, 0, 1, "dilatancy angle, 0 <= psi <= phi (default 0)"},
};

/* Elastic constants, the cone's slopes, its apex; the tangent is symmetric
 * only for associated flow. */
static int setup(mpgm_material *m, char *msg, size_t msglen) {
  MPGM_CALL(mpgm_elastic_setup(m, "mohr_coulomb", msg, msglen));
  const double c = m->param[P_C], phi = m->param[P_PHI], psi = m->param[P_PSI];
  if (!(c >= 0.0 && isfinite(c)) || !(phi > 0.0 && phi < 90.0) || !(psi >= 0.0 && psi <= phi)) {
    if (msg && msglen)
      snprintf(msg, msglen,
               "mohr_coulomb: need c >= 0, 0 < phi < 90 and 0 <= psi <= phi degrees "
               "(c = %g Pa, phi = %g, psi = %g)", c, phi, psi);
    return MPGM_ERR_INPUT;
  }
  const double sp = sin(phi * DEG), sq = sin(psi * DEG);
  m->c[MPGM_MC_K] = (1.0 + sp) / (1.0 - sp);
  m->c[MPGM_MC_M] = (1.0 + sq) / (1.0 - sq);
  m->c[MPGM_MC_SC] = 2.0 * c * cos(phi * DEG) / (1.0 - sp);
  m->c[MPGM_MC_APEXS] = c / tan(phi * DEG);
  m->symmetric = psi == phi;
  m->plastic = 1;
  return MPGM_OK;
}

/* Hencky predictor, return and elastic strains of the result in principal
 * space: e_tr the principal trial (log) strains; tau the returned principal
 * Kirchhoff stresses, a = d tau / d e_tr (3x3 row major, own order), ee the
 * elastic strains of tau, deps the increment of the equivalent plastic
 * strain. */
static void principal_step(const mpgm_material *m, const double e_tr[3], double tau[3],
                           double a[9], double ee[3], double *deps) {
  const double lam = m->c[MPGM_MC_LAMBDA], mu = m->c[MPGM_MC_MU];
  const double tr = lam * (e_tr[0] + e_tr[1] + e_tr[2]);
  double tt[3];
  for (int i = 0; i < 3; i++) tt[i] = tr + 2.0 * mu * e_tr[i];
  /* sort descending: the permutation p takes sorted -> own index */
  int p[3] = {0, 1, 2};
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2 - i; j++)
      if (tt[p[j]] < tt[p[j + 1]]) {
        const int q = p[j];
        p[j] = p[j + 1];
        p[j + 1] = q;
      }
  const double st[3] = {tt[p[0]], tt[p[1]], tt[p[2]]};
  double ss[3], dsdt[9];
  const int region = mpgm_mc_return(m, st, ss, dsdt);
  for (int i = 0; i < 3; i++) tau[p[i]] = ss[i];
  /* a = d tau / d e_tr = (d s / d st) D_e, in the own order */
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      const double rs = dsdt[3 * i] + dsdt[3 * i + 1] + dsdt[3 * i + 2];
      a[3 * p[i] + p[j]] = lam * rs + 2.0 * mu * dsdt[3 * i + j];
    }
  /* elastic strains of the returned stress, the plastic increment */
  if (region == MPGM_MC_ELASTIC) {
    memcpy(ee, e_tr, sizeof(double) * 3);
    *deps = 0.0;
    return;
  }
  const double K3 = 3.0 * lam + 2.0 * mu;
  const double ptr = (tau[0] + tau[1] + tau[2]) / K3;
  double d2 = 0.0;
  for (int i = 0; i < 3; i++) {
    ee[i] = (tau[i] - lam * ptr) / (2.0 * mu);
    const double d = e_tr[i] - ee[i];
    d2 += d * d;
  }
  *deps = sqrt(2.0 / 3.0 * d2);
}

static double plastic_strain(const mpgm_material *m, const double *state) {
  (void)m;
  return state[S_EPSP];
}

#if MPGM_DIM == 2
static void init_state(const mpgm_material *m, double *state) {
  (void)m;
  const double s[NSTATE] = {1.0, 1.0, 0.0, 1.0, 0.0};
  memcpy(state, s, sizeof s);
}

/* Eigen-decomposition of the symmetric 2x2 {xx, yy, xy}: l[0] >= l[1],
 * first eigenvector (cs[0], cs[1]), the second (-cs[1], cs[0]). */
static void eig2(const double a[3], double l[2], double cs[2]) {
  const double h = 0.5 * (a[0] - a[1]), mid = 0.5 * (a[0] + a[1]);
  const double R = hypot(h, a[2]);
  l[0] = mid + R;
  l[1] = mid - R;
  const double th = 0.5 * atan2(a[2], h);
  cs[0] = cos(th);
  cs[1] = sin(th);
}

/* The rest of a step once the principal trial strains e_tr (in-plane 0, 1
 * along (c, s), (-s, c); 2 out of plane) are known: Hencky predictor,
 * return, stress, state and tangent. finite: J, x = e_tr[0] - e_tr[1] for
 * the spin term; small: x as well. */
typedef struct trial {
  double e[3];   /* principal trial log strains (small: strains)      */
  double c, s;   /* in-plane principal direction                      */
  double x;      /* e[0] - e[1], computed without cancellation        */
  double J;      /* det F (finite), 1 (small)                         */
  int finite;
} trial;

/* Cauchy stress, the 3x3 Voigt tangent D from the principal results. */
static void spatial(const trial *t, const double tau[3], const double a[9],
                    double sigma[4], double D[9]) {
  const double c = t->c, s = t->s, iJ = 1.0 / t->J;
  sigma[0] = (c * c * tau[0] + s * s * tau[1]) * iJ;
  sigma[1] = (s * s * tau[0] + c * c * tau[1]) * iJ;
  sigma[2] = c * s * (tau[0] - tau[1]) * iJ;
  sigma[3] = tau[2] * iJ;
  if (!D) return;
  /* (tau_0 - tau_1) / x: the return is linear in e_tr inside a region and
   * symmetric in e_0, e_1, so the ratio equals its limit there */
  const double ratio = fabs(t->x) > 1e-6 ? (tau[0] - tau[1]) / t->x
                                          : 0.5 * (a[0] - a[3] + a[4] - a[1]);
  double Ap[4], G;
  if (t->finite) { /* c_tau: a - 2 tau_i delta_ij; spin term of b_tr */
    const double xc = fabs(t->x) > 1e-8 ? t->x / tanh(t->x) : 1.0;
    Ap[0] = a[0] - 2.0 * tau[0]; Ap[1] = a[1];
    Ap[2] = a[3];                Ap[3] = a[4] - 2.0 * tau[1];
    G = ratio * xc - (tau[0] + tau[1]);
  } else {
    Ap[0] = a[0]; Ap[1] = a[1]; Ap[2] = a[3]; Ap[3] = a[4];
    G = ratio;
  }
  /* principal Voigt block [[A, 0], [0, G/2]] rotated: D = Rs Dp Re */
  const double cc = c * c, ss = s * s, cs = c * s;
  const double Re[9] = {cc, ss, cs, ss, cc, -cs, -2.0 * cs, 2.0 * cs, cc - ss};
  const double Rs[9] = {cc, ss, -2.0 * cs, ss, cc, 2.0 * cs, cs, -cs, cc - ss};
  const double Dp[9] = {Ap[0], Ap[1], 0.0, Ap[2], Ap[3], 0.0, 0.0, 0.0, 0.5 * G};
  double T[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      T[3 * i + j] = Dp[3 * i] * Re[j] + Dp[3 * i + 1] * Re[3 + j] + Dp[3 * i + 2] * Re[6 + j];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      D[3 * i + j] =
          (Rs[3 * i] * T[j] + Rs[3 * i + 1] * T[3 + j] + Rs[3 * i + 2] * T[6 + j]) * iJ;
}

/* Stress, state and tangent (finite: Hencky/exponential map on b_e;
 * small: the same return on eps - eps_p). det F <= 0: MPGM_ERR_JACOBIAN,
 * outputs untouched. */
static int update(const mpgm_material *m, int kin, const double F[4], const double dF[4],
                  const double *state_n, double *state, double sigma[4], double D[9]) {
  trial t;
  double l[2], cs[2];
  if (kin == MPGM_KIN_FINITE) {
    const double J = F[0] * F[3] - F[1] * F[2], Jd = dF[0] * dF[3] - dF[1] * dF[2];
    if (!(J > 0.0) || !isfinite(J) || !(Jd > 0.0) || !isfinite(Jd)) return MPGM_ERR_JACOBIAN;
    /* b_tr = dF b_n dF^T (in plane); b_tr,zz = b_n,zz */
    const double bx = state_n[0], by = state_n[1], bs = state_n[2];
    const double A0 = dF[0] * bx + dF[1] * bs, A1 = dF[0] * bs + dF[1] * by;
    const double A2 = dF[2] * bx + dF[3] * bs, A3 = dF[2] * bs + dF[3] * by;
    const double b[3] = {A0 * dF[0] + A1 * dF[1], A2 * dF[2] + A3 * dF[3],
                         A0 * dF[2] + A1 * dF[3]};
    eig2(b, l, cs);
    const double det = b[0] * b[1] - b[2] * b[2];
    if (!(l[0] > 0.0) || !(det > 0.0) || !(state_n[3] > 0.0)) return MPGM_ERR_JACOBIAN;
    l[1] = det / l[0]; /* the small eigenvalue without cancellation */
    t.e[0] = 0.5 * log(l[0]);
    t.e[1] = 0.5 * log(l[1]);
    t.e[2] = 0.5 * log(state_n[3]);
    t.x = 0.5 * log1p((l[0] - l[1]) / l[1]);
    t.J = J;
    t.finite = 1;
  } else if (kin == MPGM_KIN_SMALL) {
    /* e_tr = eps - eps_p, eps_p = (I - state) / 2 */
    const double e[3] = {F[0] - 1.0 + 0.5 * (state_n[0] - 1.0),
                         F[3] - 1.0 + 0.5 * (state_n[1] - 1.0),
                         0.5 * (F[1] + F[2]) + 0.5 * state_n[2]};
    eig2(e, l, cs);
    t.e[0] = l[0];
    t.e[1] = l[1];
    t.e[2] = 0.5 * (state_n[3] - 1.0);
    t.x = l[0] - l[1];
    t.J = 1.0;
    t.finite = 0;
  } else {
    return MPGM_ERR_UNSUPPORTED;
  }
  t.c = cs[0];
  t.s = cs[1];
  double tau[3], a[9], ee[3], deps;
  principal_step(m, t.e, tau, a, ee, &deps);
  if (!(isfinite(tau[0]) && isfinite(tau[1]) && isfinite(tau[2]))) return MPGM_ERR_RETURN_MAP;
  spatial(&t, tau, a, sigma, D);
  if (state) {
    const double cc = t.c * t.c, ss = t.s * t.s, sc = t.c * t.s;
    double B[3];
    if (t.finite) {
      for (int i = 0; i < 3; i++) B[i] = exp(2.0 * ee[i]);
    } else { /* I - 2 eps_p = I - 2 (eps - e_e), principal along (c, s) */
      const double eps[4] = {F[0] - 1.0, F[3] - 1.0, 0.5 * (F[1] + F[2]), 0.0};
      const double exx = cc * ee[0] + ss * ee[1], eyy = ss * ee[0] + cc * ee[1];
      const double exy = sc * (ee[0] - ee[1]);
      state[0] = 1.0 - 2.0 * (eps[0] - exx);
      state[1] = 1.0 - 2.0 * (eps[1] - eyy);
      state[2] = -2.0 * (eps[2] - exy);
      state[3] = 1.0 + 2.0 * ee[2];
      state[S_EPSP] = state_n[S_EPSP] + deps;
      return MPGM_OK;
    }
    state[0] = cc * B[0] + ss * B[1];
    state[1] = ss * B[0] + cc * B[1];
    state[2] = sc * (B[0] - B[1]);
    state[3] = B[2];
    state[S_EPSP] = state_n[S_EPSP] + deps;
  }
  return MPGM_OK;
}

static double yield(const mpgm_material *m, const double tau[4]) {
  double l[2], cs[2];
  eig2(tau, l, cs);
  const double s[3] = {l[0], l[1], tau[3]};
  return mpgm_mc_yield_principal(m, s);
}

/* The state that carries s0 at F = I: e_e = D^-1 s0 (principal), b_e =
 * exp(2 e_e) (finite) or I + 2 e_e (small: eps_p = -e_e). */
static int init_stress(const mpgm_material *m, int kin, const double s0[4], double *state,
                       char *msg, size_t msglen) {
  const double fy = yield(m, s0);
  const double scale = fabs(s0[0]) + fabs(s0[1]) + fabs(s0[2]) + fabs(s0[3]) + m->param[P_C];
  if (fy > 1e-12 * scale) {
    if (msg && msglen)
      snprintf(msg, msglen,
               "mohr_coulomb: initial stress (%g, %g, %g, %g) Pa lies outside the yield "
               "surface (f = %g Pa)", s0[0], s0[1], s0[2], s0[3], fy);
    return MPGM_ERR_INPUT;
  }
  const double lam = m->c[MPGM_MC_LAMBDA], mu = m->c[MPGM_MC_MU];
  double l[2], cs[2];
  eig2(s0, l, cs);
  const double sp[3] = {l[0], l[1], s0[3]};
  const double p = (sp[0] + sp[1] + sp[2]) / (3.0 * lam + 2.0 * mu);
  double B[3];
  for (int i = 0; i < 3; i++) {
    const double e = (sp[i] - lam * p) / (2.0 * mu);
    B[i] = kin == MPGM_KIN_FINITE ? exp(2.0 * e) : 1.0 + 2.0 * e;
  }
  const double cc = cs[0] * cs[0], ss = cs[1] * cs[1], sc = cs[0] * cs[1];
  state[0] = cc * B[0] + ss * B[1];
  state[1] = ss * B[0] + cc * B[1];
  state[2] = sc * (B[0] - B[1]);
  state[3] = B[2];
  state[S_EPSP] = 0.0;
  return MPGM_OK;
}

#else
static void init_state(const mpgm_material *m, double *state) {
  (void)m;
  const double s[NSTATE] = {1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0};
  memcpy(state, s, sizeof s);
}

static double det3(const double F[9]) {
  return F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
         F[2] * (F[3] * F[7] - F[4] * F[6]);
}

/* Voigt components of sum_i w_i n_i (x) n_i, n_i the columns of V. */
static void from_principal(const double V[9], const double w[3], double out[6]) {
  for (int k = 0; k < 6; k++) {
    const int p = mpgm_voigt_pair[k][0], q = mpgm_voigt_pair[k][1];
    out[k] = V[3 * p] * V[3 * q] * w[0] + V[3 * p + 1] * V[3 * q + 1] * w[1] +
             V[3 * p + 2] * V[3 * q + 2] * w[2];
  }
}

/* The trial of a 3-D step: principal strains, directions, pair gaps. */
typedef struct trial3 {
  double e[3];   /* principal trial log strains (small: strains)          */
  double V[9];   /* principal directions, the columns                     */
  double x[3];   /* e_i - e_j for the pairs (i, j) of the Voigt shears 3..5 */
  double J;      /* det F (finite), 1 (small)                             */
  int finite;
} trial3;

/* Principal Voigt tangent: the normal block a (finite: a - 2 tau_i
 * delta_ij) and, for each principal pair (i, j) = mpgm_voigt_pair[3 + k],
 * the shear entry G_ij / 2 of the rotation of the principal axes. */
static void principal_tangent(const trial3 *t, const double tau[3], const double a[9],
                              double Dp[36]) {
  memset(Dp, 0, sizeof(double) * 36);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      Dp[6 * i + j] = a[3 * i + j] - (t->finite && i == j ? 2.0 * tau[i] : 0.0);
  for (int k = 0; k < 3; k++) {
    const int i = mpgm_voigt_pair[3 + k][0], j = mpgm_voigt_pair[3 + k][1];
    const double x = t->x[k];
    /* (tau_i - tau_j) / x; its limit when the pair is (nearly) repeated:
     * the return is affine in e_tr inside a region and symmetric in
     * e_i, e_j, so the limit is exact there */
    const double ratio = fabs(x) > 1e-6 ? (tau[i] - tau[j]) / x
                                        : 0.5 * (a[4 * i] - a[3 * j + i] + a[4 * j] - a[3 * i + j]);
    double G = ratio;
    if (t->finite) G = ratio * (fabs(x) > 1e-8 ? x / tanh(x) : 1.0) - (tau[i] + tau[j]);
    Dp[7 * (3 + k)] = 0.5 * G;
  }
}

/* Cauchy stress and the 6x6 spatial tangent from the principal results:
 * D = Ts Dp Ts^T / J, Ts the map of principal Voigt stresses to global
 * ones (its transpose maps global engineering strains to principal). */
static void spatial3(const trial3 *t, const double tau[3], const double a[9], double sigma[6],
                     double D[36]) {
  const double iJ = 1.0 / t->J;
  const double w[3] = {tau[0] * iJ, tau[1] * iJ, tau[2] * iJ};
  from_principal(t->V, w, sigma);
  if (!D) return;
  double Dp[36], Ts[36], T[36];
  principal_tangent(t, tau, a, Dp);
  const double *V = t->V;
  for (int r = 0; r < 6; r++) {
    const int p = mpgm_voigt_pair[r][0], q = mpgm_voigt_pair[r][1];
    for (int c = 0; c < 6; c++) {
      const int i = mpgm_voigt_pair[c][0], j = mpgm_voigt_pair[c][1];
      Ts[6 * r + c] = c < 3 ? V[3 * p + i] * V[3 * q + i]
                            : V[3 * p + i] * V[3 * q + j] + V[3 * p + j] * V[3 * q + i];
    }
  }
  for (int r = 0; r < 6; r++) /* T = Dp Ts^T */
    for (int c = 0; c < 6; c++) {
      double v = 0.0;
      for (int k = 0; k < 6; k++) v += Dp[6 * r + k] * Ts[6 * c + k];
      T[6 * r + c] = v;
    }
  for (int r = 0; r < 6; r++)
    for (int c = 0; c < 6; c++) {
      double v = 0.0;
      for (int k = 0; k < 6; k++) v += Ts[6 * r + k] * T[6 * k + c];
      D[6 * r + c] = v * iJ;
    }
}

/* Finite trial: b_tr = dF b_n dF^T, its principal log strains. */
static int finite_trial(const double F[9], const double dF[9], const double *state_n,
                        trial3 *t) {
  const double J = det3(F), Jd = det3(dF);
  if (!(J > 0.0) || !isfinite(J) || !(Jd > 0.0) || !isfinite(Jd)) return MPGM_ERR_JACOBIAN;
  double bn[9], A[9], b[6], l[3];
  for (int k = 0; k < 6; k++) {
    const int p = mpgm_voigt_pair[k][0], q = mpgm_voigt_pair[k][1];
    bn[3 * p + q] = bn[3 * q + p] = state_n[k];
  }
  for (int i = 0; i < 3; i++) /* A = dF b_n */
    for (int j = 0; j < 3; j++)
      A[3 * i + j] = dF[3 * i] * bn[j] + dF[3 * i + 1] * bn[3 + j] + dF[3 * i + 2] * bn[6 + j];
  for (int k = 0; k < 6; k++) {
    const int p = mpgm_voigt_pair[k][0], q = mpgm_voigt_pair[k][1];
    b[k] = A[3 * p] * dF[3 * q] + A[3 * p + 1] * dF[3 * q + 1] + A[3 * p + 2] * dF[3 * q + 2];
  }
  if (mpgm_sym3_eigen(b, l, t->V) || !(l[0] > 0.0) || !(l[1] > 0.0) || !(l[2] > 0.0))
    return MPGM_ERR_JACOBIAN;
  for (int i = 0; i < 3; i++) t->e[i] = 0.5 * log(l[i]);
  for (int k = 0; k < 3; k++) /* the gap from the ratio: no cancellation */
    t->x[k] = 0.5 * log(l[mpgm_voigt_pair[3 + k][0]] / l[mpgm_voigt_pair[3 + k][1]]);
  t->J = J;
  t->finite = 1;
  return MPGM_OK;
}

/* Tensor component k (Voigt order) of sym(F - I). */
static double small_strain(const double F[9], int k) {
  const int p = mpgm_voigt_pair[k][0], q = mpgm_voigt_pair[k][1];
  return p == q ? F[4 * p] - 1.0 : 0.5 * (F[3 * p + q] + F[3 * q + p]);
}

/* Stress, state and tangent (finite: Hencky/exponential map on b_e;
 * small: the same return on eps - eps_p). det F <= 0: MPGM_ERR_JACOBIAN,
 * outputs untouched. */
static int update(const mpgm_material *m, int kin, const double F[9], const double dF[9],
                  const double *state_n, double *state, double sigma[6], double D[36]) {
  trial3 t;
  if (kin == MPGM_KIN_FINITE) {
    MPGM_CALL(finite_trial(F, dF, state_n, &t));
  } else if (kin == MPGM_KIN_SMALL) {
    /* e_tr = eps - eps_p, eps_p = (I - state) / 2 */
    double e[6];
    for (int k = 0; k < 6; k++) e[k] = small_strain(F, k) + 0.5 * (state_n[k] - (k < 3));
    if (mpgm_sym3_eigen(e, t.e, t.V)) return MPGM_ERR_RETURN_MAP;
    for (int k = 0; k < 3; k++)
      t.x[k] = t.e[mpgm_voigt_pair[3 + k][0]] - t.e[mpgm_voigt_pair[3 + k][1]];
    t.J = 1.0;
    t.finite = 0;
  } else {
    return MPGM_ERR_UNSUPPORTED;
  }
  double tau[3], a[9], ee[3], deps;
  principal_step(m, t.e, tau, a, ee, &deps);
  if (!(isfinite(tau[0]) && isfinite(tau[1]) && isfinite(tau[2]))) return MPGM_ERR_RETURN_MAP;
  spatial3(&t, tau, a, sigma, D);
  if (state) {
    if (t.finite) {
      const double B[3] = {exp(2.0 * ee[0]), exp(2.0 * ee[1]), exp(2.0 * ee[2])};
      from_principal(t.V, B, state);
    } else { /* I - 2 eps_p = I - 2 (eps - e_e) */
      double Ee[6];
      from_principal(t.V, ee, Ee);
      for (int k = 0; k < 6; k++) state[k] = (k < 3) - 2.0 * (small_strain(F, k) - Ee[k]);
    }
    state[S_EPSP] = state_n[S_EPSP] + deps;
  }
  return MPGM_OK;
}

static double yield(const mpgm_material *m, const double tau[6]) {
  double l[3], V[9];
  if (mpgm_sym3_eigen(tau, l, V)) return NAN;
  return mpgm_mc_yield_principal(m, l);
}

/* The state that carries s0 at F = I: e_e = D^-1 s0 (principal), b_e =
 * exp(2 e_e) (finite) or I + 2 e_e (small: eps_p = -e_e). */
static int init_stress(const mpgm_material *m, int kin, const double s0[6], double *state,
                       char *msg, size_t msglen) {
  const double fy = yield(m, s0);
  double scale = m->param[P_C];
  for (int k = 0; k < 6; k++) scale += fabs(s0[k]);
  if (!(fy <= 1e-12 * scale)) {
    if (msg && msglen)
      snprintf(msg, msglen,
               "mohr_coulomb: initial stress (%g, %g, %g, %g, %g, %g) Pa lies outside the "
               "yield surface (f = %g Pa)", s0[0], s0[1], s0[2], s0[3], s0[4], s0[5], fy);
    return MPGM_ERR_INPUT;
  }
  const double lam = m->c[MPGM_MC_LAMBDA], mu = m->c[MPGM_MC_MU];
  double sp[3], V[9], B[3];
  mpgm_sym3_eigen(s0, sp, V); /* finite: yield() succeeded */
  const double p = (sp[0] + sp[1] + sp[2]) / (3.0 * lam + 2.0 * mu);
  for (int i = 0; i < 3; i++) {
    const double e = (sp[i] - lam * p) / (2.0 * mu);
    B[i] = kin == MPGM_KIN_FINITE ? exp(2.0 * e) : 1.0 + 2.0 * e;
  }
  from_principal(V, B, state);
  state[S_EPSP] = 0.0;
  return MPGM_OK;
}
#endif

/** Mohr-Coulomb elastoplasticity (plane strain or 3-D) with the Hencky elastic law
 *  at finite strain; params E [Pa], nu, c [Pa], phi, psi [deg]. Finite and
 *  small kinematics; det F <= 0 returns MPGM_ERR_JACOBIAN. */
const mpgm_material_type mpgm_material_mohr_coulomb = {
    .name = "mohr_coulomb",
    .doc = "Mohr-Coulomb elastoplasticity, Hencky elasticity at finite strain, "
           "non-associated flow (principal-space return)",
    .nparam = (int)(sizeof(params) / sizeof(params[0])),
    .params = params,
    .nstate = NSTATE,
    .finite = 1,
    .setup = setup,
    .init_state = init_state,
    .update = update,
    .plastic_strain = plastic_strain,
    .yield = yield,
    .init_stress = init_stress,
};
