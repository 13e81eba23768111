/* scene_size.c -- a run sized before it starts (docs/scene-format.md, "Runs
 * are sized and bounded"): the memory a scene's run needs, estimated from
 * the bodies' areas, mesh.h, the points per cell, the domain's grid, the
 * method, the shape functions and the solver, checked when the scene loads
 * against the memory this process can still have (physical memory, a
 * cgroup's limit, RLIMIT_AS / RLIMIT_DATA), before any large allocation.
 *
 * The estimate is meant as a lower bound of what the run touches: it counts
 * only arrays every run of its kind fills (bench/notes/memory.md compares it
 * with the peak resident memory of the cases), so that a run it refuses
 * could not have fitted, and a run it passes may still need more. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "mpgm_frontend.h"
#include "mpgm_scene_io.h"

/* Bytes per material point of the arrays every run fills (core/data.c):
 * x, x0, u, v, a (2 each), mass, vol0, vol, F, sigma, the domain r0 (4
 * each), and the trial F_t, dF_t, sigma_t (4 each), vol_t: 42 doubles;
 * mat, body, id: 3 ints. Implicit runs add the tangent D_t (9 doubles). */
/* 3-D: x .. a 3 each, F, dF_t, F_t, r0 9 each, sigma, sigma_t 6 each,
 * mass, vol0, vol, vol_t (4 more, as in 2-D): 67 + 4 doubles; D_t 36. */
#if MPGM_DIM == 2
#define POINT_BYTES (42 * 8 + 3 * 4)
#define POINT_TANGENT_BYTES (9 * 8)
#else
#define POINT_BYTES (71 * 8 + 3 * 4)
#define POINT_TANGENT_BYTES (36 * 8)
#endif
/* Per connectivity entry: the node (int), N, grad N (1 + MPGM_DIM
 * doubles); implicit runs add grad N at the iterate (MPGM_DIM doubles). */
#define ENTRY_BYTES (4 + (1 + MPGM_DIM) * 8)
#define ENTRY_ITERATE_BYTES (MPGM_DIM * 8)
/* Per node (core/data.c, mpgm_nodes_alloc): mass, X, x, u, du, v, a,
 * v_new, a_new, ubar (1 + 9 MPGM_DIM doubles), fix, contact, dof
 * (1 + 2 MPGM_DIM ints). */
#define NODE_BYTES ((1 + 9 * MPGM_DIM) * 8 + (1 + 2 * MPGM_DIM) * 4)
/* Per node of MPM's background grid: its map and flags (mpm/mpm.c). */
#define GRID_NODE_BYTES 6
/* Per nonzero of the tangent (CSC: value and row) and of a factor. */
#define NONZERO_BYTES (8 + 4)
/* Per point while VTK fields are written (J, material, id, eps_p). */
#define VTK_POINT_BYTES (4 * 8)
/* The fill of a direct factorisation per equation beyond the tangent's
 * own lower half: FILL_LOG log2(k), k the nodes across the narrowest side
 * of the largest body, the growth of nested dissection on a 2-D mesh
 * (George 1973: 31/8 N log2 N for a k x k grid, N = k^2); FILL_LOG sits
 * below every factor of bench/notes/memory.md (CHOLMOD's, 4.1 to 8.6 on the
 * cantilever's Q4 strip). */
#define FILL_LOG 4.0

/* A meshfree kind's clouds (MLS, LME): a point's nodes, and the nodes a
 * node is coupled to, on bodies of area `area` and perimeter `perim`:
 * the support disk of radius r (a disk of radius 1.5 r for the coupling,
 * short of the 2 r within which two clouds can meet), of which a point
 * within r of the boundary has about half: a share 1 - perim r / (2 area)
 * of a full disk, at least a quarter (a corner), and at least
 * shape.min_nodes (6, or 12 for a quadratic basis). 0 for the kinds of
 * cells. */
static int cloud(const mpgm_scene *s, double area, double perim, double *e, double *coupled) {
  double r = 0.0;
  if (s->shape->needs_cell || s->shape->grid_only || s->shape->domain ||
      mpgm_shape_support_radius(s->shape, &s->shape_par, &r) != 0 || !(r > 0.0))
    return 0;
  const double share = fmax(0.25, 1.0 - perim * r / (2.0 * area)), q = r / s->h;
  const double least = mpgm_shape_min_nodes(&s->shape_par);
  *e = fmax(least, share * 3.14159265358979323846 * q * q);
  *coupled = fmax(*e, share * 3.14159265358979323846 * 2.25 * q * q);
  return 1;
}

