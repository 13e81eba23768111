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
 *
 * The return checks are the same in both dimensions. In 3-D (MPGM_DIM = 3)
 * the frame checks are written for 3x3 F and six stresses, and add: the
 * Jacobi eigensolver alone (known spectra, repeated and graded ones); the
 * second step not coaxial with the first, with f(tau) = 0 after the return
 * in each plastic region, the new b_e carrying the returned stress, and the
 * plastic states with three distinct principal stresses counted apart;
 * repeated principal stretches (F = I, uniaxial, biaxial, hydrostatic).
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

#if MPGM_DIM == 2
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

#else /* MPGM_DIM == 3 */
/* ---- 3-D helpers ---------------------------------------------------------- */
static void mul(const double A[9], const double B[9], double C[9]) {
  double T[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      T[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
  memcpy(C, T, sizeof T);
}
static double det(const double F[9]) {
  return F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
         F[2] * (F[3] * F[7] - F[4] * F[6]);
}
static void eye(double I[9]) {
  for (int i = 0; i < 9; i++) I[i] = i % 4 == 0 ? 1.0 : 0.0;
}
/* Uniform random rotation (unit quaternion, Shoemake). */
static void random_rotation(rng *r, double R[9]) {
  const double u1 = uniform(r, 0, 1), u2 = uniform(r, 0, 2 * PI), u3 = uniform(r, 0, 2 * PI);
  const double w = sqrt(1 - u1) * sin(u2), x = sqrt(1 - u1) * cos(u2), y = sqrt(u1) * sin(u3),
               z = sqrt(u1) * cos(u3);
  const double Q[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                       2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                       2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)};
  memcpy(R, Q, sizeof Q);
}
/* Rotation by the angle th about the unit axis n (Rodrigues). */
static void axis_rotation(const double n[3], double th, double R[9]) {
  const double c = cos(th), s = sin(th), C = 1.0 - c;
  const double Q[9] = {c + n[0] * n[0] * C, n[0] * n[1] * C - n[2] * s, n[0] * n[2] * C + n[1] * s,
                       n[1] * n[0] * C + n[2] * s, c + n[1] * n[1] * C, n[1] * n[2] * C - n[0] * s,
                       n[2] * n[0] * C - n[1] * s, n[2] * n[1] * C + n[0] * s, c + n[2] * n[2] * C};
  memcpy(R, Q, sizeof Q);
}
/* Symmetric 3x3 from Voigt {xx, yy, zz, xy, yz, xz} and back. */
static void full_of(const double v[6], double S[9]) {
  for (int k = 0; k < 6; k++) {
    const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
    S[3 * a + b] = S[3 * b + a] = v[k];
  }
}
static void voigt_of(const double S[9], double v[6]) {
  for (int k = 0; k < 6; k++) v[k] = S[3 * mpgm_voigt_pair[k][0] + mpgm_voigt_pair[k][1]];
}

/* R diag(l) R^T as Voigt components, scaled: d_a d_b (R diag(l) R^T)_ab. */
static void spd(const double R[9], const double l[3], const double d[3], double v[6]) {
  for (int k = 0; k < 6; k++) {
    const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
    v[k] = d[a] * d[b] *
           (R[3 * a] * R[3 * b] * l[0] + R[3 * a + 1] * R[3 * b + 1] * l[1] + R[3 * a + 2] * R[3 * b + 2] * l[2]);
  }
}

/* The eigensolver on its own: S V = V diag(l) and V^T V = I for random
 * symmetric S with known eigenvalues, repeated ones included (no NaN);
 * a graded positive definite S = D A D (D = diag(1, 1e-3, 1e-6)) keeps the
 * product of its eigenvalues, det S, to relative accuracy, i.e. the tiny
 * eigenvalue is not lost to the large ones. */
static void check_eigen(rng *r) {
  double worst_l = 0.0, worst_orth = 0.0, worst_det = 0.0;
  int fails = 0;
  for (int n = 0; n < 2000; n++) {
    double R[9], lt[3], v[6], l[3], V[9];
    const double one[3] = {1, 1, 1}, grade[3] = {1.0, 1e-3, 1e-6};
    random_rotation(r, R);
    for (int i = 0; i < 3; i++) lt[i] = uniform(r, -2.0, 2.0);
    if (n % 4 == 1) lt[1] = lt[0];                /* a repeated pair */
    if (n % 4 == 2) lt[1] = lt[2] = lt[0];        /* all equal       */
    if (n % 4 == 3) lt[2] = lt[0] * (1 + 1e-13);  /* nearly repeated */
    spd(R, lt, one, v);
    fails += mpgm_sym3_eigen(v, l, V) != 0;
    double ls[3] = {l[0], l[1], l[2]}, ts[3] = {lt[0], lt[1], lt[2]};
    for (int i = 0; i < 2; i++) /* sort both ascending */
      for (int j = 0; j < 2 - i; j++) {
        if (ls[j] > ls[j + 1]) { const double q = ls[j]; ls[j] = ls[j + 1]; ls[j + 1] = q; }
        if (ts[j] > ts[j + 1]) { const double q = ts[j]; ts[j] = ts[j + 1]; ts[j + 1] = q; }
      }
    const double lmax = fmax(fabs(ts[0]), fabs(ts[2]));
    for (int i = 0; i < 3; i++) worst_l = fmax(worst_l, fabs(ls[i] - ts[i]) / lmax);
    double VtV[9];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        VtV[3 * i + j] = V[i] * V[j] + V[3 + i] * V[3 + j] + V[6 + i] * V[6 + j] - (i == j);
    for (int i = 0; i < 9; i++) worst_orth = fmax(worst_orth, fabs(VtV[i]) + !isfinite(VtV[i]));
    /* graded SPD: A with eigenvalues 0.5..2 */
    for (int i = 0; i < 3; i++) lt[i] = uniform(r, 0.5, 2.0);
    spd(R, lt, grade, v);
    fails += mpgm_sym3_eigen(v, l, V) != 0;
    const double dS = lt[0] * lt[1] * lt[2] * 1e-18; /* det A (d0 d1 d2)^2 */
    worst_det = fmax(worst_det, fabs(l[0] * l[1] * l[2] - dS) / dS + !(l[0] > 0 && l[1] > 0 && l[2] > 0));
  }
  mpgm_test(fails == 0, "eigen: 4000 decompositions converge (%d failed)", fails);
  mpgm_test_abs(worst_l, 0.0, TEST_TOL2,
                "eigen: eigenvalues of R diag(l) R^T, repeated ones included (max err / |l|max %.2e)",
                worst_l);
  mpgm_test_abs(worst_orth, 0.0, TEST_TOL2, "eigen: V^T V = I (max %.2e)", worst_orth);
  mpgm_test_abs(worst_det, 0.0, TEST_TOL3,
                "eigen: graded SPD (scales 1, 1e-3, 1e-6): l0 l1 l2 = det S (max rel err %.2e)",
                worst_det);
  const double I6[6] = {2, 2, 2, 0, 0, 0}, Z6[6] = {0, 0, 0, 0, 0, 0};
  double l[3], V[9];
  mpgm_test(mpgm_sym3_eigen(I6, l, V) == 0 && l[0] == 2 && l[1] == 2 && l[2] == 2 && V[0] == 1 &&
                V[4] == 1 && V[8] == 1,
            "eigen: 2 I gives 2, 2, 2 and V = I");
  mpgm_test(mpgm_sym3_eigen(Z6, l, V) == 0 && l[0] == 0 && l[1] == 0 && l[2] == 0,
            "eigen: the zero matrix");
  const double bad[6] = {1, 1, NAN, 0, 0, 0};
  mpgm_test(mpgm_sym3_eigen(bad, l, V) != 0, "eigen: NaN refused");
}

/* Hencky in 3-D: tau = lambda tr(e) I + 2 mu e, e = 1/2 ln(F F^T), from
 * the eigenvectors of F F^T (checked above). */
static void hencky(const mpgm_material *m, const double F[9], double sigma[6]) {
  const double lam = m->c[MPGM_MC_LAMBDA], mu = m->c[MPGM_MC_MU];
  double b[9], v[6], l[3], V[9], Ft[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) Ft[3 * i + j] = F[3 * j + i];
  mul(F, Ft, b);
  voigt_of(b, v);
  mpgm_sym3_eigen(v, l, V);
  const double e[3] = {0.5 * log(l[0]), 0.5 * log(l[1]), 0.5 * log(l[2])};
  const double tr = lam * (e[0] + e[1] + e[2]), J = det(F);
  for (int k = 0; k < 6; k++) {
    const int a = mpgm_voigt_pair[k][0], c = mpgm_voigt_pair[k][1];
    sigma[k] = 0.0;
    for (int i = 0; i < 3; i++) sigma[k] += V[3 * a + i] * V[3 * c + i] * (tr + 2 * mu * e[i]) / J;
  }
}

/* Elastic 3-D paths: one step and 7 increments through b_e = Hencky. */
static void check_hencky(rng *r) {
  mpgm_material m;
  make(7.3, &m);
  m.param[2] = 1e12; /* cohesion far beyond the path: elastic */
  char msg[128];
  m.type->setup(&m, msg, sizeof msg);
  double worst1 = 0.0, worstn = 0.0;
  for (int k = 0; k < 16; k++) {
    double Q[9], U[9] = {0}, F[9], s[6], se[6], st0[7], st1[7], st[7], ax[3];
    for (int i = 0; i < 3; i++) ax[i] = uniform(r, -1, 1);
    const double an = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
    for (int i = 0; i < 3; i++) ax[i] /= an;
    const double th = uniform(r, -PI, PI);
    axis_rotation(ax, th, Q);
    for (int i = 0; i < 3; i++)
      for (int j = i; j < 3; j++) U[3 * i + j] = i == j ? uniform(r, 0.7, 1.4) : uniform(r, -0.3, 0.3);
    mul(Q, U, F);
    hencky(&m, F, se);
    m.type->init_state(&m, st0);
    m.type->update(&m, MPGM_KIN_FINITE, F, F, st0, st1, s, NULL);
    double sn = 0.0;
    for (int i = 0; i < 6; i++) sn += fabs(se[i]);
    for (int i = 0; i < 6; i++) worst1 = fmax(worst1, fabs(s[i] - se[i]) / sn);
    /* F_i = Q(a th) (I + a (U - I)), a = i/7, then dF = F_i F_{i-1}^-1 */
    double Fn[9];
    eye(Fn);
    m.type->init_state(&m, st);
    int ierr = 0;
    for (int i = 1; i <= 7; i++) {
      const double a = i / 7.0;
      double Fi[9], inv[9], dF[9], nst[7], Qa[9], Ua[9];
      for (int q = 0; q < 9; q++) Ua[q] = (q % 4 == 0 ? 1.0 - a : 0.0) + a * U[q];
      axis_rotation(ax, a * th, Qa);
      mul(Qa, Ua, Fi);
      const double dn = det(Fn);
      for (int p = 0; p < 3; p++) /* adjugate / det */
        for (int q = 0; q < 3; q++) {
          const int p1 = (p + 1) % 3, p2 = (p + 2) % 3, q1 = (q + 1) % 3, q2 = (q + 2) % 3;
          inv[3 * q + p] = (Fn[3 * p1 + q1] * Fn[3 * p2 + q2] - Fn[3 * p1 + q2] * Fn[3 * p2 + q1]) / dn;
        }
      mul(Fi, inv, dF);
      ierr |= m.type->update(&m, MPGM_KIN_FINITE, Fi, dF, st, nst, s, NULL);
      memcpy(st, nst, sizeof st);
      memcpy(Fn, Fi, sizeof Fn);
    }
    for (int i = 0; i < 6; i++) worstn = fmax(worstn, fabs(s[i] - se[i]) / sn);
    mpgm_test(ierr == 0 && st[6] == 0.0, "elastic path #%d: updates succeed, eps_p stays 0", k);
  }
  mpgm_test_abs(worst1, 0.0, TEST_TOL4, "elastic: one step = Hencky law (max rel err %.2e)", worst1);
  mpgm_test_abs(worstn, 0.0, TEST_TOL5,
                "elastic: 7 increments through b_e = Hencky law (max rel err %.2e)", worstn);
}

/* Region of the return a finite update takes (recomputed from b_tr). */
static int finite_region(const mpgm_material *m, const double dF[9], const double *st_n) {
  double bn[9], A[9], b[9], dFt[9], v[6], l[3], V[9];
  full_of(st_n, bn);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) dFt[3 * i + j] = dF[3 * j + i];
  mul(dF, bn, A);
  mul(A, dFt, b);
  voigt_of(b, v);
  mpgm_sym3_eigen(v, l, V);
  const double e[3] = {0.5 * log(l[0]), 0.5 * log(l[1]), 0.5 * log(l[2])};
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

/* I + l n (x) n (uniaxial, mode 1) or I + l (I - n (x) n) (biaxial, mode 2)
 * along a random unit n, plus noise; mode 0: I + random entries in
 * [lo, hi] on the diagonal and +-w off it. */
static void random_stretch(rng *r, int mode, double lo, double hi, double w, double F[9]) {
  double n[3] = {uniform(r, -1, 1), uniform(r, -1, 1), uniform(r, -1, 1)};
  const double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const double l = uniform(r, lo, hi);
  for (int i = 0; i < 3; i++) n[i] /= nn;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      const double d = i == j ? 1.0 : 0.0;
      if (mode == 0) F[3 * i + j] = d + (i == j ? uniform(r, lo, hi) : uniform(r, -w, w));
      else if (mode == 1) F[3 * i + j] = d + l * n[i] * n[j] + uniform(r, -1e-4, 1e-4);
      else F[3 * i + j] = d + l * (d - n[i] * n[j]) + uniform(r, -1e-4, 1e-4);
    }
}

