/* gmm_grid.c -- method gmm over bodies filled on a grid (disk and polygon
 * bodies, scenes with obstacles): the material points of method mpm (Gauss
 * points of the grid cells inside a body, mpgm_grid_fill), persistent
 * nodes at the grid nodes of the cells holding them, and the obstacles'
 * layers of fixed nodes (docs/theory.md, section 13; gmm_impl.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gmm_impl.h"
#include "mpgm_discretisation.h"
#include "mpgm_grid.h"
#include "mpgm_kdtree.h"

#if MPGM_DIM != 2
#error "gmm/gmm_grid.c is written for plane strain only (MPGM_DIM = 2)"
#endif

int mpgm_gmm_uses_grid(const mpgm_scene *s) {
  int grid = s->nobstacle > 0 || mpgm_scene_contact_at_points(s);
  for (int b = 0; b < s->nbody; b++) grid |= s->bodies[b].geometry != MPGM_GEOM_RECTANGLE;
  return grid;
}

void mpgm_gmm_grid_destroy(gmm_grid **gp) {
  if (!gp || !*gp) return;
  gmm_grid *g = *gp;
  void *arr[] = {g->cptr, g->cnode, g->ctype, g->fix0, g->ubar0, g->parked, g->xs,
                 g->us,   g->mass,  g->obst,  g->wptr, g->widx,  g->ww,    g->eligible};
  for (size_t i = 0; i < sizeof arr / sizeof arr[0]; i++) free(arr[i]);
  free(g);
  *gp = NULL;
}

/* Obstacle nodes: layer l = 0 .. layers - 1 of obstacle o on the line
 * value + side (gap + l) h (strictly beyond the plane), across the grid's
 * extent along the plane, into X (MPGM_DIM per node, may be NULL); gid (may
 * be NULL) receives the grid node each coincides with (-1: off the grid).
 * Returns the count. 2-D only: the plane's one direction along it, a grid
 * line of nodes, x and y written out. */
static int obstacle_nodes(const mpgm_scene *s, const mpgm_grid *g, int o, double *X, int *gid) {
  const mpgm_scene_obstacle *ob = &s->obstacles[o];
  const int ax = ob->axis, along = 1 - ax, nal = along == 0 ? g->nx : g->ny;
  const long k0 = lround((ob->value - g->min[ax]) / g->h);
  int n = 0;
  for (int l = 0; l < ob->layers; l++) {
    const long k = k0 + (long)ob->side * (ob->gap + l); /* grid line across the axis */
    for (int i = 0; i <= nal; i++, n++) {
      double x[MPGM_DIM];
      x[ax] = g->min[ax] + (double)k * g->h;
      x[along] = g->min[along] + i * g->h;
      if (X) {
        X[MPGM_DIM * n] = x[0];
        X[MPGM_DIM * n + 1] = x[1];
      }
      if (gid) {
        const int nk = ax ? g->ny : g->nx;
        gid[n] = k < 0 || k > nk ? -1 : ax ? (int)k * (g->nx + 1) + i : i * (g->nx + 1) + (int)k;
      }
    }
  }
  return n;
}

/* What the setup works with. */
typedef struct build {
  mpgm_grid g;
  mpgm_fill f;        /* the bodies' Gauss points                         */
  int *gmap;          /* per grid node: -1 not a node; else its node      */
  unsigned char *ofix;/* per grid node: a body node on an obstacle layer   */
  int nobs;           /* obstacle layer nodes                             */
  int *ogid;          /* their grid nodes (-1: off the grid, -2: a body node) */
  double *Xo;         /* their positions, MPGM_DIM each                   */
  int nbody_nodes;    /* nodes at grid nodes                              */
} build;

static void build_free(build *b) {
  mpgm_fill_free(&b->f);
  free(b->gmap);
  free(b->ofix);
  free(b->ogid);
  free(b->Xo);
}

/* 1 when cell c holds a material point. */
static int holds_points(const build *b, int c) {
  for (int q = 0; q < b->f.ppc; q++)
    if (b->f.owner[(size_t)c * b->f.ppc + q] >= 0) return 1;
  return 0;
}

