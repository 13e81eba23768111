/* plot.c -- `mpgm plot STUDY.csv`: the error against the refined key
 * (mesh.h; log-log with slope-1 and slope-2 guides, the paper's Fig. 7)
 * and the error against wall time (the accuracy-cost front, one series per
 * method and shape function, Pareto-optimal runs marked), drawn by gnuplot
 * to PNG and SVG next to the CSV, with the gnuplot script beside them
 * (docs/studies.md).
 *
 * The columns of study.csv before "status" are the run keys; the completed
 * rows are plotted. Settings come from the command line, else from
 * study.json in the CSV's folder (written by `mpgm study`), else defaults.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gnuplot.h"
#include "mpgm_json_reader.h"
#include "mpgm_output.h"
#include "mpgm_vtk.h"
#include "study.h"
#include "units.h"

enum { MAX_SERIES = 64 };

typedef struct point {
  double x, err;
  int row, series, pareto;
} point;

typedef struct plot_ctx {
  mpgm_table t;
  int nkeycol;                    /**< columns before "status"         */
  int metric, time, xcol;         /**< columns (xcol -1: none)          */
  int nsk, sk[STUDY_MAX_KEYS];    /**< series key columns               */
  int nser;
  int ser_row[MAX_SERIES];        /**< first row of each series         */
  char label[MAX_SERIES][160];
  char dir[STUDY_PATH];           /**< folder of the pictures           */
  char name[STUDY_NAME];          /**< the study's name (title)         */
  char xshort[64];                /**< last part of the x key ("h")     */
  int xlog, ylog, ysigned;        /**< axes of the key plot (--xscale, --yscale) */
  int metric_default;             /**< the metric is the study's error (titles say "error") */
} plot_ctx;

/* Settings from study.json beside the CSV (absent: all stay NULL). */
typedef struct saved {
  cJSON *doc;
  const char *metric, *x, *title, *name;
  const cJSON *series;
} saved;

static void read_saved(const char *dir, saved *s) {
  memset(s, 0, sizeof *s);
  char path[STUDY_PATH + 16];
  snprintf(path, sizeof path, "%s/study.json", dir);
  mpgm_ctx quiet;
  mpgm_ctx_init(&quiet);
  if (jr_parse_file(&quiet, path, &s->doc)) return;
  const cJSON *p = cJSON_GetObjectItemCaseSensitive(s->doc, "plot");
  s->metric = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(s->doc, "metric"));
  s->name = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(s->doc, "name"));
  s->x = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(p, "x"));
  s->title = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(p, "title"));
  s->series = cJSON_GetObjectItemCaseSensitive(p, "series");
}

/* The metric's column: NAME, else metrics.NAME. */
static int metric_column(mpgm_ctx *ctx, plot_ctx *p, const char *csv, const char *name) {
  char alt[160];
  snprintf(alt, sizeof alt, "metrics.%s", name);
  p->metric = mpgm_table_col(&p->t, name, 0);
  if (p->metric < 0) p->metric = mpgm_table_col(&p->t, alt, 0);
  if (p->metric >= 0) return 0;
  char list[600] = "";
  for (int c = 0; c < p->t.ncol; c++) {
    const char *h = p->t.head[c];
    if (strncmp(h, "metrics.", 8) && strncmp(h, "reference.", 10)) continue;
    size_t n = strlen(list);
    snprintf(list + n, sizeof list - n, "%s%s", n ? ", " : "", h);
  }
  MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: no metric \"%s\" (columns %s or %s); metrics in this file: %s", csv, name,
             name, alt, list[0] ? list : "none (no run completed?)");
}

/* Series key columns: the given list, else every run key whose value
 * varies over the completed rows, except x and the refinement keys. */
