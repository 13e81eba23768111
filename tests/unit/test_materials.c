/* test_materials.c -- conformance suite run over every material type in
 * mpgm_material_types(): no per-material code, one check per line.
 *
 *   - metadata and the name lookup;
 *   - stress-free reference: sigma(I) = 0;
 *   - small kinematics: sigma against the linear law (when the type has E
 *     and nu), D against central differences of sigma w.r.t. grad u,
 *     major symmetry when the type declares it;
 *   - finite kinematics (finite = 1): the spatial tangent against central
 *     differences of the Kirchhoff stress (Lie derivative), objectivity of
 *     sigma and of D, det F <= 0 -> MPGM_ERR_JACOBIAN without NaNs, and the
 *     small-strain limit of the finite law;
 *   - types without finite kinematics refuse it (MPGM_ERR_UNSUPPORTED).
 *
 * Every point is evaluated from the reference state (F_n = I, dF = F,
 * state_n from init_state), so the checks also apply to path-dependent
 * materials for the first step.
 */
#include "mpgm_material.h"
#include "mpgm_test.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N_FINITE 24  /* random deformation gradients per finite type */
#define N_SMALL 8    /* random displacement gradients per type       */
static const double PI = 3.14159265358979323846;

/* ---- 2x2 row-major helpers ---------------------------------------------- */
static void mul(const double A[4], const double B[4], double C[4]) {
  double c0 = A[0] * B[0] + A[1] * B[2], c1 = A[0] * B[1] + A[1] * B[3];
  double c2 = A[2] * B[0] + A[3] * B[2], c3 = A[2] * B[1] + A[3] * B[3];
  C[0] = c0; C[1] = c1; C[2] = c2; C[3] = c3;
}
static void transpose(const double A[4], double T[4]) {
  double a1 = A[1];
  T[0] = A[0]; T[1] = A[2]; T[2] = a1; T[3] = A[3];
}
static void rotation(double th, double R[4]) {
  R[0] = cos(th); R[1] = -sin(th); R[2] = sin(th); R[3] = cos(th);
}
static double det(const double F[4]) { return F[0] * F[3] - F[1] * F[2]; }
/* Q A Q^T */
static void rotate(const double Q[4], const double A[4], double B[4]) {
  double Qt[4], T[4];
  transpose(Q, Qt);
  mul(Q, A, T);
  mul(T, Qt, B);
}
/* Symmetric 2x2 from stress layout {xx, yy, xy, ...}. */
static void sym_of(const double s[3], double S[4]) {
  S[0] = s[0]; S[1] = s[2]; S[2] = s[2]; S[3] = s[1];
}
/* Frobenius norm of A - B (2x2), and of A. */
static double dist(const double A[4], const double B[4]) {
  double s = 0.0;
  for (int i = 0; i < 4; i++) s += (A[i] - B[i]) * (A[i] - B[i]);
  return sqrt(s);
}
static double norm(const double A[4]) {
  double s = 0.0;
  for (int i = 0; i < 4; i++) s += A[i] * A[i];
  return sqrt(s);
}
/* T = D : sym(H) as a 2x2 tensor (Voigt, engineering shear). */
static void tangent_action(const double D[9], const double H[4], double T[4]) {
  const double v[3] = {H[0], H[3], H[1] + H[2]};
  double s[3];
  for (int i = 0; i < 3; i++)
    s[i] = D[3 * i] * v[0] + D[3 * i + 1] * v[1] + D[3 * i + 2] * v[2];
  sym_of(s, T);
}

/* ---- material set-up with high-entropy parameters ----------------------- */
static double param_value(const mpgm_param_spec *ps) {
  if (strcmp(ps->name, "E") == 0) return 2.385e7;
  if (strcmp(ps->name, "nu") == 0) return 0.2783;
  /* a strength (a stress without default, e.g. a cohesion): 1 % of E keeps
   * the small-strain checks (|grad u| <= 2.3e-4) in the elastic range; the
   * finite checks (stretches 0.6..1.6) then run in the plastic range */
  if (strcmp(ps->unit, "Pa") == 0 && !isfinite(ps->def)) return 0.01 * 2.385e7;
  if (isfinite(ps->def)) return ps->def;
  if (isfinite(ps->lo) && isfinite(ps->hi)) return ps->lo + 0.3817 * (ps->hi - ps->lo);
  if (isfinite(ps->lo)) return ps->lo + 1.2345 * (fabs(ps->lo) + 1.0);
  if (isfinite(ps->hi)) return ps->hi - 1.2345 * (fabs(ps->hi) + 1.0);
  return 1.2345;
}

