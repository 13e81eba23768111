/* fill.c -- the material points of bodies filled on a grid: the rule of
 * the particles of a grid-reset front end and the points of a persistent
 * one's grid-filled bodies. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_discretisation.h"
#include "mpgm_grid.h"

/* Written for both dimensions; the ring bodies (polar sectors) are plane
 * only. */

int mpgm_points_rule(const mpgm_scene *s, int cell, double *xi, double *w) {
  if (s->layout_centres && (cell == MPGM_CELL_Q4 || cell == MPGM_CELL_H8))
    return mpgm_fe_centres(s->ppc, xi, w);
  return mpgm_fe_gauss(cell, s->ppc, xi, w);
}

int mpgm_bodies_fill(const mpgm_scene *s, int cell, int ncell,
                     void (*xy)(const void *grid, int c, double *xn), const void *grid,
                     int *owner, double *x, int *count) {
  double gxi[MPGM_DIM * MPGM_MAXRULE], gw[MPGM_MAXRULE];
  *count = 0;
  if (mpgm_points_rule(s, cell, gxi, gw)) return MPGM_ERR_INPUT;
  const int nn = mpgm_fe_nnode(cell);
  double N[MPGM_FE_MAXNODE * MPGM_MAXRULE];
  for (int q = 0; q < s->ppc; q++) mpgm_fe_ref(cell, gxi + MPGM_DIM * q, N + nn * q, NULL);
  int n = 0;
  for (int c = 0; c < ncell; c++) {
    double xn[MPGM_DIM * MPGM_FE_MAXNODE];
    xy(grid, c, xn);
    for (int q = 0; q < s->ppc; q++) {
      double p[MPGM_DIM] = {0};
      for (int a = 0; a < nn; a++)
        for (int d = 0; d < MPGM_DIM; d++) p[d] += N[nn * q + a] * xn[MPGM_DIM * a + d];
      int b = 0; /* rings are filled in polar sectors (ring_fill) */
      while (b < s->nbody &&
             (s->bodies[b].geometry == MPGM_GEOM_RING || !mpgm_body_contains(&s->bodies[b], p)))
        b++;
      const size_t k = (size_t)c * s->ppc + q;
      if (owner) owner[k] = b < s->nbody ? b : -1;
      if (x) memcpy(x + MPGM_DIM * k, p, sizeof p);
      n += b < s->nbody;
    }
  }
  *count = n;
  return 0;
}

/* Grid cell coordinates for mpgm_bodies_fill. */
static void grid_cell_xy(const void *grid, int c, double *xn) {
  int nodes[MPGM_FE_MAXNODE];
  mpgm_grid_cell(grid, c, nodes, xn);
}

#if MPGM_DIM == 2
/* The polar sectors of a ring body: nr layers of nt sectors, about sqrt(ppc)
 * points per cell length in each direction; with x (MPGM_DIM per point),
 * vol and r0 (the sector's radial and tangential half-axes) when not
 * NULL. Returns the count. */
static int ring_sectors(const mpgm_scene_body *b, double h, int ppc, double *x, double *vol, double *r0) {
  const double n = sqrt((double)ppc), ri = b->radius_in, ro = b->radius;
  const double span = b->angle[1] - b->angle[0];
  const int nr = (int)fmax(1.0, round((ro - ri) * n / h));
  const int nt = (int)fmax(1.0, round(span * 0.5 * (ri + ro) * n / h));
  const double dr = (ro - ri) / nr, dt = span / nt;
  for (int i = 0, k = 0; i < nr && x; i++)
    for (int j = 0; j < nt; j++, k++) { /* 2-D only: x, y written out */
      const double r = ri + (i + 0.5) * dr, t = b->angle[0] + (j + 0.5) * dt, c = cos(t), s = sin(t);
      x[MPGM_DIM * k] = b->centre[0] + r * c;
      x[MPGM_DIM * k + 1] = b->centre[1] + r * s;
      vol[k] = r * dr * dt; /* the sector's area, (ro^2 - ri^2) dt / 2 */
      const double ax[4] = {0.5 * dr * c, 0.5 * dr * s, -0.5 * r * dt * s, 0.5 * r * dt * c};
      memcpy(r0 + 4 * k, ax, sizeof ax);
    }
  return nr * nt;
}

