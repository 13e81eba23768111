/* geometry.c -- body geometries of a scene: point-in-body test, bounding
 * box, area, perimeter and width, and the validation of polygons (simple,
 * with area).
 *
 * 2-D only: the bodies are disks, rectangles and polygons of the plane,
 * written out in x and y (polygon vertices are (x, y) pairs); 3-D adds
 * solids of its own here. */
#include <math.h>
#include <stdio.h>

#include "mpgm_scene.h"

#if MPGM_DIM != 2
#error "core/geometry.c is written for plane strain only (MPGM_DIM = 2)"
#endif

/* Relative tolerance of "on the boundary" (of the body's size). */
#define GEOM_REL_TOL 1e-12
#define GEOM_PI 3.14159265358979323846

/* A ring sector's box: its four corners and the outer circle's points at
 * the axes' angles inside the sector. */
static void ring_bbox(const mpgm_scene_body *b, double min[MPGM_DIM], double max[MPGM_DIM]) {
  const double a0 = b->angle[0], a1 = b->angle[1], r[2] = {b->radius_in, b->radius};
  min[0] = min[1] = INFINITY;
  max[0] = max[1] = -INFINITY;
  for (int k = 0; k < 2; k++)
    for (int i = 0; i < 2; i++) {
      const double a = i ? a1 : a0, x = b->centre[0] + r[k] * cos(a), y = b->centre[1] + r[k] * sin(a);
      min[0] = fmin(min[0], x), max[0] = fmax(max[0], x);
      min[1] = fmin(min[1], y), max[1] = fmax(max[1], y);
    }
  const double q = 0.5 * GEOM_PI;
  for (double a = ceil(a0 / q) * q; a <= a1; a += q) {
    const double x = b->centre[0] + b->radius * cos(a), y = b->centre[1] + b->radius * sin(a);
    min[0] = fmin(min[0], x), max[0] = fmax(max[0], x);
    min[1] = fmin(min[1], y), max[1] = fmax(max[1], y);
  }
}

void mpgm_body_bbox(const mpgm_scene_body *b, double min[MPGM_DIM], double max[MPGM_DIM]) {
  switch (b->geometry) {
  case MPGM_GEOM_RING:
    ring_bbox(b, min, max);
    return;
  case MPGM_GEOM_DISK:
    for (int d = 0; d < MPGM_DIM; d++) {
      min[d] = b->centre[d] - b->radius;
      max[d] = b->centre[d] + b->radius;
    }
    return;
  case MPGM_GEOM_POLYGON:
    min[0] = max[0] = b->points[0];
    min[1] = max[1] = b->points[1];
    for (int i = 1; i < b->npoints; i++)
      for (int d = 0; d < 2; d++) {
        min[d] = fmin(min[d], b->points[2 * i + d]);
        max[d] = fmax(max[d], b->points[2 * i + d]);
      }
    return;
  default: /* rectangle: its corners are the data */
    min[0] = b->min[0];
    min[1] = b->min[1];
    max[0] = b->max[0];
    max[1] = b->max[1];
  }
}

/* Crossing number with the half-open rule (an edge counts when exactly one
 * of its ends lies strictly above the horizontal through x, so a ray
 * through a vertex counts once), after a distance test against every edge
 * whose box holds x: points on an edge or vertex are inside. */
static int polygon_contains(const mpgm_scene_body *b, const double x[MPGM_DIM], double tol) {
  const double *p = b->points;
  const int n = b->npoints;
  const double tol2 = tol * tol;
  int inside = 0;
  for (int i = 0, j = n - 1; i < n; j = i++) {
    const double ax = p[2 * j], ay = p[2 * j + 1], cx = p[2 * i], cy = p[2 * i + 1];
    const double ex = cx - ax, ey = cy - ay;
    if (x[0] >= fmin(ax, cx) - tol && x[0] <= fmax(ax, cx) + tol && x[1] >= fmin(ay, cy) - tol &&
        x[1] <= fmax(ay, cy) + tol) {
      const double wx = x[0] - ax, wy = x[1] - ay, l2 = ex * ex + ey * ey;
      double t = l2 > 0.0 ? (wx * ex + wy * ey) / l2 : 0.0;
      t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
      const double dx = wx - t * ex, dy = wy - t * ey;
      if (dx * dx + dy * dy <= tol2) return 1;
    }
    if ((ay > x[1]) != (cy > x[1])) { /* ey != 0 here */
      const double xi = ax + (x[1] - ay) * ex / ey;
      if (x[0] < xi) inside = !inside;
    }
  }
  return inside;
}

