/* test_shapefn.c -- conformance suite run over every shape-function kind in
 * mpgm_shapefn_types() that needs cells (today "fe"), for both cell kinds
 * (T3, Q4), on a regular cell and on randomly distorted (valid, convex)
 * cells, at random interior points and at every point of every Gauss rule:
 *
 *   - partition of unity  sum N_I = 1;
 *   - linear reproduction sum N_I x_I = x  and  sum x_I (x) grad N_I = I;
 *   - grad N against central differences of N with respect to the physical
 *     point (local coordinates of the perturbed point from mpgm_fe_local);
 *   - mpgm_fe_local inverts the reference mapping of mpgm_fe_ref;
 *   - Gauss rules: points inside the reference cell, sum w detJ = cell area,
 *     monomials up to the rule's degree integrated exactly on the reference
 *     cell (and the first monomial above it not: the degree is tight);
 *   - an inverted (clockwise) cell returns MPGM_ERR_JACOBIAN.
 *
 * A 3-D build (MPGM_DIM = 3) runs the same checks on the trilinear
 * hexahedron H8: a regular box, the box turned by a random rotation, and
 * randomly distorted hexes (nodes moved, then rotated and translated); the
 * sum of w detJ is checked against the volume from the divergence theorem
 * over the six bilinear faces (an independent construction), the sub-cell
 * centres are checked too, and the 2-D cell kinds must be refused.
 */
#include "mpgm_shapefn.h"
#include "mpgm_test.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* Round-off of sums of a few O(1) products, with a margin for the
 * ill-conditioning of distorted cells (~4500 eps). */
#define TOL_EXACT 1e-12
/* Central differences: truncation O(h^2 |N'''|) + rounding O(eps / h). */
#define TOL_FD 1e-6
#define FD_STEP 1e-5  /* relative to the cell size */

#define N_DISTORTED 16 /* random cells per cell kind */
#define N_RANDOM 8     /* random interior points per cell */

static const double PI = 3.14159265358979323846;

#if MPGM_DIM == 2
static const double LX = 2.385, LY = 1.7; /* regular cell size [m] */

static const char *cell_name(int cell) { return cell == MPGM_CELL_T3 ? "T3" : "Q4"; }

/* ---- cells ---------------------------------------------------------------- */

/* Polygon area (shoelace; positive for counter-clockwise nodes). */
static double area(int nn, const double *xn) {
  double a = 0.0;
  for (int i = 0; i < nn; i++) {
    const int j = (i + 1) % nn;
    a += xn[2 * i] * xn[2 * j + 1] - xn[2 * j] * xn[2 * i + 1];
  }
  return 0.5 * a;
}

/* Strictly convex, counter-clockwise: every corner turns left by a margin. */
static int convex(int nn, const double *xn) {
  const double a = area(nn, xn);
  for (int i = 0; i < nn; i++) {
    const int j = (i + 1) % nn, k = (i + 2) % nn;
    const double ex = xn[2 * j] - xn[2 * i], ey = xn[2 * j + 1] - xn[2 * i + 1];
    const double fx = xn[2 * k] - xn[2 * j], fy = xn[2 * k + 1] - xn[2 * j + 1];
    if (!(ex * fy - ey * fx > 0.05 * a)) return 0;
  }
  return 1;
}

/* The undistorted cell: rectangle LX x LY (Q4) or its lower-left half (T3),
 * away from the origin so that coordinates are not trivially small. */
static void regular_cell(int cell, double *xn) {
  const double x0 = 0.3173, y0 = -0.4621;
  const double q[4][2] = {{x0, y0}, {x0 + LX, y0}, {x0 + LX, y0 + LY}, {x0, y0 + LY}};
  const double t[3][2] = {{x0, y0}, {x0 + LX, y0}, {x0, y0 + LY}};
  for (int a = 0; a < mpgm_fe_nnode(cell); a++) {
    xn[2 * a] = cell == MPGM_CELL_T3 ? t[a][0] : q[a][0];
    xn[2 * a + 1] = cell == MPGM_CELL_T3 ? t[a][1] : q[a][1];
  }
}

/* A random valid cell: the regular one with every node moved by up to
 * 0.3 of the cell size, then rotated and translated; redrawn until convex. */
static void distorted_cell(int cell, rng *r, double *xn) {
  const int nn = mpgm_fe_nnode(cell);
  double y[2 * MPGM_FE_MAXNODE];
  do {
    regular_cell(cell, y);
    for (int a = 0; a < nn; a++) {
      y[2 * a] += uniform(r, -0.3, 0.3) * LX;
      y[2 * a + 1] += uniform(r, -0.3, 0.3) * LY;
    }
  } while (!convex(nn, y));
  const double th = uniform(r, -PI, PI), c = cos(th), s = sin(th);
  const double tx = uniform(r, -3.1, 3.1), ty = uniform(r, -3.1, 3.1);
  for (int a = 0; a < nn; a++) {
    xn[2 * a] = c * y[2 * a] - s * y[2 * a + 1] + tx;
    xn[2 * a + 1] = s * y[2 * a] + c * y[2 * a + 1] + ty;
  }
}

/* Cell size: longest edge. */
static double cell_size(int nn, const double *xn) {
  double h = 0.0;
  for (int i = 0; i < nn; i++) {
    const int j = (i + 1) % nn;
    h = fmax(h, hypot(xn[2 * j] - xn[2 * i], xn[2 * j + 1] - xn[2 * i + 1]));
  }
  return h;
}

/* Physical point of local coordinates xi (reference mapping). */
static void map_point(int cell, const double *xn, const double xi[2], double x[2]) {
  double N[MPGM_FE_MAXNODE];
  mpgm_fe_ref(cell, xi, N, NULL);
  x[0] = x[1] = 0.0;
  for (int a = 0; a < mpgm_fe_nnode(cell); a++) {
    x[0] += N[a] * xn[2 * a];
    x[1] += N[a] * xn[2 * a + 1];
  }
}

