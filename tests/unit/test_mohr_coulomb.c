/* test_mohr_coulomb.c -- the Mohr-Coulomb material (materials/mohr_coulomb.c,
 * docs/theory.md section 15), for psi = 0, 0 < psi < phi and psi = phi:
 *
 *   - return mapping in principal space, random trial stresses: the region
 *     chosen agrees with an independent trial-and-error solution of the
 *     discrete Kuhn-Tucker conditions (plane, both edges, apex), the
 *     returned stress is on the surface (f <= 1e-10 scale), keeps the order
 *     s1 >= s2 >= s3, and the plastic strain is a non-negative combination
 *     of the flow directions of the active planes (apex: of all six, or
 *     dilation when psi = 0); the algorithmic tangent against central
 *     differences of the map, per region;
 *   - purely elastic finite paths reproduce the Hencky law (one step and
 *     the same path in 7 increments through b_e);
 *   - the finite-strain update from a state on the yield surface: the
 *     spatial tangent against central differences of the Kirchhoff stress
 *     (Lie derivative), per region; the small-strain tangent likewise;
 *   - major symmetry of D exactly when psi = phi; setup rejects psi > phi;
 *     the initial-stress state reproduces s0 and refuses one outside f <= 0.
 */
#include "mohr_coulomb_impl.h"
#include "mpgm_material.h"
#include "mpgm_test.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

extern const mpgm_material_type mpgm_material_mohr_coulomb;

static const double PI = 3.14159265358979323846;
static const char *const region_name[] = {"elastic", "plane", "edge s1=s2", "edge s2=s3", "apex"};

static int make(double psi, mpgm_material *m) {
  memset(m, 0, sizeof *m);
  m->type = &mpgm_material_mohr_coulomb;
  snprintf(m->name, sizeof m->name, "soil");
  m->density = 1850.0;
  m->param[0] = 1.8374e6; /* E   */
  m->param[1] = 0.2213;   /* nu: K0 = nu/(1 - nu) < 1/k, so uniaxial strain yields */
  m->param[2] = 5.137e3;  /* c   */
  m->param[3] = 25.31;    /* phi */
  m->param[4] = psi;      /* psi */
  char msg[256] = "";
  return m->type->setup(m, msg, sizeof msg);
}

/* ---- an independent reference: trial and error on the KKT conditions ---- */
static void De_times(const mpgm_material *m, const double b[3], double out[3]) {
  const double lam = m->c[MPGM_MC_LAMBDA], mu = m->c[MPGM_MC_MU];
  const double tr = b[0] + b[1] + b[2];
  for (int i = 0; i < 3; i++) out[i] = lam * tr + 2.0 * mu * b[i];
}
static void De_solve(const mpgm_material *m, const double s[3], double e[3]) {
  const double lam = m->c[MPGM_MC_LAMBDA], mu = m->c[MPGM_MC_MU];
  const double p = (s[0] + s[1] + s[2]) / (3.0 * lam + 2.0 * mu);
  for (int i = 0; i < 3; i++) e[i] = (s[i] - lam * p) / (2.0 * mu);
}
/* Plane (i, j): f = k s_i - s_j - sc, flow (m at i, -1 at j). */
static void plane(const mpgm_material *m, int i, int j, double a[3], double b[3]) {
  for (int q = 0; q < 3; q++) a[q] = b[q] = 0.0;
  a[i] = m->c[MPGM_MC_K];
  a[j] = -1.0;
  b[i] = m->c[MPGM_MC_M];
  b[j] = -1.0;
}
static double det3(const double A[9]) {
  return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
         A[2] * (A[3] * A[7] - A[4] * A[6]);
}
/* y in the cone of the flow directions of all six planes (Caratheodory:
 * in the cone of three independent ones). */
