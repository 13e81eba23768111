/* grid.c -- the background grid of a run on many processes, in the module
 * mpgm_par.so (mpgm_parallel.h, "Partitioned grid"): its nodes partitioned
 * over the processes by PETSc's DMDA (a box stencil as wide as the shape
 * functions reach), the sums over the processes' shared nodes by the DM's
 * local-to-global (ADD_VALUES) and global-to-local scatters, and records
 * (material points packed as doubles) sent to the process that owns their
 * cell by a DMSwarm of type basic (DMSwarmMigrate). */
#include <petscdmda.h>
#include <petscdmswarm.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_parallel_ops.h"

enum { MAXW = 16 }; /* values per node a sum may carry */

struct mpgm_pgrid {
  DM da;
  Vec loc, glob;
  DM daw[MAXW + 1];      /**< the same partition with w values per node
                              (made when a sum of w < dof first comes)   */
  Vec locw[MAXW + 1], globw[MAXW + 1];
  int dim, dof, rank;
  int n[3];              /**< nodes per direction                        */
  int lo[3], hi[3];      /**< nodes owned: lo <= i < hi                  */
  int glo[3], ghi[3];    /**< nodes of the ghosted box                   */
  int np[3];             /**< processes per direction                    */
  int *start[3];         /**< first node of each process's slab, np + 1  */
  DM sw;                 /**< the swarm of migrating records (lazily)    */
  int rec;               /**< doubles per record of sw                   */
};

static int fail(char *msg, size_t len, PetscErrorCode e, const char *what) {
  const char *text = NULL;
  PetscErrorMessage((int)e, &text, NULL);
  snprintf(msg, len, "PETSc %s failed (error %d: %s)", what, (int)e, text ? text : "unknown");
  return -1;
}

#define TRY(call, what)                                                                   \
  do {                                                                                    \
    PetscErrorCode e_ = (call);                                                           \
    if (e_) return fail(msg, len, e_, (what));                                            \
  } while (0)

static int slabs(mpgm_pgrid *g, char *msg, size_t len) {
  const PetscInt *l[3] = {NULL, NULL, NULL};
  PetscInt m[3] = {1, 1, 1};
  TRY(DMDAGetInfo(g->da, NULL, NULL, NULL, NULL, &m[0], &m[1], &m[2], NULL, NULL, NULL, NULL, NULL,
                  NULL), "DMDAGetInfo");
  TRY(DMDAGetOwnershipRanges(g->da, &l[0], &l[1], g->dim == 3 ? &l[2] : NULL), "DMDAGetOwnershipRanges");
  for (int d = 0; d < 3; d++) {
    g->np[d] = d < g->dim ? (int)m[d] : 1;
    g->start[d] = malloc(sizeof(int) * (g->np[d] + 1));
    if (!g->start[d]) return snprintf(msg, len, "out of memory"), -1;
    g->start[d][0] = 0;
    for (int p = 0; p < g->np[d]; p++) g->start[d][p + 1] = g->start[d][p] + (d < g->dim ? (int)l[d][p] : 1);
  }
  return 0;
}

static int corners(mpgm_pgrid *g, char *msg, size_t len) {
  PetscInt x[3], w[3], gx[3], gw[3];
  TRY(DMDAGetCorners(g->da, &x[0], &x[1], &x[2], &w[0], &w[1], &w[2]), "DMDAGetCorners");
  TRY(DMDAGetGhostCorners(g->da, &gx[0], &gx[1], &gx[2], &gw[0], &gw[1], &gw[2]),
      "DMDAGetGhostCorners");
  for (int d = 0; d < 3; d++) {
    const int on = d < g->dim;
    g->lo[d] = on ? (int)x[d] : 0;
    g->hi[d] = on ? (int)(x[d] + w[d]) : 1;
    g->glo[d] = on ? (int)gx[d] : 0;
    g->ghi[d] = on ? (int)(gx[d] + gw[d]) : 1;
  }
  return 0;
}

