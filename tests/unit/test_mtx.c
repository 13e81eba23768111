/* test_mtx.c -- Matrix Market files of the linear systems (core/mtx.c):
 * write and read back to the same doubles (general and symmetric files,
 * explicit zeros kept, duplicates summed, symmetry detected), the systems
 * read back solved by every backend to the same solution (an SPD and an
 * unsymmetric one), and malformed files refused with MPGM_ERR_INPUT and a
 * message that names the file and the line. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_mtx.h"
#include "mpgm_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char tmpdir[64];

static const char *path_of(const char *name) {
  static char p[256];
  snprintf(p, sizeof p, "%s/%s", tmpdir, name);
  return p;
}

static int write_bytes(const char *name, const char *text, size_t len) {
  FILE *f = fopen(path_of(name), "w");
  if (!f) return -1;
  fwrite(text, 1, len, f);
  return fclose(f);
}

static int write_text(const char *name, const char *text) {
  return write_bytes(name, text, strlen(text));
}

/* An n x n matrix with a 5-point-like pattern over a line of nodes:
 * A_jj = 6.125 + j/7 (diagonally dominant: SPD when symmetric), A_ij = -1.0625 - 0.3 sin(i + 2j)
 * for |i - j| in {1, 3}
 * (+ conv (i - j) when unsymmetric), one explicit zero at (0, 3) and (3, 0). */
static void build(int n, double conv, mpgm_csc *A) {
  A->n = n;
  A->colptr = malloc(((size_t)n + 1) * sizeof(int));
  A->rowind = malloc(5 * (size_t)n * sizeof(int));
  A->val = malloc(5 * (size_t)n * sizeof(double));
  int k = 0;
  for (int j = 0; j < n; j++) {
    A->colptr[j] = k;
    const int rows[5] = {j - 3, j - 1, j, j + 1, j + 3};
    for (int q = 0; q < 5; q++) {
      const int i = rows[q];
      if (i < 0 || i >= n) continue;
      A->rowind[k] = i;
      if (i == j)
        A->val[k] = 6.125 + j / 7.0;
      else if ((i == 0 && j == 3) || (i == 3 && j == 0))
        A->val[k] = 0.0;
      else
        A->val[k] = -1.0625 - 0.3 * sin((double)(i < j ? i + 2 * j : j + 2 * i)) + conv * (i - j);
      k++;
    }
  }
  A->colptr[n] = k;
  A->nnz = k;
  A->symmetric = conv == 0.0;
}

static void release(mpgm_csc *A) {
  free(A->colptr);
  free(A->rowind);
  free(A->val);
  memset(A, 0, sizeof *A);
}

static int same_csc(const mpgm_csc *A, const mpgm_csc *B) {
  if (A->n != B->n || A->nnz != B->nnz) return 0;
  for (int j = 0; j <= A->n; j++)
    if (A->colptr[j] != B->colptr[j]) return 0;
  for (int k = 0; k < A->nnz; k++)
    if (A->rowind[k] != B->rowind[k] || A->val[k] != B->val[k]) return 0;
  return 1;
}

static void check_round_trip(const char *what, double conv) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0}, B = {0};
  build(23, conv, &A);
  char name[64];
  snprintf(name, sizeof name, "%s_K.mtx", what);
  int e1 = mpgm_mtx_write_csc(&ctx, path_of(name), &A, "test matrix");
  int e2 = mpgm_mtx_read_csc(&ctx, path_of(name), &B);
  mpgm_test(e1 == 0 && e2 == 0, "%s: write, read return %d %d (%s)", what, e1, e2, ctx.msg);
  mpgm_test(e2 == 0 && same_csc(&A, &B),
            "%s: read back to the same pattern and doubles, explicit "
            "zeros kept (%d entries)",
            what, B.nnz);
  mpgm_test(B.symmetric == (conv == 0.0), "%s: symmetry detected (%d)", what, B.symmetric);
  FILE *f = fopen(path_of(name), "r");
  char banner[128] = "";
  if (f && !fgets(banner, sizeof banner, f)) banner[0] = '\0';
  if (f) fclose(f);
  mpgm_test(strstr(banner, conv == 0.0 ? "symmetric" : "general") != NULL, "%s: banner %s", what,
            banner);
  release(&A);
  mpgm_mtx_free_csc(&B);
  mpgm_test(B.colptr == NULL, "%s: free zeroes the matrix", what);
}