static int in_flow_cone(const mpgm_material *m, const double y[3]) {
  double B[6][3], a[3];
  int np = 0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      if (i != j) plane(m, i, j, a, B[np++]);
  for (int p = 0; p < 6; p++)
    for (int q = p + 1; q < 6; q++)
      for (int r = q + 1; r < 6; r++) {
        const double A[9] = {B[p][0], B[q][0], B[r][0], B[p][1], B[q][1], B[r][1],
                             B[p][2], B[q][2], B[r][2]};
        const double d = det3(A);
        if (fabs(d) < 1e-12) continue;
        double x[3], ok = 1;
        for (int c = 0; c < 3; c++) { /* Cramer */
          double Ac[9];
          memcpy(Ac, A, sizeof Ac);
          for (int row = 0; row < 3; row++) Ac[3 * row + c] = y[row];
          x[c] = det3(Ac) / d;
          if (x[c] < -1e-12 * (fabs(y[0]) + fabs(y[1]) + fabs(y[2]))) ok = 0;
        }
        if (ok) return 1;
      }
  return 0;
}
/* The region whose return satisfies the Kuhn-Tucker conditions (-1: none,
 * -2: more than one). s_ref: that return. */
static int reference_region(const mpgm_material *m, const double st[3], double s_ref[3]) {
  const double tol = 1e-12 * (fabs(st[0]) + fabs(st[1]) + fabs(st[2]) + m->param[2]);
  if (m->c[MPGM_MC_K] * st[0] - st[2] - m->c[MPGM_MC_SC] <= 0.0) {
    memcpy(s_ref, st, sizeof(double) * 3);
    return MPGM_MC_ELASTIC;
  }
  int found = -1;
  /* active sets: {13}, {13, 23} (s1 = s2), {13, 12} (s2 = s3) */
  const int sets[3][2][2] = {{{0, 2}, {-1, -1}}, {{0, 2}, {1, 2}}, {{0, 2}, {0, 1}}};
  for (int c = 0; c < 3; c++) {
    const int na = c == 0 ? 1 : 2;
    double a[2][3] = {{0}}, b[2][3] = {{0}}, Db[2][3] = {{0}}, f[2] = {0};
    for (int q = 0; q < na; q++) {
      plane(m, sets[c][q][0], sets[c][q][1], a[q], b[q]);
      De_times(m, b[q], Db[q]);
      f[q] = a[q][0] * st[0] + a[q][1] * st[1] + a[q][2] * st[2] - m->c[MPGM_MC_SC];
    }
    double dl[2] = {0, 0};
    if (na == 1) {
      dl[0] = f[0] / (a[0][0] * Db[0][0] + a[0][1] * Db[0][1] + a[0][2] * Db[0][2]);
    } else {
      double M[2][2];
      for (int p = 0; p < 2; p++)
        for (int q = 0; q < 2; q++)
          M[p][q] = a[p][0] * Db[q][0] + a[p][1] * Db[q][1] + a[p][2] * Db[q][2];
      const double d = M[0][0] * M[1][1] - M[0][1] * M[1][0];
      dl[0] = (f[0] * M[1][1] - M[0][1] * f[1]) / d;
      dl[1] = (M[0][0] * f[1] - M[1][0] * f[0]) / d;
    }
    double s[3];
    for (int i = 0; i < 3; i++) s[i] = st[i] - dl[0] * Db[0][i] - dl[1] * Db[1][i];
    const double dscale = fabs(dl[0]) + fabs(dl[1]);
    if (dl[0] < -1e-12 * dscale || dl[1] < -1e-12 * dscale) continue;
    if (s[0] < s[1] - tol || s[1] < s[2] - tol) continue;
    if (mpgm_mc_yield_principal(m, s) > tol) continue;
    if (found >= 0) return -2;
    found = 1 + c;
    memcpy(s_ref, s, sizeof s);
  }
  /* apex: the plastic strain D^-1 (st - apex) in the flow cone */
  const double sa = m->c[MPGM_MC_APEXS];
  const double d[3] = {st[0] - sa, st[1] - sa, st[2] - sa};
  double y[3];
  De_solve(m, d, y);
  const int apex = m->param[4] > 0.0 ? in_flow_cone(m, y) : (d[0] + d[1] + d[2] >= 0.0);
  if (apex) {
    if (found >= 0) return -2;
    found = MPGM_MC_APEX;
    s_ref[0] = s_ref[1] = s_ref[2] = sa;
  }
  return found;
}

