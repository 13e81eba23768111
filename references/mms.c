/* mms.c -- the manufactured solutions of 004 section 4 (mpgm_mms.h):
 * motion, Cauchy stress and body force in closed form, derived from the
 * motion and the neo-Hookean law (docs/theory.md, section 21; the printed
 * body forces of 004 carry misprints and are not used).
 *
 * Small amplitudes lose nothing to cancellation: stretches enter as
 * increments (ln J = log1p, F^2 - 1 = H (2 + H), cos a - 1 = -2 sin^2(a/2)),
 * so stresses and forces keep full relative precision at A = 1e-4.
 */
#include <math.h>
#include <string.h>

#include "mpgm_base.h"
#include "mpgm_mms.h"

#if MPGM_DIM != 2
#error "references/mms.c is written for plane strain only (MPGM_DIM = 2)"
#endif

static const double PI = 3.14159265358979323846;

/* The parameters with the paper's values for fields left 0, the Lame
 * constants and the wave speed. */
typedef struct resolved {
  double A, E, nu, rho0, L, ri, ro;
  double lam, mu, c, omega;
} resolved;

static resolved resolve(const mpgm_mms *m) {
  const int vortex = m->kind == MPGM_MMS_VORTEX, ring = m->kind == MPGM_MMS_RING;
  resolved r = {
      .A = m->A != 0.0 ? m->A : (vortex ? 1.0 : 0.1),
      .E = m->E != 0.0 ? m->E : (vortex ? 1e3 : 1e7),
      .nu = m->nu,
      .rho0 = m->rho0 != 0.0 ? m->rho0 : 1000.0,
      .L = m->L != 0.0 ? m->L : 1.0,
      .ri = m->ri != 0.0 ? m->ri : (vortex ? 0.75 : 0.4),
      .ro = m->ro != 0.0 ? m->ro : (vortex ? 1.25 : 0.6),
  };
  r.lam = r.E * r.nu / ((1.0 + r.nu) * (1.0 - 2.0 * r.nu));
  r.mu = r.E / (2.0 * (1.0 + r.nu));
  r.c = sqrt(r.E / r.rho0);
  r.omega = ring ? PI * r.c / (r.ri + r.ro) : PI * r.c / r.L;
  return r;
}

int mpgm_mms_parse_kind(const char *name, mpgm_mms_kind *kind) {
  static const char *const names[] = {"vibration", "ring", "vortex"};
  if (!name || !kind) return MPGM_ERR_INPUT;
  for (int i = 0; i < 3; i++)
    if (strcmp(name, names[i]) == 0) {
      *kind = (mpgm_mms_kind)i;
      return MPGM_OK;
    }
  return MPGM_ERR_INPUT;
}

void mpgm_mms_init(mpgm_mms *m, mpgm_mms_kind kind) {
  const mpgm_mms zero = {.kind = kind};
  const resolved r = resolve(&zero);
  *m = (mpgm_mms){.kind = kind,
                  .A = r.A,
                  .E = r.E,
                  .nu = kind == MPGM_MMS_RING ? 0.0 : 0.3,
                  .rho0 = r.rho0,
                  .L = r.L,
                  .ri = r.ri,
                  .ro = r.ro};
}

double mpgm_mms_omega(const mpgm_mms *m) {
  return resolve(m).omega;
}

/* ---------------------------------------------------------------- vibration
 * u_x = A sin(k X) s, s = sin(omega t), k = 2 pi / L; F = diag(1 + H, 1),
 * H = A k cos(k X) s. */

/* The complete state: u, v, a, F, sigma, b (all outputs non-NULL). */
static void vibration(const resolved *r, const double X[2], double t, double u[2], double v[2],
                      double a[2], double F[4], double sig[4], double b[2]) {
  const double k = 2.0 * PI / r->L, w = r->omega;
  const double s = sin(w * t), sk = sin(k * X[0]), ck = cos(k * X[0]);
  u[0] = r->A * sk * s;
  u[1] = 0.0;
  v[0] = r->A * w * sk * cos(w * t);
  v[1] = 0.0;
  a[0] = -w * w * u[0];
  a[1] = 0.0;
  const double H = r->A * k * ck * s, J = 1.0 + H, lnJ = log1p(H);
  F[0] = J;
  F[1] = F[2] = 0.0;
  F[3] = 1.0;
  const double p = r->lam * lnJ / J;
  sig[0] = p + r->mu * H * (2.0 + H) / J;
  sig[1] = sig[3] = p;
  sig[2] = 0.0;
  /* Div P = dP_xx/dX e_x, dP_xx/dJ = mu + (mu + lambda (1 - ln J)) / J^2,
   * dJ/dX = -k^2 u_x */
  const double dPdJ = r->mu + (r->mu + r->lam * (1.0 - lnJ)) / (J * J);
  b[0] = u[0] * (k * k * dPdJ / r->rho0 - w * w);
  b[1] = 0.0;
}

