/* problem.c -- a problem: a scene with its front end, integrator and
 * solver; the narrow view front ends see of it, and what it reports. */
#include <stdlib.h>
#include <string.h>

#include "mpgm_core_impl.h"


void mpgm_problem_view(mpgm_problem *pb, mpgm_fe_view *v) {
  *v = (mpgm_fe_view){.ctx = pb->ctx,
                      .scene = pb->scene,
                      .fx = &pb->fx,
                      .pts = &pb->pts,
                      .nodes = &pb->nodes,
                      .conn = &pb->conn,
                      .pool = pb->pool,
                      .cp = pb->fx.contact_points ? &pb->cp : NULL,
                      .step = pb->step,
                      .t = pb->t,
                      .dt = pb->dt,
                      .lambda = mpgm_load_factor(pb)};
}

/* Geostatic initial stress of the material points of bodies that have it,
 * vertical the axis v of gravity's largest component (y in a plane scene
 * under gravity along y, z in a 3-D one along z): sigma_vv = rho g_v
 * (surface - x_v), the other normal stresses k0 sigma_vv, no shear. A
 * material with state carries it as its own (plasticity must see the whole
 * stress); otherwise it is the initial stress S0 the assembly adds. */
static int initial_stress(mpgm_problem *pb) {
  const mpgm_scene *scene = pb->scene;
  mpgm_points *P = &pb->pts;
  const int v = mpgm_scene_vertical(scene);
  for (int p = 0; p < P->n; p++) {
    const mpgm_scene_body *b = &scene->bodies[P->body[p]];
    if (!b->geostatic) continue;
    const double svv = scene->mats[b->material].density * scene->gravity[v] *
                       (b->surface - P->x0[MPGM_DIM * p + v]);
    double s0[MPGM_NSTRESS] = {0}; /* the normal stresses, plane strain's zz too */
    for (int c = 0; c < MPGM_NSTRESS; c++)
      if (c < MPGM_DIM || (MPGM_DIM == 2 && c == MPGM_NSTRESS - 1)) s0[c] = c == v ? svv : b->k0 * svv;
    const mpgm_material *m = &scene->mats[b->material];
    memcpy(P->sigma + MPGM_NSTRESS * p, s0, sizeof s0);
    if (!m->type->init_stress || !P->nstate) {
      memcpy(P->S0 + MPGM_NSTRESS * p, s0, sizeof s0);
      continue;
    }
    char msg[256] = "";
    if (m->type->init_stress(m, scene->kinematics, s0, P->state + (size_t)P->nstate * p, msg,
                             sizeof msg))
    {
      char at[MPGM_POINT_STR];
      MPGM_ERROR(pb->ctx, MPGM_ERR_INPUT, "%s: bodies.%s: geostatic initial stress at %s: %s",
                 scene->file, b->name, mpgm_point_str(P->x0 + MPGM_DIM * p, at), msg);
    }
  }
  return 0;
}

/* Everything after the allocation of the problem itself. */
static int setup(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *scene = pb->scene;
  mpgm_fe_view v;
  mpgm_problem_view(pb, &v);
  mpgm_timer_start(ctx, MPGM_T_SHAPE);
  const int err = pb->fe->create(&v, &pb->fe_data);
  mpgm_timer_stop(ctx, MPGM_T_SHAPE);
  MPGM_CALL(err);
  if (pb->fx.prestress) MPGM_CALL(initial_stress(pb));
#if MPGM_DIM == 2 /* the manufactured solutions are plane strain (MPGM_MMS_FORCES) */
  if (pb->fx.manufactured) MPGM_CALL(mpgm_mms_setup(pb));
#endif
  mpgm_nodes_number(&pb->nodes);
  /* the integrator's own data: the implicit one's linear system, sized
   * by the node capacity the front end has now set (an explicit run
   * solves nothing and creates no solver: a scene shared with implicit
   * runs may name PETSc, which is then not loaded, nor MPI) */
  if (pb->integ->create) MPGM_CALL(pb->integ->create(pb, &pb->integ_data));
  /* the springs of contact at points are forces of t_n+1 only */
  MPGM_CHECK(ctx, !(pb->fx.contact_points && scene->hht_alpha != 0.0), MPGM_ERR_INPUT,
             "%s: time.hht_alpha: not with contact at surface points (their spring forces are "
             "not weighted between t_n and t_n+1); use newmark_beta and newmark_gamma",
             scene->file);
#if MPGM_DIM == 2 /* contact is plane strain (MPGM_MMS_FORCES) */
  if (pb->fx.contact_points) MPGM_CALL(mpgm_cpoints_setup(pb));
#endif
  MPGM_CHECK(ctx, pb->nodes.n == 0 || pb->nodes.ndof > 0, MPGM_ERR_INPUT,
             "%s: boundaries: every degree of freedom is fixed; nothing to solve", scene->file);
  return 0;
}

