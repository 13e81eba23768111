/* vtk.c -- VTK legacy unstructured-grid writer and .pvd collections, both
 * written atomically (mpgm_file.h). See mpgm_vtk.h.
 *
 * Binary legacy files hold big-endian 8-byte doubles and 4-byte ints; the
 * bytes are produced by shifts, so the output does not depend on the host's
 * byte order. Numbers go through a fixed stack buffer and are handed to
 * fwrite in chunks.
 */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_vtk.h"

#include "mpgm_file.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------------ */
/* Buffered number output                                                   */
/* ------------------------------------------------------------------------ */

enum { WBUF = 1 << 14, WSLACK = 64 };

/* Output state: file, mode, first write errno, chunk buffer. */
typedef struct {
  FILE *fp;
  int binary;
  int err;
  size_t n;
  unsigned char buf[WBUF];
} wstream;

/* Hand the buffered bytes to stdio; remember the first failure. */
static void w_flush(wstream *w) {
  if (w->n && !w->err) {
    errno = 0;
    if (fwrite(w->buf, 1, w->n, w->fp) != w->n) w->err = errno ? errno : EIO;
  }
  w->n = 0;
}

/* Make room for at least WSLACK more bytes. */
static void w_room(wstream *w) {
  if (w->n + WSLACK > WBUF) w_flush(w);
}

/* Append a text line (header lines are short; longer text is chunked). */
static void w_text(wstream *w, const char *s) {
  size_t len = strlen(s);
  while (len) {
    w_room(w);
    size_t k = WBUF - w->n < len ? WBUF - w->n : len;
    memcpy(w->buf + w->n, s, k);
    w->n += k;
    s += k;
    len -= k;
  }
}

/* printf-style header line (at most 511 characters). */
#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static void w_line(wstream *w, const char *fmt, ...) {
  char line[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  w_text(w, line);
}

/* One double: 8 big-endian bytes, or "%.17g" followed by sep. */
static void w_double(wstream *w, double v, char sep) {
  w_room(w);
  if (w->binary) {
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    for (int k = 7; k >= 0; k--) w->buf[w->n++] = (unsigned char)(u >> (8 * k));
  } else {
    int k = snprintf((char *)w->buf + w->n, WSLACK, "%.17g%c", v, sep);
    w->n += (size_t)k;
  }
}

/* One int: 4 big-endian bytes (two's complement), or "%d" followed by sep. */
static void w_int(wstream *w, int v, char sep) {
  w_room(w);
  if (w->binary) {
    uint32_t u = (uint32_t)v;
    for (int k = 3; k >= 0; k--) w->buf[w->n++] = (unsigned char)(u >> (8 * k));
  } else {
    int k = snprintf((char *)w->buf + w->n, WSLACK, "%d%c", v, sep);
    w->n += (size_t)k;
  }
}

/* End of a data block: binary blocks get their trailing newline; ASCII
 * blocks already end with one. */
static void w_end_block(wstream *w) {
  if (w->binary) w_text(w, "\n");
}

/* ------------------------------------------------------------------------ */
/* Legacy unstructured grid                                                 */
/* ------------------------------------------------------------------------ */

int mpgm_vtk_ncomp(int kind) { return kind == MPGM_VTK_SCALAR ? 1 : kind == MPGM_VTK_VECTOR ? 3 : 9; }

/* Entry k of the row-major 3x3 stress tensor: its component in mpgm's
 * layout (MPGM_NSTRESS per point), or -1 where the tensor is 0 (plane
 * strain's xz, yz). */
static int stress_entry(int k) {
  const int i = k / 3, j = k % 3;
#if MPGM_DIM == 2
  if (i == 2 || j == 2) return i == j ? MPGM_NSTRESS - 1 : -1; /* zz last */
#endif
  return mpgm_voigt_of[i][j];
}

void mpgm_vtk_components(int kind, const double *data, size_t k0, size_t n, double *out) {
  if (kind == MPGM_VTK_SCALAR) {
    memcpy(out, data + k0, sizeof(double) * n);
  } else if (kind == MPGM_VTK_STRESS) {
    int map[9];
    for (int k = 0; k < 9; k++) map[k] = stress_entry(k);
    for (size_t k = k0; k < k0 + n; k++) {
      const int m = map[k % 9];
      *out++ = m < 0 ? 0.0 : data[MPGM_NSTRESS * (k / 9) + m];
    }
  } else {
    for (size_t k = k0; k < k0 + n; k++)
      *out++ = k % 3 >= MPGM_DIM ? 0.0 : data[MPGM_DIM * (k / 3) + k % 3];
  }
}

