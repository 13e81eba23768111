/* test_xdmf.c -- mpgm_xdmf_frame: a frame of points and of a mesh written
 * into results.h5 and its indices, read back here with HDF5 itself (not
 * through xdmf.c): the geometry with its z, the vectors and the stress as
 * the 3x3 tensor (written out here by hand), the mesh's mixed topology
 * (XDMF type, then the nodes), and the index entries that name them; a
 * cell of a type XDMF output does not write is refused. Built in both
 * dimensions: plane strain z = 0, the stress {xx, yy, xy, zz}, a triangle
 * (XDMF 4) and a quadrilateral (5); 3-D the z as written, the six Voigt
 * stresses, a triangle and a hexahedron (9), plain and deflated. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_test.h"
#include "mpgm_xdmf.h"

#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { NP = 12, D = MPGM_DIM, NS = MPGM_NSTRESS };

static char dir[64];
static double x[D * NP], s[NP], v[D * NP], t[NS * NP];

/* The mesh: a triangle, then a quadrilateral (3-D: a hexahedron), and
 * the mixed list XDMF must hold of it. */
#if MPGM_DIM == 2
static const int cp[3] = {0, 3, 7}, cc[7] = {0, 1, 2, 2, 3, 4, 5};
static const int ct[2] = {MPGM_VTK_TRIANGLE, MPGM_VTK_QUAD};
static const int mixed[9] = {4, 0, 1, 2, 5, 2, 3, 4, 5};
#else
static const int cp[3] = {0, 3, 11}, cc[11] = {0, 1, 2, 4, 5, 6, 7, 8, 9, 10, 11};
static const int ct[2] = {MPGM_VTK_TRIANGLE, MPGM_VTK_HEXAHEDRON};
static const int mixed[13] = {4, 0, 1, 2, 9, 4, 5, 6, 7, 8, 9, 10, 11};
#endif

/* The 3x3 tensor of stress e as the file must hold it, row major. */
static void tensor9(const double *e, double *w) {
#if MPGM_DIM == 2 /* {xx, yy, xy, zz} */
  const double t9[9] = {e[0], e[2], 0, e[2], e[1], 0, 0, 0, e[3]};
#else /* {xx, yy, zz, xy, yz, xz} */
  const double t9[9] = {e[0], e[3], e[5], e[3], e[1], e[4], e[5], e[4], e[2]};
#endif
  memcpy(w, t9, sizeof t9);
}

/* Dataset name of file f, of n values, into out (its element count into
 * *got); 0 when it reads. */
static int read_set(hid_t f, const char *name, hid_t type, void *out, size_t n, hssize_t *got) {
  *got = -1;
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0) return -1;
  hid_t sp = H5Dget_space(d);
  *got = H5Sget_simple_extent_npoints(sp);
  herr_t e = *got == (hssize_t)n ? H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) : -1;
  H5Sclose(sp);
  H5Dclose(d);
  return e < 0 ? -1 : 0;
}

/* Vector a as the file must hold it: 3 components (z = 0 in 2-D). */
static int same_vectors(const double *got, const double *a) {
  for (int i = 0; i < NP; i++)
    for (int k = 0; k < 3; k++)
      if (got[3 * i + k] != (k < D ? a[D * i + k] : 0.0)) return 0;
  return 1;
}

/* results.h5 read back: the frame of the points and of the mesh. */
static void check_h5(const char *what) {
  char h5[128];
  snprintf(h5, sizeof h5, "%s/results.h5", dir);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
  mpgm_test(f >= 0, "%s: results.h5 opens", what);
  if (f < 0) return;
  static double g[3 * NP], w[9 * NP];
  hssize_t n;
  int ok = read_set(f, "/points/000000/geometry", H5T_NATIVE_DOUBLE, g, 3 * NP, &n) == 0;
  mpgm_test(ok && same_vectors(g, x), "%s: points geometry %d x 3 (z %s) (%lld values)", what, NP,
            D == 3 ? "as written" : "0", (long long)n);
  ok = read_set(f, "/points/000000/velocity", H5T_NATIVE_DOUBLE, g, 3 * NP, &n) == 0;
  mpgm_test(ok && same_vectors(g, v), "%s: velocity %d x 3", what, NP);
  ok = read_set(f, "/points/000000/stress", H5T_NATIVE_DOUBLE, w, 9 * NP, &n) == 0;
  for (int i = 0; ok && i < NP; i++) {
    double want[9];
    tensor9(t + NS * i, want);
    ok = !memcmp(w + 9 * i, want, sizeof want);
  }
  mpgm_test(ok, "%s: stress %d x 9, the symmetric 3x3 tensor", what, NP);
  ok = read_set(f, "/points/000000/eps_p", H5T_NATIVE_DOUBLE, w, NP, &n) == 0 && !memcmp(w, s, sizeof s);
  mpgm_test(ok, "%s: a scalar of %d values", what, NP);
  ok = read_set(f, "/mesh/000000/geometry", H5T_NATIVE_DOUBLE, g, 3 * NP, &n) == 0;
  mpgm_test(ok && same_vectors(g, x), "%s: mesh geometry", what);
  int topo[sizeof mixed / sizeof *mixed];
  ok = read_set(f, "/mesh/000000/topology", H5T_NATIVE_INT, topo, sizeof mixed / sizeof *mixed, &n) == 0;
  mpgm_test(ok && !memcmp(topo, mixed, sizeof mixed), "%s: mixed topology (XDMF %s)", what,
            D == 3 ? "triangle 4, hexahedron 9" : "triangle 4, quadrilateral 5");
  H5Fclose(f);
}