/* ---- return mapping in principal space ---------------------------------- */
static void check_return(const mpgm_material *m, rng *r, const char *tag) {
  enum { NSAMPLE = 40000 };
  int count[5] = {0}, fd_count[5] = {0}, agree = 1, nomatch = 0;
  double worst_f = -INFINITY, worst_ds = 0.0, worst_flow = 0.0, fd_err[5] = {0};
  const double sa = m->c[MPGM_MC_APEXS], R = 12.0 * m->param[2];
  int order_ok = 1;
  for (int n = 0; n < NSAMPLE; n++) {
    double st[3];
    for (int i = 0; i < 3; i++) st[i] = sa + uniform(r, -R, 0.4 * R);
    for (int i = 0; i < 2; i++) /* sort descending */
      for (int j = 0; j < 2 - i; j++)
        if (st[j] < st[j + 1]) {
          const double t = st[j];
          st[j] = st[j + 1];
          st[j + 1] = t;
        }
    double s[3], T[9], sref[3] = {0, 0, 0};
    const int reg = mpgm_mc_return(m, st, s, T);
    const int ref = reference_region(m, st, sref);
    const double scale = fabs(st[0]) + fabs(st[1]) + fabs(st[2]) + m->param[2];
    if (ref != reg) {
      if (nomatch++ < 5)
        printf("  %s: st = (%.17g, %.17g, %.17g): region %d, reference %d\n", tag, st[0], st[1],
               st[2], reg, ref);
      agree = 0;
      continue;
    }
    count[reg]++;
    for (int i = 0; i < 3; i++) worst_ds = fmax(worst_ds, fabs(s[i] - sref[i]) / scale);
    if (reg == MPGM_MC_ELASTIC) continue;
    worst_f = fmax(worst_f, fabs(mpgm_mc_yield_principal(m, s)) / scale);
    order_ok &= s[0] >= s[1] - 1e-13 * scale && s[1] >= s[2] - 1e-13 * scale;
    /* flow: D^-1 (st - s) is a combination of the active flow directions
     * (checked by the reference); here: its component off their span */
    if (reg != MPGM_MC_APEX) {
      double d[3] = {st[0] - s[0], st[1] - s[1], st[2] - s[2]}, e[3], b1[3] = {0, 0, 0}, b2[3] = {0, 0, 0}, a[3];
      De_solve(m, d, e);
      plane(m, 0, 2, a, b1);
      if (reg == MPGM_MC_EDGE_12) plane(m, 1, 2, a, b2);
      else if (reg == MPGM_MC_EDGE_23) plane(m, 0, 1, a, b2);
      double off;
      if (reg == MPGM_MC_PLANE) { /* |e x b1| / |b1| */
        double c[3] = {e[1] * b1[2] - e[2] * b1[1], e[2] * b1[0] - e[0] * b1[2],
                       e[0] * b1[1] - e[1] * b1[0]};
        off = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) /
              sqrt(b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]);
      } else { /* e . (b1 x b2) / |b1 x b2| */
        double c[3] = {b1[1] * b2[2] - b1[2] * b2[1], b1[2] * b2[0] - b1[0] * b2[2],
                       b1[0] * b2[1] - b1[1] * b2[0]};
        off = fabs(e[0] * c[0] + e[1] * c[1] + e[2] * c[2]) /
              sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
      }
      const double en = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
      worst_flow = fmax(worst_flow, off / en);
    }
    /* central differences of the map, away from region boundaries */
    const double h = 1e-6 * scale;
    double fd[9];
    int same = 1;
    for (int j = 0; j < 3 && same; j++) {
      double sp[3], sm[3], tp[3], tm[3];
      memcpy(tp, st, sizeof tp);
      memcpy(tm, st, sizeof tm);
      tp[j] += h;
      tm[j] -= h;
      same &= tp[0] >= tp[1] && tp[1] >= tp[2] && tm[0] >= tm[1] && tm[1] >= tm[2];
      same &= mpgm_mc_return(m, tp, sp, NULL) == reg && mpgm_mc_return(m, tm, sm, NULL) == reg;
      for (int i = 0; i < 3; i++) fd[3 * i + j] = (sp[i] - sm[i]) / (2.0 * h);
    }
    if (!same) continue;
    double e2 = 0.0, n2 = 0.0;
    for (int i = 0; i < 9; i++) {
      e2 += (fd[i] - T[i]) * (fd[i] - T[i]);
      n2 += T[i] * T[i];
    }
    fd_count[reg]++;
    fd_err[reg] = fmax(fd_err[reg], sqrt(e2) / fmax(sqrt(n2), 1.0));
  }
  mpgm_test(agree, "%s: region of %d trial stresses = the reference's (trial and error on "
            "the Kuhn-Tucker conditions; %d disagree)", tag, NSAMPLE, nomatch);
  for (int g = 0; g < 5; g++)
    mpgm_test(count[g] >= 200, "%s: %d trial stresses in region %s", tag, count[g],
              region_name[g]);
  mpgm_test_abs(worst_ds, 0.0, 1e-12, "%s: returned stress = reference (max rel err %.2e)",
                tag, worst_ds);
  mpgm_test_abs(worst_f, 0.0, 1e-10, "%s: |f(s)| <= 1e-10 scale on return (max %.2e)", tag,
                worst_f);
  mpgm_test(order_ok, "%s: returned stresses keep s1 >= s2 >= s3", tag);
  mpgm_test_abs(worst_flow, 0.0, 1e-10,
                "%s: plastic strain along the active flow directions (max off-span %.2e)", tag,
                worst_flow);
  for (int g = 1; g < 5; g++) {
    mpgm_test(fd_count[g] >= 100, "%s: %d FD checks in region %s", tag, fd_count[g],
              region_name[g]);
    mpgm_test_abs(fd_err[g], 0.0, 1e-6,
                  "%s: tangent d s/d st = central differences in region %s (max rel err %.2e)",
                  tag, region_name[g], fd_err[g]);
  }
}