/* Symmetric tangent of the core whose triangles differ in the last bits:
 * written as symmetric with the upper triangle. */
static void check_upper(void) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0}, B = {0};
  build(9, 0.0, &A);
  double upper = 0.0;
  for (int j = 0; j < A.n; j++)
    for (int p = A.colptr[j]; p < A.colptr[j + 1]; p++)
      if (A.rowind[p] == 2 && j == 1)
        A.val[p] *= 1.0 + 4 * 2.2e-16; /* lower (2, 1) perturbed */
      else if (A.rowind[p] == 1 && j == 2)
        upper = A.val[p];
  mpgm_test(!mpgm_csc_is_symmetric(&A), "last-bit asymmetry seen");
  int e = mpgm_mtx_write_csc(&ctx, path_of("upper_K.mtx"), &A, NULL);
  if (!e) e = mpgm_mtx_read_csc(&ctx, path_of("upper_K.mtx"), &B);
  int ok = e == 0 && B.symmetric;
  for (int j = 0; ok && j < B.n; j++)
    for (int p = B.colptr[j]; p < B.colptr[j + 1]; p++)
      if ((B.rowind[p] == 2 && j == 1) || (B.rowind[p] == 1 && j == 2)) ok &= B.val[p] == upper;
  mpgm_test(ok, "flagged symmetric: the upper triangle is written and mirrored back (%s)", ctx.msg);
  release(&A);
  mpgm_mtx_free_csc(&B);
}

static void check_vector(void) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  double b[17], *c = NULL;
  int n = 0;
  for (int i = 0; i < 17; i++) b[i] = (i % 3 ? 1.0 : -1.0) * exp(0.731 * i - 5.0) / 3.0;
  b[4] = 0.0;
  b[5] = -0.0;
  int e1 = mpgm_mtx_write_vec(&ctx, path_of("v_b.mtx"), b, 17, "test vector");
  int e2 = mpgm_mtx_read_vec(&ctx, path_of("v_b.mtx"), &c, &n);
  int same = e2 == 0 && n == 17;
  for (int i = 0; same && i < 17; i++) same &= c[i] == b[i];
  mpgm_test(e1 == 0 && same, "vector: read back to the same 17 doubles (%s)", ctx.msg);
  free(c);
}

/* A file with duplicates (summed) and a symmetric file (mirrored). */
static void check_reader_rules(void) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0};
  write_text("dup_K.mtx", "%%MatrixMarket matrix coordinate real general\n% c\n\n3 3 5\n1 1 2.5\n"
                          "3 2 -1\n1 1 0.25\n2 2 4\n3 3 1e1\n");
  int e = mpgm_mtx_read_csc(&ctx, path_of("dup_K.mtx"), &A);
  mpgm_test(e == 0 && A.nnz == 4 && A.val[0] == 2.75 && A.rowind[2] == 2 && !A.symmetric,
            "duplicates summed, rows sorted, unsymmetric (%d, %d entries: %s)", e, A.nnz, ctx.msg);
  mpgm_mtx_free_csc(&A);
  write_text("sym_K.mtx",
             "%%MatrixMarket matrix coordinate integer symmetric\n3 3 4\n1 1 4\n2 1 -1\n"
             "2 2 4\n3 3 4\n");
  e = mpgm_mtx_read_csc(&ctx, path_of("sym_K.mtx"), &A);
  mpgm_test(e == 0 && A.nnz == 5 && A.symmetric && A.colptr[1] == 2 && A.val[1] == -1.0 &&
                A.rowind[2] == 0 && A.val[2] == -1.0,
            "symmetric integer file mirrored (%d, %d entries: %s)", e, A.nnz, ctx.msg);
  mpgm_mtx_free_csc(&A);
}

/* A malformed file: MPGM_ERR_INPUT, a message naming the file, "line L"
 * and what was expected; the matrix stays zeroed. */
static void bad_matrix_n(const char *label, const char *text, size_t len, int line,
                         const char *expect) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0};
  write_bytes("bad_K.mtx", text, len);
  int e = mpgm_mtx_read_csc(&ctx, path_of("bad_K.mtx"), &A);
  char want[32];
  snprintf(want, sizeof want, "line %d:", line);
  mpgm_test(e == MPGM_ERR_INPUT && strstr(ctx.msg, "bad_K.mtx") && strstr(ctx.msg, want) &&
                strstr(ctx.msg, expect) && A.colptr == NULL && A.n == 0,
            "malformed matrix, %s: %s", label, ctx.msg);
}

