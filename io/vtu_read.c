/* vtu_read.c -- read back the .vtu files vtu.c writes (inline ascii,
 * appended raw, appended zlib blocks): the points, the cells, the point
 * data and the TimeValue, as mpgm_vtk_read gives a legacy file (mpgm_vtk_grid). Only
 * our own layout is read (UInt64 headers, little-endian, Float64 arrays);
 * every count and offset is checked against the file before it is used,
 * so a damaged or foreign file is an MPGM_ERR_INPUT naming it, never a
 * read past its end.
 */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_vtu.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

/* as vtk_read.c: a frame of ten million points of every field fits */
#define VTU_MAX_FILE ((size_t)4 << 30)

typedef struct {
  mpgm_ctx *ctx;
  const char *path;
  const char *b;        /* the file (NUL-terminated)                   */
  size_t len;
  const char *head_end; /* end of the XML part (the appended block)     */
  const unsigned char *app; /* first byte after '_' (NULL: none)        */
  int zlib;
} vr;

static int bad(vr *r, const char *what) {
  MPGM_ERROR(r->ctx, MPGM_ERR_INPUT, "%s: not a .vtu file as mpgm writes it: expected %s", r->path, what);
}

/* Attribute name="..." of the element [s, e) into out; 0 when absent. */
static int attr(const char *s, const char *e, const char *name, char *out, size_t cap) {
  char key[40];
  snprintf(key, sizeof key, " %s=\"", name);
  const size_t kl = strlen(key);
  for (const char *p = s; p + kl <= e; p++) {
    if (memcmp(p, key, kl) != 0) continue;
    const char *q = p + kl, *end = memchr(q, '"', (size_t)(e - q));
    if (!end || (size_t)(end - q) >= cap) return 0;
    memcpy(out, q, (size_t)(end - q));
    out[end - q] = '\0';
    return 1;
  }
  return 0;
}

static uint64_t get_u64(const unsigned char *p) {
  uint64_t v = 0;
  for (int b = 7; b >= 0; b--) v = (v << 8) | p[b];
  return v;
}

/* Element types of the arrays mpgm writes: the points' and the point
 * data's, the cells' connectivity and offsets, their types. */
typedef enum { T_F64 = 0, T_I64 = 1, T_U8 = 2 } etype;
static const char *const type_names[] = {"Float64", "Int64", "UInt8"};
static const size_t type_size[] = {8, 8, 1};

/* Value i of little-endian bytes raw of type t, as a double (an Int64
 * exactly below 2^53: the counts and ids of a file that fits memory). */
static double element(const unsigned char *raw, etype t, size_t i) {
  if (t == T_U8) return raw[i];
  const uint64_t u = get_u64(raw + 8 * i);
  if (t == T_I64) return (double)(int64_t)u;
  double d;
  memcpy(&d, &u, sizeof d);
  return d;
}

/* The n values of type t of an appended array at offset off into v. */
static int appended(vr *r, uint64_t off, etype t, double *v, size_t n) {
  const size_t avail = r->len - (size_t)((const char *)r->app - r->b);
  const size_t want = type_size[t] * n;
  if (off > avail || avail - off < 8) return bad(r, "array offsets inside the appended data");
  const unsigned char *p = r->app + off;
  const size_t left = avail - (size_t)off;
  unsigned char *raw = NULL;
  if (!r->zlib) {
    if (get_u64(p) != want || left - 8 < want) return bad(r, "raw arrays of their declared size");
    raw = (unsigned char *)p + 8;
  } else {
    if (left < 24) return bad(r, "a zlib header of 3 numbers");
    const uint64_t nb = get_u64(p), bs = get_u64(p + 8), last = get_u64(p + 16);
    if (bs == 0 || bs > INT_MAX || last >= bs || nb > (left - 24) / 8 ||
        (nb ? (nb - 1) * bs + (last ? last : bs) : 0) != want)
      return bad(r, "zlib blocks that hold the array's declared size");
    MPGM_ALLOC(r->ctx, raw, want + 1);
    const unsigned char *z = p + 24 + 8 * nb;
    size_t zleft = left - 24 - 8 * nb, at = 0;
    for (uint64_t k = 0; k < nb; k++) {
      const uint64_t zl = get_u64(p + 24 + 8 * k);
      uLongf out = (uLongf)(k + 1 < nb || !last ? bs : last);
      const uLongf expect = out;
      if (zl > zleft || uncompress(raw + at, &out, z, (uLong)zl) != Z_OK || out != expect) {
        free(raw);
        return bad(r, "zlib blocks that inflate to their declared sizes");
      }
      z += zl, zleft -= zl, at += out;
    }
  }
  for (size_t i = 0; i < n; i++) v[i] = element(raw, t, i);
  if (r->zlib) free(raw);
  return 0;
}

/* The DataArray element [s, e) of type t (of tuples tuples) into a new
 * array *v of *ncomp components; name into name. */
