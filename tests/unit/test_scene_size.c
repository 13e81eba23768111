/* test_scene_size.c -- the memory estimate of a run (io/scene_size.c) on
 * scenes loaded from text: the counts it starts from (points, nodes, grid,
 * entries, nonzeros, history rows) against what the cases' runs have, the
 * bytes as the per-item sizes times the counts, and the memory available
 * (a positive number, and under an RLIMIT_AS 400 MiB above the process's
 * size, the room left under it). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "mpgm_scene_io.h"
#include "mpgm_test.h"

/* A cantilever (8 m x 1 m at h = 0.125, Q4, 4 points a cell: 2048 points
 * and 585 nodes in its runs) as method and analysis `extra` say. */
/* this process's mapped size (/proc/self/statm's first field), or -1 */
static double statm_bytes(void) {
  double pages = -1.0;
  FILE *f = fopen("/proc/self/statm", "r");
  if (f && fscanf(f, "%lf", &pages) != 1) pages = -1.0;
  if (f) fclose(f);
  return pages < 0.0 ? -1.0 : pages * (double)sysconf(_SC_PAGESIZE);
}

static int load(mpgm_ctx *ctx, const char *extra, mpgm_scene **s) {
  char text[2048];
  snprintf(text, sizeof text,
           "{\"mesh\": {\"h\": 0.125, \"domain\": {\"min\": [-0.5, -3], \"max\": [9, 1.5]}}, %s"
           "\"materials\": {\"beam\": {\"type\": \"neo_hookean\", \"density\": 1000, \"E\": 9e7, "
           "\"nu\": 0}}, \"bodies\": [{\"material\": \"beam\", \"rectangle\": {\"min\": [0, 0], "
           "\"max\": [8, 1]}}], \"boundaries\": [{\"x\": 0, \"fix\": [\"x\", \"y\"]}], "
           "\"probes\": {\"tip\": [8, 0.5]}, \"output\": {\"vtk\": \"none\"}}", extra);
  return mpgm_scene_load_text(ctx, "size.json", text, strlen(text), 0, NULL, s);
}