static void bad_matrix(const char *label, const char *text, int line, const char *expect) {
  bad_matrix_n(label, text, strlen(text), line, expect);
}

static void bad_vector(const char *label, const char *text, int line, const char *expect) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  double *b = NULL;
  int n = -1;
  write_text("bad_b.mtx", text);
  int e = mpgm_mtx_read_vec(&ctx, path_of("bad_b.mtx"), &b, &n);
  char want[32];
  snprintf(want, sizeof want, "line %d:", line);
  mpgm_test(e == MPGM_ERR_INPUT && strstr(ctx.msg, "bad_b.mtx") && strstr(ctx.msg, want) &&
                strstr(ctx.msg, expect) && b == NULL && n == 0,
            "malformed vector, %s: %s", label, ctx.msg);
}

static void check_malformed(void) {
  const char *H = "%%MatrixMarket matrix coordinate real general\n";
  char t[512];
  bad_matrix("empty file", "", 1, "banner");
  bad_matrix("no banner", "3 3 1\n1 1 1\n", 1, "banner");
  bad_matrix("array, not coordinate", "%%MatrixMarket matrix array real general\n2 1\n1\n2\n", 1,
             "banner");
  bad_matrix("pattern file", "%%MatrixMarket matrix coordinate pattern general\n2 2 1\n1 1\n", 1,
             "real or integer");
  bad_matrix("hermitian", "%%MatrixMarket matrix coordinate real hermitian\n2 2 1\n1 1 1\n", 1,
             "symmetry");
  snprintf(t, sizeof t, "%s%% only comments\n", H);
  bad_matrix("no size line", t, 3, "size line");
  snprintf(t, sizeof t, "%s3 x 1\n", H);
  bad_matrix("bad size line", t, 2, "size line");
  snprintf(t, sizeof t, "%s3 2 1\n1 1 1\n", H);
  bad_matrix("not square", t, 2, "square");
  snprintf(t, sizeof t, "%s2 2 5\n", H);
  bad_matrix("more entries than n^2", t, 2, "at most 4 entries");
  snprintf(t, sizeof t, "%s2 2 2\n1 1 1\n", H);
  bad_matrix("too few entries", t, 4, "entry 2 of the 2");
  snprintf(t, sizeof t, "%s2 2 1\n1 1 1\n2 2 1\n", H);
  bad_matrix("too many entries", t, 4, "end of the file");
  snprintf(t, sizeof t, "%s2 2 2\n1 1 1\n3 1 1\n", H);
  bad_matrix("row out of range", t, 4, "ROW and COLUMN in [1, 2]");
  snprintf(t, sizeof t, "%s2 2 2\n1 1 1\n0 1 1\n", H);
  bad_matrix("row 0", t, 4, "ROW and COLUMN in [1, 2]");
  snprintf(t, sizeof t, "%s2 2 1\n1 1 nan\n", H);
  bad_matrix("not finite", t, 3, "finite VALUE");
  snprintf(t, sizeof t, "%s2 2 1\n1 1 1.5e400\n", H);
  bad_matrix("overflow", t, 3, "finite VALUE");
  snprintf(t, sizeof t, "%s2 2 1\n1 1 1 7\n", H);
  bad_matrix("trailing token", t, 3, "ROW COLUMN VALUE");
  snprintf(t, sizeof t, "%s2 2 1\n1.5 1 1\n", H);
  bad_matrix("fractional index", t, 3, "ROW COLUMN VALUE");
  bad_matrix("upper entry of a symmetric file",
             "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1\n1 2 1\n", 4,
             "ROW >= COLUMN");
  static const char bin[] = "%%MatrixMarket matrix coordinate real general\n2 2 1\n1\0 1 1\n";
  bad_matrix_n("binary", bin, sizeof bin - 1, 3, "NUL");

  bad_vector("coordinate banner", "%%MatrixMarket matrix coordinate real general\n2 1 2\n", 1,
             "banner");
  bad_vector("two columns", "%%MatrixMarket matrix array real general\n2 2\n1\n2\n3\n4\n", 2,
             "ROWS 1");
  bad_vector("too few values", "%%MatrixMarket matrix array real general\n3 1\n1\n2\n", 5,
             "value 3 of the 3");
  bad_vector("two values on a line", "%%MatrixMarket matrix array real general\n2 1\n1 2\n", 3,
             "one finite");
  bad_vector("too many values", "%%MatrixMarket matrix array real general\n1 1\n1\n2\n", 4,
             "end of the file");

  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A = {0};
  int e = mpgm_mtx_read_csc(&ctx, path_of("no_such_K.mtx"), &A);
  mpgm_test(e == MPGM_ERR_IO && strstr(ctx.msg, "no_such_K.mtx"), "missing file: MPGM_ERR_IO (%s)",
            ctx.msg);
}

