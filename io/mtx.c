/* mtx.c -- Matrix Market reader and writer of the linear systems
 * (mpgm_mtx.h). Reading is strict: every line is checked, and the first
 * problem is reported with the file, the line and what was expected. */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_mtx.h"

#include "mpgm_file.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "mpgm_vtk.h"

/* Position of row i in column j of A, or -1 (rows sorted). */
static int find_entry(const mpgm_csc *A, int i, int j) {
  int lo = A->colptr[j], hi = A->colptr[j + 1] - 1;
  while (lo <= hi) {
    const int mid = lo + (hi - lo) / 2;
    if (A->rowind[mid] == i) return mid;
    if (A->rowind[mid] < i)
      lo = mid + 1;
    else
      hi = mid - 1;
  }
  return -1;
}

/* 1 when every stored (i, j) has a stored (j, i); with values, also of
 * the same value. */
static int symmetric(const mpgm_csc *A, int values) {
  for (int j = 0; j < A->n; j++)
    for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) {
      const int i = A->rowind[p];
      if (i <= j) continue; /* each pair once, from below the diagonal */
      const int q = find_entry(A, j, i);
      if (q < 0 || (values && A->val[q] != A->val[p])) return 0;
    }
  /* the pairs seen from below cover the upper entries only if the upper
   * triangle holds no more entries than the lower one */
  long lower = 0, upper = 0;
  for (int j = 0; j < A->n; j++)
    for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) {
      if (A->rowind[p] > j) lower++;
      if (A->rowind[p] < j) upper++;
    }
  return lower == upper;
}

int mpgm_csc_is_symmetric(const mpgm_csc *A) {
  return symmetric(A, 1);
}

int mpgm_mtx_write_csc(mpgm_ctx *ctx, const char *path, const mpgm_csc *A, const char *comment) {
  const int sym = (A->symmetric && symmetric(A, 0)) || symmetric(A, 1);
  long nnz = 0;
  for (int j = 0; j < A->n; j++)
    for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) nnz += !sym || A->rowind[p] <= j;
  void *fv;
  MPGM_CALL(mpgm_atomic_open(ctx, path, &fv));
  FILE *f = fv;
  fprintf(f, "%%%%MatrixMarket matrix coordinate real %s\n", sym ? "symmetric" : "general");
  if (comment) fprintf(f, "%% %s\n", comment);
  fprintf(f, "%d %d %ld\n", A->n, A->n, nnz);
  /* symmetric: the upper triangle (the one the SPD backends read), as the
   * lower triangle the format stores */
  for (int j = 0; j < A->n; j++)
    for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) {
      if (!sym)
        fprintf(f, "%d %d %.17g\n", A->rowind[p] + 1, j + 1, A->val[p]);
      else if (A->rowind[p] <= j)
        fprintf(f, "%d %d %.17g\n", j + 1, A->rowind[p] + 1, A->val[p]);
    }
  return mpgm_atomic_close(ctx, path, f);
}

int mpgm_mtx_write_vec(mpgm_ctx *ctx, const char *path, const double *b, int n,
                       const char *comment) {
  void *fv;
  MPGM_CALL(mpgm_atomic_open(ctx, path, &fv));
  FILE *f = fv;
  fputs("%%MatrixMarket matrix array real general\n", f);
  if (comment) fprintf(f, "%% %s\n", comment);
  fprintf(f, "%d 1\n", n);
  for (int i = 0; i < n; i++) fprintf(f, "%.17g\n", b[i]);
  return mpgm_atomic_close(ctx, path, f);
}

/* ---- reading ------------------------------------------------------------ */

/* The largest Matrix Market file read: about 40 bytes an entry, so a
 * hundred million entries. */
#define MTX_MAX_FILE ((size_t)4 << 30)

typedef struct reader {
  mpgm_ctx *ctx;
  const char *path;
  FILE *f;
  char *line; /**< current line, without its newline */
  size_t cap;
  long lineno; /**< its number, from 1 */
  size_t bytes; /**< read so far (held to MTX_MAX_FILE: a file may grow) */
} reader;

/* The current line for messages: quoted, at most 60 characters. */
static const char *excerpt(const reader *r, char *buf, size_t len) {
  if (!r->line) return "end of file";
  snprintf(buf, len, "'%.60s%s'", r->line, strlen(r->line) > 60 ? "..." : "");
  return buf;
}

/* "FILE: line L: expected WHAT, found LINE" (MPGM_ERR_INPUT). */
static int bad(reader *r, const char *what) {
  char ex[80];
  return mpgm_err_set(r->ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                      "%s: line %ld: expected %s, found %s", r->path, r->lineno, what,
                      excerpt(r, ex, sizeof ex));
}