/* Does file name of dir hold text? */
static int holds(const char *name, const char *text) {
  char p[128];
  snprintf(p, sizeof p, "%s/%s", dir, name);
  FILE *f = fopen(p, "rb");
  static char buf[1 << 16];
  const size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
  if (f) fclose(f);
  buf[n] = '\0';
  return strstr(buf, text) != NULL;
}

static void frame(int deflate) {
  const char *what = deflate ? "deflated" : "plain";
  const mpgm_vtk_field pf[3] = {{"eps_p", MPGM_VTK_SCALAR, s}, {"velocity", MPGM_VTK_VECTOR, v},
                                {"stress", MPGM_VTK_STRESS, t}};
  const mpgm_vtk_field mf[1] = {{"displacement", MPGM_VTK_VECTOR, v}};
  const mpgm_vtu_piece points = {NP, x, 0, NULL, NULL, NULL, 3, pf};
  const mpgm_vtu_piece mesh = {NP, x, 2, cp, cc, ct, 1, mf};
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_xdmf *xd = NULL;
  int err = mpgm_xdmf_create(&ctx, dir, deflate, 1, &xd);
  if (!err) err = mpgm_xdmf_open(xd, &ctx, dir, 0);
  if (!err) err = mpgm_xdmf_frame(xd, &ctx, 0.25, 3, &points, &mesh);
  mpgm_test(err == 0 && mpgm_xdmf_count(xd) == 1, "%s: a frame written (%s)", what, ctx.msg);
  /* a tetrahedron (VTK 10) is not a cell XDMF output writes */
  const int bad_ptr[2] = {0, 4}, bad_conn[4] = {0, 1, 2, 3}, bad_type[1] = {10};
  const mpgm_vtu_piece bad = {NP, x, 1, bad_ptr, bad_conn, bad_type, 1, mf};
  mpgm_ctx_init(&ctx);
  err = xd ? mpgm_xdmf_frame(xd, &ctx, 0.5, 4, &points, &bad) : -1;
  mpgm_test(err == MPGM_ERR_INPUT && strstr(ctx.msg, "VTK type 10") && mpgm_xdmf_count(xd) == 1,
            "%s: a cell of another type refused (%s)", what, ctx.msg);
  mpgm_xdmf_destroy(&xd);
  check_h5(what);
  char geo[96];
  snprintf(geo, sizeof geo, "Dimensions=\"%d 3\"", NP);
  mpgm_test(holds("mesh.xdmf", "TopologyType=\"Mixed\" NumberOfElements=\"2\"") && holds("mesh.xdmf", geo) &&
                holds("points.xdmf", "AttributeType=\"Tensor\"") &&
                holds("points.xdmf", "TopologyType=\"Polyvertex\""),
            "%s: the indices name the mixed cells, %d x 3 geometry, the tensor", what, NP);
}

int main(void) {
  snprintf(dir, sizeof dir, "/tmp/mpgm_test_xdmf_XXXXXX");
  if (!mkdtemp(dir)) {
    perror("mkdtemp");
    return EXIT_FAILURE;
  }
  rng r = {0x9e3779b97f4a7c15ull};
  for (int i = 0; i < D * NP; i++) x[i] = uniform(&r, -3.7, 5.1);
  for (int i = 0; i < NP; i++) s[i] = uniform(&r, -1e-3, 2.385e5);
  for (int i = 0; i < D * NP; i++) v[i] = uniform(&r, -1.0, 1.0) / 3.0;
  for (int i = 0; i < NS * NP; i++) t[i] = uniform(&r, -7.2e6, 3.3e6); /* every component differs */
  frame(0);
  frame(1);
  static const char *const names[] = {"results.h5", "points.xdmf", "mesh.xdmf"};
  for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
    char p[128];
    snprintf(p, sizeof p, "%s/%s", dir, names[i]);
    remove(p);
  }
  mpgm_test(rmdir(dir) == 0, "temporary folder removed");
  return mpgm_test_summary();
}
