/* vtu.c -- VTK XML unstructured-grid writer (.vtu): one piece per file,
 * and the .pvtu index of a frame written in pieces, each written
 * atomically (mpgm_file.h). See mpgm_vtu.h.
 *
 * Binary files put every array in <AppendedData encoding="raw">: the
 * XML header names each array's offset into it, so the bytes of every
 * array (count + data, or the zlib blocks) are made first, in memory, and
 * the file is written in one pass after them. Numbers are stored
 * little-endian whatever the host (the bytes come from shifts), with
 * header_type UInt64 so that no array is limited to 4 GiB.
 */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_vtu.h"

#include "mpgm_file.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

/* vtkZLibDataCompressor's default block: 32 KiB of uncompressed bytes */
enum { ZBLOCK = 1 << 15 };

/* The arrays of a piece, in file order: TimeValue, the point data, the
 * points, connectivity, offsets, types. */
enum { A_TIME = 0, A_FIELDS = 1 };

/* Element types of the arrays. */
typedef enum { T_F64 = 0, T_I64 = 1, T_U8 = 2 } atype;
static const char *const type_names[] = {"Float64", "Int64", "UInt8"};
static const int type_size[] = {8, 8, 1};

/* One array as the writer sees it: its header attributes and a generator
 * of its values (k-th value of n). */
typedef struct {
  const char *name; /* NULL: no Name attribute (the points)   */
  atype type;
  int ncomp;
  size_t n;         /* values (tuples x components)           */
  unsigned char *bytes; /* appended encodings: what goes in the
                           appended block (count + data, or zlib)  */
  size_t nbytes;
} array;

/* The piece and where its arrays' values come from. */
typedef struct {
  const mpgm_vtu_piece *p;
  double time;
  int vertex; /* particle cloud: one vertex cell per point */
} source;

/* Values [k0, k0 + n) of the Float64 array a of the piece s into out: the
 * field's layout is looked up once per call, not once per value. */
static void values_f(const source *s, int a, size_t k0, size_t n, double *out) {
  const mpgm_vtu_piece *p = s->p;
  if (a == A_TIME) {
    out[0] = s->time;
    return;
  }
  const int f = a - A_FIELDS;
  const mpgm_vtk_field *fd = f < p->nfields ? &p->fields[f] : NULL;
  /* a field, or the points (a vector of MPGM_DIM components) */
  mpgm_vtk_components(fd ? fd->kind : MPGM_VTK_VECTOR, fd ? fd->data : p->x, k0, n, out);
}

static long long value_i(const source *s, int a, size_t k) {
  const mpgm_vtu_piece *p = s->p;
  const int c = a - A_FIELDS - p->nfields - 1; /* 0 connectivity, 1 offsets, 2 types */
  if (s->vertex) return c == 0 ? (long long)k : c == 1 ? (long long)k + 1 : MPGM_VTK_VERTEX;
  if (c == 0) return p->conn[p->cell_ptr[0] + (long long)k];
  if (c == 1) return p->cell_ptr[k + 1] - p->cell_ptr[0];
  return p->cell_type[k];
}

/* The little-endian bytes of values [k0, k0 + n) of array a into out
 * (Float64 values made a block of doubles at a time). */
static void encode(const source *s, int a, const array *ar, size_t k0, size_t n, unsigned char *out) {
  if (ar->type != T_F64) {
    for (size_t k = k0; k < k0 + n; k++) {
      const uint64_t u = (uint64_t)value_i(s, a, k);
      for (int b = 0; b < type_size[ar->type]; b++) *out++ = (unsigned char)(u >> (8 * b));
    }
    return;
  }
  double buf[512];
  for (size_t k = k0; k < k0 + n;) {
    const size_t m = k0 + n - k < 512 ? k0 + n - k : 512;
    values_f(s, a, k, m, buf);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    memcpy(out, buf, sizeof(double) * m);
    out += sizeof(double) * m;
#else
    for (size_t i = 0; i < m; i++) {
      uint64_t u;
      memcpy(&u, &buf[i], sizeof u);
      for (int b = 0; b < 8; b++) *out++ = (unsigned char)(u >> (8 * b));
    }
#endif
    k += m;
  }
}

static void put_u64(unsigned char *o, uint64_t v) {
  for (int b = 0; b < 8; b++) o[b] = (unsigned char)(v >> (8 * b));
}

/* The appended block of array a: UInt64 byte count and the data (raw), or
 * vtkZLibDataCompressor's header (blocks, block size, size of the last
 * partial block or 0, compressed size of each) and the blocks, each
 * compressed on its own. 0, or MPGM_ERR_NOMEM / MPGM_ERR_IO. */
