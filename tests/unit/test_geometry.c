/* test_geometry.c -- body geometries (mpgm_body_contains, mpgm_body_bbox,
 * polygon validation, box selectors) and the reference-solution metrics.
 *
 * Point-in-polygon is checked against an independent winding number (sum
 * of the angles subtended by the edges, atan2) at random points, at points
 * whose y is exactly a vertex's y (rays through vertices), and at points on
 * edges and vertices, for convex and non-convex polygons in both
 * orientations. The metrics are checked on synthetic probe histories: the
 * exact rolling history (errors 0), a known offset and a known scaling
 * (errors in closed form), and probe_value. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mpgm_core_impl.h"
#include "mpgm_scene.h"
#include "mpgm_scene_io.h"
#include "mpgm_mpm.h"
#include "mpgm_test.h"
#include "scene_impl.h"

static const double PI = 3.14159265358979323846;

/* ------------------------------------------------------------ helpers */

static mpgm_scene_body make_rect(double x0, double y0, double x1, double y1) {
  mpgm_scene_body b;
  memset(&b, 0, sizeof b);
  b.geometry = MPGM_GEOM_RECTANGLE;
  b.min[0] = x0, b.min[1] = y0, b.max[0] = x1, b.max[1] = y1;
  return b;
}

static mpgm_scene_body make_disk(double cx, double cy, double r) {
  mpgm_scene_body b;
  memset(&b, 0, sizeof b);
  b.geometry = MPGM_GEOM_DISK;
  b.centre[0] = cx, b.centre[1] = cy, b.radius = r;
  mpgm_body_bbox(&b, b.min, b.max);
  return b;
}

/* reverse: store the points in the opposite order (other orientation) */
static mpgm_scene_body make_polygon(const double *p, int n, int reverse) {
  mpgm_scene_body b;
  memset(&b, 0, sizeof b);
  b.geometry = MPGM_GEOM_POLYGON;
  b.npoints = n;
  for (int i = 0; i < n; i++) {
    const int k = reverse ? n - 1 - i : i;
    b.points[2 * i] = p[2 * k];
    b.points[2 * i + 1] = p[2 * k + 1];
  }
  mpgm_body_bbox(&b, b.min, b.max);
  return b;
}

/* Independent: winding number from the sum of subtended angles (x not on
 * the boundary). */
static int winding_inside(const double *p, int n, const double x[2]) {
  double sum = 0.0;
  for (int i = 0; i < n; i++) {
    const int j = (i + 1) % n;
    const double ax = p[2 * i] - x[0], ay = p[2 * i + 1] - x[1];
    const double bx = p[2 * j] - x[0], by = p[2 * j + 1] - x[1];
    sum += atan2(ax * by - ay * bx, ax * bx + ay * by);
  }
  return fabs(sum) > PI; /* 2 pi inside, 0 outside */
}

/* distance from x to the polygon boundary */
static double boundary_distance(const double *p, int n, const double x[2]) {
  double dmin = INFINITY;
  for (int i = 0; i < n; i++) {
    const int j = (i + 1) % n;
    const double ex = p[2 * j] - p[2 * i], ey = p[2 * j + 1] - p[2 * i + 1];
    const double wx = x[0] - p[2 * i], wy = x[1] - p[2 * i + 1];
    double t = (wx * ex + wy * ey) / (ex * ex + ey * ey);
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    dmin = fmin(dmin, hypot(wx - t * ex, wy - t * ey));
  }
  return dmin;
}

/* ------------------------------------------------------------ rectangles, disks */

static void test_rectangle(void) {
  const mpgm_scene_body b = make_rect(-0.385, 0.125, 2.615, 1.25);
  double lo[2], hi[2];
  mpgm_body_bbox(&b, lo, hi);
  mpgm_test(lo[0] == -0.385 && lo[1] == 0.125 && hi[0] == 2.615 && hi[1] == 1.25, "rectangle: bbox = corners");
  const double in[][2] = {{1.0, 0.5}, {-0.385, 0.5}, {2.615, 1.25}, {-0.385, 0.125}, {1.3, 1.25}};
  for (size_t k = 0; k < sizeof in / sizeof in[0]; k++)
    mpgm_test(mpgm_body_contains(&b, in[k]), "rectangle: (%g, %g) inside or on the boundary", in[k][0], in[k][1]);
  const double out[][2] = {{-0.385 - 1e-9, 0.5}, {2.615 + 1e-9, 1.0}, {1.0, 1.25 + 1e-9}, {1.0, 0.125 - 1e-9}};
  for (size_t k = 0; k < sizeof out / sizeof out[0]; k++)
    mpgm_test(!mpgm_body_contains(&b, out[k]), "rectangle: (%.12g, %.12g) outside", out[k][0], out[k][1]);
}