/* Read the next line into r->line (NULL at the end of the file). With
 * skip, comment ('%') and blank lines are passed over. Errors:
 * MPGM_ERR_IO. */
static int next_line(reader *r, int skip) {
  for (;;) {
    errno = 0;
    const ssize_t len = getline(&r->line, &r->cap, r->f);
    if (len < 0) {
      if (ferror(r->f))
        MPGM_ERROR(r->ctx, MPGM_ERR_IO, "%s: read error after line %ld: %s", r->path, r->lineno,
                   strerror(errno ? errno : EIO));
      free(r->line);
      r->line = NULL;
      r->cap = 0;
      r->lineno++;
      return 0;
    }
    r->lineno++;
    r->bytes += (size_t)len;
    if (r->bytes > MTX_MAX_FILE) return mpgm_err_too_large(r->ctx, r->path, MTX_MAX_FILE);
    if ((size_t)len != strlen(r->line)) {
      r->line[0] = '\0';
      MPGM_ERROR(r->ctx, MPGM_ERR_INPUT,
                 "%s: line %ld: expected text, found a NUL byte (binary file?)", r->path,
                 r->lineno);
    }
    char *e = r->line + len;
    while (e > r->line && (e[-1] == '\n' || e[-1] == '\r')) *--e = '\0';
    if (!skip) return 0;
    const char *p = r->line + strspn(r->line, " \t");
    if (*p != '\0' && *p != '%') return 0;
  }
}

/* Parse a decimal integer in [lo, hi] at *p (leading blanks skipped);
 * advances *p. Returns 0 or -1. */
static int parse_long(const char **p, long lo, long hi, long *out) {
  char *end;
  errno = 0;
  const long v = strtol(*p, &end, 10);
  if (end == *p || errno || v < lo || v > hi || (*end != '\0' && *end != ' ' && *end != '\t'))
    return -1;
  *p = end;
  *out = v;
  return 0;
}

/* Parse a finite double at *p; advances *p. Returns 0 or -1. */
static int parse_double(const char **p, double *out) {
  char *end;
  errno = 0;
  const double v = strtod(*p, &end);
  if (end == *p || !isfinite(v) || (*end != '\0' && *end != ' ' && *end != '\t')) return -1;
  *p = end;
  *out = v;
  return 0;
}

/* Only blanks left at p. */
static int at_end(const char *p) {
  return p[strspn(p, " \t")] == '\0';
}

/* The banner "%%MatrixMarket matrix FORMAT real|integer SYMMETRY" with
 * FORMAT = format; *sym = 1 for "symmetric" (accepted when allow_sym). */
static int read_banner(reader *r, const char *format, int allow_sym, int *sym) {
  MPGM_CALL(next_line(r, 0));
  char want[160];
  snprintf(want, sizeof want, "the banner '%%%%MatrixMarket matrix %s real %s'", format,
           allow_sym ? "general|symmetric" : "general");
  if (!r->line) return bad(r, want);
  char t[6][32];
  const int nt =
      sscanf(r->line, "%31s %31s %31s %31s %31s %31s", t[0], t[1], t[2], t[3], t[4], t[5]);
  if (nt != 5 || strcasecmp(t[0], "%%MatrixMarket") != 0 || strcasecmp(t[1], "matrix") != 0 ||
      strcasecmp(t[2], format) != 0)
    return bad(r, want);
  if (strcasecmp(t[3], "real") != 0 && strcasecmp(t[3], "integer") != 0)
    return bad(
        r, "a banner with real or integer values (pattern and complex files are not supported)");
  *sym = 0;
  if (allow_sym && strcasecmp(t[4], "symmetric") == 0)
    *sym = 1;
  else if (strcasecmp(t[4], "general") != 0)
    return bad(r, allow_sym ? "a banner with symmetry general or symmetric"
                            : "a banner with symmetry general");
  return 0;
}

/* Grow an array of `size`-byte items to hold at least need (doubling,
 * capped at most). Returns 0 or -1 (no memory). */
static int grow(void **a, long *cap, long need, long most, size_t size) {
  if (need <= *cap) return 0;
  long c = *cap ? *cap : 1024;
  while (c < need) c *= 2;
  if (c > most) c = most;
  void *b = realloc(*a, (size_t)c * size);
  if (!b) return -1;
  *a = b;
  *cap = c;
  return 0;
}

