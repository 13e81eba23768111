/* lme.c -- local maximum-entropy shape functions (Arroyo & Ortiz 2006;
 * Iaconeta et al. 2017, eq 61; Molinos et al., eqs 35-42): the "lme" kind.
 *
 * In coordinates scaled by the spacing h, d_a = (x - x_a) / h, and with
 * gamma = beta h^2 (equation numbers of Molinos et al.):
 *
 *   f_a(lambda) = -gamma |d_a|^2 + lambda . d_a,   Z = sum_a exp(f_a),
 *   N_a = exp(f_a) / Z                                       (36)-(37)
 *   lambda* = argmin log Z:   r = d log Z / d lambda = sum N_a d_a = 0   (39)
 *   J = d r / d lambda = sum N_a (d_a - r) (d_a - r)^T   (Hessian)    (38)
 *
 * Newton on lambda with a backtracking (Armijo) line search on log Z, which
 * is strictly convex when x is inside the convex hull of the cloud, so the
 * iteration cannot diverge: every accepted step lowers log Z. Far from the
 * solution the step is capped (LME_STEP_CAP) and a numerically singular J
 * regularised. The start is q->lambda (warm start, stored back on success)
 * or zero.
 *
 * Gradient (eq 42): differentiating r(x, lambda*(x)) = 0 gives
 * d lambda* / dx = (2 beta I - J^-1) (physical units) and
 *   grad N_a = -N_a J^-1 (x - x_a)
 * (derivation in docs/theory.md; the sign is checked against central
 * differences in tests/unit/test_shapefn_meshfree.c). We use the centred
 * form grad N_a = -N_a J^-1 (x - x_a - r) / h in scaled units, identical at
 * r = 0, which keeps sum grad N_a = 0 and sum x_a (x) grad N_a = I exact to
 * round-off even when Newton stops at |r| = tol_newton.
 *
 * Support: nodes with exp(-gamma |d_a|^2) < tol_support get N = 0, or with a
 * fixed radius (par->radius > 0) the nodes beyond it.
 *
 * Failures (recoverable MPGM_ERR_SHAPE, N = dN = 0, reason in q->info):
 *   - fewer than 3 nodes in the support (TOO_FEW);
 *   - x outside the convex hull of the nodes in the support (OUTSIDE_HULL):
 *     found by a direct O(n) test before Newton (the smallest cone from x
 *     holding every node: if it is narrower than pi - tol_newton, x is
 *     outside). A point on the hull boundary passes (weak Kronecker-delta:
 *     lambda grows along the outward normal until the nodes off the boundary
 *     are below tol_newton; about ln(1/tol_newton) iterations cold);
 *   - a degenerate cloud (the covariance of the nodes has cond_2 >
 *     max_cond: collinear) or cond_2(J) > max_cond at the converged
 *     multiplier (ILL_COND);
 *   - max_newton iterations or a stalled line search (NOT_CONVERGED; a point
 *     the cone test found on the boundary reports OUTSIDE_HULL instead).
 * The caller may then add the next-nearest node to the cloud and retry
 * (Iaconeta et al. 2017, section 5.3); this file never changes the cloud.
 */
#include "mpgm_shapefn_impl.h"

#include <math.h>
#include <string.h>

#if MPGM_DIM != 2
#error "shapefn/lme.c is written for plane strain only (MPGM_DIM = 2)"
#endif

typedef struct {
  double logZ;
  double r[2];
  double J[3]; /* J00, J01, J11 */
} lme_moments;

enum { HULL_INSIDE = 0, HULL_BOUNDARY = 1, HULL_OUTSIDE = 2 };

/* Largest change of an exponent f_a - sum_b N_b f_b in one Newton step:
 * -ln(DBL_EPSILON) = 36 takes a node from dominant to negligible. Far from
 * the solution (cold start at large gamma, where one node holds almost all
 * the weight) J is nearly singular and the raw Newton step is ~1e80 times
 * too long; capped, gamma = 100 converges in ~10 iterations. */