int main(void) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_scene *s = NULL;
  mpgm_size z;
  /* static UL-FEM, one load step with CHOLMOD (the default "auto") */
  mpgm_test(load(&ctx, "\"method\": \"fem\",", &s) == 0, "fem cantilever loads: %s", ctx.msg);
  if (s) {
    mpgm_scene_size(s, &z);
    mpgm_test_rel(z.points, 2048.0, TEST_TOL1, "fem: points of 8 m x 1 m at h = 1/8, ppc 4");
    mpgm_test_rel(z.nodes, 512.0, TEST_TOL1, "fem: nodes area / h^2 (585 in the mesh)");
    mpgm_test(z.grid_nodes == 0.0, "fem: no background grid");
    mpgm_test_rel(z.entries, 4.0 * 2048.0, TEST_TOL1, "fem: 4 entries a point");
    mpgm_test_rel(z.nnz, 4.0 * 9.0 * 512.0, TEST_TOL1, "fem: 9 nodes x 2 x 2 a node (19000 in the run)");
    mpgm_test(z.factor > 0.5 * z.nnz && z.factor < 25448.0, "fem: factor %g between half the tangent and "
              "CHOLMOD's 25448", z.factor);
    mpgm_test_rel(z.history, 1.0 * (17 + 2 + 2), TEST_TOL1, "fem: one load step's rows, one probe");
    mpgm_test_rel(z.bytes[MPGM_SIZE_POINTS], 2048.0 * (348 + 72), TEST_TOL1, "fem: 420 B a point");
    mpgm_test_rel(z.bytes[MPGM_SIZE_CONN], 4.0 * 2048.0 * 44, TEST_TOL1, "fem: 44 B an entry");
    double sum = 0.0;
    for (int i = 0; i < MPGM_SIZE_PARTS; i++) sum += z.bytes[i];
    mpgm_test_rel(z.total, sum, TEST_TOL1, "fem: the total is the parts' sum");
    char line[512];
    mpgm_size_format(&z, line, sizeof line);
    mpgm_test(strstr(line, "2.05e+03 points") && strstr(line, "factor"), "format: %s", line);
    mpgm_test(mpgm_scene_size_check(&ctx, s) == 0, "fem cantilever fits: %s", ctx.msg);
    mpgm_scene_destroy(&s);
  }
  /* explicit MPM with a fixed step: no matrix, the grid of the domain */
  mpgm_ctx_init(&ctx);
  mpgm_test(load(&ctx, "\"method\": \"mpm\", \"kinematics\": \"finite\", \"time\": {\"analysis\": "
                 "\"explicit\", \"scheme\": \"usl\", \"dt\": 1e-4, \"end\": 0.1},", &s) == 0,
            "explicit mpm loads: %s", ctx.msg);
  if (s) {
    mpgm_scene_size(s, &z);
    mpgm_test_rel(z.grid_nodes, 77.0 * 37.0, TEST_TOL1, "mpm: grid (9.5 / h + 1) x (4.5 / h + 1)");
    mpgm_test(z.nnz == 0.0 && z.factor == 0.0, "explicit: no tangent, no factor");
    mpgm_test_rel(z.history, 1000.0 * 21.0, TEST_TOL1, "explicit: 1000 fixed steps' rows");
    mpgm_test_rel(z.bytes[MPGM_SIZE_POINTS], 2048.0 * 348, TEST_TOL1, "explicit: 348 B a point");
    mpgm_scene_destroy(&s);
  }
  /* a meshfree kind's clouds: LME's support r = h sqrt(-ln 1e-6 / 1.8) */
  mpgm_ctx_init(&ctx);
  mpgm_test(load(&ctx, "\"method\": \"gmm\", \"shape\": {\"kind\": \"lme\"},", &s) == 0, "gmm lme loads: %s",
            ctx.msg);
  if (s) {
    mpgm_scene_size(s, &z);
    const double q2 = -log(1e-6) / 1.8, share = 1.0 - 18.0 * 0.125 * sqrt(q2) / 16.0;
    mpgm_test_rel(z.entries / z.points, share * 3.14159265358979323846 * q2, TEST_TOL2, "lme: the disk less the boundary's "
                  "half-disks (%g entries a point)", z.entries / z.points);
    mpgm_test_rel(z.nnz / (4.0 * z.nodes), share * 3.14159265358979323846 * 2.25 * q2, TEST_TOL2, "lme: coupled within 1.5 r");
    mpgm_scene_destroy(&s);
  }
  /* what is available: a positive number, and under an RLIMIT_AS of the
   * process's size + 400 MiB, the room under it: between the limit less
   * the size read after the call and the limit less the size read before
   * it (a thread of the process may map memory in between, e.g. a malloc
   * arena of 64 MiB, so the size is bracketed, not assumed fixed) */
  const char *what = NULL;
  const double avail = mpgm_memory_available(&what);
  mpgm_test(avail > 0.0 && what, "available %g B (%s)", avail, what ? what : "?");
  const double before = statm_bytes();
  struct rlimit old, lim;
  if (before > 0.0 && avail > 500.0 * 1048576.0 && getrlimit(RLIMIT_AS, &old) == 0) {
    lim.rlim_cur = (rlim_t)(before + 400.0 * 1048576.0);
    lim.rlim_max = old.rlim_max;
    if (setrlimit(RLIMIT_AS, &lim) == 0) {
      const double a = mpgm_memory_available(&what);
      const double after = statm_bytes();
      setrlimit(RLIMIT_AS, &old);
      const double hi = (double)lim.rlim_cur - before, lo = fmax(0.0, (double)lim.rlim_cur - after);
      mpgm_test(a >= lo && a <= hi && strstr(what, "RLIMIT"),
                "under RLIMIT_AS of the size + 400 MiB: %g B in [%g, %g] (%s)", a, lo, hi, what);
    }
  }
  return mpgm_test_summary();
}