static void test_disk(void) {
  const double cx = 0.6183, cy = 0.5, r = 0.4871;
  const mpgm_scene_body b = make_disk(cx, cy, r);
  mpgm_test(b.min[0] == cx - r && b.max[0] == cx + r && b.min[1] == cy - r && b.max[1] == cy + r,
            "disk: bbox = centre -/+ radius");
  const double c[2] = {cx, cy};
  mpgm_test(mpgm_body_contains(&b, c), "disk: centre inside");
  int on = 1, near_in = 1, near_out = 1;
  for (int k = 0; k < 64; k++) {
    const double th = 2.0 * PI * k / 64 + 0.0123;
    const double e[2] = {cos(th), sin(th)};
    const double x[2] = {cx + r * e[0], cy + r * e[1]};
    const double xi[2] = {cx + r * (1 - 1e-9) * e[0], cy + r * (1 - 1e-9) * e[1]};
    const double xo[2] = {cx + r * (1 + 1e-9) * e[0], cy + r * (1 + 1e-9) * e[1]};
    on &= mpgm_body_contains(&b, x);
    near_in &= mpgm_body_contains(&b, xi);
    near_out &= !mpgm_body_contains(&b, xo);
  }
  mpgm_test(on, "disk: 64 points on the circle count as inside");
  mpgm_test(near_in, "disk: 64 points 1e-9 r inside");
  mpgm_test(near_out, "disk: 64 points 1e-9 r outside are outside");
  const double corner[2] = {cx + 0.95 * r, cy + 0.95 * r};
  mpgm_test(!mpgm_body_contains(&b, corner), "disk: bbox corner region outside");
}

/* a ring sector: centre, radii, angles in degrees */
static mpgm_scene_body make_ring(double cx, double cy, double ri, double ro, double a0, double a1) {
  mpgm_scene_body b;
  memset(&b, 0, sizeof b);
  b.geometry = MPGM_GEOM_RING;
  b.centre[0] = cx, b.centre[1] = cy, b.radius_in = ri, b.radius = ro;
  b.angle[0] = a0 * PI / 180.0, b.angle[1] = a1 * PI / 180.0;
  mpgm_body_bbox(&b, b.min, b.max);
  return b;
}

/* x at radius r and angle a (degrees) about c */
static void polar(const mpgm_scene_body *b, double r, double a, double x[2]) {
  x[0] = b->centre[0] + r * cos(a * PI / 180.0);
  x[1] = b->centre[1] + r * sin(a * PI / 180.0);
}

static void test_ring(void) {
  const mpgm_scene_body q = make_ring(0.1, -0.2, 0.4, 0.6, 0.0, 90.0);
  mpgm_test(fabs(q.min[0] - 0.1) < 1e-15 && fabs(q.min[1] + 0.2) < 1e-15 && fabs(q.max[0] - 0.7) < 1e-15 &&
                fabs(q.max[1] - 0.4) < 1e-15,
            "quarter ring: bbox [%g, %g] x [%g, %g]", q.min[0], q.max[0], q.min[1], q.max[1]);
  const double in[][2] = {{0.5, 45.0}, {0.4, 0.0}, {0.6, 90.0}, {0.45, 89.9}, {0.59, 0.1}};
  const double out[][2] = {{0.39, 45.0}, {0.61, 45.0}, {0.5, -1.0}, {0.5, 91.0}, {0.5, 180.0}};
  int ok_in = 1, ok_out = 1;
  for (int k = 0; k < 5; k++) {
    double x[2];
    polar(&q, in[k][0], in[k][1], x);
    ok_in &= mpgm_body_contains(&q, x);
    polar(&q, out[k][0], out[k][1], x);
    ok_out &= !mpgm_body_contains(&q, x);
  }
  mpgm_test(ok_in, "quarter ring: 5 points inside or on its edges");
  mpgm_test(ok_out, "quarter ring: 5 points outside (radii, angles)");
  const mpgm_scene_body f = make_ring(0.0, 0.0, 0.75, 1.25, 0.0, 360.0);
  double x[2];
  polar(&f, 1.0, 217.0, x);
  const double c[2] = {0.0, 0.0};
  mpgm_test(mpgm_body_contains(&f, x) && !mpgm_body_contains(&f, c) && f.min[0] == -1.25 && f.max[1] == 1.25,
            "full ring: inside at any angle, its hole outside, bbox the outer circle's");
  const mpgm_scene_body s = make_ring(0.0, 0.0, 1.0, 2.0, -30.0, 30.0);
  double a[2], o[2];
  polar(&s, 1.5, -20.0, a);
  polar(&s, 1.5, 40.0, o);
  mpgm_test(mpgm_body_contains(&s, a) && !mpgm_body_contains(&s, o) && fabs(s.min[0] - cos(PI / 6)) < 1e-15 &&
                fabs(s.max[0] - 2.0) < 1e-15,
            "sector across angle 0: -20 deg inside, 40 deg outside, bbox x [%g, %g]", s.min[0], s.max[0]);
}