#define LME_STEP_CAP 36.0
/* Line search: a step halved this often has stalled. */
#define LME_MAX_HALVINGS 40

/* Where the weight exp(-beta r^2), beta = gamma / h^2, falls to w. */
static int lme_weight_radius(const mpgm_shape_params *par, double w, double *R) {
  *R = 0.0;
  if (!par || !(par->h > 0.0) || !(w > 0.0 && w < 1.0)) return MPGM_ERR_INPUT;
  const double gamma = mpgm_shape_dflt(par->gamma, MPGM_LME_GAMMA);
  *R = par->h * sqrt(-log(w) / gamma);
  return isfinite(*R) ? 0 : MPGM_ERR_INPUT;
}

static int lme_radius(const mpgm_shape_params *par, double *R) {
  *R = 0.0;
  if (!par || !(par->h > 0.0)) return MPGM_ERR_INPUT;
  /* a fixed radius (the paper's search radius, shape.radius), else where
   * the weight falls below tol_support */
  if (par->radius > 0.0) {
    *R = par->radius;
    return 0;
  }
  const double tol = par->tol_support > 0.0 && par->tol_support < 1.0 ? par->tol_support
                                                                       : MPGM_LME_TOL_SUPPORT;
  return lme_weight_radius(par, tol, R);
}

/* Where the origin lies with respect to the convex hull of the points v
 * (2 per point, none at the origin): the incremental smallest cone [lo, hi]
 * (counter-clockwise from lo to hi, opening < pi) holding every v. If no
 * such cone exists the origin is in the closed hull. The cone test is
 * exact in the sense that the only tolerance is on the final opening:
 * opening > pi - angtol is reported as the boundary. */
static int hull_class(int n, const double *v, double angtol) {
  /* the signs of the cross and dot products do not depend on the lengths:
   * only lo and hi are normalised, at the end */
  double lo[2] = {v[0], v[1]}, hi[2] = {v[0], v[1]};
  for (int a = 1; a < n; a++) {
    const double c[2] = {v[2 * a], v[2 * a + 1]};
    const double cl = lo[0] * c[1] - lo[1] * c[0]; /* lo x c */
    const double ch = c[0] * hi[1] - c[1] * hi[0]; /* c x hi */
    if (cl >= 0.0 && ch >= 0.0 && (lo[0] * c[0] + lo[1] * c[1] > 0.0 ||
                                   hi[0] * c[0] + hi[1] * c[1] > 0.0))
      continue; /* inside the cone */
    if (-cl > 0.0 && ch > 0.0) { /* c clockwise of lo, within pi of hi */
      lo[0] = c[0];
      lo[1] = c[1];
    } else if (-ch > 0.0 && cl > 0.0) { /* c counter-clockwise of hi */
      hi[0] = c[0];
      hi[1] = c[1];
    } else {
      return HULL_INSIDE; /* the directions span more than a half-plane */
    }
  }
  const double s = 1.0 / (hypot(lo[0], lo[1]) * hypot(hi[0], hi[1]));
  const double sn = (lo[0] * hi[1] - lo[1] * hi[0]) * s, cs = (lo[0] * hi[0] + lo[1] * hi[1]) * s;
  return cs > 0.0 || sn > angtol ? HULL_OUTSIDE : HULL_BOUNDARY;
}

