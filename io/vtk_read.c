/* vtk_read.c -- read back what vtk.c writes: legacy unstructured grids
 * (ASCII or big-endian binary; points, cells and point data) and
 * .pvd collections. See mpgm_vtk.h. Only our own output is supported: a
 * file of another writer is reported as malformed, with the offending
 * header line, never read past its end.
 */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_vtk.h"
#include "mpgm_vtu.h"

#include <cjson/cJSON.h>

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The largest files read back: a frame of material points or of the mesh
 * (ten million points of every field in binary take about 2 GiB), and a
 * .pvd collection (about 80 bytes a frame). */
#define VTK_MAX_FILE ((size_t)4 << 30)
#define PVD_MAX_FILE ((size_t)64 << 20)

typedef struct rd {
  mpgm_ctx *ctx;
  const char *path;
  const char *b;
  size_t len, pos;
  int binary;
} rd;

/* Next header line into out (without '\n'); ASCII files may have blank
 * lines between blocks. 0 at the end of the file. */
static int next_line(rd *r, char *out, size_t cap) {
  for (;;) {
    if (r->pos >= r->len) return 0;
    size_t k = 0;
    while (r->pos < r->len && r->b[r->pos] != '\n') {
      if (k + 1 < cap) out[k++] = r->b[r->pos] == '\r' ? ' ' : r->b[r->pos];
      r->pos++;
    }
    if (r->pos < r->len) r->pos++;
    out[k] = '\0';
    if (k > 0) return 1;
  }
}

static int malformed(rd *r, const char *expected, const char *found) {
  MPGM_ERROR(r->ctx, MPGM_ERR_INPUT, "%s: not a legacy VTK file as mpgm writes it: expected %s, found '%.60s'",
             r->path, expected, found ? found : "end of file");
}

/* n doubles into v (n may be 0). */
static int read_doubles(rd *r, double *v, size_t n) {
  if (r->binary) {
    MPGM_CHECK(r->ctx, r->len - r->pos >= 8 * n, MPGM_ERR_INPUT, "%s: binary data ends early", r->path);
    const unsigned char *p = (const unsigned char *)r->b + r->pos;
    for (size_t i = 0; i < n; i++, p += 8) {
      uint64_t u = 0;
      for (int k = 0; k < 8; k++) u = (u << 8) | p[k];
      memcpy(v + i, &u, sizeof u);
    }
    r->pos += 8 * n;
    return 0;
  }
  for (size_t i = 0; i < n; i++) {
    char *end;
    errno = 0;
    v[i] = strtod(r->b + r->pos, &end);
    MPGM_CHECK(r->ctx, end != r->b + r->pos, MPGM_ERR_INPUT, "%s: expected a number at byte %zu, found '%.20s'",
               r->path, r->pos, r->b + r->pos);
    r->pos = (size_t)(end - r->b);
  }
  return 0;
}

/* n ints into v. */
static int read_ints(rd *r, int *v, size_t n) {
  if (r->binary) {
    MPGM_CHECK(r->ctx, r->len - r->pos >= 4 * n, MPGM_ERR_INPUT, "%s: binary data ends early", r->path);
    const unsigned char *p = (const unsigned char *)r->b + r->pos;
    for (size_t i = 0; i < n; i++, p += 4)
      v[i] = (int)(int32_t)((uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]);
    r->pos += 4 * n;
    return 0;
  }
  for (size_t i = 0; i < n; i++) {
    char *end;
    errno = 0;
    const long x = strtol(r->b + r->pos, &end, 10);
    MPGM_CHECK(r->ctx, end != r->b + r->pos && errno == 0 && x >= INT_MIN && x <= INT_MAX,
               MPGM_ERR_INPUT, "%s: expected an integer at byte %zu", r->path, r->pos);
    v[i] = (int)x;
    r->pos = (size_t)(end - r->b);
  }
  return 0;
}

/* CELLS (ncells cells in m ints: each its count, then its point ids) and
 * CELL_TYPES into g's cells, every count and id checked. */
