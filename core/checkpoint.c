/* checkpoint.c -- the state a run continues from, between two steps
 * (mpgm_problem_save / mpgm_problem_restore, docs/architecture.md
 * "Checkpoints"). What a step rebuilds from this state (the connectivity,
 * the pattern, the scatter maps, the factorisation, the kd-tree, the
 * parked nodes) is not saved: it is rebuilt the same way, so a restored run
 * continues bit for bit as the run that wrote the checkpoint did.
 *
 * Saved: the step and its control, the Newton record, the run's tallies;
 * every committed array of the points (material points, probes, surface
 * points) and of the nodes; the contact state at surface points; the
 * context's work counters; then the front end's, the solver's own state.
 *
 * A checkpoint is input like a scene: every count, index and scalar read
 * back is checked against the scene and the problem before a step can
 * index with it (a material index out of range would be a crash two steps
 * later, a negative count an allocation of every byte), so that a damaged
 * or crafted file is refused with the section that is wrong. The CRC of
 * each section (base/blob.c) finds damage; these checks make the reader
 * safe whatever the bytes. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_blob.h"
#include "mpgm_core_impl.h"

/* The scalars of the problem, in one section. */
typedef struct core_state {
  double t, dt, lambda;
  long step, newton_total, step_cuts, contact_rounds;
  mpgm_newton_info last;
  mpgm_stepper sp;
  int npts[4]; /* n, nprobe, nsurf, nstate: the layout the arrays have */
  int nodes[3]; /* cap, n, ndof */
} core_state;

/* One array of the points or nodes: put (save) or get (restore). */
typedef struct arr {
  const char *tag;
  void *p;
  size_t bytes;
  int finite; /**< doubles, each finite in any state a run reaches */
} arr;

static int points_arrays(mpgm_points *P, arr *a) {
  const size_t m = (size_t)(P->n + P->nprobe + P->nsurf), d = sizeof(double);
  int k = 0;
  a[k++] = (arr){"pts.x", P->x, MPGM_DIM * m * d, 1};
  a[k++] = (arr){"pts.x0", P->x0, MPGM_DIM * m * d, 1};
  a[k++] = (arr){"pts.u", P->u, MPGM_DIM * m * d, 1};
  a[k++] = (arr){"pts.v", P->v, MPGM_DIM * m * d, 1};
  a[k++] = (arr){"pts.a", P->a, MPGM_DIM * m * d, 1};
  a[k++] = (arr){"pts.mass", P->mass, m * d, 1};
  a[k++] = (arr){"pts.vol0", P->vol0, m * d, 1};
  a[k++] = (arr){"pts.vol", P->vol, m * d, 1};
  a[k++] = (arr){"pts.F", P->F, MPGM_TENSOR * m * d, 1};
  a[k++] = (arr){"pts.sigma", P->sigma, MPGM_NSTRESS * m * d, 1};
  a[k++] = (arr){"pts.S0", P->S0, MPGM_NSTRESS * m * d, 1};
  a[k++] = (arr){"pts.r0", P->r0, MPGM_TENSOR * m * d, 1};
  a[k++] = (arr){"pts.L", P->L, MPGM_TENSOR * m * d, 1};
  a[k++] = (arr){"pts.state", P->state, (size_t)P->nstate * m * d, 1};
  a[k++] = (arr){"pts.mat", P->mat, m * sizeof(int), 0};
  a[k++] = (arr){"pts.body", P->body, m * sizeof(int), 0};
  a[k++] = (arr){"pts.id", P->id, m * sizeof(int), 0};
  return k;
}

static int nodes_arrays(mpgm_nodes *nd, arr *a) {
  const size_t c = (size_t)nd->cap, v = MPGM_DIM * c * sizeof(double);
  int k = 0;
  a[k++] = (arr){"nodes.mass", nd->mass, c * sizeof(double), 1};
  a[k++] = (arr){"nodes.X", nd->X, v, 1};
  a[k++] = (arr){"nodes.x", nd->x, v, 1};
  a[k++] = (arr){"nodes.u", nd->u, v, 1};
  a[k++] = (arr){"nodes.v", nd->v, v, 1};
  a[k++] = (arr){"nodes.a", nd->a, v, 1};
  a[k++] = (arr){"nodes.fix", nd->fix, MPGM_DIM * c, 0};
  a[k++] = (arr){"nodes.contact", nd->contact, c, 0};
  a[k++] = (arr){"nodes.ubar", nd->ubar, v, 1};
  a[k++] = (arr){"nodes.dof", nd->dof, MPGM_DIM * c * sizeof(int), 0};
  return k;
}

