/* geometry.c -- body geometries of a scene: point-in-body test, bounding
 * box, area, perimeter and width, and the validation of polygons (simple,
 * with area).
 *
 * Written for both dimensions: a rectangle (3-D: a box) and a disk (a
 * ball) in MPGM_DIM loops; a polygon is a figure of the x-y plane, its
 * vertices (x, y) pairs, extruded over [z0, z1] in 3-D; rings are plane
 * only, cylinders solid only. The loops add in the order the plane-strain
 * code wrote out by hand, so 2-D results are unchanged to the bit. */
#include <math.h>
#include <stdio.h>

#include "mpgm_scene.h"

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

/* A cylinder's box: each end's circle reaches r sqrt(1 - e_d^2) from its
 * centre along axis d (e the unit axis). */
static void cylinder_bbox(const mpgm_scene_body *b, double min[MPGM_DIM], double max[MPGM_DIM]) {
  double L2 = 0.0;
  for (int d = 0; d < MPGM_DIM; d++) L2 += b->axis[d] * b->axis[d];
  for (int d = 0; d < MPGM_DIM; d++) {
    const double e2 = L2 > 0.0 ? b->axis[d] * b->axis[d] / L2 : 0.0;
    const double r = b->radius * sqrt(fmax(0.0, 1.0 - e2));
    const double a = b->centre[d], c = b->centre[d] + b->axis[d];
    min[d] = fmin(a, c) - r;
    max[d] = fmax(a, c) + r;
  }
}

void mpgm_body_bbox(const mpgm_scene_body *b, double min[MPGM_DIM], double max[MPGM_DIM]) {
  switch (b->geometry) {
  case MPGM_GEOM_RING:
    ring_bbox(b, min, max);
    return;
  case MPGM_GEOM_CYLINDER:
    cylinder_bbox(b, min, max);
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
    if (MPGM_DIM == 3) { /* the extrusion */
      min[MPGM_DIM - 1] = b->z[0];
      max[MPGM_DIM - 1] = b->z[1];
    }
    return;
  default: /* rectangle, box: its corners are the data */
    for (int d = 0; d < MPGM_DIM; d++) {
      min[d] = b->min[d];
      max[d] = b->max[d];
    }
  }
}

/* The sum of the bounding box's sides [m]: the size "on the boundary" is
 * relative to. */
static double box_size(const mpgm_scene_body *b) {
  double L = 0.0;
  for (int d = 0; d < MPGM_DIM; d++) L += b->max[d] - b->min[d];
  return L;
}

/* x inside the bounding box, within tol. */
static int in_box(const mpgm_scene_body *b, const double x[MPGM_DIM], double tol) {
  for (int d = 0; d < MPGM_DIM; d++)
    if (!(x[d] >= b->min[d] - tol && x[d] <= b->max[d] + tol)) return 0;
  return 1;
}

/* A cylinder: the position along the axis within [0, L], the distance from
 * it within the radius, both within 1e-12 of the diameter plus length. */
static int cylinder_contains(const mpgm_scene_body *b, const double x[MPGM_DIM]) {
  double L2 = 0.0, t = 0.0, w2 = 0.0;
  for (int d = 0; d < MPGM_DIM; d++) {
    L2 += b->axis[d] * b->axis[d];
    t += (x[d] - b->centre[d]) * b->axis[d];
  }
  const double L = sqrt(L2), tol = GEOM_REL_TOL * (2.0 * b->radius + L);
  t = L > 0.0 ? t / L : 0.0; /* distance along the axis */
  if (t < -tol || t > L + tol) return 0;
  for (int d = 0; d < MPGM_DIM; d++) {
    const double w = x[d] - b->centre[d] - t * b->axis[d] / L;
    w2 += w * w;
  }
  const double r = b->radius + tol;
  return w2 <= r * r;
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
    double r2 = 0.0;
    for (int d = 0; d < MPGM_DIM; d++) {
      const double dx = x[d] - b->centre[d];
      r2 += dx * dx;
    }
    return r2 <= r * r;
  }
  case MPGM_GEOM_CYLINDER: return cylinder_contains(b, x);
  case MPGM_GEOM_POLYGON: {
    /* 2-D: the polygon's tolerance is of its width + height, in 3-D too
     * (the crossing test sees the plane figure only) */
    const double tol = GEOM_REL_TOL * (b->max[0] - b->min[0] + b->max[1] - b->min[1]);
    if (!in_box(b, x, tol)) return 0;
    return polygon_contains(b, x, tol);
  }
  default: return in_box(b, x, GEOM_REL_TOL * box_size(b));
  }
}

/* ------------------------------------------------------------- measures */

/* The length of a cylinder's axis [m]. */
static double axis_length(const mpgm_scene_body *b) {
  double L2 = 0.0;
  for (int d = 0; d < MPGM_DIM; d++) L2 += b->axis[d] * b->axis[d];
  return sqrt(L2);
}