static int data_array(vr *r, const char *s, const char *e, etype t, size_t tuples, char *name,
                      size_t cap, int *ncomp, double **v) {
  char type[32], format[32], nc[32] = "1", off[32];
  if (!attr(s, e, "type", type, sizeof type) || strcmp(type, type_names[t]) != 0)
    return bad(r, t == T_F64 ? "Float64 point arrays" : "Int64 connectivity and offsets, UInt8 types");
  if (!attr(s, e, "Name", name, cap)) snprintf(name, cap, "%s", "");
  attr(s, e, "NumberOfComponents", nc, sizeof nc);
  *ncomp = atoi(nc);
  if (*ncomp != 1 && *ncomp != 3 && *ncomp != 9) return bad(r, "arrays of 1, 3 or 9 components");
  if (!attr(s, e, "format", format, sizeof format)) return bad(r, "a format on every DataArray");
  const size_t n = tuples * (size_t)*ncomp;
  /* no array larger than its file can hold (zlib inflates at most about
   * 1032 times): a damaged count cannot ask for huge memory */
  if (n > (r->len + 64) * 1100 / type_size[t]) return bad(r, "arrays of sizes that fit the file");
  MPGM_ALLOC(r->ctx, *v, n + 1);
  if (strcmp(format, "appended") == 0) {
    char *end;
    if (!r->app || !attr(s, e, "offset", off, sizeof off)) return bad(r, "an offset into appended data");
    const unsigned long long o = strtoull(off, &end, 10);
    if (*end) return bad(r, "numeric offsets");
    return appended(r, o, t, *v, n);
  }
  if (strcmp(format, "ascii") != 0) return bad(r, "ascii or appended arrays");
  const char *p = e + 1, *stop = strstr(p, "</DataArray>");
  if (!stop) return bad(r, "</DataArray>");
  for (size_t i = 0; i < n; i++) {
    char *end;
    (*v)[i] = strtod(p, &end);
    if (end == p || end > stop) return bad(r, "as many ascii numbers as the array's size");
    p = end;
  }
  return 0;
}

/* The arrays of section tag (<PointData> or <Points>) into g. */
static int section(vr *r, mpgm_vtk_grid *g, const char *tag, int points) {
  char open[32], close[32];
  snprintf(open, sizeof open, "<%s>", tag);
  snprintf(close, sizeof close, "</%s>", tag);
  const char *s = strstr(r->b, open), *e = s ? strstr(s, close) : NULL;
  if (!s || !e || e > r->head_end) return points ? bad(r, "a <Points> element") : 0;
  for (const char *p = s; (p = strstr(p, "<DataArray")) && p < e;) {
    const char *end = strchr(p, '>');
    if (!end || end > e) return bad(r, "closed DataArray elements");
    char name[256];
    int nc;
    double *v = NULL;
    int err = data_array(r, p, end, T_F64, (size_t)g->npoints, name, sizeof name, &nc, &v);
    if (!err && points && nc != 3) err = bad(r, "3 coordinates per point");
    if (err) {
      free(v);
      return err;
    }
    if (points) {
      g->x = v;
      return 0;
    }
    mpgm_vtk_array *a = realloc(g->arrays, sizeof *a * (size_t)(g->narray + 1));
    if (!a) {
      free(v);
      MPGM_ERROR(r->ctx, MPGM_ERR_NOMEM, "%s: out of memory", r->path);
    }
    g->arrays = a;
    a += g->narray++;
    snprintf(a->name, sizeof a->name, "%s", name);
    a->ncomp = nc;
    a->v = v;
    p = end;
  }
  return points ? bad(r, "a DataArray of the points") : 0;
}

/* The DataArray called name of the <Cells> element [s, e) (n values of
 * type t) into a new array *v. */
static int cell_array(vr *r, const char *s, const char *e, const char *name, etype t, size_t n,
                      double **v) {
  char key[48], got[32];
  snprintf(key, sizeof key, "Name=\"%s\"", name);
  const char *p = s;
  while ((p = strstr(p, "<DataArray")) && p < e) {
    const char *end = strchr(p, '>');
    if (!end || end > e) break;
    const char *k = strstr(p, key);
    if (k && k < end) {
      int nc;
      MPGM_CALL(data_array(r, p, end, t, n, got, sizeof got, &nc, v));
      return nc == 1 ? 0 : bad(r, "cell arrays of one component");
    }
    p = end;
  }
  return bad(r, "the cells' connectivity, offsets and types");
}

/* The <Cells> of the piece into g: offsets increasing from the first
 * cell's, every id that of a point. */
