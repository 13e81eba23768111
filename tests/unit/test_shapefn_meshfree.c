/* test_shapefn_meshfree.c -- conformance suite of the shape-function family
 * run over every kind in mpgm_shapefn_types(): FE through its cells (T3,
 * Q4; brief, test_shapefn.c covers FE in depth), MLS with linear and
 * quadratic basis, LME, uGIMP (regular grid only; test_ugimp.c has the
 * rest). On a regular grid and on randomly perturbed, rotated node sets,
 * at random points, with the cloud found by brute-force radius search
 * within mpgm_shape_support_radius:
 *
 *   - partition of unity, linear reproduction sum N_a x_a = x,
 *     sum grad N_a = 0 and sum x_a (x) grad N_a = I (MLS quadratic: also
 *     quadratic reproduction);
 *   - grad N against central differences of N;
 *   - LME: N >= 0; weak Kronecker-delta property on a boundary edge and at a
 *     corner; convergence to the T3 functions of the (unique) Delaunay
 *     triangulation of an equilateral lattice as gamma grows;
 *   - recoverable failures (MPGM_ERR_SHAPE with a reason, N = dN = 0, no
 *     NaN): point outside the hull of its cloud, too few or collinear nodes,
 *     the LME Hessian guard; fatal MPGM_ERR_INPUT for a cloud larger than
 *     MPGM_SHAPE_MAXNODE or no length scale;
 *   - LME warm start from the stored multiplier takes fewer iterations.
 */
#include "mpgm_shapefn.h"
#include "mpgm_test.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Partition of unity and linear reproduction. MLS: round-off of a few
 * solves with cond(M) < 1e3. LME: Newton stops at |r| / h < tol_newton =
 * 1e-10 and sum N_a x_a - x = -r, so the error is below 1e-10 h (h < 1
 * here); the gradient identities hold to round-off by construction. */
#define TOL_REPRO 1e-10
/* Central differences: truncation O(e^2 |N'''|) + rounding O(eps / e) with
 * e = 1e-5 h; LME evaluated with tol_newton = 1e-13 so that the Newton
 * residual (~tol / e in the difference quotient) stays below it. */
#define TOL_FD 1e-6
#define FD_STEP 1e-5
#define FD_TOL_NEWTON 1e-13
/* Weak Kronecker delta: at convergence r . n = sum_off N_a (distance of a
 * to the edge) / h < tol_newton, and the off-edge nodes are >= 0.5 h from
 * the edge here, so their total N is below 2 tol_newton = 2e-10. */
#define TOL_KRONECKER 2e-10

#define N_POINTS 12 /* random points per node set and kind */

static const double H = 0.4137;                 /* nodal spacing [m] */
static const double X0 = 0.3173, Y0 = -0.4621;  /* grid origin [m] */
enum { NX = 11, NY = 10 };                      /* grid nodes */

/* ---- node sets -------------------------------------------------------------- */

typedef struct {
  int n;
  double x[2 * NX * NY * 2];
  int edge[NX * NY * 2]; /* 1 on the bottom edge (before rotation) */
} nodeset;

/* NX x NY grid; interior nodes moved by up to jitter * H, boundary nodes
 * only along their edge (corners fixed), then rotated by th about the
 * origin and translated, so the boundary stays straight. */
static void grid(nodeset *s, rng *r, double jitter, double th) {
  const double c = cos(th), sn = sin(th);
  s->n = 0;
  for (int j = 0; j < NY; j++)
    for (int i = 0; i < NX; i++) {
      double dx = uniform(r, -jitter, jitter) * H, dy = uniform(r, -jitter, jitter) * H;
      if (i == 0 || i == NX - 1) dx = 0.0;
      if (j == 0 || j == NY - 1) dy = 0.0;
      const double x = i * H + dx, y = j * H + dy;
      s->x[2 * s->n] = X0 + c * x - sn * y;
      s->x[2 * s->n + 1] = Y0 + sn * x + c * y;
      s->edge[s->n] = j == 0;
      s->n++;
    }
}

/* Point of grid coordinates (u, v) (in units of H, before rotation). */
static void grid_point(double th, double u, double v, double x[2]) {
  x[0] = X0 + cos(th) * u * H - sin(th) * v * H;
  x[1] = Y0 + sin(th) * u * H + cos(th) * v * H;
}

/* Nodes of s within radius of x (brute force), in their set order. */
static int cloud(const nodeset *s, const double x[2], double radius, int *id, double *xc) {
  int n = 0;
  for (int a = 0; a < s->n && n < MPGM_SHAPE_MAXNODE; a++)
    if (hypot(s->x[2 * a] - x[0], s->x[2 * a + 1] - x[1]) <= radius) {
      id[n] = a;
      xc[2 * n] = s->x[2 * a];
      xc[2 * n + 1] = s->x[2 * a + 1];
      n++;
    }
  return n;
}

/* ---- the kinds under test --------------------------------------------------- */

typedef struct {
  const mpgm_shapefn_type *t;
  mpgm_shape_params par;
  char label[32];
} variant;

static int eval_cloud(const variant *v, int n, const double *xn, const double x[2], double *lam,
                      double *N, double *dN, mpgm_shape_info *info) {
  mpgm_shape_query q = {.n = n, .xn = xn, .xp = {x[0], x[1]}, .cell = -1, .par = &v->par,
                        .lambda = lam, .info = info};
  return v->t->eval(&q, N, dN);
}