/* The extrusion of a 3-D polygon [m]; 1 in 2-D (a measure per unit
 * thickness is the plane one). */
static double depth(const mpgm_scene_body *b) {
  return MPGM_DIM == 3 ? b->z[1] - b->z[0] : 1.0;
}

double mpgm_body_area(const mpgm_scene_body *b) {
  const double r = b->radius;
  switch (b->geometry) {
  case MPGM_GEOM_DISK: return MPGM_DIM == 2 ? GEOM_PI * r * r : 4.0 / 3.0 * GEOM_PI * r * r * r;
  case MPGM_GEOM_RING:
    return 0.5 * (b->angle[1] - b->angle[0]) * (b->radius * b->radius - b->radius_in * b->radius_in);
  case MPGM_GEOM_CYLINDER: return GEOM_PI * r * r * axis_length(b);
  case MPGM_GEOM_POLYGON: return fabs(mpgm_polygon_area(b->points, b->npoints)) * depth(b);
  default: {
    double v = b->max[0] - b->min[0];
    for (int d = 1; d < MPGM_DIM; d++) v *= b->max[d] - b->min[d];
    return v;
  }
  }
}

double mpgm_body_width(const mpgm_scene_body *b) {
  if (b->geometry == MPGM_GEOM_DISK) return 2.0 * b->radius;
  if (b->geometry == MPGM_GEOM_RING) return b->radius - b->radius_in;
  if (b->geometry == MPGM_GEOM_CYLINDER) return fmin(2.0 * b->radius, axis_length(b));
  double w = b->max[0] - b->min[0];
  for (int d = 1; d < MPGM_DIM; d++) w = fmin(w, b->max[d] - b->min[d]);
  return w;
}

/* A polygon's perimeter [m]. */
static double polygon_perimeter(const mpgm_scene_body *b) {
  double p = 0.0;
  for (int i = 0; i < b->npoints; i++) {
    const int j = (i + 1) % b->npoints;
    p += hypot(b->points[2 * j] - b->points[2 * i], b->points[2 * j + 1] - b->points[2 * i + 1]);
  }
  return p;
}

double mpgm_body_perimeter(const mpgm_scene_body *b) {
  const double r = b->radius;
  switch (b->geometry) {
  case MPGM_GEOM_DISK: return MPGM_DIM == 2 ? 2.0 * GEOM_PI * r : 4.0 * GEOM_PI * r * r;
  case MPGM_GEOM_RING: {
    const double a = b->angle[1] - b->angle[0];
    return a * (b->radius + b->radius_in) + (a < 2.0 * GEOM_PI ? 2.0 * (b->radius - b->radius_in) : 0.0);
  }
  case MPGM_GEOM_CYLINDER: return 2.0 * GEOM_PI * r * (axis_length(b) + r);
  case MPGM_GEOM_POLYGON:
    if (MPGM_DIM == 2) return polygon_perimeter(b);
    return polygon_perimeter(b) * depth(b) + 2.0 * fabs(mpgm_polygon_area(b->points, b->npoints));
  default: {
    double w[MPGM_DIM];
    for (int d = 0; d < MPGM_DIM; d++) w[d] = b->max[d] - b->min[d];
    if (MPGM_DIM == 2) return 2.0 * (w[0] + w[1]);
    return 2.0 * (w[0] * w[1] + w[1] * w[MPGM_DIM - 1] + w[0] * w[MPGM_DIM - 1]);
  }
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
  for (int d = 0; d < MPGM_DIM; d++)
    if (lo[d] > b->max[d] || hi[d] < b->min[d]) return 0;
  if (b->geometry == MPGM_GEOM_DISK) { /* the box's point nearest the centre */
    double r2 = 0.0;
    for (int d = 0; d < MPGM_DIM; d++) {
      const double dx = fmin(fmax(b->centre[d], lo[d]), hi[d]) - b->centre[d];
      r2 += dx * dx;
    }
    const double r = b->radius * (1.0 + 2.0 * GEOM_REL_TOL);
    return r2 <= r * r;
  }
  if (b->geometry != MPGM_GEOM_POLYGON) return 1; /* boxes overlap (the cylinder too) */
  /* a polygon (3-D: its prism, whose z range the boxes' overlap settled) */
  const double *p = b->points;
  const int n = b->npoints;
  for (int i = 0; i < n; i++)
    if (p[2 * i] >= lo[0] && p[2 * i] <= hi[0] && p[2 * i + 1] >= lo[1] && p[2 * i + 1] <= hi[1]) return 1;
  /* the box's corners in the plane (3-D: at a z both the box and the prism
   * hold) */
  double corner[4][MPGM_DIM] = {{lo[0], lo[1]}, {hi[0], lo[1]}, {hi[0], hi[1]}, {lo[0], hi[1]}};
  for (int k = 0; k < 4 && MPGM_DIM == 3; k++) corner[k][MPGM_DIM - 1] = fmax(lo[MPGM_DIM - 1], b->min[MPGM_DIM - 1]);
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
