/* test_vtk.c -- VTK legacy writer and .pvd collections: write, read back
 * with an independent parser (ASCII tokens / big-endian binary), compare;
 * atomic writes leave no temporary behind on success or failure. Built in
 * both dimensions: plane strain a mesh of quadrilaterals and triangles (z
 * = 0, the stress {xx, yy, xy, zz}), 3-D one of hexahedra and triangles
 * (z as given, 3-component vectors, the six Voigt stresses as the 3x3
 * tensor, written out here by hand). */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_test.h"
#include "mpgm_vtk.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---------------- a small legacy-VTK reader, independent of vtk.c -------- */

typedef struct {
  char kind[16], name[64];
  int ncomp;
  double *v;
} rfield;

typedef struct {
  char title[300], format[16];
  int ok, np, ncells, csize, nf;
  double *pts;
  int *cells, *types;
  rfield f[8];
} rgrid;

typedef struct {
  unsigned char *b;
  size_t len, pos;
  int binary, bad;
} rbuf;

static unsigned char *slurp(const char *path, size_t *len) {
  FILE *fp = fopen(path, "rb");
  if (!fp) return NULL;
  fseek(fp, 0, SEEK_END);
  long n = ftell(fp);
  fseek(fp, 0, SEEK_SET);
  unsigned char *b = malloc((size_t)n + 1);
  if (b && fread(b, 1, (size_t)n, fp) != (size_t)n) { free(b); b = NULL; }
  if (b) b[n] = '\0';
  fclose(fp);
  *len = (size_t)n;
  return b;
}

/* Next text line (without '\n'); blank lines are skipped in ASCII mode. */
static int r_line(rbuf *r, char *out, size_t cap) {
  for (;;) {
    size_t k = 0;
    if (r->pos >= r->len) return 0;
    while (r->pos < r->len && r->b[r->pos] != '\n') {
      if (k + 1 < cap) out[k++] = (char)r->b[r->pos];
      r->pos++;
    }
    r->pos++;
    out[k] = '\0';
    if (k > 0 || r->binary) return 1;
  }
}

static double r_double(rbuf *r) {
  if (r->binary) {
    if (r->pos + 8 > r->len) { r->bad = 1; return NAN; }
    uint64_t u = 0;
    for (int k = 0; k < 8; k++) u = (u << 8) | r->b[r->pos++];
    double v;
    memcpy(&v, &u, sizeof v);
    return v;
  }
  char *end;
  double v = strtod((const char *)r->b + r->pos, &end);
  if (end == (const char *)r->b + r->pos) r->bad = 1;
  r->pos = (size_t)(end - (const char *)r->b);
  return v;
}

static int r_int(rbuf *r) {
  if (r->binary) {
    if (r->pos + 4 > r->len) { r->bad = 1; return -1; }
    uint32_t u = 0;
    for (int k = 0; k < 4; k++) u = (u << 8) | r->b[r->pos++];
    return (int)(int32_t)u;
  }
  char *end;
  long v = strtol((const char *)r->b + r->pos, &end, 10);
  if (end == (const char *)r->b + r->pos) r->bad = 1;
  r->pos = (size_t)(end - (const char *)r->b);
  return (int)v;
}

/* Binary blocks must end with exactly one '\n'; ASCII: skip to line end. */
static void r_endblock(rbuf *r) {
  if (r->binary) {
    if (r->pos >= r->len || r->b[r->pos] != '\n') r->bad = 1;
    r->pos++;
  } else {
    while (r->pos < r->len && r->b[r->pos] != '\n') {
      if (r->b[r->pos] != ' ') r->bad = 1;
      r->pos++;
    }
  }
}

static void rgrid_free(rgrid *g) {
  free(g->pts); free(g->cells); free(g->types);
  for (int i = 0; i < g->nf; i++) free(g->f[i].v);
  memset(g, 0, sizeof(*g));
}

