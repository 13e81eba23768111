/* xdmf.c -- XDMF 3 + HDF5 frames of the point and mesh series (see
 * mpgm_xdmf.h for the layout). Each frame's <Grid> entry is kept in memory
 * as text, so that the index is rewritten after every frame without
 * reading the HDF5 file back; a restart rebuilds the entries from the file
 * (mpgm_xdmf_restore), which is how the file and the index stay one. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_xdmf.h"

#include <hdf5.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_file.h"

#define H5_FILE "results.h5"
static const char *const kind_name[2] = {"points", "mesh"};

/* rows per write (and per chunk when deflated): 32768 rows of a 9-column
 * stress are 2.3 MiB of conversion buffer whatever the point count */
enum { BLOCK = 32768, MAXF = 24, NAME_LEN = 64 };

struct mpgm_xdmf {
  char dir[MPGM_PATH_LEN], h5[MPGM_PATH_LEN + 16];
  int deflate, kinds; /* deflate: output.compress "zlib"; kinds: 1 points, 2 and mesh */
  hid_t file;          /* -1: not open */
  int n, cap;          /* frames written */
  double *time;
  char **grid[2];      /* the <Grid> text of every frame of each kind */
  double *buf;         /* BLOCK x 9 doubles of conversion */
};

/* What a frame's <Grid> is written from: read from a piece when written,
 * from the file on a restart. */
typedef struct gdesc {
  double time;
  long long npoints, ntopo; /* ntopo: the mixed list's length (mesh) */
  int ncells, nfields;
  char name[MAXF][NAME_LEN];
  int ncomp[MAXF];
} gdesc;

/* HDF5's innermost message of its error stack, then the stack cleared. */
static herr_t walk_cb(unsigned n, const H5E_error2_t *e, void *user) {
  if (n == 0 && e->desc) snprintf(user, 256, "%s", e->desc);
  return 0;
}

static int h5_fail(mpgm_ctx *ctx, const char *path, const char *what) {
  char msg[256] = "HDF5 error";
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk_cb, msg);
  H5Eclear2(H5E_DEFAULT);
  return mpgm_err_set(ctx, MPGM_ERR_IO, __FILE__, __LINE__, "%s: cannot %s: %s", path, what, msg);
}

/* The library must not print: HDF5's own report of errors is off (its
 * messages are taken into the context by h5_fail). */
static void h5_quiet(void) { H5Eset_auto2(H5E_DEFAULT, NULL, NULL); }

int mpgm_xdmf_create(mpgm_ctx *ctx, const char *dir, int deflate, int has_mesh, mpgm_xdmf **out) {
  *out = NULL;
  mpgm_xdmf *x = calloc(1, sizeof *x);
  MPGM_CHECK(ctx, x, MPGM_ERR_NOMEM, "out of memory (XDMF output)");
  x->buf = malloc(sizeof(double) * 9 * BLOCK);
  if (!x->buf) {
    free(x);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (XDMF output)");
  }
  snprintf(x->dir, sizeof x->dir, "%s", dir);
  snprintf(x->h5, sizeof x->h5, "%s/" H5_FILE, dir);
  x->deflate = deflate;
  x->kinds = has_mesh ? 2 : 1;
  x->file = -1;
  *out = x;
  return 0;
}

int mpgm_xdmf_count(const mpgm_xdmf *x) { return x ? x->n : 0; }

void mpgm_xdmf_destroy(mpgm_xdmf **px) {
  mpgm_xdmf *x = *px;
  if (!x) return;
  if (x->file >= 0) H5Fclose(x->file);
  for (int k = 0; k < 2; k++) {
    for (int i = 0; x->grid[k] && i < x->cap; i++) free(x->grid[k][i]);
    free(x->grid[k]);
  }
  free(x->time);
  free(x->buf);
  free(x);
  *px = NULL;
}

