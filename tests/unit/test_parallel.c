/* test_parallel.c -- the context's communicator (mpgm_comm, mpgm_base.h)
 * and the module that starts MPI (mpgm_parallel.h).
 *
 * Alone, the collectives of a context without a communicator are the
 * identity and no MPI is started. Under an MPI launcher (processes.sh
 * runs it with mpiexec -n 2 and -n 3) MPI and PETSc start through
 * mpgm_par.so, the communicator has the launcher's size, every
 * collective gives on every rank what the ranks' values say, and the
 * outcome of a local part is agreed (mpgm_agree), the
 * partitioned grid (mpgm_pgrid, 2-D and 3-D) sums shared nodes as one
 * process would and migrates every point to the process of its cell. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_base.h"
#include "mpgm_core.h"
#include "mpgm_parallel.h"
#include "mpgm_scene_io.h"
#include "mpgm_test.h"

static void one_process(void) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  double v[3] = {1.5, -2.0, NAN};
  long l[2] = {7, -3};
  char b[4] = "abc";
  const int err = mpgm_allreduce(&ctx, MPGM_REDUCE_SUM, v, 3) |
                  mpgm_allreduce_long(&ctx, MPGM_REDUCE_MAX, l, 2) | mpgm_bcast(&ctx, b, 4, 0) |
                  (mpgm_agree(&ctx, MPGM_ERR_NAN) != MPGM_ERR_NAN) | mpgm_agree(&ctx, 0);
  mpgm_test(err == 0 && mpgm_ctx_size(&ctx) == 1 && mpgm_ctx_rank(&ctx) == 0 && v[0] == 1.5 &&
                v[1] == -2.0 && isnan(v[2]) && l[0] == 7 && l[1] == -3 && strcmp(b, "abc") == 0,
            "one process: size 1, rank 0, the collectives leave every value as it was");
}

#define NPT 600

/* Point q's position in cell units (deterministic: the same on every rank). */
static void position(int q, int dim, const int n[3], double x[3]) {
  rng r = {.s = 0x9e3779b97f4a7c15ull ^ (uint64_t)(q + 1) * 0x2545f4914f6cdd1dull};
  for (int d = 0; d < 3; d++) x[d] = d < dim ? uniform(&r, 0.0, n[d] - 1.0) : 0.0;
}

/* Point x's linear weights to the 2^dim nodes of its cell: ijk and w. */
static int corners(const double x[3], int dim, int ijk[8][3], double w[8]) {
  const int m = 1 << dim;
  for (int c = 0; c < m; c++) {
    w[c] = 1.0;
    for (int d = 0; d < 3; d++) {
      const int base = (int)x[d], up = d < dim && (c >> d & 1);
      const double f = x[d] - base;
      ijk[c][d] = base + up;
      if (d < dim) w[c] *= up ? f : 1.0 - f;
    }
  }
  return m;
}

/* Sums at shared nodes: each rank projects its own cells' points (values
 * 1, x, y times the linear weights) to the nodes they reach; after the
 * sums every rank holds at those nodes what all points give there. */