/* Parse a file as written by mpgm_vtk_write; g->ok = 1 on success. */
static void read_vtk(const char *path, rgrid *g) {
  memset(g, 0, sizeof(*g));
  rbuf r = {0};
  r.b = slurp(path, &r.len);
  if (!r.b) return;
  char line[512];
  int n1, n2;
  if (!r_line(&r, line, sizeof line) ||
      strcmp(line, "# vtk DataFile Version 3.0") != 0) goto done;
  if (!r_line(&r, g->title, sizeof g->title)) goto done;
  if (!r_line(&r, g->format, sizeof g->format)) goto done;
  r.binary = strcmp(g->format, "BINARY") == 0;
  if (!r_line(&r, line, sizeof line) ||
      strcmp(line, "DATASET UNSTRUCTURED_GRID") != 0) goto done;
  if (!r_line(&r, line, sizeof line) ||
      sscanf(line, "POINTS %d double", &g->np) != 1) goto done;
  g->pts = calloc(3 * (size_t)g->np + 1, sizeof(double));
  for (int i = 0; i < 3 * g->np; i++) g->pts[i] = r_double(&r);
  r_endblock(&r);
  if (!r_line(&r, line, sizeof line) ||
      sscanf(line, "CELLS %d %d", &g->ncells, &g->csize) != 2) goto done;
  g->cells = calloc((size_t)g->csize + 1, sizeof(int));
  for (int i = 0; i < g->csize; i++) g->cells[i] = r_int(&r);
  r_endblock(&r);
  if (!r_line(&r, line, sizeof line) ||
      sscanf(line, "CELL_TYPES %d", &n1) != 1 || n1 != g->ncells) goto done;
  g->types = calloc((size_t)g->ncells + 1, sizeof(int));
  for (int i = 0; i < g->ncells; i++) g->types[i] = r_int(&r);
  r_endblock(&r);
  if (r_line(&r, line, sizeof line)) {
    if (sscanf(line, "POINT_DATA %d", &n2) != 1 || n2 != g->np) goto done;
    while (g->nf < 8 && r_line(&r, line, sizeof line)) {
      if (r.binary && line[0] == '\0' && r.pos >= r.len) break;
      rfield *f = &g->f[g->nf];
      if (sscanf(line, "%15s %63s", f->kind, f->name) != 2) goto done;
      if (!strcmp(f->kind, "SCALARS")) {
        if (!r_line(&r, line, sizeof line) ||
            strcmp(line, "LOOKUP_TABLE default") != 0) goto done;
        f->ncomp = 1;
      } else if (!strcmp(f->kind, "VECTORS")) {
        f->ncomp = 3;
      } else if (!strcmp(f->kind, "TENSORS")) {
        f->ncomp = 9;
      } else {
        goto done;
      }
      g->nf++;
      f->v = calloc((size_t)(f->ncomp * g->np) + 1, sizeof(double));
      for (int i = 0; i < f->ncomp * g->np; i++) f->v[i] = r_double(&r);
      r_endblock(&r);
    }
  }
  g->ok = !r.bad && r.pos >= r.len;
done:
  free(r.b);
}

/* ---------------- helpers ------------------------------------------------ */

static char tmpdir[64];

static void join(char *out, size_t cap, const char *name) {
  snprintf(out, cap, "%s/%s", tmpdir, name);
}

/* Number of entries in tmpdir, and how many end in ".tmp". */
static int count_dir(int *ntmp) {
  DIR *d = opendir(tmpdir);
  int n = 0;
  *ntmp = 0;
  if (!d) return -1;
  for (struct dirent *e; (e = readdir(d));) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
    n++;
    size_t l = strlen(e->d_name);
    if (l >= 4 && !strcmp(e->d_name + l - 4, ".tmp")) (*ntmp)++;
  }
  closedir(d);
  return n;
}

static int exists(const char *path) {
  struct stat st;
  return stat(path, &st) == 0;
}

/* Max relative difference |a - b| / max(|b|, 1e-300) over n values. */
static double maxrel(const double *a, const double *b, int n) {
  double m = 0.0;
  for (int i = 0; i < n; i++) {
    double s = fabs(b[i]) > 1e-300 ? fabs(b[i]) : 1e-300;
    double e = fabs(a[i] - b[i]) / s;
    if (!(e <= m)) m = e; /* NaN propagates */
  }
  return m;
}

/* ---------------- the data ----------------------------------------------- */

#if MPGM_DIM == 2
enum { NZ = 1, NCELL_Z = 1, CELL_TYPE = MPGM_VTK_QUAD };
#else
enum { NZ = 2, NCELL_Z = 1, CELL_TYPE = MPGM_VTK_HEXAHEDRON };
#endif
enum { D = MPGM_DIM, NS = MPGM_NSTRESS, NV = 1 << MPGM_DIM, NX = 4, NY = 3, NP = NX * NY * NZ + 1,
       NQ = (NX - 1) * (NY - 1) * NCELL_Z, NT = 2, NC = NQ + NT, NCLOUD = 7 };