static void random_xi(int cell, rng *r, double xi[2]) {
  if (cell == MPGM_CELL_Q4) {
    xi[0] = uniform(r, -0.98, 0.98);
    xi[1] = uniform(r, -0.98, 0.98);
    return;
  }
  double a = uniform(r, 0.01, 0.99), b = uniform(r, 0.01, 0.99);
  if (a + b > 0.99) { a = 1.0 - a; b = 1.0 - b; } /* reflect into the triangle */
  xi[0] = a;
  xi[1] = b;
}

/* Evaluate a kind at physical point x of the cell (local coordinates from
 * mpgm_fe_local). */
static int eval_at(const mpgm_shapefn_type *t, int cell, const double *xn, const double x[2],
                   double *N, double *dN) {
  mpgm_shape_query q = {.n = mpgm_fe_nnode(cell), .xn = xn, .xp = {x[0], x[1]}, .cell = cell};
  int err = mpgm_fe_local(cell, xn, x, q.xi);
  if (err) return err;
  return t->eval(&q, N, dN);
}

/* ---- checks at one point ------------------------------------------------- */
static void check_point(const mpgm_shapefn_type *t, int cell, const double *xn,
                        const double xi[2], const char *where) {
  const int nn = mpgm_fe_nnode(cell);
  const double h = cell_size(nn, xn);
  const char *cn = cell_name(cell);
  double x[2];
  map_point(cell, xn, xi, x);

  /* mpgm_fe_local inverts the reference mapping */
  double xl[2] = {NAN, NAN};
  int err = mpgm_fe_local(cell, xn, x, xl);
  mpgm_test(err == 0, "%s %s %s: mpgm_fe_local returns %d", t->name, cn, where, err);
  mpgm_test_abs(fabs(xl[0] - xi[0]) + fabs(xl[1] - xi[1]), 0.0, TOL_EXACT,
                "%s %s %s: mpgm_fe_local(x(xi)) = xi", t->name, cn, where);

  mpgm_shape_query q = {.n = nn, .xn = xn, .xp = {x[0], x[1]}, .cell = cell,
                        .xi = {xi[0], xi[1]}};
  double N[MPGM_FE_MAXNODE], dN[2 * MPGM_FE_MAXNODE];
  err = t->eval(&q, N, dN);
  mpgm_test(err == 0, "%s %s %s: eval returns %d", t->name, cn, where, err);
  if (err) return;

  double sum = 0.0, rx = 0.0, ry = 0.0, Id[4] = {0, 0, 0, 0};
  for (int a = 0; a < nn; a++) {
    sum += N[a];
    rx += N[a] * xn[2 * a];
    ry += N[a] * xn[2 * a + 1];
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 2; j++) Id[2 * i + j] += xn[2 * a + i] * dN[2 * a + j];
  }
  mpgm_test_abs(sum, 1.0, TOL_EXACT, "%s %s %s: partition of unity", t->name, cn, where);
  const double xs = fmax(fabs(x[0]), fabs(x[1])) + h;
  mpgm_test_abs(fabs(rx - x[0]) + fabs(ry - x[1]), 0.0, TOL_EXACT * xs,
                "%s %s %s: sum N x_I = x", t->name, cn, where);
  mpgm_test_abs(fabs(Id[0] - 1.0) + fabs(Id[1]) + fabs(Id[2]) + fabs(Id[3] - 1.0), 0.0,
                TOL_EXACT * xs / h, "%s %s %s: sum x_I (x) grad N_I = I", t->name, cn, where);

  /* grad N against central differences of N(x) */
  const double e = FD_STEP * h;
  double gmax = 0.0, emax = 0.0;
  int ok = 1;
  for (int a = 0; a < 2 * nn; a++) gmax = fmax(gmax, fabs(dN[a]));
  for (int d = 0; d < 2; d++) {
    double xp[2] = {x[0], x[1]}, xm[2] = {x[0], x[1]};
    double Np[MPGM_FE_MAXNODE], Nm[MPGM_FE_MAXNODE], dd[2 * MPGM_FE_MAXNODE];
    xp[d] += e;
    xm[d] -= e;
    ok &= eval_at(t, cell, xn, xp, Np, dd) == 0 && eval_at(t, cell, xn, xm, Nm, dd) == 0;
    for (int a = 0; a < nn; a++)
      emax = fmax(emax, fabs((Np[a] - Nm[a]) / (2.0 * e) - dN[2 * a + d]));
  }
  mpgm_test(ok, "%s %s %s: evaluation at perturbed points", t->name, cn, where);
  mpgm_test_abs(emax / gmax, 0.0, TOL_FD, "%s %s %s: grad N = central differences (rel)",
                t->name, cn, where);
}