/* The body nodes: the grid nodes of the cells holding material points or
 * surface points that some material point has within r0 (gmap 1; others
 * -1). */
static int body_nodes(mpgm_ctx *ctx, const mpgm_scene *s, build *b, double r0) {
  const mpgm_grid *g = &b->g;
  double *xp = malloc(sizeof(double) * MPGM_DIM * (size_t)b->f.count);
  MPGM_CHECK(ctx, xp, MPGM_ERR_NOMEM, "out of memory (%d points)", b->f.count);
  for (size_t k = 0, p = 0; k < b->f.ngauss; k++)
    if (b->f.owner[k] >= 0) { /* 2-D only: x and y written out */
      xp[MPGM_DIM * p] = b->f.x[MPGM_DIM * k];
      xp[MPGM_DIM * p + 1] = b->f.x[MPGM_DIM * k + 1];
      p++;
    }
  mpgm_kdtree *tree = NULL;
  int err = mpgm_kdtree_create(ctx, xp, b->f.count, 0, &tree);
  for (int i = 0; i < g->nnode; i++) b->gmap[i] = -1;
  for (int c = 0; c < g->ncell && !err; c++) {
    if (!holds_points(b, c)) continue;
    int nodes[MPGM_FE_MAXNODE];
    mpgm_grid_cell(g, c, nodes, NULL);
    for (int a = 0; a < g->nn; a++) b->gmap[nodes[a]] = 0;
  }
  /* and of the cells holding surface points (contact at points): a point
   * on the boundary of a cell whose Gauss points are all outside the body
   * would lie outside the hull of its cloud (LME fails there) */
  const int nsurf = mpgm_surface_tracers_count(s);
  double *xs = nsurf ? malloc(sizeof(double) * MPGM_DIM * (size_t)nsurf) : NULL;
  if (!err && nsurf && !xs) err = mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory");
  if (xs) mpgm_surface_tracers_xy(s, xs);
  for (int k = 0; k < nsurf && !err; k++) {
    int c, nodes[MPGM_FE_MAXNODE];
    double xi[MPGM_DIM];
    if (mpgm_grid_locate(g, xs + MPGM_DIM * k, &c, xi)) continue; /* off the grid */
    mpgm_grid_cell(g, c, nodes, NULL);
    for (int a = 0; a < g->nn; a++) b->gmap[nodes[a]] = 0;
  }
  free(xs);
  for (int i = 0; i < g->nnode && !err; i++) {
    if (b->gmap[i] < 0) continue;
    double X[MPGM_DIM], d2;
    int nb;
    mpgm_grid_node(g, i, X);
    b->gmap[i] = mpgm_kdtree_knn(tree, X, 1, &nb, &d2) == 1 && d2 <= r0 * r0 ? 1 : -1;
  }
  mpgm_kdtree_destroy(&tree);
  free(xp);
  return err;
}

/* The obstacles' node layers; a layer node on a body node is that node,
 * fixed (ofix). Returns the nodes to add in *nnew. */
static int obstacles(mpgm_ctx *ctx, const mpgm_scene *s, build *b, int *nnew) {
  const mpgm_grid *g = &b->g;
  for (int o = 0; o < s->nobstacle; o++) b->nobs += obstacle_nodes(s, g, o, NULL, NULL);
  b->ogid = malloc(sizeof(int) * (size_t)(b->nobs + 1));
  b->Xo = malloc(sizeof(double) * MPGM_DIM * (size_t)(b->nobs + 1));
  MPGM_CHECK(ctx, b->ogid && b->Xo, MPGM_ERR_NOMEM, "out of memory (obstacle nodes)");
  for (int o = 0, k = 0; o < s->nobstacle; o++)
    k += obstacle_nodes(s, g, o, b->Xo + MPGM_DIM * k, b->ogid + k);
  *nnew = 0;
  for (int k = 0; k < b->nobs; k++) {
    if (b->ogid[k] >= 0 && b->gmap[b->ogid[k]] > 0) {
      b->ofix[b->ogid[k]] = 1;
      b->ogid[k] = -2; /* merged */
    } else {
      (*nnew)++;
    }
  }
  return 0;
}

/* Number the nodes: the body nodes in grid order, then the obstacles' new
 * ones (fixed). 2-D only: positions and fixity written out in x and y. */