/* J D : sym(H) against the Lie derivative of tau by central differences,
 * F = (I + h H) dF F_n, from the committed state st1; max rel err. */
static double lie_error(const mpgm_material *m, const double Fn[9], const double dF[9],
                        const double *st1, const double s[6], const double D[36], rng *r,
                        int reg, int *same) {
  double H[9], Ip[9], Im[9], dFp[9], dFm[9], Fp[9], Fm[9], F[9], sp[6], sm[6], tmp[7];
  for (int q = 0; q < 9; q++) H[q] = uniform(r, -1, 1);
  const double h = 1e-7;
  for (int q = 0; q < 9; q++) {
    Ip[q] = (q % 4 == 0) + h * H[q];
    Im[q] = (q % 4 == 0) - h * H[q];
  }
  mul(Ip, dF, dFp);
  mul(Im, dF, dFm);
  mul(dFp, Fn, Fp);
  mul(dFm, Fn, Fm);
  mul(dF, Fn, F);
  *same = finite_region(m, dFp, st1) == reg && finite_region(m, dFm, st1) == reg;
  if (!*same) return 0.0;
  m->type->update(m, MPGM_KIN_FINITE, Fp, dFp, st1, tmp, sp, NULL);
  m->type->update(m, MPGM_KIN_FINITE, Fm, dFm, st1, tmp, sm, NULL);
  const double J = det(F), Jp = det(Fp), Jm = det(Fm);
  double tau[9], Sp[9], Sm[9], S[9], lie[9], lhs[9], o[6], Ht[9], Htau[9], tauHt[9];
  full_of(s, S);
  full_of(sp, Sp);
  full_of(sm, Sm);
  for (int q = 0; q < 9; q++) {
    tau[q] = J * S[q];
    Ht[q] = H[3 * (q % 3) + q / 3];
  }
  mul(H, tau, Htau);
  mul(tau, Ht, tauHt);
  for (int q = 0; q < 9; q++) lie[q] = (Jp * Sp[q] - Jm * Sm[q]) / (2 * h) - Htau[q] - tauHt[q];
  double v[6];
  for (int k = 0; k < 6; k++) {
    const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
    v[k] = a == b ? H[4 * a] : H[3 * a + b] + H[3 * b + a];
  }
  for (int i = 0; i < 6; i++) {
    o[i] = 0.0;
    for (int j = 0; j < 6; j++) o[i] += J * D[6 * i + j] * v[j];
  }
  full_of(o, lhs);
  double e2 = 0, n2 = 0;
  for (int q = 0; q < 9; q++) {
    e2 += (lhs[q] - lie[q]) * (lhs[q] - lie[q]);
    n2 += lie[q] * lie[q];
  }
  return sqrt(e2 / n2);
}

