/* test_solids.c -- the bodies' geometry in 3-D (core/geometry.c built with
 * MPGM_DIM = 3): boxes, balls, cylinders about any axis and polygons
 * extruded over z.
 *
 * Each solid is checked three ways that do not share code with the one
 * under test: points placed on purpose just inside and just outside its
 * surface; its bounding box against points sampled on its edges; and its
 * volume against the count of a regular lattice of points it contains
 * (the midpoint rule on 96^3 cells of its box: within 1 %), its surface
 * area and width against closed forms. meets_box is checked on boxes that
 * touch, miss and cross each kind. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "mpgm_scene.h"
#include "mpgm_test.h"

#if MPGM_DIM != 3
#error "test_solids.c checks the 3-D solids: build it with MPGM_DIM = 3"
#endif

static const double PI = 3.14159265358979323846;

static mpgm_scene_body make(int geometry) {
  mpgm_scene_body b;
  memset(&b, 0, sizeof b);
  b.geometry = geometry;
  return b;
}

/* Volume by the midpoint rule on n^3 cells of the bounding box. */
static double lattice_volume(const mpgm_scene_body *b, int n) {
  double h[3], x[3];
  for (int d = 0; d < 3; d++) h[d] = (b->max[d] - b->min[d]) / n;
  long in = 0;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++)
      for (int k = 0; k < n; k++) {
        x[0] = b->min[0] + (i + 0.5) * h[0];
        x[1] = b->min[1] + (j + 0.5) * h[1];
        x[2] = b->min[2] + (k + 0.5) * h[2];
        in += mpgm_body_contains(b, x);
      }
  return in * h[0] * h[1] * h[2];
}

static void check_volume(const mpgm_scene_body *b, const char *name, double exact) {
  mpgm_test_rel(mpgm_body_area(b), exact, TEST_TOL2, "%s: volume = closed form", name);
  mpgm_test_rel(lattice_volume(b, 96), exact, 1e-2, "%s: volume = lattice count (1 %%)", name);
}

static void test_box(void) {
  mpgm_scene_body b = make(MPGM_GEOM_BOX);
  const double lo[3] = {-1.0, 0.5, 2.0}, hi[3] = {3.0, 1.5, 2.25};
  memcpy(b.min, lo, sizeof lo);
  memcpy(b.max, hi, sizeof hi);
  double bl[3], bh[3];
  mpgm_body_bbox(&b, bl, bh);
  mpgm_test(memcmp(bl, lo, sizeof lo) == 0 && memcmp(bh, hi, sizeof hi) == 0, "box: bbox = its corners");
  const double in[][3] = {{0, 1, 2.1}, {-1, 0.5, 2}, {3, 1.5, 2.25}, {1, 1, 2.25}};
  const double out[][3] = {{0, 1, 2.25 + 1e-9}, {-1 - 1e-9, 1, 2.1}, {0, 0.5 - 1e-9, 2.1}};
  for (int k = 0; k < 4; k++)
    mpgm_test(mpgm_body_contains(&b, in[k]), "box: (%g, %g, %g) inside or on the surface", in[k][0],
              in[k][1], in[k][2]);
  for (int k = 0; k < 3; k++)
    mpgm_test(!mpgm_body_contains(&b, out[k]), "box: (%.10g, %.10g, %.10g) outside", out[k][0],
              out[k][1], out[k][2]);
  check_volume(&b, "box", 4.0 * 1.0 * 0.25);
  mpgm_test_rel(mpgm_body_perimeter(&b), 2.0 * (4.0 + 0.25 + 1.0), TEST_TOL1, "box: surface area");
  mpgm_test_rel(mpgm_body_width(&b), 0.25, TEST_TOL0, "box: width = the shortest side");
  const double ml[3] = {3.0, 0.0, 0.0}, mh[3] = {4.0, 2.0, 3.0}; /* shares the face x = 3 */
  const double nl[3] = {0.0, 0.0, 2.3}, nh[3] = {1.0, 2.0, 3.0}; /* above it */
  mpgm_test(mpgm_body_meets_box(&b, ml, mh), "box: a box on its face meets it");
  mpgm_test(!mpgm_body_meets_box(&b, nl, nh), "box: a box above it does not meet it");
}

