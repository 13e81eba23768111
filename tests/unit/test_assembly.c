/* test_assembly.c -- the assembled tangent against an independent dense
 * assembly and against central differences of the assembled residual.
 *
 * Problems: a 4 x 3 mesh on [0, 2.385] x [0, 1.7], Q4 and T3, built either
 * by this file's front end (interior nodes moved randomly by up to 0.2 h,
 * nodes at x = 0 fixed, the bottom-right node fixed in y) or by the UL-FEM
 * front end mpgm_frontend_fem (regular mesh, a scene boundary clamping
 * x = 0). After mpgm_problem_create, begin_step and mpgm_pattern_build, all
 * nodes get a random increment du (free and fixed components), then
 * mpgm_eval_points and mpgm_assemble(pb, 1).
 *
 *  (i)  sparse vs dense: the CSC (sorted unique rows, every non-zero of the
 *       dense matrix inside the pattern) equals, entry by entry, the dense
 *       tangent assembled here from pb->pts.sigma_t, D_t, vol_t, mass and
 *       pb->conn.g, N: B^T D B v + (g_I . sigma g_K) v I (finite)
 *       + m N_I N_K / (beta dt^2) I (dynamic); it is symmetric; and the
 *       lift term of the first Newton iteration is R -= K_free,fixed lift.
 *  (ii) consistent tangent: -dR/d(du_j) by central differences of
 *       R = f_ext - f_int (- f_inertia) (mpgm_eval_points +
 *       mpgm_assemble(pb, 0)) equals column j of K for every free dof;
 *       and it differs from the tangent without the geometric (dynamic)
 *       term by far more than the tolerance, so the check sees each term.
 * Kinematics small (linear_elastic) and finite (neo_hookean), analysis
 * static and dynamic (pb->dt = time.dt of the scene).
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include "mpgm_core_impl.h"
#include "mpgm_core.h"
#include "mpgm_scene_io.h"
#include "mpgm_discretisation.h"
#include "mpgm_fem.h"
#include "mpgm_gmm.h"
#include "mpgm_test.h"
#include "support_csc.h"
#include "support_mesh.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Same sums in a different order: round-off of a few hundred products. */
#define TOL_DENSE 1e-12
/* Central differences of R: truncation O(e^2 R''') + rounding O(eps |f| / e). */
#define TOL_FD 1e-6
#define FD_STEP 1e-6 /* [m], against cells of ~0.6 m and du ~ 1e-2 m */

static const double LX = 2.385, LY = 1.7; /* domain [0, LX] x [0, LY] [m] */
static const double E_MOD = 7.31e6, NU = 0.2847, RHO = 1851.3;
/* dynamic: dt such that m / (beta dt^2) is comparable to the stiffness */
static const double DT = 8.53e-3, T_END = 1.7;

/* ---- the test's front end: distorted structured mesh ---------------------- */
/* (same as in test_patch.c, with the fixity of a clamped block) */

/* What the front end builds. mpgm_problem_create calls setup before the
 * caller can attach data, so the configuration is the test program's own
 * file-level state, set before each problem is created. */
typedef struct mesh_cfg {
  int nx, ny;        /**< cells in x and y                         */
  double jitter;     /**< interior node moves, fraction of h        */
  uint64_t seed;     /**< of the node moves                         */
} mesh_cfg;
static mesh_cfg cfg;

/* The distorted mesh goes through mpgm_fem_setup_mesh, the same path as the
 * UL-FEM front end; only the fixity is the test's own. */
static int mesh_create(const mpgm_fe_view *v, void **self) {
  MPGM_CALL(support_distorted_mesh(v, cfg.nx, cfg.ny, LX, LY, cfg.jitter, cfg.seed, (mpgm_fem_cells **)self));
  /* fixity: clamped at x = 0, bottom-right node on a roller */
  mpgm_nodes *nd = v->nodes;
  const int nx = cfg.nx, ny = cfg.ny;
  for (int j = 0; j <= ny; j++) nd->fix[2 * (j * (nx + 1))] = nd->fix[2 * (j * (nx + 1)) + 1] = 1;
  nd->fix[2 * nx + 1] = 1;
  return 0;
}