static int series_keys(mpgm_ctx *ctx, plot_ctx *p, const char *csv, const char *list, const cJSON *saved_list) {
  char buf[1024] = "";
  if (list) snprintf(buf, sizeof buf, "%s", list);
  for (const cJSON *c = list ? NULL : cJSON_IsArray(saved_list) ? saved_list->child : NULL; c; c = c->next) {
    const size_t n = strlen(buf);
    if (cJSON_IsString(c)) snprintf(buf + n, sizeof buf - n, "%s%s", n ? "," : "", c->valuestring);
  }
  if (list || cJSON_IsArray(saved_list)) {
    for (char *k = strtok(buf, ","); k && p->nsk < STUDY_MAX_KEYS; k = strtok(NULL, ",")) {
      const int c = mpgm_table_col(&p->t, k, 0);
      MPGM_CHECK(ctx, c >= 0 && c < p->nkeycol, MPGM_ERR_INPUT, "%s: series key \"%s\" is not a run key column",
                 csv, k);
      p->sk[p->nsk++] = c;
    }
    return 0;
  }
  for (int c = 0; c < p->nkeycol && p->nsk < STUDY_MAX_KEYS; c++) {
    const char *h = p->t.head[c];
    if (c == p->xcol || !strcmp(h, "mesh.h") || !strcmp(h, "time.dt")) continue;
    int varies = 0;
    const char *first = NULL;
    for (int r = 0; r < p->t.nrow; r++) {
      if (strcmp(mpgm_table_get(&p->t, r, p->nkeycol), "completed")) continue;
      const char *v = mpgm_table_get(&p->t, r, c);
      if (!first) first = v;
      else varies |= strcmp(first, v) != 0;
    }
    if (varies) p->sk[p->nsk++] = c;
  }
  return 0;
}

/* Series of row r (a new one when its key values are new); -1 if too many. */
static int series_of(plot_ctx *p, int r) {
  for (int s = 0; s < p->nser; s++) {
    int same = 1;
    for (int k = 0; k < p->nsk && same; k++)
      same = !strcmp(mpgm_table_get(&p->t, r, p->sk[k]), mpgm_table_get(&p->t, p->ser_row[s], p->sk[k]));
    if (same) return s;
  }
  if (p->nser == MAX_SERIES) return -1;
  p->ser_row[p->nser] = r;
  return p->nser++;
}

/* Labels: "GMM-LME gamma=1.8" from the summary's method and shape and the
 * other series keys; "key=value ..." when those do not tell them apart. */
static void make_labels(plot_ctx *p) {
  int cm = mpgm_table_col(&p->t, "summary.method", 0); /* "method" when it is no run key */
  if (cm < 0) cm = mpgm_table_col(&p->t, "method", 0);
  const int cs = mpgm_table_col(&p->t, "shape", 0);
  for (int pass = 0; pass < 2; pass++) {
    for (int s = 0; s < p->nser; s++) {
      const int r = p->ser_row[s];
      char *l = p->label[s];
      size_t n = 0;
      l[0] = '\0';
      if (pass == 0 && cm >= 0 && cs >= 0) {
        const char *m = mpgm_table_get(&p->t, r, cm), *sh = mpgm_table_get(&p->t, r, cs);
        for (const char *c = m; *c && n + 2 < sizeof p->label[s]; c++) l[n++] = (char)(*c >= 'a' && *c <= 'z' ? *c - 32 : *c);
        if (strcmp(sh, "fe") && n + 2 < sizeof p->label[s]) l[n++] = '-';
        for (const char *c = strcmp(sh, "fe") ? sh : ""; *c && n + 2 < sizeof p->label[s]; c++)
          l[n++] = (char)(*c >= 'a' && *c <= 'z' ? *c - 32 : *c);
        l[n] = '\0';
      }
      for (int k = 0; k < p->nsk; k++) {
        const char *key = p->t.head[p->sk[k]], *v = mpgm_table_get(&p->t, r, p->sk[k]);
        if (pass == 0 && n && (!strcmp(key, "method") || !strcmp(key, "shape.kind") || !strcmp(key, "scene")))
          continue;
        if (!*v) continue;
        const char *shortk = pass == 0 && strrchr(key, '.') ? strrchr(key, '.') + 1 : key;
        n += (size_t)snprintf(l + n, sizeof p->label[s] - n, "%s%s=%s", n ? " " : "", shortk, v);
        if (n >= sizeof p->label[s]) n = sizeof p->label[s] - 1;
      }
      if (!l[0]) snprintf(l, sizeof p->label[s], "all runs");
    }
    int unique = 1;
    for (int a = 0; a < p->nser; a++)
      for (int b = a + 1; b < p->nser; b++) unique &= strcmp(p->label[a], p->label[b]) != 0;
    if (unique) return;
  }
}