/* The points of the ring bodies after the grid's. */
static int ring_fill(mpgm_ctx *ctx, const mpgm_grid *g, const mpgm_scene *s, mpgm_fill *f) {
  for (int b = 0; b < s->nbody; b++)
    if (s->bodies[b].geometry == MPGM_GEOM_RING)
      f->nring += ring_sectors(&s->bodies[b], g->h, s->ppc, NULL, NULL, NULL);
  if (!f->nring) return 0;
  f->rowner = malloc(sizeof(int) * (size_t)f->nring);
  f->rx = malloc(sizeof(double) * MPGM_DIM * (size_t)f->nring);
  f->rvol = malloc(sizeof(double) * (size_t)f->nring);
  f->rr0 = malloc(sizeof(double) * 4 * (size_t)f->nring);
  MPGM_CHECK(ctx, f->rowner && f->rx && f->rvol && f->rr0, MPGM_ERR_NOMEM,
             "out of memory (%d points of ring bodies)", f->nring);
  for (int b = 0, k = 0; b < s->nbody; b++) {
    if (s->bodies[b].geometry != MPGM_GEOM_RING) continue;
    const int n = ring_sectors(&s->bodies[b], g->h, s->ppc, f->rx + MPGM_DIM * k, f->rvol + k, f->rr0 + 4 * k);
    for (int q = 0; q < n; q++) f->rowner[k + q] = b;
    k += n;
  }
  f->count += f->nring;
  return 0;
}
#else
/* Rings are plane figures: a 3-D scene has none (the loader refuses them). */
static int ring_fill(mpgm_ctx *ctx, const mpgm_grid *g, const mpgm_scene *s, mpgm_fill *f) {
  (void)g;
  (void)f;
  for (int b = 0; b < s->nbody; b++)
    MPGM_CHECK(ctx, s->bodies[b].geometry != MPGM_GEOM_RING, MPGM_ERR_INTERNAL,
               "%s: bodies.%d: a ring in a 3-D scene", s->file, b);
  return 0;
}
#endif

int mpgm_grid_fill(mpgm_ctx *ctx, const mpgm_grid *g, const mpgm_scene *s, mpgm_fill *f) {
  memset(f, 0, sizeof *f);
  double gxi[MPGM_DIM * MPGM_MAXRULE], gw[MPGM_MAXRULE];
  MPGM_CHECK(ctx, mpgm_points_rule(s, g->cell, gxi, gw) == 0, MPGM_ERR_INPUT,
             "%s: mesh.ppc: no Gauss rule of %d points", s->file, s->ppc);
  /* a point's volume: cell measure x Gauss weight / reference measure (2-D:
   * areas of Q4 and T3 cells, per unit thickness; 3-D: H8 cubes) */
#if MPGM_DIM == 2
  const double ref_area = g->cell == MPGM_CELL_Q4 ? 4.0 : 0.5;
  const double cell_area = g->h * g->h / (g->cell == MPGM_CELL_Q4 ? 1.0 : 2.0);
#else
  const double ref_area = 8.0, cell_area = g->h * g->h * g->h;
#endif
  for (int q = 0; q < s->ppc; q++) f->vol[q] = cell_area * gw[q] / ref_area;
  f->ppc = s->ppc;
  f->ngauss = (size_t)g->ncell * (size_t)s->ppc;
  f->owner = malloc(sizeof(int) * f->ngauss);
  f->x = malloc(sizeof(double) * MPGM_DIM * f->ngauss);
  MPGM_CHECK(ctx, f->owner && f->x, MPGM_ERR_NOMEM, "out of memory (%zu grid Gauss points)", f->ngauss);
  MPGM_CALL(mpgm_bodies_fill(s, g->cell, g->ncell, grid_cell_xy, g, f->owner, f->x, &f->count));
  MPGM_CALL(ring_fill(ctx, g, s, f));
  MPGM_CHECK(ctx, f->count > 0, MPGM_ERR_INPUT,
             "%s: bodies: no grid Gauss point lies inside any body (h = %g, ppc = %d): expected "
             "bodies larger than a grid cell", s->file, g->h, s->ppc);
  return 0;
}

void mpgm_fill_points(const mpgm_fill *f, const mpgm_scene *s, mpgm_points *P) {
  int p = 0;
  for (size_t k = 0; k < f->ngauss; k++) {
    const int b = f->owner[k];
    if (b < 0) continue;
    mpgm_point_set(P, p++, s, b, f->x + MPGM_DIM * k, f->vol[k % (size_t)f->ppc]);
  }
  for (int k = 0; k < f->nring; k++, p++) { /* the polar sectors: their own domains */
    mpgm_point_set(P, p, s, f->rowner[k], f->rx + MPGM_DIM * k, f->rvol[k]);
    memcpy(P->r0 + MPGM_TENSOR * (size_t)p, f->rr0 + MPGM_TENSOR * (size_t)k, sizeof(double) * MPGM_TENSOR);
  }
}

void mpgm_fill_free(mpgm_fill *f) {
  free(f->owner);
  free(f->x);
  free(f->rowner);
  free(f->rx);
  free(f->rvol);
  free(f->rr0);
  memset(f, 0, sizeof *f);
}

int mpgm_scene_nstate(const mpgm_scene *s) {
  int nstate = 0;
  for (int i = 0; i < s->nmat; i++)
    if (s->mats[i].type->nstate > nstate) nstate = s->mats[i].type->nstate;
  return nstate;
}

void mpgm_probes_place(mpgm_points *P, const mpgm_scene *s) {
  for (int k = 0; k < s->nprobe; k++) {
    const int p = P->n + k;
    for (int d = 0; d < MPGM_DIM; d++) P->x[MPGM_DIM * p + d] = P->x0[MPGM_DIM * p + d] = s->probes[k].x[d];
    /* the initial velocity of the first body that holds it (0 in none): a
     * front end that advances the probe's velocity by increments (MPM)
     * must start it where the material is */
    int b = 0;
    while (b < s->nbody && !mpgm_body_contains(&s->bodies[b], s->probes[k].x)) b++;
    for (int d = 0; d < MPGM_DIM; d++) P->v[MPGM_DIM * p + d] = b < s->nbody ? s->bodies[b].velocity[d] : 0.0;
  }
}
