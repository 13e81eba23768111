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
#include "support_tensor.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N_FINITE 24  /* random deformation gradients per finite type */
#define N_SMALL 8    /* random displacement gradients per type       */
static const double PI = 3.14159265358979323846;
/* Layouts follow the build's MPGM_DIM (mpgm_base.h); the same checks run
 * in plane strain and in 3-D, the s_zz checks in plane strain only. */

/* ---- DIM x DIM row-major helpers ---------------------------------------- */
enum { DIM = MPGM_DIM, NT = MPGM_TENSOR, NV = MPGM_NVOIGT, NS = MPGM_NSTRESS };

/* Frobenius norm of A - B (DIM x DIM), and of A. */
static double dist(const double A[NT], const double B[NT]) {
  double s = 0.0;
  for (int i = 0; i < NT; i++) s += (A[i] - B[i]) * (A[i] - B[i]);
  return sqrt(s);
}
static double norm(const double A[NT]) {
  double s = 0.0;
  for (int i = 0; i < NT; i++) s += A[i] * A[i];
  return sqrt(s);
}
/* Voigt strain {e_aa..., 2 e_ab} of sym(H) (engineering shear). */
static void voigt_strain(const double H[NT], double v[NV]) {
  for (int k = 0; k < NV; k++) {
    const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
    v[k] = a == b ? H[DIM * a + a] : H[DIM * a + b] + H[DIM * b + a];
  }
}
/* T = D : sym(H) as a DIM x DIM tensor (Voigt, engineering shear). */
static void tangent_action(const double D[MPGM_NTANGENT], const double H[NT], double T[NT]) {
  double v[NV], s[NV];
  voigt_strain(H, v);
  for (int i = 0; i < NV; i++) {
    s[i] = 0.0;
    for (int j = 0; j < NV; j++) s[i] += D[NV * i + j] * v[j];
  }
  sym_of(s, T);
}
/* sum over i < j of |D_ij - D_ji|: zero for a symmetric tangent. */
static double asymmetry(const double D[MPGM_NTANGENT]) {
  double a = 0.0;
  for (int i = 0; i < NV; i++)
    for (int j = i + 1; j < NV; j++) a += fabs(D[NV * i + j] - D[NV * j + i]);
  return a;
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

static int eval(point *p, int kin, const double F[NT], double sigma[NS],
                double D[MPGM_NTANGENT]) {
  return p->m.type->update(&p->m, kin, F, F, p->m.type->nstate ? p->state_n : NULL,
                           p->m.type->nstate ? p->state : NULL, sigma, D);
}

/* Kirchhoff stress tau = det F sigma as a DIM x DIM tensor (2-D: in-plane). */
static int kirchhoff(point *p, const double F[NT], double tau[NT]) {
  double s[NS];
  int ierr = eval(p, MPGM_KIN_FINITE, F, s, NULL);
  double S[NT];
  sym_of(s, S);
  for (int i = 0; i < NT; i++) tau[i] = det(F) * S[i];
  return ierr;
}

/* A random rotation: 2-D by an angle in [-pi, pi]; 3-D by a uniform unit
 * quaternion (Shoemake: uniform over SO(3)). */
static void random_rotation(rng *r, double R[NT]) {
#if MPGM_DIM == 2
  const double th = uniform(r, -PI, PI);
  R[0] = cos(th); R[1] = -sin(th); R[2] = sin(th); R[3] = cos(th);
#else
  const double u1 = uniform(r, 0.0, 1.0), u2 = uniform(r, 0.0, 2.0 * PI),
               u3 = uniform(r, 0.0, 2.0 * PI);
  const double w = sqrt(1.0 - u1) * sin(u2), x = sqrt(1.0 - u1) * cos(u2),
               y = sqrt(u1) * sin(u3), z = sqrt(u1) * cos(u3);
  const double Q[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                       2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                       2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)};
  memcpy(R, Q, sizeof Q);
#endif
}

/* A random F = R U, R a random rotation, U upper triangular with
 * stretches 0.6..1.6 and shears -0.5..0.5 (any F with det F > 0 has this
 * form). */
static void random_F(rng *r, double F[NT]) {
  double R[NT], U[NT] = {0};
  for (int i = 0; i < DIM; i++)
    for (int j = i; j < DIM; j++)
      U[DIM * i + j] = i == j ? uniform(r, 0.6, 1.6) : uniform(r, -0.5, 0.5);
  random_rotation(r, R);
  mul(R, U, F);
}