/* Entries of a coordinate file: the triplets (0-based) into ri, ci, v. */
typedef struct triplets {
  int *ri, *ci;
  double *v;
  long n, cap;
} triplets;

static int read_coordinate(reader *r, int *n_out, int *sym, triplets *T) {
  MPGM_CALL(read_banner(r, "coordinate", 1, sym));
  MPGM_CALL(next_line(r, 1));
  const char *size =
      "the size line 'ROWS COLUMNS ENTRIES' (integers, ROWS and COLUMNS >= 1, ENTRIES >= 0)";
  if (!r->line) return bad(r, size);
  const char *p = r->line;
  long m, n, nz;
  if (parse_long(&p, 1, INT_MAX, &m) || parse_long(&p, 1, INT_MAX, &n) ||
      parse_long(&p, 0, LONG_MAX, &nz) || !at_end(p))
    return bad(r, size);
  if (m != n) return bad(r, "a square matrix (ROWS = COLUMNS)");
  const double most = *sym ? 0.5 * (double)n * (n + 1) : (double)n * n;
  if ((double)nz > most || (*sym ? 2.0 : 1.0) * nz > INT_MAX) {
    char w[160];
    snprintf(w, sizeof w, "at most %.0f entries (%s n x n matrix, int indices)",
             fmin(most, INT_MAX), *sym ? "lower triangle of a symmetric" : "an");
    return bad(r, w);
  }
  for (long k = 0; k < nz; k++) {
    MPGM_CALL(next_line(r, 1));
    char w[200];
    if (!r->line) {
      snprintf(w, sizeof w, "entry %ld of the %ld the size line announces", k + 1, nz);
      return bad(r, w);
    }
    p = r->line;
    long i, j;
    double v;
    if (parse_long(&p, 1, n, &i) || parse_long(&p, 1, n, &j) || parse_double(&p, &v) ||
        !at_end(p)) {
      snprintf(w, sizeof w,
               "an entry 'ROW COLUMN VALUE' with ROW and COLUMN in [1, %ld] and a finite VALUE", n);
      return bad(r, w);
    }
    if (*sym && i < j)
      return bad(r, "an entry on or below the diagonal (ROW >= COLUMN) of a symmetric file");
    if (k == T->cap) { /* the three arrays grow together */
      long c1 = T->cap, c2 = T->cap;
      if (grow((void **)&T->ri, &c1, k + 1, nz, sizeof(int)) ||
          grow((void **)&T->ci, &c2, k + 1, nz, sizeof(int)) ||
          grow((void **)&T->v, &T->cap, k + 1, nz, sizeof(double)))
        MPGM_ERROR(r->ctx, MPGM_ERR_NOMEM, "%s: out of memory at entry %ld", r->path, k + 1);
    }
    T->ri[k] = (int)i - 1;
    T->ci[k] = (int)j - 1;
    T->v[k] = v;
    T->n = k + 1;
  }
  MPGM_CALL(next_line(r, 1));
  if (r->line) {
    char w[120];
    snprintf(w, sizeof w, "the end of the file after the %ld entries of the size line", nz);
    return bad(r, w);
  }
  *n_out = (int)n;
  return 0;
}

/* Compressed columns of the triplets (mirrored when sym), rows sorted,
 * duplicates summed. */