/* Principal values of a Voigt stress, sorted descending. */
static void principal(const double s[6], double l[3]) {
  double V[9];
  mpgm_sym3_eigen(s, l, V);
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2 - i; j++)
      if (l[j] < l[j + 1]) {
        const double q = l[j];
        l[j] = l[j + 1];
        l[j + 1] = q;
      }
}

/* From a committed state on the yield surface (one plastic step), a second
 * step dF not coaxial with it: per region, J D : sym(H) against the Lie
 * derivative of tau, f(tau) = 0 after the return, and the new b_e carries
 * the returned stress; the states with three distinct principal stresses
 * and all three shear stresses non-zero counted apart. */
static void check_finite_tangent(const mpgm_material *m, rng *r, const char *tag) {
  int count[5] = {0}, n3d = 0;
  double err[5] = {0}, asym = 0.0, worst_f = 0.0, worst_state = 0.0, err3d = 0.0;
  for (int n = 0; n < 60000; n++) {
    double st0[7], st1[7], st2[7], tmp[7], s[6], s2[6], D[36], Q[9], U1[9], Fn[9], dF[9], F[9];
    m->type->init_state(m, st0);
    const int mode = n % 3; /* random, uniaxial, biaxial compression */
    random_rotation(r, Q);
    random_stretch(r, mode, -0.02, mode ? -0.005 : 0.01, 0.02, U1);
    mul(Q, U1, Fn);
    if (m->type->update(m, MPGM_KIN_FINITE, Fn, Fn, st0, st1, s, NULL)) continue;
    if (!(st1[6] > 0.0)) continue; /* start from a state on the yield surface */
    random_stretch(r, mode, mode ? -0.01 : -0.006, mode ? -0.001 : 0.006, 0.006, dF);
    mul(dF, Fn, F);
    const int reg = finite_region(m, dF, st1);
    if (count[reg] >= 60) continue;
    if (m->type->update(m, MPGM_KIN_FINITE, F, dF, st1, st2, s, D)) continue;
    int same;
    const double e = lie_error(m, Fn, dF, st1, s, D, r, reg, &same);
    if (!same) continue;
    err[reg] = fmax(err[reg], e);
    count[reg]++;
    const double J = det(F);
    double tau[6], l[3], I[9], sn = 0.0, dn = 0.0;
    for (int k = 0; k < 6; k++) {
      tau[k] = J * s[k];
      sn += s[k] * s[k];
    }
    for (int k = 0; k < 36; k++) dn += D[k] * D[k];
    principal(tau, l);
    const double scale = fabs(l[0]) + fabs(l[1]) + fabs(l[2]) + m->param[2];
    if (reg != MPGM_MC_ELASTIC) worst_f = fmax(worst_f, fabs(m->type->yield(m, tau)) / scale);
    eye(I);
    m->type->update(m, MPGM_KIN_FINITE, F, I, st2, tmp, s2, NULL);
    for (int k = 0; k < 6; k++) worst_state = fmax(worst_state, fabs(s2[k] - s[k]) / sqrt(sn));
    const double gap = fmin(l[0] - l[1], l[1] - l[2]) / (fabs(l[0]) + fabs(l[2]));
    if (reg != MPGM_MC_ELASTIC && gap > 1e-2 && fabs(s[3]) > 1e-3 * sqrt(sn) &&
        fabs(s[4]) > 1e-3 * sqrt(sn) && fabs(s[5]) > 1e-3 * sqrt(sn)) {
      n3d++;
      err3d = fmax(err3d, e);
    }
    if (reg != MPGM_MC_ELASTIC && reg != MPGM_MC_APEX) {
      double a = 0.0;
      for (int i = 0; i < 6; i++)
        for (int j = i + 1; j < 6; j++) a += fabs(D[6 * i + j] - D[6 * j + i]);
      asym = fmax(asym, a / sqrt(dn));
    }
  }
  for (int g = 0; g < 5; g++) {
    mpgm_test(count[g] >= 20, "%s finite: %d second steps in region %s", tag, count[g],
              region_name[g]);
    mpgm_test_abs(err[g], 0.0, 1e-6,
                  "%s finite: J D:sym(H) = Lie derivative of tau (central diff) in region %s "
                  "(max rel err %.2e)", tag, region_name[g], err[g]);
  }
  mpgm_test_abs(worst_f, 0.0, 1e-10, "%s finite: |f(tau)| <= 1e-10 scale after the return (max %.2e)",
                tag, worst_f);
  mpgm_test_abs(worst_state, 0.0, TEST_TOL4,
                "%s finite: the new b_e carries the returned stress (max rel err %.2e)", tag,
                worst_state);
  mpgm_test(n3d >= 20, "%s finite: %d plastic states with distinct principal stresses and all "
            "shears non-zero", tag, n3d);
  mpgm_test_abs(err3d, 0.0, 1e-6, "%s finite: tangent in those 3-D states (max rel err %.2e)", tag,
                err3d);
  if (m->symmetric)
    mpgm_test_abs(asym, 0.0, TEST_TOL3, "%s finite: psi = phi: D symmetric (max %.2e)", tag, asym);
  else
    mpgm_test(asym > 1e-3, "%s finite: psi < phi: D unsymmetric in plastic regions (%.2e)", tag,
              asym);
}