static void make_nodes(build *b, mpgm_nodes *nd) {
  const mpgm_grid *g = &b->g;
  int n = 0;
  for (int i = 0; i < g->nnode; i++) {
    if (b->gmap[i] <= 0) continue;
    b->gmap[i] = n;
    mpgm_grid_node(g, i, nd->X + MPGM_DIM * n);
    nd->fix[MPGM_DIM * n] = nd->fix[MPGM_DIM * n + 1] = b->ofix[i];
    n++;
  }
  for (int k = 0; k < b->nobs; k++) {
    if (b->ogid[k] == -2) continue;
    nd->X[MPGM_DIM * n] = b->Xo[MPGM_DIM * k];
    nd->X[MPGM_DIM * n + 1] = b->Xo[MPGM_DIM * k + 1];
    nd->fix[MPGM_DIM * n] = nd->fix[MPGM_DIM * n + 1] = 1;
    n++;
  }
  memcpy(nd->x, nd->X, sizeof(double) * MPGM_DIM * (size_t)nd->n);
}

/* The material points (mpm's), probes and surface tracers; the free nodes
 * of a cell holding points take its body's initial velocity. */
static int make_points(const mpgm_fe_view *v, build *b) {
  const mpgm_scene *s = v->scene;
  const mpgm_grid *g = &b->g;
  const int nsurf = v->fx->contact_points ? mpgm_surface_tracers_count(s) : 0;
  MPGM_CALL(mpgm_points_alloc(v->ctx, v->pts, b->f.count, s->nprobe, nsurf, mpgm_scene_nstate(s)));
  mpgm_fill_points(&b->f, s, v->pts);
  mpgm_nodes *nd = v->nodes;
  for (size_t k = 0; k < b->f.ngauss; k++) {
    const int bd = b->f.owner[k];
    if (bd < 0) continue;
    int nodes[MPGM_FE_MAXNODE];
    mpgm_grid_cell(g, (int)(k / (size_t)b->f.ppc), nodes, NULL);
    for (int a = 0; a < g->nn; a++) {
      const int I = b->gmap[nodes[a]];
      if (I < 0 || b->ofix[nodes[a]]) continue;
      nd->v[MPGM_DIM * I] = s->bodies[bd].velocity[0]; /* 2-D only: written out */
      nd->v[MPGM_DIM * I + 1] = s->bodies[bd].velocity[1];
    }
  }
  mpgm_probes_place(v->pts, s);
  mpgm_surface_tracers_fill(v->pts, s);
  return 0;
}

/* Output cells: the cells holding points whose nodes are all kept. */
static int make_cells(mpgm_ctx *ctx, const build *b, gmm_grid *gd) {
  const mpgm_grid *g = &b->g;
  gd->cptr = malloc(sizeof(int) * (size_t)(g->ncell + 1));
  gd->cnode = malloc(sizeof(int) * (size_t)g->ncell * g->nn);
  gd->ctype = malloc(sizeof(int) * (size_t)g->ncell);
  MPGM_CHECK(ctx, gd->cptr && gd->cnode && gd->ctype, MPGM_ERR_NOMEM, "out of memory (cells)");
  int nc = 0;
  for (int c = 0; c < g->ncell; c++) {
    int all = 1, nodes[MPGM_FE_MAXNODE];
    mpgm_grid_cell(g, c, nodes, NULL);
    for (int a = 0; a < g->nn; a++) all &= b->gmap[nodes[a]] >= 0;
    if (!holds_points(b, c) || !all) continue;
    gd->cptr[nc] = nc * g->nn;
    for (int a = 0; a < g->nn; a++) gd->cnode[nc * g->nn + a] = b->gmap[nodes[a]];
    gd->ctype[nc] = g->cell == MPGM_CELL_Q4 ? 9 : 5; /* VTK_QUAD, VTK_TRIANGLE */
    nc++;
  }
  gd->cptr[nc] = nc * g->nn;
  gd->ncell = nc;
  return 0;
}