/* Every Gauss point and N_RANDOM random points of one cell; the area rule. */
static void check_cell(const mpgm_shapefn_type *t, int cell, const double *xn, rng *r,
                       const char *cname) {
  const int nn = mpgm_fe_nnode(cell);
  const char *cn = cell_name(cell);
  const int rules[2][3] = {{1, 3, 0}, {1, 4, 9}};
  char where[96];
  for (int k = 0; k < N_RANDOM; k++) {
    double xi[2];
    random_xi(cell, r, xi);
    snprintf(where, sizeof where, "%s random point %d", cname, k);
    check_point(t, cell, xn, xi, where);
  }
  for (int ir = 0; ir < 3 && rules[cell][ir]; ir++) {
    const int np = rules[cell][ir];
    double gxi[18], gw[9], sum = 0.0;
    int err = mpgm_fe_gauss(cell, np, gxi, gw);
    mpgm_test(err == 0, "%s %s: %d-point rule returns %d", t->name, cn, np, err);
    if (err) continue;
    for (int g = 0; g < np; g++) {
      snprintf(where, sizeof where, "%s Gauss %d/%d", cname, g, np);
      check_point(t, cell, xn, gxi + 2 * g, where);
      double N[MPGM_FE_MAXNODE], dN[2 * MPGM_FE_MAXNODE], detJ = NAN;
      err |= mpgm_fe_eval(cell, xn, gxi + 2 * g, N, dN, &detJ);
      sum += gw[g] * detJ;
    }
    mpgm_test(err == 0, "%s %s %s: %d-point rule: mpgm_fe_eval at every point", t->name, cn,
              cname, np);
    mpgm_test_rel(sum, area(nn, xn), TOL_EXACT, "%s %s %s: %d-point rule: sum w detJ = area",
                  t->name, cn, cname, np);
  }
}

/* ---- Gauss rules on the reference cell ------------------------------------ */

static double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

/* Exact integral of xi^a eta^b over the reference cell. */
static double exact_monomial(int cell, int a, int b) {
  if (cell == MPGM_CELL_T3) return factorial(a) * factorial(b) / factorial(a + b + 2);
  return (a % 2 ? 0.0 : 2.0 / (a + 1)) * (b % 2 ? 0.0 : 2.0 / (b + 1));
}

static double rule_monomial(int np, const double *xi, const double *w, int a, int b) {
  double s = 0.0;
  for (int g = 0; g < np; g++) s += w[g] * pow(xi[2 * g], a) * pow(xi[2 * g + 1], b);
  return s;
}

/* T3 rules (1, 3 points) are exact for total degree 1, 2; Q4 n x n rules
 * for degree 2n - 1 in each variable. */
static void check_rules(void) {
  const int t3[2][2] = {{1, 1}, {3, 2}};        /* {points, total degree} */
  const int q4[3][2] = {{1, 1}, {4, 3}, {9, 5}}; /* {points, degree per variable} */
  double xi[18], w[9];
  for (int k = 0; k < 2; k++) {
    const int np = t3[k][0], deg = t3[k][1];
    int err = mpgm_fe_gauss(MPGM_CELL_T3, np, xi, w);
    mpgm_test(err == 0, "T3 %d-point rule returns %d", np, err);
    if (err) continue;
    int inside = 1;
    for (int g = 0; g < np; g++) inside &= mpgm_fe_inside(MPGM_CELL_T3, xi + 2 * g, 0.0) && w[g] > 0;
    mpgm_test(inside, "T3 %d-point rule: points inside, weights positive", np);
    for (int a = 0; a <= deg; a++)
      for (int b = 0; a + b <= deg; b++)
        mpgm_test_abs(rule_monomial(np, xi, w, a, b), exact_monomial(MPGM_CELL_T3, a, b),
                      TOL_EXACT, "T3 %d-point rule integrates xi^%d eta^%d", np, a, b);
    const int a = deg + 1; /* degree is tight: xi^(deg+1) is not exact */
    mpgm_test(fabs(rule_monomial(np, xi, w, a, 0) - exact_monomial(MPGM_CELL_T3, a, 0)) > 1e-6,
              "T3 %d-point rule is not exact for xi^%d", np, a);
  }
  for (int k = 0; k < 3; k++) {
    const int np = q4[k][0], deg = q4[k][1];
    int err = mpgm_fe_gauss(MPGM_CELL_Q4, np, xi, w);
    mpgm_test(err == 0, "Q4 %d-point rule returns %d", np, err);
    if (err) continue;
    int inside = 1;
    for (int g = 0; g < np; g++) inside &= mpgm_fe_inside(MPGM_CELL_Q4, xi + 2 * g, 0.0) && w[g] > 0;
    mpgm_test(inside, "Q4 %d-point rule: points inside, weights positive", np);
    for (int a = 0; a <= deg; a++)
      for (int b = 0; b <= deg; b++)
        mpgm_test_abs(rule_monomial(np, xi, w, a, b), exact_monomial(MPGM_CELL_Q4, a, b),
                      TOL_EXACT, "Q4 %d-point rule integrates xi^%d eta^%d", np, a, b);
    const int a = deg + 1;
    mpgm_test(fabs(rule_monomial(np, xi, w, a, 0) - exact_monomial(MPGM_CELL_Q4, a, 0)) > 1e-6,
              "Q4 %d-point rule is not exact for xi^%d", np, a);
  }
  /* unsupported counts are refused */
  mpgm_test(mpgm_fe_gauss(MPGM_CELL_T3, 4, xi, w) == MPGM_ERR_INPUT &&
                mpgm_fe_gauss(MPGM_CELL_Q4, 3, xi, w) == MPGM_ERR_INPUT,
            "unsupported Gauss point counts return MPGM_ERR_INPUT");
}