/* Repeated principal stretches (F = I, uniaxial, biaxial and hydrostatic
 * stretch, exactly on the axes and rotated): finite outputs, and the
 * tangent against central differences where the region is the same on
 * both sides. */
static void check_repeated(const mpgm_material *m, rng *r, const char *tag) {
  const double cases[5][3] = {{1, 1, 1}, {0.97, 1, 1}, {1, 0.975, 0.975}, {1.02, 1.02, 1.02},
                              {0.96, 0.96, 0.96}};
  int finite = 1, nfd = 0;
  double worst = 0.0;
  for (int c = 0; c < 5; c++)
    for (int rot = 0; rot < 2; rot++) {
      double Q[9], F[9] = {0}, T[9], st0[7], st1[7], s[6], D[36];
      eye(Q);
      if (rot) random_rotation(r, Q);
      for (int i = 0; i < 3; i++) /* F = Q diag Q^T, symmetric */
        for (int j = 0; j < 3; j++) T[3 * i + j] = Q[3 * i + j] * cases[c][j];
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
          for (int k = 0; k < 3; k++) F[3 * i + j] += T[3 * i + k] * Q[3 * j + k];
      m->type->init_state(m, st0);
      for (int kin = 0; kin < 2; kin++) {
        const int e = m->type->update(m, kin, F, F, st0, st1, s, D);
        finite &= e == 0;
        for (int k = 0; k < 6; k++) finite &= isfinite(s[k]) != 0;
        for (int k = 0; k < 36; k++) finite &= isfinite(D[k]) != 0;
        for (int k = 0; k < 7; k++) finite &= isfinite(st1[k]) != 0;
      }
      m->type->update(m, MPGM_KIN_FINITE, F, F, st0, st1, s, D);
      double I[9];
      eye(I);
      int same;
      const double err = lie_error(m, I, F, st0, s, D, r, finite_region(m, F, st0), &same);
      if (same) {
        nfd++;
        worst = fmax(worst, err);
      }
    }
  mpgm_test(finite, "%s repeated stretches: updates succeed, stress, tangent, state finite", tag);
  mpgm_test(nfd >= 8, "%s repeated stretches: %d of 10 cases away from region boundaries", tag, nfd);
  mpgm_test_abs(worst, 0.0, 1e-6, "%s repeated stretches: tangent = central differences (max %.2e)",
                tag, worst);
}