/* Identities at one point. */
static void check_identities(const char *what, int n, const double *xn, const double x[2],
                             const double *N, const double *dN, int order) {
  double sum = 0.0, rx = 0.0, ry = 0.0, g0 = 0.0, g1 = 0.0, Id[4] = {0, 0, 0, 0};
  double q[3] = {0, 0, 0};
  int finite = 1;
  for (int a = 0; a < n; a++) {
    finite &= isfinite(N[a]) && isfinite(dN[2 * a]) && isfinite(dN[2 * a + 1]);
    sum += N[a];
    rx += N[a] * xn[2 * a];
    ry += N[a] * xn[2 * a + 1];
    g0 += dN[2 * a];
    g1 += dN[2 * a + 1];
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 2; j++) Id[2 * i + j] += xn[2 * a + i] * dN[2 * a + j];
    const double u = xn[2 * a] - x[0], w = xn[2 * a + 1] - x[1];
    q[0] += N[a] * u * u;
    q[1] += N[a] * u * w;
    q[2] += N[a] * w * w;
  }
  mpgm_test(finite, "%s: N and grad N finite", what);
  mpgm_test_abs(sum, 1.0, TOL_REPRO, "%s: partition of unity", what);
  mpgm_test_abs(hypot(rx - x[0], ry - x[1]), 0.0, TOL_REPRO, "%s: sum N_a x_a = x", what);
  mpgm_test_abs(hypot(g0, g1) * H, 0.0, TOL_REPRO, "%s: sum grad N_a = 0 (times h)", what);
  mpgm_test_abs(fabs(Id[0] - 1.0) + fabs(Id[1]) + fabs(Id[2]) + fabs(Id[3] - 1.0), 0.0,
                TOL_REPRO, "%s: sum x_a (x) grad N_a = I", what);
  if (order == 2)
    mpgm_test_abs(fabs(q[0]) + fabs(q[1]) + fabs(q[2]), 0.0, TOL_REPRO * H,
                  "%s: quadratic reproduction sum N_a (x_a - x)(x) (x_a - x) = 0", what);
}

/* Meshfree kind at a random point of a node set: identities, FD, N >= 0. */
static void check_meshfree_point(const variant *v, const nodeset *s, const double x[2],
                                 const char *where) {
  double radius = 0.0;
  int err = mpgm_shape_support_radius(v->t, &v->par, &radius);
  int id[MPGM_SHAPE_MAXNODE];
  double xn[2 * MPGM_SHAPE_MAXNODE], N[MPGM_SHAPE_MAXNODE], dN[2 * MPGM_SHAPE_MAXNODE];
  char what[128];
  snprintf(what, sizeof what, "%s %s (%.4f, %.4f)", v->label, where, x[0], x[1]);
  mpgm_test(err == 0 && radius > H, "%s: support radius %g > h", what, radius);
  const int n = cloud(s, x, radius, id, xn);
  mpgm_shape_info info;
  double lam[2] = {0.0, 0.0};
  err = eval_cloud(v, n, xn, x, lam, N, dN, &info);
  mpgm_test(err == 0 && info.reason == MPGM_SHAPE_OK, "%s: eval returns %d (%s), %d nodes", what,
            err, info.msg, n);
  if (err) return;
  check_identities(what, n, xn, x, N, dN, v->par.order);
  if (strcmp(v->t->name, "lme") == 0) {
    double nmin = INFINITY;
    for (int a = 0; a < n; a++) nmin = fmin(nmin, N[a]);
    mpgm_test(nmin >= 0.0, "%s: N >= 0 (min %g)", what, nmin);
  }
  /* central differences with the same cloud */
  variant vf = *v;
  vf.par.tol_newton = FD_TOL_NEWTON;
  const double e = FD_STEP * H;
  double gmax = 0.0, emax = 0.0;
  int ok = 1;
  for (int a = 0; a < 2 * n; a++) gmax = fmax(gmax, fabs(dN[a]));
  for (int d = 0; d < 2; d++) {
    double xp[2] = {x[0], x[1]}, xm[2] = {x[0], x[1]}, lp[2] = {lam[0], lam[1]},
           lm[2] = {lam[0], lam[1]};
    double Np[MPGM_SHAPE_MAXNODE], Nm[MPGM_SHAPE_MAXNODE], dd[2 * MPGM_SHAPE_MAXNODE];
    xp[d] += e;
    xm[d] -= e;
    ok &= eval_cloud(&vf, n, xn, xp, lp, Np, dd, NULL) == 0 &&
          eval_cloud(&vf, n, xn, xm, lm, Nm, dd, NULL) == 0;
    for (int a = 0; a < n; a++)
      emax = fmax(emax, fabs((Np[a] - Nm[a]) / (2.0 * e) - dN[2 * a + d]));
  }
  mpgm_test(ok, "%s: evaluation at perturbed points", what);
  mpgm_test_abs(emax / gmax, 0.0, TOL_FD, "%s: grad N = central differences (rel)", what);
}

/* FE kind in one cell: identities and FD through the cell path. */
static int eval_cell(const mpgm_shapefn_type *t, int cell, const double *xn, const double x[2],
                     double *N, double *dN) {
  mpgm_shape_query q = {.n = mpgm_fe_nnode(cell), .xn = xn, .xp = {x[0], x[1]}, .cell = cell};
  int err = mpgm_fe_local(cell, xn, x, q.xi);
  return err ? err : t->eval(&q, N, dN);
}