typedef struct {
  double x[D * NP], s[NP], v[D * NP], t[NS * NP];
  int ptr[NC + 1], conn[NV * NQ + 3 * NT], type[NC];
} mesh;

/* 3x2 quads on a 4x3 node grid (3-D: hexahedra on two such layers) plus
 * two triangles on an extra node. */
static void make_mesh(mesh *m) {
  for (int k = 0; k < NZ; k++)
    for (int j = 0; j < NY; j++)
      for (int i = 0; i < NX; i++) {
        double *x = m->x + D * (i + NX * j + NX * NY * k);
        x[0] = 0.385 + 1.13 * i + 0.07 * j;
        x[1] = -2.1 + 0.917 * j + 0.031 * i;
        if (D == 3) x[D - 1] = 0.5 + 0.77 * k + 0.013 * i; /* (D - 1: no 2-D warning) */
      }
  m->x[D * (NP - 1)] = 4.2718;
  m->x[D * (NP - 1) + 1] = -1.1563;
  if (D == 3) m->x[D * (NP - 1) + D - 1] = 0.6021;
  int c = 0, k = 0;
  m->ptr[0] = 0;
  for (int l = 0; l < NCELL_Z; l++)
    for (int j = 0; j + 1 < NY; j++)
      for (int i = 0; i + 1 < NX; i++) {
        for (int t = 0; t < NV / 4; t++) { /* the bottom face, then the top (VTK's order) */
          const int a = i + NX * j + NX * NY * (l + t);
          m->conn[k++] = a; m->conn[k++] = a + 1;
          m->conn[k++] = a + 1 + NX; m->conn[k++] = a + NX;
        }
        m->type[c] = CELL_TYPE;
        m->ptr[++c] = k;
      }
  const int tri[2][3] = {{3, NP - 1, 7}, {7, NP - 1, 11}};
  for (int t = 0; t < 2; t++) {
    for (int q = 0; q < 3; q++) m->conn[k++] = tri[t][q];
    m->type[c] = MPGM_VTK_TRIANGLE;
    m->ptr[++c] = k;
  }
  for (int p = 0; p < NP; p++) {
    m->s[p] = 2.385 * sin(1.7 * p + 0.3) + 1e-7 * p;
    m->v[D * p] = -0.0137 * cos(0.9 * p);
    m->v[D * p + 1] = 3.3e-5 * p - 1.0 / 3.0;
    double *t = m->t + NS * p;
    t[0] = 1.25e6 * sin(p + 0.1);
    t[1] = -7.7e5 * cos(p * 0.37);
#if MPGM_DIM == 2
    t[2] = 3.1415e4 * (p - 4.5);
    t[3] = -2.0e5 / (p + 1.0);
#else
    m->v[D * p + 2] = 2.7e-3 * p - 0.25;
    t[2] = -2.0e5 / (p + 1.0);        /* zz */
    t[3] = 3.1415e4 * (p - 4.5);      /* xy */
    t[4] = 5.5e3 * (p + 0.25);        /* yz */
    t[5] = -1.9e4 * (1.0 + 0.1 * p);  /* xz: all three shears differ */
#endif
  }
}

/* The 3x3 tensor of stress s as the files must hold it, row major. */
static void tensor9(const double *s, double *t9) {
#if MPGM_DIM == 2 /* {xx, yy, xy, zz} */
  const double w[9] = {s[0], s[2], 0, s[2], s[1], 0, 0, 0, s[3]};
#else /* {xx, yy, zz, xy, yz, xz} */
  const double w[9] = {s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2]};
#endif
  memcpy(t9, w, sizeof w);
}

