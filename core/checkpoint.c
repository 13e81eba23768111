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
 * context's work counters; then the front end's, the solver's own state. */
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
} arr;

static int points_arrays(mpgm_points *P, arr *a) {
  const size_t m = (size_t)(P->n + P->nprobe + P->nsurf), d = sizeof(double);
  int k = 0;
  a[k++] = (arr){"pts.x", P->x, MPGM_DIM * m * d};
  a[k++] = (arr){"pts.x0", P->x0, MPGM_DIM * m * d};
  a[k++] = (arr){"pts.u", P->u, MPGM_DIM * m * d};
  a[k++] = (arr){"pts.v", P->v, MPGM_DIM * m * d};
  a[k++] = (arr){"pts.a", P->a, MPGM_DIM * m * d};
  a[k++] = (arr){"pts.mass", P->mass, m * d};
  a[k++] = (arr){"pts.vol0", P->vol0, m * d};
  a[k++] = (arr){"pts.vol", P->vol, m * d};
  a[k++] = (arr){"pts.F", P->F, MPGM_TENSOR * m * d};
  a[k++] = (arr){"pts.sigma", P->sigma, MPGM_NSTRESS * m * d};
  a[k++] = (arr){"pts.S0", P->S0, MPGM_NSTRESS * m * d};
  a[k++] = (arr){"pts.r0", P->r0, 2 * MPGM_DIM * m * d};
  a[k++] = (arr){"pts.L", P->L, MPGM_TENSOR * m * d};
  a[k++] = (arr){"pts.state", P->state, (size_t)P->nstate * m * d};
  a[k++] = (arr){"pts.mat", P->mat, m * sizeof(int)};
  a[k++] = (arr){"pts.body", P->body, m * sizeof(int)};
  a[k++] = (arr){"pts.id", P->id, m * sizeof(int)};
  return k;
}

static int nodes_arrays(mpgm_nodes *nd, arr *a) {
  const size_t c = (size_t)nd->cap, v = MPGM_DIM * c * sizeof(double);
  int k = 0;
  a[k++] = (arr){"nodes.mass", nd->mass, c * sizeof(double)};
  a[k++] = (arr){"nodes.X", nd->X, v};
  a[k++] = (arr){"nodes.x", nd->x, v};
  a[k++] = (arr){"nodes.u", nd->u, v};
  a[k++] = (arr){"nodes.v", nd->v, v};
  a[k++] = (arr){"nodes.a", nd->a, v};
  a[k++] = (arr){"nodes.fix", nd->fix, MPGM_DIM * c};
  a[k++] = (arr){"nodes.contact", nd->contact, c};
  a[k++] = (arr){"nodes.ubar", nd->ubar, v};
  a[k++] = (arr){"nodes.dof", nd->dof, MPGM_DIM * c * sizeof(int)};
  return k;
}

/* Contact at surface points: who is held where, the run's tallies. */
static int cpoints_arrays(mpgm_cpoints *cp, arr *a) {
  int k = 0;
  a[k++] = (arr){"cp.plane", cp->plane, (size_t)cp->n};
  a[k++] = (arr){"cp.anchor", cp->anchor, MPGM_DIM * (size_t)cp->n * sizeof(double)};
  a[k++] = (arr){"cp.held", &cp->held, sizeof cp->held};
  a[k++] = (arr){"cp.holds", &cp->holds, sizeof cp->holds};
  a[k++] = (arr){"cp.releases", &cp->releases, sizeof cp->releases};
  a[k++] = (arr){"cp.unenforced", &cp->unenforced, sizeof cp->unenforced};
  return k;
}

/* Every array section of the problem, in file order. */
static int all_arrays(mpgm_problem *pb, arr *a) {
  int k = points_arrays(&pb->pts, a);
  k += nodes_arrays(&pb->nodes, a + k);
  if (pb->fx.contact_points) k += cpoints_arrays(&pb->cp, a + k);
  a[k++] = (arr){"ctx.count", pb->ctx->count, sizeof pb->ctx->count};
  a[k++] = (arr){"energy.work_int", &pb->work_int, sizeof pb->work_int};
  a[k++] = (arr){"energy.work_ext", &pb->work_ext, sizeof pb->work_ext};
  if (pb->scene->kinetic_damping) a[k++] = (arr){"energy.ke_last", &pb->ke_last, sizeof pb->ke_last};
  return k;
}

/* What a step rebuilds when it is not there: the equation numbers, the
 * point groups and node graph, the pattern and its scatter maps, the
 * solver's analysis (UMFPACK's depends on the values of the matrix it
 * sees first) and the factorisation. A restored problem has none; the run
 * that wrote the checkpoint drops them too, so both build them anew from
 * the same state at the next step and continue alike. */
void mpgm_problem_drop_rebuilt(mpgm_problem *pb) {
  pb->pattern_version = -1;
  pb->graph_version = -1;
  if (pb->solver) pb->solver->analysed = 0;
  pb->factor_valid = 0;
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
  return pb->solver ? mpgm_solver_save(pb->solver, ctx, b) : 0; /* explicit: none */
}

int mpgm_problem_restore(mpgm_problem *pb, mpgm_blob *b) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_points *P = &pb->pts;
  core_state cs;
  MPGM_CALL(mpgm_blob_get(ctx, b, "core", &cs, sizeof cs));
  const int npts[4] = {P->n, P->nprobe, P->nsurf, P->nstate};
  MPGM_CHECK(ctx, memcmp(cs.npts, npts, sizeof npts) == 0 && cs.nodes[0] == pb->nodes.cap,
             MPGM_ERR_INPUT, "checkpoint: %d points, %d probes, %d surface points, %d nodes; this "
             "scene makes %d, %d, %d, %d (another scene)", cs.npts[0], cs.npts[1], cs.npts[2],
             cs.nodes[0], npts[0], npts[1], npts[2], pb->nodes.cap);
  pb->t = cs.t, pb->dt = cs.dt, pb->lambda = cs.lambda, pb->step = cs.step;
  pb->newton_total = cs.newton_total, pb->step_cuts = cs.step_cuts;
  pb->contact_rounds = cs.contact_rounds, pb->last = cs.last, pb->sp = cs.sp;
  pb->nodes.n = cs.nodes[1], pb->nodes.ndof = cs.nodes[2];
  arr a[40];
  const int k = all_arrays(pb, a);
  for (int i = 0; i < k; i++) MPGM_CALL(mpgm_blob_get(ctx, b, a[i].tag, a[i].p, a[i].bytes));
  if (pb->fe->restore) MPGM_CALL(pb->fe->restore(pb->fe_data, ctx, b));
  if (pb->solver) MPGM_CALL(mpgm_solver_restore(pb->solver, ctx, b));
  mpgm_problem_drop_rebuilt(pb);
  pb->resumed = 1;
  return 0;
}
