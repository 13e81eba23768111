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
 * In MPGM_DIM terms; second steps not coaxial with the first, f(tau) = 0
 * after the return, the new b_e gives the returned stress back, repeated
 * stretches stay finite; 3-D also checks the Jacobi eigensolver.
 */
#include "mohr_coulomb_impl.h"
#include "mpgm_material.h"
#include "mpgm_test.h"
#include "support_tensor.h"

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

/* Sort three values in descending order. */
static void sort3(double t[3]) {
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2 - i; j++)
      if (t[j] < t[j + 1]) {
        const double q = t[j];
        t[j] = t[j + 1];
        t[j + 1] = q;
      }
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
    sort3(st);
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

/* ---- finite strain: DIM x DIM helpers ------------------------------------ */
/* Layouts of the build's MPGM_DIM: F row major, stresses and the b_e slots
 * of the state in the stress layout (2-D {xx, yy, xy, zz}, 3-D Voigt). */
enum { DIM = MPGM_DIM, NT = MPGM_TENSOR, NV = MPGM_NVOIGT, NS = MPGM_NSTRESS, NST = NS + 1 };

/* Rotation by th about the unit axis n (Rodrigues; 2-D: about z). */
static void axis_rotation(const double n[3], double th, double R[NT]) {
  const double c = cos(th), s = sin(th);
#if MPGM_DIM == 2
  (void)n;
  R[0] = c; R[1] = -s; R[2] = s; R[3] = c;
#else
  const double C = 1.0 - c;
  const double Q[9] = {c + n[0] * n[0] * C, n[0] * n[1] * C - n[2] * s, n[0] * n[2] * C + n[1] * s,
                       n[1] * n[0] * C + n[2] * s, c + n[1] * n[1] * C, n[1] * n[2] * C - n[0] * s,
                       n[2] * n[0] * C - n[1] * s, n[2] * n[1] * C + n[0] * s, c + n[2] * n[2] * C};
  memcpy(R, Q, sizeof Q);
#endif
}
/* A random unit vector (2-D: in the plane). */
static void random_unit(rng *r, double n[3]) {
  double nn;
  do {
    for (int i = 0; i < 3; i++) n[i] = i < DIM ? uniform(r, -1, 1) : 0.0;
    nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  } while (!(nn > 0.1 && nn <= 1.0));
  for (int i = 0; i < 3; i++) n[i] /= nn;
}
/* A random rotation: random axis (3-D), angle in [-pi, pi]. */
static void random_rotation(rng *r, double R[NT]) {
  double n[3];
  random_unit(r, n);
  axis_rotation(n, uniform(r, -PI, PI), R);
}
/* Principal values l and directions (the columns of V) of a symmetric
 * tensor in the stress layout: 2-D the in-plane pair in closed form, then
 * zz (direction z, not in V); 3-D the library's Jacobi solver (checked on
 * its own in check_eigen). */
static void eig_layout(const double v[NS], double l[3], double V[NT]) {
#if MPGM_DIM == 2
  const double h = 0.5 * (v[0] - v[1]), R = hypot(h, v[2]), mid = 0.5 * (v[0] + v[1]);
  const double th = 0.5 * atan2(v[2], h);
  l[0] = mid + R; l[1] = mid - R; l[2] = v[3];
  V[0] = cos(th); V[1] = -sin(th); V[2] = sin(th); V[3] = cos(th);
#else
  mpgm_sym3_eigen(v, l, V);
#endif
}
/* b = A B A^T in the stress layout for b0 = B in it (2-D: b_zz = B_zz). */
static void push(const double A[NT], const double B[NS], double b[NS]) {
  double Bf[NT], T[NT], At[NT], bf[NT];
  sym_of(B, Bf);
  transpose(A, At);
  mul(A, Bf, T);
  mul(T, At, bf);
  voigt_of(bf, b);
#if MPGM_DIM == 2
  b[3] = B[3];
#endif
}
/* Hencky: tau = lambda tr(e) I + 2 mu e, e = 1/2 ln(F F^T). */
static void hencky(const mpgm_material *m, const double F[NT], double sigma[NS]) {
  const double lam = m->c[MPGM_MC_LAMBDA], mu = m->c[MPGM_MC_MU];
  double I[NS] = {0}, b[NS], l[3], V[NT];
  for (int k = 0; k < NS; k++) I[k] = k < DIM || k == NV ? 1.0 : 0.0;
  push(F, I, b);
  eig_layout(b, l, V);
  const double e[3] = {0.5 * log(l[0]), 0.5 * log(l[1]), 0.5 * log(l[2])};
  const double tr = lam * (e[0] + e[1] + e[2]), J = det(F);
  for (int k = 0; k < NV; k++) {
    const int a = mpgm_voigt_pair[k][0], c = mpgm_voigt_pair[k][1];
    sigma[k] = 0.0;
    for (int i = 0; i < DIM; i++) sigma[k] += V[DIM * a + i] * V[DIM * c + i] * (tr + 2 * mu * e[i]) / J;
  }
#if MPGM_DIM == 2
  sigma[3] = tr / J;
#endif
}