/* Contact at surface points: who is held where, the run's tallies. */
static int cpoints_arrays(mpgm_cpoints *cp, arr *a) {
  int k = 0;
  a[k++] = (arr){"cp.plane", cp->plane, (size_t)cp->n, 0};
  a[k++] = (arr){"cp.anchor", cp->anchor, MPGM_DIM * (size_t)cp->n * sizeof(double), 1};
  a[k++] = (arr){"cp.held", &cp->held, sizeof cp->held, 0};
  a[k++] = (arr){"cp.holds", &cp->holds, sizeof cp->holds, 0};
  a[k++] = (arr){"cp.releases", &cp->releases, sizeof cp->releases, 0};
  a[k++] = (arr){"cp.unenforced", &cp->unenforced, sizeof cp->unenforced, 0};
  return k;
}

/* Every array section of the problem, in file order. */
static int all_arrays(mpgm_problem *pb, arr *a) {
  int k = points_arrays(&pb->pts, a);
  k += nodes_arrays(&pb->nodes, a + k);
  if (pb->fx.contact_points) k += cpoints_arrays(&pb->cp, a + k);
  a[k++] = (arr){"ctx.count", pb->ctx->count, sizeof pb->ctx->count, 0};
  a[k++] = (arr){"energy.work_int", &pb->work_int, sizeof pb->work_int, 1};
  a[k++] = (arr){"energy.work_ext", &pb->work_ext, sizeof pb->work_ext, 1};
  if (pb->scene->kinetic_damping)
    a[k++] = (arr){"energy.ke_last", &pb->ke_last, sizeof pb->ke_last, 1};
  return k;
}

/* What a step rebuilds when it is not there: the equation numbers, the
 * point groups and node graph, the pattern and its scatter maps, the
 * solver's analysis (UMFPACK's depends on the values of the matrix it
 * sees first) and the factorisation. A restored problem has none; the run
 * that wrote the checkpoint drops them too, so both build them anew from
 * the same state at the next step and continue alike. */
void mpgm_problem_drop_rebuilt(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  if (!ls) return; /* explicit: nothing is rebuilt */
  ls->pattern_version = -1;
  ls->graph_version = -1;
  ls->solver->analysed = 0;
  ls->factor_valid = 0;
}

int mpgm_problem_save(const mpgm_problem *cpb, mpgm_blob *b) {
  mpgm_problem *pb = (mpgm_problem *)cpb; /* the arrays are only read */
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_points *P = &pb->pts;
  core_state cs;
  memset(&cs, 0, sizeof cs); /* padding too: the same state, the same bytes */
  cs.t = pb->t, cs.dt = pb->dt, cs.lambda = pb->lambda, cs.step = pb->step;
  cs.newton_total = pb->newton_total, cs.step_cuts = pb->step_cuts;
  cs.contact_rounds = pb->contact_rounds, cs.last = pb->last, cs.sp = pb->sp;
  const int npts[4] = {P->n, P->nprobe, P->nsurf, P->nstate};
  const int nodes[3] = {pb->nodes.cap, pb->nodes.n, pb->nodes.ndof};
  memcpy(cs.npts, npts, sizeof npts);
  memcpy(cs.nodes, nodes, sizeof nodes);
  MPGM_CALL(mpgm_blob_put(ctx, b, "core", &cs, sizeof cs));
  arr a[40];
  const int k = all_arrays(pb, a);
  for (int i = 0; i < k; i++) MPGM_CALL(mpgm_blob_put(ctx, b, a[i].tag, a[i].p, a[i].bytes));
  if (pb->fe->save) MPGM_CALL(pb->fe->save(pb->fe_data, ctx, b));
  return pb->ls ? mpgm_solver_save(pb->ls->solver, ctx, b) : 0; /* explicit: none */
}

/* ---- checks of what is read back ---------------------------------------- */

/* A tally a run only adds to may be read back up to this: room for any
 * run's additions (LONG_MAX would overflow at the next). */
#define TALLY_MAX (LONG_MAX / 2)

/* The finite arrays among a[0..k), each of items entries: the first `use`
 * of them must hold finite doubles only (nodes past those in use hold what
 * an earlier step left: nothing reads them). */
static int check_finite(mpgm_ctx *ctx, const arr *a, int k, size_t items, size_t use,
                        const char *what) {
  for (int i = 0; i < k; i++) {
    if (!a[i].finite || !items || !a[i].bytes) continue;
    const double *x = a[i].p;
    const size_t w = a[i].bytes / sizeof(double) / items;
    for (size_t e = 0; e < w * use; e++)
      MPGM_CHECK(ctx, isfinite(x[e]), MPGM_ERR_INPUT,
                 "checkpoint: section '%s': %s %zu holds %g, "
                 "not a finite number",
                 a[i].tag, what, e / w, x[e]);
  }
  return 0;
}

