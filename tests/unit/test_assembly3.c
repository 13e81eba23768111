/* test_assembly3.c -- the assembled tangent in 3-D (core/assembly.c built
 * with MPGM_DIM = 3) against an independent dense assembly and against
 * central differences of the assembled residual: test_assembly.c's checks
 * on problems built without the scene reader (io/ has no 3-D build).
 *
 * Problems: a box [0, 1.8] x [0, 1.2] x [0, 1.1] of H8 cells, by the
 * UL-FEM front end mpgm_frontend_fem (mesh.h 0.6: 3 x 2 x 2 cells, 8
 * Gauss points each; x = 0 clamped, the face x = 1.8 held in z: a node
 * with some components numbered and not others), or by the MPM front end
 * mpgm_frontend_mpm with uGIMP or CPDI on the H8 grid (mesh.h 0.3, 8
 * points per cell, the light-node rule; z = 0 held in z, x = 0 in x: node
 * clouds, whose tangent is merged into K in batches without a map). After
 * mpgm_problem_create, begin_step and mpgm_pattern_build every component
 * gets a random increment du (free and fixed ones), then mpgm_eval_points
 * and mpgm_assemble(pb, 1).
 *
 *  (i)  sparse vs dense: the CSC (sorted unique rows, every non-zero of the
 *       dense matrix inside the pattern) equals, entry by entry, the dense
 *       tangent assembled here from pb->pts.sigma_t, D_t, vol_t, mass and
 *       pb->conn.g, N with B written out (rows xx, yy, zz, xy, yz, xz,
 *       engineering shear): B^T D B v + (g_I . sigma g_K) v I (finite) +
 *       M / (beta dt^2) (dynamic; consistent m N_I N_K I or lumped
 *       diag m N_I); it is symmetric; and the lift term of the first Newton
 *       iteration is R -= K_free,fixed lift.
 *  (ii) consistent tangent: -dR/d(du_j) by central differences of
 *       R = f_ext - f_int (- f_inertia) equals column j of K for every free
 *       dof; and it differs from the tangent without the geometric
 *       (dynamic) term by far more than the tolerance, so the check sees
 *       each term.
 * Kinematics small (linear_elastic) and finite (neo_hookean), analysis
 * static and dynamic. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core.h"
#include "mpgm_core_impl.h"
#include "mpgm_fem.h"
#include "mpgm_mpm.h"
#include "mpgm_test.h"
#include "support_csc.h"

#if MPGM_DIM != 3
#error "test_assembly3.c checks the 3-D assembly: build it with MPGM_DIM = 3"
#endif

/* Same sums in a different order: round-off of a few hundred products
 * (relative to max |K|). */
#define TOL_DENSE TEST_TOL4
/* Central differences of R: truncation O(e^2 R''') + rounding O(eps |f| / e). */
#define TOL_FD 1e-6
#define FD_STEP 1e-6 /* [m], against cells of 0.3-0.6 m and du ~ 1e-2 m */

static const double E_MOD = 7.31e6, NU = 0.2847, RHO = 1851.3;
/* dynamic: dt such that m / (beta dt^2) is comparable to the stiffness */
static const double DT = 8.53e-3;

/* Steps are never taken here: a tangent-making integrator without a step,
 * owning its linear system as the implicit one does. */
static int no_step_create(mpgm_problem *pb, void **self) {
  const int err = mpgm_linsys_create(pb);
  *self = pb->ls;
  return err;
}
static void no_step_destroy(void *self) { mpgm_linsys_destroy(self); }
static const mpgm_integrator_type no_step = {
    .name = "test-no-step", .implicit = 1, .create = no_step_create, .destroy = no_step_destroy};

typedef struct asm_case {
  const char *name;
  const char *mat;   /* linear_elastic (small) or neo_hookean (finite) */
  int dynamic, lumped;
  const char *shape; /* fe: UL-FEM; ugimp, cpdi: MPM on the grid */
} asm_case;

typedef struct world {
  mpgm_scene s;
  mpgm_material mat;
  mpgm_scene_body body;
  mpgm_scene_boundary bcs[2];
} world;

