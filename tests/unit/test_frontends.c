/* test_frontends.c -- conformance of every front end of the list
 * (mpgm_frontend_types()) with every shape kind it accepts (its traits),
 * on scenes built in memory: a front end added to the list is tested here
 * without editing this file.
 *
 * For each front end x shape kind x cell kind (quad, tri):
 *   1. after begin_step, sum N = 1 and sum grad N = 0 at every material
 *      point and probe (partition of unity: rigid motions cause no strain);
 *   2. mass and momentum projected through the connectivity (m_I =
 *      sum_p N_Ip m_p) equal the points' to round-off, and so do the
 *      nodes' own masses and momenta where the front end projects them;
 *   3. the connectivity version changes only when the pattern does: a
 *      second begin_step with nothing moved keeps the version (and the
 *      lists are then identical); after the points moved (a tenth of the
 *      way to their centroid), lists that differ come with a new version
 *      or new map version, and a kept version means the same pattern
 *      (node count and coupled node pairs);
 *   4. after a converged step, a step that fails (Newton limited to one
 *      iteration) leaves the points (by id) and persistent nodes exactly
 *      as before (rollback);
 *   5. the implicit problem owns a linear system with a solver; the same
 *      scene explicit (time.analysis "explicit", max_iter 0 below) has
 *      none: an explicit run allocates no tangent, vectors nor solver.
 *
 * Tolerances: the sums run over at most MPGM_SHAPE_MAXNODE O(1) terms;
 * LME reproduces to its Newton tolerance 1e-10, so TOL_PU = 1e-9 (grad N
 * scaled by h). Mass and momentum totals: TEST_TOL4 relative (sums over
 * ~1000 points of the same sign). */
#include "mpgm_core_impl.h"
#include "mpgm_frontends.h"
#include "mpgm_scene_io.h"
#include "mpgm_test.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TOL_PU 1e-9
#define H 0.2

/* The first body geometry fe accepts, as a scene body: a block resting on
 * the left edge of the domain, with an initial velocity (momentum). */
static const char *body_for(const mpgm_frontend_type *fe) {
  if (fe->geometries & (1u << MPGM_GEOM_RECTANGLE))
    return "{\"material\": \"m\", \"velocity\": [0.731, -0.219], "
           "\"rectangle\": {\"min\": [0.0, 0.2], \"max\": [1.6, 1.0]}}";
  if (fe->geometries & (1u << MPGM_GEOM_DISK))
    return "{\"material\": \"m\", \"velocity\": [0.731, -0.219], "
           "\"disk\": {\"centre\": [0.8, 0.6], \"radius\": 0.5}}";
  return "{\"material\": \"m\", \"velocity\": [0.731, -0.219], "
         "\"polygon\": {\"points\": [[0.0, 0.2], [1.6, 0.2], [1.2, 1.0], [0.0, 1.0]]}}";
}

/* The scene of a combination (dynamic, gravity, clamped at x = 0 where
 * the body meets the domain's edge; max_iter: Newton's limit, 0 for the
 * scene explicit). */
