/* test_vtk_read.c -- mpgm_vtk_read / mpgm_pvd_read read back exactly what
 * mpgm_vtk_write / mpgm_pvd_add write (ASCII and binary, points, cells
 * and their types, SCALARS, VECTORS, TENSORS), and reject what is not our
 * format with a message, never reading past the end. Built in both
 * dimensions: plane strain z = 0 and the stress {xx, yy, xy, zz} of a
 * triangle and a quadrilateral; 3-D the z, the six Voigt stresses as the
 * 3x3 tensor (written out here) of a triangle and a hexahedron. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_test.h"
#include "mpgm_vtk.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { NP = 10, D = MPGM_DIM, NS = MPGM_NSTRESS };

/* The cells: a triangle, then a quadrilateral (3-D: a hexahedron). */
#if MPGM_DIM == 2
static const int cp[3] = {0, 3, 7}, cc[7] = {0, 1, 2, 2, 3, 4, 5};
static const int ct[2] = {MPGM_VTK_TRIANGLE, MPGM_VTK_QUAD};
#else
static const int cp[3] = {0, 3, 11}, cc[11] = {0, 1, 2, 2, 3, 4, 5, 6, 7, 8, 9};
static const int ct[2] = {MPGM_VTK_TRIANGLE, MPGM_VTK_HEXAHEDRON};
#endif

/* |d - the 3x3 tensor of stress e|, summed over its 9 entries. */
static double tensor_error(const double *d, const double *e) {
#if MPGM_DIM == 2 /* {xx, yy, xy, zz} */
  const double w[9] = {e[0], e[2], 0, e[2], e[1], 0, 0, 0, e[3]};
#else /* {xx, yy, zz, xy, yz, xz} */
  const double w[9] = {e[0], e[3], e[5], e[3], e[1], e[4], e[5], e[4], e[2]};
#endif
  double err = 0.0;
  for (int k = 0; k < 9; k++) err += fabs(d[k] - w[k]);
  return err;
}

static char dir[64];

static void path_of(char *buf, size_t cap, const char *name) { snprintf(buf, cap, "%s/%s", dir, name); }