static void test_ball(void) {
  mpgm_scene_body b = make(MPGM_GEOM_SPHERE);
  const double c[3] = {0.3, -0.2, 1.1}, r = 0.7;
  memcpy(b.centre, c, sizeof c);
  b.radius = r;
  mpgm_body_bbox(&b, b.min, b.max);
  mpgm_test(b.min[0] == c[0] - r && b.max[2] == c[2] + r, "ball: bbox = centre -+ r");
  int on = 1, in = 1, out = 1;
  for (int i = 0; i < 12; i++)
    for (int j = 0; j < 24; j++) { /* directions over the sphere */
      const double th = PI * (i + 0.5) / 12, ph = 2 * PI * j / 24;
      const double n[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)};
      double x[3], xi[3], xo[3];
      for (int d = 0; d < 3; d++) {
        x[d] = c[d] + r * n[d];
        xi[d] = c[d] + r * (1 - 1e-9) * n[d];
        xo[d] = c[d] + r * (1 + 1e-9) * n[d];
      }
      on &= mpgm_body_contains(&b, x);
      in &= mpgm_body_contains(&b, xi);
      out &= !mpgm_body_contains(&b, xo);
    }
  mpgm_test(on && in && out, "ball: 288 points on its sphere inside, 1e-9 r within and beyond it in and out");
  check_volume(&b, "ball", 4.0 / 3.0 * PI * r * r * r);
  mpgm_test_rel(mpgm_body_perimeter(&b), 4.0 * PI * r * r, TEST_TOL1, "ball: surface area 4 pi r^2");
  mpgm_test_rel(mpgm_body_width(&b), 2.0 * r, TEST_TOL0, "ball: width = diameter");
  /* a box whose corner lies on the sphere meets it; one in the bbox's corner does not */
  const double k = r / sqrt(3.0);
  const double tl[3] = {c[0] + k, c[1] + k, c[2] + k}, th[3] = {c[0] + r, c[1] + r, c[2] + r};
  const double ul[3] = {c[0] + 0.6 * r, c[1] + 0.6 * r, c[2] + 0.6 * r};
  mpgm_test(mpgm_body_meets_box(&b, tl, th), "ball: a box with a corner on the sphere meets it");
  mpgm_test(!mpgm_body_meets_box(&b, ul, th), "ball: a box in the bbox's corner does not meet it");
}

/* A cylinder from a to a + axis with radius r, and its rim points. */
static void test_cylinder(const double a[3], const double ax[3], double r, const char *name) {
  mpgm_scene_body b = make(MPGM_GEOM_CYLINDER);
  memcpy(b.centre, a, sizeof b.centre);
  memcpy(b.axis, ax, sizeof b.axis);
  b.radius = r;
  mpgm_body_bbox(&b, b.min, b.max);
  const double L = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
  double e[3], u[3], w[3];
  for (int d = 0; d < 3; d++) e[d] = ax[d] / L;
  /* u, w: unit vectors normal to e */
  const int m = fabs(e[0]) < 0.6 ? 0 : 1;
  double t[3] = {0, 0, 0};
  t[m] = 1.0;
  u[0] = e[1] * t[2] - e[2] * t[1], u[1] = e[2] * t[0] - e[0] * t[2], u[2] = e[0] * t[1] - e[1] * t[0];
  const double un = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (int d = 0; d < 3; d++) u[d] /= un;
  w[0] = e[1] * u[2] - e[2] * u[1], w[1] = e[2] * u[0] - e[0] * u[2], w[2] = e[0] * u[1] - e[1] * u[0];
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  int side = 1, caps = 1, inside = 1;
  for (int j = 0; j < 720; j++) {
    const double ph = 2 * PI * j / 720, cs = cos(ph), sn = sin(ph);
    for (int end = 0; end < 2; end++) {
      double x[3], xo[3], xa[3];
      for (int d = 0; d < 3; d++) {
        const double n = cs * u[d] + sn * w[d];
        x[d] = a[d] + end * ax[d] + r * n;                            /* on the rim    */
        xo[d] = a[d] + 0.5 * ax[d] + r * (1 + 1e-9) * n;              /* beyond the side */
        xa[d] = a[d] + (end ? 1 + 1e-9 : -1e-9) * ax[d] + 0.5 * r * n; /* beyond a cap  */
        lo[d] = fmin(lo[d], x[d]);
        hi[d] = fmax(hi[d], x[d]);
      }
      inside &= mpgm_body_contains(&b, x);
      side &= !mpgm_body_contains(&b, xo);
      caps &= !mpgm_body_contains(&b, xa);
    }
  }
  mpgm_test(inside, "%s: its rims inside (on the surface)", name);
  mpgm_test(side && caps, "%s: 1e-9 beyond its side and its caps outside", name);
  double gap = 0.0, over = 0.0;
  for (int d = 0; d < 3; d++) {
    gap = fmax(gap, fmax(lo[d] - b.min[d], b.max[d] - hi[d]));
    over = fmax(over, fmax(b.min[d] - lo[d], hi[d] - b.max[d]));
  }
  mpgm_test(over <= TEST_TOL2 * (L + r) && gap <= 1e-4 * r,
            "%s: bbox holds the rims tightly (beyond %.2g, short %.2g)", name, over, gap);
  check_volume(&b, name, PI * r * r * L);
  mpgm_test_rel(mpgm_body_perimeter(&b), 2 * PI * r * L + 2 * PI * r * r, TEST_TOL1, "%s: surface area", name);
  mpgm_test_rel(mpgm_body_width(&b), fmin(2 * r, L), TEST_TOL0, "%s: width", name);
  double fl[3], fh[3];
  for (int d = 0; d < 3; d++) fl[d] = b.max[d] + 1e-6, fh[d] = b.max[d] + 1.0;
  mpgm_test(!mpgm_body_meets_box(&b, fl, fh), "%s: a box beyond its bbox does not meet it", name);
}

