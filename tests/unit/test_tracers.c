/* test_tracers.c -- tracers (probes and surface points) away from the
 * material (issue 16, item 1: a surface point left behind grew its search
 * radius across the domain):
 *   - mpgm_clouds_build gives a surface point with no node within its
 *     support no functions and never grows its radius (radius_growths
 *     stays 0, its search is one query), and leaves it unenforced;
 *   - mpgm_tracers_carry then gives it the functions of its nearest
 *     material point, exactly (the same nodes, N and grad N), counts it,
 *     and leaves the other points' lists as they were;
 *   - a probe moved away is treated the same (item 5: a probe the material
 *     has left follows the material, the run does not stop).
 * The scene is built in memory: GMM-MLS on a 0.8 m x 0.4 m block with a
 * contact plane under it and a probe in it; one surface point and the
 * probe are then moved 5 m away. */
#include "mpgm_core_impl.h"
#include "mpgm_discretisation.h"
#include "mpgm_kdtree.h"
#include "mpgm_scene_io.h"
#include "mpgm_test.h"

#include <cjson/cJSON.h>
#include <stdlib.h>
#include <string.h>

static int make(mpgm_ctx *ctx, mpgm_scene **s, mpgm_problem **pb) {
  const char *text =
      "{\"method\": \"gmm\", \"shape\": {\"kind\": \"mls\"},"
      " \"mesh\": {\"h\": 0.1, \"domain\": {\"min\": [0, 0], \"max\": [6, 1]}},"
      " \"time\": {\"analysis\": \"dynamic\", \"dt\": 0.01, \"end\": 0.1},"
      " \"materials\": {\"m\": {\"type\": \"neo_hookean\", \"density\": 2385.7, \"E\": 3.1e6, \"nu\": 0.287}},"
      " \"bodies\": [{\"material\": \"m\", \"rectangle\": {\"min\": [0.3, 0.0], \"max\": [1.1, 0.4]}}],"
      " \"boundaries\": [{\"y\": 0.0, \"condition\": \"contact\", \"enforce\": \"points\", \"spacing\": 0.2}],"
      " \"probes\": {\"mid\": [0.7, 0.2]},"
      " \"gravity\": [0.0, -9.81], \"output\": {\"vtk\": \"none\"}}";
  cJSON *j = cJSON_Parse(text);
  int err = j ? mpgm_scene_load_json(ctx, "tracers", j, s) : MPGM_ERR_INTERNAL;
  cJSON_Delete(j);
  if (!err) err = mpgm_problem_create(ctx, *s, NULL, pb);
  return err;
}