static void check_sums(mpgm_ctx *ctx, int dim) {
  const int n[3] = {13, 9, 7}, r = ctx->comm->rank;
  mpgm_pgrid *g = NULL;
  if (mpgm_pgrid_create(ctx, dim, n, 3, 1, NULL, &g)) {
    mpgm_test(0, "%d-D grid: %s", dim, ctx->msg);
    return;
  }
  const int nn = n[0] * n[1] * (dim == 3 ? n[2] : 1);
  double *mine = calloc(3 * (size_t)nn, sizeof(double)), *all = calloc(3 * (size_t)nn, sizeof(double));
  int *touched = calloc((size_t)nn, sizeof(int));
  for (int q = 0; q < NPT; q++) {
    double x[3], w[8];
    int ijk[8][3], cell[3];
    position(q, dim, n, x);
    for (int d = 0; d < 3; d++) cell[d] = (int)x[d];
    const int own = mpgm_pgrid_owner(g, cell) == r, m = corners(x, dim, ijk, w);
    for (int c = 0; c < m; c++) {
      const int I = ijk[c][0] + n[0] * (ijk[c][1] + n[1] * ijk[c][2]);
      const double v[3] = {w[c], w[c] * x[0], w[c] * x[1]};
      for (int k = 0; k < 3; k++) {
        all[3 * I + k] += v[k];
        if (own) mine[3 * I + k] += v[k];
      }
      touched[I] |= own;
    }
  }
  int nt = 0, *ijk = malloc(sizeof(int) * 3 * (size_t)nn);
  double *val = malloc(sizeof(double) * 3 * (size_t)nn);
  for (int I = 0; I < nn; I++)
    if (touched[I]) {
      const int at[3] = {I % n[0], I / n[0] % n[1], I / (n[0] * n[1])};
      for (int d = 0; d < dim; d++) ijk[dim * nt + d] = at[d];
      for (int k = 0; k < 3; k++) val[3 * nt + k] = mine[3 * I + k];
      nt++;
    }
  const int err = mpgm_pgrid_sum(ctx, g, nt, ijk, 3, val);
  double worst = 0.0;
  for (int t = 0, I = 0; I < nn && !err; I++)
    if (touched[I]) {
      for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(val[3 * t + k] - all[3 * I + k]) / (fabs(all[3 * I + k]) + 1e-300));
      t++;
    }
  mpgm_test(err == 0 && nt > 0 && worst <= TEST_TOL3, "%d-D rank %d: the sums at its %d nodes are "
            "all points' (worst relative difference %.2e) %s", dim, r, nt, worst, err ? ctx->msg : "");
  free(mine), free(all), free(touched), free(ijk), free(val);
  mpgm_pgrid_destroy(&g);
}

/* A partition cut by weights: a 41 x 21 (x 11) grid whose x weight lies
 * on its first ten node layers only (the y and z weights even). Every
 * process's slabs are at least width + 1 = 3 nodes wide, the slabs cover
 * the grid, and each process's share of the weight -- the product of its
 * slabs' shares -- is its even share to within the layers a cut rounds to
 * (0.1 of x, 1/21 of y, 1/11 of z). */
static void check_weights(mpgm_ctx *ctx, int dim) {
  const int n[3] = {41, 21, 11}, r = ctx->comm->rank, np = ctx->comm->size;
  double wx[41], wy[21], wz[11];
  for (int i = 0; i < 41; i++) wx[i] = i < 10 ? 1.0 : 0.0;
  for (int i = 0; i < 21; i++) wy[i] = 1.0;
  for (int i = 0; i < 11; i++) wz[i] = 1.0;
  const double *const w[3] = {wx, wy, wz};
  mpgm_pgrid *g = NULL;
  if (mpgm_pgrid_create(ctx, dim, n, 1, 2, w, &g)) {
    mpgm_test(0, "%d-D weighted grid: %s", dim, ctx->msg);
    return;
  }
  int lo[3], hi[3], narrow = 0;
  mpgm_pgrid_boxes(g, lo, hi, NULL, NULL);
  double share = 1.0, slack = 0.0, cover = 1.0;
  const double *wd[3] = {wx, wy, wz}, tot[3] = {10.0, 21.0, 11.0}, layer[3] = {0.1, 1.0 / 21, 1.0 / 11};
  for (int d = 0; d < dim; d++) {
    double s = 0.0;
    for (int i = lo[d]; i < hi[d]; i++) s += wd[d][i];
    share *= s / tot[d];
    slack += layer[d];
    cover *= hi[d] - lo[d];
    narrow |= hi[d] - lo[d] < 3;
  }
  double sum[2] = {share, cover};
  mpgm_allreduce(ctx, MPGM_REDUCE_SUM, sum, 2);
  mpgm_test(!narrow && fabs(sum[0] - 1.0) < 1e-12 && sum[1] == (dim == 3 ? 41.0 * 21 * 11 : 41.0 * 21) &&
                share <= 1.0 / np + slack,
            "%d-D rank %d of %d: slabs [%d, %d) x [%d, %d)%s, its share of the weight %.3f (even %.3f)",
            dim, r, np, lo[0], hi[0], lo[1], hi[1], dim == 3 ? " x ..." : "", share, 1.0 / np);
  mpgm_pgrid_destroy(&g);
}