/* The n nodes of a direction cut into m slabs of about equal weight
 * (w[i]: the work of the cells whose lowest node is i), each at least
 * minl nodes: the slabs' sizes into l. */
static void weighted_cuts(const double *w, int n, int m, int minl, PetscInt *l) {
  double total = 0.0;
  for (int i = 0; i < n; i++) total += w[i] > 0.0 ? w[i] : 0.0;
  int prev = 0;
  double cum = 0.0;
  for (int r = 1, i = 0; r < m; r++) {
    const double want = total * r / m;
    for (; i < n; i++) { /* the layer that brings the sum nearest the share */
      const double wi = w[i] > 0.0 ? w[i] : 0.0;
      if (cum + wi > want && want - cum <= cum + wi - want) break;
      cum += wi;
    }
    int c = total > 0.0 ? i : (int)((long)n * r / m); /* (no weight: even) */
    if (c < prev + minl) c = prev + minl;
    if (c > n - (m - r) * minl) c = n - (m - r) * minl;
    l[r - 1] = c - prev;
    prev = c;
  }
  l[m - 1] = n - prev;
}

/* The DMDA of n nodes over the processes: PETSc's process grid, and with
 * weights the slabs cut by them (a first DMDA tells the process grid). */
static int make_da(MPI_Comm c, int dim, const int n[3], int dof, int width, const double *const w[3],
                   DM *da, char *msg, size_t len) {
  const DMBoundaryType b = DM_BOUNDARY_NONE;
  PetscInt *l[3] = {NULL, NULL, NULL};
  /* (ownership ranges need the process grid given: PETSc's, found first) */
  PetscInt m[3] = {PETSC_DECIDE, PETSC_DECIDE, PETSC_DECIDE};
  for (int pass = 0; pass < (w ? 2 : 1); pass++) {
    if (dim == 2)
      TRY(DMDACreate2d(c, b, b, DMDA_STENCIL_BOX, n[0], n[1], m[0], m[1], dof, width, l[0], l[1], da),
          "DMDACreate2d");
    else
      TRY(DMDACreate3d(c, b, b, b, DMDA_STENCIL_BOX, n[0], n[1], n[2], m[0], m[1], m[2], dof, width,
                       l[0], l[1], l[2], da), "DMDACreate3d");
    TRY(DMSetUp(*da), "DMSetUp of the DMDA");
    if (!w || pass == 1) break;
    TRY(DMDAGetInfo(*da, NULL, NULL, NULL, NULL, &m[0], &m[1], &m[2], NULL, NULL, NULL, NULL, NULL,
                    NULL), "DMDAGetInfo");
    TRY(DMDestroy(da), "DMDestroy");
    for (int d = 0; d < dim; d++) {
      l[d] = malloc(sizeof(PetscInt) * (size_t)m[d]);
      if (!l[d]) return snprintf(msg, len, "out of memory"), -1;
      weighted_cuts(w[d], n[d], (int)m[d], width + 1, l[d]);
    }
  }
  for (int d = 0; d < 3; d++) free(l[d]);
  return 0;
}

static int pg_create(void *comm, int dim, const int n[3], int dof, int width, const double *const w[3],
                     mpgm_pgrid **out, char *msg, size_t len) {
  MPI_Comm c = *(MPI_Comm *)comm;
  mpgm_pgrid *g = calloc(1, sizeof *g);
  if (!g) return snprintf(msg, len, "out of memory"), -1;
  *out = g;
  g->dim = dim;
  g->dof = dof;
  MPI_Comm_rank(c, &g->rank);
  for (int d = 0; d < 3; d++) g->n[d] = d < dim ? n[d] : 1;
  if (make_da(c, dim, n, dof, width, w, &g->da, msg, len)) return -1;
  TRY(DMCreateLocalVector(g->da, &g->loc), "DMCreateLocalVector");
  TRY(DMCreateGlobalVector(g->da, &g->glob), "DMCreateGlobalVector");
  if (corners(g, msg, len) || slabs(g, msg, len)) return -1;
  return 0;
}