static void random_H(rng *r, double H[NT]) {
  for (int i = 0; i < NT; i++) H[i] = uniform(r, -1.0, 1.0);
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
  double I[NT], s[NS] = {0}, D[MPGM_NTANGENT] = {0};
  identity(I);
  int ierr = eval(p, kin, I, s, D);
  double dn = 0.0, sn = 0.0;
  for (int i = 0; i < MPGM_NTANGENT; i++) dn += D[i] * D[i];
  for (int i = 0; i < NS; i++) sn += s[i] * s[i];
  mpgm_test(ierr == 0, "%s %s: update at F = I returns %d", p->m.type->name, kn,
            ierr);
  mpgm_test_abs(sqrt(sn), 0.0, TEST_TOL1 * sqrt(dn),
                "%s %s: stress-free reference sigma(I) = 0", p->m.type->name, kn);
}

/* The linear law for grad u = G in the stress layout (2-D: with s_zz). */
static void linear_law(double lam, double mu, const double G[NT], double se[NS]) {
  double tr = 0.0;
  for (int i = 0; i < DIM; i++) tr += G[(DIM + 1) * i];
  for (int k = 0; k < NV; k++) {
    const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
    se[k] = (a == b ? lam * tr : 0.0) + mu * (G[DIM * a + b] + G[DIM * b + a]);
  }
#if MPGM_DIM == 2
  se[3] = lam * tr;
#endif
}