/* The arrays of the light-node rule, and which nodes are the obstacles'. */
static int park_arrays(mpgm_ctx *ctx, const build *b, const mpgm_nodes *nd, gmm_grid *gd) {
  const int n = nd->n;
  gd->fix0 = malloc(MPGM_DIM * (size_t)n);
  gd->ubar0 = malloc(sizeof(double) * MPGM_DIM * (size_t)n);
  gd->parked = calloc((size_t)n, 1);
  gd->xs = malloc(sizeof(double) * MPGM_DIM * (size_t)n);
  gd->us = malloc(sizeof(double) * MPGM_DIM * (size_t)n);
  gd->mass = malloc(sizeof(double) * (size_t)n);
  gd->obst = calloc((size_t)n, 1);
  gd->wptr = malloc(sizeof(int) * (size_t)(n + 1));
  gd->eligible = malloc((size_t)n + 1);
  MPGM_CHECK(ctx, gd->fix0 && gd->ubar0 && gd->parked && gd->xs && gd->us && gd->mass && gd->obst &&
                      gd->wptr && gd->eligible, MPGM_ERR_NOMEM, "out of memory (grid-filled bodies)");
  for (int i = b->nbody_nodes; i < n; i++) gd->obst[i] = 1;
  for (int i = 0; i < b->g.nnode; i++)
    if (b->gmap[i] >= 0 && b->ofix[i]) gd->obst[b->gmap[i]] = 1;
  memcpy(gd->fix0, nd->fix, MPGM_DIM * (size_t)n);
  memcpy(gd->ubar0, nd->ubar, sizeof(double) * MPGM_DIM * (size_t)n);
  /* only free nodes may be parked (the light-node rule); 2-D only: x, y */
  for (int i = 0; i < n; i++)
    gd->eligible[i] = !gd->fix0[MPGM_DIM * i] && !gd->fix0[MPGM_DIM * i + 1];
  return 0;
}

static int setup(const mpgm_fe_view *v, double r0, build *b, gmm_grid *gd) {
  mpgm_ctx *ctx = v->ctx;
  const mpgm_scene *s = v->scene;
  MPGM_CALL(mpgm_grid_init(ctx, &b->g, s));
  MPGM_CALL(mpgm_grid_fill(ctx, &b->g, s, &b->f));
  b->gmap = malloc(sizeof(int) * (size_t)b->g.nnode);
  b->ofix = calloc((size_t)b->g.nnode, 1);
  MPGM_CHECK(ctx, b->gmap && b->ofix, MPGM_ERR_NOMEM, "out of memory (grid of %d nodes)", b->g.nnode);
  MPGM_CALL(body_nodes(ctx, s, b, r0));
  for (int i = 0; i < b->g.nnode; i++) b->nbody_nodes += b->gmap[i] > 0;
  int nnew = 0;
  MPGM_CALL(obstacles(ctx, s, b, &nnew));
  MPGM_CALL(mpgm_nodes_alloc(ctx, v->nodes, b->nbody_nodes + nnew));
  make_nodes(b, v->nodes);
  MPGM_CALL(make_points(v, b));
  MPGM_CALL(make_cells(ctx, b, gd));
  /* boundaries: nodes selected by a geometric predicate */
  MPGM_CALL(mpgm_nodes_apply_boundaries(ctx, s, v->nodes));
  return park_arrays(ctx, b, v->nodes, gd);
}

int mpgm_gmm_grid_setup(const mpgm_fe_view *v, double r0, gmm_grid **out) {
  gmm_grid *gd;
  MPGM_ALLOC(v->ctx, gd, 1);
  *out = gd;
  build b = {0};
  const int err = setup(v, r0, &b, gd);
  build_free(&b);
  return err;
}

/* The free body nodes each parked node follows: within r0 (grown x1.25
 * until there is one), inverse-distance weights. */
