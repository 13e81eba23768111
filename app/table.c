/* table.c -- text tables and their CSV form (table.h). */
#define _POSIX_C_SOURCE 200809L
#include "table.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_file.h"

/* The largest CSV read (a study.csv of ten thousand runs and two hundred
 * columns is about 40 MiB). */
#define TABLE_MAX_FILE ((size_t)1 << 30)

void mpgm_format_double(double v, char *buf, size_t cap) {
  if (v == floor(v) && fabs(v) < 1e15) { /* whole numbers as such: 640, not 6.4e+02 */
    snprintf(buf, cap, "%.0f", v);
    return;
  }
  for (int p = 1; p <= 17; p++) {
    snprintf(buf, cap, "%.*g", p, v);
    if (strtod(buf, NULL) == v) return;
  }
}

int mpgm_table_col(mpgm_table *t, const char *name, int create) {
  for (int c = 0; c < t->ncol; c++)
    if (strcmp(t->head[c], name) == 0) return c;
  if (!create) return -1;
  if (t->ncol == t->capcol) {
    const int cap = t->capcol ? 2 * t->capcol : 16;
    char **h = realloc(t->head, sizeof *h * (size_t)cap);
    if (!h) return -1;
    t->head = h;
    for (int r = 0; r < t->nrow; r++) {
      char **row = realloc(t->row[r], sizeof *row * (size_t)cap);
      if (!row) return -1;
      memset(row + t->capcol, 0, sizeof *row * (size_t)(cap - t->capcol));
      t->row[r] = row;
    }
    t->capcol = cap;
  }
  char *dup = strdup(name);
  if (!dup) return -1;
  t->head[t->ncol] = dup;
  return t->ncol++;
}

int mpgm_table_add_row(mpgm_table *t) {
  if (t->nrow == t->caprow) {
    const int cap = t->caprow ? 2 * t->caprow : 16;
    char ***r = realloc(t->row, sizeof *r * (size_t)cap);
    if (!r) return -1;
    t->row = r;
    t->caprow = cap;
  }
  char **row = calloc(t->capcol ? (size_t)t->capcol : 1, sizeof *row);
  if (!row) return -1;
  t->row[t->nrow] = row;
  return t->nrow++;
}

int mpgm_table_set(mpgm_table *t, int row, int col, const char *value) {
  if (row < 0 || row >= t->nrow || col < 0 || col >= t->ncol) return MPGM_ERR_NOMEM;
  free(t->row[row][col]);
  t->row[row][col] = NULL;
  if (value && *value && !(t->row[row][col] = strdup(value))) return MPGM_ERR_NOMEM;
  return 0;
}

int mpgm_table_set_named(mpgm_table *t, int row, const char *name, const char *value) {
  return mpgm_table_set(t, row, mpgm_table_col(t, name, 1), value);
}

const char *mpgm_table_get(const mpgm_table *t, int row, int col) {
  if (row < 0 || row >= t->nrow || col < 0 || col >= t->ncol || !t->row[row][col]) return "";
  return t->row[row][col];
}

int mpgm_table_num(const mpgm_table *t, int row, int col, double *v) {
  const char *s = mpgm_table_get(t, row, col);
  char *end;
  if (!*s) return 0;
  errno = 0;
  *v = strtod(s, &end);
  return *end == '\0' && isfinite(*v);
}

static void put_cell(FILE *f, const char *s) {
  if (!strpbrk(s, ",\"\r\n")) {
    fputs(s, f);
    return;
  }
  fputc('"', f);
  for (; *s; s++) {
    if (*s == '"') fputc('"', f);
    fputc(*s, f);
  }
  fputc('"', f);
}