static int read_cells(rd *r, mpgm_vtk_grid *g, long m) {
  char line[512];
  const int nc = g->ncells;
  MPGM_CHECK(r->ctx, m >= nc, MPGM_ERR_INPUT, "%s: CELLS %d %ld: fewer values than cells", r->path, nc, m);
  MPGM_ALLOC(r->ctx, g->cell_ptr, (size_t)nc + 1);
  MPGM_ALLOC(r->ctx, g->conn, (size_t)(m - nc) + 1);
  MPGM_ALLOC(r->ctx, g->cell_type, (size_t)nc + 1);
  int *all;
  MPGM_ALLOC(r->ctx, all, (size_t)m + 1);
  int err = read_ints(r, all, (size_t)m);
  long at = 0, k = 0;
  for (int c = 0; !err && c < nc; c++) {
    const long n = all[at++];
    g->cell_ptr[c] = (int)k;
    if (n < 1 || n > m - at - (nc - c - 1)) {
      err = mpgm_err_set(r->ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                         "%s: cell %d of %ld points does not fit CELLS %d %ld", r->path, c, n, nc, m);
      break;
    }
    for (long q = 0; !err && q < n; q++, at++) {
      if (all[at] < 0 || all[at] >= g->npoints)
        err = mpgm_err_set(r->ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                           "%s: cell %d refers to point %d of %d", r->path, c, all[at], g->npoints);
      g->conn[k++] = all[at];
    }
  }
  g->cell_ptr[nc] = (int)k;
  if (!err && at != m)
    err = mpgm_err_set(r->ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: CELLS %d %ld holds %ld values "
                       "after its cells", r->path, nc, m, m - at);
  free(all);
  MPGM_CALL(err);
  long n = -1;
  if (!next_line(r, line, sizeof line) || sscanf(line, "CELL_TYPES %ld", &n) != 1 || n != nc)
    return malformed(r, "'CELL_TYPES n' with the count of CELLS", line);
  return read_ints(r, g->cell_type, (size_t)nc);
}

/* A count from a header line, bounded by what the file can hold (one byte
 * per value at least), so a corrupt header cannot ask for huge memory. */
static int bounded(rd *r, long v, const char *line) {
  if (v < 0 || v > INT_MAX / 9 || (size_t)v > r->len) return malformed(r, "a count that fits the file", line);
  return 0;
}

static int read_body(rd *r, mpgm_vtk_grid *g) {
  char line[512];
  if (!next_line(r, line, sizeof line) || strcmp(line, "# vtk DataFile Version 3.0") != 0)
    /* not a VTK file at all: what it holds is not repeated (a .pvd may
     * name any file; its first line can be a secret) */
    MPGM_ERROR(r->ctx, MPGM_ERR_INPUT, "%s: not a legacy VTK file: expected '# vtk DataFile Version "
               "3.0' as its first line", r->path);
  if (!next_line(r, g->title, sizeof g->title)) return malformed(r, "a title line", NULL);
  if (!next_line(r, line, sizeof line)) return malformed(r, "ASCII or BINARY", NULL);
  if (strcmp(line, "BINARY") == 0) r->binary = 1;
  else if (strcmp(line, "ASCII") != 0) return malformed(r, "ASCII or BINARY", line);
  if (!next_line(r, line, sizeof line) || strcmp(line, "DATASET UNSTRUCTURED_GRID") != 0)
    return malformed(r, "'DATASET UNSTRUCTURED_GRID'", line);
  long n = -1, m = -1;
  char kind[32], name[300], type[32];
  if (!next_line(r, line, sizeof line) || sscanf(line, "POINTS %ld double", &n) != 1)
    return malformed(r, "'POINTS n double'", line);
  MPGM_CALL(bounded(r, n, line));
  g->npoints = (int)n;
  MPGM_ALLOC(r->ctx, g->x, 3 * (size_t)n);
  MPGM_CALL(read_doubles(r, g->x, 3 * (size_t)n));
  if (!next_line(r, line, sizeof line) || sscanf(line, "CELLS %ld %ld", &n, &m) != 2)
    return malformed(r, "'CELLS n size'", line);
  MPGM_CALL(bounded(r, n, line));
  MPGM_CALL(bounded(r, m, line));
  g->ncells = (int)n;
  MPGM_CALL(read_cells(r, g, m));
  if (!next_line(r, line, sizeof line)) return 0; /* no point data */
  if (sscanf(line, "POINT_DATA %ld", &n) != 1 || n != g->npoints)
    return malformed(r, "'POINT_DATA n' with the count of POINTS", line);
  while (next_line(r, line, sizeof line)) {
    if (sscanf(line, "%31s %299s %31s", kind, name, type) != 3 || strcmp(type, "double") != 0)
      return malformed(r, "'SCALARS|VECTORS|TENSORS name double'", line);
    int nc = strcmp(kind, "SCALARS") == 0 ? 1 : strcmp(kind, "VECTORS") == 0 ? 3
             : strcmp(kind, "TENSORS") == 0 ? 9 : 0;
    if (!nc) return malformed(r, "'SCALARS|VECTORS|TENSORS name double'", line);
    if (nc == 1 && (!next_line(r, line, sizeof line) || strcmp(line, "LOOKUP_TABLE default") != 0))
      return malformed(r, "'LOOKUP_TABLE default'", line);
    MPGM_CHECK(r->ctx, strlen(name) < sizeof g->arrays[0].name, MPGM_ERR_INPUT, "%s: field name too long",
               r->path);
    mpgm_vtk_array *a = realloc(g->arrays, sizeof *a * (size_t)(g->narray + 1));
    MPGM_CHECK(r->ctx, a, MPGM_ERR_NOMEM, "%s: out of memory", r->path);
    g->arrays = a;
    a += g->narray++;
    memset(a, 0, sizeof *a);
    memcpy(a->name, name, strlen(name) + 1); /* length checked above */
    a->ncomp = nc;
    MPGM_ALLOC(r->ctx, a->v, (size_t)nc * (size_t)g->npoints);
    MPGM_CALL(read_doubles(r, a->v, (size_t)nc * (size_t)g->npoints));
  }
  return 0;
}