static int make_scene(mpgm_ctx *ctx, const mpgm_frontend_type *fe, const mpgm_shapefn_type *sh,
                      const char *cell, int max_iter, mpgm_scene **out) {
  /* the time step at which a step takes several Newton iterations */
  char text[2048], time[160];
  if (max_iter > 0)
    snprintf(time, sizeof time, "\"time\": {\"analysis\": \"dynamic\", \"dt\": 0.01, "
             "\"end\": 0.05}, \"solver\": {\"max_iterations\": %d},", max_iter);
  else
    snprintf(time, sizeof time, "\"time\": {\"analysis\": \"explicit\", \"dt\": 1e-4, "
             "\"end\": 1e-3},");
  snprintf(text, sizeof text,
           "{\"method\": \"%s\", \"shape\": {\"kind\": \"%s\"},"
           " \"mesh\": {\"h\": %g, \"cell\": \"%s\", \"layout\": \"%s\","
           " \"domain\": {\"min\": [0, 0], \"max\": [2.4, 1.6]}},"
           " %s"
           " \"materials\": {\"m\": {\"type\": \"neo_hookean\", \"density\": 2385.7, \"E\": 3.1e6, "
           "\"nu\": 0.287}},"
           " \"bodies\": [%s], \"boundaries\": [{\"x\": 0.0, \"fix\": [\"x\", \"y\"]}],"
           " \"gravity\": [0.0, -9.81], \"probes\": {\"in\": [0.9137, 0.5713]},"
           " \"output\": {\"vtk\": \"none\"}}",
           fe->name, sh->name, H, cell, sh->grid_only ? "centres" : "gauss", time, body_for(fe));
  cJSON *j = cJSON_Parse(text);
  if (!j) return mpgm_err_set(ctx, MPGM_ERR_INTERNAL, __FILE__, __LINE__, "bad test scene JSON");
  char name[96];
  snprintf(name, sizeof name, "frontends/%s-%s-%s", fe->name, sh->name, cell);
  const int err = mpgm_scene_load_json(ctx, name, j, out);
  cJSON_Delete(j);
  return err;
}

/* 1: partition of unity at every material point and probe. */
static void check_unity(const char *what, const mpgm_problem *pb) {
  const mpgm_conn *C = &pb->conn;
  const int m = pb->pts.n + pb->pts.nprobe;
  double worst = 0.0, worst_g = 0.0;
  int empty = 0;
  for (int p = 0; p < m; p++) {
    double s = 0.0, g[MPGM_DIM] = {0};
    empty += C->ptr[p + 1] == C->ptr[p];
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      s += C->N[k];
      for (int d = 0; d < MPGM_DIM; d++) g[d] += C->dN[MPGM_DIM * k + d];
    }
    worst = fmax(worst, fabs(s - 1.0));
    for (int d = 0; d < MPGM_DIM; d++) worst_g = fmax(worst_g, fabs(g[d]) * H);
  }
  mpgm_test(empty == 0 && worst <= TOL_PU && worst_g <= TOL_PU,
            "%s: sum N = 1 (worst %.2e) and sum grad N = 0 (worst %.2e h^-1) at %d points and "
            "probes, %d without nodes", what, worst, worst_g, m, empty);
}

/* 2: mass and momentum projected through the connectivity, and the
 * nodes' own where the front end projects them. */
static void check_projection(const char *what, const mpgm_problem *pb) {
  const mpgm_conn *C = &pb->conn;
  const mpgm_points *P = &pb->pts;
  const mpgm_nodes *nd = &pb->nodes;
  double mp = 0.0, qp[MPGM_DIM] = {0}, mc = 0.0, qc[MPGM_DIM] = {0};
  for (int p = 0; p < P->n; p++) {
    mp += P->mass[p];
    for (int d = 0; d < MPGM_DIM; d++) qp[d] += P->mass[p] * P->v[MPGM_DIM * p + d];
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      mc += C->N[k] * P->mass[p];
      for (int d = 0; d < MPGM_DIM; d++) qc[d] += C->N[k] * P->mass[p] * P->v[MPGM_DIM * p + d];
    }
  }
  mpgm_test_rel(mc, mp, TEST_TOL4, "%s: mass through the connectivity = the points' %.6g kg", what, mp);
  for (int d = 0; d < MPGM_DIM; d++)
    mpgm_test_rel(qc[d], qp[d], TEST_TOL4, "%s: momentum %c through the connectivity = the points' %.6g",
                  what, "xyz"[d], qp[d]);
  double mn = 0.0, qn[MPGM_DIM] = {0};
  for (int i = 0; i < nd->n; i++) {
    mn += nd->mass[i];
    for (int d = 0; d < MPGM_DIM; d++) qn[d] += nd->mass[i] * nd->v[MPGM_DIM * i + d];
  }
  if (mn == 0.0) return; /* persistent nodes carry their own history, no projection */
  mpgm_test_rel(mn, mp, TEST_TOL4, "%s: the nodes' projected mass = the points' %.6g kg", what, mp);
  for (int d = 0; d < MPGM_DIM; d++)
    mpgm_test_rel(qn[d], qp[d], TEST_TOL4, "%s: the nodes' projected momentum %c = the points' %.6g",
                  what, "xyz"[d], qp[d]);
}

