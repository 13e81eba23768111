/* test_patch.c -- patch tests through the real core (mpgm_problem_create +
 * mpgm_step), driven by a front end of this file on a distorted mesh.
 *
 * Mesh: 4 x 3 cells (Q4, or T3 from splitting each quad along alternating
 * diagonals) on [0, 2.385] x [0, 1.7]; every interior node moved randomly by
 * up to 0.2 h per component (the cells stay convex); material points at the
 * Gauss points of the cells (volume w detJ, mass density * volume). Every
 * boundary node is fixed in x and y with ubar = u(X) = c + G X.
 *
 * Cases, one static load step each, no gravity:
 *   (a) small kinematics, linear_elastic, |G| ~ 1e-3;
 *   (b) small kinematics, neo_hookean (its linear limit);
 *   (c) finite kinematics, neo_hookean, |G| ~ 0.15 with a rotation-like skew:
 *       a homogeneous deformation also solves the nonlinear problem exactly.
 * Checks: interior nodes' total displacement = u(X); every point's Cauchy
 * stress = the stress of the homogeneous deformation (linear law of sym(G)
 * for (a), (b); the material's update at F = I + G for (c)); F = I + G;
 * point displacement = u(X); for (c) point positions x = X + u(X) and
 * volumes det(I + G) vol0.
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include "mpgm_core_impl.h"
#include "mpgm_core.h"
#include "mpgm_scene_io.h"
#include "mpgm_test.h"
#include "support_mesh.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Patch tests are exact up to round-off: the solve of a well-conditioned
 * system (~1e3 cond) and the Newton tolerance of the scene (rtol 1e-13). */
#define TOL_PATCH 1e-10

static const double LX = 2.385, LY = 1.7; /* domain [0, LX] x [0, LY] [m] */
static const double E_MOD = 7.31e6, NU = 0.2847, RHO = 1851.3;

/* ---- the test's front end: distorted structured mesh ---------------------- */

/* What the front end builds. mpgm_problem_create calls setup before the
 * caller can attach data, so the configuration is the test program's own
 * file-level state, set before each problem is created. */
typedef struct mesh_cfg {
  int nx, ny;        /**< cells in x and y                         */
  double jitter;     /**< interior node moves, fraction of h        */
  uint64_t seed;     /**< of the node moves                         */
  double c[2], G[4]; /**< ubar = c + G X on every boundary node    */
} mesh_cfg;
static mesh_cfg cfg;

/* The distorted mesh goes through mpgm_fem_setup_mesh, the same path as the
 * UL-FEM front end; only the fixity is the test's own. */