int mpgm_body_contains(const mpgm_scene_body *b, const double x[MPGM_DIM]) {
  switch (b->geometry) {
  case MPGM_GEOM_RING: { /* the radii, then the angle from angle[0] */
    const double dx = x[0] - b->centre[0], dy = x[1] - b->centre[1], r = hypot(dx, dy);
    const double tol = GEOM_REL_TOL * b->radius * 2.0;
    if (r < b->radius_in - tol || r > b->radius + tol) return 0;
    if (b->angle[1] - b->angle[0] >= 2.0 * GEOM_PI) return 1;
    double a = atan2(dy, dx) - b->angle[0];
    a -= 2.0 * GEOM_PI * floor(a / (2.0 * GEOM_PI));
    const double span = b->angle[1] - b->angle[0], atol = r > 0.0 ? tol / r : 0.0;
    return a <= span + atol || a >= 2.0 * GEOM_PI - atol;
  }
  case MPGM_GEOM_DISK: {
    const double r = b->radius * (1.0 + 2.0 * GEOM_REL_TOL);
    const double dx = x[0] - b->centre[0], dy = x[1] - b->centre[1];
    return dx * dx + dy * dy <= r * r;
  }
  case MPGM_GEOM_POLYGON: {
    const double tol = GEOM_REL_TOL * (b->max[0] - b->min[0] + b->max[1] - b->min[1]);
    if (x[0] < b->min[0] - tol || x[0] > b->max[0] + tol || x[1] < b->min[1] - tol ||
        x[1] > b->max[1] + tol)
      return 0;
    return polygon_contains(b, x, tol);
  }
  default: {
    const double tol = GEOM_REL_TOL * (b->max[0] - b->min[0] + b->max[1] - b->min[1]);
    return x[0] >= b->min[0] - tol && x[0] <= b->max[0] + tol && x[1] >= b->min[1] - tol &&
           x[1] <= b->max[1] + tol;
  }
  }
}

/* ------------------------------------------------------------- measures */

double mpgm_body_area(const mpgm_scene_body *b) {
  switch (b->geometry) {
  case MPGM_GEOM_DISK: return GEOM_PI * b->radius * b->radius;
  case MPGM_GEOM_RING:
    return 0.5 * (b->angle[1] - b->angle[0]) * (b->radius * b->radius - b->radius_in * b->radius_in);
  case MPGM_GEOM_POLYGON: return fabs(mpgm_polygon_area(b->points, b->npoints));
  default: return (b->max[0] - b->min[0]) * (b->max[1] - b->min[1]);
  }
}

double mpgm_body_width(const mpgm_scene_body *b) {
  if (b->geometry == MPGM_GEOM_DISK) return 2.0 * b->radius;
  if (b->geometry == MPGM_GEOM_RING) return b->radius - b->radius_in;
  return fmin(b->max[0] - b->min[0], b->max[1] - b->min[1]);
}

double mpgm_body_perimeter(const mpgm_scene_body *b) {
  switch (b->geometry) {
  case MPGM_GEOM_DISK: return 2.0 * GEOM_PI * b->radius;
  case MPGM_GEOM_RING: {
    const double a = b->angle[1] - b->angle[0];
    return a * (b->radius + b->radius_in) + (a < 2.0 * GEOM_PI ? 2.0 * (b->radius - b->radius_in) : 0.0);
  }
  case MPGM_GEOM_POLYGON: {
    double p = 0.0;
    for (int i = 0; i < b->npoints; i++) {
      const int j = (i + 1) % b->npoints;
      p += hypot(b->points[2 * j] - b->points[2 * i], b->points[2 * j + 1] - b->points[2 * i + 1]);
    }
    return p;
  }
  default: return 2.0 * (b->max[0] - b->min[0] + b->max[1] - b->min[1]);
  }
}

/* ---------------------------------------------------------------- validation */