/* Compare a read-back grid with what was written. */
static void check_grid(const rgrid *g, const mesh *m, int np, int cloud,
                       int binary, const char *what) {
  double tol = binary ? 0.0 : 1e-15;
  mpgm_test(g->ok, "%s: parses", what);
  mpgm_test(!strcmp(g->format, binary ? "BINARY" : "ASCII"), "%s: format", what);
  mpgm_test(g->np == np, "%s: %d points", what, np);
  if (!g->ok || g->np != np) return;
  double xw[3 * NP], vw[3 * NP], tw[9 * NP];
  for (int p = 0; p < np; p++) {
    for (int c = 0; c < 3; c++) {
      xw[3 * p + c] = c < D ? m->x[D * p + c] : 0.0;
      vw[3 * p + c] = c < D ? m->v[D * p + c] : 0.0;
    }
    tensor9(m->t + NS * p, tw + 9 * p);
  }
  if (D == 3 && np > 1) /* the data do have a z (a writer that drops it fails) */
    mpgm_test(xw[3 * (np - 1) + 2] != 0.0 && vw[3 * (np - 1) + 2] != 0.0 && tw[2] != tw[5],
              "%s: the expected z and shears are not 0", what);
  mpgm_test_abs(maxrel(g->pts, xw, 3 * np), 0.0, tol, "%s: coordinates", what);
  if (cloud) {
    int ok = g->ncells == np && g->csize == 2 * np;
    for (int p = 0; ok && p < np; p++)
      ok = g->cells[2 * p] == 1 && g->cells[2 * p + 1] == p &&
           g->types[p] == MPGM_VTK_VERTEX;
    mpgm_test(ok, "%s: one VTK_VERTEX per point", what);
  } else {
    int ok = g->ncells == NC && g->csize == NC + m->ptr[NC];
    for (int c = 0, k = 0; ok && c < NC; c++) {
      int n = m->ptr[c + 1] - m->ptr[c];
      ok = g->cells[k++] == n && g->types[c] == m->type[c];
      for (int q = 0; ok && q < n; q++) ok = g->cells[k++] == m->conn[m->ptr[c] + q];
    }
    mpgm_test(ok, "%s: connectivity and cell types", what);
#if MPGM_DIM == 3 /* the first hexahedron as VTK numbers its corners */
    static const int hex0[9] = {8, 0, 1, 5, 4, 12, 13, 17, 16};
    mpgm_test(g->ncells > 0 && g->types[0] == 12 && !memcmp(g->cells, hex0, sizeof hex0),
              "%s: cell 0 a VTK_HEXAHEDRON (12) of corners 0 1 5 4 12 13 17 16", what);
#endif
  }
  mpgm_test(g->nf == 3, "%s: 3 fields", what);
  if (g->nf != 3) return;
  mpgm_test(!strcmp(g->f[0].kind, "SCALARS") && !strcmp(g->f[0].name, "mass"),
            "%s: SCALARS mass", what);
  mpgm_test_abs(maxrel(g->f[0].v, m->s, np), 0.0, tol, "%s: mass values", what);
  mpgm_test(!strcmp(g->f[1].kind, "VECTORS") && !strcmp(g->f[1].name, "velocity"),
            "%s: VECTORS velocity", what);
  mpgm_test_abs(maxrel(g->f[1].v, vw, 3 * np), 0.0, tol, "%s: velocity values", what);
  mpgm_test(!strcmp(g->f[2].kind, "TENSORS") && !strcmp(g->f[2].name, "stress"),
            "%s: TENSORS stress", what);
  mpgm_test_abs(maxrel(g->f[2].v, tw, 9 * np), 0.0, tol, "%s: stress values", what);
}

/* ---------------- tests -------------------------------------------------- */

static void test_roundtrip(const mesh *m) {
  const mpgm_vtk_field f[3] = {{"mass", MPGM_VTK_SCALAR, m->s},
                               {"velocity", MPGM_VTK_VECTOR, m->v},
                               {"stress", MPGM_VTK_STRESS, m->t}};
  char longtitle[400];
  memset(longtitle, 'a', sizeof longtitle - 1);
  longtitle[sizeof longtitle - 1] = '\0';
  longtitle[3] = '\n';
  for (int binary = 0; binary <= 1; binary++) {
    char path[256], what[64];
    mpgm_ctx ctx;
    rgrid g;
    mpgm_ctx_init(&ctx);
    join(path, sizeof path, binary ? "mesh_b.vtk" : "mesh_a.vtk");
    int ierr = mpgm_vtk_write(&ctx, path, binary, "mixed\r\nmesh", NP, m->x, NC,
                              m->ptr, m->conn, m->type, 3, f);
    mpgm_test(ierr == 0 && ctx.code == 0, "write %s: %d %s", path, ierr, ctx.msg);
    read_vtk(path, &g);
    snprintf(what, sizeof what, "mesh %s", binary ? "binary" : "ascii");
    check_grid(&g, m, NP, 0, binary, what);
    mpgm_test(!strcmp(g.title, "mixedmesh"), "%s: title without newlines", what);
    rgrid_free(&g);

    join(path, sizeof path, binary ? "cloud_b.vtk" : "cloud_a.vtk");
    ierr = mpgm_vtk_write(&ctx, path, binary, longtitle, NCLOUD, m->x, 0, NULL,
                          NULL, NULL, 3, f);
    mpgm_test(ierr == 0 && ctx.code == 0, "write %s: %d %s", path, ierr, ctx.msg);
    read_vtk(path, &g);
    snprintf(what, sizeof what, "cloud %s", binary ? "binary" : "ascii");
    check_grid(&g, m, NCLOUD, 1, binary, what);
    mpgm_test(strlen(g.title) == 255 && strspn(g.title, "a") == 255,
              "%s: title truncated to 255 chars", what);
    rgrid_free(&g);
  }
  int ntmp, n = count_dir(&ntmp);
  mpgm_test(n == 4 && ntmp == 0, "4 files written, no *.tmp left (%d, %d)", n, ntmp);
}