static int param_index(const mpgm_material_type *t, const char *name) {
  for (int i = 0; i < t->nparam; i++)
    if (strcmp(t->params[i].name, name) == 0) return i;
  return -1;
}

/* One material point evaluated from the reference state. */
typedef struct point {
  mpgm_material m;
  double *state_n, *state;
} point;

static int eval(point *p, int kin, const double F[4], double sigma[4],
                double D[9]) {
  return p->m.type->update(&p->m, kin, F, F, p->m.type->nstate ? p->state_n : NULL,
                           p->m.type->nstate ? p->state : NULL, sigma, D);
}

/* Kirchhoff stress tau = det F sigma, in-plane {xx, yy, xy} as 2x2. */
static int kirchhoff(point *p, const double F[4], double tau[4]) {
  double s[4];
  int ierr = eval(p, MPGM_KIN_FINITE, F, s, NULL);
  double S[4];
  sym_of(s, S);
  for (int i = 0; i < 4; i++) tau[i] = det(F) * S[i];
  return ierr;
}

/* A random F = R(theta) U, theta in [-pi, pi], U upper triangular with
 * stretches 0.6..1.6 and shear (any F with det F > 0 has this form). */
static void random_F(rng *r, double F[4]) {
  double R[4], U[4] = {uniform(r, 0.6, 1.6), uniform(r, -0.5, 0.5), 0.0,
                       uniform(r, 0.6, 1.6)};
  rotation(uniform(r, -PI, PI), R);
  mul(R, U, F);
}

static void random_H(rng *r, double H[4]) {
  for (int i = 0; i < 4; i++) H[i] = uniform(r, -1.0, 1.0);
}

/* ---- checks ------------------------------------------------------------- */
static void check_meta(const mpgm_material_type *t, const point *p) {
  mpgm_test(t->name && t->name[0] && mpgm_material_type_find(t->name) == t,
            "%s: found by name", t->name);
  mpgm_test(t->update != NULL && t->setup != NULL, "%s: setup and update set",
            t->name);
  mpgm_test(t->nparam >= 0 && t->nparam <= MPGM_MAT_MAXPARAM &&
                (t->nparam == 0 || t->params != NULL),
            "%s: parameter table (%d entries)", t->name, t->nparam);
  mpgm_test(t->nstate >= 0 && (p->m.symmetric == 0 || p->m.symmetric == 1) &&
                (p->m.plastic == 0 || p->m.plastic == 1),
            "%s: nstate, symmetric, plastic flags", t->name);
}

static void check_reference(point *p, int kin) {
  const char *kn = kin == MPGM_KIN_FINITE ? "finite" : "small";
  const double I[4] = {1.0, 0.0, 0.0, 1.0};
  double s[4] = {0}, D[9] = {0};
  int ierr = eval(p, kin, I, s, D);
  double dn = 0.0, sn = 0.0;
  for (int i = 0; i < 9; i++) dn += D[i] * D[i];
  for (int i = 0; i < 4; i++) sn += s[i] * s[i];
  mpgm_test(ierr == 0, "%s %s: update at F = I returns %d", p->m.type->name, kn,
            ierr);
  mpgm_test_abs(sqrt(sn), 0.0, TEST_TOL1 * sqrt(dn),
                "%s %s: stress-free reference sigma(I) = 0", p->m.type->name, kn);
}