/* Migration: rank r starts with the points q = r (mod P), each a record
 * (q, x, y, z, 2 q + 1); after it every rank holds exactly the points of
 * its own cells, each once, with its record whole. */
static void check_migration(mpgm_ctx *ctx, int dim) {
  const int n[3] = {11, 8, 6}, r = ctx->comm->rank, P = ctx->comm->size, rec = 5;
  mpgm_pgrid *g = NULL;
  if (mpgm_pgrid_create(ctx, dim, n, 1, 1, NULL, &g)) {
    mpgm_test(0, "%d-D grid: %s", dim, ctx->msg);
    return;
  }
  double *out = malloc(sizeof(double) * rec * NPT), *in = NULL;
  int *dest = malloc(sizeof(int) * NPT), nout = 0, nin = 0, mine = 0;
  for (int q = 0; q < NPT; q++) {
    double x[3];
    int cell[3];
    position(q, dim, n, x);
    for (int d = 0; d < 3; d++) cell[d] = (int)x[d];
    const int o = mpgm_pgrid_owner(g, cell);
    mine += o == r;
    if (q % P != r) continue;
    double *R = out + rec * nout;
    R[0] = q, R[1] = x[0], R[2] = x[1], R[3] = x[2], R[4] = 2.0 * q + 1.0;
    dest[nout++] = o;
  }
  const int err = mpgm_pgrid_migrate(ctx, g, rec, nout, out, dest, &nin, &in);
  int bad = 0;
  long ids[2] = {0, nin};
  for (int i = 0; i < nin && !err; i++) {
    const double *R = in + rec * i;
    double x[3];
    int cell[3];
    position((int)R[0], dim, n, x);
    for (int d = 0; d < 3; d++) cell[d] = (int)x[d];
    bad += mpgm_pgrid_owner(g, cell) != r || R[1] != x[0] || R[2] != x[1] || R[3] != x[2] ||
           R[4] != 2.0 * R[0] + 1.0;
    ids[0] += (long)R[0];
  }
  mpgm_allreduce_long(ctx, MPGM_REDUCE_SUM, ids, 2);
  mpgm_test(err == 0 && nin == mine && bad == 0 && ids[1] == NPT && ids[0] == (long)NPT * (NPT - 1) / 2,
            "%d-D rank %d: after the migration it holds the %d points of its cells, records whole "
            "(%d wrong); %ld points in all %s", dim, r, nin, bad, ids[1], err ? ctx->msg : "");
  free(out), free(in), free(dest);
  mpgm_pgrid_destroy(&g);
}

/* The explicit MPM scene of the comparison: a block thrown against a
 * fixed floor under gravity, 100 steps of a fixed dt, the scheme given. */
static int mpm_scene(mpgm_ctx *ctx, const char *scheme, mpgm_scene **s) {
  char text[2048];
#if MPGM_DIM == 2
  const char *dom = "[0, 0], \"max\": [3.2, 1.6]", *box = "[0.4, 0.2], \"max\": [2.2, 1.4]",
             *vel = "[0.731, -0.219]", *g = "[0.0, -9.81]", *body = "rectangle";
#else
  const char *dom = "[0, 0, 0], \"max\": [2.4, 1.2, 1.2]",
             *box = "[0.3, 0.2, 0.2], \"max\": [1.7, 1.0, 1.0]", *vel = "[0.731, -0.219, 0.3]",
             *g = "[0.0, -9.81, 0.0]", *body = "box";
#endif
  snprintf(text, sizeof text,
           "{\"method\": \"mpm\", \"shape\": {\"kind\": \"fe\"},"
           " \"mesh\": {\"h\": 0.2, \"ppc\": %d, \"domain\": {\"min\": %s}},"
           " \"time\": {\"analysis\": \"explicit\", \"scheme\": \"%s\", \"dt\": 1e-3, \"end\": 0.1},"
           " \"materials\": {\"m\": {\"type\": \"neo_hookean\", \"density\": 2385.7, \"E\": 3.1e6, "
           "\"nu\": 0.287}},"
           " \"bodies\": [{\"material\": \"m\", \"velocity\": %s, \"%s\": {\"min\": %s}}],"
           " \"boundaries\": [{\"y\": 0.0, \"fix\": [\"y\"]}, {\"x\": 0.0, \"fix\": [\"x\"]}],"
           " \"gravity\": %s, \"output\": {\"vtk\": \"none\"}}",
           MPGM_DIM == 2 ? 4 : 8, dom, scheme, vel, body, box, g);
  return mpgm_scene_load_text(ctx, "parallel/mpm", text, strlen(text), 0, NULL, s);
}