static int follow_weights(mpgm_ctx *ctx, const mpgm_scene *s, const mpgm_nodes *nd, gmm_grid *g,
                          const mpgm_kdtree *tree, double r0) {
  const int n = nd->n;
  int nw = 0, idx[MPGM_SHAPE_MAXNODE];
  double d2[MPGM_SHAPE_MAXNODE];
  for (int i = 0; i < n; i++) {
    g->wptr[i] = nw;
    if (!g->parked[i]) continue;
    int cnt = 0;
    double r = r0;
    for (int tries = 0; cnt == 0 && tries < 60; tries++, r *= MPGM_SHAPE_GROWTH) {
      const int k = mpgm_kdtree_radius(tree, nd->x + MPGM_DIM * i, r, MPGM_SHAPE_MAXNODE, idx, d2);
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
  return 0;
}

int mpgm_gmm_grid_park(const mpgm_fe_view *v, gmm_grid *g, const mpgm_kdtree *tree, double r0,
                       mpgm_conn *c) {
  const mpgm_scene *s = v->scene;
  const mpgm_points *P = v->pts;
  mpgm_nodes *nd = v->nodes;
  const int n = nd->n;
  memcpy(nd->fix, g->fix0, MPGM_DIM * (size_t)n);
  memcpy(nd->ubar, g->ubar0, sizeof(double) * MPGM_DIM * (size_t)n);
  /* a free body node on an obstacle's plane or beyond it is parked
   * whatever its mass. On the plane counts (to round-off): the grid puts
   * body nodes on it at the start, and were they free in the first step
   * only, the body would drop onto the obstacle's layers in that step and
   * be held from the second on (docs/theory.md section 13, "nodes on the
   * plane") */
  const double on = 1e-9 * s->h;
  for (int i = 0; i < n; i++) {
    g->parked[i] = 0;
    for (int o = 0; o < s->nobstacle && g->eligible[i]; o++) {
      const mpgm_scene_obstacle *ob = &s->obstacles[o];
      g->parked[i] |= ob->side * (nd->x[MPGM_DIM * i + ob->axis] - ob->value) > -on;
    }
  }
  g->nparked = mpgm_light_nodes(c, P->n, P->mass, n, g->eligible, s->mesh_par.min_node_mass, g->mass, g->parked);
  /* a parked node is held where it is: lambda ubar = u at the step's load
   * factor */
  const double lam = v->lambda;
  for (int i = 0; i < n; i++) {
    if (!g->parked[i]) continue;
    for (int k = 0; k < MPGM_DIM; k++) {
      g->xs[MPGM_DIM * i + k] = nd->x[MPGM_DIM * i + k];
      g->us[MPGM_DIM * i + k] = nd->u[MPGM_DIM * i + k];
      nd->fix[MPGM_DIM * i + k] = 1;
      nd->ubar[MPGM_DIM * i + k] = lam > 0.0 ? nd->u[MPGM_DIM * i + k] / lam : 0.0;
    }
  }
  if (!g->nparked) return 0;
  MPGM_CALL(follow_weights(v->ctx, s, nd, g, tree, r0));
  return mpgm_light_drop(v->ctx, c, P->n + P->nprobe + P->nsurf, g->parked, P, v->cp, v->step,
                         s->mesh_par.min_node_mass);
}

void mpgm_gmm_grid_unpark(const mpgm_fe_view *v, gmm_grid *g) {
  mpgm_nodes *nd = v->nodes;
  const int move = v->fx->geometric;
  for (int i = 0; i < nd->n && g->nparked; i++) {
    if (!g->parked[i]) continue;
    double du[MPGM_DIM] = {0}, v[MPGM_DIM] = {0}, a[MPGM_DIM] = {0};
    for (int k = g->wptr[i]; k < g->wptr[i + 1]; k++) {
      const int J = g->widx[k];
      const double w = g->ww[k];
      for (int c = 0; c < MPGM_DIM; c++) {
        du[c] += w * nd->du[MPGM_DIM * J + c];
        v[c] += w * nd->v[MPGM_DIM * J + c];
        a[c] += w * nd->a[MPGM_DIM * J + c];
      }
    }
    for (int c = 0; c < MPGM_DIM; c++) {
      nd->du[MPGM_DIM * i + c] = du[c];
      nd->u[MPGM_DIM * i + c] = g->us[MPGM_DIM * i + c] + du[c];
      nd->x[MPGM_DIM * i + c] = g->xs[MPGM_DIM * i + c] + (move ? du[c] : 0.0);
      nd->v[MPGM_DIM * i + c] = v[c];
      nd->a[MPGM_DIM * i + c] = a[c];
    }
  }
}