/* ---- finite strain ------------------------------------------------------- */
static void mul(const double A[4], const double B[4], double C[4]) {
  const double c0 = A[0] * B[0] + A[1] * B[2], c1 = A[0] * B[1] + A[1] * B[3];
  const double c2 = A[2] * B[0] + A[3] * B[2], c3 = A[2] * B[1] + A[3] * B[3];
  C[0] = c0; C[1] = c1; C[2] = c2; C[3] = c3;
}
static double det(const double F[4]) { return F[0] * F[3] - F[1] * F[2]; }

/* Hencky: tau = lambda tr(e) I + 2 mu e, e = 1/2 ln(F F^T) (plane strain). */
static void hencky(const mpgm_material *m, const double F[4], double sigma[4]) {
  const double lam = m->c[MPGM_MC_LAMBDA], mu = m->c[MPGM_MC_MU];
  const double b[3] = {F[0] * F[0] + F[1] * F[1], F[2] * F[2] + F[3] * F[3],
                       F[0] * F[2] + F[1] * F[3]};
  const double h = 0.5 * (b[0] - b[1]), R = hypot(h, b[2]), mid = 0.5 * (b[0] + b[1]);
  const double l0 = mid + R, l1 = det(F) * det(F) / l0, th = 0.5 * atan2(b[2], h);
  const double e0 = 0.5 * log(l0), e1 = 0.5 * log(l1), tr = lam * (e0 + e1);
  const double t0 = tr + 2 * mu * e0, t1 = tr + 2 * mu * e1, c = cos(th), s = sin(th);
  const double J = det(F);
  sigma[0] = (c * c * t0 + s * s * t1) / J;
  sigma[1] = (s * s * t0 + c * c * t1) / J;
  sigma[2] = c * s * (t0 - t1) / J;
  sigma[3] = tr / J;
}