static int append_bytes(mpgm_ctx *ctx, const source *s, int a, array *ar, int zlib) {
  const size_t raw = ar->n * (size_t)type_size[ar->type];
  if (!zlib) { /* streamed by write_file, a block at a time: only its size here */
    ar->nbytes = 8 + raw;
    return 0;
  }
  const size_t per = ZBLOCK / (size_t)type_size[ar->type]; /* values per block */
  const size_t nblock = (ar->n + per - 1) / per;
  const size_t head = 8 * (3 + nblock);
  const uLong bound = compressBound(ZBLOCK);
  size_t cap = head + nblock * bound + 1;
  unsigned char *plain = malloc(ZBLOCK);
  ar->bytes = malloc(cap);
  if (!plain || !ar->bytes) {
    free(plain);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (a .vtu array of %zu bytes)", raw);
  }
  put_u64(ar->bytes, nblock);
  put_u64(ar->bytes + 8, ZBLOCK);
  put_u64(ar->bytes + 16, raw % ZBLOCK);
  size_t at = head;
  int zerr = Z_OK;
  for (size_t b = 0; b < nblock && zerr == Z_OK; b++) {
    const size_t n = b + 1 < nblock ? per : ar->n - b * per;
    encode(s, a, ar, b * per, n, plain);
    uLongf len = bound;
    zerr = compress2(ar->bytes + at, &len, plain, (uLong)(n * (size_t)type_size[ar->type]),
                     Z_DEFAULT_COMPRESSION);
    put_u64(ar->bytes + 24 + 8 * b, len);
    at += len;
  }
  free(plain);
  MPGM_CHECK(ctx, zerr == Z_OK, zerr == Z_MEM_ERROR ? MPGM_ERR_NOMEM : MPGM_ERR_IO,
             "zlib could not compress a .vtu array (error %d)", zerr);
  ar->nbytes = at;
  return 0;
}

/* One DataArray element: inline ascii values, or its appended offset. */
static void data_array(FILE *f, const source *s, int a, const array *ar, int ascii, uint64_t offset,
                       const char *indent) {
  fprintf(f, "%s<DataArray type=\"%s\"", indent, type_names[ar->type]);
  if (ar->name) fprintf(f, " Name=\"%s\"", ar->name);
  if (a == A_TIME) fputs(" NumberOfTuples=\"1\"", f);
  if (ar->ncomp > 1) fprintf(f, " NumberOfComponents=\"%d\"", ar->ncomp);
  if (!ascii) {
    fprintf(f, " format=\"appended\" offset=\"%llu\"/>\n", (unsigned long long)offset);
    return;
  }
  fprintf(f, " format=\"ascii\">\n");
  for (size_t k = 0; k < ar->n; k++) {
    if (ar->type == T_F64) {
      double v;
      values_f(s, a, k, 1, &v);
      fprintf(f, "%.17g", v);
    } else {
      fprintf(f, "%lld", value_i(s, a, k));
    }
    fputc((k + 1) % (size_t)(ar->ncomp > 1 ? ar->ncomp : 6) == 0 || k + 1 == ar->n ? '\n' : ' ', f);
  }
  fprintf(f, "%s</DataArray>\n", indent);
}

/* Raw array a into f: its UInt64 byte count, then its values encoded a
 * block at a time into buf (ZBLOCK bytes), so that a frame is never held
 * whole in memory. */
static void stream_raw(FILE *f, const source *s, int a, const array *ar, unsigned char *buf) {
  const size_t size = (size_t)type_size[ar->type], per = ZBLOCK / size;
  put_u64(buf, ar->n * size);
  fwrite(buf, 1, 8, f);
  for (size_t k = 0; k < ar->n; k += per) {
    const size_t n = ar->n - k < per ? ar->n - k : per;
    encode(s, a, ar, k, n, buf);
    fwrite(buf, size, n, f);
  }
}

/* The whole file to f: the XML header (arrays with their offsets) and the
 * appended block (zlib: the arrays' compressed bytes; raw: streamed
 * through buf). */
static void write_file(FILE *f, const source *s, const array *ar, int narr, int enc, unsigned char *buf) {
  const mpgm_vtu_piece *p = s->p;
  const int ascii = enc == MPGM_VTU_ASCII;
  const int ncell = s->vertex ? p->npoints : p->ncells;
  uint64_t off[64 + 8];
  off[0] = 0;
  for (int a = 0; a < narr; a++) off[a + 1] = off[a] + (ascii ? 0 : ar[a].nbytes);
  fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
             "byte_order=\"LittleEndian\" header_type=\"UInt64\"%s>\n  <UnstructuredGrid>\n"
             "    <FieldData>\n",
          enc == MPGM_VTU_ZLIB ? " compressor=\"vtkZLibDataCompressor\"" : "");
  data_array(f, s, A_TIME, &ar[A_TIME], ascii, off[A_TIME], "      ");
  fprintf(f, "    </FieldData>\n    <Piece NumberOfPoints=\"%d\" NumberOfCells=\"%d\">\n"
             "      <PointData>\n", p->npoints, ncell);
  int a = A_FIELDS;
  for (; a < A_FIELDS + p->nfields; a++) data_array(f, s, a, &ar[a], ascii, off[a], "        ");
  fputs("      </PointData>\n      <Points>\n", f);
  data_array(f, s, a, &ar[a], ascii, off[a], "        ");
  fputs("      </Points>\n      <Cells>\n", f);
  for (a++; a < narr; a++) data_array(f, s, a, &ar[a], ascii, off[a], "        ");
  fputs("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n", f);
  if (!ascii) {
    fputs("  <AppendedData encoding=\"raw\">\n   _", f);
    for (a = 0; a < narr; a++)
      if (enc == MPGM_VTU_ZLIB) fwrite(ar[a].bytes, 1, ar[a].nbytes, f);
      else stream_raw(f, s, a, &ar[a], buf);
    fputs("\n  </AppendedData>\n", f);
  }
  fputs("</VTKFile>\n", f);
}