/* A copy of the connectivity's lists (ptr and node), its versions, the
 * node count and the pattern: which node pairs some point couples. */
typedef struct lists {
  int np, nnz, nnode, version, map_version;
  int *ptr, *node;
  unsigned char *pairs; /* nnode x nnode */
} lists;

static void lists_take(const mpgm_problem *pb, lists *l) {
  const mpgm_conn *C = &pb->conn;
  free(l->ptr);
  free(l->node);
  free(l->pairs);
  l->np = C->np;
  l->nnz = C->ptr[C->np];
  l->nnode = pb->nodes.n;
  l->version = C->version;
  l->map_version = C->map_version;
  l->ptr = malloc(sizeof(int) * (size_t)(l->np + 1));
  l->node = malloc(sizeof(int) * (size_t)(l->nnz + 1));
  l->pairs = calloc((size_t)l->nnode * l->nnode + 1, 1);
  if (l->ptr) memcpy(l->ptr, C->ptr, sizeof(int) * (size_t)(l->np + 1));
  if (l->node) memcpy(l->node, C->node, sizeof(int) * (size_t)l->nnz);
  for (int p = 0; l->pairs && p < pb->pts.n; p++)
    for (int a = C->ptr[p]; a < C->ptr[p + 1]; a++)
      for (int b = C->ptr[p]; b < C->ptr[p + 1]; b++)
        l->pairs[(size_t)C->node[a] * l->nnode + C->node[b]] = 1;
}

static void lists_free(lists *l) {
  free(l->ptr);
  free(l->node);
  free(l->pairs);
}

static int lists_same(const lists *a, const lists *b) {
  return a->np == b->np && a->nnz == b->nnz && a->nnode == b->nnode && a->ptr && b->ptr && a->node &&
         b->node && memcmp(a->ptr, b->ptr, sizeof(int) * (size_t)(a->np + 1)) == 0 &&
         memcmp(a->node, b->node, sizeof(int) * (size_t)a->nnz) == 0;
}

static int end_step(mpgm_problem *pb) {
  if (!pb->fe->end_step) return 0;
  mpgm_fe_view v;
  mpgm_problem_view(pb, &v);
  return pb->fe->end_step(pb->fe_data, &v);
}

/* 3: the connectivity version follows the pattern. */
static void check_versions(const char *what, mpgm_problem *pb) {
  lists a = {0}, b = {0}, c = {0};
  int err = mpgm_begin_step(pb);
  if (!err) lists_take(pb, &a);
  if (!err) err = end_step(pb);
  if (!err) err = mpgm_begin_step(pb);
  if (!err) lists_take(pb, &b);
  mpgm_test(!err && b.version == a.version && lists_same(&a, &b),
            "%s: begin_step again with nothing moved: version %d -> %d, same lists (%s)", what,
            a.version, b.version, err ? pb->ctx->msg : "ok");
  if (!err) err = end_step(pb);
  /* every point moved a tenth of the way to the points' centroid (they
   * stay inside the body: meshfree functions need the nodes' hull) */
  mpgm_points *P = &pb->pts;
  double xc[MPGM_DIM] = {0};
  for (int p = 0; p < P->n; p++)
    for (int d = 0; d < MPGM_DIM; d++) xc[d] += P->x[MPGM_DIM * p + d] / P->n;
  for (int p = 0; p < P->n + P->nprobe; p++)
    for (int d = 0; d < MPGM_DIM; d++) P->x[MPGM_DIM * p + d] += 0.1 * (xc[d] - P->x[MPGM_DIM * p + d]);
  if (!err) err = mpgm_begin_step(pb);
  if (!err) lists_take(pb, &c);
  const int differ = !lists_same(&b, &c);
  const int new_pattern = c.version != b.version, new_maps = c.map_version != b.map_version;
  const int same_pattern = b.nnode == c.nnode && b.pairs && c.pairs &&
                           memcmp(b.pairs, c.pairs, (size_t)b.nnode * b.nnode) == 0;
  mpgm_test(!err && (!differ || new_pattern || new_maps) && (new_pattern || same_pattern),
            "%s: points moved: lists %s, pattern %s; version %d -> %d, map version %d -> %d (%s)",
            what, differ ? "differ" : "same", same_pattern ? "the same" : "new", b.version,
            c.version, b.map_version, c.map_version, err ? pb->ctx->msg : "ok");
  lists_free(&a);
  lists_free(&b);
  lists_free(&c);
}