static void check_hencky(rng *r) {
  mpgm_material m;
  make(7.3, &m);
  m.param[2] = 1e12; /* cohesion far beyond the path: elastic */
  char msg[128];
  m.type->setup(&m, msg, sizeof msg);
  double worst1 = 0.0, worstn = 0.0;
  for (int k = 0; k < 16; k++) {
    const double th = uniform(r, -PI, PI);
    const double U[4] = {uniform(r, 0.7, 1.4), uniform(r, -0.3, 0.3), 0.0, uniform(r, 0.7, 1.4)};
    const double Q[4] = {cos(th), -sin(th), sin(th), cos(th)};
    double F[4], s[4], se[4], st0[5], st1[5], st[5];
    mul(Q, U, F);
    hencky(&m, F, se);
    m.type->init_state(&m, st0);
    m.type->update(&m, MPGM_KIN_FINITE, F, F, st0, st1, s, NULL);
    const double sn = fabs(se[0]) + fabs(se[1]) + fabs(se[2]) + fabs(se[3]);
    for (int i = 0; i < 4; i++) worst1 = fmax(worst1, fabs(s[i] - se[i]) / sn);
    /* the same end point in 7 increments F_i = Q(a th) (I + a (U - I)),
     * a = i/7, through b_e */
    double Fn[4] = {1, 0, 0, 1};
    m.type->init_state(&m, st);
    int ierr = 0;
    for (int i = 1; i <= 7; i++) {
      const double a = i / 7.0;
      const double Qa[4] = {cos(a * th), -sin(a * th), sin(a * th), cos(a * th)};
      double Ua[4], Fi[4], Fninv[4], dF[4];
      for (int q = 0; q < 4; q++) Ua[q] = (q == 0 || q == 3 ? 1.0 - a : 0.0) + a * U[q];
      mul(Qa, Ua, Fi);
      const double dn = det(Fn);
      Fninv[0] = Fn[3] / dn; Fninv[1] = -Fn[1] / dn; Fninv[2] = -Fn[2] / dn; Fninv[3] = Fn[0] / dn;
      mul(Fi, Fninv, dF);
      double nst[5];
      ierr |= m.type->update(&m, MPGM_KIN_FINITE, Fi, dF, st, nst, s, NULL);
      memcpy(st, nst, sizeof st);
      memcpy(Fn, Fi, sizeof Fn);
    }
    for (int i = 0; i < 4; i++) worstn = fmax(worstn, fabs(s[i] - se[i]) / sn);
    mpgm_test(ierr == 0 && st[4] == 0.0, "elastic path #%d: updates succeed, eps_p stays 0", k);
  }
  mpgm_test_abs(worst1, 0.0, TEST_TOL4, "elastic: one step = Hencky law (max rel err %.2e)", worst1);
  mpgm_test_abs(worstn, 0.0, TEST_TOL5,
                "elastic: 7 increments through b_e = Hencky law (max rel err %.2e)", worstn);
}

/* Region of the return a finite update takes (recomputed from b_tr). */
static int finite_region(const mpgm_material *m, const double dF[4], const double *st_n) {
  const double bx = st_n[0], by = st_n[1], bs = st_n[2];
  const double A0 = dF[0] * bx + dF[1] * bs, A1 = dF[0] * bs + dF[1] * by;
  const double A2 = dF[2] * bx + dF[3] * bs, A3 = dF[2] * bs + dF[3] * by;
  const double b[3] = {A0 * dF[0] + A1 * dF[1], A2 * dF[2] + A3 * dF[3], A0 * dF[2] + A1 * dF[3]};
  const double h = 0.5 * (b[0] - b[1]), R = hypot(h, b[2]), mid = 0.5 * (b[0] + b[1]);
  const double e[3] = {0.5 * log(mid + R), 0.5 * log(mid - R), 0.5 * log(st_n[3])};
  const double lam = m->c[MPGM_MC_LAMBDA], mu = m->c[MPGM_MC_MU];
  const double tr = lam * (e[0] + e[1] + e[2]);
  double t[3];
  for (int i = 0; i < 3; i++) t[i] = tr + 2 * mu * e[i];
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2 - i; j++)
      if (t[j] < t[j + 1]) {
        const double q = t[j];
        t[j] = t[j + 1];
        t[j + 1] = q;
      }
  double s[3];
  return mpgm_mc_return(m, t, s, NULL);
}