/* Small kinematics from a plastic state: D against central differences of
 * sigma w.r.t. the engineering strain. */
static void check_small_tangent(const mpgm_material *m, rng *r, const char *tag) {
  double unit[6][9] = {{0}};
  for (int k = 0; k < 6; k++) {
    const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
    if (a == b) unit[k][4 * a] = 1.0;
    else unit[k][3 * a + b] = unit[k][3 * b + a] = 0.5;
  }
  double worst = 0.0;
  int nplastic = 0, count[5] = {0};
  for (int n = 0; n < 300; n++) {
    double st0[7], st1[7], tmp[7], s[6], D[36], F1[9], F[9];
    m->type->init_state(m, st0);
    for (int q = 0; q < 9; q++) F1[q] = (q % 4 == 0 ? 1.0 : 0.0) + uniform(r, -0.02, 0.01);
    m->type->update(m, MPGM_KIN_SMALL, F1, F1, st0, st1, s, NULL);
    for (int q = 0; q < 9; q++) F[q] = F1[q] + uniform(r, -0.004, 0.004);
    m->type->update(m, MPGM_KIN_SMALL, F, F, st1, tmp, s, D);
    if (tmp[6] == st1[6]) continue; /* elastic second step */
    nplastic++;
    const double h = 1e-8;
    double e2 = 0, n2 = 0;
    for (int j = 0; j < 6; j++) {
      double Fp[9], Fm[9], sp[6], sm[6];
      for (int q = 0; q < 9; q++) {
        Fp[q] = F[q] + h * unit[j][q];
        Fm[q] = F[q] - h * unit[j][q];
      }
      m->type->update(m, MPGM_KIN_SMALL, Fp, Fp, st1, tmp, sp, NULL);
      m->type->update(m, MPGM_KIN_SMALL, Fm, Fm, st1, tmp, sm, NULL);
      for (int i = 0; i < 6; i++) {
        const double fd = (sp[i] - sm[i]) / (2 * h);
        e2 += (fd - D[6 * i + j]) * (fd - D[6 * i + j]);
      }
    }
    for (int i = 0; i < 36; i++) n2 += D[i] * D[i];
    /* the region of this step, from the principal trial stresses */
    double l[3], tt[3] = {0};
    {
      double e[6];
      for (int k = 0; k < 6; k++) {
        const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
        e[k] = (a == b ? F[4 * a] - 1.0 : 0.5 * (F[3 * a + b] + F[3 * b + a])) +
               0.5 * (st1[k] - (k < 3));
      }
      principal(e, l);
      const double lam = m->c[MPGM_MC_LAMBDA], mu = m->c[MPGM_MC_MU], tr = lam * (l[0] + l[1] + l[2]);
      for (int i = 0; i < 3; i++) tt[i] = tr + 2 * mu * l[i];
    }
    double ss[3];
    count[mpgm_mc_return(m, tt, ss, NULL)]++;
    worst = fmax(worst, sqrt(e2) / fmax(sqrt(n2), m->c[MPGM_MC_MU]));
  }
  mpgm_test(nplastic >= 50, "%s small: %d plastic second steps (plane %d, edges %d %d, apex %d)",
            tag, nplastic, count[1], count[2], count[3], count[4]);
  mpgm_test_abs(worst, 0.0, 1e-6, "%s small: D = d sigma/d eps (central diff, max rel err %.2e)",
                tag, worst);
}
#endif