static void pg_destroy(mpgm_pgrid *g) {
  if (!g) return;
  VecDestroy(&g->loc);
  VecDestroy(&g->glob);
  DMDestroy(&g->da);
  DMDestroy(&g->sw);
  for (int w = 0; w <= MAXW; w++) {
    VecDestroy(&g->locw[w]);
    VecDestroy(&g->globw[w]);
    DMDestroy(&g->daw[w]);
  }
  for (int d = 0; d < 3; d++) free(g->start[d]);
  free(g);
}

static void pg_boxes(const mpgm_pgrid *g, int lo[3], int hi[3], int glo[3], int ghi[3]) {
  for (int d = 0; d < 3; d++) {
    if (lo) lo[d] = g->lo[d];
    if (hi) hi[d] = g->hi[d];
    if (glo) glo[d] = g->glo[d];
    if (ghi) ghi[d] = g->ghi[d];
  }
}

/* The slab of direction d that holds node i (the last slab for i past
 * the end: a cell of the last node row belongs to the last process). */
static int slab_of(const mpgm_pgrid *g, int d, int i) {
  int a = 0, b = g->np[d] - 1;
  while (a < b) { /* the last slab whose start is <= i */
    const int m = (a + b + 1) / 2;
    if (g->start[d][m] <= i) a = m;
    else b = m - 1;
  }
  return a;
}

static int pg_owner(const mpgm_pgrid *g, const int ijk[3]) {
  int r = 0;
  for (int d = g->dim - 1; d >= 0; d--) r = r * g->np[d] + slab_of(g, d, ijk[d]);
  return r;
}

/* The offset of node ijk in the ghosted local vector (-1 outside it). */
static long local_at(const mpgm_pgrid *g, const int *ijk) {
  long o = 0;
  for (int d = g->dim - 1; d >= 0; d--) {
    if (ijk[d] < g->glo[d] || ijk[d] >= g->ghi[d]) return -1;
    o = o * (g->ghi[d] - g->glo[d]) + (ijk[d] - g->glo[d]);
  }
  return o;
}

/* The DM and vectors of sums of w values per node: the grid's own (w =
 * dof), or a compatible DMDA of w fields, made once. */
static int sums_dm(mpgm_pgrid *g, int w, DM *da, Vec *loc, Vec *glob, char *msg, size_t len) {
  if (w == g->dof) {
    *da = g->da, *loc = g->loc, *glob = g->glob;
    return 0;
  }
  if (!g->daw[w]) {
    TRY(DMDACreateCompatibleDMDA(g->da, w, &g->daw[w]), "DMDACreateCompatibleDMDA");
    TRY(DMCreateLocalVector(g->daw[w], &g->locw[w]), "DMCreateLocalVector");
    TRY(DMCreateGlobalVector(g->daw[w], &g->globw[w]), "DMCreateGlobalVector");
  }
  *da = g->daw[w], *loc = g->locw[w], *glob = g->globw[w];
  return 0;
}

static int pg_sum(mpgm_pgrid *g, int n, const int *ijk, int w, double *val, char *msg, size_t len) {
  if (w < 1 || w > g->dof || w > MAXW)
    return snprintf(msg, len, "sums of %d values per node on a grid of %d", w, g->dof), -1;
  DM da;
  Vec loc, glob;
  if (sums_dm(g, w, &da, &loc, &glob, msg, len)) return -1;
  PetscScalar *a;
  TRY(VecZeroEntries(loc), "VecZeroEntries");
  TRY(VecGetArray(loc, &a), "VecGetArray");
  for (int i = 0; i < n; i++) {
    const long o = local_at(g, ijk + g->dim * i);
    if (o < 0) {
      VecRestoreArray(loc, &a);
      snprintf(msg, len, "node %d of %d lies outside process %d's ghosted box (the shape "
               "functions reach further than the grid's stencil)", i, n, g->rank);
      return -1;
    }
    for (int c = 0; c < w; c++) a[w * o + c] += val[w * i + c];
  }
  TRY(VecRestoreArray(loc, &a), "VecRestoreArray");
  TRY(VecZeroEntries(glob), "VecZeroEntries");
  TRY(DMLocalToGlobal(da, loc, ADD_VALUES, glob), "DMLocalToGlobal");
  TRY(DMGlobalToLocal(da, glob, INSERT_VALUES, loc), "DMGlobalToLocal");
  const PetscScalar *r;
  TRY(VecGetArrayRead(loc, &r), "VecGetArrayRead");
  for (int i = 0; i < n; i++) {
    const long o = local_at(g, ijk + g->dim * i);
    for (int c = 0; c < w; c++) val[w * i + c] = r[w * o + c];
  }
  TRY(VecRestoreArrayRead(loc, &r), "VecRestoreArrayRead");
  return 0;
}