/* Small kinematics: linear law and D against central differences. */
static void check_small(point *p, rng *r) {
  const char *name = p->m.type->name;
  const int iE = param_index(p->m.type, "E"), inu = param_index(p->m.type, "nu");
  /* unit Voigt strains {xx, yy, gamma_xy} as grad u */
  const double unit[3][4] = {{1, 0, 0, 0}, {0, 0, 0, 1}, {0, 0.5, 0.5, 0}};
  for (int k = 0; k < N_SMALL; k++) {
    double G[4], F[4], s[4], D[9];
    for (int i = 0; i < 4; i++) G[i] = uniform(r, -2.3e-4, 2.3e-4);
    for (int i = 0; i < 4; i++) F[i] = G[i] + (i == 0 || i == 3 ? 1.0 : 0.0);
    int ierr = eval(p, MPGM_KIN_SMALL, F, s, D);
    mpgm_test(ierr == 0, "%s small #%d: update returns %d", name, k, ierr);
    if (iE >= 0 && inu >= 0) {
      double lam, mu;
      mpgm_lame(p->m.param[iE], p->m.param[inu], &lam, &mu);
      const double tr = G[0] + G[3];
      const double se[4] = {lam * tr + 2 * mu * G[0], lam * tr + 2 * mu * G[3],
                            mu * (G[1] + G[2]), lam * tr};
      double e = 0.0, n = 0.0;
      for (int i = 0; i < 4; i++) {
        e += (s[i] - se[i]) * (s[i] - se[i]);
        n += se[i] * se[i];
      }
      mpgm_test_abs(sqrt(e / n), 0.0, 1e-9,
                    "%s small #%d: sigma = linear law (rel err)", name, k);
    }
    /* D by central differences; the law is linear, so h only sets the
     * rounding error of F - I */
    const double h = 1e-5;
    double e = 0.0, n = 0.0;
    for (int j = 0; j < 3; j++) {
      double Fp[4], Fm[4], sp[4], sm[4];
      for (int i = 0; i < 4; i++) {
        Fp[i] = F[i] + h * unit[j][i];
        Fm[i] = F[i] - h * unit[j][i];
      }
      eval(p, MPGM_KIN_SMALL, Fp, sp, NULL);
      eval(p, MPGM_KIN_SMALL, Fm, sm, NULL);
      for (int i = 0; i < 3; i++) {
        double fd = (sp[i] - sm[i]) / (2.0 * h), dij = D[3 * i + j];
        e += (fd - dij) * (fd - dij);
        n += dij * dij;
      }
    }
    mpgm_test_abs(sqrt(e / n), 0.0, 1e-9,
                  "%s small #%d: D = d sigma / d grad u (central diff, rel err)",
                  name, k);
    if (p->m.symmetric)
      mpgm_test_abs(fabs(D[1] - D[3]) + fabs(D[2] - D[6]) + fabs(D[5] - D[7]),
                    0.0, TEST_TOL1 * sqrt(n),
                    "%s small #%d: D has major symmetry", name, k);
  }
}