/* From a committed state on the yield surface (one plastic step), a second
 * step dF: J D : sym(H) against the Lie derivative of tau by central
 * differences, F = (I + e H) dF F_n. */
static void check_finite_tangent(const mpgm_material *m, rng *r, const char *tag) {
  int count[5] = {0};
  double err[5] = {0}, asym = 0.0, dnorm_max = 0.0;
  for (int n = 0; n < 40000; n++) {
    double st0[5], st1[5], st2[5], s[4], D[9];
    m->type->init_state(m, st0);
    const double th = uniform(r, -PI, PI), Q[4] = {cos(th), -sin(th), sin(th), cos(th)};
    const double U1[4] = {1 + uniform(r, -0.02, 0.01), uniform(r, -0.02, 0.02), 0,
                          1 + uniform(r, -0.02, 0.01)};
    double Fn[4], dF[4], F[4];
    mul(Q, U1, Fn);
    const double ca = cos(th), sa = sin(th);
    if (n % 2) /* uniaxial compression along (ca, sa): near the edge s1 = s2 */
      for (int q = 0; q < 4; q++) {
        const double l = uniform(r, -0.02, -0.005), A[4] = {ca * ca, ca * sa, ca * sa, sa * sa};
        Fn[q] = (q == 0 || q == 3 ? 1.0 : 0.0) + l * A[q] + uniform(r, -1e-4, 1e-4);
      }
    if (m->type->update(m, MPGM_KIN_FINITE, Fn, Fn, st0, st1, s, NULL)) continue;
    if (!(st1[4] > 0.0)) continue; /* start from a state on the yield surface */
    for (int q = 0; q < 4; q++) dF[q] = (q == 0 || q == 3 ? 1.0 : 0.0) + uniform(r, -0.006, 0.006);
    if (n % 2) /* and more of it */
      for (int q = 0; q < 4; q++) {
        const double l = uniform(r, -0.01, -0.001), A[4] = {ca * ca, ca * sa, ca * sa, sa * sa};
        dF[q] = (q == 0 || q == 3 ? 1.0 : 0.0) + l * A[q] + uniform(r, -1e-4, 1e-4);
      }
    mul(dF, Fn, F);
    const int reg = finite_region(m, dF, st1);
    if (count[reg] >= 60) continue;
    if (m->type->update(m, MPGM_KIN_FINITE, F, dF, st1, st2, s, D)) continue;
    double H[4];
    for (int q = 0; q < 4; q++) H[q] = uniform(r, -1, 1);
    const double h = 1e-7;
    const double Ip[4] = {1 + h * H[0], h * H[1], h * H[2], 1 + h * H[3]};
    const double Im[4] = {1 - h * H[0], -h * H[1], -h * H[2], 1 - h * H[3]};
    double dFp[4], dFm[4], Fp[4], Fm[4], sp[4], sm[4], tmp[5];
    mul(Ip, dF, dFp);
    mul(Im, dF, dFm);
    mul(dFp, Fn, Fp);
    mul(dFm, Fn, Fm);
    if (finite_region(m, dFp, st1) != reg || finite_region(m, dFm, st1) != reg) continue;
    m->type->update(m, MPGM_KIN_FINITE, Fp, dFp, st1, tmp, sp, NULL);
    m->type->update(m, MPGM_KIN_FINITE, Fm, dFm, st1, tmp, sm, NULL);
    const double J = det(F), Jp = det(Fp), Jm = det(Fm);
    const double tau[4] = {J * s[0], J * s[2], J * s[2], J * s[1]}; /* 2x2 */
    double lie[4], lhs[4];
    const double dtau[4] = {(Jp * sp[0] - Jm * sm[0]) / (2 * h), (Jp * sp[2] - Jm * sm[2]) / (2 * h),
                            (Jp * sp[2] - Jm * sm[2]) / (2 * h), (Jp * sp[1] - Jm * sm[1]) / (2 * h)};
    double Ht[4] = {H[0], H[2], H[1], H[3]}, Htau[4], tauHt[4];
    mul(H, tau, Htau);
    mul(tau, Ht, tauHt);
    for (int i = 0; i < 4; i++) lie[i] = dtau[i] - Htau[i] - tauHt[i];
    const double v[3] = {H[0], H[3], H[1] + H[2]};
    double o[3];
    for (int i = 0; i < 3; i++) o[i] = J * (D[3 * i] * v[0] + D[3 * i + 1] * v[1] + D[3 * i + 2] * v[2]);
    lhs[0] = o[0]; lhs[1] = o[2]; lhs[2] = o[2]; lhs[3] = o[1];
    double e2 = 0, n2 = 0, dn = 0;
    for (int i = 0; i < 4; i++) {
      e2 += (lhs[i] - lie[i]) * (lhs[i] - lie[i]);
      n2 += lie[i] * lie[i];
    }
    for (int i = 0; i < 9; i++) dn += D[i] * D[i];
    err[reg] = fmax(err[reg], sqrt(e2 / n2));
    count[reg]++;
    if (reg != MPGM_MC_ELASTIC && reg != MPGM_MC_APEX) {
      asym = fmax(asym, (fabs(D[1] - D[3]) + fabs(D[2] - D[6]) + fabs(D[5] - D[7])) / sqrt(dn));
      dnorm_max = fmax(dnorm_max, sqrt(dn));
    }
  }
  for (int g = 0; g < 5; g++) {
    mpgm_test(count[g] >= 20, "%s finite: %d second steps in region %s", tag, count[g],
              region_name[g]);
    mpgm_test_abs(err[g], 0.0, 1e-6,
                  "%s finite: J D:sym(H) = Lie derivative of tau (central diff) in region %s "
                  "(max rel err %.2e)", tag, region_name[g], err[g]);
  }
  if (m->symmetric)
    mpgm_test_abs(asym, 0.0, TEST_TOL3, "%s finite: psi = phi: D symmetric (max %.2e)", tag, asym);
  else
    mpgm_test(asym > 1e-3, "%s finite: psi < phi: D unsymmetric in plastic regions (%.2e)", tag,
              asym);
}