int mpgm_problem_create(mpgm_ctx *ctx, const mpgm_scene *scene, const mpgm_frontend_type *fe,
                        mpgm_problem **out) {
  *out = NULL;
  if (!fe) fe = scene->frontend;
  MPGM_CHECK(ctx, fe && scene->integrator, MPGM_ERR_INTERNAL, "%s: no front end or integrator",
             scene->file);
  mpgm_problem *pb;
  MPGM_ALLOC(ctx, pb, 1);
  pb->ctx = ctx;
  pb->scene = scene;
  /* the scene's step (the run loop may cut it): time step, or load
   * increment in static analysis (t then counts the load factor) */
  pb->dt = scene->analysis != MPGM_ANALYSIS_STATIC ? scene->dt : 1.0 / scene->load_steps;
  pb->fe = fe;
  pb->integ = scene->integrator;
  /* effects: decided once, when the scene loads */
  mpgm_effects_of_scene(scene, &pb->fx);
  mpgm_solver_threads(scene->threads);
  /* mpgm's own loops: worker threads live as long as the problem */
  /* threads 0: one per core, the cores shared among the run's processes
   * on this machine (mpiexec -n 2 on two cores: one each) */
  int nt = scene->loop_threads;
  if (nt <= 0 && ctx->comm && ctx->comm->local > 1) {
    nt = mpgm_ncores() / ctx->comm->local;
    nt = nt < 1 ? 1 : nt;
  }
  int err = mpgm_pool_create(ctx, nt, &pb->pool);
  if (!err) err = setup(pb);
  if (err) {
    mpgm_problem_destroy(&pb);
    return err;
  }
  *out = pb;
  return 0;
}

void mpgm_problem_destroy(mpgm_problem **pp) {
  if (!pp || !*pp) return;
  mpgm_problem *pb = *pp;
  if (pb->integ && pb->integ->destroy) pb->integ->destroy(pb->integ_data);
  if (pb->fe && pb->fe->destroy) pb->fe->destroy(pb->fe_data);
  mpgm_points_free(&pb->pts);
  mpgm_nodes_free(&pb->nodes);
  mpgm_conn_release(&pb->conn);
  free(pb->mms_b);
  mpgm_pool_destroy(&pb->pool);
#if MPGM_DIM == 2
  mpgm_cpoints_free(&pb->cp);
#endif
  free(pb);
  *pp = NULL;
}

const mpgm_scene *mpgm_problem_scene(const mpgm_problem *pb) { return pb->scene; }
const mpgm_effects *mpgm_problem_effects(const mpgm_problem *pb) { return &pb->fx; }
const mpgm_points *mpgm_problem_points(const mpgm_problem *pb) { return &pb->pts; }
const mpgm_nodes *mpgm_problem_nodes(const mpgm_problem *pb) { return &pb->nodes; }

int mpgm_problem_cells(const mpgm_problem *pb, mpgm_cells *out) {
  memset(out, 0, sizeof *out);
  if (!pb->fe->cells) return 0;
  pb->fe->cells(pb->fe_data, out);
  return 1;
}

int mpgm_problem_background(const mpgm_problem *pb, mpgm_background *out) {
  memset(out, 0, sizeof *out);
  if (!pb->fe->background) return 0;
  pb->fe->background(pb->fe_data, out);
  return 1;
}

void mpgm_problem_report(const mpgm_problem *pb, mpgm_report *r) {
  memset(r, 0, sizeof *r);
  r->step = pb->step;
  r->t = pb->t;
  r->dt = pb->dt;
  r->lambda = pb->lambda;
  r->last = pb->last;
  r->newton_total = pb->newton_total;
  r->step_cuts = pb->step_cuts;
  r->contact_resolves = pb->contact_rounds;
  r->nodes = pb->nodes.n;
  r->ndof = pb->nodes.ndof;
  const mpgm_linsys *ls = pb->ls;
  r->nnz = ls ? ls->K.nnz : 0;
  mpgm_cells c;
  mpgm_problem_cells(pb, &c);
  r->ncells = c.n;
  r->threads = mpgm_pool_size(pb->pool);
  mpgm_solver *sv = ls ? ls->solver : NULL;
  r->solver = sv ? mpgm_solver_name(sv) : "none";
  r->solver_iterative = sv && sv->type->iterative;
  r->have_solver_stats = sv && mpgm_solver_get_stats(sv, &r->solver_stats) == 0;
  if (pb->fx.contact_points) {
    r->contact_points = pb->cp.n;
    r->contact_points_held = pb->cp.held;
    r->contact_point_holds = pb->cp.holds;
    r->contact_point_releases = pb->cp.releases;
    r->contact_points_unenforced = pb->cp.unenforced;
  }
}