/* Room for need frames (their times and entries). */
static int grow(mpgm_xdmf *x, mpgm_ctx *ctx, int need) {
  if (need <= x->cap) return 0;
  int c = x->cap ? x->cap : 64;
  while (c < need) c = c > INT_MAX / 2 ? need : 2 * c;
  double *t = realloc(x->time, sizeof(double) * (size_t)c);
  MPGM_CHECK(ctx, t, MPGM_ERR_NOMEM, "out of memory (XDMF index of %d frames)", c);
  x->time = t;
  for (int k = 0; k < 2; k++) {
    char **g = realloc(x->grid[k], sizeof(char *) * (size_t)c);
    MPGM_CHECK(ctx, g, MPGM_ERR_NOMEM, "out of memory (XDMF index of %d frames)", c);
    memset(g + x->cap, 0, sizeof(char *) * (size_t)(c - x->cap));
    x->grid[k] = g;
  }
  x->cap = c;
  return 0;
}

/* ---- the index ----------------------------------------------------------- */

/* A DataItem of the HDF5 dataset path, rows x cols (cols 0: 1-D). */
static void item(FILE *f, const char *type, int prec, long long rows, int cols, const char *path) {
  fprintf(f, "        <DataItem Dimensions=\"%lld", rows);
  if (cols) fprintf(f, " %d", cols);
  fprintf(f, "\" NumberType=\"%s\" Precision=\"%d\" Format=\"HDF\">" H5_FILE ":%s</DataItem>\n",
          type, prec, path);
}

/* The <Grid> of frame i of kind k, as a new string (NULL: out of memory). */
static char *grid_text(int k, int i, const gdesc *d) {
  char *s = NULL, path[128];
  size_t len = 0;
  FILE *f = open_memstream(&s, &len);
  if (!f) return NULL;
  fprintf(f, "    <Grid Name=\"%s_%06d\" GridType=\"Uniform\">\n", kind_name[k], i);
  fprintf(f, "      <Time Value=\"%.17g\"/>\n", d->time);
  if (k == 0) {
    fprintf(f, "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%lld\" "
               "NodesPerElement=\"1\">\n", d->npoints);
    snprintf(path, sizeof path, "/vertices/%lld", d->npoints);
    item(f, "Int", 4, d->npoints, 0, path);
  } else {
    fprintf(f, "      <Topology TopologyType=\"Mixed\" NumberOfElements=\"%d\">\n", d->ncells);
    snprintf(path, sizeof path, "/mesh/%06d/topology", i);
    item(f, "Int", 4, d->ntopo, 0, path);
  }
  fprintf(f, "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n");
  snprintf(path, sizeof path, "/%s/%06d/geometry", kind_name[k], i);
  item(f, "Float", 8, d->npoints, 3, path);
  fprintf(f, "      </Geometry>\n");
  for (int a = 0; a < d->nfields; a++) {
    const int c = d->ncomp[a];
    fprintf(f, "      <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", d->name[a],
            c == 1 ? "Scalar" : c == 3 ? "Vector" : "Tensor");
    snprintf(path, sizeof path, "/%s/%06d/%s", kind_name[k], i, d->name[a]);
    item(f, "Float", 8, d->npoints, c == 1 ? 0 : c, path);
    fprintf(f, "      </Attribute>\n");
  }
  fprintf(f, "    </Grid>\n");
  if (fclose(f) != 0) {
    free(s);
    return NULL;
  }
  return s;
}

/* DIR/points.xdmf (and mesh.xdmf), atomically: a temporal collection of
 * the frames written. */
static int index_write(mpgm_xdmf *x, mpgm_ctx *ctx) {
  char path[MPGM_PATH_LEN + 32];
  for (int k = 0; k < x->kinds; k++) {
    snprintf(path, sizeof path, "%s/%s.xdmf", x->dir, kind_name[k]);
    void *fv;
    MPGM_CALL(mpgm_atomic_open(ctx, path, &fv));
    FILE *f = fv;
    fprintf(f, "<?xml version=\"1.0\"?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n"
               "  <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
            kind_name[k]);
    for (int i = 0; i < x->n; i++) fputs(x->grid[k][i], f);
    fputs("  </Grid>\n  </Domain>\n</Xdmf>\n", f);
    MPGM_CALL(mpgm_atomic_close(ctx, path, f));
  }
  return 0;
}

/* ---- writing -------------------------------------------------------------- */

/* A new dataset name of g, rows (x cols, 0: 1-D) of file type ft: chunked
 * by BLOCK rows and deflated when the output is compressed. */