/* ------------------------------------------------------------ polygons */

typedef struct poly_case {
  const char *name;
  int n;
  double p[2 * 12];
} poly_case;

static const poly_case polys[] = {
    {"convex hexagon", 6, {1.0, 0.0, 2.0, 0.1, 2.6, 0.9, 2.1, 1.7, 0.9, 1.8, 0.3, 0.85}},
    {"triangle", 3, {0.1, 0.2, 1.9, 0.35, 0.7, 1.6}},
    {"notched (one reflex vertex)", 5, {0.2, 0.0, 1.0, 0.0, 1.0, 0.8, 0.6, 0.3, 0.2, 0.8}},
    {"L-shape", 6, {0.0, 0.0, 2.0, 0.0, 2.0, 0.5, 0.5, 0.5, 0.5, 1.5, 0.0, 1.5}},
    {"star (5 reflex vertices)", 10,
     {1.0, 0.0, 1.25, 0.65, 1.95, 0.69, 1.4, 1.1, 1.6, 1.8, 1.0, 1.4, 0.4, 1.8, 0.6, 1.1, 0.05, 0.69, 0.75, 0.65}},
    {"comb (vertices sharing y)", 8, {0.0, 0.0, 3.0, 0.0, 3.0, 1.0, 2.0, 1.0, 2.0, 0.5, 1.0, 0.5, 1.0, 1.0, 0.0, 1.0}},
};

static void test_polygon(const poly_case *pc, int reverse, rng *r) {
  const mpgm_scene_body b = make_polygon(pc->p, pc->n, reverse);
  const char *ori = reverse ? "reversed" : "as given";
  const double *p = b.points;
  const int n = b.npoints;
  char msg[256] = "";
  mpgm_test(mpgm_polygon_check(p, n, msg, sizeof msg) == 0, "%s (%s): accepted by mpgm_polygon_check %s",
            pc->name, ori, msg);
  /* bbox against the vertices */
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (int i = 0; i < n; i++)
    for (int d = 0; d < 2; d++) lo[d] = fmin(lo[d], p[2 * i + d]), hi[d] = fmax(hi[d], p[2 * i + d]);
  mpgm_test(b.min[0] == lo[0] && b.min[1] == lo[1] && b.max[0] == hi[0] && b.max[1] == hi[1],
            "%s (%s): bbox = extent of the vertices", pc->name, ori);
  /* vertices and points along every edge are inside */
  int vert = 1, edge = 1;
  for (int i = 0; i < n; i++) {
    vert &= mpgm_body_contains(&b, p + 2 * i);
    const int j = (i + 1) % n;
    for (int k = 1; k < 8; k++) {
      const double t = k / 8.0 + 0.0137 * (k % 3);
      const double x[2] = {p[2 * i] + t * (p[2 * j] - p[2 * i]), p[2 * i + 1] + t * (p[2 * j + 1] - p[2 * i + 1])};
      edge &= mpgm_body_contains(&b, x);
    }
  }
  mpgm_test(vert, "%s (%s): every vertex counts as inside", pc->name, ori);
  mpgm_test(edge, "%s (%s): 7 points on every edge count as inside", pc->name, ori);
  /* random points against the winding number (away from the boundary) */
  const double L = hi[0] - lo[0] + hi[1] - lo[1];
  int agree = 1, nin = 0, ntested = 0;
  for (int k = 0; k < 4000; k++) {
    double x[2] = {uniform(r, lo[0] - 0.1 * L, hi[0] + 0.1 * L), uniform(r, lo[1] - 0.1 * L, hi[1] + 0.1 * L)};
    if (k % 4 == 0) x[1] = p[2 * (k / 4 % n) + 1]; /* horizontal ray through a vertex */
    if (boundary_distance(p, n, x) < 1e-9 * L) continue;
    const int want = winding_inside(p, n, x), got = mpgm_body_contains(&b, x);
    if (want != got) {
      agree = 0;
      printf("  %s (%s): (%.17g, %.17g) contains %d, winding %d\n", pc->name, ori, x[0], x[1], got, want);
    }
    nin += want;
    ntested++;
  }
  mpgm_test(agree && nin > 100 && ntested - nin > 100,
            "%s (%s): %d random points (%d inside, 1/4 on vertex rows) agree with the winding number",
            pc->name, ori, ntested, nin);
  /* just outside the middle of every edge (outward normal) is outside */
  const double sgn = mpgm_polygon_area(p, n) > 0 ? 1.0 : -1.0; /* ccw: outward = right of edge */
  int outside = 1, inside = 1;
  for (int i = 0; i < n; i++) {
    const int j = (i + 1) % n;
    const double ex = p[2 * j] - p[2 * i], ey = p[2 * j + 1] - p[2 * i + 1], le = hypot(ex, ey);
    const double m[2] = {0.5 * (p[2 * i] + p[2 * j]), 0.5 * (p[2 * i + 1] + p[2 * j + 1])};
    const double nx = sgn * ey / le, ny = -sgn * ex / le, d = 1e-9 * L;
    const double xo[2] = {m[0] + d * nx, m[1] + d * ny}, xi[2] = {m[0] - d * nx, m[1] - d * ny};
    outside &= !mpgm_body_contains(&b, xo);
    inside &= mpgm_body_contains(&b, xi);
  }
  mpgm_test(outside, "%s (%s): 1e-9 L outside every edge midpoint is outside", pc->name, ori);
  mpgm_test(inside, "%s (%s): 1e-9 L inside every edge midpoint is inside", pc->name, ori);
}