#if MPGM_DIM == 3
/* The counts of a 3-D scene (H8 cells; bodies of volume mpgm_body_area):
 * 8 nodes a point, 27 coupled to a node, 3 x 3 entries a pair; a direct
 * factor's fill on a k^3 grid grows as N^(4/3) (George and Liu 1981),
 * here FILL_LOG k coupled / 27 entries per equation beyond the tangent's
 * lower half (unchecked against measured factors in 3-D). */
static int size_counts3(const mpgm_scene *s, mpgm_size *z) {
  double vol = 0.0, big = 0.0, width = 0.0, g = 1.0;
  for (int b = 0; b < s->nbody; b++) {
    const double v = mpgm_body_area(&s->bodies[b]);
    vol += v;
    if (v > big) {
      big = v;
      width = mpgm_body_width(&s->bodies[b]);
    }
  }
  const double h3 = s->h * s->h * s->h;
  z->points = s->ppc * vol / h3;
  z->nodes = vol / h3;
  for (int d = 0; d < 3; d++) g *= ceil((s->dom_max[d] - s->dom_min[d]) / s->h) + 1.0;
  z->grid_nodes = s->frontend->persistent_nodes ? 0.0 : g;
  const double coupled = 27.0;
  z->entries = z->points * 8.0;
  const int implicit = s->analysis != MPGM_ANALYSIS_EXPLICIT;
  z->nnz = implicit ? 9.0 * z->nodes * coupled : 0.0;
  const double ndof = 3.0 * z->nodes, k = fmax(2.0, width / s->h + 1.0);
  z->factor = implicit && !s->solver->iterative ? 0.5 * z->nnz + ndof * FILL_LOG * k * coupled / 27.0 : 0.0;
  const double steps = s->analysis == MPGM_ANALYSIS_STATIC ? s->load_steps
                       : s->dt > 0.0                        ? ceil(s->t_end / s->dt)
                                                            : 0.0;
  z->history = steps * (17.0 + 2.0 + 2.0 * s->nprobe);
  return 1;
}
#endif

/* The counts: points, nodes, entries, the tangent's and a factor's
 * nonzeros, the rows of the histories. */
static void size_counts(const mpgm_scene *s, mpgm_size *z) {
#if MPGM_DIM == 3
  if (size_counts3(s, z)) return;
#endif
  const double cells_per_area = (s->cell == MPGM_CELL_Q4 ? 1.0 : 2.0) / (s->h * s->h);
  double area = 0.0, perim = 0.0, big = 0.0, width = 0.0;
  for (int b = 0; b < s->nbody; b++) {
    const double a = mpgm_body_area(&s->bodies[b]);
    area += a;
    perim += mpgm_body_perimeter(&s->bodies[b]);
    if (a > big) {
      big = a;
      width = mpgm_body_width(&s->bodies[b]);
    }
  }
  z->points = cells_per_area * s->ppc * area;
  z->nodes = area / (s->h * s->h);
  const double gx = ceil((s->dom_max[0] - s->dom_min[0]) / s->h), gy = ceil((s->dom_max[1] - s->dom_min[1]) / s->h);
  z->grid_nodes = s->frontend->persistent_nodes ? 0.0 : (gx + 1.0) * (gy + 1.0);
  /* a cell's nodes, and the nodes of the cells around a node (9 of Q4, 7
   * of T3 on the grid) */
  double e = s->cell == MPGM_CELL_Q4 ? 4.0 : 3.0, coupled = s->cell == MPGM_CELL_Q4 ? 9.0 : 7.0;
  (void)cloud(s, area, perim, &e, &coupled);
  z->entries = z->points * e;
  const int implicit = s->analysis != MPGM_ANALYSIS_EXPLICIT;
  z->nnz = implicit ? 4.0 * z->nodes * coupled : 0.0; /* 2 x 2 entries a pair */
  /* the factor's growth beyond the tangent's lower half widens with the
   * coupling, as the separators of nested dissection do */
  const double ndof = 2.0 * z->nodes, k = fmax(2.0, width / s->h + 1.0);
  z->factor = implicit && !s->solver->iterative
                  ? 0.5 * z->nnz + ndof * FILL_LOG * log2(k) * coupled / 9.0 : 0.0;
  /* steps.csv (17 numbers a step) and probes.csv (2 + 2 per probe): the
   * fixed steps; the CFL condition's are not known before the run */
  const double steps = s->analysis == MPGM_ANALYSIS_STATIC ? s->load_steps
                       : s->dt > 0.0                        ? ceil(s->t_end / s->dt)
                                                            : 0.0;
  z->history = steps * (17.0 + 2.0 + 2.0 * s->nprobe);
}