int main(void) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene *s = NULL;
  mpgm_problem *pb = NULL;
  mpgm_clouds *cl = NULL;
  mpgm_kdtree *tree = NULL;
  mpgm_conn out = {0}, scratch = {0};
  int err = make(&ctx, &s, &pb);
  mpgm_test(!err && pb->pts.nsurf > 0, "problem with %d surface points (%s)", err ? 0 : pb->pts.nsurf,
            err ? ctx.msg : "ok");
  if (err) goto done;
  mpgm_points *P = &pb->pts;
  const int first = P->n + P->nprobe, stray = first + P->nsurf / 2;
  mpgm_fe_view v;
  mpgm_problem_view(pb, &v);
  err = mpgm_clouds_create(&ctx, s, &cl);
  if (!err) err = mpgm_kdtree_create(&ctx, pb->nodes.x, pb->nodes.n, 0, &tree);
  /* the clouds as they are, then with one surface point 5 m from every
   * node: its search adds no radius growth and no enlargement */
  mpgm_cpoints_enforce_all(v.cp);
  if (!err) err = mpgm_clouds_build(cl, &v, tree, NULL, &out);
  const long g0 = ctx.count[MPGM_C_RADIUS_GROWTHS], e0 = ctx.count[MPGM_C_CLOUD_ENLARGEMENTS];
  P->x[MPGM_DIM * stray] += 5.0;
  P->x[MPGM_DIM * P->n] += 5.0; /* the probe */
  mpgm_cpoints_enforce_all(v.cp);
  if (!err) err = mpgm_clouds_build(cl, &v, tree, NULL, &out);
  const long dg = ctx.count[MPGM_C_RADIUS_GROWTHS] - 2 * g0;
  const long de = ctx.count[MPGM_C_CLOUD_ENLARGEMENTS] - 2 * e0;
  mpgm_test(!err && dg <= 0 && de <= 0 && out.ptr[stray + 1] == out.ptr[stray] &&
                out.ptr[P->n + 1] == out.ptr[P->n] &&
                mpgm_cpoints_unenforced(v.cp, stray - first),
            "a surface point and a probe 5 m away: no functions (no error), the surface point "
            "unenforced, no radius growth or enlargement for them (%ld, %ld more than with the point on the body) (%s)", dg, de, err ? ctx.msg : "ok");
  if (err) goto done;
  /* its nearest material point, by brute force */
  int q = 0;
  double dmin = 1e300;
  for (int p = 0; p < P->n; p++) {
    const double dx = P->x[2 * p] - P->x[2 * stray], dy = P->x[2 * p + 1] - P->x[2 * stray + 1];
    if (dx * dx + dy * dy < dmin) dmin = dx * dx + dy * dy, q = p;
  }
  const int q0 = out.ptr[q], nq = out.ptr[q + 1] - q0, other = first + (stray == first);
  int *qn = malloc(sizeof(int) * (size_t)nq);
  double *qN = malloc(sizeof(double) * (size_t)nq), *qdN = malloc(sizeof(double) * 2 * (size_t)nq);
  const int no = out.ptr[other + 1] - out.ptr[other];
  int *on = malloc(sizeof(int) * (size_t)(no + 1));
  memcpy(qn, out.node + q0, sizeof(int) * (size_t)nq);
  memcpy(qN, out.N + q0, sizeof(double) * (size_t)nq);
  memcpy(qdN, out.dN + 2 * q0, sizeof(double) * 2 * (size_t)nq);
  memcpy(on, out.node + out.ptr[other], sizeof(int) * (size_t)no);
  err = mpgm_tracers_carry(&v, &out, &scratch, NULL);
  const int k0 = out.ptr[stray], nk = out.ptr[stray + 1] - k0;
  const int same = !err && nk == nq && memcmp(out.node + k0, qn, sizeof(int) * (size_t)nq) == 0 &&
                   memcmp(out.N + k0, qN, sizeof(double) * (size_t)nq) == 0 &&
                   memcmp(out.dN + 2 * k0, qdN, sizeof(double) * 2 * (size_t)nq) == 0;
  mpgm_test(same && ctx.count[MPGM_C_SURFACE_CARRIED] == 1,
            "carried: the stray surface point takes the %d functions of its nearest point %d "
            "exactly, counted %ld time(s)", nq, q, ctx.count[MPGM_C_SURFACE_CARRIED]);
  /* the probe: the same from its own nearest point */
  int qp = 0;
  dmin = 1e300;
  for (int p = 0; p < P->n; p++) {
    const double dx = P->x[2 * p] - P->x[2 * P->n], dy = P->x[2 * p + 1] - P->x[2 * P->n + 1];
    if (dx * dx + dy * dy < dmin) dmin = dx * dx + dy * dy, qp = p;
  }
  const int np = out.ptr[P->n + 1] - out.ptr[P->n], nqp = out.ptr[qp + 1] - out.ptr[qp];
  mpgm_test(!err && np == nqp && np > 0 &&
                memcmp(out.node + out.ptr[P->n], out.node + out.ptr[qp], sizeof(int) * (size_t)np) == 0 &&
                memcmp(out.N + out.ptr[P->n], out.N + out.ptr[qp], sizeof(double) * (size_t)np) == 0 &&
                ctx.count[MPGM_C_PROBES_CARRIED] == 1,
            "carried: the probe takes the %d functions of its nearest point %d, counted %ld time(s)",
            nqp, qp, ctx.count[MPGM_C_PROBES_CARRIED]);
  const int other_same = out.ptr[other + 1] - out.ptr[other] == no &&
                         memcmp(out.node + out.ptr[other], on, sizeof(int) * (size_t)no) == 0;
  mpgm_test(other_same && mpgm_cpoints_unenforced(v.cp, stray - first),
            "the other points keep their lists; the carried point stays unenforced");
  free(qn);
  free(qN);
  free(qdN);
  free(on);
done:
  mpgm_conn_release(&out);
  mpgm_conn_release(&scratch);
  mpgm_kdtree_destroy(&tree);
  mpgm_clouds_destroy(cl);
  mpgm_problem_destroy(&pb);
  mpgm_scene_destroy(&s);
  return mpgm_test_summary();
}