int mpgm_table_write(mpgm_ctx *ctx, const mpgm_table *t, const char *path) {
  void *fv;
  MPGM_CALL(mpgm_atomic_open(ctx, path, &fv));
  FILE *f = fv;
  for (int c = 0; c < t->ncol; c++) {
    if (c) fputc(',', f);
    put_cell(f, t->head[c]);
  }
  fputc('\n', f);
  for (int r = 0; r < t->nrow; r++) {
    for (int c = 0; c < t->ncol; c++) {
      if (c) fputc(',', f);
      put_cell(f, mpgm_table_get(t, r, c));
    }
    fputc('\n', f);
  }
  return mpgm_atomic_close(ctx, path, f);
}

/* One CSV record from *p into cells (each a new string); *p moves past it.
 * Returns the cell count, -1 on a quote left open, -2 out of memory. */
static int parse_record(const char **p, char ***cells, int *cap) {
  const char *s = *p;
  int n = 0;
  for (;;) {
    size_t len = 0, room = 64;
    char *cell = malloc(room);
    if (!cell) return -2;
    int quoted = *s == '"';
    if (quoted) s++;
    for (;;) {
      char c = *s;
      if (quoted) {
        if (c == '\0') {
          free(cell);
          return -1;
        }
        if (c == '"') {
          if (s[1] == '"') s++;
          else {
            quoted = 0;
            s++;
            continue;
          }
        }
      } else if (c == ',' || c == '\n' || c == '\r' || c == '\0') {
        break;
      }
      if (len + 2 > room) {
        char *nc = realloc(cell, room *= 2);
        if (!nc) {
          free(cell);
          return -2;
        }
        cell = nc;
      }
      cell[len++] = c;
      s++;
    }
    cell[len] = '\0';
    if (n == *cap) {
      const int c2 = *cap ? 2 * *cap : 32;
      char **nc = realloc(*cells, sizeof *nc * (size_t)c2);
      if (!nc) {
        free(cell);
        return -2;
      }
      *cells = nc;
      *cap = c2;
    }
    (*cells)[n++] = cell;
    if (*s == ',') {
      s++;
      continue;
    }
    if (*s == '\r') s++;
    if (*s == '\n') s++;
    *p = s;
    return n;
  }
}

int mpgm_table_read(mpgm_ctx *ctx, const char *path, mpgm_table *t) {
  memset(t, 0, sizeof *t);
  char *text;
  size_t n;
  MPGM_CALL(mpgm_read_file(ctx, path, TABLE_MAX_FILE, &text, &n));
  int err = 0;
  if (!err && n == 0) err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: empty file", path);
  const char *p = text;
  char **cells = NULL;
  int ccap = 0;
  for (int line = 1; !err && *p; line++) {
    const int nc = parse_record(&p, &cells, &ccap);
    if (nc < 0) {
      err = nc == -1 ? mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                                    "%s: record %d: a quoted cell is not closed", path, line)
                     : mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "%s: out of memory", path);
      break;
    }
    if (line == 1) {
      for (int c = 0; c < nc && !err; c++) {
        if (mpgm_table_col(t, cells[c], 0) >= 0)
          err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: column \"%s\" appears twice",
                             path, cells[c]);
        else if (mpgm_table_col(t, cells[c], 1) < 0)
          err = mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "%s: out of memory", path);
      }
    } else if (!(nc == 1 && !cells[0][0])) { /* a blank line is no row */
      if (nc > t->ncol) {
        err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                           "%s: record %d has %d cells, the header %d", path, line, nc, t->ncol);
      } else {
        const int r = mpgm_table_add_row(t);
        for (int c = 0; c < nc && !err; c++)
          if (r < 0 || mpgm_table_set(t, r, c, cells[c]))
            err = mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "%s: out of memory", path);
      }
    }
    for (int c = 0; c < nc; c++) free(cells[c]);
  }
  free(cells);
  free(text);
  if (err) mpgm_table_free(t);
  return err;
}

void mpgm_table_free(mpgm_table *t) {
  for (int r = 0; r < t->nrow; r++) {
    for (int c = 0; c < t->ncol; c++) free(t->row[r][c]);
    free(t->row[r]);
  }
  for (int c = 0; c < t->ncol; c++) free(t->head[c]);
  free(t->row);
  free(t->head);
  memset(t, 0, sizeof *t);
}