static void test_polygon_check(void) {
  char msg[256];
  const struct {
    const char *name;
    int n;
    double p[12];
  } bad[] = {
      {"2 points", 2, {0, 0, 1, 0}},
      {"closing point repeated", 4, {0, 0, 1, 0, 0.5, 1, 0, 0}},
      {"consecutive points equal", 4, {0, 0, 1, 0, 1, 0, 0.5, 1}},
      {"collinear (zero area)", 3, {0.2, 0.0, 0.6, 0.4, 1.0, 0.8}},
      {"bow-tie", 4, {0.2, 0.0, 1.0, 0.8, 1.0, 0.0, 0.2, 0.5}},
      {"vertex touching an edge", 6, {0, 0, 2, 0, 2, 2, 1, 0, 0.5, 1.5, 0, 2}},
      {"edge folding back", 4, {0, 0, 2, 0, 1, 0, 1, 1}},
      {"spike back along the first edge", 5, {0, 0, 2, 0, 2, 1, 0, 1, 1, 0}},
  };
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
    msg[0] = '\0';
    const int rc = mpgm_polygon_check(bad[k].p, bad[k].n, msg, sizeof msg);
    mpgm_test(rc != 0 && msg[0], "polygon check rejects %s: %s", bad[k].name, msg);
  }
  const double sq[] = {0, 0, 1, 0, 1, 1, 0, 1};
  mpgm_test_rel(mpgm_polygon_area(sq, 4), 1.0, TEST_TOL0, "polygon area: unit square ccw = 1");
  const double sqr[] = {0, 1, 1, 1, 1, 0, 0, 0};
  mpgm_test_rel(mpgm_polygon_area(sqr, 4), -1.0, TEST_TOL0, "polygon area: unit square cw = -1");
  double big[2 * (MPGM_POLYGON_MAX + 1)];
  for (int i = 0; i <= MPGM_POLYGON_MAX; i++) {
    big[2 * i] = cos(2 * PI * i / (MPGM_POLYGON_MAX + 1));
    big[2 * i + 1] = sin(2 * PI * i / (MPGM_POLYGON_MAX + 1));
  }
  mpgm_test(mpgm_polygon_check(big, MPGM_POLYGON_MAX + 1, msg, sizeof msg) != 0,
            "polygon check rejects %d points: %s", MPGM_POLYGON_MAX + 1, msg);
  for (int i = 0; i < MPGM_POLYGON_MAX; i++) {
    big[2 * i] = cos(2 * PI * i / MPGM_POLYGON_MAX);
    big[2 * i + 1] = sin(2 * PI * i / MPGM_POLYGON_MAX);
  }
  msg[0] = '\0';
  mpgm_test(mpgm_polygon_check(big, MPGM_POLYGON_MAX, msg, sizeof msg) == 0,
            "polygon check accepts a regular %d-gon %s", MPGM_POLYGON_MAX, msg);
}