static int by_x_desc(const void *a, const void *b) {
  const point *p = a, *q = b;
  if (p->series != q->series) return p->series - q->series;
  return (p->x < q->x) - (p->x > q->x);
}

static int by_x_asc(const void *a, const void *b) {
  const point *p = a, *q = b;
  if (p->series != q->series) return p->series - q->series;
  return (p->x > q->x) - (p->x < q->x);
}

static int by_time(const void *a, const void *b) {
  const point *p = a, *q = b;
  if (p->x != q->x) return (p->x > q->x) - (p->x < q->x);
  return (p->err > q->err) - (p->err < q->err);
}

/* The completed rows with a finite error and x (column xc), positive
 * where its axis is logarithmic. */
static int collect(plot_ctx *p, int xc, point *pts, int xlog, int ylog) {
  int n = 0;
  for (int r = 0; r < p->t.nrow; r++) {
    double x, e;
    if (strcmp(mpgm_table_get(&p->t, r, p->nkeycol), "completed")) continue;
    if (!mpgm_table_num(&p->t, r, xc, &x) || !mpgm_table_num(&p->t, r, p->metric, &e) || !isfinite(x) ||
        !isfinite(e) || (xlog && !(x > 0)) || (ylog && !(e > 0)))
      continue;
    const int s = series_of(p, r);
    if (s < 0) continue;
    pts[n++] = (point){x, e, r, s, 0};
  }
  return n;
}

/* Tics of a log axis over [lo, hi]: powers of ten (10^n labels) when it
 * spans 3 decades or more, else also 2 and 5 times them, labelled %g. */
static void log_tics(FILE *f, char axis, double lo, double hi, int powers) {
  if (!(lo > 0) || !(hi >= lo)) return;
  if (log10(hi / lo) >= 3.0) {
    if (powers) fprintf(f, "set format %c '10^{%%L}'\n", axis);
    return;
  }
  fprintf(f, "set format %c '%%g'\nset %ctics add (", axis, axis);
  int k = 0;
  for (double d = pow(10.0, floor(log10(lo))); d <= hi * 1.0001; d *= 10.0)
    for (int m = 1; m <= 5; m += m == 1 ? 1 : 3) /* 1, 2, 5 */
      if (m * d >= lo * 0.9999 && m * d <= hi * 1.0001) fprintf(f, "%s%.3g", k++ ? ", " : "", m * d);
  fprintf(f, ")\n");
}

/* Error range of the points. */
static void err_range(const point *pts, int n, double *lo, double *hi) {
  *lo = INFINITY;
  *hi = -INFINITY;
  for (int i = 0; i < n; i++) {
    *lo = fmin(*lo, pts[i].err);
    *hi = fmax(*hi, pts[i].err);
  }
}

/* The common head of both plots. */
static void script_head(FILE *f, const char *title, const char *xlabel, const char *ylabel, int xlog, int ylog) {
  fprintf(f, "set encoding utf8\n%s%s", xlog ? "set logscale x\n" : "", ylog ? "set logscale y\n" : "");
  fprintf(f, "set grid xtics ytics mxtics mytics lc rgb '#dddddd'\n"
             "set key inside top right spacing 1.2 box opaque\nset title ");
  mpgm_gnuplot_quote(f, title);
  fprintf(f, " noenhanced\nset xlabel ");
  mpgm_gnuplot_quote(f, xlabel);
  fprintf(f, " noenhanced\nset ylabel ");
  mpgm_gnuplot_quote(f, ylabel);
  fprintf(f, " noenhanced\n");
}

/* Datablock $sN per series; x and error, in the order given. */
static void script_data(FILE *f, const point *pts, int n, int nser) {
  for (int s = 0; s < nser; s++) {
    fprintf(f, "$s%d << EOD\n", s);
    for (int i = 0; i < n; i++)
      if (pts[i].series == s) fprintf(f, "%.17g %.17g\n", pts[i].x, pts[i].err);
    fprintf(f, "EOD\n");
  }
}