static int cells(vr *r, mpgm_vtk_grid *g) {
  const char *s = strstr(r->b, "<Cells>"), *e = s ? strstr(s, "</Cells>") : NULL;
  if (!s || !e || e > r->head_end) return bad(r, "a <Cells> element");
  const int nc = g->ncells;
  double *off = NULL, *conn = NULL, *type = NULL;
  int err = cell_array(r, s, e, "offsets", T_I64, (size_t)nc, &off);
  const double last = !err && nc ? off[nc - 1] : 0.0;
  if (!err && !(last >= 0 && last <= INT_MAX)) err = bad(r, "offsets within the connectivity");
  if (!err) err = cell_array(r, s, e, "connectivity", T_I64, (size_t)last, &conn);
  if (!err) err = cell_array(r, s, e, "types", T_U8, (size_t)nc, &type);
  if (!err && (!(g->cell_ptr = malloc(sizeof(int) * ((size_t)nc + 1))) ||
               !(g->conn = malloc(sizeof(int) * ((size_t)last + 1))) ||
               !(g->cell_type = malloc(sizeof(int) * ((size_t)nc + 1)))))
    err = mpgm_err_set(r->ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "%s: out of memory", r->path);
  for (int c = 0; !err && c < nc; c++) {
    g->cell_ptr[c] = c ? (int)off[c - 1] : 0;
    g->cell_type[c] = (int)type[c];
    if (!(off[c] > (c ? off[c - 1] : 0))) err = bad(r, "offsets that grow from cell to cell");
  }
  if (!err) g->cell_ptr[nc] = (int)last;
  for (int k = 0; !err && k < (int)last; k++) {
    g->conn[k] = (int)conn[k];
    if (!(conn[k] >= 0 && conn[k] < g->npoints)) err = bad(r, "cells of the piece's points");
  }
  free(off);
  free(conn);
  free(type);
  return err;
}

static int read_grid(vr *r, mpgm_vtk_grid *g) {
  const char *h = strstr(r->b, "<VTKFile"), *he = h ? strchr(h, '>') : NULL;
  char v[64];
  if (!h || !he || !attr(h, he, "type", v, sizeof v) || strcmp(v, "UnstructuredGrid") != 0)
    return bad(r, "<VTKFile type=\"UnstructuredGrid\"");
  if (!attr(h, he, "byte_order", v, sizeof v) || strcmp(v, "LittleEndian") != 0 ||
      !attr(h, he, "header_type", v, sizeof v) || strcmp(v, "UInt64") != 0)
    return bad(r, "byte_order LittleEndian, header_type UInt64");
  r->zlib = attr(h, he, "compressor", v, sizeof v);
  if (r->zlib && strcmp(v, "vtkZLibDataCompressor") != 0) return bad(r, "vtkZLibDataCompressor");
  const char *a = strstr(he, "<AppendedData");
  r->head_end = a ? a : r->b + r->len;
  if (a) {
    const char *u = strchr(a, '_');
    if (!strstr(a, "encoding=\"raw\"") || !u) return bad(r, "<AppendedData encoding=\"raw\"> _");
    r->app = (const unsigned char *)u + 1;
  }
  const char *p = strstr(he, "<Piece"), *pe = p ? strchr(p, '>') : NULL;
  char np[32], nc[32];
  if (!p || !pe || pe > r->head_end || !attr(p, pe, "NumberOfPoints", np, sizeof np) ||
      !attr(p, pe, "NumberOfCells", nc, sizeof nc))
    return bad(r, "<Piece NumberOfPoints NumberOfCells>");
  const long n = strtol(np, NULL, 10), c = strtol(nc, NULL, 10);
  if (n < 0 || c < 0 || n > INT_MAX / 9 || c > INT_MAX || (size_t)n > r->len)
    return bad(r, "counts of points and cells that fit the file");
  g->npoints = (int)n, g->ncells = (int)c;
  double t = 0.0;
  const char *fd = strstr(he, "<FieldData>"), *tv = fd ? strstr(fd, "<DataArray") : NULL;
  const char *te = tv ? strchr(tv, '>') : NULL;
  char name[64];
  int ncomp;
  double *tval = NULL;
  if (!tv || !te || te > p) return bad(r, "the TimeValue field data");
  int err = data_array(r, tv, te, T_F64, 1, name, sizeof name, &ncomp, &tval);
  if (!err && (strcmp(name, "TimeValue") != 0 || ncomp != 1)) err = bad(r, "a TimeValue of one value");
  if (!err) t = tval[0];
  free(tval);
  MPGM_CALL(err);
  snprintf(g->title, sizeof g->title, "TimeValue = %.17g", t);
  MPGM_CALL(section(r, g, "Points", 1));
  MPGM_CALL(cells(r, g));
  return section(r, g, "PointData", 0);
}

/* See mpgm_vtu.h. */
int mpgm_vtu_read(mpgm_ctx *ctx, const char *path, mpgm_vtk_grid **out) {
  *out = NULL;
  vr r = {ctx, path, NULL, 0, NULL, NULL, 0};
  char *buf;
  MPGM_CALL(mpgm_read_file(ctx, path, VTU_MAX_FILE, &buf, &r.len));
  r.b = buf;
  mpgm_vtk_grid *g = calloc(1, sizeof *g);
  int err = g ? read_grid(&r, g) : mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory");
  free(buf);
  if (err) {
    mpgm_vtk_grid_destroy(&g);
    return err;
  }
  *out = g;
  return 0;
}