static void test_meets_box(void) {
  const mpgm_scene_body d = make_disk(0.6, 0.5, 0.5);
  const double lo1[2] = {0.0, -1e-8}, hi1[2] = {4.2, 1e-8}; /* the floor line y = 0 */
  mpgm_test(mpgm_body_meets_box(&d, lo1, hi1), "box: disk tangent to a thin box at y = 0 meets it");
  const double lo2[2] = {0.0, 0.0}, hi2[2] = {0.15, 0.15}; /* in the bbox corner, off the disk */
  mpgm_test(!mpgm_body_meets_box(&d, lo2, hi2), "box: bbox corner away from the disk does not meet it");
  const double lo2b[2] = {0.0, 0.0}, hi2b[2] = {0.2, 0.2}; /* corner (0.2, 0.2) on the circle */
  mpgm_test(mpgm_body_meets_box(&d, lo2b, hi2b), "box: a box whose corner touches the circle meets the disk");
  const poly_case *pc = &polys[2]; /* notched */
  const mpgm_scene_body b = make_polygon(pc->p, pc->n, 0);
  const double lo3[2] = {0.55, 0.5}, hi3[2] = {0.65, 0.7}; /* inside the notch */
  mpgm_test(!mpgm_body_meets_box(&b, lo3, hi3), "box: inside the notch does not meet the polygon");
  const double lo4[2] = {0.5, 0.1}, hi4[2] = {0.7, 0.2}; /* inside the polygon */
  mpgm_test(mpgm_body_meets_box(&b, lo4, hi4), "box: inside the polygon meets it");
  const double lo5[2] = {-1.0, 0.4}, hi5[2] = {3.0, 0.45}; /* crosses, no vertex inside */
  mpgm_test(mpgm_body_meets_box(&b, lo5, hi5), "box: a band across the polygon meets it");
  const double lo6[2] = {0.6, 0.3}, hi6[2] = {0.6, 0.3}; /* a point: the reflex vertex */
  mpgm_test(mpgm_body_meets_box(&b, lo6, hi6), "box: a point box on a vertex meets the polygon");
}

/* ------------------------------------------------------------ reference metrics */

static double metric(const cJSON *m, const char *name) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(m, name);
  return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

enum { NPROBE = 2, NCOL = 2 + 2 * NPROBE, NROW = 1001 };

/* history: probe 1 runs s(t) = s_ref(t) * (1 + scale) + offset, probe 0 junk */
static void rolling_history(double *h, double alpha_deg, double g, double dt, double scale, double offset) {
  const double acc = g * sin(alpha_deg * PI / 180.0) / 3.0;
  for (int k = 0; k < NROW; k++) {
    double *row = h + (size_t)NCOL * k;
    const double t = k * dt, s = acc * t * t;
    row[0] = k;
    row[1] = t;
    row[2] = 123.0, row[3] = -45.6; /* probe 0: must be ignored */
    row[4] = k ? s * (1.0 + scale) + offset : 0.0;
    row[5] = 0.0123 * k;
  }
}