/* The plot command's series, with a trailing ", \" when more follows. */
static void script_series(FILE *f, const plot_ctx *p, const point *pts, int n, int more) {
  int first = 1;
  for (int s = 0; s < p->nser; s++) {
    int has = 0;
    for (int i = 0; i < n; i++) has |= pts[i].series == s;
    if (!has) continue;
    static const char *const colour[] = {"#0072b2", "#d55e00", "#009e73", "#cc79a7",
                                         "#e69f00", "#56b4e9", "#000000", "#8c564b"};
    /* points shrink from series to series: coinciding curves stay visible */
    fprintf(f, "%s$s%d using 1:2 with linespoints lc rgb '%s' pt %d ps %.1f lw 1.6 title ",
            first ? "plot " : ", \\\n     ", s, colour[s % 8], (int[]){7, 5, 9, 11, 13, 4, 6, 8}[s % 8],
            2.0 - 0.3 * (s % 4));
    mpgm_gnuplot_quote(f, p->label[s]);
    fprintf(f, " noenhanced");
    first = 0;
  }
  if (more) fprintf(f, ", \\\n     ");
}

/* Run the script (in p->dir) for PNG and SVG, keep it as NAME.gp. */
static int draw(mpgm_ctx *ctx, const plot_ctx *p, const char *name, const char *body, size_t len) {
  char path[STUDY_PATH + 80];
  snprintf(path, sizeof path, "%s/%s.gp", p->dir, name);
  void *fv;
  MPGM_CALL(mpgm_atomic_open(ctx, path, &fv));
  fprintf(fv, "# %s: drawn by `mpgm plot`; redraw in this folder with `gnuplot %s.gp`\n", name, name);
  fprintf(fv, "set terminal pngcairo size 960,640 enhanced font ',11'\nset output '%s.png'\n", name);
  fwrite(body, 1, len, fv);
  fprintf(fv, "set terminal svg size 960,640 enhanced dynamic font 'Arial,11'\nset output '%s.svg'\nreplot\n"
              "unset output\n", name);
  MPGM_CALL(mpgm_atomic_close(ctx, path, fv));
  for (int ext = 0; ext < 2; ext++) { /* gnuplot must not wait on a FIFO there */
    char pic[STUDY_PATH + 80];
    snprintf(pic, sizeof pic, "%s/%s.%s", p->dir, name, ext ? "svg" : "png");
    MPGM_CALL(mpgm_output_regular(ctx, pic));
  }
  FILE *in;
  MPGM_CALL(mpgm_fopen_regular(ctx, path, (size_t)1 << 30, &in, NULL));
  mpgm_gnuplot g;
  int err = mpgm_gnuplot_open(ctx, &g, p->dir);
  char buf[1 << 14];
  size_t k;
  while (!err && (k = fread(buf, 1, sizeof buf, in)) > 0)
    if (fwrite(buf, 1, k, g.in) != k) break;
  fclose(in);
  if (!err) err = mpgm_gnuplot_close(ctx, &g);
  for (int ext = 0; ext < 2 && !err; ext++) {
    snprintf(path, sizeof path, "%s/%s.%s", p->dir, name, ext ? "svg" : "png");
    err = mpgm_file_nonempty(ctx, path);
  }
  if (!err) printf("plot: %s/%s.png, .svg\n", p->dir, name);
  return err;
}

/* Error against the refined key, with slope-1 and slope-2 guides from a
 * common point at the finest value, half the smallest error there (so a
 * series converging at least as fast stays above them); observed orders
 * printed. */