static void world_init(world *w, const asm_case *ac) {
  memset(w, 0, sizeof *w);
  mpgm_scene *s = &w->s;
  const int fem = strcmp(ac->shape, "fe") == 0;
  snprintf(s->file, sizeof s->file, "assembly3_%s.json", ac->name);
  s->shape = mpgm_shapefn_type_find(ac->shape);
  s->cell = MPGM_CELL_H8;
  s->h = fem ? 0.6 : 0.3;
  s->ppc = 8;
  s->mesh_par.min_node_mass = fem ? 0.0 : 1e-2;
  if (s->shape->grid_only) s->shape_par.half_width = s->h / (2.0 * cbrt((double)s->ppc));
  s->shape_par.h = s->h;
  const double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {1.8, 1.2, 1.1};
  const double bhi[3] = {0.9, 0.6, 0.6}; /* MPM: 3 x 2 x 2 cells of the grid */
  for (int d = 0; d < 3; d++) {
    s->dom_min[d] = fem ? lo[d] : -0.6;
    s->dom_max[d] = fem ? hi[d] : 1.5;
  }
  w->mat.type = mpgm_material_type_find(ac->mat);
  w->mat.density = RHO;
  w->mat.param[0] = E_MOD, w->mat.param[1] = NU;
  char msg[128];
  w->mat.type->setup(&w->mat, msg, sizeof msg);
  s->mats = &w->mat;
  s->nmat = 1;
  w->body.geometry = MPGM_GEOM_BOX;
  memcpy(w->body.min, lo, sizeof lo);
  memcpy(w->body.max, fem ? hi : bhi, sizeof hi);
  s->bodies = &w->body;
  s->nbody = 1;
  if (fem) {
    w->bcs[0] = (mpgm_scene_boundary){.select = MPGM_SELECT_X, .value = 0.0, .tol = 1e-9, .fix = {1, 1, 1}};
    w->bcs[1] = (mpgm_scene_boundary){.select = MPGM_SELECT_X, .value = 1.8, .tol = 1e-9, .fix = {0, 0, 1}};
  } else {
    w->bcs[0] = (mpgm_scene_boundary){.select = MPGM_SELECT_Z, .value = 0.0, .tol = 1e-9, .fix = {0, 0, 1}};
    w->bcs[1] = (mpgm_scene_boundary){.select = MPGM_SELECT_X, .value = 0.0, .tol = 1e-9, .fix = {1, 0, 0}};
  }
  s->bcs = w->bcs;
  s->nbc = 2;
  s->kinematics = strcmp(ac->mat, "linear_elastic") == 0 ? MPGM_KIN_SMALL : MPGM_KIN_FINITE;
  s->analysis = ac->dynamic ? MPGM_ANALYSIS_DYNAMIC : MPGM_ANALYSIS_STATIC;
  s->dt = DT;
  s->t_end = 100 * DT;
  s->load_steps = 1;
  s->beta = 0.25;
  s->gamma = 0.5;
  s->lumped_mass = ac->lumped;
  s->integrator = &no_step;
  s->solver = mpgm_solver_type_find("auto");
  s->solver_opts = mpgm_solver_opts_default();
  s->loop_threads = 2; /* the assembly's phases over more than one thread */
}

/* Tangent over all 3 nnode components (free and fixed), row major, from
 * the trial point state and the current gradients:
 *   K_IK = v B_I^T D B_K + geo v (g_I . sigma g_K) 1 + dyn M_IK / (beta dt^2) 1,
 * M_IK = m N_I N_K (consistent) or delta_IK m N_I (lumped). */
static void dense_tangent(const mpgm_problem *pb, int geo, int dyn, double *K) {
  const int nf = 3 * pb->nodes.n;
  const mpgm_points *P = &pb->pts;
  const mpgm_conn *C = &pb->conn;
  const double kdyn = 1.0 / (pb->scene->beta * pb->dt * pb->dt);
  const int lumped = pb->scene->lumped_mass;
  memset(K, 0, sizeof(double) * (size_t)nf * nf);
  for (int p = 0; p < P->n; p++) {
    const double *s = P->sigma_t + 6 * p, *D = P->D_t + 36 * p;
    const double S[3][3] = {{s[0], s[3], s[5]}, {s[3], s[1], s[4]}, {s[5], s[4], s[2]}};
    const double v = P->vol_t[p], m = P->mass[p];
    for (int a = C->ptr[p]; a < C->ptr[p + 1]; a++) {
      const double *ga = C->g + 3 * a;
      const double Ba[6][3] = {{ga[0], 0, 0}, {0, ga[1], 0}, {0, 0, ga[2]},
                               {ga[1], ga[0], 0}, {0, ga[2], ga[1]}, {ga[2], 0, ga[0]}};
      for (int b = C->ptr[p]; b < C->ptr[p + 1]; b++) {
        const double *gb = C->g + 3 * b;
        const double Bb[6][3] = {{gb[0], 0, 0}, {0, gb[1], 0}, {0, 0, gb[2]},
                                 {gb[1], gb[0], 0}, {0, gb[2], gb[1]}, {gb[2], 0, gb[0]}};
        double gsg = 0.0;
        for (int i = 0; i < 3; i++)
          for (int j = 0; j < 3; j++) gsg += ga[i] * S[i][j] * gb[j];
        const double mab = lumped ? (a == b ? m * C->N[a] : 0.0) : m * C->N[a] * C->N[b];
        for (int i = 0; i < 3; i++)
          for (int j = 0; j < 3; j++) {
            double k = 0.0;
            for (int q = 0; q < 6; q++)
              for (int l = 0; l < 6; l++) k += Ba[q][i] * D[6 * q + l] * Bb[l][j];
            k *= v;
            if (i == j && geo) k += v * gsg;
            if (i == j && dyn) k += kdyn * mab;
            K[(size_t)(3 * C->node[a] + i) * nf + 3 * C->node[b] + j] += k;
          }
      }
    }
  }
}

