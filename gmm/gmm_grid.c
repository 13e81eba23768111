/* gmm_grid.c -- method gmm over bodies filled on a grid (disk and polygon
 * bodies, scenes with obstacles): the material points of method mpm (Gauss
 * points of the grid cells inside a body, mpgm_bodies_fill), persistent
 * nodes at the grid nodes of the cells holding them, and the obstacles'
 * layers of fixed nodes (docs/theory.md, section 13; gmm_impl.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gmm_impl.h"
#include "mpgm_discretisation.h"
#include "mpgm_kdtree.h"

/* The grid over mesh.domain, numbered as method mpm's (mpm/mpgm_grid.h):
 * square (i, j) is j nx + i, node (i, j) is j (nx + 1) + i; a Q4 cell is
 * its square, T3 cells 2 sq (q0 q1 q2) and 2 sq + 1 (q0 q2 q3). */
typedef struct ggrid {
  int cell, nn, per, nx, ny;
  double h, min[2];
} ggrid;

static void gg_nodes(const ggrid *g, int c, int *nodes) {
  const int sq = c / g->per, i = sq % g->nx, j = sq / g->nx, w = g->nx + 1;
  const int q[4] = {j * w + i, j * w + i + 1, (j + 1) * w + i + 1, (j + 1) * w + i};
  if (g->per == 1) {
    for (int a = 0; a < 4; a++) nodes[a] = q[a];
  } else if (c % 2 == 0) {
    nodes[0] = q[0];
    nodes[1] = q[1];
    nodes[2] = q[2];
  } else {
    nodes[0] = q[0];
    nodes[1] = q[2];
    nodes[2] = q[3];
  }
}

static void gg_node_x(const ggrid *g, int id, double X[2]) {
  X[0] = g->min[0] + (id % (g->nx + 1)) * g->h;
  X[1] = g->min[1] + (id / (g->nx + 1)) * g->h;
}

static void gg_cell_xy(const void *grid, int c, double *xn) {
  const ggrid *g = grid;
  int nodes[MPGM_FE_MAXNODE];
  gg_nodes(g, c, nodes);
  for (int a = 0; a < g->nn; a++) gg_node_x(g, nodes[a], xn + 2 * a);
}

int mpgm_gmm_uses_grid(const mpgm_scene *s) {
  int grid = s->nobstacle > 0;
  for (int i = 0; i < s->nbc; i++) /* contact at surface points */
    grid |= mpgm_bc_at_points(&s->bcs[i]);
  for (int b = 0; b < s->nbody; b++) grid |= s->bodies[b].geometry != MPGM_GEOM_RECTANGLE;
  return grid;
}

void mpgm_gmm_grid_destroy(gmm_grid **gp) {
  if (!gp || !*gp) return;
  free((*gp)->cptr);
  free((*gp)->cnode);
  free((*gp)->ctype);
  free((*gp)->fix0);
  free((*gp)->ubar0);
  free((*gp)->parked);
  free((*gp)->xs);
  free((*gp)->us);
  free((*gp)->mass);
  free((*gp)->obst);
  free((*gp)->wptr);
  free((*gp)->widx);
  free((*gp)->ww);
  free(*gp);
  *gp = NULL;
}

/* Obstacle nodes: layer l = 0 .. layers - 1 of obstacle o on the line
 * value + side (gap + l) h (strictly beyond the plane), across the grid's
 * extent along the plane, into X (2 per node, may be NULL); gid (may be
 * NULL) receives the grid node each coincides with (-1: off the grid).
 * Returns the count. */
static int obstacle_nodes(const mpgm_scene *s, const ggrid *g, int o, double *X, int *gid) {
  const mpgm_scene_obstacle *ob = &s->obstacles[o];
  const int ax = ob->axis, along = 1 - ax, nal = along == 0 ? g->nx : g->ny;
  const long k0 = lround((ob->value - g->min[ax]) / g->h);
  int n = 0;
  for (int l = 0; l < ob->layers; l++) {
    const long k = k0 + (long)ob->side * (ob->gap + l); /* grid line across the axis */
    for (int i = 0; i <= nal; i++, n++) {
      double x[2];
      x[ax] = g->min[ax] + (double)k * g->h;
      x[along] = g->min[along] + i * g->h;
      if (X) {
        X[2 * n] = x[0];
        X[2 * n + 1] = x[1];
      }
      if (gid) {
        const int nk = ax ? g->ny : g->nx;
        gid[n] = k < 0 || k > nk ? -1 : ax ? (int)k * (g->nx + 1) + i : i * (g->nx + 1) + (int)k;
      }
    }
  }
  return n;
}