static int swarm(mpgm_pgrid *g, int rec, char *msg, size_t len) {
  if (g->sw) {
    if (rec == g->rec) return 0;
    snprintf(msg, len, "records of %d doubles, where the grid's swarm holds %d", rec, g->rec);
    return -1;
  }
  MPI_Comm c;
  TRY(PetscObjectGetComm((PetscObject)g->da, &c), "PetscObjectGetComm");
  TRY(DMCreate(c, &g->sw), "DMCreate");
  TRY(DMSetType(g->sw, DMSWARM), "DMSetType");
  TRY(DMSetDimension(g->sw, g->dim), "DMSetDimension");
  TRY(DMSwarmSetType(g->sw, DMSWARM_BASIC), "DMSwarmSetType");
  TRY(DMSwarmRegisterPetscDatatypeField(g->sw, "record", rec, PETSC_REAL), "DMSwarmRegister");
  TRY(DMSwarmFinalizeFieldRegister(g->sw), "DMSwarmFinalizeFieldRegister");
  g->rec = rec;
  return 0;
}

static int pg_migrate(mpgm_pgrid *g, int rec, int nout, const double *out, const int *dest,
                      int *nin, double **in, char *msg, size_t len) {
  *nin = 0;
  *in = NULL;
  if (swarm(g, rec, msg, len)) return -1;
  TRY(DMSwarmSetLocalSizes(g->sw, nout, 16), "DMSwarmSetLocalSizes");
  PetscReal *r;
  PetscInt *rk;
  TRY(DMSwarmGetField(g->sw, "record", NULL, NULL, (void **)&r), "DMSwarmGetField");
  if (nout) memcpy(r, out, sizeof(double) * (size_t)rec * nout);
  TRY(DMSwarmRestoreField(g->sw, "record", NULL, NULL, (void **)&r), "DMSwarmRestoreField");
  TRY(DMSwarmGetField(g->sw, DMSwarmField_rank, NULL, NULL, (void **)&rk), "DMSwarmGetField");
  for (int i = 0; i < nout; i++) rk[i] = dest[i];
  TRY(DMSwarmRestoreField(g->sw, DMSwarmField_rank, NULL, NULL, (void **)&rk), "DMSwarmRestoreField");
  TRY(DMSwarmMigrate(g->sw, PETSC_TRUE), "DMSwarmMigrate");
  PetscInt m;
  TRY(DMSwarmGetLocalSize(g->sw, &m), "DMSwarmGetLocalSize");
  *in = malloc(sizeof(double) * ((size_t)rec * m + 1));
  if (!*in) return snprintf(msg, len, "out of memory for %d records", (int)m), -1;
  TRY(DMSwarmGetField(g->sw, "record", NULL, NULL, (void **)&r), "DMSwarmGetField");
  if (m) memcpy(*in, r, sizeof(double) * (size_t)rec * m);
  TRY(DMSwarmRestoreField(g->sw, "record", NULL, NULL, (void **)&r), "DMSwarmRestoreField");
  *nin = (int)m;
  return 0;
}

const mpgm_pgrid_ops mpgm_par_module_grid = {
    .create = pg_create, .destroy = pg_destroy, .boxes = pg_boxes, .owner = pg_owner,
    .sum = pg_sum, .migrate = pg_migrate};