static const mpgm_frontend_type mesh_frontend = {
    .name = "test-distorted-mesh",
    .persistent_nodes = 1,
    .point_velocity = MPGM_PV_INTERPOLATE,
    .shapes = MPGM_FE_SHAPE_CELL,
    .create = mesh_create,
    .destroy = support_fem_destroy,
    .begin_step = support_fem_begin_step,
    .cells = support_fem_cells,
};

/* ---- scene files ----------------------------------------------------------- */

/* shape: NULL for method fem with FE functions (h = 0.6), else method gmm
 * with that shape object (h = 0.15: 221 nodes, clouds of up to ~50) */
static int write_scene(const char *dir, const char *name, int cell, const char *kin,
                       const char *mat, int dynamic, int clamp, const char *shape, char *path,
                       size_t len) {
  snprintf(path, len, "%s/%s.json", dir, name);
  FILE *f = fopen(path, "w");
  if (!f) return -1;
  fprintf(f,
          "{\n"
          "  \"description\": \"assembly test %s\",\n"
          "  \"method\": \"%s\",\n"
          "  \"shape\": %s,\n"
          "  \"mesh\": {\"h\": %g, \"cell\": \"%s\", \"ppc\": %d,\n"
          "           \"domain\": {\"min\": [0.0, 0.0], \"max\": [%.17g, %.17g]}},\n"
          "  \"kinematics\": \"%s\",\n",
          name, shape ? "gmm" : "fem", shape ? shape : "{\"kind\": \"fe\"}", shape ? 0.15 : 0.6,
          cell == MPGM_CELL_Q4 ? "quad" : "tri", cell == MPGM_CELL_Q4 ? 4 : 3, LX, LY, kin);
  if (dynamic)
    fprintf(f, "  \"time\": {\"analysis\": \"dynamic\", \"dt\": %.17g, \"end\": %.17g},\n", DT,
            T_END);
  else
    fprintf(f, "  \"time\": {\"analysis\": \"static\", \"load_steps\": 1},\n");
  fprintf(f,
          "  \"materials\": {\"m\": {\"type\": \"%s\", \"density\": %.17g, \"E\": %.17g, "
          "\"nu\": %.17g}},\n"
          "  \"bodies\": [{\"name\": \"block\", \"material\": \"m\",\n"
          "              \"rectangle\": {\"min\": [0.0, 0.0], \"max\": [%.17g, %.17g]}}],\n"
          "%s"
          "  \"gravity\": [0.0, 0.0],\n"
          "  \"output\": {\"vtk\": \"none\"}\n"
          "}\n",
          mat, RHO, E_MOD, NU, LX, LY,
          clamp ? "  \"boundaries\": [{\"name\": \"clamp\", \"x\": 0.0, \"fix\": [\"x\", \"y\"]}],\n"
                : "");
  return fclose(f) ? -1 : 0;
}

/* ---- independent dense assembly ---------------------------------------------- */

/* Tangent over all 2 nnode components (free and fixed), row major, from the
 * trial point state and the current gradients:
 *   K_IK = v B_I^T D B_K + geo v (g_I . sigma g_K) 1 + dyn m N_I N_K / (beta dt^2) 1. */