static hid_t dataset(const mpgm_xdmf *x, hid_t g, const char *name, hid_t ft, hsize_t rows, int cols) {
  const hsize_t dims[2] = {rows, (hsize_t)cols};
  const int rank = cols ? 2 : 1;
  hid_t sp = H5Screate_simple(rank, dims, NULL);
  hid_t pl = H5Pcreate(H5P_DATASET_CREATE);
  if (sp < 0 || pl < 0) {
    if (sp >= 0) H5Sclose(sp);
    if (pl >= 0) H5Pclose(pl);
    return -1;
  }
  herr_t e = 0;
  if (x->deflate && rows > 0) {
    const hsize_t chunk[2] = {rows < BLOCK ? rows : BLOCK, (hsize_t)cols};
    e = H5Pset_chunk(pl, rank, chunk);
    if (e >= 0) e = H5Pset_shuffle(pl);
    if (e >= 0) e = H5Pset_deflate(pl, 6); /* zlib's default level, as the .vtu arrays */
  }
  hid_t d = e < 0 ? -1 : H5Dcreate2(g, name, ft, sp, H5P_DEFAULT, pl, H5P_DEFAULT);
  H5Sclose(sp);
  H5Pclose(pl);
  return d;
}

/* Rows [r0, r0 + b) of dataset d (cols as dataset) from buf of memory type mt. */
static herr_t put_rows(hid_t d, hid_t mt, hsize_t r0, hsize_t b, int cols, const void *buf) {
  const hsize_t start[2] = {r0, 0}, count[2] = {b, (hsize_t)cols};
  const int rank = cols ? 2 : 1;
  hid_t fs = H5Dget_space(d), ms = H5Screate_simple(rank, count, NULL);
  herr_t e = fs < 0 || ms < 0 ? -1 : H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL);
  if (e >= 0) e = H5Dwrite(d, mt, ms, fs, H5P_DEFAULT, buf);
  if (fs >= 0) H5Sclose(fs);
  if (ms >= 0) H5Sclose(ms);
  return e;
}

/* Point data of kind (mpgm_vtk_kind; the geometry is a VECTOR) as dataset
 * name of g, npoints rows of 1, 3 or 9 float64, the values of the VTK
 * frames: vectors of 3 components (z = 0 in plane strain), the stress as
 * the row-major 3x3 tensor (mpgm_vtk_components, as vtk.c and vtu.c). */
static herr_t put_field(mpgm_xdmf *x, hid_t g, const char *name, int kind, hsize_t n, const double *v) {
  const int nc = mpgm_vtk_ncomp(kind);
  hid_t d = dataset(x, g, name, H5T_IEEE_F64LE, n, nc == 1 ? 0 : nc);
  if (d < 0) return -1;
  herr_t e = 0;
  for (hsize_t r0 = 0; e >= 0 && r0 < n; r0 += BLOCK) {
    const hsize_t b = n - r0 < BLOCK ? n - r0 : BLOCK;
    mpgm_vtk_components(kind, v, (size_t)(nc * r0), (size_t)(nc * b), x->buf);
    e = put_rows(d, H5T_NATIVE_DOUBLE, r0, b, nc == 1 ? 0 : nc, x->buf);
  }
  H5Dclose(d);
  return e;
}

/* A 1-D int32 dataset name of g: n values v. */
static herr_t put_ints(mpgm_xdmf *x, hid_t g, const char *name, hsize_t n, const int *v) {
  hid_t d = dataset(x, g, name, H5T_STD_I32LE, n, 0);
  if (d < 0) return -1;
  herr_t e = n ? put_rows(d, H5T_NATIVE_INT, 0, n, 0, v) : 0;
  H5Dclose(d);
  return e;
}

/* A scalar attribute name of object o: file type ft, memory type mt. */
static herr_t put_attr(hid_t o, const char *name, hid_t ft, hid_t mt, const void *v) {
  hid_t sp = H5Screate(H5S_SCALAR);
  hid_t a = sp < 0 ? -1 : H5Acreate2(o, name, ft, sp, H5P_DEFAULT, H5P_DEFAULT);
  herr_t e = a < 0 ? -1 : H5Awrite(a, mt, v);
  if (a >= 0) H5Aclose(a);
  if (sp >= 0) H5Sclose(sp);
  return e;
}