/* N_a (into p), r, J and log Z at lambda; d: scaled offsets, f0: -gamma |d|^2. */
static void moments(int n, const double *d, const double *f0, const double lam[2], double *p,
                    lme_moments *s) {
  double fmax = -INFINITY;
  for (int a = 0; a < n; a++) {
    p[a] = f0[a] + lam[0] * d[2 * a] + lam[1] * d[2 * a + 1];
    fmax = fmax > p[a] ? fmax : p[a];
  }
  double Z = 0.0;
  for (int a = 0; a < n; a++) {
    p[a] = exp(p[a] - fmax);
    Z += p[a];
  }
  const double iZ = 1.0 / Z;
  double r0 = 0.0, r1 = 0.0;
  for (int a = 0; a < n; a++) {
    p[a] *= iZ;
    r0 += p[a] * d[2 * a];
    r1 += p[a] * d[2 * a + 1];
  }
  /* centred second moments: accurate when J is small against r r^T */
  double J00 = 0.0, J01 = 0.0, J11 = 0.0;
  for (int a = 0; a < n; a++) {
    const double e0 = d[2 * a] - r0, e1 = d[2 * a + 1] - r1;
    J00 += p[a] * e0 * e0;
    J01 += p[a] * e0 * e1;
    J11 += p[a] * e1 * e1;
  }
  s->logZ = fmax + log(Z);
  s->r[0] = r0;
  s->r[1] = r1;
  s->J[0] = J00;
  s->J[1] = J01;
  s->J[2] = J11;
}

/* 2-norm condition number of the symmetric 2x2 J (inf if not positive). */
static double cond2(const double J[3]) {
  const double m = 0.5 * (J[0] + J[2]), h = 0.5 * (J[0] - J[2]);
  const double lmax = m + sqrt(h * h + J[1] * J[1]);
  const double lmin = (J[0] * J[2] - J[1] * J[1]) / lmax; /* det / lmax: no cancellation */
  return lmax > 0.0 && lmin > 0.0 ? lmax / lmin : INFINITY;
}

/* Condition number of the covariance of the scaled offsets d (ns of
 * them): infinite for a degenerate (collinear) cloud. */
static double cloud_cond(int ns, const double *d) {
  double m0 = 0.0, m1 = 0.0, C[3] = {0.0, 0.0, 0.0};
  for (int a = 0; a < ns; a++) m0 += d[2 * a], m1 += d[2 * a + 1];
  m0 /= ns;
  m1 /= ns;
  for (int a = 0; a < ns; a++) {
    const double e0 = d[2 * a] - m0, e1 = d[2 * a + 1] - m1;
    C[0] += e0 * e0;
    C[1] += e0 * e1;
    C[2] += e1 * e1;
  }
  return cond2(C);
}

/* One damped Newton step on the multiplier lam (moments s at lam): the
 * new lam and its moments *st (p: N at it). Returns 1 when the line
 * search fails. */
static int newton_step(int ns, const double *d, const double *f0, double *p, double lam[2],
                       const lme_moments *s, lme_moments *st) {
  /* Newton direction dl = -(J + mu I)^-1 r; mu > 0 only when J is
   * numerically singular at an iterate (far from the solution, when one
   * node holds almost all the weight) */
  const double tr = s->J[0] + s->J[2];
  double J0 = s->J[0], J2 = s->J[2];
  double det = J0 * J2 - s->J[1] * s->J[1];
  if (!(det > 1e-24 * tr * tr)) {
    const double mu = 1e-12 * tr + 1e-300;
    J0 += mu;
    J2 += mu;
    det = J0 * J2 - s->J[1] * s->J[1];
  }
  double dl[2] = {-(J2 * s->r[0] - s->J[1] * s->r[1]) / det,
                  -(-s->J[1] * s->r[0] + J0 * s->r[1]) / det};
  const double slope = s->r[0] * dl[0] + s->r[1] * dl[1]; /* < 0 */
  /* step cap: no exponent f_a moves by more than LME_STEP_CAP against
   * the weighted mean in one step (J nearly singular gives huge steps
   * that the line search would have to halve ~50 times) */
  double fch = 0.0;
  for (int a = 0; a < ns; a++)
    fch = fmax(fch, fabs(dl[0] * (d[2 * a] - s->r[0]) + dl[1] * (d[2 * a + 1] - s->r[1])));
  double t = fch > LME_STEP_CAP ? LME_STEP_CAP / fch : 1.0;
  /* Armijo backtracking; the slack lets a full step through when log Z
   * changes below its round-off near the solution */
  const double slack = 8.0 * 2.220446049250313e-16 * (1.0 + fabs(s->logZ));
  double trial[2];
  int halvings = 0;
  for (;; halvings++) {
    trial[0] = lam[0] + t * dl[0];
    trial[1] = lam[1] + t * dl[1];
    moments(ns, d, f0, trial, p, st);
    if (st->logZ <= s->logZ + 1e-4 * t * slope + slack || halvings == LME_MAX_HALVINGS) break;
    t *= 0.5;
  }
  if (halvings == LME_MAX_HALVINGS || !isfinite(st->logZ)) return 1;
  lam[0] = trial[0];
  lam[1] = trial[1];
  return 0;
}