/* The committed state of the points, in id order, and of the nodes. */
typedef struct state {
  int np, nn;
  double *pts; /* per id: x, u, v, a (2 each), vol, F (4), sigma (4), state */
  double *nodes; /* per node: X, x, u, v, a (2 each) */
} state;

static int state_take(const mpgm_problem *pb, state *s) {
  const mpgm_points *P = &pb->pts;
  const mpgm_nodes *nd = &pb->nodes;
  const int w = 4 * MPGM_DIM + 1 + MPGM_TENSOR + MPGM_NSTRESS + P->nstate, wn = 5 * MPGM_DIM;
  s->np = P->n;
  s->nn = nd->n;
  s->pts = calloc((size_t)w * P->n + 1, sizeof(double));
  s->nodes = calloc((size_t)wn * nd->n + 1, sizeof(double));
  if (!s->pts || !s->nodes) return -1;
  for (int p = 0; p < P->n; p++) {
    double *r = s->pts + (size_t)w * P->id[p];
    const double *src[4] = {P->x, P->u, P->v, P->a};
    for (int a = 0; a < 4; a++) memcpy(r + MPGM_DIM * a, src[a] + MPGM_DIM * p, sizeof(double) * MPGM_DIM);
    r[4 * MPGM_DIM] = P->vol[p];
    memcpy(r + 4 * MPGM_DIM + 1, P->F + MPGM_TENSOR * p, sizeof(double) * MPGM_TENSOR);
    memcpy(r + 4 * MPGM_DIM + 1 + MPGM_TENSOR, P->sigma + MPGM_NSTRESS * p, sizeof(double) * MPGM_NSTRESS);
    if (P->nstate)
      memcpy(r + 4 * MPGM_DIM + 1 + MPGM_TENSOR + MPGM_NSTRESS, P->state + (size_t)P->nstate * p,
             sizeof(double) * (size_t)P->nstate);
  }
  for (int i = 0; i < nd->n; i++) {
    const double *src[5] = {nd->X, nd->x, nd->u, nd->v, nd->a};
    for (int a = 0; a < 5; a++)
      memcpy(s->nodes + (size_t)wn * i + MPGM_DIM * a, src[a] + MPGM_DIM * i, sizeof(double) * MPGM_DIM);
  }
  return 0;
}

/* 4: a failed step rolls back (after a converged first step: the initial
 * acceleration, part of the state at t = 0, is made by the first step). */