typedef struct bufs {
  double *Kf, *Kg, *Kd, *Kfd, *R0, *Rp, *Rm, *lift;
  unsigned char *in;
} bufs;

/* (i) the CSC against the dense tangent, its symmetry; returns max |K|
 * (0 when the structure is broken). */
static double check_dense(mpgm_problem *pb, bufs *B, const char *name) {
  const mpgm_nodes *nd = &pb->nodes;
  const int n = nd->ndof, nf = 3 * nd->n;
  if (csc_dense(&pb->ls->K, B->Kd, B->in, name)) return 0.0;
  dense_tangent(pb, pb->fx.geometric, pb->fx.inertia, B->Kf);
  double kmax = 0.0, emax = 0.0, amax = 0.0;
  int wi = -1, wj = -1, missing = 0;
  for (int I = 0; I < nf; I++)
    for (int J = 0; J < nf; J++) {
      const int i = nd->dof[I], j = nd->dof[J];
      if (i < 0 || j < 0) continue;
      const double k = B->Kf[(size_t)I * nf + J];
      kmax = fmax(kmax, fabs(k));
      if (k != 0.0 && !B->in[(size_t)i * n + j]) missing++;
      const double e = fabs(B->Kd[(size_t)i * n + j] - k);
      if (e > emax) emax = e, wi = i, wj = j;
      amax = fmax(amax, fabs(B->Kd[(size_t)i * n + j] - B->Kd[(size_t)j * n + i]));
    }
  mpgm_test(kmax > 0.0, "%s: non-zero tangent (max |K| = %.3g)", name, kmax);
  mpgm_test(missing == 0, "%s: CSC pattern holds every non-zero of the dense tangent (%d missing)",
            name, missing);
  mpgm_test_abs(emax / kmax, 0.0, TOL_DENSE,
                "%s: CSC = dense tangent, every entry (rel; worst at row %d, col %d)", name, wi, wj);
  mpgm_test(pb->ls->K.symmetric == 1, "%s: K flagged symmetric", name);
  mpgm_test_abs(amax / kmax, 0.0, TOL_DENSE, "%s: K symmetric (rel)", name);
  return kmax;
}

/* The lift of the first Newton iteration: R -= K_free,fixed lift. */
static void check_lift(mpgm_problem *pb, bufs *B, rng *r, double amp, const char *name) {
  const mpgm_nodes *nd = &pb->nodes;
  const int n = nd->ndof, nf = 3 * nd->n;
  for (int i = 0; i < nf; i++) B->lift[i] = uniform(r, -amp, amp);
  pb->ls->lift = B->lift;
  const int err = mpgm_assemble(pb, 1);
  pb->ls->lift = NULL;
  double lmax = 0.0, lref = 0.0, rmax = 0.0;
  for (int i = 0; i < n; i++) rmax = fmax(rmax, fabs(B->R0[i]));
  for (int I = 0; I < nf; I++) {
    const int i = nd->dof[I];
    if (i < 0) continue;
    double dR = 0.0;
    for (int J = 0; J < nf; J++)
      if (nd->dof[J] < 0) dR -= B->Kf[(size_t)I * nf + J] * B->lift[J];
    lmax = fmax(lmax, fabs(pb->ls->R[i] - B->R0[i] - dR));
    lref = fmax(lref, fabs(dR));
  }
  mpgm_test(err == 0 && lref > 0.0, "%s: assemble with a lift (%d)", name, err);
  mpgm_test_abs(lmax / (rmax + lref), 0.0, TOL_DENSE,
                "%s: lift adds -K_free,fixed lift to R (rel; max |dR| = %.3g N)", name, lref);
}

/* Static, without gravity: the support forces (mpgm_reactions) balance
 * the free components' residual in each direction, since sum_a grad N_a
 * = 0 at every point makes the internal forces sum to zero. */