static void test_errors(const mesh *m) {
  char path[256], tmp[300];
  mpgm_ctx ctx;
  int n0, n, ntmp;

  /* missing directory: the open fails */
  n0 = count_dir(&ntmp);
  mpgm_ctx_init(&ctx);
  join(path, sizeof path, "no_such_dir/mesh.vtk");
  int ierr = mpgm_vtk_write(&ctx, path, 1, "t", NP, m->x, 0, NULL, NULL, NULL,
                            0, NULL);
  mpgm_test(ierr == MPGM_ERR_IO && ctx.code == MPGM_ERR_IO,
            "missing dir: MPGM_ERR_IO (%d)", ierr);
  mpgm_test(strstr(ctx.msg, path) != NULL && strstr(ctx.msg, strerror(ENOENT)),
            "missing dir: message names path and reason: %s", ctx.msg);
  n = count_dir(&ntmp);
  join(path, sizeof path, "no_such_dir");
  mpgm_test(n == n0 && ntmp == 0 && !exists(path), "missing dir: nothing left");

  /* target is a directory: the rename fails, the temporary goes away */
  join(path, sizeof path, "adir");
  mkdir(path, 0700);
  mpgm_ctx_init(&ctx);
  ierr = mpgm_vtk_write(&ctx, path, 0, "t", NP, m->x, 0, NULL, NULL, NULL, 0, NULL);
  snprintf(tmp, sizeof tmp, "%s.tmp", path);
  mpgm_test(ierr == MPGM_ERR_IO && strstr(ctx.msg, path) && !exists(tmp),
            "rename onto a directory: MPGM_ERR_IO, temporary removed: %s", ctx.msg);
  rmdir(path);

  /* a write fails midway (file size limit): old file intact, no temporary */
  join(path, sizeof path, "mesh_b.vtk");
  struct stat st0, st1;
  stat(path, &st0);
  struct rlimit old, lim;
  getrlimit(RLIMIT_FSIZE, &old);
  lim = old;
  lim.rlim_cur = 200;
  void (*oldsig)(int) = signal(SIGXFSZ, SIG_IGN);
  if (setrlimit(RLIMIT_FSIZE, &lim) == 0) {
    mpgm_ctx_init(&ctx);
    ierr = mpgm_vtk_write(&ctx, path, 1, "t", NP, m->x, 0, NULL, NULL, NULL, 0,
                          NULL);
    setrlimit(RLIMIT_FSIZE, &old);
    stat(path, &st1);
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    mpgm_test(ierr == MPGM_ERR_IO && strstr(ctx.msg, path) && !exists(tmp),
              "failed write: MPGM_ERR_IO, temporary removed: %s", ctx.msg);
    mpgm_test(st1.st_size == st0.st_size && st1.st_mtime == st0.st_mtime,
              "failed write: previous file kept");
  } else {
    mpgm_test(1, "setrlimit unavailable: failed-write check skipped");
  }
  signal(SIGXFSZ, oldsig);

  /* bad arguments */
  mpgm_ctx_init(&ctx);
  int badconn[4] = {0, 1, 2, NP};
  int badptr[2] = {0, 4}, qt[1] = {MPGM_VTK_QUAD};
  join(path, sizeof path, "bad.vtk");
  ierr = mpgm_vtk_write(&ctx, path, 1, "t", NP, m->x, 1, badptr, badconn, qt,
                        0, NULL);
  mpgm_test(ierr == MPGM_ERR_INPUT && !exists(path), "point id out of range: %d", ierr);
  mpgm_ctx_init(&ctx);
  const mpgm_vtk_field sp[1] = {{"two words", MPGM_VTK_SCALAR, m->s}};
  ierr = mpgm_vtk_write(&ctx, path, 1, "t", NP, m->x, 0, NULL, NULL, NULL, 1, sp);
  mpgm_test(ierr == MPGM_ERR_INPUT && !exists(path), "field name with space: %d", ierr);
}