/* The scalars of section "core": the layout this scene makes, the step
 * control as this scene starts it (end, first step) and as a run can have
 * left it, before any of it is used. */
static int check_core(const mpgm_problem *pb, const core_state *cs) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *s = pb->scene;
  const mpgm_points *P = &pb->pts;
  const int npts[4] = {P->n, P->nprobe, P->nsurf, P->nstate};
  MPGM_CHECK(ctx, memcmp(cs->npts, npts, sizeof npts) == 0 && cs->nodes[0] == pb->nodes.cap,
             MPGM_ERR_INPUT,
             "checkpoint: %d points, %d probes, %d surface points, %d nodes; this "
             "scene makes %d, %d, %d, %d (another scene)",
             cs->npts[0], cs->npts[1], cs->npts[2], cs->nodes[0], npts[0], npts[1], npts[2],
             pb->nodes.cap);
  const int n = cs->nodes[1], ndof = cs->nodes[2];
  /* nodes that persist (GMM, FEM) are those the scene made; a grid's (MPM)
   * are any of it */
  MPGM_CHECK(ctx, n >= 0 && n <= pb->nodes.cap && (!pb->fe->persistent_nodes || n == pb->nodes.n),
             MPGM_ERR_INPUT, "checkpoint: section 'core': %d nodes in use; this scene has %d%s", n,
             pb->fe->persistent_nodes ? pb->nodes.n : pb->nodes.cap,
             pb->fe->persistent_nodes ? "" : " at most");
  MPGM_CHECK(ctx, ndof >= 0 && ndof <= MPGM_DIM * n, MPGM_ERR_INPUT,
             "checkpoint: section 'core': %d equations for %d nodes", ndof, n);
  MPGM_CHECK(ctx,
             cs->step >= 0 && cs->step < INT_MAX && cs->newton_total >= 0 &&
                 cs->newton_total <= TALLY_MAX && cs->step_cuts >= 0 &&
                 cs->step_cuts <= TALLY_MAX && cs->contact_rounds >= 0 &&
                 cs->contact_rounds <= TALLY_MAX && cs->last.iterations >= 0 &&
                 cs->last.nhist >= 0 &&
                 cs->last.nhist <= (int)(sizeof cs->last.hist / sizeof *cs->last.hist),
             MPGM_ERR_INPUT,
             "checkpoint: section 'core': a count out of range (step %ld, Newton "
             "iterations %ld, step cuts %ld, contact rounds %ld, %d residuals)",
             cs->step, cs->newton_total, cs->step_cuts, cs->contact_rounds, cs->last.nhist);
  const mpgm_stepper *sp = &cs->sp;
  const int dyn = s->analysis != MPGM_ANALYSIS_STATIC;
  double end, dt0;
  mpgm_run_span(s, &end, &dt0);
  MPGM_CHECK(ctx, sp->end == end && sp->dt0 == dt0, MPGM_ERR_INPUT,
             "checkpoint: section 'core': "
             "a run to %.17g in steps of %.17g; this scene runs to %.17g in steps of %.17g",
             sp->end, sp->dt0, end, dt0);
  /* the steps counted since a cut and the wait for a growth: at most 2^21
   * in any run (run.c), far below where a count would overflow */
  MPGM_CHECK(ctx,
             sp->dt_now > 0.0 && sp->dt_now <= dt0 && sp->level >= 0 && sp->level <= s->max_cuts &&
                 sp->easy >= 0 && sp->easy <= 1 << 30 && sp->wait >= 0 && sp->wait <= 1 << 30 &&
                 (sp->grown == 0 || sp->grown == 1) && sp->nout >= 0 && sp->nout <= s->ntimes,
             MPGM_ERR_INPUT,
             "checkpoint: section 'core': step control out of range (step %.17g "
             "of at most %.17g, %d cuts of at most %d, %d easy steps, wait %d, grown %d, %d output "
             "times passed of %d)",
             sp->dt_now, dt0, sp->level, s->max_cuts, sp->easy, sp->wait, sp->grown, sp->nout,
             s->ntimes);
  MPGM_CHECK(ctx,
             isfinite(cs->t) && cs->t >= 0.0 && cs->t <= end && isfinite(cs->dt) && cs->dt > 0.0 &&
                 isfinite(cs->lambda),
             MPGM_ERR_INPUT,
             "checkpoint: section 'core': %s %.17g (0 to %.17g), %s %.17g, load factor %.17g",
             dyn ? "time" : "load factor at the start", cs->t, end, dyn ? "step" : "increment",
             cs->dt, cs->lambda);
  return 0;
}