/* Small kinematics from a plastic state: D against central differences of
 * sigma w.r.t. the engineering strain. */
static void check_small_tangent(const mpgm_material *m, rng *r, const char *tag) {
  const double unit[3][4] = {{1, 0, 0, 0}, {0, 0, 0, 1}, {0, 0.5, 0.5, 0}};
  double worst = 0.0;
  int nplastic = 0;
  for (int n = 0; n < 200; n++) {
    double st0[5], st1[5], tmp[5], s[4], D[9], F1[4], F[4];
    m->type->init_state(m, st0);
    for (int q = 0; q < 4; q++) F1[q] = (q == 0 || q == 3 ? 1.0 : 0.0) + uniform(r, -0.02, 0.01);
    m->type->update(m, MPGM_KIN_SMALL, F1, F1, st0, st1, s, NULL);
    for (int q = 0; q < 4; q++) F[q] = F1[q] + uniform(r, -0.004, 0.004);
    m->type->update(m, MPGM_KIN_SMALL, F, F, st1, tmp, s, D);
    if (tmp[4] == st1[4]) continue; /* elastic second step */
    nplastic++;
    const double h = 1e-8;
    double e2 = 0, n2 = 0;
    for (int j = 0; j < 3; j++) {
      double Fp[4], Fm[4], sp[4], sm[4];
      for (int q = 0; q < 4; q++) {
        Fp[q] = F[q] + h * unit[j][q];
        Fm[q] = F[q] - h * unit[j][q];
      }
      m->type->update(m, MPGM_KIN_SMALL, Fp, Fp, st1, tmp, sp, NULL);
      m->type->update(m, MPGM_KIN_SMALL, Fm, Fm, st1, tmp, sm, NULL);
      for (int i = 0; i < 3; i++) {
        const double fd = (sp[i] - sm[i]) / (2 * h);
        e2 += (fd - D[3 * i + j]) * (fd - D[3 * i + j]);
      }
    }
    for (int i = 0; i < 9; i++) n2 += D[i] * D[i];
    /* relative to |D|, or to mu at the apex (D = 0) */
    worst = fmax(worst, sqrt(e2) / fmax(sqrt(n2), m->c[MPGM_MC_MU]));
  }
  mpgm_test(nplastic >= 50, "%s small: %d plastic second steps", tag, nplastic);
  /* h = 1e-8 of strain: a region boundary within h of a sample is unlikely
   * at this count; the bound is the FD truncation/rounding level */
  mpgm_test_abs(worst, 0.0, 1e-6, "%s small: D = d sigma/d eps (central diff, max rel err %.2e)",
                tag, worst);
}