static int lme_eval(const mpgm_shape_query *q, double *N, double *dN) {
  int err = mpgm_shape_check_cloud(q, N, dN);
  if (err) return err;
  const mpgm_shape_params *par = q->par;
  double rmax;
  if (lme_radius(par, &rmax)) return mpgm_shape_fail(q, N, dN, MPGM_ERR_INPUT, MPGM_SHAPE_BAD_INPUT);
  const double h = par->h, ih = 1.0 / h;
  const double gamma = mpgm_shape_dflt(par->gamma, MPGM_LME_GAMMA);
  const double tol = mpgm_shape_dflt(par->tol_newton, MPGM_LME_TOL_NEWTON);
  const int max_newton = par->max_newton > 0 ? par->max_newton : MPGM_LME_MAX_NEWTON;
  const double max_cond = mpgm_shape_dflt(par->max_cond, MPGM_LME_MAX_COND);
  const double r2max = (rmax * ih) * (rmax * ih);

  /* the nodes in the support, scaled offsets d = (x - x_a) / h */
  int idx[MPGM_SHAPE_MAXNODE], ns = 0, at_node = 0;
  double d[2 * MPGM_SHAPE_MAXNODE], f0[MPGM_SHAPE_MAXNODE], p[MPGM_SHAPE_MAXNODE];
  memset(N, 0, sizeof(double) * (size_t)q->n);
  memset(dN, 0, sizeof(double) * 2 * (size_t)q->n);
  for (int a = 0; a < q->n; a++) {
    const double d0 = (q->xp[0] - q->xn[2 * a]) * ih, d1 = (q->xp[1] - q->xn[2 * a + 1]) * ih;
    const double r2 = d0 * d0 + d1 * d1;
    if (!(r2 <= r2max)) continue;
    idx[ns] = a;
    d[2 * ns] = d0;
    d[2 * ns + 1] = d1;
    f0[ns] = -gamma * r2;
    at_node |= r2 < 1e-28;
    ns++;
  }
  if (ns < 3) return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_TOO_FEW);
  /* at a node the point is in the hull; otherwise the cone test
   * (directions x_a - x = -d_a: the sign does not matter for the test) */
  const int hull = at_node ? HULL_INSIDE : hull_class(ns, d, tol);
  if (hull == HULL_OUTSIDE) return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_OUTSIDE_HULL);
  /* a degenerate (collinear) cloud: its own covariance is singular, and so
   * is J at any lambda */
  const double cc = cloud_cond(ns, d);
  if (!(cc <= max_cond)) {
    if (q->info) q->info->cond = cc;
    return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, MPGM_SHAPE_ILL_COND);
  }

  double lam[2] = {0.0, 0.0};
  if (q->lambda && isfinite(q->lambda[0]) && isfinite(q->lambda[1])) {
    lam[0] = q->lambda[0] * h;
    lam[1] = q->lambda[1] * h;
  }
  lme_moments s;
  moments(ns, d, f0, lam, p, &s);
  int it = 0, reason = MPGM_SHAPE_OK;
  double cond = cond2(s.J), rn = hypot(s.r[0], s.r[1]);
  for (;; it++) {
    rn = hypot(s.r[0], s.r[1]);
    if (rn < tol) {
      cond = cond2(s.J); /* the Hessian the gradient is built from */
      if (!(cond <= max_cond)) reason = MPGM_SHAPE_ILL_COND;
      break;
    }
    if (it >= max_newton) { reason = MPGM_SHAPE_NOT_CONVERGED; break; }
    lme_moments st;
    if (newton_step(ns, d, f0, p, lam, &s, &st)) {
      reason = MPGM_SHAPE_NOT_CONVERGED;
      break;
    }
    s = st;
  }
  if (q->info) {
    q->info->iterations = it;
    q->info->nsupport = ns;
    q->info->cond = cond;
    q->info->residual = rn;
  }
  if (reason != MPGM_SHAPE_OK) {
    if (hull == HULL_BOUNDARY) reason = MPGM_SHAPE_OUTSIDE_HULL;
    return mpgm_shape_fail(q, N, dN, MPGM_ERR_SHAPE, reason);
  }
  /* p holds N at the accepted lambda (the last moments() call) */
  const double det = s.J[0] * s.J[2] - s.J[1] * s.J[1];
  const double i00 = s.J[2] / det, i01 = -s.J[1] / det, i11 = s.J[0] / det;
  for (int k = 0; k < ns; k++) {
    const int a = idx[k];
    const double e0 = d[2 * k] - s.r[0], e1 = d[2 * k + 1] - s.r[1];
    N[a] = p[k];
    dN[2 * a] = -p[k] * (i00 * e0 + i01 * e1) * ih;
    dN[2 * a + 1] = -p[k] * (i01 * e0 + i11 * e1) * ih;
  }
  if (q->lambda) {
    q->lambda[0] = lam[0] * ih;
    q->lambda[1] = lam[1] * ih;
  }
  mpgm_shape_ok(q, it, ns, cond, rn);
  return 0;
}