int mpgm_vtk_read(mpgm_ctx *ctx, const char *path, mpgm_vtk_grid **out) {
  *out = NULL;
  if (mpgm_ends_with(path, ".vtu")) return mpgm_vtu_read(ctx, path, out);
  rd r = {ctx, path, NULL, 0, 0, 0};
  char *buf;
  MPGM_CALL(mpgm_read_file(ctx, path, VTK_MAX_FILE, &buf, &r.len));
  r.b = buf;
  mpgm_vtk_grid *g = calloc(1, sizeof *g);
  int err = g ? read_body(&r, g) : mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory");
  free(buf);
  if (err) {
    mpgm_vtk_grid_destroy(&g);
    return err;
  }
  *out = g;
  return 0;
}

const mpgm_vtk_array *mpgm_vtk_array_find(const mpgm_vtk_grid *g, const char *name) {
  for (int i = 0; g && i < g->narray; i++)
    if (strcmp(g->arrays[i].name, name) == 0) return &g->arrays[i];
  return NULL;
}

void mpgm_vtk_grid_destroy(mpgm_vtk_grid **g) {
  if (!g || !*g) return;
  for (int i = 0; i < (*g)->narray; i++) free((*g)->arrays[i].v);
  free((*g)->arrays);
  free((*g)->x);
  free((*g)->cell_ptr);
  free((*g)->conn);
  free((*g)->cell_type);
  free(*g);
  *g = NULL;
}

/* ------------------------------------------------------------------------ */
/* .pvd collections                                                         */
/* ------------------------------------------------------------------------ */

/* Value of attribute `name="..."` in the element text [s, e), unescaped
 * (the escapes vtk.c writes) into out. 0 if absent or too long. */