/* Run the scene to its end on the context's processes: the problem (the
 * caller destroys it). */
static int mpm_run(mpgm_ctx *ctx, const mpgm_scene *s, mpgm_problem **pb, long *n0) {
  MPGM_CALL(mpgm_problem_create(ctx, s, NULL, pb));
  *n0 = mpgm_problem_points(*pb)->n; /* the points of this process's cells at the start */
  mpgm_run_result res = {0};
  const mpgm_run_control rc = {0};
  const int err = mpgm_problem_run(*pb, &rc, &res);
  mpgm_run_result_free(&res);
  return err;
}

/* Explicit MPM on every process against one process alone (each rank
 * runs the whole problem by itself too): the energies, and every point's
 * position and velocity by its id, after 100 steps. */
static void check_mpm(mpgm_ctx *ctx, const char *scheme) {
  mpgm_ctx one;
  mpgm_ctx_init(&one);
  mpgm_scene *s = NULL;
  mpgm_problem *ref = NULL, *pb = NULL;
  int err = mpm_scene(&one, scheme, &s);
  long n0 = 0, moved = 0;
  if (!err) err = mpm_run(&one, s, &ref, &n0);
  mpgm_test(!err, "%s: the one-process run (%s)", scheme, err ? one.msg : "ok");
  err = err ? err : mpm_run(ctx, s, &pb, &n0);
  mpgm_test(!err, "%s, rank %d: the run on %d processes (%s)", scheme, ctx->comm->rank,
            ctx->comm->size, err ? ctx->msg : "ok");
  if (!err) {
    const mpgm_points *R = mpgm_problem_points(ref), *P = mpgm_problem_points(pb);
    int *at = malloc(sizeof(int) * (size_t)R->n), bad = 0;
    for (int p = 0; p < R->n; p++) at[R->id[p]] = p;
    double dx = 0.0, dv = 0.0, vmax = 0.0;
    for (int p = 0; p < R->n; p++)
      for (int c = 0; c < MPGM_DIM; c++) vmax = fmax(vmax, fabs(R->v[MPGM_DIM * p + c]));
    for (int p = 0; p < P->n; p++) {
      const int q = P->id[p] >= 0 && P->id[p] < R->n ? at[P->id[p]] : -1;
      if (q < 0) {
        bad++;
        continue;
      }
      for (int c = 0; c < MPGM_DIM; c++) {
        dx = fmax(dx, fabs(P->x[MPGM_DIM * p + c] - R->x[MPGM_DIM * q + c]));
        dv = fmax(dv, fabs(P->v[MPGM_DIM * p + c] - R->v[MPGM_DIM * q + c]));
      }
    }
    long n = P->n;
    moved = labs(n - n0); /* some points crossed to another process */
    mpgm_allreduce_long(ctx, MPGM_REDUCE_SUM, &n, 1);
    mpgm_allreduce_long(ctx, MPGM_REDUCE_MAX, &moved, 1);
    mpgm_energy e, f;
    mpgm_problem_energy(ref, &e);
    mpgm_problem_energy(pb, &f);
    const double de = fabs(f.total - e.total) / fabs(e.total), dk = fabs(f.kinetic - e.kinetic) / e.kinetic;
    mpgm_test(moved > 0, "%s: points crossed to other processes (on one, %ld more or fewer than "
              "at the start)", scheme, moved);
    mpgm_test(bad == 0 && n == R->n && dx <= 1e-10 * 3.2 && dv <= 1e-10 * vmax && de <= 1e-10 &&
                  dk <= 1e-10,
              "%s, rank %d of %d: %d of the %d points here, every one as on one process after 100 "
              "steps (|dx| %.2e m, |dv| %.2e of %.3g m/s; energy %.2e, kinetic %.2e relative)",
              scheme, ctx->comm->rank, ctx->comm->size, P->n, R->n, dx, dv, vmax, de, dk);
    free(at);
  }
  mpgm_problem_destroy(&ref);
  mpgm_problem_destroy(&pb);
  mpgm_scene_destroy(&s);
}