static void dense_tangent(const mpgm_problem *pb, int geo, int dyn, double *K) {
  const int nf = 2 * pb->nodes.n;
  const mpgm_points *P = &pb->pts;
  const mpgm_conn *C = &pb->conn;
  const double kdyn = 1.0 / (pb->scene->beta * pb->dt * pb->dt);
  memset(K, 0, sizeof(double) * (size_t)nf * nf);
  for (int p = 0; p < P->n; p++) {
    const double *s = P->sigma_t + 4 * p, *D = P->D_t + 9 * p;
    const double v = P->vol_t[p], m = P->mass[p];
    for (int a = C->ptr[p]; a < C->ptr[p + 1]; a++) {
      const double *ga = C->g + 2 * a;
      const double Ba[3][2] = {{ga[0], 0.0}, {0.0, ga[1]}, {ga[1], ga[0]}};
      for (int b = C->ptr[p]; b < C->ptr[p + 1]; b++) {
        const double *gb = C->g + 2 * b;
        const double Bb[3][2] = {{gb[0], 0.0}, {0.0, gb[1]}, {gb[1], gb[0]}};
        const double gsg = ga[0] * (s[0] * gb[0] + s[2] * gb[1]) + ga[1] * (s[2] * gb[0] + s[1] * gb[1]);
        for (int i = 0; i < 2; i++)
          for (int j = 0; j < 2; j++) {
            double k = 0.0;
            for (int q = 0; q < 3; q++)
              for (int l = 0; l < 3; l++) k += Ba[q][i] * D[3 * q + l] * Bb[l][j];
            k *= v;
            if (i == j && geo) k += v * gsg;
            if (i == j && dyn) k += kdyn * m * C->N[a] * C->N[b];
            K[(size_t)(2 * C->node[a] + i) * nf + 2 * C->node[b] + j] += k;
          }
      }
    }
  }
}

/* ---- one problem ---------------------------------------------------------------- */

typedef struct asm_case {
  const char *name;
  const char *kin, *mat;
  int dynamic;
  int fem; /* 1: mpgm_frontend_fem (or gmm) with a clamp boundary; 0: this file's mesh */
  const char *shape; /* NULL: FE; else the GMM front end with this shape object
                      * (node clouds: K merged in batches of nearby points,
                      * assembly.c, exercised across several batches) */
} asm_case;