/* Small kinematics: linear law and D against central differences. */
static void check_small(point *p, rng *r) {
  const char *name = p->m.type->name;
  const int iE = param_index(p->m.type, "E"), inu = param_index(p->m.type, "nu");
  /* unit Voigt strains {e_aa, gamma_ab} as grad u */
  double unit[NV][NT] = {{0}};
  for (int k = 0; k < NV; k++) {
    const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
    if (a == b) unit[k][DIM * a + a] = 1.0;
    else unit[k][DIM * a + b] = unit[k][DIM * b + a] = 0.5;
  }
  for (int k = 0; k < N_SMALL; k++) {
    double G[NT], F[NT], s[NS], D[MPGM_NTANGENT];
    for (int i = 0; i < NT; i++) G[i] = uniform(r, -2.3e-4, 2.3e-4);
    identity(F);
    for (int i = 0; i < NT; i++) F[i] += G[i];
    int ierr = eval(p, MPGM_KIN_SMALL, F, s, D);
    mpgm_test(ierr == 0, "%s small #%d: update returns %d", name, k, ierr);
    if (iE >= 0 && inu >= 0) {
      double lam, mu, se[NS];
      mpgm_lame(p->m.param[iE], p->m.param[inu], &lam, &mu);
      linear_law(lam, mu, G, se);
      double e = 0.0, n = 0.0;
      for (int i = 0; i < NS; i++) {
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
    for (int j = 0; j < NV; j++) {
      double Fp[NT], Fm[NT], sp[NS], sm[NS];
      for (int i = 0; i < NT; i++) {
        Fp[i] = F[i] + h * unit[j][i];
        Fm[i] = F[i] - h * unit[j][i];
      }
      eval(p, MPGM_KIN_SMALL, Fp, sp, NULL);
      eval(p, MPGM_KIN_SMALL, Fm, sm, NULL);
      for (int i = 0; i < NV; i++) {
        double fd = (sp[i] - sm[i]) / (2.0 * h), dij = D[NV * i + j];
        e += (fd - dij) * (fd - dij);
        n += dij * dij;
      }
    }
    mpgm_test_abs(sqrt(e / n), 0.0, 1e-9,
                  "%s small #%d: D = d sigma / d grad u (central diff, rel err)",
                  name, k);
    if (p->m.symmetric)
      mpgm_test_abs(asymmetry(D), 0.0, TEST_TOL1 * sqrt(n),
                    "%s small #%d: D has major symmetry", name, k);
  }
}

/* Finite kinematics at one random F: tangent, objectivity, symmetry. */
static void check_finite_at(point *p, rng *r, int k) {
  const char *name = p->m.type->name;
  double F[NT], H[NT], s[NS], D[MPGM_NTANGENT];
  random_F(r, F);
  random_H(r, H);
  const double J = det(F);
  int ierr = eval(p, MPGM_KIN_FINITE, F, s, D);
  mpgm_test(ierr == 0, "%s finite #%d: update returns %d (det F = %.4g)", name,
            k, ierr, J);
  if (ierr) return;

  /* J D : sym(H) = d/de tau((I + e H) F) - (H tau + tau H^T) */
  const double h = 1e-6;
  double Fp[NT], Fm[NT], Ip[NT], Im[NT];
  identity(Ip);
  identity(Im);
  for (int i = 0; i < NT; i++) {
    Ip[i] += h * H[i];
    Im[i] -= h * H[i];
  }
  mul(Ip, F, Fp);
  mul(Im, F, Fm);
  double tp[NT], tm[NT], tau[NT], S[NT], Ht[NT], Htau[NT], tauHt[NT], lie[NT], lhs[NT];
  int e1 = kirchhoff(p, Fp, tp), e2 = kirchhoff(p, Fm, tm);
  sym_of(s, S);
  for (int i = 0; i < NT; i++) tau[i] = J * S[i];
  transpose(H, Ht);
  mul(H, tau, Htau);
  mul(tau, Ht, tauHt);
  for (int i = 0; i < NT; i++)
    lie[i] = (tp[i] - tm[i]) / (2.0 * h) - Htau[i] - tauHt[i];
  tangent_action(D, H, lhs);
  for (int i = 0; i < NT; i++) lhs[i] *= J;
  mpgm_test(e1 == 0 && e2 == 0, "%s finite #%d: perturbed updates succeed",
            name, k);
  mpgm_test_abs(dist(lhs, lie) / norm(lhs), 0.0, 1e-6,
                "%s finite #%d: J D:sym(H) = Lie derivative of tau (rel err)",
                name, k);

  /* objectivity: sigma(Q F) = Q sigma(F) Q^T (2-D: s_zz unchanged) */
  double Q[NT], QF[NT], sq[NS], Dq[MPGM_NTANGENT], Sq[NT], QSQ[NT];
  random_rotation(r, Q);
  mul(Q, F, QF);
  ierr = eval(p, MPGM_KIN_FINITE, QF, sq, Dq);
  mpgm_test(ierr == 0, "%s finite #%d: update at Q F returns %d", name, k, ierr);
  sym_of(sq, Sq);
  rotate(Q, S, QSQ);
#if MPGM_DIM == 2
  const double sn = sqrt(norm(S) * norm(S) + s[3] * s[3]);
#else
  const double sn = norm(S);
#endif
  mpgm_test_abs(dist(Sq, QSQ) / sn, 0.0, TEST_TOL4,
                "%s finite #%d: sigma(Q F) = Q sigma(F) Q^T (rel err)", name, k);
#if MPGM_DIM == 2
  mpgm_test_abs(fabs(sq[3] - s[3]) / sn, 0.0, TEST_TOL4,
                "%s finite #%d: s_zz(Q F) = s_zz(F) (rel err)", name, k);
#endif
  /* D(Q F) : sym(Q H Q^T) = Q (D(F) : sym(H)) Q^T */
  double QHQ[NT], T[NT], QTQ[NT], Tq[NT];
  rotate(Q, H, QHQ);
  tangent_action(D, H, T);
  rotate(Q, T, QTQ);
  tangent_action(Dq, QHQ, Tq);
  mpgm_test_abs(dist(Tq, QTQ) / norm(QTQ), 0.0, TEST_TOL4,
                "%s finite #%d: D(Q F):sym(Q H Q^T) = Q (D:sym(H)) Q^T (rel err)",
                name, k);
  if (p->m.symmetric) {
    double dn = 0.0;
    for (int i = 0; i < MPGM_NTANGENT; i++) dn += D[i] * D[i];
    mpgm_test_abs(asymmetry(D), 0.0, TEST_TOL1 * sqrt(dn),
                  "%s finite #%d: D has major symmetry", name, k);
  }
}

/* det F <= 0: MPGM_ERR_JACOBIAN and no NaN or Inf written. */
static void check_jacobian(point *p, rng *r) {
  const char *name = p->m.type->name;
#if MPGM_DIM == 2
  double F[6][NT] = {{1.5, 3.0, 0.5, 1.0}, /* det = 0 exactly */
                     {0.0, 0.0, 0.0, 0.0}};
#else
  double F[6][NT] = {{1.5, 3.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 1.0}, /* det = 0 */
                     {0.0}};
#endif
  for (int k = 2; k < 6; k++) { /* det < 0: a reflection of a random F */
    random_F(r, F[k]);
    for (int i = 0; i < DIM; i++) F[k][DIM * i + 1] = -F[k][DIM * i + 1];
  }
  for (int k = 0; k < 6; k++) {
    double s[NS] = {0}, D[MPGM_NTANGENT] = {0};
    int ierr = eval(p, MPGM_KIN_FINITE, F[k], s, D);
    int finite = 1;
    for (int i = 0; i < NS; i++) finite &= isfinite(s[i]) != 0;
    for (int i = 0; i < MPGM_NTANGENT; i++) finite &= isfinite(D[i]) != 0;
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
    double G[NT], F[NT], sf[NS], ss[NS];
    random_H(r, G);
    identity(F);
    for (int i = 0; i < NT; i++) F[i] += eps * G[i];
    int e1 = eval(p, MPGM_KIN_FINITE, F, sf, NULL);
    int e2 = eval(p, MPGM_KIN_SMALL, F, ss, NULL);
    double e = 0.0, n = 0.0;
    for (int i = 0; i < NS; i++) {
      double w = i >= DIM && i < NV ? 2.0 : 1.0; /* shears count twice */
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
      double F[NT], s[NS], D[MPGM_NTANGENT];
      identity(F);
      F[0] = 1.01, F[1] = 0.02, F[DIM] = -0.01, F[DIM + 1] = 0.99;
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
