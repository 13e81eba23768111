/* test_vtu.c -- mpgm_vtu_write / mpgm_vtu_read (through mpgm_vtk_read, as
 * mpgm render reads frames): a piece written inline ascii, appended raw
 * and zlib-compressed reads back to the same bits (points with z = 0,
 * vectors with z = 0, the stress as 3x3, TimeValue); every truncation and
 * a damaged byte at every position of the raw and zlib files give an
 * error with a message or a read, never a read past the end (run under
 * the sanitizers). Built in both dimensions: plane strain points and
 * vectors with z = 0, the stress {xx, yy, xy, zz}, a triangle and a
 * quadrilateral; 3-D the z as written, the six Voigt stresses as the 3x3
 * tensor (written out here by hand), a triangle and a hexahedron; the
 * cells are read back too. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_test.h"
#include "mpgm_vtu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { NP = 5000 }; /* more than one zlib block of 32 KiB per array */
enum { D = MPGM_DIM, NS = MPGM_NSTRESS };

static char dir[64];

static double x[D * NP], s[NP], v[D * NP], t[NS * NP];

/* The cells: a triangle, then a quadrilateral (3-D: a hexahedron). */
#if MPGM_DIM == 2
static const int cp[3] = {0, 3, 7}, cc[7] = {0, 1, 2, 2, 3, 4, 5};
static const int ct[2] = {MPGM_VTK_TRIANGLE, MPGM_VTK_QUAD};
#else
static const int cp[3] = {0, 3, 11}, cc[11] = {0, 1, 2, 2, 3, 4, 5, 6, 7, 8, 9};
static const int ct[2] = {MPGM_VTK_TRIANGLE, MPGM_VTK_HEXAHEDRON};
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

/* 1 when the grid holds the piece's cells. */
static int same_cells(const mpgm_vtk_grid *g) {
  if (g->ncells != 2 || !g->cell_ptr || !g->conn || !g->cell_type) return 0;
  for (int c = 0; c < 2; c++)
    if (g->cell_type[c] != ct[c] || g->cell_ptr[c + 1] != cp[c + 1]) return 0;
  return g->cell_ptr[0] == 0 && !memcmp(g->conn, cc, sizeof cc);
}

/* 1 when the grid holds the piece's numbers to the bit. */
static int same(const mpgm_vtk_grid *g) {
  const mpgm_vtk_array *a = mpgm_vtk_array_find(g, "eps_p"), *b = mpgm_vtk_array_find(g, "velocity"),
                       *c = mpgm_vtk_array_find(g, "stress");
  if (g->npoints != NP || g->ncells != 2 || g->narray != 3 || !a || !b || !c || a->ncomp != 1 ||
      b->ncomp != 3 || c->ncomp != 9 || strcmp(g->title, "TimeValue = 0.123456789"))
    return 0;
  for (int i = 0; i < NP; i++) {
    double want[9];
    tensor9(t + NS * i, want);
    if (memcmp(c->v + 9 * i, want, sizeof want) || a->v[i] != s[i]) return 0;
    for (int k = 0; k < 3; k++)
      if (g->x[3 * i + k] != (k < D ? x[D * i + k] : 0.0) ||
          b->v[3 * i + k] != (k < D ? v[D * i + k] : 0.0))
        return 0;
  }
  return same_cells(g);
}

/* About 300 prefixes and 300 copies with one byte changed, spread over
 * the file (the XML header, the counts, the data): each
 * read fails with a message or succeeds. */
static void damaged(const char *p) {
  FILE *f = fopen(p, "rb");
  char *buf = malloc(1 << 22);
  const size_t n = f ? fread(buf, 1, 1 << 22, f) : 0;
  if (f) fclose(f);
  char q[160];
  snprintf(q, sizeof q, "%s.bad.vtu", p);
  int quiet = 1, tried = 0;
  for (size_t k = 0; k < n; k += n / 300 + 1) {
    for (int mode = 0; mode < 2; mode++) {
      f = fopen(q, "wb");
      const char keep = buf[k];
      if (mode) buf[k] ^= 0x5a;
      fwrite(buf, 1, mode ? n : k, f);
      fclose(f);
      buf[k] = keep;
      mpgm_ctx ctx;
      mpgm_ctx_init(&ctx);
      mpgm_vtk_grid *g = NULL;
      const int err = mpgm_vtk_read(&ctx, q, &g);
      quiet &= err ? (g == NULL && ctx.msg[0] != '\0') : g != NULL;
      mpgm_vtk_grid_destroy(&g);
      tried++;
    }
  }
  remove(q);
  free(buf);
  mpgm_test(quiet && tried > 100, "%s: %d damaged copies read or refused with a message", p, tried);
}

static void roundtrip(int enc, const char *name) {
  const mpgm_vtk_field f[3] = {{"eps_p", MPGM_VTK_SCALAR, s}, {"velocity", MPGM_VTK_VECTOR, v},
                               {"stress", MPGM_VTK_STRESS, t}};
  const mpgm_vtu_piece piece = {NP, x, 2, cp, cc, ct, 3, f};
  char p[128];
  snprintf(p, sizeof p, "%s/%s", dir, name);
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  int err = mpgm_vtu_write(&ctx, p, enc, 0.123456789, &piece);
  mpgm_test(err == 0, "%s: written (%s)", p, ctx.msg);
  mpgm_vtk_grid *g = NULL;
  err = mpgm_vtk_read(&ctx, p, &g);
  mpgm_test(err == 0 && g && same(g), "%s: read back to the bit (%s)", p, ctx.msg);
  mpgm_vtk_grid_destroy(&g);
  if (enc != MPGM_VTU_ASCII) damaged(p);
  remove(p);
}

int main(void) {
  snprintf(dir, sizeof dir, "/tmp/mpgm_test_vtu_XXXXXX");
  if (!mkdtemp(dir)) {
    perror("mkdtemp");
    return EXIT_FAILURE;
  }
  rng r = {0x9e3779b97f4a7c15ull};
  for (int i = 0; i < D * NP; i++) x[i] = uniform(&r, -3.7, 5.1);
  for (int i = 0; i < NP; i++) s[i] = uniform(&r, -1e-3, 2.385e5);
  for (int i = 0; i < D * NP; i++) v[i] = uniform(&r, -1.0, 1.0) / 3.0;
  for (int i = 0; i < NS * NP; i++) t[i] = uniform(&r, -7.2e6, 3.3e6); /* every component differs */
  roundtrip(MPGM_VTU_ASCII, "a.vtu");
  roundtrip(MPGM_VTU_RAW, "r.vtu");
  roundtrip(MPGM_VTU_ZLIB, "z.vtu");
  mpgm_test(rmdir(dir) == 0, "temporary folder removed");
  return mpgm_test_summary();
}