/* See mpgm_vtk.h. */
int mpgm_vtk_check(mpgm_ctx *ctx, const char *path, int npoints,
                          const double *x, int ncells, const int *cell_ptr,
                          const int *conn, const int *cell_type, int nfields,
                          const mpgm_vtk_field *fields) {
  MPGM_CHECK(ctx, path && *path, MPGM_ERR_INPUT, "mpgm_vtk_write: empty path");
  MPGM_CHECK(ctx, npoints >= 0 && (npoints == 0 || x), MPGM_ERR_INPUT,
             "%s: bad points (n = %d)", path, npoints);
  MPGM_CHECK(ctx, nfields >= 0 && (nfields == 0 || fields), MPGM_ERR_INPUT,
             "%s: bad field list", path);
  if (ncells == 0 && !conn) {
    MPGM_CHECK(ctx, npoints <= INT_MAX / 2, MPGM_ERR_INPUT,
               "%s: too many points for a vertex cloud", path);
  } else {
    MPGM_CHECK(ctx, ncells >= 0 && cell_ptr && conn && cell_type,
               MPGM_ERR_INPUT, "%s: bad cells (n = %d)", path, ncells);
    MPGM_CHECK(ctx, cell_ptr[0] >= 0, MPGM_ERR_INPUT, "%s: cell_ptr[0] < 0",
               path);
    for (int c = 0; c < ncells; c++) {
      MPGM_CHECK(ctx, cell_ptr[c + 1] > cell_ptr[c] && cell_type[c] > 0,
                 MPGM_ERR_INPUT, "%s: cell %d empty or bad type", path, c);
      for (int k = cell_ptr[c]; k < cell_ptr[c + 1]; k++)
        MPGM_CHECK(ctx, conn[k] >= 0 && conn[k] < npoints, MPGM_ERR_INPUT,
                   "%s: cell %d refers to point %d of %d", path, c, conn[k],
                   npoints);
    }
    long long size = (long long)ncells + cell_ptr[ncells] - cell_ptr[0];
    MPGM_CHECK(ctx, size <= INT_MAX, MPGM_ERR_INPUT,
               "%s: connectivity too large for the legacy format", path);
  }
  for (int f = 0; f < nfields; f++) {
    const mpgm_vtk_field *fd = &fields[f];
    int ok = fd->name && *fd->name && strlen(fd->name) < 256 &&
             (npoints == 0 || fd->data) &&
             (fd->kind == MPGM_VTK_SCALAR || fd->kind == MPGM_VTK_VECTOR ||
              fd->kind == MPGM_VTK_STRESS);
    for (const char *s = ok ? fd->name : ""; *s; s++)
      if ((unsigned char)*s <= ' ') ok = 0;
    MPGM_CHECK(ctx, ok, MPGM_ERR_INPUT,
               "%s: field %d: bad name, kind or data", path, f);
  }
  return MPGM_OK;
}

/* A point or vector of MPGM_DIM components as 3 (2-D: z = 0). */
static void w_vector(wstream *w, const double *v) {
  for (int c = 0; c < 3; c++) w_double(w, c < MPGM_DIM ? v[c] : 0.0, c == 2 ? '\n' : ' ');
}