/* --------------------------------------------------------------------- ring
 * u = U E_R, U = A s g(R); stretches l1 = 1 + h1 (radial), l2 = 1 + h2
 * (hoop), h1 = A s g'(R), h2 = A s g(R) / R. */

typedef struct ring_kin {
  double R, e[2];     /* radius, E_R                                  */
  double U, Ud, Udd;  /* radial displacement and its time derivatives */
  double h1, h2, dl1; /* stretch increments, d l1 / dR                */
} ring_kin;

static ring_kin ring_kinematics(const resolved *r, const double X[2], double t) {
  const double ri = r->ri, ro = r->ro, den = ro * ro * (ro - 3.0 * ri);
  const double c1 = -6.0 * ri / (ro * (ro - 3.0 * ri)), c2 = 3.0 * (ri + ro) / den, c3 = -2.0 / den;
  ring_kin k;
  k.R = hypot(X[0], X[1]);
  k.e[0] = X[0] / k.R;
  k.e[1] = X[1] / k.R;
  const double R = k.R, w = r->omega, s = sin(w * t);
  const double g = ((c3 * R + c2) * R + c1) * R, g1 = (3.0 * c3 * R + 2.0 * c2) * R + c1,
               g2 = 6.0 * c3 * R + 2.0 * c2;
  k.U = r->A * s * g;
  k.Ud = r->A * w * cos(w * t) * g;
  k.Udd = -w * w * k.U;
  k.h1 = r->A * s * g1;
  k.h2 = k.U / R;
  k.dl1 = r->A * s * g2;
  return k;
}

/* The complete state (all outputs non-NULL). */
static void ring(const resolved *r, const double X[2], double t, double u[2], double v[2],
                 double a[2], double F[4], double sig[4], double b[2]) {
  const ring_kin k = ring_kinematics(r, X, t);
  const double *e = k.e, l1 = 1.0 + k.h1, l2 = 1.0 + k.h2, J = l1 * l2;
  const double lnJ = log1p(k.h1) + log1p(k.h2);
  for (int i = 0; i < 2; i++) {
    u[i] = k.U * e[i];
    v[i] = k.Ud * e[i];
    a[i] = k.Udd * e[i];
  }
  /* F = (1 + h2) 1 + (h1 - h2) E_R (x) E_R */
  F[0] = 1.0 + k.h2 + (k.h1 - k.h2) * e[0] * e[0];
  F[1] = F[2] = (k.h1 - k.h2) * e[0] * e[1];
  F[3] = 1.0 + k.h2 + (k.h1 - k.h2) * e[1] * e[1];
  /* sigma = s_rr E_R (x) E_R + s_tt E_Th (x) E_Th, the hoop direction
   * E_Th = (-e[1], e[0]) */
  const double p = r->lam * lnJ / J;
  const double srr = p + r->mu * k.h1 * (2.0 + k.h1) / J;
  const double stt = p + r->mu * k.h2 * (2.0 + k.h2) / J;
  sig[0] = srr * e[0] * e[0] + stt * e[1] * e[1];
  sig[1] = srr * e[1] * e[1] + stt * e[0] * e[0];
  sig[2] = (srr - stt) * e[0] * e[1];
  sig[3] = p;
  /* Div P = (dP_rr/dR + (P_rr - P_tt) / R) E_R
   *       = [mu + (mu + lambda (1 - ln J)) / l1^2] dl1/dR
   *       + (l1 - l2) / R [mu + (mu + lambda (1 - ln J)) / J] E_R */
  const double m1 = r->mu + r->lam * (1.0 - lnJ);
  const double divP = (r->mu + m1 / (l1 * l1)) * k.dl1 + (k.h1 - k.h2) / k.R * (r->mu + m1 / J);
  const double br = k.Udd - divP / r->rho0;
  b[0] = br * e[0];
  b[1] = br * e[1];
}

/* ------------------------------------------------------------------- vortex
 * x = R (cos beta, sin beta), beta = Theta + alpha, alpha = A h(R) s. */