/* See mpgm_vtu.h. */
int mpgm_vtu_write(mpgm_ctx *ctx, const char *path, int encoding, double time,
                   const mpgm_vtu_piece *p) {
  MPGM_CHECK(ctx, p, MPGM_ERR_INPUT, "%s: no piece", path ? path : "mpgm_vtu_write");
  MPGM_CALL(mpgm_vtk_check(ctx, path, p->npoints, p->x, p->ncells, p->cell_ptr, p->conn,
                           p->cell_type, p->nfields, p->fields));
  MPGM_CHECK(ctx, p->nfields <= 64 && isfinite(time) && encoding >= MPGM_VTU_ASCII &&
                      encoding <= MPGM_VTU_ZLIB,
             MPGM_ERR_INPUT, "%s: %d fields (at most 64), time %g, encoding %d", path, p->nfields,
             time, encoding);
  const source s = {p, time, p->ncells == 0 && !p->conn};
  const size_t np = (size_t)p->npoints;
  const size_t nc = s.vertex ? np : (size_t)p->ncells;
  const size_t nconn = s.vertex ? np : (size_t)(p->cell_ptr[p->ncells] - p->cell_ptr[0]);
  array ar[64 + 5];
  int narr = 0;
  ar[narr++] = (array){"TimeValue", T_F64, 1, 1, NULL, 0};
  for (int f = 0; f < p->nfields; f++) {
    const int nk = mpgm_vtk_ncomp(p->fields[f].kind);
    ar[narr++] = (array){p->fields[f].name, T_F64, nk, np * (size_t)nk, NULL, 0};
  }
  ar[narr++] = (array){NULL, T_F64, 3, 3 * np, NULL, 0};
  ar[narr++] = (array){"connectivity", T_I64, 1, nconn, NULL, 0};
  ar[narr++] = (array){"offsets", T_I64, 1, nc, NULL, 0};
  ar[narr++] = (array){"types", T_U8, 1, nc, NULL, 0};
  int err = 0;
  for (int a = 0; !err && encoding != MPGM_VTU_ASCII && a < narr; a++)
    err = append_bytes(ctx, &s, a, &ar[a], encoding == MPGM_VTU_ZLIB);
  unsigned char *buf = err ? NULL : malloc(ZBLOCK);
  if (!err && !buf) err = mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory (.vtu output)");
  void *fp = NULL;
  if (!err) err = mpgm_atomic_open(ctx, path, &fp);
  if (!err) {
    write_file(fp, &s, ar, narr, encoding, buf);
    err = mpgm_atomic_close(ctx, path, fp); /* checks ferror */
  }
  free(buf);
  for (int a = 0; a < narr; a++) free(ar[a].bytes);
  return err;
}

/* See mpgm_vtu.h. */
int mpgm_pvtu_write(mpgm_ctx *ctx, const char *path, const mpgm_vtu_piece *p, int n,
                    const char *stem) {
  MPGM_CHECK(ctx, p && n >= 1 && p->nfields <= 64 && stem && !strchr(stem, '"'), MPGM_ERR_INPUT,
             "%s: an index of %d pieces", path, n);
  void *fp;
  MPGM_CALL(mpgm_atomic_open(ctx, path, &fp));
  FILE *f = fp;
  fputs("<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" "
        "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <PUnstructuredGrid "
        "GhostLevel=\"0\">\n    <PFieldData>\n      <PDataArray type=\"Float64\" "
        "Name=\"TimeValue\" NumberOfTuples=\"1\"/>\n    </PFieldData>\n    <PPointData>\n", f);
  for (int k = 0; k < p->nfields; k++) {
    const int nk = mpgm_vtk_ncomp(p->fields[k].kind);
    fprintf(f, "      <PDataArray type=\"Float64\" Name=\"%s\"", p->fields[k].name);
    if (nk > 1) fprintf(f, " NumberOfComponents=\"%d\"", nk);
    fputs("/>\n", f);
  }
  fputs("    </PPointData>\n    <PPoints>\n      <PDataArray type=\"Float64\" "
        "NumberOfComponents=\"3\"/>\n    </PPoints>\n    <PCells>\n"
        "      <PDataArray type=\"Int64\" Name=\"connectivity\"/>\n"
        "      <PDataArray type=\"Int64\" Name=\"offsets\"/>\n"
        "      <PDataArray type=\"UInt8\" Name=\"types\"/>\n    </PCells>\n", f);
  for (int r = 0; r < n; r++) fprintf(f, "    <Piece Source=\"%s_%d.vtu\"/>\n", stem, r);
  fputs("  </PUnstructuredGrid>\n</VTKFile>\n", f);
  return mpgm_atomic_close(ctx, path, f);
}