/* /vertices/N (0 .. N-1) unless the file has it: a point cloud's
 * topology, shared by its frames. */
static int put_vertices(mpgm_xdmf *x, mpgm_ctx *ctx, int npoints) {
  char name[48];
  snprintf(name, sizeof name, "/vertices/%d", npoints);
  const htri_t has = H5Lexists(x->file, name, H5P_DEFAULT);
  if (has > 0) return 0;
  if (has < 0) return h5_fail(ctx, x->h5, "look up /vertices");
  int *v = malloc(sizeof(int) * (size_t)(npoints ? npoints : 1));
  MPGM_CHECK(ctx, v, MPGM_ERR_NOMEM, "out of memory (XDMF topology of %d points)", npoints);
  for (int p = 0; p < npoints; p++) v[p] = p;
  hid_t g = H5Gopen2(x->file, "/vertices", H5P_DEFAULT);
  const herr_t e = g < 0 ? -1 : put_ints(x, g, name + 10, (hsize_t)npoints, v);
  if (g >= 0) H5Gclose(g);
  free(v);
  return e < 0 ? h5_fail(ctx, x->h5, "write /vertices") : 0;
}

/* The XDMF mixed-topology code of a cell of VTK type t with nn nodes (the
 * node order is VTK's, XDMF's the same for these), 0 for none written. */
static int xdmf_type(int t, int nn) {
  if (t == MPGM_VTK_TRIANGLE && nn == 3) return 4;
  if (t == MPGM_VTK_QUAD && nn == 4) return 5;
  if (t == MPGM_VTK_HEXAHEDRON && nn == 8) return 9;
  return 0;
}

/* The mesh's cells as XDMF's mixed list (each cell's XDMF type, then its
 * nodes) in a new array *out of *len ints. */
static int mixed_list(mpgm_ctx *ctx, const mpgm_vtu_piece *p, int **out, long long *len) {
  long long n = 0;
  for (int c = 0; c < p->ncells; c++) {
    const int t = p->cell_type[c], nn = p->cell_ptr[c + 1] - p->cell_ptr[c];
    MPGM_CHECK(ctx, xdmf_type(t, nn), MPGM_ERR_INPUT,
               "XDMF output: cell %d is of VTK type %d with %d nodes (triangles, "
               "quadrilaterals and hexahedra are written)", c, t, nn);
    n += 1 + nn;
  }
  MPGM_CHECK(ctx, n <= INT_MAX, MPGM_ERR_INPUT, "XDMF output: %lld entries of cells", n);
  int *v = malloc(sizeof(int) * (size_t)(n ? n : 1));
  MPGM_CHECK(ctx, v, MPGM_ERR_NOMEM, "out of memory (XDMF topology of %d cells)", p->ncells);
  long long k = 0;
  for (int c = 0; c < p->ncells; c++) {
    v[k++] = xdmf_type(p->cell_type[c], p->cell_ptr[c + 1] - p->cell_ptr[c]);
    for (int j = p->cell_ptr[c]; j < p->cell_ptr[c + 1]; j++) v[k++] = p->conn[j];
  }
  *out = v, *len = n;
  return 0;
}