/* ---- inverted cells ----------------------------------------------------------- */
static void check_inverted(const mpgm_shapefn_type *t, int cell, const double *xn,
                           const char *cname) {
  const int nn = mpgm_fe_nnode(cell);
  const char *cn = cell_name(cell);
  double rev[2 * MPGM_FE_MAXNODE]; /* same nodes, clockwise */
  for (int a = 0; a < nn; a++) {
    rev[2 * a] = xn[2 * (nn - 1 - a)];
    rev[2 * a + 1] = xn[2 * (nn - 1 - a) + 1];
  }
  double xi[2], N[MPGM_FE_MAXNODE], dN[2 * MPGM_FE_MAXNODE], detJ = 0.0;
  xi[0] = cell == MPGM_CELL_T3 ? 0.2817 : 0.1934;
  xi[1] = cell == MPGM_CELL_T3 ? 0.3529 : -0.4172;
  int err = mpgm_fe_eval(cell, rev, xi, N, dN, &detJ);
  mpgm_test(err == MPGM_ERR_JACOBIAN && detJ < 0.0,
            "%s %s %s inverted: mpgm_fe_eval returns MPGM_ERR_JACOBIAN (got %d, detJ %g)",
            t->name, cn, cname, err, detJ);
  mpgm_shape_query q = {.n = nn, .xn = rev, .cell = cell, .xi = {xi[0], xi[1]}};
  map_point(cell, rev, xi, q.xp);
  err = t->eval(&q, N, dN);
  mpgm_test(err == MPGM_ERR_JACOBIAN, "%s %s %s inverted: eval returns MPGM_ERR_JACOBIAN (got %d)",
            t->name, cn, cname, err);
  /* a wrong node count is refused rather than read out of bounds */
  q.xn = xn;
  q.n = nn - 1;
  err = t->eval(&q, N, dN);
  mpgm_test(err != 0, "%s %s %s: eval with %d nodes fails (got %d)", t->name, cn, cname, nn - 1,
            err);
}

/* mpgm_fe_local on small cells far from the origin and at points outside
 * the cell (extrapolation, as for a surface point next to its cell): the
 * Newton correction stalls at round-off, about 1e-15 times the coordinates
 * over the cell size, so a fixed 1e-14 on it could never be met (this T3
 * of h = 0.02 at x ~ 1 failed before). */
static void check_local_far(void) {
  const double tri[6] = {0.96, 0.14, 0.98, 0.16, 0.96, 0.16};
  const double x[2] = {0.96482549240872539, 0.15809012870533989};
  double xi[2], back[2];
  int err = mpgm_fe_local(MPGM_CELL_T3, tri, x, xi);
  map_point(MPGM_CELL_T3, tri, xi, back);
  mpgm_test(err == 0 && fabs(back[0] - x[0]) < 1e-14 && fabs(back[1] - x[1]) < 1e-14,
            "T3 of h = 0.02 at x ~ 1: mpgm_fe_local returns %d, x(xi) - x = (%.1e, %.1e)", err,
            back[0] - x[0], back[1] - x[1]);
  for (int cell = MPGM_CELL_T3; cell <= MPGM_CELL_Q4; cell++) {
    const int nn = mpgm_fe_nnode(cell);
    double xn[2 * MPGM_FE_MAXNODE];
    const double base[8] = {0, 0, 1, 0, 1, 1, 0, 1}, t3[6] = {0, 0, 1, 0, 1, 1};
    for (int a = 0; a < nn; a++) { /* a cell of h = 0.01 at (1234.5, 678.9) */
      xn[2 * a] = 1234.5 + 0.01 * (cell == MPGM_CELL_T3 ? t3 : base)[2 * a];
      xn[2 * a + 1] = 678.9 + 0.01 * (cell == MPGM_CELL_T3 ? t3 : base)[2 * a + 1];
    }
    const double y[2] = {1234.5 + 0.013, 678.9 - 0.002}; /* outside */
    err = mpgm_fe_local(cell, xn, y, xi);
    map_point(cell, xn, xi, back);
    mpgm_test(err == 0 && fabs(back[0] - y[0]) < 1e-11 && fabs(back[1] - y[1]) < 1e-11,
              "%s of h = 0.01 at x ~ 1e3, point outside: mpgm_fe_local returns %d, x(xi) - x = "
              "(%.1e, %.1e)", cell_name(cell), err, back[0] - y[0], back[1] - y[1]);
  }
}

static void check_cells(void) {
  const mpgm_shapefn_type *const *all = mpgm_shapefn_types();
  int ncell_kinds = 0;
  check_rules();
  for (int it = 0; all[it]; it++) {
    const mpgm_shapefn_type *t = all[it];
    mpgm_test(t->name && mpgm_shapefn_type_find(t->name) == t && t->eval,
              "%s: found by name, eval set", t->name);
    if (!t->needs_cell) continue;
    ncell_kinds++;
    for (int cell = MPGM_CELL_T3; cell <= MPGM_CELL_Q4; cell++) {
      rng r = {0x9E3779B97F4A7C15ULL ^ (uint64_t)(1 + it * 2 + cell)};
      double xn[2 * MPGM_FE_MAXNODE];
      regular_cell(cell, xn);
      check_cell(t, cell, xn, &r, "regular");
      check_inverted(t, cell, xn, "regular");
      for (int k = 0; k < N_DISTORTED; k++) {
        char cname[32];
        snprintf(cname, sizeof cname, "distorted %d", k);
        distorted_cell(cell, &r, xn);
        check_cell(t, cell, xn, &r, cname);
        check_inverted(t, cell, xn, cname);
      }
    }
  }
  mpgm_test(ncell_kinds > 0, "at least one cell-based kind (%d)", ncell_kinds);
}

#else /* MPGM_DIM == 3 */
static const double LX = 2.385, LY = 1.7, LZ = 1.33; /* regular cell size [m] */

/* The H8's node signs (s, t, u) = xi of node a. */
static double node_xi(int a, int k) { return mpgm_corner_sign(a, k); }

/* The undistorted cell: a box LX x LY x LZ away from the origin. */
static void regular_hex(double *xn) {
  const double x0[3] = {0.3173, -0.4621, 0.2489}, L[3] = {LX, LY, LZ};
  for (int a = 0; a < 8; a++)
    for (int d = 0; d < 3; d++) xn[3 * a + d] = x0[d] + 0.5 * (1.0 + node_xi(a, d)) * L[d];
}