void mpgm_scene_size(const mpgm_scene *s, mpgm_size *z) {
  memset(z, 0, sizeof *z);
  size_counts(s, z);
  const int implicit = s->analysis != MPGM_ANALYSIS_EXPLICIT;
  int nstate = 0;
  for (int i = 0; i < s->nmat; i++)
    if (s->mats[i].type->nstate > nstate) nstate = s->mats[i].type->nstate;
  const double point = POINT_BYTES + (implicit ? POINT_TANGENT_BYTES : 0) + 2.0 * 8 * nstate +
                       (s->vtk != MPGM_VTK_NONE ? VTK_POINT_BYTES : 0);
  z->bytes[MPGM_SIZE_POINTS] = z->points * point;
  z->bytes[MPGM_SIZE_CONN] = z->entries * (ENTRY_BYTES + (implicit ? ENTRY_ITERATE_BYTES : 0));
  z->bytes[MPGM_SIZE_NODES] = z->nodes * NODE_BYTES + z->grid_nodes * GRID_NODE_BYTES;
  z->bytes[MPGM_SIZE_MATRIX] = z->nnz * NONZERO_BYTES * (implicit && s->solver->iterative ? 2 : 1);
  z->bytes[MPGM_SIZE_FACTOR] = z->factor * NONZERO_BYTES;
  z->bytes[MPGM_SIZE_HISTORY] = z->history * 8.0;
  z->bytes[MPGM_SIZE_LIBRARY] = implicit ? s->solver->library_bytes : 0.0; /* a library loaded */
  for (int i = 0; i < MPGM_SIZE_PARTS; i++) z->total += z->bytes[i];
}

/* A number of bytes in a file's first line ("max" and unreadable: none,
 * INFINITY). */
static double file_bytes(const char *path) {
  FILE *f = fopen(path, "r");
  if (!f) return INFINITY;
  char line[64] = "";
  const int got = fgets(line, sizeof line, f) != NULL;
  fclose(f);
  char *end;
  const double v = got ? strtod(line, &end) : NAN;
  return got && end != line && v >= 0.0 ? v : INFINITY;
}

/* The room left under a cgroup's memory limit, from the cgroup of this
 * process (/proc/self/cgroup) up to the root of the mount: cgroup v2's
 * memory.max - memory.current, v1's memory.limit_in_bytes -
 * memory.usage_in_bytes, the least over the levels (INFINITY: none). */
static double cgroup_room(void) {
  FILE *f = fopen("/proc/self/cgroup", "r");
  if (!f) return INFINITY;
  char line[1024], v2[1024] = "", v1[1024] = "";
  while (fgets(line, sizeof line, f)) {
    line[strcspn(line, "\n")] = '\0';
    char *c1 = strchr(line, ':'), *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
    if (!c2) continue;
    *c2 = '\0';
    if (strcmp(line, "0") == 0 && c1[1] == '\0') snprintf(v2, sizeof v2, "%s", c2 + 1);
    else if (strstr(c1 + 1, "memory")) snprintf(v1, sizeof v1, "%s", c2 + 1);
  }
  fclose(f);
  double room = INFINITY;
  for (int v = 0; v < 2; v++) {
    char rel[1024];
    snprintf(rel, sizeof rel, "%s", v == 0 ? v2 : v1);
    if (v == 1 && !v1[0]) break;
    if (v == 0 && !v2[0]) continue;
    for (;;) { /* this level, then its parents */
      char lim[1200], use[1200];
      const char *root = v == 0 ? "/sys/fs/cgroup" : "/sys/fs/cgroup/memory";
      snprintf(lim, sizeof lim, "%s%s/%s", root, rel, v == 0 ? "memory.max" : "memory.limit_in_bytes");
      snprintf(use, sizeof use, "%s%s/%s", root, rel, v == 0 ? "memory.current" : "memory.usage_in_bytes");
      const double l = file_bytes(lim), u = file_bytes(use);
      if (isfinite(l) && l < 1e18) room = fmin(room, isfinite(u) ? fmax(0.0, l - u) : l);
      char *slash = strrchr(rel, '/');
      if (!slash || !rel[0]) break;
      *slash = '\0';
    }
  }
  return room;
}

/* The physical memory the system can still give (MemAvailable of
 * /proc/meminfo; INFINITY when unknown). */