static void check_rollback(const char *what, mpgm_scene *s, mpgm_problem *pb) {
  state before = {0}, after = {0};
  int err = mpgm_step(pb);
  mpgm_test(!err, "%s: the first step converges (%s)", what, err ? pb->ctx->msg : "ok");
  if (err) return;
  const int e0 = state_take(pb, &before);
  const long steps = pb->step;
  s->max_iter = 1; /* Newton cannot converge in one iteration */
  err = mpgm_step(pb);
  const int e1 = state_take(pb, &after);
  const size_t w = 4 * MPGM_DIM + 1 + MPGM_TENSOR + MPGM_NSTRESS + pb->pts.nstate;
  const int same_pts = !e0 && !e1 && before.np == after.np &&
                       memcmp(before.pts, after.pts, sizeof(double) * w * (size_t)before.np) == 0;
  /* a grid reset every step has no nodes to keep */
  const int same_nodes = !pb->fe->persistent_nodes ||
                         (!e0 && !e1 && before.nn == after.nn &&
                          memcmp(before.nodes, after.nodes,
                                 sizeof(double) * 5 * MPGM_DIM * (size_t)before.nn) == 0);
  mpgm_test(err > 0 && pb->step == steps && same_pts && same_nodes,
            "%s: a step that fails (%d: %.60s) leaves the points%s exactly as before", what, err,
            pb->ctx->msg, pb->fe->persistent_nodes ? " and nodes" : "");
  mpgm_err_clear(pb->ctx);
  free(before.pts);
  free(before.nodes);
  free(after.pts);
  free(after.nodes);
}

/* 5: the scene explicit has no linear system (where the front end and
 * shape kind run explicit; otherwise the loader refuses the scene). */
static int nexplicit; /* combinations checked explicit */
static void check_explicit(const mpgm_frontend_type *fe, const mpgm_shapefn_type *sh,
                           const char *cell, const char *what) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene *s = NULL;
  mpgm_problem *pb = NULL;
  if (make_scene(&ctx, fe, sh, cell, 0, &s)) return;
  const int err = mpgm_problem_create(&ctx, s, NULL, &pb);
  mpgm_test(!err, "%s explicit: problem made (%s)", what, err ? ctx.msg : "ok");
  nexplicit++;
  if (!err) {
    mpgm_report r;
    mpgm_problem_report(pb, &r);
    mpgm_test(!pb->ls && r.nnz == 0 && strcmp(r.solver, "none") == 0,
              "%s explicit: no linear system, no solver (%s)", what, r.solver);
  }
  mpgm_problem_destroy(&pb);
  mpgm_scene_destroy(&s);
}

static void check_combination(const mpgm_frontend_type *fe, const mpgm_shapefn_type *sh,
                              const char *cell) {
  char what[96];
  snprintf(what, sizeof what, "%s / %s / %s", fe->name, sh->name, cell);
  for (int pass = 0; pass < 2; pass++) {
    mpgm_ctx ctx;
    mpgm_ctx_init(&ctx);
    mpgm_scene *s = NULL;
    mpgm_problem *pb = NULL;
    /* pass 0: checks 1-3; pass 1: rollback (4) */
    int err = make_scene(&ctx, fe, sh, cell, 25, &s);
    if (!err) err = mpgm_problem_create(&ctx, s, NULL, &pb);
    mpgm_test(!err && pb->fe == fe, "%s: problem made (%s)", what, err ? ctx.msg : "ok");
    if (!err && pass == 0) {
      err = mpgm_begin_step(pb);
      mpgm_test(!err, "%s: begin_step (%s)", what, err ? ctx.msg : "ok");
      if (!err) check_unity(what, pb);
      if (!err) check_projection(what, pb);
      if (!err) err = end_step(pb);
      if (!err) check_versions(what, pb);
    }
    if (!err && pass == 1) check_rollback(what, s, pb);
    if (!err) mpgm_test(pb->ls && pb->ls->solver, "%s: the implicit problem has its linear system",
                        what);
    mpgm_problem_destroy(&pb);
    mpgm_scene_destroy(&s);
  }
  check_explicit(fe, sh, cell, what);
}

/* A communicator of two processes whose collectives are never called: the
 * load's check only asks its size. */
static int no_reduce(void *impl, mpgm_reduce op, double *v, int n) {
  (void)impl, (void)op, (void)v, (void)n;
  return -1;
}