/* Materials, bodies and ids of the points: what every step indexes with. */
static int check_point_ids(mpgm_ctx *ctx, const mpgm_problem *pb) {
  const mpgm_scene *s = pb->scene;
  const mpgm_points *P = &pb->pts;
  const int m = P->n + P->nprobe + P->nsurf;
  for (int p = 0; p < m; p++) {
    MPGM_CHECK(ctx, P->mat[p] >= 0 && P->mat[p] < s->nmat, MPGM_ERR_INPUT,
               "checkpoint: section "
               "'pts.mat': point %d has material %d; the scene has %d (0 to %d)",
               p, P->mat[p], s->nmat, s->nmat - 1);
    MPGM_CHECK(ctx, P->body[p] >= 0 && P->body[p] < s->nbody, MPGM_ERR_INPUT,
               "checkpoint: "
               "section 'pts.body': point %d is of body %d; the scene has %d (0 to %d)",
               p, P->body[p], s->nbody, s->nbody - 1);
    /* material points are made of their body's material (a tracer's is unused) */
    const int mat = p < P->n ? s->bodies[P->body[p]].material : P->mat[p];
    MPGM_CHECK(ctx, P->mat[p] == mat, MPGM_ERR_INPUT,
               "checkpoint: section 'pts.mat': point %d has "
               "material %d, its body \"%s\" is of material %d",
               p, P->mat[p], s->bodies[P->body[p]].name, mat);
    /* tracers keep their place, material points move (ids stay with them) */
    MPGM_CHECK(ctx, p < P->n ? P->id[p] >= 0 && P->id[p] < P->n : P->id[p] == p, MPGM_ERR_INPUT,
               "checkpoint: section 'pts.id': point %d has id %d (%s)", p, P->id[p],
               p < P->n ? "the material points' are 0 to n - 1" : "a tracer's is its place");
  }
  unsigned char *seen = calloc((size_t)P->n + 1, 1);
  MPGM_CHECK(ctx, seen, MPGM_ERR_NOMEM, "out of memory (checkpoint of %d points)", P->n);
  int dup = -1;
  for (int p = 0; p < P->n && dup < 0; p++) {
    if (seen[P->id[p]]) dup = p;
    seen[P->id[p]] = 1;
  }
  free(seen);
  MPGM_CHECK(ctx, dup < 0, MPGM_ERR_INPUT,
             "checkpoint: section 'pts.id': point %d has id %d, "
             "which another point has",
             dup, dup >= 0 ? P->id[dup] : 0);
  return 0;
}

/* Fixity, contact codes and equation numbers of the nodes in use. */
static int check_node_dofs(mpgm_ctx *ctx, const mpgm_problem *pb) {
  const mpgm_nodes *nd = &pb->nodes;
  for (int i = 0; i < nd->n; i++)
    MPGM_CHECK(ctx, nd->contact[i] >= -MPGM_DIM && nd->contact[i] <= MPGM_DIM, MPGM_ERR_INPUT,
               "checkpoint: section 'nodes.contact': node %d has contact code %d (0, or +-1 to "
               "+-%d)",
               i, nd->contact[i], MPGM_DIM);
  int k = 0;
  for (int i = 0; i < MPGM_DIM * nd->n; i++) {
    MPGM_CHECK(ctx, nd->fix[i] <= 1, MPGM_ERR_INPUT,
               "checkpoint: section 'nodes.fix': node %d "
               "component %d has fixity %d (0 or 1)",
               i / MPGM_DIM, i % MPGM_DIM, nd->fix[i]);
    /* implicit runs number the equations of the nodes as they are fixed
     * (mpgm_nodes_number); explicit runs solve none, keep none up to date
     * and read none */
    if (!pb->fx.tangent) continue;
    const int e = nd->dof[i];
    MPGM_CHECK(ctx, e >= -1 && e < nd->ndof, MPGM_ERR_INPUT,
               "checkpoint: section 'nodes.dof': "
               "node %d component %d has equation %d (-1, or 0 to %d)",
               i / MPGM_DIM, i % MPGM_DIM, e, nd->ndof - 1);
    const int want = nd->fix[i] && !nd->contact[i / MPGM_DIM] ? -1 : k++;
    MPGM_CHECK(ctx, e == want, MPGM_ERR_INPUT,
               "checkpoint: section 'nodes.dof': node %d "
               "component %d has equation %d; its fixity numbers it %d",
               i / MPGM_DIM, i % MPGM_DIM, e, want);
  }
  MPGM_CHECK(ctx, !pb->fx.tangent || k == nd->ndof, MPGM_ERR_INPUT,
             "checkpoint: section "
             "'nodes.dof': %d equations numbered, section 'core' says %d",
             k, nd->ndof);
  return 0;
}