/* A random rotation (from a random unit quaternion) and translation. */
static void rotate_translate(rng *r, double *xn) {
  double q[4], n = 0.0;
  do {
    n = 0.0;
    for (int k = 0; k < 4; k++) {
      q[k] = uniform(r, -1.0, 1.0);
      n += q[k] * q[k];
    }
  } while (n < 0.05 || n > 1.0);
  for (int k = 0; k < 4; k++) q[k] /= sqrt(n);
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double R[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                          {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                          {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
  const double t[3] = {uniform(r, -3.1, 3.1), uniform(r, -3.1, 3.1), uniform(r, -3.1, 3.1)};
  for (int a = 0; a < 8; a++) {
    const double p[3] = {xn[3 * a], xn[3 * a + 1], xn[3 * a + 2]};
    for (int i = 0; i < 3; i++) xn[3 * a + i] = R[i][0] * p[0] + R[i][1] * p[1] + R[i][2] * p[2] + t[i];
  }
}

/* Smallest det J over the 8 nodes and the 27 Gauss points, relative to
 * the regular box's LX LY LZ / 8. */
static double min_det(const double *xn) {
  double xi[81], w[27], N[8], dN[24], det, m = HUGE_VAL;
  mpgm_fe_gauss(MPGM_CELL_H8, 27, xi, w);
  for (int k = 0; k < 35; k++) {
    double c[3];
    for (int d = 0; d < 3; d++) c[d] = k < 8 ? node_xi(k, d) : xi[3 * (k - 8) + d];
    mpgm_fe_eval(MPGM_CELL_H8, xn, c, N, dN, &det);
    m = fmin(m, det);
  }
  return m / (LX * LY * LZ / 8.0);
}

/* A random valid hex: every node of the box moved by up to 0.25 of the
 * cell size, redrawn until det J > 0.1 (relative) at the nodes and the
 * Gauss points, then rotated and translated. */
static void distorted_hex(rng *r, double *xn) {
  const double L[3] = {LX, LY, LZ};
  do {
    regular_hex(xn);
    for (int a = 0; a < 8; a++)
      for (int d = 0; d < 3; d++) xn[3 * a + d] += uniform(r, -0.25, 0.25) * L[d];
  } while (!(min_det(xn) > 0.1));
  rotate_translate(r, xn);
}

/* The 12 edges' longest. */
static double hex_size(const double *xn) {
  double h = 0.0;
  for (int a = 0; a < 8; a++)
    for (int b = a + 1; b < 8; b++) {
      int diff = 0; /* an edge: the nodes' signs differ in one direction */
      for (int k = 0; k < 3; k++) diff += node_xi(a, k) != node_xi(b, k);
      if (diff != 1) continue;
      double e = 0.0;
      for (int d = 0; d < 3; d++) e += (xn[3 * a + d] - xn[3 * b + d]) * (xn[3 * a + d] - xn[3 * b + d]);
      h = fmax(h, sqrt(e));
    }
  return h;
}

static void map_hex(const double *xn, const double xi[3], double x[3]) {
  double N[8];
  mpgm_fe_ref(MPGM_CELL_H8, xi, N, NULL);
  x[0] = x[1] = x[2] = 0.0;
  for (int a = 0; a < 8; a++)
    for (int d = 0; d < 3; d++) x[d] += N[a] * xn[3 * a + d];
}

/* Volume by the divergence theorem, V = (1/3) sum over the faces of the
 * integral of x . n dA, each face the bilinear patch of its 4 nodes
 * (counter-clockwise seen from outside); the integrand has degree 2 in
 * each face coordinate, so 2 x 2 Gauss is exact. */
static double hex_volume(const double *xn) {
  static const int face[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                 {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  static const double qs[4] = {-1, 1, 1, -1}, qt[4] = {-1, -1, 1, 1};
  const double g = 1.0 / sqrt(3.0);
  double V = 0.0;
  for (int f = 0; f < 6; f++)
    for (int i = 0; i < 4; i++) {
      const double u = qs[i] * g, v = qt[i] * g;
      double x[3] = {0, 0, 0}, xu[3] = {0, 0, 0}, xv[3] = {0, 0, 0};
      for (int a = 0; a < 4; a++) {
        const double *p = xn + 3 * face[f][a];
        for (int d = 0; d < 3; d++) {
          x[d] += 0.25 * (1 + qs[a] * u) * (1 + qt[a] * v) * p[d];
          xu[d] += 0.25 * qs[a] * (1 + qt[a] * v) * p[d];
          xv[d] += 0.25 * qt[a] * (1 + qs[a] * u) * p[d];
        }
      }
      const double n[3] = {xu[1] * xv[2] - xu[2] * xv[1], xu[2] * xv[0] - xu[0] * xv[2],
                           xu[0] * xv[1] - xu[1] * xv[0]};
      V += (x[0] * n[0] + x[1] * n[1] + x[2] * n[2]) / 3.0;
    }
  return V;
}

static int eval_hex(const mpgm_shapefn_type *t, const double *xn, const double x[3], double *N,
                    double *dN) {
  mpgm_shape_query q = {.n = 8, .xn = xn, .xp = {x[0], x[1], x[2]}, .cell = MPGM_CELL_H8};
  int err = mpgm_fe_local(MPGM_CELL_H8, xn, x, q.xi);
  if (err) return err;
  return t->eval(&q, N, dN);
}

/* ---- checks at one point ------------------------------------------------- */
static void check_point_h8(const mpgm_shapefn_type *t, const double *xn, const double xi[3],
                           const char *where) {
  const double h = hex_size(xn);
  double x[3];
  map_hex(xn, xi, x);
  double xl[3] = {NAN, NAN, NAN};
  int err = mpgm_fe_local(MPGM_CELL_H8, xn, x, xl);
  mpgm_test(err == 0, "%s H8 %s: mpgm_fe_local returns %d", t->name, where, err);
  mpgm_test_abs(fabs(xl[0] - xi[0]) + fabs(xl[1] - xi[1]) + fabs(xl[2] - xi[2]), 0.0, TOL_EXACT,
                "%s H8 %s: mpgm_fe_local(x(xi)) = xi", t->name, where);

  mpgm_shape_query q = {.n = 8, .xn = xn, .xp = {x[0], x[1], x[2]}, .cell = MPGM_CELL_H8,
                        .xi = {xi[0], xi[1], xi[2]}};
  double N[8], dN[24];
  err = t->eval(&q, N, dN);
  mpgm_test(err == 0, "%s H8 %s: eval returns %d", t->name, where, err);
  if (err) return;
  double sum = 0.0, rx[3] = {0, 0, 0}, Id[9] = {0};
  for (int a = 0; a < 8; a++) {
    sum += N[a];
    for (int i = 0; i < 3; i++) {
      rx[i] += N[a] * xn[3 * a + i];
      for (int j = 0; j < 3; j++) Id[3 * i + j] += xn[3 * a + i] * dN[3 * a + j];
    }
  }
  mpgm_test_abs(sum, 1.0, TOL_EXACT, "%s H8 %s: partition of unity", t->name, where);
  const double xs = fmax(fmax(fabs(x[0]), fabs(x[1])), fabs(x[2])) + h;
  double ex = 0.0, eI = 0.0;
  for (int i = 0; i < 3; i++) {
    ex += fabs(rx[i] - x[i]);
    for (int j = 0; j < 3; j++) eI += fabs(Id[3 * i + j] - (i == j));
  }
  mpgm_test_abs(ex, 0.0, TOL_EXACT * xs, "%s H8 %s: sum N x_I = x", t->name, where);
  mpgm_test_abs(eI, 0.0, TOL_EXACT * xs / h, "%s H8 %s: sum x_I (x) grad N_I = I", t->name, where);

  const double e = FD_STEP * h;
  double gmax = 0.0, emax = 0.0;
  int ok = 1;
  for (int a = 0; a < 24; a++) gmax = fmax(gmax, fabs(dN[a]));
  for (int d = 0; d < 3; d++) {
    double xp[3] = {x[0], x[1], x[2]}, xm[3] = {x[0], x[1], x[2]}, Np[8], Nm[8], dd[24];
    xp[d] += e;
    xm[d] -= e;
    ok &= eval_hex(t, xn, xp, Np, dd) == 0 && eval_hex(t, xn, xm, Nm, dd) == 0;
    for (int a = 0; a < 8; a++) emax = fmax(emax, fabs((Np[a] - Nm[a]) / (2.0 * e) - dN[3 * a + d]));
  }
  mpgm_test(ok, "%s H8 %s: evaluation at perturbed points", t->name, where);
  mpgm_test_abs(emax / gmax, 0.0, TOL_FD, "%s H8 %s: grad N = central differences (rel)", t->name,
                where);
}

/* Random points, every Gauss point of the 3 rules, sum w detJ = volume. */
static void check_hex(const mpgm_shapefn_type *t, const double *xn, rng *r, const char *cname) {
  char where[96];
  const double vol = hex_volume(xn);
  for (int k = 0; k < N_RANDOM; k++) {
    const double xi[3] = {uniform(r, -0.98, 0.98), uniform(r, -0.98, 0.98), uniform(r, -0.98, 0.98)};
    snprintf(where, sizeof where, "%s random point %d", cname, k);
    check_point_h8(t, xn, xi, where);
  }
  const int rules[3] = {1, 8, 27};
  for (int ir = 0; ir < 3; ir++) {
    double gxi[81], gw[27], sum = 0.0;
    int err = mpgm_fe_gauss(MPGM_CELL_H8, rules[ir], gxi, gw);
    mpgm_test(err == 0, "%s H8: %d-point rule returns %d", t->name, rules[ir], err);
    if (err) continue;
    for (int g = 0; g < rules[ir]; g++) {
      snprintf(where, sizeof where, "%s Gauss %d/%d", cname, g, rules[ir]);
      check_point_h8(t, xn, gxi + 3 * g, where);
      double N[8], dN[24], detJ = NAN;
      err |= mpgm_fe_eval(MPGM_CELL_H8, xn, gxi + 3 * g, N, dN, &detJ);
      sum += gw[g] * detJ;
    }
    mpgm_test(err == 0, "%s H8 %s: %d-point rule: mpgm_fe_eval at every point", t->name, cname,
              rules[ir]);
    /* det J has degree 2 in each xi_k: the 1-point rule is not exact on
     * a distorted hex, the 8- and 27-point rules are */
    if (rules[ir] > 1 || strcmp(cname, "regular") == 0 || strcmp(cname, "rotated") == 0)
      mpgm_test_rel(sum, vol, TOL_EXACT, "%s H8 %s: %d-point rule: sum w detJ = volume (%.15g)",
                    t->name, cname, rules[ir], vol);
  }
}

static double rule_monomial3(int np, const double *xi, const double *w, int a, int b, int c) {
  double s = 0.0;
  for (int g = 0; g < np; g++)
    s += w[g] * pow(xi[3 * g], a) * pow(xi[3 * g + 1], b) * pow(xi[3 * g + 2], c);
  return s;
}

static double exact_monomial3(int a, int b, int c) {
  return (a % 2 ? 0.0 : 2.0 / (a + 1)) * (b % 2 ? 0.0 : 2.0 / (b + 1)) *
         (c % 2 ? 0.0 : 2.0 / (c + 1));
}

/* n x n x n rules exact for degree 2n - 1 in each variable (and not for
 * 2n); sub-cell centres; the 2-D kinds refused. */
static void check_rules_h8(void) {
  double xi[81], w[27];
  for (int n = 1; n <= 3; n++) {
    const int np = n * n * n, deg = 2 * n - 1;
    int err = mpgm_fe_gauss(MPGM_CELL_H8, np, xi, w);
    mpgm_test(err == 0, "H8 %d-point rule returns %d", np, err);
    if (err) continue;
    int inside = 1;
    for (int g = 0; g < np; g++) inside &= mpgm_fe_inside(MPGM_CELL_H8, xi + 3 * g, 0.0) && w[g] > 0;
    mpgm_test(inside, "H8 %d-point rule: points inside, weights positive", np);
    double worst = 0.0;
    for (int a = 0; a <= deg; a++)
      for (int b = 0; b <= deg; b++)
        for (int c = 0; c <= deg; c++)
          worst = fmax(worst, fabs(rule_monomial3(np, xi, w, a, b, c) - exact_monomial3(a, b, c)));
    mpgm_test_abs(worst, 0.0, TOL_EXACT, "H8 %d-point rule integrates xi^a eta^b zeta^c, a, b, c "
                  "<= %d", np, deg);
    for (int k = 0; k < 3; k++) { /* tight in each variable */
      const int e[3] = {k == 0 ? deg + 1 : 0, k == 1 ? deg + 1 : 0, k == 2 ? deg + 1 : 0};
      mpgm_test(fabs(rule_monomial3(np, xi, w, e[0], e[1], e[2]) -
                     exact_monomial3(e[0], e[1], e[2])) > 1e-6,
                "H8 %d-point rule is not exact for degree %d in variable %d", np, deg + 1, k);
    }
    err = mpgm_fe_centres(np, xi, w);
    double sw = 0.0, m1 = 0.0, dmin = HUGE_VAL;
    inside = err == 0;
    for (int g = 0; g < np && !err; g++) {
      sw += w[g];
      inside &= mpgm_fe_inside(MPGM_CELL_H8, xi + 3 * g, 0.0) && w[g] == 8.0 / np;
      for (int d = 0; d < 3; d++) { /* each coordinate at a sub-interval's centre */
        const double u = (xi[3 * g + d] + 1.0) * n / 2.0 - 0.5;
        dmin = fmin(dmin, -fabs(u - round(u)));
        m1 += w[g] * xi[3 * g + d];
      }
    }
    mpgm_test(inside && fabs(sw - 8.0) < TOL_EXACT && fabs(m1) < TOL_EXACT && dmin > -TOL_EXACT,
              "H8 %d sub-cell centres: inside, at the sub-cells' centres, weights 8/%d (sum %.15g)",
              np, np, sw);
  }
  mpgm_test(mpgm_fe_gauss(MPGM_CELL_H8, 4, xi, w) == MPGM_ERR_INPUT &&
                mpgm_fe_gauss(MPGM_CELL_Q4, 8, xi, w) == MPGM_ERR_INPUT &&
                mpgm_fe_centres(9, xi, w) == MPGM_ERR_INPUT,
            "unsupported Gauss point / centre counts and 2-D cells return MPGM_ERR_INPUT");
  double N[8], dN[24], xq[24] = {0};
  const double c[3] = {0, 0, 0};
  mpgm_test(mpgm_fe_nnode(MPGM_CELL_T3) == 0 && mpgm_fe_nnode(MPGM_CELL_Q4) == 0 &&
                mpgm_fe_nnode(MPGM_CELL_H8) == 8 &&
                mpgm_fe_eval(MPGM_CELL_Q4, xq, c, N, dN, NULL) == MPGM_ERR_INPUT,
            "3-D build: T3 and Q4 have no nodes and do not evaluate; H8 has 8");
}

/* Inverted hex (top and bottom faces swapped: a mirror image), wrong node
 * count, a 2-D cell kind. */
static void check_inverted_h8(const mpgm_shapefn_type *t, const double *xn, const char *cname) {
  double rev[24];
  for (int a = 0; a < 8; a++)
    for (int d = 0; d < 3; d++) rev[3 * a + d] = xn[3 * ((a + 4) % 8) + d];
  const double xi[3] = {0.1934, -0.4172, 0.3071};
  double N[8], dN[24], detJ = 0.0;
  int err = mpgm_fe_eval(MPGM_CELL_H8, rev, xi, N, dN, &detJ);
  mpgm_test(err == MPGM_ERR_JACOBIAN && detJ < 0.0,
            "%s H8 %s inverted: mpgm_fe_eval returns MPGM_ERR_JACOBIAN (got %d, detJ %g)", t->name,
            cname, err, detJ);
  mpgm_shape_query q = {.n = 8, .xn = rev, .cell = MPGM_CELL_H8, .xi = {xi[0], xi[1], xi[2]}};
  map_hex(rev, xi, q.xp);
  err = t->eval(&q, N, dN);
  mpgm_test(err == MPGM_ERR_JACOBIAN, "%s H8 %s inverted: eval returns MPGM_ERR_JACOBIAN (got %d)",
            t->name, cname, err);
  q.xn = xn;
  q.n = 7;
  err = t->eval(&q, N, dN);
  mpgm_test(err != 0, "%s H8 %s: eval with 7 nodes fails (got %d)", t->name, cname, err);
  q.n = 4;
  q.cell = MPGM_CELL_Q4;
  err = t->eval(&q, N, dN);
  mpgm_test(err != 0, "%s H8 %s: eval of a Q4 cell in 3-D fails (got %d)", t->name, cname, err);
}

/* mpgm_fe_local on a small hex far from the origin with a point outside
 * it, and on a strongly distorted hex (a twisted, tapered top) at points
 * near its corners. */
static void check_local_h8(void) {
  double xn[24], xi[3], back[3];
  const double far[3] = {1234.5, 678.9, -345.6}; /* a cube of h = 0.01 there */
  for (int a = 0; a < 8; a++)
    for (int d = 0; d < 3; d++) xn[3 * a + d] = far[d] + 0.005 * (1.0 + node_xi(a, d));
  const double y[3] = {1234.5 + 0.013, 678.9 - 0.002, -345.6 + 0.004};
  int err = mpgm_fe_local(MPGM_CELL_H8, xn, y, xi);
  map_hex(xn, xi, back);
  mpgm_test(err == 0 && fabs(back[0] - y[0]) < 1e-11 && fabs(back[1] - y[1]) < 1e-11 &&
                fabs(back[2] - y[2]) < 1e-11,
            "H8 of h = 0.01 at x ~ 1e3, point outside: mpgm_fe_local returns %d, x(xi) - x = "
            "(%.1e, %.1e, %.1e)", err, back[0] - y[0], back[1] - y[1], back[2] - y[2]);
  /* unit cube whose top face is turned by 40 degrees and shrunk to 0.5 */
  const double th = 40.0 * PI / 180.0, c = 0.5 * cos(th), s = 0.5 * sin(th);
  for (int a = 0; a < 8; a++) {
    const double u = 0.5 * node_xi(a, 0), v = 0.5 * node_xi(a, 1);
    xn[3 * a] = a < 4 ? u : c * u - s * v;
    xn[3 * a + 1] = a < 4 ? v : s * u + c * v;
    xn[3 * a + 2] = a < 4 ? 0.0 : 1.0;
  }
  double worst = 0.0;
  int fails = 0;
  for (int k = 0; k < 8; k++) {
    const double z[3] = {0.97 * node_xi(k, 0), 0.97 * node_xi(k, 1), 0.97 * node_xi(k, 2)};
    double x[3];
    map_hex(xn, z, x);
    fails += mpgm_fe_local(MPGM_CELL_H8, xn, x, xi) != 0;
    for (int d = 0; d < 3; d++) worst = fmax(worst, fabs(xi[d] - z[d]));
  }
  mpgm_test(fails == 0 && worst < TOL_EXACT,
            "H8 twisted (40 deg) and tapered: mpgm_fe_local at 0.97 of each corner (%d failed, "
            "worst %.1e)", fails, worst);
}

/* mpgm_fe_cube (the MPM grid's H8) against mpgm_fe_eval on the same cube
 * of side h far from the origin, at random points of the cell. */
static void check_cube_h8(rng *r) {
  const double h = 0.02, x0[3] = {-3.5, 12.25, 0.75};
  double xn[24], worst = 0.0;
  for (int a = 0; a < 8; a++)
    for (int d = 0; d < 3; d++) xn[3 * a + d] = x0[d] + 0.5 * h * (1.0 + node_xi(a, d));
  for (int k = 0; k < 64; k++) {
    double xi[3], N[8], dN[24], Nc[8], dNc[24];
    for (int d = 0; d < 3; d++) xi[d] = uniform(r, -1.0, 1.0);
    mpgm_fe_eval(MPGM_CELL_H8, xn, xi, N, dN, NULL);
    mpgm_fe_cube(xi, h, Nc, dNc);
    for (int a = 0; a < 8; a++) {
      worst = fmax(worst, fabs(Nc[a] - N[a]));
      for (int d = 0; d < 3; d++) worst = fmax(worst, h * fabs(dNc[3 * a + d] - dN[3 * a + d]));
    }
  }
  mpgm_test(worst < 1e-12, "H8 cube of h = %g: mpgm_fe_cube = mpgm_fe_eval at 64 points "
            "(worst |N|, h |grad N| difference %.1e)", h, worst);
}

static void check_h8(void) {
  const mpgm_shapefn_type *const *all = mpgm_shapefn_types();
  int ncell_kinds = 0;
  check_local_h8();
  check_rules_h8();
  rng rc = {0x2545F4914F6CDD1DULL};
  check_cube_h8(&rc);
  for (int it = 0; all[it]; it++) {
    const mpgm_shapefn_type *t = all[it];
    mpgm_test(t->name && mpgm_shapefn_type_find(t->name) == t && t->eval,
              "%s: found by name, eval set", t->name);
    if (!t->needs_cell) continue;
    ncell_kinds++;
    rng r = {0x9E3779B97F4A7C15ULL ^ (uint64_t)(1 + it * 2 + MPGM_CELL_H8)};
    double xn[24];
    regular_hex(xn);
    mpgm_test_rel(hex_volume(xn), LX * LY * LZ, TOL_EXACT, "H8: the faces' volume of the box");
    check_hex(t, xn, &r, "regular");
    check_inverted_h8(t, xn, "regular");
    rotate_translate(&r, xn);
    mpgm_test_rel(hex_volume(xn), LX * LY * LZ, TOL_EXACT, "H8: the faces' volume of the turned box");
    check_hex(t, xn, &r, "rotated");
    check_inverted_h8(t, xn, "rotated");
    for (int k = 0; k < N_DISTORTED; k++) {
      char cname[32];
      snprintf(cname, sizeof cname, "distorted %d", k);
      distorted_hex(&r, xn);
      check_hex(t, xn, &r, cname);
      check_inverted_h8(t, xn, cname);
    }
  }
  mpgm_test(ncell_kinds > 0, "at least one cell-based kind (%d)", ncell_kinds);
}
#endif

int main(void) {
#if MPGM_DIM == 2
  check_local_far();
  check_cells();
#else
  check_h8();
#endif
  mpgm_test(mpgm_shapefn_type_find("no-such-kind") == NULL, "unknown kind name: NULL");
  return mpgm_test_summary();
}