static int mesh_create(const mpgm_fe_view *v, void **self) {
  MPGM_CALL(support_distorted_mesh(v, cfg.nx, cfg.ny, LX, LY, cfg.jitter, cfg.seed, (mpgm_fem_cells **)self));
  /* fixity: every boundary node, both components, ubar = c + G X */
  mpgm_nodes *nd = v->nodes;
  const int nx = cfg.nx, ny = cfg.ny;
  for (int j = 0; j <= ny; j++)
    for (int i = 0; i <= nx; i++) {
      const int k = j * (nx + 1) + i;
      if (!(i == 0 || i == nx || j == 0 || j == ny)) continue;
      const double *X = nd->X + 2 * k;
      for (int dd = 0; dd < 2; dd++) {
        nd->fix[2 * k + dd] = 1;
        nd->ubar[2 * k + dd] = cfg.c[dd] + cfg.G[2 * dd] * X[0] + cfg.G[2 * dd + 1] * X[1];
      }
    }
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

/* Write a scene to dir/name.json; path receives the file name. */
static int write_scene(const char *dir, const char *name, int cell, const char *kin,
                       const char *mat, char *path, size_t len) {
  snprintf(path, len, "%s/%s.json", dir, name);
  FILE *f = fopen(path, "w");
  if (!f) return -1;
  fprintf(f,
          "{\n"
          "  \"description\": \"patch test %s\",\n"
          "  \"method\": \"fem\",\n"
          "  \"shape\": {\"kind\": \"fe\"},\n"
          "  \"mesh\": {\"h\": 0.6, \"cell\": \"%s\", \"ppc\": %d,\n"
          "           \"domain\": {\"min\": [0.0, 0.0], \"max\": [%.17g, %.17g]}},\n"
          "  \"kinematics\": \"%s\",\n"
          "  \"time\": {\"analysis\": \"static\", \"load_steps\": 1},\n"
          "  \"solver\": {\"linear\": \"auto\", \"rtol\": 1e-13, \"atol\": 0.0, \"dtol\": 1e-12,\n"
          "             \"max_iterations\": 25},\n"
          "  \"materials\": {\"m\": {\"type\": \"%s\", \"density\": %.17g, \"E\": %.17g, "
          "\"nu\": %.17g}},\n"
          "  \"bodies\": [{\"name\": \"block\", \"material\": \"m\",\n"
          "              \"rectangle\": {\"min\": [0.0, 0.0], \"max\": [%.17g, %.17g]}}],\n"
          "  \"gravity\": [0.0, 0.0],\n"
          "  \"output\": {\"vtk\": \"none\"}\n"
          "}\n",
          name, cell == MPGM_CELL_Q4 ? "quad" : "tri", cell == MPGM_CELL_Q4 ? 4 : 3, LX, LY, kin,
          mat, RHO, E_MOD, NU, LX, LY);
  return fclose(f) ? -1 : 0;
}

/* ---- one patch test ---------------------------------------------------------- */

typedef struct patch_case {
  const char *name;
  const char *kin, *mat;
  int finite;
} patch_case;

static double max_abs(const double *v, int n) {
  double m = 0.0;
  for (int i = 0; i < n; i++) m = fmax(m, fabs(v[i]));
  return m;
}

static void run_patch(const char *dir, const patch_case *pc, int cell, rng *r) {
  const char *cn = cell == MPGM_CELL_Q4 ? "Q4" : "T3";
  char name[64], path[512];
  snprintf(name, sizeof name, "patch_%s_%s", pc->name, cn);
  int err = write_scene(dir, name, cell, pc->kin, pc->mat, path, sizeof path);
  mpgm_test(err == 0, "%s: scene written", name);
  if (err) return;
  /* the prescribed linear field */
  memset(&cfg, 0, sizeof cfg);
  cfg.nx = 4;
  cfg.ny = 3;
  cfg.jitter = 0.2;
  cfg.seed = 0x5DEECE66DULL + (uint64_t)cell * 977u;
  if (pc->finite) {
    /* stretch/shear ~0.1 plus a skew (rotation-like) part ~0.15 */
    const double w = uniform(r, 0.12, 0.16) * (uniform(r, -1, 1) < 0 ? -1.0 : 1.0);
    const double sxy = uniform(r, -0.08, 0.08);
    cfg.G[0] = uniform(r, -0.12, 0.12);
    cfg.G[1] = sxy - w;
    cfg.G[2] = sxy + w;
    cfg.G[3] = uniform(r, -0.12, 0.12);
    cfg.c[0] = uniform(r, -0.05, 0.05);
    cfg.c[1] = uniform(r, -0.05, 0.05);
  } else {
    for (int i = 0; i < 4; i++) cfg.G[i] = uniform(r, -1.3e-3, 1.3e-3);
    cfg.c[0] = uniform(r, -1e-3, 1e-3);
    cfg.c[1] = uniform(r, -1e-3, 1e-3);
  }
  const double *G = cfg.G, *c = cfg.c;

  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene *sc = NULL;
  mpgm_problem *pb = NULL;
  err = mpgm_scene_load(&ctx, path, 0, NULL, &sc);
  mpgm_test(err == 0, "%s: scene loads (%d: %s)", name, err, ctx.msg);
  if (!err) err = mpgm_problem_create(&ctx, sc, &mesh_frontend, &pb);
  mpgm_test(err == 0, "%s: problem created (%d: %s)", name, err, ctx.msg);
  if (!err) err = mpgm_step(pb);
  mpgm_test(err == 0, "%s: step converges (%d: %s)", name, err, ctx.msg);
  if (err) {
    mpgm_problem_destroy(&pb);
    mpgm_scene_destroy(&sc);
    return;
  }
  mpgm_test(pb->last.iterations >= 1 && pb->last.iterations <= (pc->finite ? 10 : 3),
            "%s: Newton iterations (%d)", name, pb->last.iterations);

  /* nodes: total displacement = u(X) */
  const mpgm_nodes *nd = &pb->nodes;
  const mpgm_points *P = &pb->pts;
  const double umax = max_abs(nd->ubar, 2 * nd->n);
  double ei = 0.0, eb = 0.0;
  int ninterior = 0;
  for (int k = 0; k < nd->n; k++) {
    const double *X = nd->X + 2 * k;
    const double ue[2] = {c[0] + G[0] * X[0] + G[1] * X[1], c[1] + G[2] * X[0] + G[3] * X[1]};
    const double e = fmax(fabs(nd->u[2 * k] - ue[0]), fabs(nd->u[2 * k + 1] - ue[1]));
    if (nd->fix[2 * k]) eb = fmax(eb, e);
    else { ei = fmax(ei, e); ninterior++; }
  }
  mpgm_test(ninterior == (cfg.nx - 1) * (cfg.ny - 1) && nd->ndof == 2 * ninterior,
            "%s: %d interior nodes free", name, ninterior);
  mpgm_test_abs(ei / umax, 0.0, TOL_PATCH, "%s: interior nodes u = c + G X (rel)", name);
  mpgm_test_abs(eb / umax, 0.0, TOL_PATCH, "%s: boundary nodes u = ubar (rel)", name);

  /* points: F, stress, displacement, position, volume */
  const double Fe[4] = {1.0 + G[0], G[1], G[2], 1.0 + G[3]};
  const mpgm_material *m = &sc->mats[0];
  double se[4];
  if (pc->finite) {
    err = m->type->update(m, MPGM_KIN_FINITE, Fe, Fe, NULL, NULL, se, NULL);
    mpgm_test(err == 0, "%s: material update at F = I + G", name);
  } else {
    double lam, mu;
    mpgm_lame(E_MOD, NU, &lam, &mu);
    const double tr = G[0] + G[3];
    se[0] = lam * tr + 2.0 * mu * G[0];
    se[1] = lam * tr + 2.0 * mu * G[3];
    se[2] = mu * (G[1] + G[2]);
    se[3] = lam * tr;
  }
  const double snorm = sqrt(se[0] * se[0] + se[1] * se[1] + 2 * se[2] * se[2] + se[3] * se[3]);
  const double J = Fe[0] * Fe[3] - Fe[1] * Fe[2];
  double es = 0.0, eF = 0.0, eu = 0.0, ex = 0.0, ev = 0.0;
  for (int p = 0; p < P->n; p++) {
    const double *s = P->sigma + 4 * p, *F = P->F + 4 * p, *X = P->x0 + 2 * p;
    for (int i = 0; i < 4; i++) {
      es = fmax(es, fabs(s[i] - se[i]));
      eF = fmax(eF, fabs(F[i] - Fe[i]));
    }
    const double ue[2] = {c[0] + G[0] * X[0] + G[1] * X[1], c[1] + G[2] * X[0] + G[3] * X[1]};
    for (int d = 0; d < 2; d++) {
      eu = fmax(eu, fabs(P->u[2 * p + d] - ue[d]));
      /* finite: the points move with the body; small: they stay */
      ex = fmax(ex, fabs(P->x[2 * p + d] - (X[d] + (pc->finite ? ue[d] : 0.0))));
    }
    ev = fmax(ev, fabs(P->vol[p] - (pc->finite ? J : 1.0) * P->vol0[p]) / P->vol0[p]);
  }
  mpgm_test(snorm > 0.0, "%s: non-trivial stress (|sigma| = %g Pa)", name, snorm);
  mpgm_test_abs(es / snorm, 0.0, TOL_PATCH, "%s: every point's sigma = homogeneous stress (rel)",
                name);
  mpgm_test_abs(eF, 0.0, TOL_PATCH, "%s: every point's F = I + G", name);
  mpgm_test_abs(eu / umax, 0.0, TOL_PATCH, "%s: every point's u = c + G X (rel)", name);
  mpgm_test_abs(ex / umax, 0.0, TOL_PATCH, "%s: point positions x = X%s (rel)", name,
                pc->finite ? " + u(X)" : "");
  mpgm_test_abs(ev, 0.0, TOL_PATCH, "%s: point volumes = %s vol0", name,
                pc->finite ? "det(I + G)" : "");
  mpgm_problem_destroy(&pb);
  mpgm_scene_destroy(&sc);
  mpgm_test(pb == NULL && sc == NULL, "%s: destroy nulls the pointers", name);
  unlink(path);
}

int main(void) {
  char dir[] = "/tmp/mpgm_patch_XXXXXX";
  if (!mkdtemp(dir)) {
    mpgm_test(0, "mkdtemp %s", dir);
    return mpgm_test_summary();
  }
  const patch_case cases[] = {
      {"a_small_linear_elastic", "small", "linear_elastic", 0},
      {"b_small_neo_hookean", "small", "neo_hookean", 0},
      {"c_finite_neo_hookean", "finite", "neo_hookean", 1},
  };
  rng r = {0x2545F4914F6CDD1DULL};
  for (int cell = MPGM_CELL_T3; cell <= MPGM_CELL_Q4; cell++)
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) run_patch(dir, &cases[i], cell, &r);
  mpgm_test(rmdir(dir) == 0, "temporary directory %s removed", dir);
  return mpgm_test_summary();
}