static int plot_convergence(mpgm_ctx *ctx, plot_ctx *p, point *pts, const char *ylabel, const char *title) {
  const int n = collect(p, p->xcol, pts, p->xlog, p->ylog);
  const int loglog = p->xlog && p->ylog; /* slope guides and observed orders */
  if (n == 0) {
    printf("plot: no completed run with a positive %s and %s: no error-against-%s plot\n", p->t.head[p->metric],
           p->t.head[p->xcol], p->t.head[p->xcol]);
    return 0; /* plot_main says when neither plot is drawn */
  }
  qsort(pts, (size_t)n, sizeof *pts, by_x_desc);
  double xmin = INFINITY, xmax = -INFINITY, a = INFINITY;
  for (int i = 0; i < n; i++) {
    xmin = fmin(xmin, pts[i].x);
    xmax = fmax(xmax, pts[i].x);
  }
  for (int i = 0; i < n; i++)
    if (pts[i].x == xmin) a = fmin(a, 0.5 * pts[i].err);
  char *body = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&body, &len);
  MPGM_CHECK(ctx, f, MPGM_ERR_NOMEM, "out of memory (plot)");
  char t[STUDY_NAME + 128], xl[STUDY_NAME + 64];
  snprintf(t, sizeof t, "%s: %s against %s", title, p->metric_default ? "error" : p->t.head[p->metric],
           p->t.head[p->xcol]);
  const char *xu = mpgm_column_unit(p->t.head[p->xcol]);
  snprintf(xl, sizeof xl, "%s%s%s%s (refined to the right)", p->t.head[p->xcol], xu ? " [" : "", xu ? xu : "",
           xu ? "]" : "");
  script_head(f, t, xl, ylabel, p->xlog, p->ylog);
  double lo, hi;
  err_range(pts, n, &lo, &hi);
  if (p->ylog) log_tics(f, 'y', loglog ? 0.5 * a : lo, hi, 1);
  if (p->ysigned) fprintf(f, "set xzeroaxis lt -1 lw 1\n"); /* the line y = 0 */
  const double pad = xmax > xmin ? 0.08 * (xmax - xmin) : fmax(0.5 * fabs(xmax), 1e-300);
  if (p->xlog && xmax > xmin) fprintf(f, "set xrange [%.17g:%.17g]\n", xmax * 1.25, xmin / 1.25);
  else if (p->xlog) fprintf(f, "set xrange [%.17g:%.17g]\n", xmax * 2, xmax / 2);
  else fprintf(f, "set xrange [%.17g:%.17g]\n", xmax + pad, xmin - pad);
  fprintf(f, "set xtics ("); /* a tic at every value of the key (at most 16) */
  for (int i = 0, k = 0; i < n && k < 16; i++) {
    int seen = 0;
    for (int j = 0; j < i; j++) seen |= pts[j].x == pts[i].x;
    if (!seen) fprintf(f, "%s'%g' %.17g", k++ ? ", " : "", pts[i].x, pts[i].x);
  }
  fprintf(f, ")\n");
  script_data(f, pts, n, p->nser);
  fprintf(f, "$g1 << EOD\n%.17g %.17g\n%.17g %.17g\nEOD\n", xmin, a, xmax, a * xmax / xmin);
  fprintf(f, "$g2 << EOD\n%.17g %.17g\n%.17g %.17g\nEOD\n", xmin, a, xmax, a * (xmax / xmin) * (xmax / xmin));
  script_series(f, p, pts, n, loglog);
  if (loglog)
    fprintf(f, "$g1 using 1:2 with lines dt 2 lw 1.2 lc rgb '#555555' title 'slope 1', \\\n"
               "     $g2 using 1:2 with lines dt 4 lw 1.2 lc rgb '#555555' title 'slope 2'\n");
  else fprintf(f, "\n");
  fclose(f);
  char name[96];
  snprintf(name, sizeof name, "study_error_%s", p->xshort);
  int err = draw(ctx, p, name, body, len);
  free(body);
  for (int s = 0; !err && loglog && s < p->nser; s++) { /* observed orders, coarse to fine */
    int first = 1;
    for (int i = 0; i + 1 < n; i++) {
      if (pts[i].series != s || pts[i + 1].series != s || !(pts[i].x > pts[i + 1].x)) continue;
      if (first) printf("  observed order, %s:", p->label[s]);
      printf(" %.2f", log(pts[i].err / pts[i + 1].err) / log(pts[i].x / pts[i + 1].x));
      first = 0;
    }
    if (!first) printf("\n");
  }
  return err;
}

/* Error against wall time; a run is Pareto-optimal when no other run is
 * both faster and more accurate (strictly). */