/* Write the header, points, cells and point data to w. */
static void vtk_body(wstream *w, const char *title, int npoints,
                     const double *x, int ncells, const int *cell_ptr,
                     const int *conn, const int *cell_type, int nfields,
                     const mpgm_vtk_field *fields) {
  char t[256];
  size_t m = 0;
  for (const char *s = title ? title : "mpgm"; *s && m < 255; s++)
    if (*s != '\n' && *s != '\r') t[m++] = *s;
  t[m] = '\0';

  w_line(w, "# vtk DataFile Version 3.0\n%s\n%s\nDATASET UNSTRUCTURED_GRID\n",
         t, w->binary ? "BINARY" : "ASCII");
  w_line(w, "POINTS %d double\n", npoints);
  for (int p = 0; p < npoints; p++) w_vector(w, x + MPGM_DIM * p);
  w_end_block(w);

  if (ncells == 0 && !conn) { /* particle cloud: one vertex per point */
    w_line(w, "CELLS %d %d\n", npoints, 2 * npoints);
    for (int p = 0; p < npoints; p++) {
      w_int(w, 1, ' ');
      w_int(w, p, '\n');
    }
    w_end_block(w);
    w_line(w, "CELL_TYPES %d\n", npoints);
    for (int p = 0; p < npoints; p++) w_int(w, MPGM_VTK_VERTEX, '\n');
    w_end_block(w);
  } else {
    w_line(w, "CELLS %d %d\n", ncells,
           ncells + cell_ptr[ncells] - cell_ptr[0]);
    for (int c = 0; c < ncells; c++) {
      w_int(w, cell_ptr[c + 1] - cell_ptr[c], ' ');
      for (int k = cell_ptr[c]; k < cell_ptr[c + 1]; k++)
        w_int(w, conn[k], k + 1 < cell_ptr[c + 1] ? ' ' : '\n');
    }
    w_end_block(w);
    w_line(w, "CELL_TYPES %d\n", ncells);
    for (int c = 0; c < ncells; c++) w_int(w, cell_type[c], '\n');
    w_end_block(w);
  }

  if (nfields > 0) w_line(w, "POINT_DATA %d\n", npoints);
  for (int f = 0; f < nfields; f++) {
    const mpgm_vtk_field *fd = &fields[f];
    const double *d = fd->data;
    if (fd->kind == MPGM_VTK_SCALAR) {
      w_line(w, "SCALARS %s double 1\nLOOKUP_TABLE default\n", fd->name);
      for (int p = 0; p < npoints; p++) w_double(w, d[p], '\n');
    } else if (fd->kind == MPGM_VTK_VECTOR) {
      w_line(w, "VECTORS %s double\n", fd->name);
      for (int p = 0; p < npoints; p++) w_vector(w, d + MPGM_DIM * p);
    } else { /* the 3x3 tensor, row major (mpgm_vtk_components) */
      w_line(w, "TENSORS %s double\n", fd->name);
      double row[9];
      for (int p = 0; p < npoints; p++) {
        mpgm_vtk_components(MPGM_VTK_STRESS, d, 9 * (size_t)p, 9, row);
        for (int k = 0; k < 9; k++) w_double(w, row[k], k % 3 == 2 ? '\n' : ' ');
      }
    }
    w_end_block(w);
  }
  w_flush(w);
}

/* See mpgm_vtk.h. */
int mpgm_vtk_write(mpgm_ctx *ctx, const char *path, int binary,
                   const char *title, int npoints, const double *x,
                   int ncells, const int *cell_ptr, const int *conn,
                   const int *cell_type, int nfields,
                   const mpgm_vtk_field *fields) {
  MPGM_CALL(mpgm_vtk_check(ctx, path, npoints, x, ncells, cell_ptr, conn,
                           cell_type, nfields, fields));
  wstream *w = malloc(sizeof(*w));
  MPGM_CHECK(ctx, w != NULL, MPGM_ERR_NOMEM, "%s: out of memory", path);
  w->binary = binary != 0;
  w->err = 0;
  w->n = 0;
  void *fp = NULL;
  int ierr = mpgm_atomic_open(ctx, path, &fp);
  if (ierr) {
    free(w);
    return ierr;
  }
  w->fp = fp;
  vtk_body(w, title, npoints, x, ncells, cell_ptr, conn, cell_type, nfields,
           fields);
  int err = w->err;
  free(w);
  if (err) {
    mpgm_atomic_discard(path, fp);
    MPGM_ERROR(ctx, MPGM_ERR_IO, "%s: %s", path, strerror(err));
  }
  return mpgm_atomic_close(ctx, path, fp);
}

/* ------------------------------------------------------------------------ */
/* .pvd collections                                                         */
/* ------------------------------------------------------------------------ */

struct mpgm_pvd {
  char *path;   /**< where the collection is written (owned) */
  int n, cap;   /**< entries used / allocated                */
  double *time; /**< time of every entry                     */
  char **file;  /**< file of every entry (owned strings)     */
};

/* See mpgm_vtk.h. */
int mpgm_pvd_create(mpgm_ctx *ctx, const char *path, mpgm_pvd **out) {
  MPGM_CHECK(ctx, path && *path && out, MPGM_ERR_INPUT,
             "mpgm_pvd_create: empty path or NULL output");
  *out = NULL;
  mpgm_pvd *p = calloc(1, sizeof(*p));
  if (p) p->path = strdup(path);
  if (!p || !p->path) {
    mpgm_pvd_destroy(&p);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "%s: out of memory", path);
  }
  *out = p;
  return MPGM_OK;
}