static int attribute(const char *s, const char *e, const char *name, char *out, size_t cap) {
  char key[32];
  snprintf(key, sizeof key, " %s=\"", name);
  const size_t kl = strlen(key);
  for (const char *p = s; p + kl <= e; p++) {
    if (memcmp(p, key, kl) != 0) continue;
    size_t n = 0;
    for (p += kl; p < e && *p != '"'; p++) {
      char c = *p;
      static const char *const esc[][2] = {{"&amp;", "&"}, {"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}};
      for (size_t k = 0; c == '&' && k < 4; k++) {
        const size_t l = strlen(esc[k][0]);
        if ((size_t)(e - p) >= l && memcmp(p, esc[k][0], l) == 0) {
          p += l - 1;
          c = esc[k][1][0];
          break;
        }
      }
      if (n + 1 >= cap) return 0;
      out[n++] = c;
    }
    out[n] = '\0';
    return p < e;
  }
  return 0;
}

/* Entry (time, file) appended to the list; the file checked as below the
 * collection's folder. */
static int list_add(mpgm_ctx *ctx, const char *path, mpgm_pvd_list *out, double time, const char *f) {
  MPGM_CHECK(ctx, mpgm_path_below(f), MPGM_ERR_INPUT, /* a collection from elsewhere must not open /etc/... */
             "%s: file \"%.200s\": expected a path inside the run's folder (relative, without '..')",
             path, f);
  double *tt = realloc(out->time, sizeof *tt * (size_t)(out->n + 1));
  if (tt) out->time = tt;
  char **ff = tt ? realloc(out->file, sizeof *ff * (size_t)(out->n + 1)) : NULL;
  if (ff) out->file = ff;
  char *dup = ff ? strdup(f) : NULL;
  MPGM_CHECK(ctx, dup, MPGM_ERR_NOMEM, "%s: out of memory", path);
  out->time[out->n] = time;
  out->file[out->n++] = dup;
  return 0;
}

/* A .vtk.series (JSON) into out. */
static int series_read(mpgm_ctx *ctx, const char *path, const char *buf, mpgm_pvd_list *out) {
  cJSON *root = cJSON_Parse(buf);
  const cJSON *files = cJSON_GetObjectItemCaseSensitive(root, "files");
  const cJSON *ver = cJSON_GetObjectItemCaseSensitive(root, "file-series-version");
  int err = 0;
  if (!cJSON_IsString(ver) || !cJSON_IsArray(files))
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: not a .vtk.series: expected "
                       "{\"file-series-version\": ..., \"files\": [...]}", path);
  for (const cJSON *e = err ? NULL : files->child; e && !err; e = e->next) {
    const cJSON *n = cJSON_GetObjectItemCaseSensitive(e, "name");
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(e, "time");
    if (!cJSON_IsString(n) || !cJSON_IsNumber(t) || !isfinite(t->valuedouble))
      err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: files[%d]: expected "
                         "{\"name\": FILE, \"time\": NUMBER}", path, out->n);
    else
      err = list_add(ctx, path, out, t->valuedouble, n->valuestring);
  }
  cJSON_Delete(root);
  return err;
}

int mpgm_pvd_read(mpgm_ctx *ctx, const char *path, mpgm_pvd_list *out) {
  memset(out, 0, sizeof *out);
  char *buf;
  size_t len;
  MPGM_CALL(mpgm_read_file(ctx, path, PVD_MAX_FILE, &buf, &len));
  if (mpgm_ends_with(path, ".series")) {
    const int e = series_read(ctx, path, buf, out);
    free(buf);
    if (e) mpgm_pvd_list_free(out);
    return e;
  }
  int err = 0;
  if (!strstr(buf, "<VTKFile") || !strstr(buf, "type=\"Collection\""))
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: not a .pvd collection", path);
  for (const char *p = buf; !err && (p = strstr(p, "<DataSet")); ) {
    const char *e = strchr(p, '>');
    char t[64], f[4096];
    if (!e || !attribute(p, e, "timestep", t, sizeof t) || !attribute(p, e, "file", f, sizeof f)) {
      err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                         "%s: a DataSet without timestep or file attribute", path);
      break;
    }
    char *end;
    const double time = strtod(t, &end);
    if (end == t || *end || !isfinite(time)) {
      err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: timestep \"%s\" is not a number", path, t);
      break;
    }
    if ((err = list_add(ctx, path, out, time, f))) break;
    p = e;
  }
  free(buf);
  if (err) mpgm_pvd_list_free(out);
  return err;
}

void mpgm_pvd_list_free(mpgm_pvd_list *l) {
  if (!l) return;
  for (int i = 0; i < l->n; i++) free(l->file[i]);
  free(l->file);
  free(l->time);
  memset(l, 0, sizeof *l);
}