static int plot_cost(mpgm_ctx *ctx, plot_ctx *p, point *pts, const char *ylabel, const char *title) {
  const int n = collect(p, p->time, pts, 1, 1);
  if (n == 0) {
    printf("plot: no completed run with a positive %s and wall time: no error-against-time plot\n",
           p->t.head[p->metric]);
    return 0;
  }
  qsort(pts, (size_t)n, sizeof *pts, by_x_asc);
  int nfront = 0;
  for (int i = 0; i < n; i++) {
    pts[i].pareto = 1;
    for (int j = 0; j < n && pts[i].pareto; j++)
      if (pts[j].x < pts[i].x && pts[j].err < pts[i].err) pts[i].pareto = 0;
    nfront += pts[i].pareto;
  }
  char *body = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&body, &len);
  MPGM_CHECK(ctx, f, MPGM_ERR_NOMEM, "out of memory (plot)");
  char t[STUDY_NAME + 64];
  snprintf(t, sizeof t, "%s: accuracy against cost", title);
  script_head(f, t, "wall time of the run [s] (time_s.total)", ylabel, 1, 1);
  double lo, hi;
  err_range(pts, n, &lo, &hi);
  log_tics(f, 'y', lo, hi, 1);
  double tlo = INFINITY, thi = -INFINITY;
  for (int i = 0; i < n; i++) {
    tlo = fmin(tlo, pts[i].x);
    thi = fmax(thi, pts[i].x);
  }
  log_tics(f, 'x', tlo, thi, 0);
  fprintf(f, "set xrange [%.17g:%.17g]\n", tlo / 1.6, thi * 1.6); /* room for the circles */
  script_data(f, pts, n, p->nser);
  /* the front, fastest first: a staircase bounding the dominated region */
  fprintf(f, "$front << EOD\n");
  point *fr = malloc(sizeof *fr * (size_t)(n > 0 ? n : 1));
  int m = 0;
  for (int i = 0; fr && i < n; i++)
    if (pts[i].pareto) fr[m++] = pts[i];
  if (fr) qsort(fr, (size_t)m, sizeof *fr, by_time);
  for (int a = 0; a < m; a++) /* equal times: the most accurate only */
    if (a == 0 || fr[a].x > fr[a - 1].x) fprintf(f, "%.17g %.17g\n", fr[a].x, fr[a].err);
  free(fr);
  fprintf(f, "EOD\n");
  script_series(f, p, pts, n, 1);
  fprintf(f, "$front using 1:2 with steps dt 3 lw 1.2 lc rgb 'black' notitle, \\\n"
             "     $front using 1:2 with points pt 6 ps 2.6 lw 1.5 lc rgb 'black' "
             "title 'Pareto-optimal'\n");
  fclose(f);
  int err = draw(ctx, p, "study_error_time", body, len);
  free(body);
  if (!err) {
    printf("  Pareto-optimal runs (%d of %d):", nfront, n);
    for (int i = 0; i < n; i++)
      if (pts[i].pareto) printf(" %s (%.3g s, %.3g);", mpgm_table_get(&p->t, pts[i].row, mpgm_table_col(&p->t, "dir", 0)),
                                pts[i].x, pts[i].err);
    printf("\n");
  }
  return err;
}