/* Finite kinematics at one random F: tangent, objectivity, symmetry. */
static void check_finite_at(point *p, rng *r, int k) {
  const char *name = p->m.type->name;
  double F[4], H[4], s[4], D[9];
  random_F(r, F);
  random_H(r, H);
  const double J = det(F);
  int ierr = eval(p, MPGM_KIN_FINITE, F, s, D);
  mpgm_test(ierr == 0, "%s finite #%d: update returns %d (det F = %.4g)", name,
            k, ierr, J);
  if (ierr) return;

  /* J D : sym(H) = d/de tau((I + e H) F) - (H tau + tau H^T) */
  const double h = 1e-6;
  double Fp[4], Fm[4], Ip[4] = {1 + h * H[0], h * H[1], h * H[2], 1 + h * H[3]},
                       Im[4] = {1 - h * H[0], -h * H[1], -h * H[2], 1 - h * H[3]};
  mul(Ip, F, Fp);
  mul(Im, F, Fm);
  double tp[4], tm[4], tau[4], S[4], Ht[4], Htau[4], tauHt[4], lie[4], lhs[4];
  int e1 = kirchhoff(p, Fp, tp), e2 = kirchhoff(p, Fm, tm);
  sym_of(s, S);
  for (int i = 0; i < 4; i++) tau[i] = J * S[i];
  transpose(H, Ht);
  mul(H, tau, Htau);
  mul(tau, Ht, tauHt);
  for (int i = 0; i < 4; i++)
    lie[i] = (tp[i] - tm[i]) / (2.0 * h) - Htau[i] - tauHt[i];
  tangent_action(D, H, lhs);
  for (int i = 0; i < 4; i++) lhs[i] *= J;
  mpgm_test(e1 == 0 && e2 == 0, "%s finite #%d: perturbed updates succeed",
            name, k);
  mpgm_test_abs(dist(lhs, lie) / norm(lhs), 0.0, 1e-6,
                "%s finite #%d: J D:sym(H) = Lie derivative of tau (rel err)",
                name, k);

  /* objectivity: sigma(Q F) = Q sigma(F) Q^T, s_zz unchanged */
  double Q[4], QF[4], sq[4], Dq[9], Sq[4], QSQ[4];
  rotation(uniform(r, -PI, PI), Q);
  mul(Q, F, QF);
  ierr = eval(p, MPGM_KIN_FINITE, QF, sq, Dq);
  mpgm_test(ierr == 0, "%s finite #%d: update at Q F returns %d", name, k, ierr);
  sym_of(sq, Sq);
  rotate(Q, S, QSQ);
  const double sn = sqrt(norm(S) * norm(S) + s[3] * s[3]);
  mpgm_test_abs(dist(Sq, QSQ) / sn, 0.0, TEST_TOL4,
                "%s finite #%d: sigma(Q F) = Q sigma(F) Q^T (rel err)", name, k);
  mpgm_test_abs(fabs(sq[3] - s[3]) / sn, 0.0, TEST_TOL4,
                "%s finite #%d: s_zz(Q F) = s_zz(F) (rel err)", name, k);
  /* D(Q F) : sym(Q H Q^T) = Q (D(F) : sym(H)) Q^T */
  double QHQ[4], T[4], QTQ[4], Tq[4];
  rotate(Q, H, QHQ);
  tangent_action(D, H, T);
  rotate(Q, T, QTQ);
  tangent_action(Dq, QHQ, Tq);
  mpgm_test_abs(dist(Tq, QTQ) / norm(QTQ), 0.0, TEST_TOL4,
                "%s finite #%d: D(Q F):sym(Q H Q^T) = Q (D:sym(H)) Q^T (rel err)",
                name, k);
  if (p->m.symmetric) {
    double dn = 0.0;
    for (int i = 0; i < 9; i++) dn += D[i] * D[i];
    mpgm_test_abs(fabs(D[1] - D[3]) + fabs(D[2] - D[6]) + fabs(D[5] - D[7]),
                  0.0, TEST_TOL1 * sqrt(dn),
                  "%s finite #%d: D has major symmetry", name, k);
  }
}

/* det F <= 0: MPGM_ERR_JACOBIAN and no NaN or Inf written. */
static void check_jacobian(point *p, rng *r) {
  const char *name = p->m.type->name;
  double F[6][4] = {{1.5, 3.0, 0.5, 1.0}, /* det = 0 exactly */
                    {0.0, 0.0, 0.0, 0.0}};
  for (int k = 2; k < 6; k++) { /* det < 0: a reflection of a random F */
    random_F(r, F[k]);
    F[k][1] = -F[k][1];
    F[k][3] = -F[k][3];
  }
  for (int k = 0; k < 6; k++) {
    double s[4] = {0}, D[9] = {0};
    int ierr = eval(p, MPGM_KIN_FINITE, F[k], s, D);
    int finite = 1;
    for (int i = 0; i < 4; i++) finite &= isfinite(s[i]) != 0;
    for (int i = 0; i < 9; i++) finite &= isfinite(D[i]) != 0;
    mpgm_test(ierr == MPGM_ERR_JACOBIAN && finite,
              "%s: det F = %.3g gives MPGM_ERR_JACOBIAN (%d), no NaN written",
              name, det(F[k]), ierr);
  }
}