static void test_rolling_disk(void) {
  mpgm_scene s;
  memset(&s, 0, sizeof s);
  s.reference.type = mpgm_reference_type_find("rolling_disk");
  mpgm_test(s.reference.type != NULL, "reference kind rolling_disk is listed");
  if (!s.reference.type) return;
  s.reference.probe = 1;
  const double alpha = 60.0, g = 9.81, dt = 0.001;
  s.reference.param[0] = alpha;
  s.reference.param[1] = g;
  const double ca = cos(alpha * PI / 180.0), acc = g * sin(alpha * PI / 180.0) / 3.0;
  double *h = malloc(sizeof(double) * NCOL * NROW);
  /* exact rolling: every error is 0 */
  rolling_history(h, alpha, g, dt, 0.0, 0.0);
  cJSON *m = cJSON_CreateObject();
  mpgm_test(mpgm_reference_metrics(&s, NROW, NCOL, h, NULL, m) == 0, "rolling_disk: metrics return 0");
  const double sref1 = acc * 1.0 * 1.0;
  mpgm_test_rel(metric(m, "s_ref_final"), sref1, TEST_TOL1, "rolling_disk exact: s_ref_final = g sin60 / 3");
  mpgm_test_rel(sref1, 2.8319030703751142, TEST_TOL1, "rolling_disk: s_ref(1 s) = 2.8319030703751142 m");
  mpgm_test_rel(metric(m, "s_final"), sref1, TEST_TOL1, "rolling_disk exact: s_final = s_ref_final");
  mpgm_test_abs(metric(m, "s_error"), 0.0, TEST_TOL2, "rolling_disk exact: s_error = 0");
  mpgm_test_abs(metric(m, "error"), 0.0, TEST_TOL3, "rolling_disk exact: error = 0");
  mpgm_test_abs(metric(m, "error_rms"), 0.0, TEST_TOL3, "rolling_disk exact: error_rms = 0");
  mpgm_test_abs(metric(m, "error_max"), 0.0, TEST_TOL3, "rolling_disk exact: error_max = 0");
  cJSON_Delete(m);
  /* constant offset d along the incline: |u_ref - u| = d cos(alpha) in every row */
  const double d = 0.0371;
  rolling_history(h, alpha, g, dt, 0.0, d);
  m = cJSON_CreateObject();
  mpgm_reference_metrics(&s, NROW, NCOL, h, NULL, m);
  mpgm_test_rel(metric(m, "s_final"), sref1 + d, TEST_TOL1, "rolling_disk offset: s_final");
  mpgm_test_rel(metric(m, "s_error"), d / sref1, TEST_TOL3, "rolling_disk offset: s_error = d / s_ref_final");
  mpgm_test_rel(metric(m, "error"), sqrt((double)(NROW - 1)) * d * ca, TEST_TOL4,
                "rolling_disk offset: error = sqrt(1000) d cos60");
  mpgm_test_rel(metric(m, "error_rms"), d * ca, TEST_TOL4, "rolling_disk offset: error_rms = d cos60");
  mpgm_test_rel(metric(m, "error_max"), d * ca, TEST_TOL4, "rolling_disk offset: error_max = d cos60");
  cJSON_Delete(m);
  /* scaled: s = (1 + e) s_ref: |u_ref - u| = e acc t^2 cos(alpha); sum t^4 in closed form */
  const double e = -0.0625;
  rolling_history(h, alpha, g, dt, e, 0.0);
  m = cJSON_CreateObject();
  mpgm_reference_metrics(&s, NROW, NCOL, h, NULL, m);
  const double N = NROW - 1; /* sum_{k=1}^N k^4 = N(N+1)(2N+1)(3N^2+3N-1)/30 */
  const double s4 = N * (N + 1) * (2 * N + 1) * (3 * N * N + 3 * N - 1) / 30.0 * pow(dt, 4);
  mpgm_test_rel(metric(m, "error"), fabs(e) * acc * ca * sqrt(s4), TEST_TOL4, "rolling_disk scaled: error");
  mpgm_test_rel(metric(m, "error_rms"), fabs(e) * acc * ca * sqrt(s4 / N), TEST_TOL4,
                "rolling_disk scaled: error_rms");
  mpgm_test_rel(metric(m, "error_max"), fabs(e) * acc * ca, TEST_TOL4, "rolling_disk scaled: error_max at t = 1");
  mpgm_test_rel(metric(m, "s_error"), fabs(e), TEST_TOL3, "rolling_disk scaled: s_error = |e|");
  cJSON_Delete(m);
  /* only the initial row: s values, no error over steps */
  m = cJSON_CreateObject();
  mpgm_reference_metrics(&s, 1, NCOL, h, NULL, m);
  mpgm_test(cJSON_GetObjectItem(m, "s_final") && !cJSON_GetObjectItem(m, "error") &&
                !cJSON_GetObjectItem(m, "s_error"),
            "rolling_disk, row 0 only: s_final, no error, no s_error");
  cJSON_Delete(m);
  /* history narrower than the probe's columns: error, nothing added */
  m = cJSON_CreateObject();
  mpgm_test(mpgm_reference_metrics(&s, NROW, 4, h, NULL, m) != 0 && m->child == NULL,
            "rolling_disk: history without the probe's columns is refused, nothing added");
  cJSON_Delete(m);
  free(h);
}

static void test_probe_value(void) {
  mpgm_scene s;
  memset(&s, 0, sizeof s);
  s.reference.type = mpgm_reference_type_find("probe_value");
  mpgm_test(s.reference.type != NULL, "reference kind probe_value is listed");
  if (!s.reference.type) return;
  s.reference.probe = 1;
  s.reference.component = 1;
  s.reference.param[0] = -0.67437;
  const double h[3 * NCOL] = {0, 0, 0, 0, 0, 0, 1, 0.5, 9, 9, -0.01, -0.3, 2, 1.0, 9, 9, -0.0315, -0.66912};
  cJSON *m = cJSON_CreateObject();
  mpgm_test(mpgm_reference_metrics(&s, 3, NCOL, h, NULL, m) == 0, "probe_value: metrics return 0");
  mpgm_test_rel(metric(m, "reference_value"), -0.67437, TEST_TOL0, "probe_value: reference_value");
  mpgm_test_rel(metric(m, "error"), 0.67437 - 0.66912, TEST_TOL2, "probe_value: error = |u_final - value|");
  mpgm_test_rel(metric(m, "relative_error"), (0.67437 - 0.66912) / 0.67437, TEST_TOL2,
                "probe_value: relative_error = error / |value|");
  cJSON_Delete(m);
  s.reference.component = 0;
  s.reference.param[0] = 0.0;
  m = cJSON_CreateObject();
  mpgm_reference_metrics(&s, 3, NCOL, h, NULL, m);
  mpgm_test_rel(metric(m, "error"), 0.0315, TEST_TOL1, "probe_value x, value 0: error = |ux|");
  mpgm_test(!cJSON_GetObjectItem(m, "relative_error"), "probe_value, value 0: no relative_error");
  cJSON_Delete(m);
  s.reference.type = NULL;
  m = cJSON_CreateObject();
  mpgm_test(mpgm_reference_metrics(&s, 3, NCOL, h, NULL, m) == 0 && m->child == NULL,
            "no reference: nothing added");
  cJSON_Delete(m);
  int nk = 0;
  for (const mpgm_reference_type *const *t = mpgm_reference_types(); *t; t++, nk++)
    mpgm_test((*t)->name && (*t)->doc && (*t)->metrics && (*t)->nparam <= MPGM_REF_MAXPARAM &&
                  mpgm_reference_type_find((*t)->name) == *t,
              "reference kind %s: complete record, found by name", (*t)->name);
  mpgm_test(nk >= 2 && !mpgm_reference_type_find("nosuch") && !mpgm_reference_type_find(NULL),
            "reference list: %d kinds, unknown names not found", nk);
}