/* Write s with the XML attribute escapes for &, <, >, ". */
static void xml_escaped(FILE *fp, const char *s) {
  for (; *s; s++) {
    switch (*s) {
    case '&': fputs("&amp;", fp); break;
    case '<': fputs("&lt;", fp); break;
    case '>': fputs("&gt;", fp); break;
    case '"': fputs("&quot;", fp); break;
    default: fputc(*s, fp);
    }
  }
}

/* s as a JSON string's contents (quotes, backslashes and control
 * characters escaped). */
static void json_escaped(FILE *fp, const char *s) {
  for (; *s; s++) {
    if (*s == '"' || *s == '\\') fprintf(fp, "\\%c", *s);
    else if ((unsigned char)*s < 0x20) fprintf(fp, "\\u%04x", (unsigned char)*s);
    else fputc(*s, fp);
  }
}

/* The collection as ParaView's .vtk.series: {"file-series-version":
 * "1.0", "files": [{"name": ..., "time": ...}, ...]}. */
static void series_body(const mpgm_pvd *p, FILE *fp) {
  fputs("{\n  \"file-series-version\": \"1.0\",\n  \"files\": [", fp);
  for (int i = 0; i < p->n; i++) {
    fputs(i ? ",\n    {\"name\": \"" : "\n    {\"name\": \"", fp);
    json_escaped(fp, p->file[i]);
    fprintf(fp, "\", \"time\": %.17g}", p->time[i]);
  }
  fputs(p->n ? "\n  ]\n}\n" : "]\n}\n", fp);
}

/* Rewrite the whole collection atomically. */
static int pvd_write(const mpgm_pvd *p, mpgm_ctx *ctx) {
  void *vfp = NULL;
  MPGM_CALL(mpgm_atomic_open(ctx, p->path, &vfp));
  FILE *fp = vfp;
  if (mpgm_ends_with(p->path, ".series")) { /* ParaView's JSON series of legacy files */
    series_body(p, fp);
    return mpgm_atomic_close(ctx, p->path, fp);
  }
  fputs("<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"Collection\" version=\"0.1\" "
        "byte_order=\"LittleEndian\">\n  <Collection>\n", fp);
  for (int i = 0; i < p->n; i++) {
    fprintf(fp, "    <DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"",
            p->time[i]);
    xml_escaped(fp, p->file[i]);
    fputs("\"/>\n", fp);
  }
  fputs("  </Collection>\n</VTKFile>\n", fp);
  return mpgm_atomic_close(ctx, p->path, fp); /* checks ferror */
}

/* Room for twice the entries; 0 when out of memory. */
static int pvd_grow(mpgm_pvd *pvd) {
  const int cap = pvd->cap ? 2 * pvd->cap : 16;
  if (cap <= pvd->cap || (size_t)cap >= SIZE_MAX / sizeof(double)) return 0;
  double *t = realloc(pvd->time, (size_t)cap * sizeof(*t));
  if (t) pvd->time = t;
  char **f = t ? realloc(pvd->file, (size_t)cap * sizeof(*f)) : NULL;
  if (f) pvd->file = f;
  if (!t || !f) return 0;
  pvd->cap = cap;
  return 1;
}

/* See mpgm_vtk.h. On failure the entry is not kept. */
int mpgm_pvd_add(mpgm_pvd *pvd, mpgm_ctx *ctx, double time, const char *file) {
  MPGM_CHECK(ctx, pvd && file && *file, MPGM_ERR_INPUT,
             "mpgm_pvd_add: NULL collection or empty file name");
  MPGM_CHECK(ctx, isfinite(time), MPGM_ERR_INPUT, "%s: time %g not finite",
             pvd->path, time);
  MPGM_CHECK(ctx, pvd->n < pvd->cap || pvd_grow(pvd), MPGM_ERR_NOMEM, "%s: out of memory",
             pvd->path);
  char *name = strdup(file);
  MPGM_CHECK(ctx, name != NULL, MPGM_ERR_NOMEM, "%s: out of memory", pvd->path);
  pvd->time[pvd->n] = time;
  pvd->file[pvd->n] = name;
  pvd->n++;
  int ierr = pvd_write(pvd, ctx);
  if (ierr) { /* roll back: the collection on disk is unchanged */
    pvd->n--;
    free(name);
  }
  return ierr;
}