/* The system written, read back and solved by every backend: the same
 * solution (direct to round-off, iterative to its tolerance). */
static void check_solve(const char *what, double conv) {
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_csc A0 = {0}, A = {0};
  build(41, conv, &A0);
  double b0[41], *b = NULL, xt[41], x[41];
  int nb = 0;
  for (int i = 0; i < 41; i++) xt[i] = 1.2345 + sin(0.37 * i);
  for (int i = 0; i < 41; i++) b0[i] = 0.0;
  for (int j = 0; j < 41; j++)
    for (int p = A0.colptr[j]; p < A0.colptr[j + 1]; p++) b0[A0.rowind[p]] += A0.val[p] * xt[j];
  char kn[64], bn[64];
  snprintf(kn, sizeof kn, "%s_K.mtx", what);
  snprintf(bn, sizeof bn, "%s_b.mtx", what);
  int e = mpgm_mtx_write_csc(&ctx, path_of(kn), &A0, NULL);
  if (!e) e = mpgm_mtx_write_vec(&ctx, path_of(bn), b0, 41, NULL);
  if (!e) e = mpgm_mtx_read_csc(&ctx, path_of(kn), &A);
  if (!e) e = mpgm_mtx_read_vec(&ctx, path_of(bn), &b, &nb);
  mpgm_test(e == 0 && nb == 41, "%s: system written and read (%s)", what, ctx.msg);
  const mpgm_solver_type *const *types = mpgm_solver_types();
  for (int k = 0; !e && types[k]; k++) {
    const mpgm_solver_type *t = types[k];
    if (t->needs_spd && !A.symmetric) continue;
    mpgm_ctx c;
    mpgm_ctx_init(&c);
    mpgm_solver *s = NULL;
    int ierr = mpgm_solver_create(&c, t, NULL, &s);
    if (!ierr) ierr = mpgm_solver_analyse(s, &c, &A, NULL);
    if (!ierr) ierr = mpgm_solver_factor(s, &c, &A);
    if (!ierr) ierr = mpgm_solver_solve(s, &c, b, x);
    mpgm_solver_destroy(&s);
    double dx = 0.0, nx = 0.0;
    for (int i = 0; i < 41; i++) {
      dx = fmax(dx, fabs(x[i] - xt[i]));
      nx = fmax(nx, fabs(xt[i]));
    }
    /* direct: round-off of a matrix with condition number below 10;
     * iterative: 100 times its relative-residual tolerance */
    const double tol = t->iterative ? 100.0 * mpgm_solver_opts_default().tol : TEST_TOL3;
    mpgm_test(ierr == 0 && dx <= tol * nx,
              "%s: %s solves the system read back (%d): |x - xt| / |xt| "
              "= %.2e <= %.1e %s",
              what, t->name, ierr, dx / nx, tol, c.msg);
  }
  free(b);
  release(&A0);
  mpgm_mtx_free_csc(&A);
}

int main(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/mpgm_test_mtx_XXXXXX");
  if (!mkdtemp(tmpdir)) {
    mpgm_test(0, "mkdtemp");
    return mpgm_test_summary();
  }
  check_round_trip("symmetric", 0.0);
  check_round_trip("general", 0.173);
  check_upper();
  check_vector();
  check_reader_rules();
  check_malformed();
  check_solve("spd", 0.0);
  check_solve("unsymmetric", 0.173);
  /* leave nothing behind */
  const char *names[] = {"symmetric_K.mtx", "general_K.mtx",     "upper_K.mtx",
                         "v_b.mtx",         "dup_K.mtx",         "sym_K.mtx",
                         "bad_K.mtx",       "bad_b.mtx",         "spd_K.mtx",
                         "spd_b.mtx",       "unsymmetric_K.mtx", "unsymmetric_b.mtx"};
  for (size_t i = 0; i < sizeof names / sizeof *names; i++) remove(path_of(names[i]));
  mpgm_test(rmdir(tmpdir) == 0, "temporary folder removed (nothing else left in it)");
  return mpgm_test_summary();
}