static int plot_main(mpgm_ctx *ctx, plot_ctx *p, const char *csv, const mpgm_plot_opts *o, const saved *sv) {
  const char *xs = o->xscale ? o->xscale : "log", *ys = o->yscale ? o->yscale : "log";
  MPGM_CHECK(ctx, !strcmp(xs, "log") || !strcmp(xs, "linear"), MPGM_ERR_INPUT,
             "--xscale: expected linear or log, found '%s'", xs);
  MPGM_CHECK(ctx, !strcmp(ys, "log") || !strcmp(ys, "linear") || !strcmp(ys, "signed"), MPGM_ERR_INPUT,
             "--yscale: expected linear, log or signed, found '%s'", ys);
  p->xlog = !strcmp(xs, "log");
  p->ylog = !strcmp(ys, "log");
  p->ysigned = !strcmp(ys, "signed");
  MPGM_CALL(mpgm_table_read(ctx, csv, &p->t));
  p->nkeycol = mpgm_table_col(&p->t, "status", 0);
  MPGM_CHECK(ctx, p->nkeycol >= 0, MPGM_ERR_INPUT, "%s: not a study.csv (no \"status\" column)", csv);
  const char *metric = o->metric ? o->metric : sv->metric ? sv->metric : "error";
  p->metric_default = !o->metric;
  MPGM_CALL(metric_column(ctx, p, csv, metric));
  p->time = mpgm_table_col(&p->t, "time_s.total", 0);
  const char *x = o->x ? o->x : sv->x ? sv->x : "mesh.h";
  p->xcol = mpgm_table_col(&p->t, x, 0);
  if (p->xcol >= p->nkeycol && !o->x) p->xcol = -1; /* by default a run key; --x may name any column */
  MPGM_CHECK(ctx, p->xcol >= 0 || !o->x, MPGM_ERR_INPUT, "%s: --x %s: no such column", csv, x);
  snprintf(p->xshort, sizeof p->xshort, "%s", strrchr(x, '.') ? strrchr(x, '.') + 1 : x);
  MPGM_CALL(series_keys(ctx, p, csv, o->series, sv->series));
  const int ncomp = p->t.nrow;
  int done = 0;
  for (int r = 0; r < ncomp; r++) done += !strcmp(mpgm_table_get(&p->t, r, p->nkeycol), "completed");
  MPGM_CHECK(ctx, done > 0, MPGM_ERR_INPUT, "%s: no completed run: nothing to plot", csv);
  for (int r = 0; r < p->t.nrow; r++) /* series numbered in row order, whatever plots first */
    if (!strcmp(mpgm_table_get(&p->t, r, p->nkeycol), "completed")) series_of(p, r);
  make_labels(p);
  const char *title = o->title ? o->title : sv->title && sv->title[0] ? sv->title : sv->name ? sv->name : "study";
  char ylabel[200];
  const char *yu = mpgm_column_unit(p->t.head[p->metric]); /* an unknown metric: no unit */
  snprintf(ylabel, sizeof ylabel, "%s%s%s%s", p->t.head[p->metric], yu ? " [" : "", yu ? yu : "", yu ? "]" : "");
  printf("plot: %d completed run(s) of %d, %d series, metric %s\n", done, p->t.nrow, p->nser, ylabel);
  point *pts = malloc(sizeof *pts * (size_t)(p->t.nrow + 1));
  MPGM_CHECK(ctx, pts, MPGM_ERR_NOMEM, "out of memory (plot)");
  int err = 0;
  if (p->xcol >= 0 || p->time >= 0) { /* neither plot drawn: bad input, and why */
    int usable = 0;
    for (int pass = 0; pass < 2; pass++) {
      const int c = pass ? p->time : p->xcol;
      if (c >= 0) usable += pass ? collect(p, c, pts, 1, 1) : collect(p, c, pts, p->xlog, p->ylog);
    }
    if (!usable) {
      free(pts);
      MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: no completed run has a positive finite %s and %s: nothing to plot", csv,
                 p->t.head[p->metric], p->xcol >= 0 ? p->t.head[p->xcol] : "time_s.total");
    }
  } else {
    free(pts);
    MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: neither %s nor time_s.total is a column: nothing to plot", csv, x);
  }
  if (p->xcol >= 0) err = plot_convergence(ctx, p, pts, ylabel, title);
  else printf("plot: no %s column among the run keys: no error-against-%s plot\n", x, x);
  if (!err && p->time >= 0) err = plot_cost(ctx, p, pts, ylabel, title);
  else if (!err) printf("plot: no time_s.total column: no error-against-time plot\n");
  free(pts);
  return err;
}

void mpgm_plot_outputs(const char *dir, const char *x, char names[][STUDY_PATH + 96], mpgm_write_path *w) {
  const char *xshort = strrchr(x, '.') ? strrchr(x, '.') + 1 : x;
  static const char *const ext[] = {"gp", "png", "svg"};
  for (int k = 0; k < STUDY_PLOT_FILES; k++) {
    /* plot_ctx.xshort holds 63 characters */
    snprintf(names[k], STUDY_PATH + 96, "%s/study_error_%.63s.%s", dir, k < 3 ? xshort : "time", ext[k % 3]);
    w[k] = (mpgm_write_path){names[k], k % 3 ? MPGM_WRITE_FILE : MPGM_WRITE_ATOMIC};
  }
}

/* The pictures and scripts, and --out itself, must not replace the CSV or
 * the study.json they are drawn from. */