/* sigma_finite(I + eps G) -> sigma_small(I + eps G) as eps -> 0, relative
 * to their size: the small-strain limit of the finite law. (Both at the same
 * F: a law with a yield stress is not homogeneous, so sigma_small(I + G)
 * would leave the elastic range.) */
static void check_small_limit(point *p, rng *r) {
  const char *name = p->m.type->name;
  const double eps = 1e-7;
  for (int k = 0; k < 4; k++) {
    double G[4], F[4], sf[4], ss[4];
    random_H(r, G);
    for (int i = 0; i < 4; i++) F[i] = ((i == 0 || i == 3) ? 1.0 : 0.0) + eps * G[i];
    int e1 = eval(p, MPGM_KIN_FINITE, F, sf, NULL);
    int e2 = eval(p, MPGM_KIN_SMALL, F, ss, NULL);
    double e = 0.0, n = 0.0;
    for (int i = 0; i < 4; i++) {
      double w = i == 2 ? 2.0 : 1.0; /* xy counts twice */
      e += w * (sf[i] - ss[i]) * (sf[i] - ss[i]);
      n += w * ss[i] * ss[i];
    }
    mpgm_test(e1 == 0 && e2 == 0, "%s limit #%d: updates succeed", name, k);
    mpgm_test_abs(sqrt(e / n), 0.0, 1e-5,
                  "%s limit #%d: sigma_finite(I + eps G) = sigma_small(I + eps G), "
                  "eps = 1e-7 (rel err)", name, k);
  }
}

int main(void) {
  const mpgm_material_type *const *types = mpgm_material_types();
  int ntypes = 0;
  while (types[ntypes]) ntypes++;
  mpgm_test(ntypes >= 2, "material list holds %d types", ntypes);
  mpgm_test(mpgm_material_type_find("no_such_material") == NULL &&
                mpgm_material_type_find(NULL) == NULL,
            "unknown names are not found");

  rng r = {0x9E3779B97F4A7C15ULL};
  for (int it = 0; types[it]; it++) {
    const mpgm_material_type *t = types[it];
    point p;
    memset(&p, 0, sizeof(p));
    p.m.type = t;
    snprintf(p.m.name, sizeof(p.m.name), "test_%s", t->name);
    p.m.density = 1873.4;
    for (int i = 0; i < t->nparam && i < MPGM_MAT_MAXPARAM; i++)
      p.m.param[i] = param_value(&t->params[i]);
    char msg[256] = "";
    int ierr = t->setup ? t->setup(&p.m, msg, sizeof(msg)) : MPGM_ERR_INTERNAL;
    mpgm_test(ierr == 0, "%s: setup returns %d %s", t->name, ierr, msg);
    p.state_n = calloc((size_t)(t->nstate > 0 ? t->nstate : 1), sizeof(double));
    p.state = calloc((size_t)(t->nstate > 0 ? t->nstate : 1), sizeof(double));
    if (!p.state_n || !p.state) {
      mpgm_test(0, "%s: allocation", t->name);
      free(p.state_n);
      free(p.state);
      break;
    }
    if (t->init_state) t->init_state(&p.m, p.state_n);
    check_meta(t, &p);
    if (ierr) goto next;

    check_reference(&p, MPGM_KIN_SMALL);
    check_small(&p, &r);
    if (t->finite) {
      check_reference(&p, MPGM_KIN_FINITE);
      for (int k = 0; k < N_FINITE; k++) check_finite_at(&p, &r, k);
      check_jacobian(&p, &r);
      check_small_limit(&p, &r);
    } else {
      const double F[4] = {1.01, 0.02, -0.01, 0.99};
      double s[4], D[9];
      int e = eval(&p, MPGM_KIN_FINITE, F, s, D);
      mpgm_test(e == MPGM_ERR_UNSUPPORTED,
                "%s: finite kinematics refused with MPGM_ERR_UNSUPPORTED (%d)",
                t->name, e);
    }
  next:
    free(p.state_n);
    free(p.state);
  }
  return mpgm_test_summary();
}