static void roundtrip(int binary, int with_cells) {
  rng r = {0x9e3779b97f4a7c15ull};
  double x[D * NP], s[NP], v[D * NP], t[NS * NP];
  for (int i = 0; i < D * NP; i++) x[i] = uniform(&r, -3.7, 5.1);
  for (int i = 0; i < NP; i++) s[i] = uniform(&r, -1e-3, 2.385e5);
  for (int i = 0; i < D * NP; i++) v[i] = uniform(&r, -1.0, 1.0) / 3.0;
  for (int i = 0; i < NS * NP; i++) t[i] = uniform(&r, -7.2e6, 3.3e6);
  const mpgm_vtk_field f[3] = {{"eps_p", MPGM_VTK_SCALAR, s}, {"velocity", MPGM_VTK_VECTOR, v},
                               {"stress", MPGM_VTK_STRESS, t}};
  char p[128];
  path_of(p, sizeof p, binary ? "b.vtk" : "a.vtk");
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  int err = mpgm_vtk_write(&ctx, p, binary, "round trip", NP, x, with_cells ? 2 : 0, with_cells ? cp : NULL,
                           with_cells ? cc : NULL, with_cells ? ct : NULL, 3, f);
  mpgm_test(err == 0, "%s: written", p);
  mpgm_vtk_grid *g = NULL;
  err = mpgm_vtk_read(&ctx, p, &g);
  mpgm_test(err == 0 && g, "%s: read back (%s)", p, ctx.msg);
  if (!g) return;
  mpgm_test(g->npoints == NP && g->ncells == (with_cells ? 2 : NP) && g->narray == 3,
            "%s: %d points, %d cells, %d arrays", p, g->npoints, g->ncells, g->narray);
  mpgm_test(!strcmp(g->title, "round trip"), "%s: title", p);
  int cells_ok = g->ncells == (with_cells ? 2 : NP) && g->cell_ptr && g->conn && g->cell_type;
  for (int c = 0; cells_ok && c < g->ncells; c++) /* a cloud: one VTK_VERTEX per point */
    cells_ok = with_cells ? g->cell_type[c] == ct[c] && g->cell_ptr[c + 1] == cp[c + 1]
                          : g->cell_type[c] == MPGM_VTK_VERTEX && g->cell_ptr[c + 1] == c + 1 && g->conn[c] == c;
  if (cells_ok && with_cells) cells_ok = !memcmp(g->conn, cc, sizeof cc);
  mpgm_test(cells_ok, "%s: the cells and their types read back (%s)", p,
            with_cells ? (D == 3 ? "a triangle, a hexahedron" : "a triangle, a quadrilateral") : "vertices");
  double worst = 0.0;
  for (int i = 0; i < NP; i++) {
    for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(g->x[3 * i + k] - (k < D ? x[D * i + k] : 0.0)));
    const mpgm_vtk_array *a = mpgm_vtk_array_find(g, "eps_p"), *b = mpgm_vtk_array_find(g, "velocity"),
                         *c = mpgm_vtk_array_find(g, "stress");
    if (!a || !b || !c || a->ncomp != 1 || b->ncomp != 3 || c->ncomp != 9) {
      worst = INFINITY;
      break;
    }
    worst = fmax(worst, fabs(a->v[i] - s[i]));
    for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(b->v[3 * i + k] - (k < D ? v[D * i + k] : 0.0)));
    worst = fmax(worst, tensor_error(c->v + 9 * i, t + NS * i));
  }
  /* %.17g and big-endian bytes both carry every bit */
  mpgm_test_abs(worst, 0.0, 0.0, "%s: every value read back exactly", p);
  mpgm_test(mpgm_vtk_array_find(g, "nosuch") == NULL, "%s: an absent array is NULL", p);
  mpgm_vtk_grid_destroy(&g);
  mpgm_test(g == NULL, "destroy nulls the pointer");
  mpgm_vtk_grid_destroy(&g); /* accepts NULL */
}

/* A file with given content; reading it must fail with code and needle. */
static void bad_file(const char *name, const char *content, size_t len, int code, const char *needle) {
  char p[128];
  path_of(p, sizeof p, name);
  FILE *f = fopen(p, "wb");
  if (f) {
    fwrite(content, 1, len, f);
    fclose(f);
  }
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_vtk_grid *g = (mpgm_vtk_grid *)&ctx; /* must be set to NULL */
  const int err = mpgm_vtk_read(&ctx, p, &g);
  mpgm_test(err == code && g == NULL && strstr(ctx.msg, needle) && strstr(ctx.msg, name),
            "%s: rejected with \"%s\" (got %d: %s)", name, needle, err, ctx.msg);
}