int mpgm_gmm_grid_setup(const mpgm_fe_view *v, double r0, gmm_grid **out) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_scene *s = v->scene;
  gmm_grid *gd;
  MPGM_ALLOC(ctx, gd, 1);
  *out = gd;
  ggrid g = {.cell = s->cell,
             .nn = mpgm_fe_nnode(s->cell),
             .per = s->cell == MPGM_CELL_Q4 ? 1 : 2,
             .h = s->h,
             .min = {s->dom_min[0], s->dom_min[1]}};
  const double fx = ceil((s->dom_max[0] - s->dom_min[0]) / s->h - 1e-9);
  const double fy = ceil((s->dom_max[1] - s->dom_min[1]) / s->h - 1e-9);
  MPGM_CHECK(ctx, (fx + 1) * (fy + 1) < 5e7 && fx * fy * g.per * s->ppc < 1e8, MPGM_ERR_INPUT,
             "%s: mesh.h: expected a grid of at most 5e7 nodes and 1e8 Gauss points over "
             "mesh.domain, found %.4g nodes (h = %g)",
             s->file, (fx + 1) * (fy + 1), s->h);
  g.nx = fx < 1 ? 1 : (int)fx;
  g.ny = fy < 1 ? 1 : (int)fy;
  const int ncell = g.nx * g.ny * g.per, ngn = (g.nx + 1) * (g.ny + 1);
  const size_t ngp = (size_t)ncell * (size_t)s->ppc;
  int nobs = 0;
  for (int o = 0; o < s->nobstacle; o++) nobs += obstacle_nodes(s, &g, o, NULL, NULL);
  int *owner = malloc(sizeof(int) * ngp), *gmap = malloc(sizeof(int) * (size_t)ngn);
  int *ogid = malloc(sizeof(int) * (size_t)(nobs + 1));
  double *xg = malloc(sizeof(double) * 2 * ngp), *xp = NULL,
         *Xo = malloc(sizeof(double) * 2 * (nobs + 1));
  unsigned char *ofix = calloc((size_t)ngn, 1);
  mpgm_kdtree *tree = NULL;
  int err = owner && gmap && xg && ogid && Xo && ofix ? 0 : MPGM_ERR_NOMEM, np = 0;
  if (err) mpgm_err_set(ctx, err, __FILE__, __LINE__, "out of memory (grid of %d cells)", ncell);
  if (!err) err = mpgm_bodies_fill(s, g.cell, ncell, gg_cell_xy, &g, owner, xg, &np);
  if (!err && np == 0)
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                       "%s: bodies: no grid Gauss point lies inside any body (h = %g, ppc = %d): "
                       "expected bodies larger than a grid cell",
                       s->file, s->h, s->ppc);
  /* the material points, compacted, for the reach test */
  if (!err && !(xp = malloc(sizeof(double) * 2 * (size_t)np))) err = MPGM_ERR_NOMEM;
  for (size_t k = 0, p = 0; !err && k < ngp; k++)
    if (owner[k] >= 0) {
      xp[2 * p] = xg[2 * k];
      xp[2 * p + 1] = xg[2 * k + 1];
      p++;
    }
  if (!err) err = mpgm_kdtree_create(ctx, xp, np, 0, &tree);
  /* candidate nodes: the nodes of the cells holding points (gmap 0); kept
   * when a material point lies within r0 (gmap 1) */
  if (!err) {
    for (int i = 0; i < ngn; i++) gmap[i] = -1;
    for (int c = 0; c < ncell; c++) {
      int has = 0, nodes[MPGM_FE_MAXNODE];
      for (int q = 0; q < s->ppc; q++) has |= owner[(size_t)c * s->ppc + q] >= 0;
      if (!has) continue;
      gg_nodes(&g, c, nodes);
      for (int a = 0; a < g.nn; a++) gmap[nodes[a]] = 0;
    }
    for (int i = 0; i < ngn; i++) {
      if (gmap[i] < 0) continue;
      double X[2], d2;
      int nb;
      gg_node_x(&g, i, X);
      gmap[i] = mpgm_kdtree_knn(tree, X, 1, &nb, &d2) == 1 && d2 <= r0 * r0 ? 1 : -1;
    }
  }
  /* obstacle nodes; those on a kept body node are that node, fixed */
  int nbody_nodes = 0, nnew = 0;
  if (!err) {
    for (int i = 0; i < ngn; i++) nbody_nodes += gmap[i] > 0;
    int k = 0;
    for (int o = 0; o < s->nobstacle; o++) k += obstacle_nodes(s, &g, o, Xo + 2 * k, ogid + k);
    for (int k2 = 0; k2 < nobs; k2++) {
      if (ogid[k2] >= 0 && gmap[ogid[k2]] > 0) {
        ofix[ogid[k2]] = 1;
        ogid[k2] = -2; /* merged */
      } else {
        nnew++;
      }
    }
  }
  const int nnode = nbody_nodes + nnew;
  if (!err) err = mpgm_nodes_alloc(ctx, v->nodes, nnode);
  int nstate = 0;
  for (int i = 0; i < s->nmat; i++)
    if (s->mats[i].type->nstate > nstate) nstate = s->mats[i].type->nstate;
  /* contact at points: tracers on the bodies' boundaries, after the probes */
  const int nsurf = v->fx->contact_points ? mpgm_surface_tracers_count(s) : 0;
  if (!err) err = mpgm_points_alloc(ctx, v->pts, np, s->nprobe, nsurf, nstate);
  if (!err) {
    mpgm_nodes *nd = v->nodes;
    mpgm_points *P = v->pts;
    int n = 0;
    for (int i = 0; i < ngn; i++) {
      if (gmap[i] <= 0) continue;
      gmap[i] = n;
      gg_node_x(&g, i, nd->X + 2 * n);
      nd->fix[2 * n] = nd->fix[2 * n + 1] = ofix[i];
      n++;
    }
    for (int k = 0; k < nobs; k++) {
      if (ogid[k] == -2) continue;
      nd->X[2 * n] = Xo[2 * k];
      nd->X[2 * n + 1] = Xo[2 * k + 1];
      nd->fix[2 * n] = nd->fix[2 * n + 1] = 1;
      n++;
    }
    memcpy(nd->x, nd->X, sizeof(double) * 2 * (size_t)nnode);
    /* points (volume: cell area x Gauss weight / reference area, as mpm),
     * and the initial velocity of the nodes of their cells */
    double gxi[18], gw[9];
    mpgm_fe_gauss(g.cell, s->ppc, gxi, gw);
    const double ref_area = g.per == 1 ? 4.0 : 0.5, cell_area = g.h * g.h / g.per;
    int p = 0;
    for (size_t k = 0; k < ngp; k++) {
      const int b = owner[k];
      if (b < 0) continue;
      const int q = (int)(k % (size_t)s->ppc), c = (int)(k / (size_t)s->ppc);
      const mpgm_scene_body *bd = &s->bodies[b];
      mpgm_point_set(P, p, s, b, xg[2 * k], xg[2 * k + 1], cell_area * gw[q] / ref_area);
      int nodes[MPGM_FE_MAXNODE];
      gg_nodes(&g, c, nodes);
      for (int a = 0; a < g.nn; a++) {
        const int I = gmap[nodes[a]];
        if (I < 0 || ofix[nodes[a]]) continue;
        nd->v[2 * I] = bd->velocity[0];
        nd->v[2 * I + 1] = bd->velocity[1];
      }
      p++;
    }
    for (int k = 0; k < s->nprobe; k++, p++) {
      P->x[2 * p] = P->x0[2 * p] = s->probes[k].x[0];
      P->x[2 * p + 1] = P->x0[2 * p + 1] = s->probes[k].x[1];
    }
    mpgm_surface_tracers_fill(P, s);
    /* output cells: the cells holding points whose nodes are all kept */
    int nc = 0;
    err = (gd->cptr = malloc(sizeof(int) * (size_t)(ncell + 1))) &&
                  (gd->cnode = malloc(sizeof(int) * (size_t)ncell * g.nn)) &&
                  (gd->ctype = malloc(sizeof(int) * (size_t)ncell))
              ? 0
              : mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory (cells)");
    for (int c = 0; c < ncell && !err; c++) {
      int has = 0, all = 1, nodes[MPGM_FE_MAXNODE];
      for (int q = 0; q < s->ppc; q++) has |= owner[(size_t)c * s->ppc + q] >= 0;
      gg_nodes(&g, c, nodes);
      for (int a = 0; a < g.nn; a++) all &= gmap[nodes[a]] >= 0;
      if (!has || !all) continue;
      gd->cptr[nc] = nc * g.nn;
      for (int a = 0; a < g.nn; a++) gd->cnode[nc * g.nn + a] = gmap[nodes[a]];
      gd->ctype[nc] = g.per == 1 ? 9 : 5; /* VTK_QUAD, VTK_TRIANGLE */
      nc++;
    }
    if (!err) {
      gd->cptr[nc] = nc * g.nn;
      gd->ncell = nc;
    }
    /* boundaries: nodes selected by a geometric predicate */
    if (!err) err = mpgm_nodes_apply_boundaries(ctx, s, nd);
  }
  if (!err) {
    const int n = v->nodes->n;
    gd->fix0 = malloc(2 * (size_t)n);
    gd->ubar0 = malloc(sizeof(double) * 2 * (size_t)n);
    gd->parked = calloc((size_t)n, 1);
    gd->xs = malloc(sizeof(double) * 2 * (size_t)n);
    gd->us = malloc(sizeof(double) * 2 * (size_t)n);
    gd->mass = malloc(sizeof(double) * (size_t)n);
    gd->obst = calloc((size_t)n, 1);
    gd->wptr = malloc(sizeof(int) * (size_t)(n + 1));
    if (gd->fix0 && gd->ubar0 && gd->parked && gd->xs && gd->us && gd->mass && gd->obst &&
        gd->wptr) {
      for (int i = nbody_nodes; i < n; i++) gd->obst[i] = 1;
      for (int i = 0; i < ngn; i++)
        if (gmap[i] >= 0 && ofix[i]) gd->obst[gmap[i]] = 1;
      memcpy(gd->fix0, v->nodes->fix, 2 * (size_t)n);
      memcpy(gd->ubar0, v->nodes->ubar, sizeof(double) * 2 * (size_t)n);
    } else {
      err = MPGM_ERR_NOMEM;
    }
  }
  mpgm_kdtree_destroy(&tree);
  free(owner);
  free(gmap);
  free(ogid);
  free(xg);
  free(xp);
  free(Xo);
  free(ofix);
  if (err == MPGM_ERR_NOMEM && !ctx->code)
    mpgm_err_set(ctx, err, __FILE__, __LINE__, "out of memory (grid-filled bodies)");
  return err;
}

