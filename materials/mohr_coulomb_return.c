/* mohr_coulomb_return.c -- the Mohr-Coulomb return mapping in principal
 * stress space, after Clausen, Damkilde & Andersen (Computers & Structures
 * 2006; IJNME 2007: non-associated flow): the region of the trial stress
 * decides the return (plane, edge s1 = s2, edge s2 = s3, apex), each a
 * closed-form projection along the elastic image of the plastic flow, and
 * the algorithmic tangent of each is a constant matrix (docs/theory.md,
 * section 15). Tension positive, sorted s[0] >= s[1] >= s[2].
 */
#include <math.h>
#include <string.h>

#include "mohr_coulomb_impl.h"


/* c = a x b */
static void cross(const double a[3], const double b[3], double c[3]) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* D b for the isotropic elastic matrix D = lambda 1 1^T + 2 mu I. */
static void elastic_times(const mpgm_material *m, const double b[3], double Db[3]) {
  const double lam = m->c[MPGM_MC_LAMBDA], mu2 = 2.0 * m->c[MPGM_MC_MU];
  const double tr = lam * (b[0] + b[1] + b[2]);
  for (int i = 0; i < 3; i++) Db[i] = tr + mu2 * b[i];
}

double mpgm_mc_yield_principal(const mpgm_material *m, const double s[3]) {
  double hi = s[0], lo = s[0];
  for (int i = 1; i < 3; i++) {
    if (s[i] > hi) hi = s[i];
    if (s[i] < lo) lo = s[i];
  }
  return m->c[MPGM_MC_K] * hi - lo - m->c[MPGM_MC_SC];
}

/* Projection onto the edge through the apex sa (1, 1, 1) with direction r,
 * along the plane spanned by the elastic flow images Dbp, Dbq:
 * s = sa + t r, t = N.(st - sa) / N.r, N = Dbp x Dbq. The tangent is
 * r N^T / N.r. Returns t (t <= 0 on the admissible half of the edge). */
static double edge_param(const double Dbp[3], const double Dbq[3], const double r[3],
                         const double st[3], double sa, double N[3]) {
  cross(Dbp, Dbq, N);
  const double d[3] = {st[0] - sa, st[1] - sa, st[2] - sa};
  return dot(N, d) / dot(N, r);
}

int mpgm_mc_return(const mpgm_material *m, const double st[3], double s[3], double dsdt[9]) {
  const double k = m->c[MPGM_MC_K], mm = m->c[MPGM_MC_M], sa = m->c[MPGM_MC_APEXS];
  const double f = k * st[0] - st[2] - m->c[MPGM_MC_SC];
  if (f <= 0.0) {
    memcpy(s, st, sizeof(double) * 3);
    if (dsdt) {
      memset(dsdt, 0, sizeof(double) * 9);
      dsdt[0] = dsdt[4] = dsdt[8] = 1.0;
    }
    return MPGM_MC_ELASTIC;
  }
  /* gradients a and flow directions b of the plane of the sextant (1) and
   * of its neighbours across the edges s1 = s2 (2) and s2 = s3 (3) */
  const double a1[3] = {k, 0.0, -1.0};
  const double b1[3] = {mm, 0.0, -1.0}, b2[3] = {0.0, mm, -1.0}, b3[3] = {mm, -1.0, 0.0};
  double Db1[3], Db2[3], Db3[3];
  elastic_times(m, b1, Db1);
  elastic_times(m, b2, Db2);
  elastic_times(m, b3, Db3);
  /* return to the plane: s = st - f Db1 / (a1 . Db1) */
  const double den = dot(a1, Db1);
  double rp[3], sp[3];
  for (int i = 0; i < 3; i++) {
    rp[i] = Db1[i] / den;
    sp[i] = st[i] - f * rp[i];
  }
  /* the plane return is the answer when it keeps the order of the sextant;
   * the sign of each order test is that of the trial stress against the
   * boundary plane of the plane region (a linear function of st) */
  const int beyond12 = sp[0] < sp[1], beyond23 = sp[1] < sp[2];
  if (!beyond12 && !beyond23) {
    memcpy(s, sp, sizeof sp);
    if (dsdt)
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) dsdt[3 * i + j] = (i == j ? 1.0 : 0.0) - rp[i] * a1[j];
    return MPGM_MC_PLANE;
  }
  /* an edge, unless the edge return would pass the apex (t > 0) */
  const double r12[3] = {1.0, 1.0, k}, r23[3] = {1.0, k, k};
  const double *r = beyond12 ? r12 : r23;
  double N[3];
  const double t = edge_param(Db1, beyond12 ? Db2 : Db3, r, st, sa, N);
  if (t <= 0.0) {
    const double nr = dot(N, r);
    for (int i = 0; i < 3; i++) s[i] = sa + t * r[i];
    if (dsdt)
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) dsdt[3 * i + j] = r[i] * N[j] / nr;
    return beyond12 ? MPGM_MC_EDGE_12 : MPGM_MC_EDGE_23;
  }
  s[0] = s[1] = s[2] = sa;
  if (dsdt) memset(dsdt, 0, sizeof(double) * 9);
  return MPGM_MC_APEX;
}