static void check_reactions(mpgm_problem *pb, bufs *B, const char *name) {
  const mpgm_nodes *nd = &pb->nodes;
  const int nf = 3 * nd->n;
  double *r = B->lift; /* 3 nnode doubles, free again */
  const int err = mpgm_reactions(pb, r);
  double sum[3] = {0, 0, 0}, ref = 0.0, rmax = 0.0;
  for (int I = 0; I < nf; I++) {
    const int i = nd->dof[I];
    if (nd->fix[I]) sum[I % 3] += r[I], rmax = fmax(rmax, fabs(r[I]));
    else if (i >= 0) sum[I % 3] -= B->R0[i];
    if (i >= 0) ref = fmax(ref, fabs(B->R0[i]));
  }
  const double e = fmax(fabs(sum[0]), fmax(fabs(sum[1]), fabs(sum[2])));
  mpgm_test(err == 0 && rmax > 1e-3 * ref, "%s: support forces (max %.3g N)", name, rmax);
  mpgm_test_abs(e / ref, 0.0, TOL_DENSE, "%s: support forces balance the residual in x, y and z (rel)", name);
}

/* (ii) central differences of R(du), column by column; then the tangent
 * without each term against them. */
static void check_fd(mpgm_problem *pb, bufs *B, double kmax, const char *name) {
  mpgm_nodes *nd = &pb->nodes;
  const int n = nd->ndof, nf = 3 * nd->n;
  const double e = FD_STEP;
  int err = 0;
  for (int J = 0; J < nf && !err; J++) {
    const int j = nd->dof[J];
    if (j < 0) continue;
    const double du0 = nd->du[J];
    nd->du[J] = du0 + e;
    err = mpgm_eval_points(pb, 1);
    if (!err) err = mpgm_assemble(pb, 0);
    memcpy(B->Rp, pb->ls->R, sizeof(double) * n);
    nd->du[J] = du0 - e;
    if (!err) err = mpgm_eval_points(pb, 1);
    if (!err) err = mpgm_assemble(pb, 0);
    memcpy(B->Rm, pb->ls->R, sizeof(double) * n);
    nd->du[J] = du0;
    double cerr = 0.0;
    int wr = -1;
    for (int i = 0; i < n; i++) {
      B->Kfd[(size_t)i * n + j] = -(B->Rp[i] - B->Rm[i]) / (2.0 * e);
      const double d = fabs(B->Kfd[(size_t)i * n + j] - B->Kd[(size_t)i * n + j]);
      if (d > cerr) cerr = d, wr = i;
    }
    mpgm_test_abs(cerr / kmax, 0.0, TOL_FD,
                  "%s: column %d (node %d %c) of K = -dR/du by central differences (rel; worst "
                  "row %d)", name, j, J / 3, "xyz"[J % 3], wr);
  }
  mpgm_test(err == 0, "%s: residual evaluations (%d: %s)", name, err, pb->ctx->msg);
  for (int term = 0; term < 2; term++) { /* the check sees each term */
    if ((term == 0 && !pb->fx.geometric) || (term == 1 && !pb->fx.inertia)) continue;
    dense_tangent(pb, term == 0 ? 0 : pb->fx.geometric, term == 1 ? 0 : pb->fx.inertia, B->Kg);
    double dmax = 0.0;
    for (int I = 0; I < nf; I++)
      for (int J = 0; J < nf; J++) {
        const int i = nd->dof[I], j = nd->dof[J];
        if (i >= 0 && j >= 0) dmax = fmax(dmax, fabs(B->Kg[(size_t)I * nf + J] - B->Kfd[(size_t)i * n + j]));
      }
    mpgm_test(dmax / kmax > 1e3 * TOL_FD, "%s: the tangent without the %s term misses -dR/du (rel %.3g)",
              name, term == 0 ? "geometric" : "dynamic", dmax / kmax);
  }
}