static void check_setup_and_init(void) {
  mpgm_material m;
  mpgm_test(make(25.31, &m) == 0 && m.symmetric == 1 && m.plastic == 1,
            "psi = phi: symmetric tangent, plastic");
  mpgm_test(make(0.0, &m) == 0 && m.symmetric == 0, "psi = 0: unsymmetric tangent");
  mpgm_test(make(30.0, &m) == MPGM_ERR_INPUT, "psi > phi refused");
  mpgm_test(m.type->nstate == MPGM_NSTRESS + 1 && m.type->plastic_strain && m.type->yield,
            "state of %d doubles, eps_p and yield operations", m.type->nstate);
  make(4.1, &m);
  /* apex at c cot phi; yield value 0 on the triaxial compression line */
  const double sp = sin(25.31 * PI / 180), c = 5.137e3;
  mpgm_test_rel(m.c[MPGM_MC_APEXS], c / tan(25.31 * PI / 180), TEST_TOL2, "apex at c cot phi");
  const double s3 = -4.0e4, s1 = s3 * (1 + sp) / (1 - sp) - 2 * c * cos(25.31 * PI / 180) / (1 - sp);
#if MPGM_DIM == 2
  const double tau[4] = {s3, s1, 0.0, s3};
#else
  const double tau[6] = {s3, s1, s3, 0.0, 0.0, 0.0};
#endif
  mpgm_test_abs(m.type->yield(&m, tau), 0.0, TEST_TOL3 * fabs(s1),
                "yield = 0 at sigma_1 = sigma_3 (1 + sin phi)/(1 - sin phi) + 2c cos phi/(1 - sin phi)");
  /* initial stress */
#if MPGM_DIM == 2
  const double s0[4] = {-2.31e4, -4.17e4, 3.2e3, -2.29e4};
  const double I[4] = {1, 0, 0, 1};
  const double bad[4] = {-1.0e3, -4.17e5, 0.0, -1.0e3};
#else /* three distinct principal stresses, principal axes off the frame */
  const double s0[6] = {-2.31e4, -4.17e4, -2.29e4, 3.2e3, -1.7e3, 2.1e3};
  const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double bad[6] = {-1.0e3, -4.17e5, -1.0e3, 0.0, 0.0, 0.0};
#endif
  for (int kin = 0; kin < 2; kin++) {
    double st[MPGM_NSTRESS + 1], st1[MPGM_NSTRESS + 1], s[MPGM_NSTRESS];
    char msg[256] = "";
    int e = m.type->init_stress(&m, kin, s0, st, msg, sizeof msg);
    m.type->update(&m, kin, I, I, st, st1, s, NULL);
    double err = 0;
    for (int i = 0; i < MPGM_NSTRESS; i++) err = fmax(err, fabs(s[i] - s0[i]) / 4.17e4);
    mpgm_test(e == 0, "init_stress %s returns %d", kin ? "small" : "finite", e);
    mpgm_test_abs(err, 0.0, TEST_TOL3, "init_stress %s: update at F = I returns s0 (rel err %.2e)",
                  kin ? "small" : "finite", err);
    mpgm_test(m.type->init_stress(&m, kin, bad, st, msg, sizeof msg) == MPGM_ERR_INPUT &&
                  strstr(msg, "outside the yield surface"),
              "init_stress %s: s0 outside the surface refused (%s)", kin ? "small" : "finite", msg);
  }
}

int main(void) {
  rng r = {0x2545F4914F6CDD1DULL};
  check_setup_and_init();
#if MPGM_DIM == 3
  check_eigen(&r);
#endif
  const double psis[3] = {0.0, 11.7, 25.31};
  const char *tags[3] = {"psi = 0", "psi = 11.7", "psi = phi"};
  for (int k = 0; k < 3; k++) {
    mpgm_material m;
    make(psis[k], &m);
    check_return(&m, &r, tags[k]);
    check_finite_tangent(&m, &r, tags[k]);
    check_small_tangent(&m, &r, tags[k]);
#if MPGM_DIM == 3
    check_repeated(&m, &r, tags[k]);
#endif
  }
  check_hencky(&r);
  return mpgm_test_summary();
}