static double mem_available(void) {
  FILE *f = fopen("/proc/meminfo", "r");
  if (!f) return INFINITY;
  char line[256];
  double kb = INFINITY;
  while (fgets(line, sizeof line, f))
    if (sscanf(line, "MemAvailable: %lf kB", &kb) == 1) break;
  fclose(f);
  return isfinite(kb) ? 1024.0 * kb : INFINITY;
}

/* The room under RLIMIT_AS (address space) and RLIMIT_DATA (data
 * segment), less what this process maps now (/proc/self/statm). */
static double rlimit_room(void) {
  double room = INFINITY, size = 0.0, data = 0.0;
  FILE *f = fopen("/proc/self/statm", "r");
  if (f) {
    double pages[6] = {0};
    if (fscanf(f, "%lf %*f %*f %*f %*f %lf", &pages[0], &pages[5]) == 2) {
      const double page = (double)sysconf(_SC_PAGESIZE);
      size = page * pages[0];
      data = page * pages[5];
    }
    fclose(f);
  }
  struct rlimit r;
  if (getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    room = fmin(room, fmax(0.0, (double)r.rlim_cur - size));
  if (getrlimit(RLIMIT_DATA, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    room = fmin(room, fmax(0.0, (double)r.rlim_cur - data));
  return room;
}

double mpgm_memory_available(const char **what) {
  const double m = mem_available(), c = cgroup_room(), r = rlimit_room();
  double a = m;
  *what = "physical memory available (MemAvailable)";
  if (c < a) {
    a = c;
    *what = "room under the cgroup's memory limit";
  }
  if (r < a) {
    a = r;
    *what = "room under the process's RLIMIT_AS / RLIMIT_DATA";
  }
  return a;
}

/* bytes as "12.3 GiB", "456 MiB" into buf. */
static const char *human(double bytes, char *buf, size_t n) {
  static const char *const unit[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024.0 && u < 6) {
    bytes /= 1024.0;
    u++;
  }
  snprintf(buf, n, "%.3g %s", bytes, unit[u]);
  return buf;
}

void mpgm_size_format(const mpgm_size *z, char *buf, size_t n) {
  static const char *const name[MPGM_SIZE_PARTS] = {"points", "connectivity", "nodes", "matrix",
                                                    "factor", "histories", "PETSc"};
  char h[32];
  int k = snprintf(buf, n, "about %s (%.3g points, %.3g nodes", human(z->total, h, sizeof h),
                   z->points, z->nodes + z->grid_nodes);
  if (z->nnz > 0.0 && k >= 0 && (size_t)k < n) k += snprintf(buf + k, n - (size_t)k, ", %.3g nonzeros", z->nnz);
  if (z->factor > 0.0 && k >= 0 && (size_t)k < n)
    k += snprintf(buf + k, n - (size_t)k, ", %.3g in the factor", z->factor);
  for (int i = 0; i < MPGM_SIZE_PARTS && k >= 0 && (size_t)k < n; i++)
    if (z->bytes[i] > 0.0)
      k += snprintf(buf + k, n - (size_t)k, "%s%s %s", i == 0 ? ": " : ", ", name[i],
                    human(z->bytes[i], h, sizeof h));
  if (k >= 0 && (size_t)k < n) snprintf(buf + k, n - (size_t)k, ")");
}

int mpgm_scene_size_check(mpgm_ctx *ctx, const mpgm_scene *s) {
  mpgm_size z;
  mpgm_scene_size(s, &z);
  const char *what;
  const double avail = mpgm_memory_available(&what);
  if (!(z.total > avail)) return 0;
  char est[512], a[32];
  mpgm_size_format(&z, est, sizeof est);
  /* the largest part says what to change */
  int big = 0;
  for (int i = 1; i < MPGM_SIZE_PARTS; i++)
    if (z.bytes[i] > z.bytes[big]) big = i;
  const char *key = big == MPGM_SIZE_HISTORY ? (s->analysis == MPGM_ANALYSIS_STATIC ? "time.load_steps" : "time.dt")
                                             : "mesh.h";
  const char *change = big == MPGM_SIZE_HISTORY ? "fewer steps (a larger time.dt, fewer load steps)"
                       : big == MPGM_SIZE_FACTOR ? "a coarser mesh.h, or an iterative solver.linear (\"petsc\")"
                                                 : "a coarser mesh.h or fewer points per cell (mesh.ppc)";
  MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: %s: the run needs %s, and %s are available (%s): %s", s->file,
             key, est, human(avail, a, sizeof a), what, change);
}