/* See mpgm_vtk.h: n, the times, the file names NUL-separated. */
int mpgm_pvd_save(const mpgm_pvd *pvd, mpgm_ctx *ctx, mpgm_blob *b, const char *tag) {
  char t[MPGM_BLOB_TAG];
  const int n = pvd ? pvd->n : 0;
  size_t len = 0;
  for (int i = 0; i < n; i++) len += strlen(pvd->file[i]) + 1;
  char *names = malloc(len ? len : 1);
  MPGM_CHECK(ctx, names, MPGM_ERR_NOMEM, "out of memory (checkpoint)");
  for (int i = 0, k = 0; i < n; i++) {
    const size_t l = strlen(pvd->file[i]) + 1;
    memcpy(names + k, pvd->file[i], l);
    k += (int)l;
  }
  snprintf(t, sizeof t, "%s.n", tag);
  int err = mpgm_blob_put(ctx, b, t, &n, sizeof n);
  snprintf(t, sizeof t, "%s.time", tag);
  if (!err) err = mpgm_blob_put(ctx, b, t, n ? pvd->time : NULL, sizeof(double) * (size_t)n);
  snprintf(t, sizeof t, "%s.file", tag);
  if (!err) err = mpgm_blob_put(ctx, b, t, names, len);
  free(names);
  return err;
}

int mpgm_pvd_restore(mpgm_pvd *pvd, mpgm_ctx *ctx, mpgm_blob *b, const char *tag) {
  char t[MPGM_BLOB_TAG];
  int n;
  size_t len;
  snprintf(t, sizeof t, "%s.n", tag);
  MPGM_CALL(mpgm_blob_get(ctx, b, t, &n, sizeof n));
  MPGM_CHECK(ctx, n >= 0 && (pvd ? pvd->n == 0 : n == 0), MPGM_ERR_INPUT,
             "checkpoint: section '%s': %d entries%s", t, n, pvd ? "" : " of no collection");
  /* the sizes before any allocation: a count is only as good as its data */
  snprintf(t, sizeof t, "%s.time", tag);
  MPGM_CALL(mpgm_blob_peek(ctx, b, t, &len));
  MPGM_CHECK(ctx, len == sizeof(double) * (size_t)n, MPGM_ERR_INPUT,
             "checkpoint: section '%s' "
             "holds %zu bytes, %d entries need %zu",
             t, len, n, sizeof(double) * (size_t)n);
  double *time = malloc(sizeof(double) * (size_t)(n ? n : 1));
  MPGM_CHECK(ctx, time, MPGM_ERR_NOMEM, "out of memory (checkpoint)");
  int err = mpgm_blob_get(ctx, b, t, time, sizeof(double) * (size_t)n);
  for (int i = 0; !err && i < n; i++)
    if (!isfinite(time[i]))
      err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                         "checkpoint: section '%s': "
                         "entry %d at time %g, not a finite number",
                         t, i, time[i]);
  snprintf(t, sizeof t, "%s.file", tag);
  if (!err) err = mpgm_blob_peek(ctx, b, t, &len);
  char *names = err ? NULL : malloc(len + 1);
  if (!err && !names) err = mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory");
  if (!err) err = mpgm_blob_get(ctx, b, t, names, len);
  if (!err) names[len] = '\0';
  /* the entries again: n names, none empty, and nothing after them */
  const char *p = names;
  for (int i = 0; !err && i < n; i++) {
    if ((size_t)(p - names) >= len || !*p) {
      err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                         "checkpoint: section '%s': "
                         "%d names of files for %d entries",
                         t, i, n);
      break;
    }
    char *name = strdup(p);
    if (!name || (pvd->n == pvd->cap && !pvd_grow(pvd))) {
      free(name);
      err = mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory");
      break;
    }
    pvd->time[pvd->n] = time[i];
    pvd->file[pvd->n++] = name;
    p += strlen(p) + 1;
  }
  if (!err && (size_t)(p - names) != len)
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                       "checkpoint: section '%s': %zu "
                       "bytes after the names of its %d entries",
                       t, len - (size_t)(p - names), n);
  free(time);
  free(names);
  return err;
}

int mpgm_pvd_write(mpgm_pvd *pvd, mpgm_ctx *ctx) {
  return pvd ? pvd_write(pvd, ctx) : 0;
}

int mpgm_pvd_count(const mpgm_pvd *pvd) {
  return pvd ? pvd->n : 0;
}

/* See mpgm_vtk.h. */
void mpgm_pvd_destroy(mpgm_pvd **pvd) {
  if (!pvd || !*pvd) return;
  mpgm_pvd *p = *pvd;
  for (int i = 0; i < p->n; i++) free(p->file[i]);
  free(p->file);
  free(p->time);
  free(p->path);
  free(p);
  *pvd = NULL;
}