/* Contact at surface points: each held on a boundary that holds points. */
static int check_cpoints(mpgm_ctx *ctx, const mpgm_problem *pb) {
  const mpgm_cpoints *cp = &pb->cp;
  const mpgm_scene *s = pb->scene;
  int held = 0;
  for (int t = 0; t < cp->n; t++) {
    const int b = cp->plane[t];
    MPGM_CHECK(ctx, b == -1 || (b >= 0 && b < s->nbc && mpgm_bc_at_points(&s->bcs[b])),
               MPGM_ERR_INPUT,
               "checkpoint: section 'cp.plane': surface point %d is held on "
               "boundary %d, not one of the scene's %d with contact at points",
               t, b, s->nbc);
    held += b >= 0;
  }
  MPGM_CHECK(ctx,
             cp->held == held && cp->holds >= 0 && cp->holds <= TALLY_MAX && cp->releases >= 0 &&
                 cp->releases <= TALLY_MAX && cp->unenforced >= 0 && cp->unenforced <= TALLY_MAX,
             MPGM_ERR_INPUT,
             "checkpoint: section 'cp.held': %d surface points held, 'cp.plane' "
             "holds %d (holds %ld, releases %ld, unenforced %ld)",
             cp->held, held, cp->holds, cp->releases, cp->unenforced);
  return 0;
}

/* Everything the arrays of the problem were read into. */
static int check_arrays(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_points *P = &pb->pts;
  arr a[40];
  int k = points_arrays(&pb->pts, a);
  const size_t m = (size_t)(P->n + P->nprobe + P->nsurf);
  MPGM_CALL(check_finite(ctx, a, k, m, m, "point"));
  MPGM_CALL(check_point_ids(ctx, pb));
  k = nodes_arrays(&pb->nodes, a);
  MPGM_CALL(check_finite(ctx, a, k, (size_t)pb->nodes.cap, (size_t)pb->nodes.n, "node"));
  MPGM_CALL(check_node_dofs(ctx, pb));
  if (pb->fx.contact_points) {
    k = cpoints_arrays(&pb->cp, a);
    MPGM_CALL(check_finite(ctx, a, k, (size_t)pb->cp.n, (size_t)pb->cp.n, "surface point"));
    MPGM_CALL(check_cpoints(ctx, pb));
  }
  for (int i = 0; i < MPGM_C_COUNT; i++)
    MPGM_CHECK(ctx, ctx->count[i] >= 0 && ctx->count[i] <= TALLY_MAX, MPGM_ERR_INPUT,
               "checkpoint: section 'ctx.count': count "
               "%s is %ld",
               mpgm_counter_name(i), ctx->count[i]);
  k = all_arrays(pb, a);
  for (int i = 0; i < k; i++) /* the energy tallies: one double each */
    if (a[i].finite && a[i].bytes == sizeof(double))
      MPGM_CALL(check_finite(ctx, a + i, 1, 1, 1, "value"));
  return 0;
}

int mpgm_problem_restore(mpgm_problem *pb, mpgm_blob *b) {
  mpgm_ctx *ctx = pb->ctx;
  core_state cs;
  MPGM_CALL(mpgm_blob_get(ctx, b, "core", &cs, sizeof cs));
  MPGM_CALL(check_core(pb, &cs));
  pb->t = cs.t, pb->dt = cs.dt, pb->lambda = cs.lambda, pb->step = cs.step;
  pb->newton_total = cs.newton_total, pb->step_cuts = cs.step_cuts;
  pb->contact_rounds = cs.contact_rounds, pb->last = cs.last, pb->sp = cs.sp;
  pb->nodes.n = cs.nodes[1], pb->nodes.ndof = cs.nodes[2];
  arr a[40];
  const int k = all_arrays(pb, a);
  for (int i = 0; i < k; i++) MPGM_CALL(mpgm_blob_get(ctx, b, a[i].tag, a[i].p, a[i].bytes));
  MPGM_CALL(check_arrays(pb));
  if (pb->fe->restore) {
    mpgm_fe_view v;
    mpgm_problem_view(pb, &v);
    MPGM_CALL(pb->fe->restore(pb->fe_data, &v, b));
  }
  if (pb->ls) MPGM_CALL(mpgm_solver_restore(pb->ls->solver, ctx, b));
  mpgm_problem_drop_rebuilt(pb);
  pb->resumed = 1;
  return 0;
}