static void test_pvd(void) {
  char path[256];
  mpgm_ctx ctx;
  mpgm_pvd *pvd = NULL;
  mpgm_ctx_init(&ctx);
  join(path, sizeof path, "points.pvd");
  int ierr = mpgm_pvd_create(&ctx, path, &pvd);
  mpgm_test(ierr == 0 && pvd && !exists(path), "pvd create writes nothing yet");
  const char *files[3] = {"vtk/points_000000.vtk", "vtk/points_000010.vtk",
                          "vtk/a&b<c>\"d.vtk"};
  const double times[3] = {0.0, 0.1875, 0.3875};
  for (int i = 0; i < 3 && pvd; i++) {
    ierr = mpgm_pvd_add(pvd, &ctx, times[i], files[i]);
    mpgm_test(ierr == 0, "pvd add %d: %s", i, ctx.msg);
  }
  mpgm_pvd_destroy(&pvd);
  mpgm_test(pvd == NULL, "pvd destroy nulls the pointer");
  mpgm_pvd_destroy(&pvd);
  mpgm_pvd_destroy(NULL);

  size_t len = 0;
  char *s = (char *)slurp(path, &len);
  mpgm_test(s != NULL, "pvd written");
  if (s) {
    int nds = 0;
    for (const char *q = s; (q = strstr(q, "<DataSet ")); q++) nds++;
    mpgm_test(nds == 3, "pvd lists 3 data sets (%d)", nds);
    mpgm_test(strstr(s, "type=\"Collection\" version=\"0.1\" "
                        "byte_order=\"LittleEndian\"") != NULL,
              "pvd header");
    mpgm_test(strstr(s, "timestep=\"0\" group=\"\" part=\"0\" "
                        "file=\"vtk/points_000000.vtk\"/>") != NULL &&
                  strstr(s, "timestep=\"0.1875\" group=\"\" part=\"0\" "
                            "file=\"vtk/points_000010.vtk\"/>") != NULL,
              "pvd lists files 1 and 2 with their times");
    mpgm_test(strstr(s, "timestep=\"0.38750000000000001\" group=\"\" part=\"0\" "
                        "file=\"vtk/a&amp;b&lt;c&gt;&quot;d.vtk\"/>") != NULL &&
                  strstr(s, "a&b") == NULL,
              "pvd escapes &, <, >, \" in file 3");
    mpgm_test(strstr(s, "</Collection>\n</VTKFile>\n") != NULL, "pvd closed");
    free(s);
  }
  remove(path);

  /* a collection in a missing directory */
  mpgm_ctx_init(&ctx);
  join(path, sizeof path, "no_such_dir/mesh.pvd");
  ierr = mpgm_pvd_create(&ctx, path, &pvd);
  if (!ierr) ierr = mpgm_pvd_add(pvd, &ctx, 1.5, "x.vtk");
  mpgm_test(ierr == MPGM_ERR_IO && strstr(ctx.msg, path) != NULL,
            "pvd in missing dir: MPGM_ERR_IO: %s", ctx.msg);
  mpgm_pvd_destroy(&pvd);
}

static void cleanup(void) {
  DIR *d = opendir(tmpdir);
  if (d) {
    for (struct dirent *e; (e = readdir(d));) {
      if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
      char path[512];
      join(path, sizeof path, e->d_name);
      remove(path);
    }
    closedir(d);
  }
  rmdir(tmpdir);
}

int main(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/mpgm_test_vtk_XXXXXX");
  if (!mkdtemp(tmpdir)) {
    perror("mkdtemp");
    return EXIT_FAILURE;
  }
  static mesh m;
  make_mesh(&m);
  test_roundtrip(&m);
  test_errors(&m);
  test_pvd();
  cleanup();
  mpgm_test(!exists(tmpdir), "temporary directory removed");
  return mpgm_test_summary();
}