/* An L-shaped polygon (x-y) extruded over [z0, z1]. */
static void test_prism(void) {
  const double p[] = {0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2};
  mpgm_scene_body b = make(MPGM_GEOM_POLYGON);
  b.npoints = 6;
  memcpy(b.points, p, sizeof p);
  b.z[0] = -0.5, b.z[1] = 0.25;
  mpgm_body_bbox(&b, b.min, b.max);
  mpgm_test(b.min[0] == 0 && b.max[1] == 2 && b.min[2] == -0.5 && b.max[2] == 0.25,
            "prism: bbox = the polygon's x [z0, z1]");
  const double in[][3] = {{0.5, 0.5, 0}, {1.5, 0.5, -0.5}, {0.5, 1.5, 0.25}, {1, 1, 0}};
  const double out[][3] = {{1.5, 1.5, 0}, {0.5, 0.5, 0.25 + 1e-9}, {0.5, 0.5, -0.5 - 1e-9}, {2 + 1e-9, 0.5, 0}};
  for (int k = 0; k < 4; k++)
    mpgm_test(mpgm_body_contains(&b, in[k]), "prism: (%g, %g, %g) inside", in[k][0], in[k][1], in[k][2]);
  for (int k = 0; k < 4; k++)
    mpgm_test(!mpgm_body_contains(&b, out[k]), "prism: (%.10g, %.10g, %.10g) outside", out[k][0], out[k][1],
              out[k][2]);
  check_volume(&b, "prism", 3.0 * 0.75);
  mpgm_test_rel(mpgm_body_perimeter(&b), 8.0 * 0.75 + 2 * 3.0, TEST_TOL1, "prism: surface area");
  mpgm_test_rel(mpgm_body_width(&b), 0.75, TEST_TOL0, "prism: width = the smallest extent");
  const double nl[3] = {1.2, 1.2, -1}, nh[3] = {1.8, 1.8, 1};  /* in the notch */
  const double zl[3] = {0.2, 0.2, 0.3}, zh[3] = {0.4, 0.4, 1}; /* above it */
  const double cl[3] = {-1, 0.4, 0.1}, ch[3] = {3, 0.45, 0.2}; /* a bar across it */
  const double vl[3] = {1, 1, 0.25}, vh[3] = {1, 1, 2};          /* on the reflex edge's top */
  mpgm_test(!mpgm_body_meets_box(&b, nl, nh), "prism: a box in the notch does not meet it");
  mpgm_test(!mpgm_body_meets_box(&b, zl, zh), "prism: a box above it does not meet it");
  mpgm_test(mpgm_body_meets_box(&b, cl, ch), "prism: a bar across it meets it");
  mpgm_test(mpgm_body_meets_box(&b, vl, vh), "prism: a box touching its reflex edge's end meets it");
}

int main(void) {
  test_box();
  test_ball();
  const double a1[3] = {0.5, 0.5, 0.0}, z[3] = {0.0, 0.0, 2.0};
  test_cylinder(a1, z, 0.5, "cylinder along z");
  const double a2[3] = {-1.0, 0.2, 0.4}, x[3] = {1.5, 0.0, 0.0};
  test_cylinder(a2, x, 0.25, "cylinder along x");
  const double a3[3] = {0.1, -0.3, 0.7}, o[3] = {0.8, -0.6, 1.2};
  test_cylinder(a3, o, 0.4, "cylinder along (0.8, -0.6, 1.2)");
  test_prism();
  return mpgm_test_summary();
}