/* Elastic paths: one step and 7 increments through b_e = Hencky. */
static void check_hencky(rng *r) {
  mpgm_material m;
  make(7.3, &m);
  m.param[2] = 1e12; /* cohesion far beyond the path: elastic */
  char msg[128];
  m.type->setup(&m, msg, sizeof msg);
  double worst1 = 0.0, worstn = 0.0;
  for (int k = 0; k < 16; k++) {
    double Q[NT], U[NT] = {0}, F[NT], s[NS], se[NS], st0[NST], st1[NST], st[NST], ax[3];
    random_unit(r, ax);
    const double th = uniform(r, -PI, PI);
    axis_rotation(ax, th, Q);
    for (int i = 0; i < DIM; i++)
      for (int j = i; j < DIM; j++)
        U[DIM * i + j] = i == j ? uniform(r, 0.7, 1.4) : uniform(r, -0.3, 0.3);
    mul(Q, U, F);
    hencky(&m, F, se);
    m.type->init_state(&m, st0);
    m.type->update(&m, MPGM_KIN_FINITE, F, F, st0, st1, s, NULL);
    double sn = 0.0;
    for (int i = 0; i < NS; i++) sn += fabs(se[i]);
    for (int i = 0; i < NS; i++) worst1 = fmax(worst1, fabs(s[i] - se[i]) / sn);
    /* the same end point in 7 increments F_i = Q(a th) (I + a (U - I)),
     * a = i/7, through b_e */
    double Fn[NT];
    identity(Fn);
    m.type->init_state(&m, st);
    int ierr = 0;
    for (int i = 1; i <= 7; i++) {
      const double a = i / 7.0;
      double Fi[NT], inv[NT], dF[NT], nst[NST], Qa[NT], Ua[NT];
      for (int q = 0; q < NT; q++) Ua[q] = (q % (DIM + 1) == 0 ? 1.0 - a : 0.0) + a * U[q];
      axis_rotation(ax, a * th, Qa);
      mul(Qa, Ua, Fi);
      inverse(Fn, inv);
      mul(Fi, inv, dF);
      ierr |= m.type->update(&m, MPGM_KIN_FINITE, Fi, dF, st, nst, s, NULL);
      memcpy(st, nst, sizeof st);
      memcpy(Fn, Fi, sizeof Fn);
    }
    for (int i = 0; i < NS; i++) worstn = fmax(worstn, fabs(s[i] - se[i]) / sn);
    mpgm_test(ierr == 0 && st[NS] == 0.0, "elastic path #%d: updates succeed, eps_p stays 0", k);
  }
  mpgm_test_abs(worst1, 0.0, TEST_TOL4, "elastic: one step = Hencky law (max rel err %.2e)", worst1);
  mpgm_test_abs(worstn, 0.0, TEST_TOL5,
                "elastic: 7 increments through b_e = Hencky law (max rel err %.2e)", worstn);
}

/* Region of the return for the trial tensor x in the stress layout:
 * principal trial strains 1/2 ln of its eigenvalues (logs: x = b_tr) or
 * the eigenvalues themselves (x = eps_tr). */
static int trial_region(const mpgm_material *m, const double x[NS], int logs) {
  double l[3], V[NT], t[3], s[3];
  eig_layout(x, l, V);
  if (logs)
    for (int i = 0; i < 3; i++) l[i] = 0.5 * log(l[i]);
  const double lam = m->c[MPGM_MC_LAMBDA], mu = m->c[MPGM_MC_MU];
  const double tr = lam * (l[0] + l[1] + l[2]);
  for (int i = 0; i < 3; i++) t[i] = tr + 2 * mu * l[i];
  sort3(t);
  return mpgm_mc_return(m, t, s, NULL);
}