static void check_setup_and_init(void) {
  mpgm_material m;
  mpgm_test(make(25.31, &m) == 0 && m.symmetric == 1 && m.plastic == 1,
            "psi = phi: symmetric tangent, plastic");
  mpgm_test(make(0.0, &m) == 0 && m.symmetric == 0, "psi = 0: unsymmetric tangent");
  mpgm_test(make(30.0, &m) == MPGM_ERR_INPUT, "psi > phi refused");
  mpgm_test(m.type->nstate == 5 && m.type->plastic_strain && m.type->yield,
            "state of 5 doubles, eps_p and yield operations");
  make(4.1, &m);
  /* apex at c cot phi; yield value 0 on the triaxial compression line */
  const double sp = sin(25.31 * PI / 180), c = 5.137e3;
  mpgm_test_rel(m.c[MPGM_MC_APEXS], c / tan(25.31 * PI / 180), TEST_TOL2, "apex at c cot phi");
  const double s3 = -4.0e4, s1 = s3 * (1 + sp) / (1 - sp) - 2 * c * cos(25.31 * PI / 180) / (1 - sp);
  const double tau[4] = {s3, s1, 0.0, s3};
  mpgm_test_abs(m.type->yield(&m, tau), 0.0, TEST_TOL3 * fabs(s1),
                "yield = 0 at sigma_1 = sigma_3 (1 + sin phi)/(1 - sin phi) + 2c cos phi/(1 - sin phi)");
  /* initial stress */
  const double s0[4] = {-2.31e4, -4.17e4, 3.2e3, -2.29e4};
  for (int kin = 0; kin < 2; kin++) {
    double st[5], st1[5], s[4];
    char msg[256] = "";
    int e = m.type->init_stress(&m, kin, s0, st, msg, sizeof msg);
    const double I[4] = {1, 0, 0, 1};
    m.type->update(&m, kin, I, I, st, st1, s, NULL);
    double err = 0;
    for (int i = 0; i < 4; i++) err = fmax(err, fabs(s[i] - s0[i]) / 4.17e4);
    mpgm_test(e == 0, "init_stress %s returns %d", kin ? "small" : "finite", e);
    mpgm_test_abs(err, 0.0, TEST_TOL3, "init_stress %s: update at F = I returns s0 (rel err %.2e)",
                  kin ? "small" : "finite", err);
    const double bad[4] = {-1.0e3, -4.17e5, 0.0, -1.0e3};
    mpgm_test(m.type->init_stress(&m, kin, bad, st, msg, sizeof msg) == MPGM_ERR_INPUT &&
                  strstr(msg, "outside the yield surface"),
              "init_stress %s: s0 outside the surface refused (%s)", kin ? "small" : "finite", msg);
  }
}

int main(void) {
  rng r = {0x2545F4914F6CDD1DULL};
  check_setup_and_init();
  const double psis[3] = {0.0, 11.7, 25.31};
  const char *tags[3] = {"psi = 0", "psi = 11.7", "psi = phi"};
  for (int k = 0; k < 3; k++) {
    mpgm_material m;
    make(psis[k], &m);
    check_return(&m, &r, tags[k]);
    check_finite_tangent(&m, &r, tags[k]);
    check_small_tangent(&m, &r, tags[k]);
  }
  check_hencky(&r);
  return mpgm_test_summary();
}