static void bad_files(void) {
  static const char hdr[] = "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
  bad_file("empty.vtk", "", 0, MPGM_ERR_INPUT, "expected '# vtk DataFile Version 3.0'");
  bad_file("poly.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\n", 52, MPGM_ERR_INPUT,
           "DATASET UNSTRUCTURED_GRID");
  char buf[256];
  int n = snprintf(buf, sizeof buf, "%sPOINTS 3 double\n", hdr);
  memset(buf + n, 0, 40); /* 3 points need 72 bytes */
  bad_file("short.vtk", buf, (size_t)n + 40, MPGM_ERR_INPUT, "binary data ends early");
  n = snprintf(buf, sizeof buf, "%sPOINTS 2000000000 double\n", hdr);
  bad_file("huge.vtk", buf, (size_t)n, MPGM_ERR_INPUT, "a count that fits the file");
  n = snprintf(buf, sizeof buf, "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                                "POINTS 1 double\n1 2 0\nCELLS 1 2\n1 0\nCELL_TYPES 1\n1\nPOINT_DATA 1\n"
                                "FIELD f 1\n");
  bad_file("field.vtk", buf, (size_t)n, MPGM_ERR_INPUT, "SCALARS|VECTORS|TENSORS");
  n = snprintf(buf, sizeof buf, "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                                "POINTS 1 double\n1 2 0\nCELLS 1 2\n1 5\nCELL_TYPES 1\n1\n");
  bad_file("cellid.vtk", buf, (size_t)n, MPGM_ERR_INPUT, "refers to point 5 of 1");
  n = snprintf(buf, sizeof buf, "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                                "POINTS 1 double\n1 2 0\nCELLS 1 2\n3 0\nCELL_TYPES 1\n1\n");
  bad_file("cellsize.vtk", buf, (size_t)n, MPGM_ERR_INPUT, "does not fit CELLS 1 2");
  n = snprintf(buf, sizeof buf, "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                                "POINTS 2 double\n1 2 0 x\n");
  bad_file("text.vtk", buf, (size_t)n, MPGM_ERR_INPUT, "expected a number");
  char p[128];
  path_of(p, sizeof p, "missing.vtk");
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_vtk_grid *g = NULL;
  mpgm_test(mpgm_vtk_read(&ctx, p, &g) == MPGM_ERR_IO && strstr(ctx.msg, "cannot open"), "missing file: I/O error");
}

static void pvd(void) {
  char p[128], q[128];
  path_of(p, sizeof p, "points.pvd");
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_pvd *w = NULL;
  mpgm_pvd_create(&ctx, p, &w);
  const double times[3] = {0.0, 0.1, 2.385};
  const char *files[3] = {"vtk/a.vtk", "vtk/b&\"c\".vtk", "vtk/<d>.vtk"};
  for (int i = 0; i < 3; i++) mpgm_pvd_add(w, &ctx, times[i], files[i]);
  mpgm_pvd_destroy(&w);
  mpgm_pvd_list l;
  const int err = mpgm_pvd_read(&ctx, p, &l);
  int same = err == 0 && l.n == 3;
  for (int i = 0; same && i < 3; i++) same = l.time[i] == times[i] && !strcmp(l.file[i], files[i]);
  mpgm_test(same, "pvd: times and (escaped) file names read back");
  mpgm_pvd_list_free(&l);
  mpgm_pvd_list_free(&l); /* accepts an empty list */
  path_of(q, sizeof q, "not.pvd");
  FILE *f = fopen(q, "w");
  if (f) {
    fputs("<VTKFile type=\"Collection\"><Collection><DataSet file=\"x.vtk\"/></Collection></VTKFile>", f);
    fclose(f);
  }
  mpgm_test(mpgm_pvd_read(&ctx, q, &l) == MPGM_ERR_INPUT && strstr(ctx.msg, "without timestep") && l.n == 0,
            "pvd: a DataSet without timestep is rejected (%s)", ctx.msg);
}

int main(void) {
  snprintf(dir, sizeof dir, "/tmp/mpgm_test_vtk_read_XXXXXX");
  if (!mkdtemp(dir)) {
    perror("mkdtemp");
    return EXIT_FAILURE;
  }
  for (int binary = 0; binary < 2; binary++)
    for (int cells = 0; cells < 2; cells++) roundtrip(binary, cells);
  bad_files();
  pvd();
  static const char *const names[] = {"a.vtk", "b.vtk", "empty.vtk", "poly.vtk", "short.vtk", "huge.vtk",
                                      "field.vtk", "text.vtk", "cellid.vtk", "cellsize.vtk", "points.pvd", "not.pvd"};
  for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
    char p[128];
    path_of(p, sizeof p, names[i]);
    remove(p);
  }
  mpgm_test(rmdir(dir) == 0, "temporary folder removed");
  return mpgm_test_summary();
}