static void run_case(const asm_case *ac, rng *r) {
  const char *name = ac->name;
  world w;
  world_init(&w, ac);
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_problem *pb = NULL;
  bufs B = {0};
  const int fem = strcmp(ac->shape, "fe") == 0;
  int err = mpgm_problem_create(&ctx, &w.s, fem ? &mpgm_frontend_fem : &mpgm_frontend_mpm, &pb);
  mpgm_test(err == 0, "%s: problem created (%d: %s)", name, err, ctx.msg);
  if (err) return;
  err = mpgm_begin_step(pb);
  mpgm_nodes_number(&pb->nodes); /* MPM: the step's nodes (implicit.c does the same) */
  if (!err) err = mpgm_pattern_build(pb);
  mpgm_test(err == 0, "%s: begin_step and pattern (%d: %s)", name, err, ctx.msg);
  if (err) goto done;
  mpgm_nodes *nd = &pb->nodes;
  const int n = nd->ndof, nf = 3 * nd->n;
  int single = 0; /* groups of one point (merged into the batch directly) */
  const mpgm_linsys *ls = pb->ls;
  for (int g = 0; g < ls->ngroups; g++) single += ls->grp_ptr[g + 1] - ls->grp_ptr[g] == 1;
  mpgm_test(n > 0 && n < nf && ls->K.n == n && ls->nomap == !fem,
            "%s: %d free of %d components, K is %d x %d, %s; %d groups of points, %d of one", name,
            n, nf, ls->K.n, ls->K.n, ls->nomap ? "merged in batches" : "scatter maps", ls->ngroups,
            single);
  const size_t nn = (size_t)n * n, ff = (size_t)nf * nf;
  B.Kf = malloc(sizeof(double) * ff);
  B.Kg = malloc(sizeof(double) * ff);
  B.Kd = malloc(sizeof(double) * nn);
  B.Kfd = malloc(sizeof(double) * nn);
  B.R0 = malloc(sizeof(double) * n);
  B.Rp = malloc(sizeof(double) * n);
  B.Rm = malloc(sizeof(double) * n);
  B.lift = malloc(sizeof(double) * nf);
  B.in = malloc(nn);
  if (!B.Kf || !B.Kg || !B.Kd || !B.Kfd || !B.R0 || !B.Rp || !B.Rm || !B.lift || !B.in) {
    mpgm_test(0, "%s: test allocations", name);
    goto done;
  }
  /* a random state: every component moves (fixed ones: a prescribed increment) */
  const double amp = pb->fx.geometric ? 1.1e-2 : 2.3e-3;
  for (int i = 0; i < nf; i++) {
    nd->du[i] = uniform(r, -amp, amp);
    nd->v[i] = uniform(r, -0.37, 0.37);
    nd->a[i] = uniform(r, -4.1, 4.1);
  }
  err = mpgm_eval_points(pb, 1);
  if (!err) err = mpgm_assemble(pb, 1);
  mpgm_test(err == 0, "%s: eval_points and assemble (%d: %s)", name, err, ctx.msg);
  if (err) goto done;
  memcpy(B.R0, pb->ls->R, sizeof(double) * n);
  double smax[2] = {0.0, 0.0}; /* normal and shear stresses */
  for (int p = 0; p < pb->pts.n; p++)
    for (int i = 0; i < 6; i++) smax[i >= 3] = fmax(smax[i >= 3], fabs(pb->pts.sigma_t[6 * p + i]));
  mpgm_test(fmin(smax[0], smax[1]) > 1e-4 * E_MOD * amp,
            "%s: non-trivial stress state (max |sigma| normal %.3g Pa, shear %.3g Pa)", name, smax[0],
            smax[1]);
  const double kmax = check_dense(pb, &B, name);
  if (kmax == 0.0) goto done;
  if (!pb->fx.inertia) check_reactions(pb, &B, name);
  check_lift(pb, &B, r, amp, name);
  check_fd(pb, &B, kmax, name);
done:
  free(B.Kf), free(B.Kg), free(B.Kd), free(B.Kfd), free(B.R0), free(B.Rp), free(B.Rm), free(B.lift);
  free(B.in);
  mpgm_problem_destroy(&pb);
}

int main(void) {
  const asm_case cases[] = {
      {"fem_small_linear_elastic_static", "linear_elastic", 0, 0, "fe"},
      {"fem_small_linear_elastic_dynamic", "linear_elastic", 1, 0, "fe"},
      {"fem_finite_neo_hookean_static", "neo_hookean", 0, 0, "fe"},
      {"fem_finite_neo_hookean_dynamic", "neo_hookean", 1, 0, "fe"},
      {"fem_finite_neo_hookean_dynamic_lumped", "neo_hookean", 1, 1, "fe"},
      {"mpm_ugimp_finite_neo_hookean_dynamic", "neo_hookean", 1, 0, "ugimp"},
      {"mpm_ugimp_small_linear_elastic_static", "linear_elastic", 0, 0, "ugimp"},
      {"mpm_cpdi_finite_neo_hookean_static", "neo_hookean", 0, 0, "cpdi"},
      {"mpm_cpdi_finite_neo_hookean_dynamic_lumped", "neo_hookean", 1, 1, "cpdi"},
  };
  rng r = {0x9E3779B97F4A7C15ULL};
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) run_case(&cases[i], &r);
  return mpgm_test_summary();
}