/* (b - a) x (c - a): > 0 when a, b, c turn left. */
static double orient(const double *a, const double *b, const double *c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* r, collinear with p-q, lies on the closed segment p-q (within tol). */
static int on_segment(const double *p, const double *q, const double *r, double tol) {
  return r[0] >= fmin(p[0], q[0]) - tol && r[0] <= fmax(p[0], q[0]) + tol &&
         r[1] >= fmin(p[1], q[1]) - tol && r[1] <= fmax(p[1], q[1]) + tol;
}

/* Closed segments a-b and c-d meet (cross, touch or overlap). eps: tolerance
 * of the orientation tests [m^2], tol: of the coordinates [m]. */
static int segments_meet(const double *a, const double *b, const double *c, const double *d,
                         double eps, double tol) {
  const double d1 = orient(c, d, a), d2 = orient(c, d, b);
  const double d3 = orient(a, b, c), d4 = orient(a, b, d);
  if (((d1 > eps && d2 < -eps) || (d1 < -eps && d2 > eps)) &&
      ((d3 > eps && d4 < -eps) || (d3 < -eps && d4 > eps)))
    return 1;
  return (fabs(d1) <= eps && on_segment(c, d, a, tol)) || (fabs(d2) <= eps && on_segment(c, d, b, tol)) ||
         (fabs(d3) <= eps && on_segment(a, b, c, tol)) || (fabs(d4) <= eps && on_segment(a, b, d, tol));
}

int mpgm_body_meets_box(const mpgm_scene_body *b, const double lo[MPGM_DIM],
                        const double hi[MPGM_DIM]) {
  if (lo[0] > b->max[0] || hi[0] < b->min[0] || lo[1] > b->max[1] || hi[1] < b->min[1]) return 0;
  if (b->geometry == MPGM_GEOM_DISK) {
    const double cx = fmin(fmax(b->centre[0], lo[0]), hi[0]), cy = fmin(fmax(b->centre[1], lo[1]), hi[1]);
    const double dx = cx - b->centre[0], dy = cy - b->centre[1];
    const double r = b->radius * (1.0 + 2.0 * GEOM_REL_TOL);
    return dx * dx + dy * dy <= r * r;
  }
  if (b->geometry != MPGM_GEOM_POLYGON) return 1; /* boxes overlap */
  const double *p = b->points;
  const int n = b->npoints;
  for (int i = 0; i < n; i++)
    if (p[2 * i] >= lo[0] && p[2 * i] <= hi[0] && p[2 * i + 1] >= lo[1] && p[2 * i + 1] <= hi[1]) return 1;
  const double corner[4][2] = {{lo[0], lo[1]}, {hi[0], lo[1]}, {hi[0], hi[1]}, {lo[0], hi[1]}};
  for (int k = 0; k < 4; k++)
    if (mpgm_body_contains(b, corner[k])) return 1;
  const double L = b->max[0] - b->min[0] + b->max[1] - b->min[1];
  for (int i = 0, j = n - 1; i < n; j = i++)
    for (int k = 0; k < 4; k++)
      if (segments_meet(p + 2 * j, p + 2 * i, corner[k], corner[(k + 1) % 4], GEOM_REL_TOL * L * L,
                        GEOM_REL_TOL * L))
        return 1;
  return 0;
}

double mpgm_polygon_area(const double *p, int n) {
  double a = 0.0;
  for (int i = 0, j = n - 1; i < n; j = i++) a += p[2 * j] * p[2 * i + 1] - p[2 * i] * p[2 * j + 1];
  return 0.5 * a;
}

int mpgm_polygon_check(const double *p, int n, char *msg, size_t len) {
  if (n < 3) {
    snprintf(msg, len, "expected at least 3 points [x, y], found %d", n);
    return 1;
  }
  if (n > MPGM_POLYGON_MAX) {
    snprintf(msg, len, "expected at most %d points, found %d", MPGM_POLYGON_MAX, n);
    return 1;
  }
  double lo[2] = {p[0], p[1]}, hi[2] = {p[0], p[1]};
  for (int i = 1; i < n; i++)
    for (int d = 0; d < 2; d++) {
      lo[d] = fmin(lo[d], p[2 * i + d]);
      hi[d] = fmax(hi[d], p[2 * i + d]);
    }
  const double L = hi[0] - lo[0] + hi[1] - lo[1];
  const double tol = GEOM_REL_TOL * L, eps = GEOM_REL_TOL * L * L;
  for (int i = 0, j = n - 1; i < n; j = i++)
    if (fabs(p[2 * i] - p[2 * j]) <= tol && fabs(p[2 * i + 1] - p[2 * j + 1]) <= tol) {
      snprintf(msg, len, "expected distinct consecutive points, found points %d and %d at (%g, %g)%s",
               j < i ? j : i, j < i ? i : j, p[2 * i], p[2 * i + 1],
               (i == 0 && n > 1) ? " (the polygon closes itself: do not repeat the first point)" : "");
      return 1;
    }
  const double area = mpgm_polygon_area(p, n);
  if (!(fabs(area) > eps)) {
    snprintf(msg, len, "expected a polygon with area, found area %g (points on one line?)", area);
    return 1;
  }
  /* edge i joins points i and i+1 (mod n) */
  for (int i = 0; i < n; i++) {
    const double *a = p + 2 * i, *b = p + 2 * ((i + 1) % n);
    for (int j = i + 1; j < n; j++) {
      const double *c = p + 2 * j, *d = p + 2 * ((j + 1) % n);
      int bad;
      if (j == i + 1) /* share b = c: bad if d folds back along a-b */
        bad = fabs(orient(a, b, d)) <= eps && (a[0] - b[0]) * (d[0] - b[0]) + (a[1] - b[1]) * (d[1] - b[1]) > 0;
      else if (i == 0 && j == n - 1) /* share a = d: bad if c folds back along a-b */
        bad = fabs(orient(a, b, c)) <= eps && (b[0] - a[0]) * (c[0] - a[0]) + (b[1] - a[1]) * (c[1] - a[1]) > 0;
      else
        bad = segments_meet(a, b, c, d, eps, tol);
      if (bad) {
        snprintf(msg, len, "expected a simple polygon, found self-intersecting edges %d-%d and %d-%d "
                 "(edge k joins points k and k+1)", i, (i + 1) % n, j, (j + 1) % n);
        return 1;
      }
    }
  }
  return 0;
}