/* mpgm_agree: every rank succeeds (0 on all), then ranks 1 and the last
 * fail with codes of their own: all get rank 1's code, and the ranks but 1
 * its message as "process 1 of N: ..." (rank 1 keeps its own). */
static void check_agree(mpgm_ctx *ctx) {
  const int r = mpgm_ctx_rank(ctx), n = mpgm_ctx_size(ctx);
  int e = mpgm_agree(ctx, 0);
  mpgm_test(e == 0 && ctx->code == 0, "rank %d: every process succeeded: agreed 0", r);
  int mine = 0;
  if (r == 1) mine = mpgm_err_set(ctx, MPGM_ERR_SHAPE, __FILE__, __LINE__, "point 7 left the grid");
  if (r == n - 1 && r != 1) mine = mpgm_err_set(ctx, MPGM_ERR_NAN, __FILE__, __LINE__, "a NaN");
  e = mpgm_agree(ctx, mine);
  char want[64];
  snprintf(want, sizeof want, r == 1 ? "point 7 left the grid" : "process 1 of %d: point 7 left the grid", n);
  mpgm_test(e == MPGM_ERR_SHAPE && ctx->code == MPGM_ERR_SHAPE && strcmp(ctx->msg, want) == 0,
            "rank %d: rank 1's failure on every process (code %d, '%s')", r, e, ctx->msg);
  mpgm_err_clear(ctx);
}

static void many(int launched) {
  const mpgm_comm *comm = NULL;
  char msg[512];
  const int err = mpgm_parallel_start(&comm, msg, sizeof msg);
  mpgm_test(err == 0 && comm && comm->size == launched && comm->rank >= 0 && comm->rank < launched,
            "MPI started on %d processes (%s)", launched, err ? msg : "ok");
  if (err || !comm) return;
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  ctx.comm = comm;
  const int r = comm->rank, n = comm->size;
  double s[2] = {r + 1.0, 0.5 * r}, lo = 10.0 - r, hi = r * r;
  long c[2] = {r, 1};
  int e = mpgm_allreduce(&ctx, MPGM_REDUCE_SUM, s, 2) | mpgm_allreduce(&ctx, MPGM_REDUCE_MIN, &lo, 1) |
          mpgm_allreduce(&ctx, MPGM_REDUCE_MAX, &hi, 1) |
          mpgm_allreduce_long(&ctx, MPGM_REDUCE_SUM, c, 2);
  mpgm_test(e == 0 && s[0] == n * (n + 1) / 2.0 && s[1] == 0.25 * n * (n - 1) && lo == 11.0 - n &&
                hi == (n - 1.0) * (n - 1.0) && c[0] == (long)n * (n - 1) / 2 && c[1] == n,
            "rank %d of %d: sum, min, max of doubles and the sum of integers", r, n);
  char text[32] = "";
  if (r == n - 1) strcpy(text, "from the last rank");
  e = mpgm_bcast(&ctx, text, sizeof text, n - 1);
  mpgm_test(e == 0 && strcmp(text, "from the last rank") == 0, "rank %d: a broadcast from rank %d",
            r, n - 1);
  check_agree(&ctx);
  for (int dim = 2; dim <= 3; dim++) {
    check_weights(&ctx, dim);
    check_sums(&ctx, dim);
    check_migration(&ctx, dim);
  }
  static const char *const schemes[] = {"usl", "fe", "npc"};
  for (int k = 0; k < 3; k++) check_mpm(&ctx, schemes[k]);
  mpgm_test(mpgm_parallel_start(&comm, msg, sizeof msg) == -1 && strstr(msg, "once"),
            "a second start is refused (%s)", msg);
  mpgm_parallel_finalize();
}

int main(void) {
  int rank;
  const char *var;
  const int launched = mpgm_parallel_launched(&rank, &var);
  one_process();
  if (launched > 1) many(launched);
  return mpgm_test_summary();
}