static void run_case(const char *dir, const asm_case *ac, int cell, rng *r) {
  const char *cn = cell == MPGM_CELL_Q4 ? "Q4" : "T3";
  char name[80], path[512];
  snprintf(name, sizeof name, "%s_%s", ac->name, cn);
  int err = write_scene(dir, name, cell, ac->kin, ac->mat, ac->dynamic, ac->fem, ac->shape, path,
                        sizeof path);
  mpgm_test(err == 0, "%s: scene written", name);
  if (err) return;
  cfg.nx = 4;
  cfg.ny = 3;
  cfg.jitter = 0.2;
  cfg.seed = 0x853C49E6748FEA9BULL + (uint64_t)cell;

  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene *sc = NULL;
  mpgm_problem *pb = NULL;
  double *Kf = NULL, *Kg = NULL, *Kd = NULL, *Kfd = NULL, *R0 = NULL, *Rp = NULL, *Rm = NULL,
         *lift = NULL;
  unsigned char *in = NULL;
  err = mpgm_scene_load(&ctx, path, 0, NULL, &sc);
  mpgm_test(err == 0, "%s: scene loads (%d: %s)", name, err, ctx.msg);
  if (!err)
    err = mpgm_problem_create(&ctx, sc,
                              ac->shape ? &mpgm_frontend_gmm : ac->fem ? &mpgm_frontend_fem : &mesh_frontend,
                              &pb);
  mpgm_test(err == 0, "%s: problem created (%d: %s)", name, err, ctx.msg);
  if (err) goto done;
  pb->dt = sc->dt;
  err = mpgm_begin_step(pb);
  if (!err) err = mpgm_pattern_build(pb);
  mpgm_test(err == 0, "%s: begin_step and pattern (%d: %s)", name, err, ctx.msg);
  if (err) goto done;

  mpgm_nodes *nd = &pb->nodes;
  const int n = nd->ndof, nf = 2 * nd->n;
  mpgm_test(n > 0 && n < nf && pb->ls->K.n == n, "%s: %d free of %d components, K is %d x %d", name,
            n, nf, pb->ls->K.n, pb->ls->K.n);
  Kf = malloc(sizeof(double) * (size_t)nf * nf);
  Kg = malloc(sizeof(double) * (size_t)nf * nf);
  Kd = malloc(sizeof(double) * (size_t)n * n);
  Kfd = malloc(sizeof(double) * (size_t)n * n);
  R0 = malloc(sizeof(double) * n);
  Rp = malloc(sizeof(double) * n);
  Rm = malloc(sizeof(double) * n);
  lift = malloc(sizeof(double) * nf);
  in = malloc((size_t)n * n);
  if (!Kf || !Kg || !Kd || !Kfd || !R0 || !Rp || !Rm || !lift || !in) {
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
  memcpy(R0, pb->ls->R, sizeof(double) * n);
  double smax = 0.0;
  for (int p = 0; p < pb->pts.n; p++)
    for (int i = 0; i < 3; i++) smax = fmax(smax, fabs(pb->pts.sigma_t[4 * p + i]));
  mpgm_test(smax > 1e-4 * E_MOD * amp, "%s: non-trivial stress state (max |sigma| = %.3g Pa)",
            name, smax);

  /* (i) sparse vs dense */
  if (csc_dense(&pb->ls->K, Kd, in, name)) goto done;
  dense_tangent(pb, pb->fx.geometric, pb->fx.inertia, Kf);
  double kmax = 0.0, emax = 0.0, amax = 0.0;
  int wi = -1, wj = -1, missing = 0;
  for (int I = 0; I < nf; I++)
    for (int J = 0; J < nf; J++) {
      const int i = nd->dof[I], j = nd->dof[J];
      if (i < 0 || j < 0) continue;
      const double k = Kf[(size_t)I * nf + J];
      kmax = fmax(kmax, fabs(k));
      if (k != 0.0 && !in[(size_t)i * n + j]) missing++;
      const double e = fabs(Kd[(size_t)i * n + j] - k);
      if (e > emax) { emax = e; wi = i; wj = j; }
      amax = fmax(amax, fabs(Kd[(size_t)i * n + j] - Kd[(size_t)j * n + i]));
    }
  mpgm_test(kmax > 0.0, "%s: non-zero tangent (max |K| = %.3g)", name, kmax);
  mpgm_test(missing == 0, "%s: CSC pattern holds every non-zero of the dense tangent (%d missing)",
            name, missing);
  mpgm_test_abs(emax / kmax, 0.0, TOL_DENSE,
                "%s: CSC = dense tangent, every entry (rel; worst at row %d, col %d)", name, wi, wj);
  mpgm_test(pb->ls->K.symmetric == 1, "%s: K flagged symmetric", name);
  mpgm_test_abs(amax / kmax, 0.0, TOL_DENSE, "%s: K symmetric (rel)", name);

  /* lift of the first Newton iteration: R -= K_free,fixed lift */
  for (int i = 0; i < nf; i++) lift[i] = uniform(r, -amp, amp);
  pb->ls->lift = lift;
  err = mpgm_assemble(pb, 1);
  pb->ls->lift = NULL;
  double lmax = 0.0, lref = 0.0, rmax = 0.0;
  for (int i = 0; i < n; i++) rmax = fmax(rmax, fabs(R0[i]));
  for (int I = 0; I < nf; I++) {
    const int i = nd->dof[I];
    if (i < 0) continue;
    double dR = 0.0;
    for (int J = 0; J < nf; J++)
      if (nd->dof[J] < 0) dR -= Kf[(size_t)I * nf + J] * lift[J];
    lmax = fmax(lmax, fabs(pb->ls->R[i] - R0[i] - dR));
    lref = fmax(lref, fabs(dR));
  }
  mpgm_test(err == 0 && lref > 0.0, "%s: assemble with a lift (%d)", name, err);
  mpgm_test_abs(lmax / (rmax + lref), 0.0, TOL_DENSE,
                "%s: lift adds -K_free,fixed lift to R (rel; max |dR| = %.3g N)", name, lref);

  /* (ii) central differences of R(du), column by column */
  const double e = FD_STEP;
  for (int J = 0; J < nf; J++) {
    const int j = nd->dof[J];
    if (j < 0) continue;
    const double du0 = nd->du[J];
    nd->du[J] = du0 + e;
    err = mpgm_eval_points(pb, 1);
    if (!err) err = mpgm_assemble(pb, 0);
    memcpy(Rp, pb->ls->R, sizeof(double) * n);
    nd->du[J] = du0 - e;
    if (!err) err = mpgm_eval_points(pb, 1);
    if (!err) err = mpgm_assemble(pb, 0);
    memcpy(Rm, pb->ls->R, sizeof(double) * n);
    nd->du[J] = du0;
    if (err) break;
    double cerr = 0.0;
    int wr = -1;
    for (int i = 0; i < n; i++) {
      Kfd[(size_t)i * n + j] = -(Rp[i] - Rm[i]) / (2.0 * e);
      const double d = fabs(Kfd[(size_t)i * n + j] - Kd[(size_t)i * n + j]);
      if (d > cerr) { cerr = d; wr = i; }
    }
    mpgm_test_abs(cerr / kmax, 0.0, TOL_FD,
                  "%s: column %d (node %d %c) of K = -dR/du by central differences (rel; worst "
                  "row %d)", name, j, J / 2, "xy"[J % 2], wr);
  }
  mpgm_test(err == 0, "%s: residual evaluations (%d: %s)", name, err, ctx.msg);
  /* the check sees each term: without it the tangent misses by far more */
  if (pb->fx.geometric || pb->fx.inertia) {
    for (int term = 0; term < 2; term++) {
      if (term == 0 && !pb->fx.geometric) continue;
      if (term == 1 && !pb->fx.inertia) continue;
      dense_tangent(pb, term == 0 ? 0 : pb->fx.geometric, term == 1 ? 0 : pb->fx.inertia, Kg);
      double dmax = 0.0;
      for (int I = 0; I < nf; I++)
        for (int J = 0; J < nf; J++) {
          const int i = nd->dof[I], j = nd->dof[J];
          if (i >= 0 && j >= 0) dmax = fmax(dmax, fabs(Kg[(size_t)I * nf + J] - Kfd[(size_t)i * n + j]));
        }
      mpgm_test(dmax / kmax > 1e3 * TOL_FD,
                "%s: the tangent without the %s term misses -dR/du (rel %.3g)", name,
                term == 0 ? "geometric" : "dynamic", dmax / kmax);
    }
  }

done:
  free(Kf); free(Kg); free(Kd); free(Kfd); free(R0); free(Rp); free(Rm); free(lift); free(in);
  mpgm_problem_destroy(&pb);
  mpgm_scene_destroy(&sc);
  unlink(path);
}

int main(void) {
  char dir[] = "/tmp/mpgm_assembly_XXXXXX";
  if (!mkdtemp(dir)) {
    mpgm_test(0, "mkdtemp %s", dir);
    return mpgm_test_summary();
  }
  const asm_case cases[] = {
      {"mesh_small_linear_elastic_static", "small", "linear_elastic", 0, 0, NULL},
      {"mesh_finite_neo_hookean_static", "finite", "neo_hookean", 0, 0, NULL},
      {"mesh_finite_neo_hookean_dynamic", "finite", "neo_hookean", 1, 0, NULL},
      {"fem_finite_neo_hookean_static", "finite", "neo_hookean", 0, 1, NULL},
      {"fem_finite_neo_hookean_dynamic", "finite", "neo_hookean", 1, 1, NULL},
  };
  const asm_case clouds[] = {
      {"gmm_lme_finite_neo_hookean_dynamic", "finite", "neo_hookean", 1, 1,
       "{\"kind\": \"lme\", \"gamma\": 0.8}"},
      {"gmm_mls_finite_neo_hookean_static", "finite", "neo_hookean", 0, 1, "{\"kind\": \"mls\"}"},
  };
  rng r = {0xDA942042E4DD58B5ULL};
  for (int cell = MPGM_CELL_T3; cell <= MPGM_CELL_Q4; cell++)
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) run_case(dir, &cases[i], cell, &r);
  for (size_t i = 0; i < sizeof clouds / sizeof clouds[0]; i++) run_case(dir, &clouds[i], MPGM_CELL_T3, &r);
  mpgm_test(rmdir(dir) == 0, "temporary directory %s removed", dir);
  return mpgm_test_summary();
}
