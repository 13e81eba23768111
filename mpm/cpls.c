/* cpls.c -- the nodal velocities of CPLS (Tran et al. 2019, eqs 25, 31,
 * 41; docs/theory.md section 20.3): instead of the projection
 * sum_p N_Ip m_p v_p / m_I, each node's velocity is reconstructed by
 * improved moving least squares (shapefn/imls.c) from five data points per
 * particle, its centre with v_p and the four corners of its domain with
 * v_c = v_p + L_p (x_c - x_p) (L_p the velocity gradient of the last
 * step): v_I = sum_k phi_k(x_I) v_k. The data points are binned by grid
 * cell once per step; a node reads the 4 x 4 cells around it, which hold
 * every point of the weight's support |x - x_I|_inf < 2 h. A node the data
 * reach from one side only extrapolates; where the quadratic coefficients
 * would amplify the data (sum |phi| > MPGM_CPLS_MAX_GAIN) it takes the
 * linear basis, and where even those would, the projection. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_cpls.h"
#include "mpgm_imls.h"

#if MPGM_DIM != 2
#error "mpm/cpls.c is written for plane strain only (MPGM_DIM = 2)"
#endif

struct mpgm_cpls {
  int cap;          /**< data points allocated (5 per particle)        */
  double *x, *v;    /**< positions and velocities, MPGM_DIM each        */
  int *cell, *sorted, *start; /**< bins: cell of each, data by cell, offsets */
  int ncell;
  int gcap;         /**< gathered points allocated                     */
  double *gx, *phi, *work;
  int *gk;
};

void mpgm_cpls_destroy(mpgm_cpls *c) {
  if (!c) return;
  free(c->x);
  free(c->v);
  free(c->cell);
  free(c->sorted);
  free(c->start);
  free(c->gx);
  free(c->phi);
  free(c->work);
  free(c->gk);
  free(c);
}

static int grow_data(mpgm_ctx *ctx, mpgm_cpls *c, int n, int ncell) {
  if (n > c->cap) {
    free(c->x);
    free(c->v);
    free(c->cell);
    free(c->sorted);
    c->x = c->v = NULL;
    c->cell = c->sorted = NULL;
    c->cap = 0;
    MPGM_ALLOC(ctx, c->x, MPGM_DIM * (size_t)n);
    MPGM_ALLOC(ctx, c->v, MPGM_DIM * (size_t)n);
    MPGM_ALLOC(ctx, c->cell, n);
    MPGM_ALLOC(ctx, c->sorted, n);
    c->cap = n;
  }
  if (!c->start || c->ncell != ncell) {
    free(c->start);
    c->start = NULL;
    MPGM_ALLOC(ctx, c->start, (size_t)ncell + 2);
    c->ncell = ncell;
  }
  return 0;
}

/* Room for n gathered points; what was gathered so far is kept. */
static int grow_gather(mpgm_ctx *ctx, mpgm_cpls *c, int n) {
  if (n <= c->gcap) return 0;
  const int cap = n + n / 2 + 16;
  double *gx = realloc(c->gx, sizeof(double) * MPGM_DIM * (size_t)cap);
  if (gx) c->gx = gx;
  int *gk = realloc(c->gk, sizeof(int) * (size_t)cap);
  if (gk) c->gk = gk;
  free(c->phi);
  free(c->work);
  c->phi = malloc(sizeof(double) * (size_t)cap);
  c->work = malloc(sizeof(double) * mpgm_imls_work_len(cap));
  MPGM_CHECK(ctx, gx && gk && c->phi && c->work, MPGM_ERR_NOMEM,
             "out of memory (CPLS: %d data points around a node)", cap);
  c->gcap = cap;
  return 0;
}

/* The cell (i, j) of a position, clamped to the grid. */
static inline void cell_of(const mpgm_grid *g, const double *x, int *i, int *j) {
  *i = mpgm_grid_line(g, 0, x[0]);
  *j = mpgm_grid_line(g, 1, x[1]);
  *i = *i < 0 ? 0 : *i >= g->nx ? g->nx - 1 : *i;
  *j = *j < 0 ? 0 : *j >= g->ny ? g->ny - 1 : *j;
}