/* Frame x->n of kind k from piece p: group /KIND/NNNNNN; d describes it. */
static int frame_kind(mpgm_xdmf *x, mpgm_ctx *ctx, int k, double time, long step,
                      const mpgm_vtu_piece *p, gdesc *d) {
  MPGM_CALL(mpgm_vtk_check(ctx, x->h5, p->npoints, p->x, p->ncells, p->cell_ptr, p->conn,
                           p->cell_type, p->nfields, p->fields));
  MPGM_CHECK(ctx, p->nfields <= MAXF, MPGM_ERR_INPUT, "XDMF output: %d arrays (at most %d)",
             p->nfields, MAXF);
  memset(d, 0, sizeof *d);
  d->time = time, d->npoints = p->npoints, d->nfields = p->nfields;
  int *topo = NULL;
  if (k == 0) MPGM_CALL(put_vertices(x, ctx, p->npoints));
  else MPGM_CALL(mixed_list(ctx, p, &topo, &d->ntopo));
  d->ncells = k ? p->ncells : 0;
  char name[32];
  snprintf(name, sizeof name, "/%s/%06d", kind_name[k], x->n);
  /* the arrays in the order they are written (the VTK frames' order) */
  hid_t gcpl = H5Pcreate(H5P_GROUP_CREATE);
  herr_t e = gcpl < 0 ? -1 : H5Pset_link_creation_order(gcpl, H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
  hid_t g = e < 0 ? -1 : H5Gcreate2(x->file, name, H5P_DEFAULT, gcpl, H5P_DEFAULT);
  const long long st = step;
  e = g < 0 ? -1 : put_attr(g, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &time);
  if (e >= 0) e = put_attr(g, "step", H5T_STD_I64LE, H5T_NATIVE_LLONG, &st);
  if (e >= 0) e = put_field(x, g, "geometry", MPGM_VTK_VECTOR, (hsize_t)p->npoints, p->x);
  if (e >= 0 && k) e = put_ints(x, g, "topology", (hsize_t)d->ntopo, topo);
  if (e >= 0 && k) e = put_attr(g, "cells", H5T_STD_I32LE, H5T_NATIVE_INT, &p->ncells);
  for (int a = 0; e >= 0 && a < p->nfields; a++) {
    const mpgm_vtk_field *f = &p->fields[a];
    snprintf(d->name[a], NAME_LEN, "%s", f->name);
    d->ncomp[a] = mpgm_vtk_ncomp(f->kind);
    e = put_field(x, g, f->name, f->kind, (hsize_t)p->npoints, f->data);
  }
  free(topo);
  if (g >= 0) H5Gclose(g);
  if (gcpl >= 0) H5Pclose(gcpl);
  return e < 0 ? h5_fail(ctx, x->h5, "write a frame") : 0;
}

int mpgm_xdmf_frame(mpgm_xdmf *x, mpgm_ctx *ctx, double time, long step,
                    const mpgm_vtu_piece *points, const mpgm_vtu_piece *mesh) {
  MPGM_CHECK(ctx, x->file >= 0 && isfinite(time) && (mesh != NULL) == (x->kinds == 2),
             MPGM_ERR_INTERNAL, "XDMF frame %d: file not open, time %g or mesh %s", x->n, time,
             mesh ? "given" : "missing");
  h5_quiet();
  MPGM_CALL(grow(x, ctx, x->n + 1));
  gdesc d;
  for (int k = 0; k < x->kinds; k++) {
    MPGM_CALL(frame_kind(x, ctx, k, time, step, k ? mesh : points, &d));
    free(x->grid[k][x->n]);
    x->grid[k][x->n] = grid_text(k, x->n, &d);
    MPGM_CHECK(ctx, x->grid[k][x->n], MPGM_ERR_NOMEM, "out of memory (XDMF index)");
  }
  /* the file holds the frame before the index names it */
  if (H5Fflush(x->file, H5F_SCOPE_GLOBAL) < 0) return h5_fail(ctx, x->h5, "flush");
  x->time[x->n++] = time;
  return index_write(x, ctx);
}

/* ---- opening, checkpoints ------------------------------------------------- */

/* Remove what an earlier run wrote (a new run, or one without XDMF). */
static void remove_earlier(const char *dir) {
  char path[MPGM_PATH_LEN + 32];
  for (int k = 0; k < 2; k++) {
    snprintf(path, sizeof path, "%s/%s.xdmf", dir, kind_name[k]);
    remove(path);
  }
  snprintf(path, sizeof path, "%s/" H5_FILE, dir);
  remove(path);
}

int mpgm_xdmf_open(mpgm_xdmf *x, mpgm_ctx *ctx, const char *dir, int keep) {
  if (!x || keep == 0) remove_earlier(dir);
  if (!x) return 0;
  h5_quiet();
  MPGM_CHECK(ctx, keep == x->n && x->file < 0, MPGM_ERR_INTERNAL,
             "XDMF output opened keeping %d of %d frames", keep, x->n);
  if (keep == 0) {
    x->file = H5Fcreate(x->h5, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (x->file < 0) return h5_fail(ctx, x->h5, "create");
    for (int k = 0; k < x->kinds + 1; k++) {
      const hid_t g = H5Gcreate2(x->file, k < x->kinds ? kind_name[k] : "vertices", H5P_DEFAULT,
                                 H5P_DEFAULT, H5P_DEFAULT);
      if (g < 0) return h5_fail(ctx, x->h5, "create its groups");
      H5Gclose(g);
    }
    return 0;
  }
  x->file = H5Fopen(x->h5, H5F_ACC_RDWR, H5P_DEFAULT);
  if (x->file < 0) return h5_fail(ctx, x->h5, "open");
  for (int k = 0; k < x->kinds; k++) {
    /* the names first, then the deletions: a group is not changed while
     * it is iterated */
    hid_t g = H5Gopen2(x->file, kind_name[k], H5P_DEFAULT);
    herr_t e = g < 0 ? -1 : 0;
    for (int i = keep; e >= 0; i++) {
      char name[32];
      snprintf(name, sizeof name, "%06d", i);
      const htri_t has = H5Lexists(g, name, H5P_DEFAULT);
      if (has <= 0) {
        e = has;
        break;
      }
      e = H5Ldelete(g, name, H5P_DEFAULT);
    }
    if (g >= 0) H5Gclose(g);
    if (e < 0) return h5_fail(ctx, x->h5, "drop the frames written after the checkpoint");
  }
  if (H5Fflush(x->file, H5F_SCOPE_GLOBAL) < 0) return h5_fail(ctx, x->h5, "flush");
  return index_write(x, ctx);
}

int mpgm_xdmf_save(const mpgm_xdmf *x, mpgm_ctx *ctx, mpgm_blob *b, const char *tag) {
  if (!x) return 0;
  return mpgm_blob_put(ctx, b, tag, x->time, sizeof(double) * (size_t)x->n);
}

/* The dims of dataset name of g: *rank and dims (at most 2), -1 when it
 * is not a dataset of that many dimensions. */
static int dims_of(hid_t g, const char *name, int *rank, hsize_t dims[2]) {
  *rank = -1;
  if (H5Lexists(g, name, H5P_DEFAULT) <= 0) return -1;
  hid_t d = H5Dopen2(g, name, H5P_DEFAULT);
  hid_t sp = d < 0 ? -1 : H5Dget_space(d);
  const int r = sp < 0 ? -1 : H5Sget_simple_extent_ndims(sp);
  if (r >= 1 && r <= 2 && H5Sget_simple_extent_dims(sp, dims, NULL) == r) *rank = r;
  if (sp >= 0) H5Sclose(sp);
  if (d >= 0) H5Dclose(d);
  return *rank;
}

/* A scalar attribute name of o read as memory type mt into v. */
static herr_t get_attr(hid_t o, const char *name, hid_t mt, void *v) {
  if (H5Aexists(o, name) <= 0) return -1;
  hid_t a = H5Aopen(o, name, H5P_DEFAULT);
  hid_t sp = a < 0 ? -1 : H5Aget_space(a);
  herr_t e = sp < 0 || H5Sget_simple_extent_npoints(sp) != 1 ? -1 : H5Aread(a, mt, v);
  if (sp >= 0) H5Sclose(sp);
  if (a >= 0) H5Aclose(a);
  return e;
}

/* The arrays of a frame's group, in the order written; a name outside
 * [A-Za-z0-9_.-] (it goes into the index's XML) or too many stop it. */
static herr_t names_cb(hid_t g, const char *name, const H5L_info_t *info, void *user) {
  (void)g, (void)info;
  gdesc *d = user;
  if (!strcmp(name, "geometry") || !strcmp(name, "topology")) return 0;
  if (d->nfields == MAXF || strlen(name) >= NAME_LEN || !name[0] ||
      strspn(name, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-") != strlen(name))
    return 1;
  snprintf(d->name[d->nfields++], NAME_LEN, "%s", name);
  return 0;
}

/* Frame i of kind k as results.h5 holds it into d, checked against the
 * layout (mpgm_xdmf.h) and the checkpoint's time. */
static int read_desc(mpgm_xdmf *x, mpgm_ctx *ctx, hid_t file, int k, int i, gdesc *d) {
  char name[48];
  snprintf(name, sizeof name, "/%s/%06d", kind_name[k], i);
  memset(d, 0, sizeof *d);
  const int has = H5Lexists(file, kind_name[k], H5P_DEFAULT) > 0 && H5Lexists(file, name, H5P_DEFAULT) > 0;
  MPGM_CHECK(ctx, has, MPGM_ERR_INPUT, "%s: holds no frame %s, the checkpoint lists %d frames",
             x->h5, name, x->n);
  hid_t g = H5Gopen2(file, name, H5P_DEFAULT);
  if (g < 0) return h5_fail(ctx, x->h5, "read a frame");
  int rank, cells = 0, ok = get_attr(g, "time", H5T_NATIVE_DOUBLE, &d->time) >= 0 && d->time == x->time[i];
  hsize_t dims[2];
  ok = ok && dims_of(g, "geometry", &rank, dims) == 2 && dims[1] == 3 && dims[0] <= INT_MAX;
  d->npoints = ok ? (long long)dims[0] : 0;
  if (ok && k) {
    ok = dims_of(g, "topology", &rank, dims) == 1 && dims[0] <= INT_MAX &&
         get_attr(g, "cells", H5T_NATIVE_INT, &cells) >= 0 && cells >= 0 &&
         (hsize_t)cells * 4 <= dims[0];
    d->ntopo = (long long)dims[0], d->ncells = cells;
  }
  hsize_t at = 0;
  ok = ok && H5Literate(g, H5_INDEX_CRT_ORDER, H5_ITER_INC, &at, names_cb, d) == 0;
  for (int a = 0; ok && a < d->nfields; a++) {
    ok = dims_of(g, d->name[a], &rank, dims) > 0 && dims[0] == (hsize_t)d->npoints &&
         (rank == 1 || dims[1] == 3 || dims[1] == 9);
    d->ncomp[a] = rank == 1 ? 1 : (int)dims[1];
  }
  H5Gclose(g);
  H5Eclear2(H5E_DEFAULT);
  snprintf(name, sizeof name, "/vertices/%lld", d->npoints);
  ok = ok && (k || H5Lexists(file, "/vertices", H5P_DEFAULT) > 0) &&
       (k || H5Lexists(file, name, H5P_DEFAULT) > 0);
  MPGM_CHECK(ctx, ok, MPGM_ERR_INPUT,
             "%s: frame %d of the %s is not as written (time, geometry, topology or an array), "
             "or not of time %.17g as the checkpoint has it", x->h5, i, kind_name[k], x->time[i]);
  return 0;
}

int mpgm_xdmf_restore(mpgm_xdmf *x, mpgm_ctx *ctx, mpgm_blob *b, const char *tag, int nframes) {
  if (!x) return 0;
  size_t len;
  MPGM_CALL(mpgm_blob_peek(ctx, b, tag, &len));
  MPGM_CHECK(ctx, nframes >= 0 && len == sizeof(double) * (size_t)nframes, MPGM_ERR_INPUT,
             "checkpoint: section '%s' holds %zu bytes; the times of %d XDMF frames are %zu", tag,
             len, nframes, sizeof(double) * (size_t)(nframes > 0 ? nframes : 0));
  MPGM_CALL(grow(x, ctx, nframes));
  MPGM_CALL(mpgm_blob_get(ctx, b, tag, x->time, len));
  for (int i = 0; i < nframes; i++)
    MPGM_CHECK(ctx, isfinite(x->time[i]), MPGM_ERR_INPUT,
               "checkpoint: section '%s': time %g of frame %d", tag, x->time[i], i);
  x->n = nframes;
  if (nframes == 0) return 0;
  h5_quiet();
  hid_t file = H5Fopen(x->h5, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) return h5_fail(ctx, x->h5, "read the frames the checkpoint lists");
  int err = 0;
  for (int k = 0; !err && k < x->kinds; k++)
    for (int i = 0; !err && i < nframes; i++) {
      gdesc d;
      err = read_desc(x, ctx, file, k, i, &d);
      if (!err && !(x->grid[k][i] = grid_text(k, i, &d)))
        err = mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory (XDMF index)");
    }
  H5Fclose(file);
  return err;
}
