/* surface.c -- points on the bodies' boundaries: the surface tracers of
 * contact at points (core/contact_points.c), made in one place for every
 * front end. */
#include <math.h>
#include <string.h>

#include "mpgm_discretisation.h"

/* The bodies' surface points are plane figures' (contact at surface points
 * in 3-D comes with the 3-D meshfree methods); carrying tracers with their
 * nearest material point is written for both dimensions. */
#if MPGM_DIM == 2
static const double PI = 3.14159265358979323846;

/* A circle and the edges of polygons (vertices: (x, y) pairs), written out
 * in x and y. */
int mpgm_body_surface(const mpgm_scene_body *b, double spacing, double *x) {
  int n = 0;
  if (b->geometry == MPGM_GEOM_DISK) {
    const double c = 2.0 * PI * b->radius;
    n = (int)ceil(c / spacing);
    if (n < 8) n = 8;
    for (int k = 0; k < n && x; k++) {
      const double th = -0.5 * PI + 2.0 * PI * k / n;
      x[MPGM_DIM * k] = b->centre[0] + b->radius * cos(th);
      x[MPGM_DIM * k + 1] = b->centre[1] + b->radius * sin(th);
    }
    /* the lowest point exactly: a disk resting on a floor touches it */
    if (x) x[1] = b->centre[1] - b->radius;
    return n;
  }
  double v[2 * MPGM_POLYGON_MAX];
  int nv;
  if (b->geometry == MPGM_GEOM_RECTANGLE) {
    const double r[8] = {b->min[0], b->min[1], b->max[0], b->min[1],
                         b->max[0], b->max[1], b->min[0], b->max[1]};
    memcpy(v, r, sizeof r);
    nv = 4;
  } else {
    nv = b->npoints;
    memcpy(v, b->points, sizeof(double) * 2 * (size_t)nv);
  }
  for (int e = 0; e < nv; e++) {
    const double *a = v + 2 * e, *q = v + 2 * ((e + 1) % nv);
    const int m = (int)fmax(1.0, ceil(hypot(q[0] - a[0], q[1] - a[1]) / spacing));
    for (int k = 0; k < m; k++, n++)
      if (x) {
        const double t = (double)k / m;
        x[MPGM_DIM * n] = a[0] + t * (q[0] - a[0]);
        x[MPGM_DIM * n + 1] = a[1] + t * (q[1] - a[1]);
      }
  }
  return n;
}
#endif

/* Spacing of the surface points: the smallest of the contact boundaries
 * enforced at points. */
static double surface_spacing(const mpgm_scene *s) {
  double spacing = INFINITY;
  for (int i = 0; i < s->nbc; i++)
    if (mpgm_bc_at_points(&s->bcs[i])) spacing = fmin(spacing, s->bcs[i].spacing);
  return spacing;
}

int mpgm_surface_tracers_count(const mpgm_scene *s) { return mpgm_surface_tracers_xy(s, NULL); }

int mpgm_surface_tracers_xy(const mpgm_scene *s, double *x) {
  const double spacing = surface_spacing(s);
  int n = 0;
#if MPGM_DIM == 2
  for (int b = 0; b < s->nbody && isfinite(spacing); b++)
    n += mpgm_body_surface(&s->bodies[b], spacing, x ? x + MPGM_DIM * n : NULL);
#else /* none: a 3-D scene has no contact at points (refused when it loads) */
  (void)x;
  (void)spacing;
#endif
  return n;
}

void mpgm_surface_tracers_fill(mpgm_points *P, const mpgm_scene *s) {
  const double spacing = surface_spacing(s);
#if MPGM_DIM == 2
  for (int b = 0, p = P->n + P->nprobe; b < s->nbody && P->nsurf; b++) {
    const int k = mpgm_body_surface(&s->bodies[b], spacing, P->x + MPGM_DIM * p);
    for (int q = p; q < p + k; q++) {
      memcpy(P->x0 + MPGM_DIM * q, P->x + MPGM_DIM * q, sizeof(double) * MPGM_DIM);
      P->body[q] = b;
      memcpy(P->v + MPGM_DIM * q, s->bodies[b].velocity, sizeof(double) * MPGM_DIM);
    }
    p += k;
  }
#else
  (void)P;
  (void)spacing;
#endif
}

/* The nearest material point to x (ties: the lowest index). */
static int nearest_point(const mpgm_points *P, const double *x) {
  int best = 0;
  double dmin = INFINITY;
  for (int q = 0; q < P->n; q++) {
    double d2 = 0.0;
    for (int d = 0; d < MPGM_DIM; d++) {
      const double e = P->x[MPGM_DIM * q + d] - x[d];
      d2 += e * e;
    }
    if (d2 < dmin) {
      dmin = d2;
      best = q;
    }
  }
  return best;
}

/* Tracer p (of the first at `first`) has no functions and is carried. */
static int carried(const mpgm_conn *c, int first, int p, const unsigned char *skip) {
  return p >= first && c->ptr[p + 1] == c->ptr[p] && !(skip && skip[p - first]);
}

int mpgm_tracers_carry(const mpgm_fe_view *v, mpgm_conn *c, mpgm_conn *scratch,
                       const unsigned char *skip) {
  const mpgm_points *P = v->pts;
  const int first = P->n, m = first + P->nprobe + P->nsurf;
  int nempty = 0;
  for (int p = first; p < m; p++) nempty += carried(c, first, p, skip);
  if (!nempty || P->n == 0) return 0;
  /* the new lists: a carried tracer's are its nearest point's */
  int nnz = 0;
  for (int p = 0; p < m; p++) {
    const int q = carried(c, first, p, skip) ? nearest_point(P, P->x + MPGM_DIM * p) : p;
    nnz += c->ptr[q + 1] - c->ptr[q];
  }
  MPGM_CALL(mpgm_conn_reserve(v->ctx, scratch, m, 0));
  MPGM_CALL(mpgm_conn_grow(v->ctx, scratch, 0, nnz));
  int k = 0;
  for (int p = 0; p < m; p++) {
    int q = p;
    if (carried(c, first, p, skip)) {
      q = nearest_point(P, P->x + MPGM_DIM * p);
      mpgm_count(v->ctx, p < P->n + P->nprobe ? MPGM_C_PROBES_CARRIED : MPGM_C_SURFACE_CARRIED, 1);
    }
    scratch->ptr[p] = k;
    for (int e = c->ptr[q]; e < c->ptr[q + 1]; e++, k++) {
      scratch->node[k] = c->node[e];
      scratch->N[k] = c->N[e];
      for (int d = 0; d < MPGM_DIM; d++) scratch->dN[MPGM_DIM * k + d] = c->dN[MPGM_DIM * e + d];
    }
  }
  scratch->ptr[m] = k;
  /* the lists change places; the versions stay the caller's */
  mpgm_conn t = *c;
  c->ptr = scratch->ptr, c->node = scratch->node, c->N = scratch->N, c->dN = scratch->dN;
  c->g = scratch->g, c->cap = scratch->cap, c->pcap = scratch->pcap, c->np = m;
  scratch->ptr = t.ptr, scratch->node = t.node, scratch->N = t.N, scratch->dN = t.dN;
  scratch->g = t.g, scratch->cap = t.cap, scratch->pcap = t.pcap, scratch->np = t.np;
  return 0;
}