/* The complete state (all outputs non-NULL). */
static void vortex(const resolved *r, const double X[2], double t, double u[2], double v[2],
                   double a[2], double F[4], double sig[4], double b[2]) {
  const double R = hypot(X[0], X[1]), w = r->omega, s = sin(w * t), co = cos(w * t);
  const double half = 0.5 * (r->ro - r->ri), q = (R - 0.5 * (r->ri + r->ro)) / half;
  const double h = (1.0 - q * q) * (1.0 - q * q), h1 = -4.0 * q * (1.0 - q * q) / half,
               h2 = -4.0 * (1.0 - 3.0 * q * q) / (half * half);
  const double al = r->A * h * s, ald = r->A * h * w * co, gam = R * r->A * h1 * s;
  const double ca = cos(al), sa = sin(al), cm1 = -2.0 * sin(0.5 * al) * sin(0.5 * al);
  /* current position x and the polar bases: E_R, E_Th at Theta (ref.),
   * e_r, e_b at beta (current) */
  const double x0 = X[0] * ca - X[1] * sa, x1 = X[0] * sa + X[1] * ca;
  const double ER[2] = {X[0] / R, X[1] / R}, ET[2] = {-ER[1], ER[0]};
  const double er[2] = {x0 / R, x1 / R}, eb[2] = {-er[1], er[0]};
  u[0] = X[0] * cm1 - X[1] * sa;
  u[1] = X[0] * sa + X[1] * cm1;
  /* v = R alpha' e_b, a = R alpha'' e_b - R alpha'^2 e_r, alpha'' = -w^2 alpha */
  for (int i = 0; i < 2; i++) {
    v[i] = R * ald * eb[i];
    a[i] = -R * w * w * al * eb[i] - R * ald * ald * er[i];
  }
  /* F = e_r (x) E_R + e_b (x) (gamma E_R + E_Th) */
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) F[2 * i + j] = er[i] * ER[j] + eb[i] * (gam * ER[j] + ET[j]);
  /* J = 1: sigma = mu (b - 1) = mu gamma (e_r e_b + e_b e_r) + mu gamma^2 e_b e_b */
  const double srb = r->mu * gam, sbb = r->mu * gam * gam;
  sig[0] = 2.0 * srb * er[0] * eb[0] + sbb * eb[0] * eb[0];
  sig[1] = 2.0 * srb * er[1] * eb[1] + sbb * eb[1] * eb[1];
  sig[2] = srb * (er[0] * eb[1] + eb[0] * er[1]) + sbb * eb[0] * eb[1];
  sig[3] = 0.0;
  /* Div P = div sigma (J = 1), in the current polar basis:
   * (div s)_r = -s_bb / R, (div s)_b = d s_rb / dR + 2 s_rb / R
   *                                  = mu A s (R h'' + 3 h') */
  const double br = -R * ald * ald + sbb / (r->rho0 * R);
  const double bb = -r->A * s * (R * w * w * h + r->mu / r->rho0 * (R * h2 + 3.0 * h1));
  for (int i = 0; i < 2; i++) b[i] = br * er[i] + bb * eb[i];
}

/* ---------------------------------------------------------------- public */

/* Everything at (X, t); the public functions copy what they are asked. */
static void state(const mpgm_mms *m, const double X[2], double t, double u[2], double v[2],
                  double a[2], double F[4], double sig[4], double b[2]) {
  const resolved r = resolve(m);
  switch (m->kind) {
  case MPGM_MMS_VIBRATION:
    vibration(&r, X, t, u, v, a, F, sig, b);
    break;
  case MPGM_MMS_RING:
    ring(&r, X, t, u, v, a, F, sig, b);
    break;
  case MPGM_MMS_VORTEX:
    vortex(&r, X, t, u, v, a, F, sig, b);
    break;
  default:
    for (int i = 0; i < 2; i++) u[i] = v[i] = a[i] = b[i] = NAN;
    for (int i = 0; i < 4; i++) F[i] = sig[i] = NAN;
  }
}

static void copy(double *dst, const double *src, int n) {
  if (dst) memcpy(dst, src, (size_t)n * sizeof(double));
}

void mpgm_mms_motion(const mpgm_mms *m, const double X[2], double t, double u[2], double v[2],
                     double a[2], double F[4]) {
  double uu[2], vv[2], aa[2], FF[4], ss[4], bb[2];
  state(m, X, t, uu, vv, aa, FF, ss, bb);
  copy(u, uu, 2);
  copy(v, vv, 2);
  copy(a, aa, 2);
  copy(F, FF, 4);
}

void mpgm_mms_cauchy(const mpgm_mms *m, const double X[2], double t, double sig[4]) {
  double uu[2], vv[2], aa[2], FF[4], ss[4], bb[2];
  state(m, X, t, uu, vv, aa, FF, ss, bb);
  copy(sig, ss, 4);
}

void mpgm_mms_body_force(const mpgm_mms *m, const double X[2], double t, double b[2]) {
  double uu[2], vv[2], aa[2], FF[4], ss[4], bb[2];
  state(m, X, t, uu, vv, aa, FF, ss, bb);
  copy(b, bb, 2);
}