/* 6: on two processes a scene loads when the front end runs its analysis
 * on many (mpgm_frontend_type.processes), and is otherwise refused at
 * load, on the key "method", naming the method and the analysis. */
static void check_processes(const mpgm_frontend_type *fe) {
  const mpgm_shapefn_type *const *t = mpgm_shapefn_types(), *sh = NULL;
  for (int k = 0; t[k] && !sh; k++) /* the first kind it takes */
    if (fe->shapes & (t[k]->needs_cell ? MPGM_FE_SHAPE_CELL : MPGM_FE_SHAPE_CLOUD) &&
        !(t[k]->grid_only && fe->persistent_nodes) && !t[k]->velocity_ls)
      sh = t[k];
  const mpgm_comm two = {.rank = 1, .size = 2, .allreduce = no_reduce};
  for (int expl = 0; expl < 2; expl++) {
    if (expl && !fe->explicit_schemes) continue;
    mpgm_ctx ctx;
    mpgm_ctx_init(&ctx);
    ctx.comm = &two;
    mpgm_scene *s = NULL;
    const int err = make_scene(&ctx, fe, sh, "quad", expl ? 0 : 25, &s);
    const unsigned bit = expl ? MPGM_FE_MANY_EXPLICIT : MPGM_FE_MANY_IMPLICIT;
    char want[160];
    snprintf(want, sizeof want, ": method: method %s runs its %s analyses on one process only so "
             "far, and this run was started on 2", fe->name, expl ? "explicit" : "implicit");
    if (fe->processes & bit)
      mpgm_test(err == 0, "%s %s on 2 processes: loads (%s)", fe->name, expl ? "explicit" : "implicit",
                ctx.msg);
    else
      mpgm_test(err == MPGM_ERR_INPUT && strstr(ctx.msg, want), "%s %s on 2 processes: refused at "
                "load (%s)", fe->name, expl ? "explicit" : "implicit", ctx.msg);
    mpgm_scene_destroy(&s);
  }
}

int main(void) {
  const mpgm_frontend_type *const *fe = mpgm_frontend_types();
  const mpgm_shapefn_type *const *sh = mpgm_shapefn_types();
  static const char *const cells[] = {"quad", "tri"};
  int nfe = 0, ncomb = 0;
  for (; fe[nfe]; nfe++) {
    mpgm_test(mpgm_frontend_type_find(fe[nfe]->name) == fe[nfe] && fe[nfe]->create &&
                  fe[nfe]->destroy && fe[nfe]->begin_step && fe[nfe]->shapes && fe[nfe]->geometries,
              "%s: found by name; create, destroy, begin_step; takes some shape and geometry",
              fe[nfe]->name);
    check_processes(fe[nfe]);
    for (int k = 0; sh[k]; k++) {
      const unsigned need = sh[k]->needs_cell ? MPGM_FE_SHAPE_CELL : MPGM_FE_SHAPE_CLOUD;
      if (!(fe[nfe]->shapes & need)) continue;
      /* a grid-only kind (uGIMP): the background grid of a grid-reset
       * front end, square cells with points at their sub-cell centres
       * (the other front ends refuse it, tests/scripts/explicit.sh) */
      if (sh[k]->grid_only && fe[nfe]->persistent_nodes) continue;
      /* a kind that replaces the projected velocity of an explicit usl
       * step (CPLS) has no implicit problem to make (tests/scripts/mms.sh) */
      if (sh[k]->velocity_ls) continue;
      for (int c = 0; c < (sh[k]->grid_only ? 1 : 2); c++, ncomb++)
        check_combination(fe[nfe], sh[k], cells[c]);
    }
  }
  mpgm_test(nfe >= 3 && ncomb >= 3 * 2, "%d front ends, %d combinations of front end, shape kind "
            "and cell", nfe, ncomb);
  mpgm_test(nexplicit >= 6, "%d of them checked explicit too", nexplicit);
  return mpgm_test_summary();
}