/* Region of the return a finite update takes (recomputed from b_tr). */
static int finite_region(const mpgm_material *m, const double dF[NT], const double *st_n) {
  double b[NS];
  push(dF, st_n, b);
  return trial_region(m, b, 1);
}

/* I + l n (x) n (uniaxial, mode 1) or I + l (I - n (x) n) (biaxial, mode 2)
 * along a random unit n, plus noise; mode 0: I + random entries in
 * [lo, hi] on the diagonal and +-w off it. */
static void random_stretch(rng *r, int mode, double lo, double hi, double w, double F[NT]) {
  double n[3];
  random_unit(r, n);
  const double l = uniform(r, lo, hi);
  for (int i = 0; i < DIM; i++)
    for (int j = 0; j < DIM; j++) {
      const double d = i == j ? 1.0 : 0.0;
      double *v = &F[DIM * i + j];
      if (mode == 0) *v = d + (i == j ? uniform(r, lo, hi) : uniform(r, -w, w));
      else *v = d + l * (mode == 1 ? n[i] * n[j] : d - n[i] * n[j]) + uniform(r, -1e-4, 1e-4);
    }
}

/* J D : sym(H) against the Lie derivative of tau by central differences,
 * F = (I + h H) dF F_n, from the committed state st1: rel err, or
 * *same = 0 when the perturbed steps leave the region reg. */
static double lie_error(const mpgm_material *m, const double Fn[NT], const double dF[NT],
                        const double *st1, const double s[NS], const double D[MPGM_NTANGENT],
                        rng *r, int reg, int *same) {
  double H[NT], Ip[NT], Im[NT], dFp[NT], dFm[NT], Fp[NT], Fm[NT], F[NT], sp[NS], sm[NS], tmp[NST];
  const double h = 1e-7;
  for (int q = 0; q < NT; q++) {
    H[q] = uniform(r, -1, 1);
    Ip[q] = (q % (DIM + 1) == 0) + h * H[q];
    Im[q] = (q % (DIM + 1) == 0) - h * H[q];
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
  double Sp[NT], Sm[NT], S[NT], lie[NT], lhs[NT], o[NS], Ht[NT], HS[NT], SHt[NT];
  sym_of(s, S);
  sym_of(sp, Sp);
  sym_of(sm, Sm);
  transpose(H, Ht);
  mul(H, S, HS);
  mul(S, Ht, SHt); /* tau = J sigma */
  for (int q = 0; q < NT; q++) lie[q] = (Jp * Sp[q] - Jm * Sm[q]) / (2 * h) - J * (HS[q] + SHt[q]);
  for (int i = 0; i < NV; i++) { /* J D : sym(H), engineering shear */
    o[i] = 0.0;
    for (int j = 0; j < NV; j++) {
      const int a = mpgm_voigt_pair[j][0], b = mpgm_voigt_pair[j][1];
      o[i] += J * D[NV * i + j] * (a == b ? H[(DIM + 1) * a] : H[DIM * a + b] + H[DIM * b + a]);
    }
  }
  sym_of(o, lhs);
  double e2 = 0, n2 = 0;
  for (int q = 0; q < NT; q++) {
    e2 += (lhs[q] - lie[q]) * (lhs[q] - lie[q]);
    n2 += lie[q] * lie[q];
  }
  return sqrt(e2 / n2);
}

#if MPGM_DIM == 3
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
    sort3(l);
    sort3(lt);
    const double lmax = fmax(fabs(lt[0]), fabs(lt[2]));
    for (int i = 0; i < 3; i++) worst_l = fmax(worst_l, fabs(l[i] - lt[i]) / lmax);
    for (int q = 0; q < 9; q++) { /* V^T V - I */
      const int i = q / 3, j = q % 3;
      const double d = V[i] * V[j] + V[3 + i] * V[3 + j] + V[6 + i] * V[6 + j] - (i == j);
      worst_orth = fmax(worst_orth, isfinite(d) ? fabs(d) : 1.0);
    }
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
  const double I6[6] = {2, 2, 2, 0, 0, 0}, bad[6] = {1, 1, NAN, 0, 0, 0};
  double l[3], V[9];
  mpgm_test(mpgm_sym3_eigen(I6, l, V) == 0 && l[0] == 2 && l[1] == 2 && l[2] == 2 && V[0] == 1 &&
                V[4] == 1 && V[8] == 1, "eigen: 2 I gives 2, 2, 2 and V = I");
  mpgm_test(mpgm_sym3_eigen(bad, l, V) != 0, "eigen: NaN refused");
}