/* The data points (centres and corners, r_k = F r_k^0) and their bins. */
static int bin_data(mpgm_ctx *ctx, mpgm_cpls *c, const mpgm_grid *g, const mpgm_points *P) {
  const int n = 5 * P->n, ncell = g->nx * g->ny;
  MPGM_CALL(grow_data(ctx, c, n, ncell));
  for (int p = 0; p < P->n; p++) { /* 2-D only: L written out */
    const double *L = P->L + MPGM_TENSOR * p, *xp = P->x + MPGM_DIM * p, *vp = P->v + MPGM_DIM * p;
    double r[2 * MPGM_DIM], off[4][2];
    mpgm_point_domain(P, p, r);
    mpgm_domain_corners(r, off);
    double *x = c->x + MPGM_DIM * 5 * p, *v = c->v + MPGM_DIM * 5 * p;
    x[0] = xp[0];
    x[1] = xp[1];
    v[0] = vp[0];
    v[1] = vp[1];
    for (int k = 0; k < 4; k++) {
      const double dx = off[k][0], dy = off[k][1];
      x[2 * k + 2] = xp[0] + dx;
      x[2 * k + 3] = xp[1] + dy;
      v[2 * k + 2] = vp[0] + L[0] * dx + L[1] * dy; /* eq 25 */
      v[2 * k + 3] = vp[1] + L[2] * dx + L[3] * dy;
    }
  }
  memset(c->start, 0, sizeof(int) * ((size_t)ncell + 2));
  for (int k = 0; k < n; k++) {
    int i, j;
    cell_of(g, c->x + MPGM_DIM * k, &i, &j);
    c->cell[k] = j * g->nx + i;
    c->start[c->cell[k] + 2]++;
  }
  for (int e = 0; e < ncell; e++) c->start[e + 2] += c->start[e + 1];
  for (int k = 0; k < n; k++) c->sorted[c->start[c->cell[k] + 1]++] = k;
  return 0; /* start[e] .. start[e + 1]: the data of cell e */
}

/* sum_k |phi_k|: how much the reconstruction may amplify the data's errors
 * (1 for a convex combination). */
static double gain(const double *phi, int n) {
  double s = 0.0;
  for (int a = 0; a < n; a++) s += fabs(phi[a]);
  return s;
}

/* One node's velocity from the data of the 4 x 4 cells around it; 1 when
 * no data point has weight there, or the reconstruction would amplify the
 * data too much (the projected velocity stays); *lower counts the nodes
 * that took the linear basis. */
static int node_velocity(mpgm_ctx *ctx, mpgm_cpls *c, const mpgm_grid *g,
                         const mpgm_imls_params *par, int gi, double *v, int *err, long *lower) {
  const int i = gi % (g->nx + 1), j = gi / (g->nx + 1);
  const double xI[MPGM_DIM] = {g->min[0] + i * g->h, g->min[1] + j * g->h};
  int n = 0;
  for (int cj = j - 2; cj <= j + 1; cj++)
    for (int ci = i - 2; ci <= i + 1; ci++) {
      if (ci < 0 || cj < 0 || ci >= g->nx || cj >= g->ny) continue;
      const int e = cj * g->nx + ci, m = c->start[e + 1] - c->start[e];
      if ((*err = grow_gather(ctx, c, n + m))) return 1;
      for (int q = c->start[e]; q < c->start[e + 1]; q++) {
        const int k = c->sorted[q];
        c->gk[n] = k;
        c->gx[MPGM_DIM * n] = c->x[MPGM_DIM * k];
        c->gx[MPGM_DIM * n + 1] = c->x[MPGM_DIM * k + 1];
        n++;
      }
    }
  if (n == 0 || mpgm_imls_coeffs(par, xI, n, c->gx, c->phi, NULL, c->work)) return 1;
  /* a node the data reach from one side (a body's edge, a hole) is an
   * extrapolation: when the coefficients amplify the data (sum |phi| above
   * MPGM_CPLS_MAX_GAIN), the linear basis, then the projection */
  if (gain(c->phi, n) > MPGM_CPLS_MAX_GAIN && par->order == 2) {
    mpgm_imls_params p1 = *par;
    p1.order = 1;
    if (mpgm_imls_coeffs(&p1, xI, n, c->gx, c->phi, NULL, c->work)) return 1;
    (*lower)++;
  }
  if (gain(c->phi, n) > MPGM_CPLS_MAX_GAIN) return 1;
  v[0] = v[1] = 0.0;
  for (int a = 0; a < n; a++) {
    v[0] += c->phi[a] * c->v[MPGM_DIM * c->gk[a]];
    v[1] += c->phi[a] * c->v[MPGM_DIM * c->gk[a] + 1];
  }
  return 0;
}

int mpgm_cpls_velocities(mpgm_ctx *ctx, mpgm_cpls **cp, const mpgm_grid *g, const mpgm_points *P,
                         int order, int nnode, const int *lglob, double *v, long *lower,
                         long *kept) {
  if (!*cp) MPGM_ALLOC(ctx, *cp, 1);
  mpgm_cpls *c = *cp;
  MPGM_CALL(bin_data(ctx, c, g, P));
  const mpgm_imls_params par = {.dim = MPGM_DIM, .order = order, .h = g->h, .tol_rel = 0.0};
  *kept = *lower = 0;
  for (int I = 0; I < nnode; I++) {
    int err = 0;
    double w[MPGM_DIM];
    if (node_velocity(ctx, c, g, &par, lglob[I], w, &err, lower)) {
      MPGM_CALL(err);
      (*kept)++;
      continue;
    }
    v[MPGM_DIM * I] = w[0];
    v[MPGM_DIM * I + 1] = w[1];
  }
  return 0;
}