static void check_cell_kind(const mpgm_shapefn_type *t, rng *r) {
  for (int cell = MPGM_CELL_T3; cell <= MPGM_CELL_Q4; cell++) {
    const int nn = mpgm_fe_nnode(cell);
    for (int k = 0; k < 4; k++) {
      /* a cell of the perturbed grid: corners (i, j) (i+1, j) (i+1, j+1) (i, j+1) */
      double xn[8];
      const double c[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      const double tri[3][2] = {{0, 0}, {1, 0}, {0, 1}};
      for (int a = 0; a < nn; a++) {
        const double *u = cell == MPGM_CELL_T3 ? tri[a] : c[a];
        double p[2];
        grid_point(0.3 * k, 3.0 + u[0] + uniform(r, -0.2, 0.2),
                   2.0 + u[1] + uniform(r, -0.2, 0.2), p);
        xn[2 * a] = p[0];
        xn[2 * a + 1] = p[1];
      }
      double xi[2] = {uniform(r, 0.05, 0.45), uniform(r, 0.05, 0.45)}, x[2] = {0, 0};
      if (cell == MPGM_CELL_Q4) xi[0] = 2.0 * xi[0] - 0.5, xi[1] = 2.0 * xi[1] - 0.5;
      double N[4], dN[8];
      mpgm_fe_ref(cell, xi, N, NULL);
      for (int a = 0; a < nn; a++) x[0] += N[a] * xn[2 * a], x[1] += N[a] * xn[2 * a + 1];
      char what[96];
      snprintf(what, sizeof what, "%s %s cell %d", t->name, cell == MPGM_CELL_T3 ? "T3" : "Q4", k);
      int err = eval_cell(t, cell, xn, x, N, dN);
      mpgm_test(err == 0, "%s: eval returns %d", what, err);
      if (err) continue;
      check_identities(what, nn, xn, x, N, dN, 1);
      const double e = FD_STEP * H;
      double gmax = 0.0, emax = 0.0;
      for (int a = 0; a < 2 * nn; a++) gmax = fmax(gmax, fabs(dN[a]));
      for (int d = 0; d < 2; d++) {
        double xp[2] = {x[0], x[1]}, xm[2] = {x[0], x[1]}, Np[4], Nm[4], dd[8];
        xp[d] += e;
        xm[d] -= e;
        err = eval_cell(t, cell, xn, xp, Np, dd) | eval_cell(t, cell, xn, xm, Nm, dd);
        for (int a = 0; a < nn; a++)
          emax = fmax(emax, fabs((Np[a] - Nm[a]) / (2.0 * e) - dN[2 * a + d]));
      }
      mpgm_test(err == 0, "%s: evaluation at perturbed points", what);
      mpgm_test_abs(emax / gmax, 0.0, TOL_FD, "%s: grad N = central differences (rel)", what);
    }
    double rad = 0.0;
    mpgm_test(mpgm_shape_support_radius(t, NULL, &rad) == MPGM_ERR_UNSUPPORTED,
              "%s: support radius is MPGM_ERR_UNSUPPORTED", t->name);
  }
}

/* ---- LME: weak Kronecker delta on the hull boundary ------------------------- */

static void check_kronecker(const variant *v, const nodeset *s, double th, rng *r,
                            const char *sname) {
  double radius = 0.0;
  mpgm_shape_support_radius(v->t, &v->par, &radius);
  int id[MPGM_SHAPE_MAXNODE];
  double xn[2 * MPGM_SHAPE_MAXNODE], N[MPGM_SHAPE_MAXNODE], dN[2 * MPGM_SHAPE_MAXNODE];
  for (int k = 0; k < 4; k++) {
    /* a point on the bottom edge, between its end nodes */
    double x[2];
    grid_point(th, uniform(r, 1.5, NX - 2.5), 0.0, x);
    const int n = cloud(s, x, radius, id, xn);
    mpgm_shape_info info;
    int err = eval_cloud(v, n, xn, x, NULL, N, dN, &info);
    char what[128];
    snprintf(what, sizeof what, "lme %s edge point %d (%.4f, %.4f)", sname, k, x[0], x[1]);
    mpgm_test(err == 0, "%s: eval returns %d (%s, cond %.3g, %d iterations)", what, err, info.msg,
              info.cond, info.iterations);
    if (err) continue;
    double off = 0.0, on = 0.0;
    int finite = 1;
    for (int a = 0; a < n; a++) {
      if (s->edge[id[a]]) on += N[a];
      else off += N[a];
      finite &= isfinite(dN[2 * a]) && isfinite(dN[2 * a + 1]);
    }
    mpgm_test_abs(off, 0.0, TOL_KRONECKER, "%s: nodes off the edge have N ~ 0", what);
    mpgm_test_abs(on, 1.0, TOL_KRONECKER, "%s: the edge nodes carry N", what);
    mpgm_test(finite, "%s: grad N finite", what);
  }
  /* the corner nodes of the bottom edge */
  for (int c = 0; c < 2; c++) {
    const int a0 = c ? NX - 1 : 0;
    const double x[2] = {s->x[2 * a0], s->x[2 * a0 + 1]};
    const int n = cloud(s, x, radius, id, xn);
    mpgm_shape_info info;
    int err = eval_cloud(v, n, xn, x, NULL, N, dN, &info);
    double Nc = -1.0;
    for (int a = 0; a < n; a++)
      if (id[a] == a0) Nc = N[a];
    mpgm_test(err == 0, "lme %s corner %d: eval returns %d (%s)", sname, c, err, info.msg);
    mpgm_test_abs(Nc, 1.0, TOL_KRONECKER, "lme %s corner %d: N = 1 at the corner node", sname, c);
  }
}

/* ---- LME -> T3 of the Delaunay triangulation as gamma grows ----------------- */

/* Barycentric coordinates of x in triangle (a, b, c). */
static void bary(const double *a, const double *b, const double *c, const double x[2],
                 double l[3]) {
  const double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
  l[1] = ((x[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (x[1] - a[1])) / det;
  l[2] = ((b[0] - a[0]) * (x[1] - a[1]) - (x[0] - a[0]) * (b[1] - a[1])) / det;
  l[0] = 1.0 - l[1] - l[2];
}

/* The Delaunay triangle of the cloud holding x, by brute force: the triple
 * whose triangle contains x and whose circumcircle holds no other node.
 * Returns 1 and fills tri (cloud indices), or 0 if none or not unique. */
static int delaunay_triangle(int n, const double *xn, const double x[2], int tri[3]) {
  int found = 0;
  for (int a = 0; a < n; a++)
    for (int b = a + 1; b < n; b++)
      for (int c = b + 1; c < n; c++) {
        const double *pa = xn + 2 * a, *pb = xn + 2 * b, *pc = xn + 2 * c;
        const double det = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pc[0] - pa[0]) * (pb[1] - pa[1]);
        if (fabs(det) < 1e-12) continue;
        double l[3];
        bary(pa, pb, pc, x, l);
        if (l[0] < 0.0 || l[1] < 0.0 || l[2] < 0.0) continue;
        /* circumcentre */
        const double bx = pb[0] - pa[0], by = pb[1] - pa[1], cx = pc[0] - pa[0],
                     cy = pc[1] - pa[1];
        const double dd = 2.0 * (bx * cy - by * cx);
        const double ux = (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / dd;
        const double uy = (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / dd;
        const double R2 = ux * ux + uy * uy;
        int empty = 1;
        for (int e = 0; e < n && empty; e++) {
          if (e == a || e == b || e == c) continue;
          const double ex = xn[2 * e] - pa[0] - ux, ey = xn[2 * e + 1] - pa[1] - uy;
          empty = ex * ex + ey * ey > R2 * (1.0 + 1e-9);
        }
        if (!empty) continue;
        tri[0] = a, tri[1] = b, tri[2] = c;
        found++;
      }
  return found == 1;
}

static void check_fe_limit(const mpgm_shapefn_type *lme, rng *r) {
  /* equilateral lattice (unique Delaunay triangulation), rotated */
  static nodeset s;
  const double th = 0.4129, cth = cos(th), sth = sin(th);
  s.n = 0;
  for (int j = 0; j < 14; j++)
    for (int i = 0; i < 14; i++) {
      const double u = (i + 0.5 * j) * H, v = j * H * sqrt(3.0) / 2.0;
      s.x[2 * s.n] = X0 + cth * u - sth * v;
      s.x[2 * s.n + 1] = Y0 + sth * u + cth * v;
      s.edge[s.n++] = 0;
    }
  const double gammas[3] = {10.0, 30.0, 100.0};
  /* Measured max |N_lme - N_fe| at 20 points: 1.0e-3, 2.4e-12, 1.3e-14 for
   * gamma 10, 30, 100 (h |grad N| differences 1.1e-1, 3.0e-10, 1.3e-15):
   * the difference decays like exp(-gamma) (the power of the nearest
   * non-Delaunay node with respect to the circumcircle of the triangle is
   * h^2 on this lattice), down to the Newton residual (1e-13) times
   * |J^-1| ~ 10 at gamma 100. */
  const double tol_final = 1e-12;
  double errN[3] = {0, 0, 0}, errG[3] = {0, 0, 0};
  int ok = 1, npt = 0;
  for (int k = 0; k < 20; k++) {
    /* a point in the middle of the lattice */
    const double a = uniform(r, 5.0, 7.0), b = uniform(r, 5.0, 7.0); /* lattice coordinates */
    const double u = (a + 0.5 * b) * H, v = b * H * sqrt(3.0) / 2.0;
    const double x[2] = {X0 + cth * u - sth * v, Y0 + sth * u + cth * v};
    int id[MPGM_SHAPE_MAXNODE], tri[3];
    double xn[2 * MPGM_SHAPE_MAXNODE];
    const int n = cloud(&s, x, 2.5 * H, id, xn);
    if (!delaunay_triangle(n, xn, x, tri)) { ok = 0; continue; }
    double l[3];
    bary(xn + 2 * tri[0], xn + 2 * tri[1], xn + 2 * tri[2], x, l);
    double Nfe[MPGM_SHAPE_MAXNODE] = {0}, Gfe[2 * MPGM_SHAPE_MAXNODE] = {0};
    {
      const double *pa = xn + 2 * tri[0], *pb = xn + 2 * tri[1], *pc = xn + 2 * tri[2];
      const double det = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pc[0] - pa[0]) * (pb[1] - pa[1]);
      const double g[3][2] = {{(pb[1] - pc[1]) / det, (pc[0] - pb[0]) / det},
                              {(pc[1] - pa[1]) / det, (pa[0] - pc[0]) / det},
                              {(pa[1] - pb[1]) / det, (pb[0] - pa[0]) / det}};
      for (int i = 0; i < 3; i++) {
        Nfe[tri[i]] = l[i];
        Gfe[2 * tri[i]] = g[i][0];
        Gfe[2 * tri[i] + 1] = g[i][1];
      }
    }
    npt++;
    for (int ig = 0; ig < 3; ig++) {
      /* the cloud (2.5 h) is the caller's; no cut-off inside it. Newton to
       * 1e-13 so that its residual (N error ~ |J^-1 r|) is below the
       * LME-FE difference being measured */
      variant v = {.t = lme,
                   .par = {.h = H, .gamma = gammas[ig], .tol_support = 1e-300, .tol_newton = 1e-13}};
      double N[MPGM_SHAPE_MAXNODE], dN[2 * MPGM_SHAPE_MAXNODE];
      mpgm_shape_info info;
      int err = eval_cloud(&v, n, xn, x, NULL, N, dN, &info);
      if (err) {
        ok = 0;
        printf("  gamma %g at (%g, %g): %s\n", gammas[ig], x[0], x[1], info.msg);
        continue;
      }
      for (int a = 0; a < n; a++) {
        errN[ig] = fmax(errN[ig], fabs(N[a] - Nfe[a]));
        errG[ig] = fmax(errG[ig], H * hypot(dN[2 * a] - Gfe[2 * a], dN[2 * a + 1] - Gfe[2 * a + 1]));
      }
    }
  }
  mpgm_test(ok && npt == 20, "LME -> FE: Delaunay triangle unique and LME converged at %d points",
            npt);
  printf("LME vs T3 of the Delaunay triangulation (equilateral lattice, %d points):\n", npt);
  for (int ig = 0; ig < 3; ig++)
    printf("  gamma %5.0f: max |N_lme - N_fe| = %.3e, max h |grad N_lme - grad N_fe| = %.3e\n",
           gammas[ig], errN[ig], errG[ig]);
  mpgm_test(errN[1] < errN[0] && errN[2] < errN[1] && errG[1] < errG[0] && errG[2] < errG[1],
            "LME -> FE: error decreases as gamma grows (10, 30, 100)");
  mpgm_test_abs(errN[2], 0.0, tol_final, "LME -> FE: N at gamma 100");
  mpgm_test_abs(errG[2], 0.0, tol_final, "LME -> FE: h grad N at gamma 100");
}

/* ---- failures ----------------------------------------------------------------- */

static int all_zero(int n, const double *N, const double *dN) {
  for (int a = 0; a < n; a++)
    if (N[a] != 0.0 || dN[2 * a] != 0.0 || dN[2 * a + 1] != 0.0) return 0;
  return 1;
}

/* Expect MPGM_ERR_SHAPE with the given reason and zeroed outputs. */
static void expect_fail(const variant *v, int n, const double *xn, const double x[2], int code,
                        int reason, const char *what) {
  double N[MPGM_SHAPE_MAXNODE], dN[2 * MPGM_SHAPE_MAXNODE];
  for (int a = 0; a < MPGM_SHAPE_MAXNODE; a++) N[a] = dN[2 * a] = dN[2 * a + 1] = NAN;
  mpgm_shape_info info;
  double lam[2] = {0.25, -0.5};
  int err = eval_cloud(v, n, xn, x, lam, N, dN, &info);
  mpgm_test(err == code && info.reason == reason,
            "%s %s: returns %d (%s), expected %d (%s)", v->label, what, err, info.msg, code,
            mpgm_shape_reason_str(reason));
  mpgm_test(n > MPGM_SHAPE_MAXNODE || all_zero(n, N, dN), "%s %s: N = dN = 0, no NaN", v->label,
            what);
  mpgm_test(lam[0] == 0.25 && lam[1] == -0.5, "%s %s: lambda untouched", v->label, what);
}

static void check_failures(const variant *mls1, const variant *mls2, const variant *lme,
                           const nodeset *s) {
  double xn[2 * MPGM_SHAPE_MAXNODE];
  int id[MPGM_SHAPE_MAXNODE];
  const variant *mf[3] = {mls1, mls2, lme};
  /* a point outside the node set: LME by the hull test; MLS has no hull
   * condition but too few nodes in its support there */
  double x[2];
  int err;
  grid_point(0.0, NX + 0.7, 3.3, x);
  int n = cloud(s, x, 3.0 * H, id, xn);
  expect_fail(lme, n, xn, x, MPGM_ERR_SHAPE, MPGM_SHAPE_OUTSIDE_HULL, "point outside the grid");
  /* inside the grid, but the cloud holds only the nodes to its right */
  grid_point(0.0, 4.3, 4.6, x);
  n = 0;
  for (int a = 0; a < s->n; a++)
    if (s->x[2 * a] > x[0] + 0.1 * H && hypot(s->x[2 * a] - x[0], s->x[2 * a + 1] - x[1]) < 2.5 * H)
      xn[2 * n] = s->x[2 * a], xn[2 * n + 1] = s->x[2 * a + 1], n++;
  expect_fail(lme, n, xn, x, MPGM_ERR_SHAPE, MPGM_SHAPE_OUTSIDE_HULL,
              "point outside the hull of a one-sided cloud");
  /* two nodes */
  const double two[4] = {X0, Y0, X0 + H, Y0 + 0.3 * H};
  const double xm[2] = {X0 + 0.5 * H, Y0 + 0.15 * H};
  for (int k = 0; k < 3; k++)
    expect_fail(mf[k], 2, two, xm, MPGM_ERR_SHAPE, MPGM_SHAPE_TOO_FEW, "two nodes");
  /* five nodes: enough for the linear basis, not for the quadratic one */
  double five[10];
  const double c5[5][2] = {{0, 0}, {1, 0.1}, {0.2, 1}, {0.9, 0.8}, {0.45, 0.55}};
  for (int a = 0; a < 5; a++) five[2 * a] = X0 + c5[a][0] * H, five[2 * a + 1] = Y0 + c5[a][1] * H;
  const double x5[2] = {X0 + 0.5 * H, Y0 + 0.4 * H};
  expect_fail(mls2, 5, five, x5, MPGM_ERR_SHAPE, MPGM_SHAPE_TOO_FEW, "five nodes, quadratic");
  double N[MPGM_SHAPE_MAXNODE], dN[2 * MPGM_SHAPE_MAXNODE];
  mpgm_test(eval_cloud(mls1, 5, five, x5, NULL, N, dN, NULL) == 0, "mls linear: five nodes work");
  /* collinear nodes, point on their line */
  double line[12];
  for (int a = 0; a < 6; a++) line[2 * a] = X0 + a * 0.4 * H, line[2 * a + 1] = Y0 + a * 0.3 * H;
  const double xl[2] = {X0 + 1.13 * 0.4 * H, Y0 + 1.13 * 0.3 * H};
  for (int k = 0; k < 3; k++)
    expect_fail(mf[k], 6, line, xl, MPGM_ERR_SHAPE, MPGM_SHAPE_ILL_COND, "collinear nodes");
  /* the guards: cond >= 1 always, so max_cond = 1 + 1e-6 trips them at a
   * point where the cloud is not isotropic */
  variant tight = *lme;
  tight.par.max_cond = 1.0 + 1e-6;
  grid_point(0.0, 4.37, 3.71, x);
  double rad;
  mpgm_shape_support_radius(lme->t, &lme->par, &rad);
  n = cloud(s, x, rad, id, xn);
  expect_fail(&tight, n, xn, x, MPGM_ERR_SHAPE, MPGM_SHAPE_ILL_COND, "max_cond = 1 + 1e-6");
  mpgm_test(eval_cloud(lme, n, xn, x, NULL, N, dN, NULL) == 0, "lme: default max_cond passes");
  /* the Hessian guard proper: 1e-8 h inside the bottom edge the cloud is
   * fine but J ~ 1e-8 across the edge (cond ~ 1e8 > 1e6) */
  {
    variant mid = *lme;
    mid.par.max_cond = 1e6;
    double xe[2];
    grid_point(0.0, 4.61, 1e-8, xe);
    const int ne = cloud(s, xe, rad, id, xn);
    mpgm_shape_info ie;
    err = eval_cloud(&mid, ne, xn, xe, NULL, N, dN, &ie);
    mpgm_test(err == MPGM_ERR_SHAPE && ie.reason == MPGM_SHAPE_ILL_COND && ie.iterations > 0 &&
                  ie.cond > 1e6 && all_zero(ne, N, dN),
              "lme 1e-8 h from the edge, max_cond 1e6: Hessian guard (%s, cond %.3g after %d "
              "iterations)", ie.msg, ie.cond, ie.iterations);
    err = eval_cloud(lme, ne, xn, xe, NULL, N, dN, &ie);
    mpgm_test(err == 0, "lme 1e-8 h from the edge, default max_cond: converges (cond %.3g)",
              ie.cond);
  }
  /* Newton iteration limit, at an interior point that needs more than one
   * iteration from a cold start */
  variant one = *lme;
  one.par.max_newton = 1;
  mpgm_shape_info info;
  err = eval_cloud(lme, n, xn, x, NULL, N, dN, &info);
  mpgm_test(err == 0 && info.iterations > 1, "lme: cold start at (%g, %g) takes %d > 1 iterations",
            x[0], x[1], info.iterations);
  expect_fail(&one, n, xn, x, MPGM_ERR_SHAPE, MPGM_SHAPE_NOT_CONVERGED, "max_newton = 1");
  /* a non-finite point */
  const double xnan[2] = {NAN, 0.0};
  for (int k = 0; k < 3; k++)
    expect_fail(mf[k], 5, five, xnan, MPGM_ERR_SHAPE, MPGM_SHAPE_BAD_INPUT, "NaN point");
  /* fatal: more nodes than MPGM_SHAPE_MAXNODE, no parameters, no length */
  static double big[2 * (MPGM_SHAPE_MAXNODE + 1)];
  for (int a = 0; a <= MPGM_SHAPE_MAXNODE; a++) big[2 * a] = a * 1e-3, big[2 * a + 1] = (a % 7) * 1e-3;
  for (int k = 0; k < 3; k++) {
    const double xb[2] = {0.05, 0.003};
    expect_fail(mf[k], MPGM_SHAPE_MAXNODE + 1, big, xb, MPGM_ERR_INPUT, MPGM_SHAPE_BAD_INPUT,
                "MPGM_SHAPE_MAXNODE + 1 nodes");
    mpgm_shape_query q = {.n = 5, .xn = five, .xp = {x5[0], x5[1]}, .cell = -1};
    mpgm_test(mf[k]->t->eval(&q, N, dN) == MPGM_ERR_INPUT, "%s: no parameters: MPGM_ERR_INPUT",
              mf[k]->label);
    mpgm_shape_params zero = {0};
    q.par = &zero;
    mpgm_test(mf[k]->t->eval(&q, N, dN) == MPGM_ERR_INPUT && all_zero(5, N, dN),
              "%s: no length scale: MPGM_ERR_INPUT", mf[k]->label);
    double rad0 = 1.0;
    mpgm_test(mpgm_shape_support_radius(mf[k]->t, &zero, &rad0) == MPGM_ERR_INPUT && rad0 == 0.0,
              "%s: support radius without h: MPGM_ERR_INPUT", mf[k]->label);
  }
}

/* ---- LME warm start ----------------------------------------------------------- */

/* A point moves by up to 5 % of h (a time step) and is evaluated again,
 * cold (lambda = 0) and warm (the lambda stored at its previous position).
 * Interior points need 2-4 iterations cold, so a warm start saves about
 * one; points on the boundary (lambda large along the outward normal) need
 * ~20 cold and a few warm; large gamma (lambda ~ gamma) likewise. */
static void check_warm_start(const variant *lme, const nodeset *s, rng *r) {
  const char *gname[3] = {"interior", "edge", "interior, gamma 30"};
  for (int g = 0; g < 3; g++) {
    variant v = *lme;
    if (g == 2) v.par.gamma = 30.0, v.par.tol_support = 1e-100;
    double rad;
    mpgm_shape_support_radius(v.t, &v.par, &rad);
    rad = fmin(rad, 2.5 * H);
    long cold = 0, warm = 0;
    int ok = 1;
    double diff = 0.0;
    for (int k = 0; k < 20; k++) {
      double x[2];
      grid_point(0.0, uniform(r, 3.0, NX - 4.0), g == 1 ? 0.0 : uniform(r, 3.0, NY - 4.0), x);
      int id[MPGM_SHAPE_MAXNODE];
      double xn[2 * MPGM_SHAPE_MAXNODE], N0[MPGM_SHAPE_MAXNODE], N1[MPGM_SHAPE_MAXNODE],
          dN[2 * MPGM_SHAPE_MAXNODE], lam[2] = {0.0, 0.0};
      const int n = cloud(s, x, rad + 0.2 * H, id, xn);
      mpgm_shape_info ic, iw;
      ok &= eval_cloud(&v, n, xn, x, lam, N0, dN, NULL) == 0; /* the previous step */
      x[0] += uniform(r, -0.05, 0.05) * H; /* the point moves a little */
      if (g != 1) x[1] += uniform(r, -0.05, 0.05) * H;
      ok &= eval_cloud(&v, n, xn, x, NULL, N0, dN, &ic) == 0;
      ok &= eval_cloud(&v, n, xn, x, lam, N1, dN, &iw) == 0;
      cold += ic.iterations;
      warm += iw.iterations;
      if (getenv("MPGM_TEST_VERBOSE"))
        printf("  warm start %s %d: %d iterations, cold %d\n", gname[g], k, iw.iterations,
               ic.iterations);
      for (int a = 0; a < n; a++) diff = fmax(diff, fabs(N1[a] - N0[a]));
    }
    printf("LME warm start (%s, 20 points moved by <= 0.05 h): %.2f Newton iterations per point "
           "warm, %.2f cold\n", gname[g], warm / 20.0, cold / 20.0);
    mpgm_test(ok, "lme warm start %s: every evaluation converges", gname[g]);
    mpgm_test(g == 1 ? 2 * warm <= cold : warm < cold,
              "lme warm start %s: %ld Newton iterations against %ld cold", gname[g], warm, cold);
    /* both stop at |r| / h < 1e-10; N differs by at most ~ |J^-1 r| */
    mpgm_test_abs(diff, 0.0, 1e-8, "lme warm start %s: same N as cold start", gname[g]);
  }
}

/* ---- defaults and the support ------------------------------------------------- */

static void check_defaults(const variant *mls1, const variant *lme) {
  double r = 0.0;
  mpgm_shape_params p = {.h = H};
  int err = mpgm_shape_support_radius(lme->t, &p, &r);
  mpgm_test_rel(r, H * sqrt(-log(1e-6) / 1.8), TEST_TOL2,
                "lme default support radius h sqrt(-ln 1e-6 / 1.8) (err %d)", err);
  err = mpgm_shape_support_radius(mls1->t, &p, &r);
  mpgm_test_rel(r, 2.0 * H, TEST_TOL0, "mls default support radius 2 h (err %d)", err);
  p.radius = 0.987;
  err = mpgm_shape_support_radius(mls1->t, &p, &r);
  mpgm_test_rel(r, 0.987, TEST_TOL0, "mls explicit radius (err %d)", err);
  err = mpgm_shape_support_radius(lme->t, &p, &r);
  mpgm_test_rel(r, 0.987, TEST_TOL0, "lme explicit radius (err %d)", err);
  /* LME with radius R is LME with tol_support = exp(-gamma R^2 / h^2):
   * the same nodes in the support, the same functions */
  {
    double xn[2 * 13], N1[13], dN1[26], N2[13], dN2[26];
    for (int a = 0; a < 13; a++) {
      xn[2 * a] = H * (0.9 * cos(0.7 * a) * (1 + a % 3) * 0.8);
      xn[2 * a + 1] = H * (0.9 * sin(0.7 * a) * (1 + a % 3) * 0.8);
    }
    const double R = 1.7 * H;
    mpgm_shape_params pr = {.h = H, .radius = R};
    mpgm_shape_params pt = {.h = H, .tol_support = exp(-1.8 * (R / H) * (R / H) * (1 + 1e-12))};
    mpgm_shape_query q1 = {.n = 13, .xn = xn, .xp = {0.1 * H, -0.05 * H}, .cell = -1, .par = &pr};
    mpgm_shape_query q2 = q1;
    q2.par = &pt;
    const int e1 = lme->t->eval(&q1, N1, dN1), e2 = lme->t->eval(&q2, N2, dN2);
    double diff = 0.0;
    int zeros = 0;
    for (int a = 0; a < 13; a++) {
      diff = fmax(diff, fabs(N1[a] - N2[a]));
      diff = fmax(diff, H * fmax(fabs(dN1[2 * a] - dN2[2 * a]), fabs(dN1[2 * a + 1] - dN2[2 * a + 1])));
      zeros += N1[a] == 0.0;
    }
    mpgm_test(e1 == 0 && e2 == 0 && zeros > 0 && diff < 1e-12,
              "lme radius R = lme tol_support exp(-gamma R^2/h^2): %d nodes cut, max diff %g "
              "(err %d %d)", zeros, diff, e1, e2);
  }
  /* a node just outside the support gets exactly zero, one inside does not */
  for (int k = 0; k < 2; k++) {
    const mpgm_shapefn_type *t = k ? lme->t : mls1->t;
    mpgm_shape_params q = {.h = H};
    mpgm_shape_support_radius(t, &q, &r);
    double xn[2 * 9], N[9], dN[18];
    const double c[8][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}};
    for (int a = 0; a < 8; a++) xn[2 * a] = c[a][0] * H, xn[2 * a + 1] = c[a][1] * H;
    xn[16] = 1.001 * r, xn[17] = 0.0;
    const double x[2] = {0.0, 0.0};
    mpgm_shape_query qq = {.n = 9, .xn = xn, .xp = {x[0], x[1]}, .cell = -1, .par = &q};
    err = t->eval(&qq, N, dN);
    mpgm_test(err == 0 && N[8] == 0.0 && dN[16] == 0.0 && dN[17] == 0.0 && N[0] > 0.0,
              "%s: node beyond the support radius has N = 0 (err %d)", t->name, err);
  }
}

int main(void) {
  const mpgm_shapefn_type *const *all = mpgm_shapefn_types();
  const mpgm_shapefn_type *mls = mpgm_shapefn_type_find("mls"), *lme = mpgm_shapefn_type_find("lme");
  const mpgm_shapefn_type *ugimp = mpgm_shapefn_type_find("ugimp");
  mpgm_test(mls && lme && !mls->needs_cell && !lme->needs_cell && mls->support_radius &&
                lme->support_radius,
            "mls and lme registered as meshfree kinds");
  if (!mls || !lme) return mpgm_test_summary();
  variant vmls1 = {.t = mls, .par = {.h = H, .order = 1}, .label = "mls linear"};
  variant vmls2 = {.t = mls, .par = {.h = H, .order = 2}, .label = "mls quadratic"};
  variant vlme = {.t = lme, .par = {.h = H}, .label = "lme"};
  variant vlme_g = {.t = lme, .par = {.h = H, .gamma = 4.0}, .label = "lme gamma 4"};
  /* uGIMP: regular grids only (its weights are those of a grid of spacing h) */
  variant vug = {.t = ugimp, .par = {.h = H, .half_width = 0.25 * H}, .label = "ugimp"};
  const variant *mf[5] = {&vmls1, &vmls2, &vlme, &vlme_g, &vug};
  static nodeset sets[3];
  rng r = {0x9E3779B97F4A7C15ULL};
  const double th[3] = {0.0, 0.0, 0.7311};
  grid(&sets[0], &r, 0.0, th[0]);   /* regular */
  grid(&sets[1], &r, 0.25, th[1]);  /* perturbed */
  grid(&sets[2], &r, 0.3, th[2]);   /* perturbed and rotated */
  const char *sname[3] = {"regular", "perturbed", "perturbed-rotated"};

  int nmesh = 0, ncell = 0;
  for (int it = 0; all[it]; it++) {
    const mpgm_shapefn_type *t = all[it];
    if (t->needs_cell) {
      check_cell_kind(t, &r);
      ncell++;
      continue;
    }
    nmesh++;
    for (int k = 0; k < 5; k++) {
      if (mf[k]->t != t) continue;
      for (int is = 0; is < (t->grid_only ? 1 : 3); is++)
        for (int p = 0; p < N_POINTS; p++) {
          double x[2];
          grid_point(th[is], uniform(&r, 2.0, NX - 3.0), uniform(&r, 2.0, NY - 3.0), x);
          char where[48];
          snprintf(where, sizeof where, "%s point %d", sname[is], p);
          check_meshfree_point(mf[k], &sets[is], x, where);
        }
    }
  }
  mpgm_test(ncell >= 1 && nmesh >= 2, "kinds covered: %d cell-based, %d meshfree", ncell, nmesh);
  for (int is = 0; is < 3; is++) check_kronecker(&vlme, &sets[is], th[is], &r, sname[is]);
  check_fe_limit(lme, &r);
  check_failures(&vmls1, &vmls2, &vlme, &sets[1]);
  check_warm_start(&vlme, &sets[1], &r);
  check_defaults(&vmls1, &vlme);
  return mpgm_test_summary();
}