#endif

/* From a committed state on the yield surface (one plastic step), a second
 * step dF not coaxial with it: per region, J D : sym(H) against the Lie
 * derivative of tau, f(tau) = 0 after the return, and the new b_e carries
 * the returned stress; the states with three distinct principal stresses
 * and all three shear stresses non-zero counted apart. */
static void check_finite_tangent(const mpgm_material *m, rng *r, const char *tag) {
  int count[5] = {0}, n3d = 0;
  double err[5] = {0}, asym = 0.0, worst_f = 0.0, worst_state = 0.0;
  for (int n = 0; n < 60000; n++) {
    double st0[NST], st1[NST], st2[NST], tmp[NST], s[NS], s2[NS], D[MPGM_NTANGENT], Q[NT], U1[NT], Fn[NT], dF[NT], F[NT];
    m->type->init_state(m, st0);
    const int mode = n % 3; /* random, uniaxial, biaxial compression */
    random_rotation(r, Q);
    random_stretch(r, mode, -0.02, mode ? -0.005 : 0.01, 0.02, U1);
    mul(Q, U1, Fn);
    if (m->type->update(m, MPGM_KIN_FINITE, Fn, Fn, st0, st1, s, NULL)) continue;
    if (!(st1[NS] > 0.0)) continue; /* start from a state on the yield surface */
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
    double tau[NS], l[3], V[NT], sn = 0.0, dn = 0.0;
    for (int k = 0; k < NS; k++) {
      tau[k] = J * s[k];
      sn += s[k] * s[k];
    }
    for (int k = 0; k < MPGM_NTANGENT; k++) dn += D[k] * D[k];
    eig_layout(tau, l, V);
    sort3(l);
    const double scale = fabs(l[0]) + fabs(l[1]) + fabs(l[2]) + m->param[2];
    if (reg != MPGM_MC_ELASTIC) worst_f = fmax(worst_f, fabs(m->type->yield(m, tau)) / scale);
    identity(V); /* dF = I from the new state */
    m->type->update(m, MPGM_KIN_FINITE, F, V, st2, tmp, s2, NULL);
    for (int k = 0; k < NS; k++) worst_state = fmax(worst_state, fabs(s2[k] - s[k]) / sqrt(sn));
    const double gap = fmin(l[0] - l[1], l[1] - l[2]) / (fabs(l[0]) + fabs(l[2]));
    int shears = 1;
    for (int k = DIM; k < NV; k++) shears &= fabs(s[k]) > 1e-3 * sqrt(sn);
    n3d += reg != MPGM_MC_ELASTIC && gap > 1e-2 && shears;
    if (reg != MPGM_MC_ELASTIC && reg != MPGM_MC_APEX) {
      double a = 0.0;
      for (int i = 0; i < NV; i++)
        for (int j = i + 1; j < NV; j++) a += fabs(D[NV * i + j] - D[NV * j + i]);
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
  mpgm_test(n3d >= 20, "%s finite: %d of the checked plastic states have distinct principal "
            "stresses and all shears non-zero", tag, n3d);
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
      double Q[NT], Qt[NT], G[NT] = {0}, T[NT], F[NT], st0[NST], st1[NST], s[NS], D[MPGM_NTANGENT];
      identity(Q);
      if (rot) random_rotation(r, Q);
      for (int i = 0; i < DIM; i++) G[(DIM + 1) * i] = cases[c][i];
      transpose(Q, Qt); /* F = Q G Q^T, symmetric */
      mul(Q, G, T);
      mul(T, Qt, F);
      m->type->init_state(m, st0);
      for (int kin = 0; kin < 2; kin++) {
        const int e = m->type->update(m, kin, F, F, st0, st1, s, D);
        finite &= e == 0;
        for (int k = 0; k < MPGM_NTANGENT; k++)
          finite &= isfinite(D[k]) && (k >= NS || isfinite(s[k])) && (k >= NST || isfinite(st1[k]));
      }
      m->type->update(m, MPGM_KIN_FINITE, F, F, st0, st1, s, D);
      identity(Q); /* F_n = I */
      int same;
      const double err = lie_error(m, Q, F, st0, s, D, r, finite_region(m, F, st0), &same);
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
  double unit[NV][NT] = {{0}};
  for (int k = 0; k < NV; k++) {
    const int a = mpgm_voigt_pair[k][0], b = mpgm_voigt_pair[k][1];
    if (a == b) unit[k][(DIM + 1) * a] = 1.0;
    else unit[k][DIM * a + b] = unit[k][DIM * b + a] = 0.5;
  }
  double worst = 0.0;
  int nplastic = 0;
  for (int n = 0; n < 300; n++) {
    double st0[NST], st1[NST], tmp[NST], s[NS], D[MPGM_NTANGENT], F1[NT], F[NT];
    m->type->init_state(m, st0);
    for (int q = 0; q < NT; q++) F1[q] = (q % (DIM + 1) == 0 ? 1.0 : 0.0) + uniform(r, -0.02, 0.01);
    m->type->update(m, MPGM_KIN_SMALL, F1, F1, st0, st1, s, NULL);
    for (int q = 0; q < NT; q++) F[q] = F1[q] + uniform(r, -0.004, 0.004);
    m->type->update(m, MPGM_KIN_SMALL, F, F, st1, tmp, s, D);
    if (tmp[NS] == st1[NS]) continue; /* elastic second step */
    nplastic++;
    const double h = 1e-8;
    double e2 = 0, n2 = 0;
    for (int j = 0; j < NV; j++) {
      double Fp[NT], Fm[NT], sp[NS], sm[NS];
      for (int q = 0; q < NT; q++) {
        Fp[q] = F[q] + h * unit[j][q];
        Fm[q] = F[q] - h * unit[j][q];
      }
      m->type->update(m, MPGM_KIN_SMALL, Fp, Fp, st1, tmp, sp, NULL);
      m->type->update(m, MPGM_KIN_SMALL, Fm, Fm, st1, tmp, sm, NULL);
      for (int i = 0; i < NV; i++) {
        const double fd = (sp[i] - sm[i]) / (2 * h);
        e2 += (fd - D[NV * i + j]) * (fd - D[NV * i + j]);
      }
    }
    for (int i = 0; i < MPGM_NTANGENT; i++) n2 += D[i] * D[i];
    worst = fmax(worst, sqrt(e2) / fmax(sqrt(n2), m->c[MPGM_MC_MU]));
  }
  mpgm_test(nplastic >= 50, "%s small: %d plastic second steps", tag, nplastic);
  mpgm_test_abs(worst, 0.0, 1e-6, "%s small: D = d sigma/d eps (central diff, max rel err %.2e)",
                tag, worst);
}

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
  double tau[NS] = {0}; /* xx = zz = s3, yy = s1 */
  tau[0] = tau[DIM == 2 ? 3 : 2] = s3;
  tau[1] = s1;
  mpgm_test_abs(m.type->yield(&m, tau), 0.0, TEST_TOL3 * fabs(s1),
                "yield = 0 at sigma_1 = sigma_3 (1 + sin phi)/(1 - sin phi) + 2c cos phi/(1 - sin phi)");
  /* initial stress */
#if MPGM_DIM == 2
  const double s0[4] = {-2.31e4, -4.17e4, 3.2e3, -2.29e4};
  const double bad[4] = {-1.0e3, -4.17e5, 0.0, -1.0e3};
#else /* three distinct principal stresses, principal axes off the frame */
  const double s0[6] = {-2.31e4, -4.17e4, -2.29e4, 3.2e3, -1.7e3, 2.1e3};
  const double bad[6] = {-1.0e3, -4.17e5, -1.0e3, 0.0, 0.0, 0.0};
#endif
  double I[NT];
  identity(I);
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
    check_repeated(&m, &r, tags[k]);
  }
  check_hencky(&r);
  return mpgm_test_summary();
}