int mpgm_gmm_grid_park(const mpgm_fe_view *v, gmm_grid *g, const mpgm_kdtree *tree, double r0, int m,
                       int *ptr, int *node, double *N, double *dN) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_scene *s = v->scene;
  const mpgm_points *P = v->pts;
  mpgm_nodes *nd = v->nodes;
  const int n = nd->n;
  memcpy(nd->fix, g->fix0, 2 * (size_t)n);
  memcpy(nd->ubar, g->ubar0, sizeof(double) * 2 * (size_t)n);
  memset(g->parked, 0, (size_t)n);
  g->nparked = 0;
  for (int i = 0; i < n; i++) g->mass[i] = 0.0;
  for (int p = 0; p < P->n; p++)
    for (int k = ptr[p]; k < ptr[p + 1]; k++) g->mass[node[k]] += N[k] * P->mass[p];
  double mmax = 0.0;
  for (int i = 0; i < n; i++) mmax = fmax(mmax, g->mass[i]);
  const double cut = s->min_node_mass * mmax;
  /* the load factor of the step (as the core sets it): a parked node is
   * held where it is, lambda ubar = u */
  const double lam = v->lambda;
  for (int i = 0; i < n; i++) {
    if (g->fix0[2 * i] || g->fix0[2 * i + 1]) continue;
    int beyond = 0; /* a body node that moved into an obstacle */
    for (int o = 0; o < s->nobstacle; o++) {
      const mpgm_scene_obstacle *ob = &s->obstacles[o];
      beyond |= ob->side * (nd->x[2 * i + ob->axis] - ob->value) > 0.0;
    }
    if (!beyond && g->mass[i] > cut) continue;
    g->parked[i] = 1;
    g->nparked++;
    for (int c = 0; c < 2; c++) {
      g->xs[2 * i + c] = nd->x[2 * i + c];
      g->us[2 * i + c] = nd->u[2 * i + c];
      nd->fix[2 * i + c] = 1;
      nd->ubar[2 * i + c] = lam > 0.0 ? nd->u[2 * i + c] / lam : 0.0;
    }
  }
  if (!g->nparked) return 0;
  /* the free body nodes each parked node follows: within r0 (grown x1.25
   * until there is one), inverse-distance weights */
  int nw = 0, idx[MPGM_SHAPE_MAXNODE];
  double d2[MPGM_SHAPE_MAXNODE];
  for (int i = 0; i < n; i++) {
    g->wptr[i] = nw;
    if (!g->parked[i]) continue;
    int cnt = 0;
    double r = r0;
    for (int tries = 0; cnt == 0 && tries < 60; tries++, r *= MPGM_SHAPE_GROWTH) {
      const int k = mpgm_kdtree_radius(tree, nd->x + 2 * i, r, MPGM_SHAPE_MAXNODE, idx, d2);
      if (nw + MPGM_SHAPE_MAXNODE > g->wcap) {
        const int cap = 2 * (nw + MPGM_SHAPE_MAXNODE);
        int *wi = realloc(g->widx, sizeof(int) * (size_t)cap);
        if (wi) g->widx = wi;
        double *ww = realloc(g->ww, sizeof(double) * (size_t)cap);
        if (ww) g->ww = ww;
        MPGM_CHECK(ctx, wi && ww, MPGM_ERR_NOMEM, "out of memory (parked nodes)");
        g->wcap = cap;
      }
      double sw = 0.0;
      for (int a = 0; a < k && a < MPGM_SHAPE_MAXNODE; a++) {
        const int J = idx[a];
        if (g->parked[J] || g->obst[J] || J == i) continue;
        g->widx[nw + cnt] = J;
        g->ww[nw + cnt] = 1.0 / (d2[a] + 1e-6 * s->h * s->h);
        sw += g->ww[nw + cnt];
        cnt++;
      }
      for (int a = 0; a < cnt; a++) g->ww[nw + a] /= sw;
    }
    nw += cnt;
  }
  g->wptr[n] = nw;
  /* drop the parked nodes from the lists; Shepard renormalisation of the
   * points that used one (sum N = 1, sum grad N = 0 still hold) */
  int w = 0;
  for (int p = 0; p < m; p++) {
    const int k0 = ptr[p], k1 = ptr[p + 1];
    ptr[p] = w;
    double S = 0, Sx = 0, Sy = 0;
    int lost = 0;
    for (int k = k0; k < k1; k++) {
      if (g->parked[node[k]]) {
        lost = 1;
        continue;
      }
      S += N[k];
      Sx += dN[2 * k];
      Sy += dN[2 * k + 1];
    }
    if (lost && !(fabs(S) > 1e-12) && p >= P->n + P->nprobe) {
      /* a surface point among parked nodes only: not enforced this step */
      mpgm_cpoints_unenforce(v->cp, p - P->n - P->nprobe);
      continue;
    }
    MPGM_CHECK(ctx, !lost || fabs(S) > 1e-12, MPGM_ERR_SHAPE,
               "step %ld: %s %d at (%g, %g) lost every node to mesh.min_node_mass = %g",
               v->step + 1, p < P->n ? "point" : "probe", p < P->n ? P->id[p] : p - P->n,
               P->x[2 * p], P->x[2 * p + 1], s->min_node_mass);
    for (int k = k0; k < k1; k++) {
      if (g->parked[node[k]]) continue;
      const double Nk = N[k], gx = dN[2 * k], gy = dN[2 * k + 1];
      node[w] = node[k];
      if (lost) {
        N[w] = Nk / S;
        dN[2 * w] = gx / S - Nk * Sx / (S * S);
        dN[2 * w + 1] = gy / S - Nk * Sy / (S * S);
      } else {
        N[w] = Nk;
        dN[2 * w] = gx;
        dN[2 * w + 1] = gy;
      }
      w++;
    }
  }
  ptr[m] = w;
  return 0;
}

void mpgm_gmm_grid_unpark(const mpgm_fe_view *v, gmm_grid *g) {
  mpgm_nodes *nd = v->nodes;
  const int move = v->fx->geometric;
  for (int i = 0; i < nd->n && g->nparked; i++) {
    if (!g->parked[i]) continue;
    double du[2] = {0, 0}, v[2] = {0, 0}, a[2] = {0, 0};
    for (int k = g->wptr[i]; k < g->wptr[i + 1]; k++) {
      const int J = g->widx[k];
      const double w = g->ww[k];
      for (int c = 0; c < 2; c++) {
        du[c] += w * nd->du[2 * J + c];
        v[c] += w * nd->v[2 * J + c];
        a[c] += w * nd->a[2 * J + c];
      }
    }
    for (int c = 0; c < 2; c++) {
      nd->du[2 * i + c] = du[c];
      nd->u[2 * i + c] = g->us[2 * i + c] + du[c];
      nd->x[2 * i + c] = g->xs[2 * i + c] + (move ? du[c] : 0.0);
      nd->v[2 * i + c] = v[c];
      nd->a[2 * i + c] = a[c];
    }
  }
}