/* shape.* of "lme" (docs/scene-format.md, "shape") */
static const mpgm_key_spec lme_keys[] = {
    {.name = "gamma", .type = MPGM_KEY_REAL, .offset = offsetof(mpgm_shape_params, gamma),
     .def = MPGM_LME_GAMMA, .lo = 0.0, .hi = INFINITY, .lo_open = 1, .unit = "-",
     .doc = "locality gamma = beta h^2 (0.8 spread out ... 4 nearly FE)"},
    {.name = "tol_support", .type = MPGM_KEY_REAL,
     .offset = offsetof(mpgm_shape_params, tol_support), .def = MPGM_LME_TOL_SUPPORT, .lo = 0.0,
     .hi = 1.0, .lo_open = 1, .hi_open = 1, .unit = "-",
     .doc = "nodes where exp(-gamma r^2 / h^2) < tol_support get N = 0"},
    {.name = "radius", .type = MPGM_KEY_REAL, .offset = offsetof(mpgm_shape_params, radius),
     .def = 0.0, .lo = 0.0, .hi = INFINITY, .unit = "m",
     .doc = "a fixed search radius (replaces tol_support); 0: from tol_support"},
    MPGM_MAX_COND_KEY,
    MPGM_CLOUD_KEYS,
};

const mpgm_shapefn_type mpgm_shapefn_lme = {
    .name = "lme",
    .doc = "local maximum-entropy (Arroyo-Ortiz), beta = gamma / h^2, support cut where "
           "exp(-beta r^2) < tol_support or at a fixed radius",
    .needs_cell = 0,
    .eval = lme_eval,
    .support_radius = lme_radius,
    .weight_radius = lme_weight_radius,
    .keys = lme_keys,
    .nkeys = sizeof lme_keys / sizeof *lme_keys,
};