static int build_csc(mpgm_ctx *ctx, const char *path, int n, int sym, const triplets *T,
                     mpgm_csc *A) {
  long total = 0;
  for (long k = 0; k < T->n; k++) total += 1 + (sym && T->ri[k] != T->ci[k]);
  int *cnt = calloc((size_t)n + 1, sizeof(int)),
      *rr = malloc((size_t)(total ? total : 1) * sizeof(int));
  int *cc = malloc((size_t)(total ? total : 1) * sizeof(int));
  double *vv = malloc((size_t)(total ? total : 1) * sizeof(double));
  A->colptr = calloc((size_t)n + 1, sizeof(int));
  A->rowind = malloc((size_t)(total ? total : 1) * sizeof(int));
  A->val = malloc((size_t)(total ? total : 1) * sizeof(double));
  int err = 0;
  if (!cnt || !rr || !cc || !vv || !A->colptr || !A->rowind || !A->val) {
    err = mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "%s: out of memory (%ld entries)",
                       path, total);
    goto done;
  }
  /* bucket by row, then (stably) by column: rows end up sorted per column */
  for (long k = 0; k < T->n; k++) {
    cnt[T->ri[k] + 1]++;
    if (sym && T->ri[k] != T->ci[k]) cnt[T->ci[k] + 1]++;
  }
  for (int i = 0; i < n; i++) cnt[i + 1] += cnt[i];
  for (long k = 0; k < T->n; k++) {
    int q = cnt[T->ri[k]]++;
    rr[q] = T->ri[k], cc[q] = T->ci[k], vv[q] = T->v[k];
    if (sym && T->ri[k] != T->ci[k]) {
      q = cnt[T->ci[k]]++;
      rr[q] = T->ci[k], cc[q] = T->ri[k], vv[q] = T->v[k];
    }
  }
  int *cp = A->colptr;
  for (long q = 0; q < total; q++) cp[cc[q] + 1]++;
  for (int j = 0; j < n; j++) cp[j + 1] += cp[j];
  memcpy(cnt, cp, (size_t)n * sizeof(int));
  for (long q = 0; q < total; q++) {
    const int d = cnt[cc[q]]++;
    A->rowind[d] = rr[q];
    A->val[d] = vv[q];
  }
  /* sum duplicates (adjacent now), compacting the columns in place */
  int w = 0;
  for (int j = 0; j < n; j++) {
    const int start = w, lo = cp[j], hi = cp[j + 1];
    for (int p = lo; p < hi; p++) {
      if (w > start && A->rowind[w - 1] == A->rowind[p]) {
        A->val[w - 1] += A->val[p];
      } else {
        A->rowind[w] = A->rowind[p];
        A->val[w++] = A->val[p];
      }
    }
    cp[j] = start;
  }
  cp[n] = w;
  A->n = n;
  A->nnz = w;
  A->symmetric = mpgm_csc_is_symmetric(A);
done:
  free(cnt);
  free(rr);
  free(cc);
  free(vv);
  return err;
}

int mpgm_mtx_read_csc(mpgm_ctx *ctx, const char *path, mpgm_csc *A) {
  memset(A, 0, sizeof *A);
  reader r = {.ctx = ctx, .path = path};
  MPGM_CALL(mpgm_fopen_regular(ctx, path, MTX_MAX_FILE, &r.f, NULL));
  triplets T = {0};
  int n = 0, sym = 0;
  int err = read_coordinate(&r, &n, &sym, &T);
  fclose(r.f);
  free(r.line);
  if (!err) err = build_csc(ctx, path, n, sym, &T, A);
  free(T.ri);
  free(T.ci);
  free(T.v);
  if (err) mpgm_mtx_free_csc(A);
  return err;
}

static int read_array(reader *r, double **b, int *n_out) {
  int sym;
  MPGM_CALL(read_banner(r, "array", 0, &sym));
  MPGM_CALL(next_line(r, 1));
  const char *size = "the size line 'ROWS 1' (ROWS >= 1: a column vector)";
  if (!r->line) return bad(r, size);
  const char *p = r->line;
  long m, ncol;
  if (parse_long(&p, 1, INT_MAX, &m) || parse_long(&p, 1, INT_MAX, &ncol) || !at_end(p) ||
      ncol != 1)
    return bad(r, size);
  long cap = 0;
  for (long k = 0; k < m; k++) {
    MPGM_CALL(next_line(r, 1));
    char w[120];
    if (!r->line) {
      snprintf(w, sizeof w, "value %ld of the %ld the size line announces", k + 1, m);
      return bad(r, w);
    }
    p = r->line;
    double v;
    if (parse_double(&p, &v) || !at_end(p)) return bad(r, "one finite value on the line");
    if (grow((void **)b, &cap, k + 1, m, sizeof(double)))
      MPGM_ERROR(r->ctx, MPGM_ERR_NOMEM, "%s: out of memory at value %ld", r->path, k + 1);
    (*b)[k] = v;
  }
  MPGM_CALL(next_line(r, 1));
  if (r->line) {
    char w[120];
    snprintf(w, sizeof w, "the end of the file after the %ld values of the size line", m);
    return bad(r, w);
  }
  *n_out = (int)m;
  return 0;
}

int mpgm_mtx_read_vec(mpgm_ctx *ctx, const char *path, double **b, int *n) {
  *b = NULL;
  *n = 0;
  reader r = {.ctx = ctx, .path = path};
  MPGM_CALL(mpgm_fopen_regular(ctx, path, MTX_MAX_FILE, &r.f, NULL));
  int err = read_array(&r, b, n);
  fclose(r.f);
  free(r.line);
  if (err) {
    free(*b);
    *b = NULL;
    *n = 0;
  }
  return err;
}

void mpgm_mtx_free_csc(mpgm_csc *A) {
  if (!A) return;
  free(A->colptr);
  free(A->rowind);
  free(A->val);
  memset(A, 0, sizeof *A);
}