static int refuse_overwrite(mpgm_ctx *ctx, const char *dir, const mpgm_plot_opts *o, const char *x,
                            const char *csv, const char *csvdir) {
  char names[STUDY_PLOT_FILES][STUDY_PATH + 96], saved[STUDY_PATH + 16];
  mpgm_write_path w[STUDY_PLOT_FILES + 1];
  mpgm_plot_outputs(dir, x, names, w);
  w[STUDY_PLOT_FILES] = (mpgm_write_path){o->out, MPGM_WRITE_FILE};
  snprintf(saved, sizeof saved, "%s/study.json", csvdir);
  const char *in[] = {csv, saved};
  return mpgm_refuse_overwrite(ctx, w, STUDY_PLOT_FILES + 1, in, 2);
}

int mpgm_plot(mpgm_ctx *ctx, const char *csv, const mpgm_plot_opts *o) {
  MPGM_CALL(mpgm_gnuplot_check(ctx));
  plot_ctx *p = calloc(1, sizeof *p);
  MPGM_CHECK(ctx, p, MPGM_ERR_NOMEM, "out of memory (plot)");
  const char *slash = strrchr(csv, '/');
  char csvdir[STUDY_PATH];
  if (slash) snprintf(csvdir, sizeof csvdir, "%.*s", (int)(slash - csv), csv);
  else snprintf(csvdir, sizeof csvdir, ".");
  if (slash == csv) snprintf(csvdir, sizeof csvdir, "/");
  snprintf(p->dir, sizeof p->dir, "%s", o->out ? o->out : csvdir);
  saved sv;
  read_saved(csvdir, &sv);
  int err = refuse_overwrite(ctx, p->dir, o, o->x ? o->x : sv.x ? sv.x : "mesh.h", csv, csvdir);
  if (!err && o->out) err = mpgm_mkdir_p(ctx, o->out);
  if (!err) err = plot_main(ctx, p, csv, o, &sv);
  cJSON_Delete(sv.doc);
  mpgm_table_free(&p->t);
  free(p);
  return err;
}

static void usage_plot(FILE *f) {
  fprintf(f, "usage: mpgm plot STUDY.csv [--y|--metric NAME] [--x KEY] [--xscale linear|log]\n"
             "                 [--yscale linear|log|signed] [--series KEY,...] [--out DIR] [--title TEXT]\n"
             "  draws study_error_<x>.png/.svg (the metric NAME, default error, against the run key KEY,\n"
             "  default mesh.h) and study_error_time.png/.svg (the metric against wall time) next to\n"
             "  STUDY.csv; axes carry the units of known keys and metrics (docs/studies.md).\n"
             "  The key plot is log-log by default; signed: a linear y axis with a line at zero\n");
}

int mpgm_cmd_plot(int argc, char **argv) {
  mpgm_plot_opts o;
  memset(&o, 0, sizeof o);
  const char *csv = NULL;
  for (int i = 2; i < argc; i++) {
    static const char *const flags[] = {"--metric", "--x", "--series", "--out", "--title", "--xscale", "--yscale", "--y"};
    int f = -1;
    for (int k = 0; k < 8; k++)
      if (!strcmp(argv[i], flags[k])) f = k == 7 ? 0 : k; /* --y is --metric */
    if (f >= 0) {
      if (i + 1 >= argc) {
        fprintf(stderr, "mpgm plot: %s needs a value\n", argv[i]);
        return 2;
      }
      const char **slot[] = {&o.metric, &o.x, &o.series, &o.out, &o.title, &o.xscale, &o.yscale};
      *slot[f] = argv[++i];
    } else if (argv[i][0] == '-' && argv[i][1] == '-') {
      fprintf(stderr, "mpgm plot: unknown option %s\n", argv[i]);
      usage_plot(stderr);
      return 2;
    } else if (!csv) {
      csv = argv[i];
    } else {
      fprintf(stderr, "mpgm plot: unexpected argument %s (one study.csv)\n", argv[i]);
      return 2;
    }
  }
  if (!csv) {
    fprintf(stderr, "mpgm plot: no STUDY.csv given\n");
    usage_plot(stderr);
    return 2;
  }
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  const int err = mpgm_plot(&ctx, csv, &o);
  if (err) fprintf(stderr, "mpgm plot: %s\n", ctx.msg[0] ? ctx.msg : mpgm_code_str(err));
  return mpgm_exit_code(err);
}