/* column_wave: a history that is the modal series itself (summed here,
 * independently of the closed form the kind uses) has no error; its
 * amplitude is rho g H^2 / M; a history off by a constant is off by it. */
static double column_series(double H, double M, double rho, double g, double t) {
  const double c = sqrt(M / rho);
  double w = 0.5 * H * H; /* u_top = -(rho g / M) (H^2/2 - sum ...) */
  for (int n = 1; n <= 20000; n++) {
    const double k = (2 * n - 1) * PI / (2.0 * H);
    w -= (n % 2 ? 2.0 : -2.0) / (H * k * k * k) * cos(c * k * t);
  }
  return -rho * g / M * w;
}

static void test_column_wave(void) {
  mpgm_scene s;
  memset(&s, 0, sizeof s);
  s.reference.type = mpgm_reference_type_find("column_wave");
  mpgm_test(s.reference.type != NULL, "reference kind column_wave is listed");
  if (!s.reference.type) return;
  const double H = 10.0, M = 13461538.461538462, rho = 2000.0, g = 9.81;
  s.reference.probe = 1;
  s.reference.component = 1;
  s.reference.param[0] = H, s.reference.param[1] = M, s.reference.param[2] = rho, s.reference.param[3] = g;
  static double h[NROW * NCOL];
  const double T = 4.0 * H / sqrt(M / rho), dt = 2.3 * T / (NROW - 1); /* 2.3 periods */
  for (int shift = 0; shift < 2; shift++) {
    for (int k = 0; k < NROW; k++) {
      double *row = h + (size_t)NCOL * k;
      row[0] = k, row[1] = k * dt, row[2] = 7.0, row[3] = 8.0, row[4] = -1.0;
      row[5] = column_series(H, M, rho, g, k * dt) + (shift && k ? 1e-3 : 0.0);
    }
    cJSON *m = cJSON_CreateObject();
    mpgm_test(mpgm_reference_metrics(&s, NROW, NCOL, h, NULL, m) == 0, "column_wave: metrics return 0");
    const double amp = rho * g * H * H / M;
    mpgm_test_rel(metric(m, "top_amplitude_ref"), amp, TEST_TOL1, "column_wave: amplitude rho g H^2 / M");
    mpgm_test_rel(metric(m, "period_ref"), T, TEST_TOL1, "column_wave: period 4 H / c");
    /* the series, cut after 20000 terms, is exact to about amp / n^2 */
    if (!shift) {
      mpgm_test_abs(metric(m, "error_max"), 0.0, 1e-8 * amp,
                    "column_wave: the closed form is the modal series (error_max %.3g m)",
                    metric(m, "error_max"));
      /* (sampled every T / 435: the extremes are missed by g (dt / 2)^2 / 2 at most) */
      mpgm_test_rel(metric(m, "top_amplitude"), amp, 1e-4, "column_wave: the series spans 0 .. -amplitude");
    } else {
      mpgm_test_rel(metric(m, "error_max"), 1e-3, 1e-5, "column_wave: a history 1 mm off has error_max 1 mm");
      mpgm_test_rel(metric(m, "relative_error_max"), 1e-3 / amp, 1e-5,
                    "column_wave: relative_error_max = error_max / amplitude");
    }
    cJSON_Delete(m);
  }
}

/* ------------------------------------------------------------ through the loader */

static int write_text(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  if (!f) return 1;
  fputs(text, f);
  return fclose(f) != 0;
}

static const char *scene_text =
    "{\"method\": \"mpm\", \"mesh\": {\"h\": 0.05, \"cell\": \"tri\", \"domain\": {\"min\": [0, 0], \"max\": [4.2, 1.2]}},"
    " \"time\": {\"analysis\": \"dynamic\", \"dt\": 0.01, \"end\": 0.1},"
    " \"materials\": {\"steel\": {\"type\": \"neo_hookean\", \"density\": 7800, \"E\": 2e8, \"nu\": 0.3}},"
    " \"bodies\": [{\"material\": \"steel\", \"disk\": {\"centre\": [0.6, 0.5], \"radius\": 0.5}},"
    "  {\"material\": \"steel\", \"polygon\": {\"points\": [[3.0, 0.0], [3.0, 0.8], [3.4, 0.3], [3.8, 0.8], [3.8, 0.0]]}}],"
    " \"boundaries\": [{\"y\": 0, \"condition\": \"slip\"}, {\"x\": 4.2, \"condition\": \"stick\"}],"
    " \"probes\": {\"centre\": [0.6, 0.5], \"notch\": [3.4, 0.3]},"
    " \"reference\": {\"kind\": \"rolling_disk\", \"probe\": \"centre\"}}";

static void test_loader(const char *dir) {
  char path[512];
  snprintf(path, sizeof path, "%s/scene.json", dir);
  if (write_text(path, scene_text)) {
    mpgm_test(0, "write %s", path);
    return;
  }
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene *s = NULL;
  const int err = mpgm_scene_load(&ctx, path, 0, NULL, &s);
  mpgm_test(err == 0 && s, "loader: mpm scene with a disk and a polygon loads %s", ctx.msg);
  if (s) {
    const mpgm_scene_body *d = &s->bodies[0], *p = &s->bodies[1];
    mpgm_test(s->frontend == &mpgm_frontend_mpm && strcmp(s->frontend->name, "mpm") == 0,
              "loader: method mpm");
    mpgm_test(d->geometry == MPGM_GEOM_DISK && d->radius == 0.5 && d->centre[0] == 0.6,
              "loader: disk geometry");
    mpgm_test_rel(d->min[0], 0.1, TEST_TOL1, "loader: disk bbox min x");
    mpgm_test_rel(d->max[1], 1.0, TEST_TOL1, "loader: disk bbox max y");
    mpgm_test(p->geometry == MPGM_GEOM_POLYGON && p->npoints == 5 && p->min[0] == 3.0 &&
                  p->max[0] == 3.8 && p->min[1] == 0.0 && p->max[1] == 0.8,
              "loader: polygon geometry and bbox");
    mpgm_test(s->bcs[0].condition == MPGM_COND_SLIP && !s->bcs[0].fix[0] && s->bcs[0].fix[1],
              "loader: slip on y = 0 fixes y only");
    mpgm_test(s->bcs[1].condition == MPGM_COND_STICK && s->bcs[1].fix[0] && s->bcs[1].fix[1],
              "loader: stick fixes x and y");
    mpgm_test(s->reference.type == mpgm_reference_type_find("rolling_disk") && s->reference.probe == 0 &&
                  s->reference.param[0] == 60.0 && s->reference.param[1] == 9.81,
              "loader: rolling_disk reference with defaults incline_deg 60, g 9.81");
  }
  mpgm_scene_destroy(&s);
  /* the notch is outside the polygon: a probe there is rejected */
  const char *sets[] = {"probes={\"centre\": [0.6, 0.5], \"notch\": [3.4, 0.5]}"};
  mpgm_ctx_init(&ctx);
  mpgm_test(mpgm_scene_load(&ctx, path, 1, sets, &s) == MPGM_ERR_INPUT && strstr(ctx.msg, "probes.notch"),
            "loader: probe in the notch of a polygon is outside every body: %s", ctx.msg);
  mpgm_scene_destroy(&s);
  /* a probe in the disk's bounding box but off the disk is rejected */
  const char *sets2[] = {"probes={\"centre\": [0.15, 0.05]}"};
  mpgm_ctx_init(&ctx);
  mpgm_test(mpgm_scene_load(&ctx, path, 1, sets2, &s) == MPGM_ERR_INPUT && strstr(ctx.msg, "probes.centre"),
            "loader: probe in the disk's bbox corner is outside every body: %s", ctx.msg);
  mpgm_scene_destroy(&s);
  remove(path);
}

int main(void) {
  test_rectangle();
  test_disk();
  test_ring();
  rng r = {0x9E3779B97F4A7C15ULL};
  for (size_t k = 0; k < sizeof polys / sizeof polys[0]; k++)
    for (int rev = 0; rev < 2; rev++) test_polygon(&polys[k], rev, &r);
  test_polygon_check();
  test_meets_box();
  test_rolling_disk();
  test_probe_value();
  test_column_wave();
  char dir[] = "/tmp/mpgm_test_geometry_XXXXXX";
  if (mkdtemp(dir)) {
    test_loader(dir);
    rmdir(dir);
  } else {
    mpgm_test(0, "mkdtemp %s", dir);
  }
  return mpgm_test_summary();
}
