/* render.c -- `mpgm render RUN_DIR --field NAME --time T,...`: a run's
 * material points coloured by a field at given times, drawn by gnuplot to
 * PNG with a colour bar, a time label and equal axis scales
 * (docs/studies.md).
 *
 * For each requested time the frame of RUN_DIR/points.pvd (or, for legacy frames
 * only, points.vtk.series) nearest to it
 * is drawn (a note says which, a warning when it is more than half the
 * frame spacing away). The colour scale is common to all the pictures of
 * one call, and so is the view (the scene's mesh.domain from summary.json,
 * grown to hold every point), so the pictures compare. Each point is a
 * disc of its own area (the VTK field volume; else h^2 / ppc of the scene,
 * times J) so the cloud reads as the body.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "gnuplot.h"
#include "mpgm_file.h"
#include "mpgm_json_reader.h"
#include "mpgm_output.h"
#include "mpgm_vtk.h"
#include "study.h"
#include "units.h"

enum { MAX_TIMES = 64, MAX_CATS = 64 };

typedef struct ropts {
  const char *run, *field, *times, *out, *sheet, *title;
  int w, h, rows, cols;
  double range[2], xr[2], yr[2]; /* NAN: automatic */
  double radius;                 /* <= 0: automatic */
  int ax[3];                     /* --view: the axes across, up and toward the viewer; ax[0] < 0: automatic */
} ropts;

typedef struct frame {
  int index;          /**< in the .pvd                      */
  double t_req, t;    /**< requested and drawn time          */
  char token[32];     /**< the requested time as written     */
  mpgm_vtk_grid *g;   /**< the frame (shared by equal index) */
  double *v, *r;      /**< field value and disc radius per point */
  int *order;         /**< the points from far to near (3-D), or NULL */
  int owner;          /**< 1: g, v and r are this frame's (freed with it) */
} frame;

/* "A:B" into v[2] (either side may be empty: NAN); 0 on success. */
static int parse_range(const char *s, double v[2]) {
  const char *c = strchr(s, ':');
  if (!c) return -1;
  char *end;
  v[0] = v[1] = NAN;
  if (c > s) {
    v[0] = strtod(s, &end);
    if (end != c || !isfinite(v[0])) return -1;
  }
  if (c[1]) {
    v[1] = strtod(c + 1, &end);
    if (*end || !isfinite(v[1])) return -1;
  }
  return isnan(v[0]) || isnan(v[1]) || v[1] > v[0] ? 0 : -1;
}

/* "AB", two different axes of x, y, z: ax = A, B and the third (the
 * depth); 0 on success. */
static int parse_view(const char *s, int ax[3]) {
  if (strlen(s) != 2) return -1;
  for (int k = 0; k < 2; k++) {
    const char *c = strchr("xyz", s[k]);
    if (!s[k] || !c) return -1;
    ax[k] = (int)(c - "xyz");
  }
  ax[2] = 3 - ax[0] - ax[1];
  return ax[0] == ax[1] ? -1 : 0;
}

static void usage_render(FILE *f) {
  fprintf(f, "usage: mpgm render RUN_DIR [--field NAME] [--time T,...|last] [--out DIR] [--sheet FILE.png]\n"
             "                   [--layout RxC] [--size WxH] [--range MIN:MAX] [--xrange A:B] [--yrange A:B]\n"
             "                   [--radius R] [--title TEXT] [--view AB]\n"
             "  draws RUN_DIR's material points coloured by NAME (default displacement) at each time\n"
             "  (default: the last frame) into DIR/NAME_tT.png (default DIR: RUN_DIR/render), or all\n"
             "  of them as panels of one picture with --sheet. The colour bar runs from the 1st to the\n"
             "  99th percentile of the field over the frames drawn (--range MIN:MAX, in the field's unit,\n"
             "  overrides a side) and names the unit (stresses in Pa, kPa or MPa); material and body\n"
             "  get one named colour each. A 3-D run is drawn projected, seen from the positive side of\n"
             "  the third axis of --view AB (A across, B up; default x across, gravity's axis up)\n");
}

static int parse(int argc, char **argv, ropts *o) {
  memset(o, 0, sizeof *o);
  o->field = "displacement";
  o->times = "last";
  for (int k = 0; k < 2; k++) o->range[k] = o->xr[k] = o->yr[k] = NAN;
  o->ax[0] = -1;
  static const char *const flags[] = {"--field", "--time", "--out", "--sheet", "--title", "--size",
                                      "--layout", "--range", "--xrange", "--yrange", "--radius", "--view"};
  for (int i = 2; i < argc; i++) {
    int f = -1;
    for (int k = 0; k < 12; k++)
      if (!strcmp(argv[i], flags[k])) f = k;
    if (f < 0 && argv[i][0] == '-' && argv[i][1] == '-') {
      fprintf(stderr, "mpgm render: unknown option %s\n", argv[i]);
      usage_render(stderr);
      return 2;
    }
    if (f < 0) {
      if (o->run) {
        fprintf(stderr, "mpgm render: unexpected argument %s (one RUN_DIR)\n", argv[i]);
        return 2;
      }
      o->run = argv[i];
      continue;
    }
    if (i + 1 >= argc) {
      fprintf(stderr, "mpgm render: %s needs a value\n", argv[i]);
      return 2;
    }
    const char *v = argv[++i];
    const char **text[] = {&o->field, &o->times, &o->out, &o->sheet, &o->title};
    int bad = 0;
    char *end;
    if (f < 5) *text[f] = v;
    else if (f == 5) bad = sscanf(v, "%dx%d", &o->w, &o->h) != 2 || o->w < 100 || o->h < 100 || o->w > 10000 || o->h > 10000;
    else if (f == 6) bad = sscanf(v, "%dx%d", &o->rows, &o->cols) != 2 || o->rows < 1 || o->cols < 1 || o->rows * o->cols > MAX_TIMES;
    else if (f == 7) bad = parse_range(v, o->range) != 0;
    else if (f == 8) bad = parse_range(v, o->xr) != 0 || isnan(o->xr[0]) || isnan(o->xr[1]);
    else if (f == 9) bad = parse_range(v, o->yr) != 0 || isnan(o->yr[0]) || isnan(o->yr[1]);
    else if (f == 10) bad = (o->radius = strtod(v, &end), *end || !(o->radius > 0) || !isfinite(o->radius));
    else bad = parse_view(v, o->ax) != 0;
    if (bad) {
      static const char *const want[] = {"", "", "", "", "", "WxH in pixels (100 to 10000)",
                                         "RxC (rows x columns)", "MIN:MAX with MIN < MAX (a side may be empty)",
                                         "A:B with A < B", "A:B with A < B", "a positive length [m]",
                                         "two different axes of x, y, z (across, up), e.g. xz"};
      fprintf(stderr, "mpgm render: %s: expected %s, found '%s'\n", flags[f], want[f], v);
      return 2;
    }
  }
  if (!o->run) {
    fprintf(stderr, "mpgm render: no RUN_DIR given\n");
    usage_render(stderr);
    return 2;
  }
  return 0;
}

/* The frames nearest to the requested times (o->times). */
static int pick_frames(mpgm_ctx *ctx, const ropts *o, const mpgm_pvd_list *pvd, frame *fr, int *nfr) {
  char buf[1024];
  snprintf(buf, sizeof buf, "%s", o->times);
  *nfr = 0;
  for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
    MPGM_CHECK(ctx, *nfr < MAX_TIMES, MPGM_ERR_INPUT, "--time: at most %d times", MAX_TIMES);
    frame *f = &fr[(*nfr)++];
    memset(f, 0, sizeof *f);
    char *end;
    if (!strcmp(tok, "last")) {
      f->index = pvd->n - 1;
      f->t_req = pvd->time[f->index];
      snprintf(f->token, sizeof f->token, "%g", f->t_req);
    } else {
      f->t_req = strtod(tok, &end);
      MPGM_CHECK(ctx, end != tok && !*end && isfinite(f->t_req) && strlen(tok) < sizeof f->token, MPGM_ERR_INPUT,
                 "--time: expected numbers or \"last\", separated by commas, found '%s'", tok);
      snprintf(f->token, sizeof f->token, "%s", tok);
      f->index = 0;
      for (int k = 1; k < pvd->n; k++)
        if (fabs(pvd->time[k] - f->t_req) < fabs(pvd->time[f->index] - f->t_req)) f->index = k;
    }
    f->t = pvd->time[f->index];
    const double off = fabs(f->t - f->t_req);
    if (off <= 1e-9 * fmax(1.0, fabs(f->t_req))) continue;
    /* the spacing of the frames around the one chosen */
    double gap = INFINITY;
    if (f->index > 0) gap = fmin(gap, pvd->time[f->index] - pvd->time[f->index - 1]);
    if (f->index + 1 < pvd->n) gap = fmin(gap, pvd->time[f->index + 1] - pvd->time[f->index]);
    const int far = !(off <= 0.5 * gap) || f->t_req < pvd->time[0] || f->t_req > pvd->time[pvd->n - 1];
    fprintf(stderr, "mpgm render: %s: t = %s requested, frame at t = %.9g drawn (off by %.3g%s)\n",
            far ? "warning" : "note", tok, f->t, off,
            far ? ", more than half the spacing of the frames, or outside the run's times" : "");
  }
  MPGM_CHECK(ctx, *nfr > 0, MPGM_ERR_INPUT, "--time: no time given");
  return 0;
}

/* Value of field name at point p of g; names: a SCALARS field; a VECTORS
 * field (its length) or NAME_x, NAME_y, NAME_z; a TENSORS field's NAME_xx,
 * _yy, _xy, _zz, _yz, _xz, _p (mean pressure, -tr/3) and _q (von Mises).
 * 0 if unknown. */
static int field_values(const mpgm_vtk_grid *g, const char *name, double *v) {
  char base[256];
  snprintf(base, sizeof base, "%s", name);
  char *us = strrchr(base, '_');
  const char *suffix = us ? us + 1 : "";
  const mpgm_vtk_array *a = mpgm_vtk_array_find(g, name);
  if (!a && us) {
    *us = '\0';
    a = mpgm_vtk_array_find(g, base);
  } else {
    suffix = "";
  }
  if (!a) return 0;
  static const char *const vec[] = {"x", "y", "z"};
  static const char *const ten[] = {"xx", "yy", "xy", "zz", "p", "q", "yz", "xz"};
  int comp = -1;
  if (a->ncomp == 3)
    for (int k = 0; k < 3; k++)
      if (!strcmp(suffix, vec[k])) comp = k;
  if (a->ncomp == 9)
    for (int k = 0; k < 8; k++)
      if (!strcmp(suffix, ten[k])) comp = k;
  if ((a->ncomp == 1 && *suffix) || (a->ncomp == 9 && comp < 0) || (a->ncomp == 3 && *suffix && comp < 0)) return 0;
  for (int p = 0; p < g->npoints; p++) {
    const double *d = a->v + (size_t)a->ncomp * p;
    if (a->ncomp == 1) v[p] = d[0];
    else if (a->ncomp == 3) v[p] = comp < 0 ? hypot(hypot(d[0], d[1]), d[2]) : d[comp];
    else { /* (plane strain: yz = xz = 0) */
      const double xx = d[0], yy = d[4], zz = d[8], xy = d[1], yz = d[5], xz = d[2], m = (xx + yy + zz) / 3.0;
      const double q = sqrt(1.5 * ((xx - m) * (xx - m) + (yy - m) * (yy - m) + (zz - m) * (zz - m) +
                                   2 * (xy * xy + yz * yz + xz * xz)));
      const double tv[8] = {xx, yy, xy, zz, -m, q, yz, xz};
      v[p] = tv[comp];
    }
  }
  return 1;
}

/* "eps_p, J, displacement (|u|), displacement_x, ..." */
static void field_list(const mpgm_vtk_grid *g, char *buf, size_t cap) {
  size_t n = 0;
  buf[0] = '\0';
  for (int i = 0; i < g->narray && n < cap; i++) {
    const mpgm_vtk_array *a = &g->arrays[i];
    if (a->ncomp == 1) n += (size_t)snprintf(buf + n, cap - n, "%s%s", n ? ", " : "", a->name);
    else if (a->ncomp == 3)
      n += (size_t)snprintf(buf + n, cap - n, "%s%s (length), %s_x, %s_y, %s_z", n ? ", " : "", a->name, a->name,
                            a->name, a->name);
    else
      n += (size_t)snprintf(buf + n, cap - n, "%s%s_xx, %s_yy, %s_xy, %s_zz, %s_yz, %s_xz, %s_p, %s_q",
                            n ? ", " : "", a->name, a->name, a->name, a->name, a->name, a->name, a->name, a->name);
  }
}

/* What RUN_DIR/summary.json tells about the picture (absent: zeros). */
typedef struct run_info {
  int have_domain, is_static;
  int dim;         /**< 2, or 3 for a 3-D scene (three coordinates in mesh.domain) */
  double dom[6];   /**< xmin, xmax, ymin, ymax (, zmin, zmax) [m] */
  double g[3];     /**< gravity [m/s^2]                   */
  double area0;    /**< area (3-D: volume) of a point at the start: h^2 / ppc (quad), h^2 / (2 ppc)
                        (tri), h^3 / ppc (hex) */
  int nmat, nbody;                /**< names of the scene's materials (in order) and bodies */
  char mat[MAX_CATS][64], body[MAX_CATS][64];
} run_info;

static void read_info(const char *run, run_info *ri) {
  memset(ri, 0, sizeof *ri);
  char path[STUDY_PATH + 32];
  snprintf(path, sizeof path, "%s/summary.json", run);
  mpgm_ctx quiet;
  mpgm_ctx_init(&quiet);
  cJSON *doc = NULL;
  if (jr_parse_file(&quiet, path, &doc)) return;
  const cJSON *sc = cJSON_GetObjectItemCaseSensitive(doc, "scene");
  const cJSON *mesh = cJSON_GetObjectItemCaseSensitive(sc, "mesh");
  const cJSON *dom = cJSON_GetObjectItemCaseSensitive(mesh, "domain");
  const cJSON *mn = cJSON_GetObjectItemCaseSensitive(dom, "min"), *mx = cJSON_GetObjectItemCaseSensitive(dom, "max");
  const int nd = cJSON_GetArraySize(mn);
  ri->dim = nd == 3 ? 3 : 2;
  if ((nd == 2 || nd == 3) && cJSON_GetArraySize(mx) == nd) {
    double sum = 0.0;
    for (int k = 0; k < nd; k++) {
      ri->dom[2 * k] = cJSON_GetNumberValue(cJSON_GetArrayItem(mn, k));
      ri->dom[2 * k + 1] = cJSON_GetNumberValue(cJSON_GetArrayItem(mx, k));
      sum += ri->dom[2 * k] + ri->dom[2 * k + 1];
    }
    ri->have_domain = isfinite(sum);
  }
  const cJSON *g = cJSON_GetObjectItemCaseSensitive(sc, "gravity");
  for (int k = 0; k < 3 && k < cJSON_GetArraySize(g); k++) ri->g[k] = cJSON_GetNumberValue(cJSON_GetArrayItem(g, k));
  const double h = cJSON_GetNumberValue(cJSON_GetObjectItemCaseSensitive(mesh, "h"));
  const double ppc = cJSON_GetNumberValue(cJSON_GetObjectItemCaseSensitive(mesh, "ppc"));
  const char *cell = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(mesh, "cell"));
  if (h > 0 && ppc > 0)
    ri->area0 = ri->dim == 3 ? h * h * h / ppc : h * h / ppc / (cell && !strcmp(cell, "tri") ? 2.0 : 1.0);
  const char *an = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(sc, "time"),
                                                                         "analysis"));
  ri->is_static = an && !strcmp(an, "static");
  /* the index fields' names: materials in the order of the object, bodies by name (else bodyN) */
  const cJSON *mats = cJSON_GetObjectItemCaseSensitive(sc, "materials");
  for (const cJSON *m = cJSON_IsObject(mats) ? mats->child : NULL; m && ri->nmat < MAX_CATS; m = m->next)
    snprintf(ri->mat[ri->nmat++], sizeof ri->mat[0], "%s", m->string ? m->string : "?");
  const cJSON *bodies = cJSON_GetObjectItemCaseSensitive(sc, "bodies");
  for (int i = 0; cJSON_IsArray(bodies) && i < cJSON_GetArraySize(bodies) && ri->nbody < MAX_CATS; i++) {
    const char *nm = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(bodies, i), "name"));
    if (nm) snprintf(ri->body[ri->nbody], sizeof ri->body[0], "%s", nm);
    else snprintf(ri->body[ri->nbody], sizeof ri->body[0], "body%d", i);
    ri->nbody++;
  }
  cJSON_Delete(doc);
}

/* Disc radius of every point of f: half the side of its area (3-D: of
 * its volume's cube), a little more so that neighbours touch. */
static void radii(const ropts *o, const run_info *ri, frame *f, const double *bbox) {
  const mpgm_vtk_grid *g = f->g;
  const mpgm_vtk_array *vol = mpgm_vtk_array_find(g, "volume"), *J = mpgm_vtk_array_find(g, "J");
  if (vol && vol->ncomp != 1) vol = NULL;
  if (J && J->ncomp != 1) J = NULL;
  const double box = (bbox[1] - bbox[0]) * (bbox[3] - bbox[2]) / (g->npoints ? g->npoints : 1);
  for (int p = 0; p < g->npoints; p++) {
    double a = 0.0;
    if (vol && vol->v[p] > 0) a = vol->v[p];
    else if (ri->area0 > 0) a = ri->area0 * (J && J->v[p] > 0 ? J->v[p] : 1.0);
    const double side = a > 0 ? (ri->dim == 3 ? cbrt(a) : sqrt(a)) : sqrt(box);
    f->r[p] = o->radius > 0 ? o->radius : 0.6 * side;
  }
}

/* One panel: the points of f as discs coloured by the field. */
static void panel(FILE *gp, const run_info *ri, const frame *f, const int ax[3], const char *title, double scale) {
  fprintf(gp, "set title ");
  mpgm_gnuplot_quote(gp, title);
  fprintf(gp, " noenhanced\nset label 1 ");
  char lab[96];
  snprintf(lab, sizeof lab, ri->is_static ? "load factor %.4g" : "t = %.4g s", f->t);
  if (ri->dim == 3) /* a projection: say along which axis */
    snprintf(lab + strlen(lab), sizeof lab - strlen(lab), ", seen from +%c", "xyz"[ax[2]]);
  mpgm_gnuplot_quote(gp, lab);
  fprintf(gp, " at graph 0.02, graph 0.95 left front font ',13' noenhanced\n");
  fprintf(gp, "$p << EOD\n");
  for (int i = 0; i < f->g->npoints; i++) { /* far points first: the near ones cover them */
    const int p = f->order ? f->order[i] : i;
    fprintf(gp, "%.9g %.9g %.6g %.9g\n", f->g->x[3 * p + ax[0]], f->g->x[3 * p + ax[1]], f->r[p], f->v[p] / scale);
  }
  fprintf(gp, "EOD\nplot $p using 1:2:3:4 with circles lc palette fs solid noborder notitle\n");
}

/* The colour bar: its range, the divisor of the values drawn (stresses
 * in kPa or MPa), its label, and the names of an index field. */
typedef struct colour {
  double cr[2];    /**< range, in the field's unit (Pa for stresses)  */
  double scale;    /**< values are drawn divided by this              */
  char how[32];    /**< how the range was found: "1-99 %", ...         */
  char label[320]; /**< "stress_q [kPa], 1-99 %"                      */
  int ncat;        /**< an index field's number of names (0: continuous) */
  const char (*names)[64];
  int nnames;      /**< names known (from the scene); the rest are numbers */
} colour;

static int by_value(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The q-quantile (0..1) of sorted v[0..n-1], linear between ranks. */
static double quantile(const double *v, size_t n, double q) {
  const double r = q * (double)(n - 1);
  const size_t i = (size_t)floor(r);
  return i + 1 < n ? v[i] + (r - (double)i) * (v[i + 1] - v[i]) : v[n - 1];
}

/* The colour bar of the frames drawn: the 1st to 99th percentile of the
 * field's finite values over them (each frame once), a side of --range
 * instead of its percentile; material and body get one colour per index.
 * lohi: the values' own range. */
static int colour_scale(mpgm_ctx *ctx, const ropts *o, const run_info *ri, const frame *fr, int nfr, double lohi[2],
                        colour *c) {
  memset(c, 0, sizeof *c);
  c->scale = 1.0;
  size_t n = 0, cap = 0;
  for (int i = 0; i < nfr; i++) cap += fr[i].owner ? (size_t)fr[i].g->npoints : 0;
  double *v = malloc(sizeof *v * (cap ? cap : 1));
  MPGM_CHECK(ctx, v, MPGM_ERR_NOMEM, "out of memory (render)");
  for (int i = 0; i < nfr; i++)
    for (int p = 0; fr[i].owner && p < fr[i].g->npoints; p++)
      if (isfinite(fr[i].v[p])) v[n++] = fr[i].v[p];
  if (n == 0) {
    free(v);
    MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: no finite value of %s in the frames drawn: nothing to draw", o->run,
               o->field);
  }
  qsort(v, n, sizeof *v, by_value);
  lohi[0] = v[0];
  lohi[1] = v[n - 1];
  const int is_mat = !strcmp(o->field, "material"), is_body = !strcmp(o->field, "body");
  if (is_mat || is_body) { /* an index: one colour per value, named from the scene */
    c->names = is_mat ? ri->mat : ri->body;
    c->nnames = is_mat ? ri->nmat : ri->nbody;
    c->ncat = (int)fmin(MAX_CATS, fmax(c->nnames, floor(v[n - 1]) + 1));
    free(v);
    c->cr[0] = -0.5;
    c->cr[1] = c->ncat - 0.5;
    snprintf(c->how, sizeof c->how, "index");
    snprintf(c->label, sizeof c->label, "%s", o->field);
    return 0;
  }
  c->cr[0] = isnan(o->range[0]) ? quantile(v, n, 0.01) : o->range[0];
  c->cr[1] = isnan(o->range[1]) ? quantile(v, n, 0.99) : o->range[1];
  free(v);
  const int given0 = !isnan(o->range[0]), given1 = !isnan(o->range[1]);
  snprintf(c->how, sizeof c->how, "%s", given0 && given1 ? "--range" : given0 ? "--range to 99 %"
                                       : given1 ? "1 % to --range" : "1-99 %");
  if (!(c->cr[1] > c->cr[0])) { /* a constant field: a scale around it */
    const double d = fmax(1e-12, 0.05 * fabs(c->cr[0]));
    c->cr[0] -= d;
    c->cr[1] += d;
  }
  const char *unit = mpgm_field_unit(o->field);
  if (unit && !strcmp(unit, "Pa")) c->scale = mpgm_stress_scale(fmax(fabs(c->cr[0]), fabs(c->cr[1])), &unit);
  if (unit) snprintf(c->label, sizeof c->label, "%s [%s], %s", o->field, unit, c->how);
  else snprintf(c->label, sizeof c->label, "%s, %s", o->field, c->how);
  return 0;
}

/* The gnuplot preamble: terminal, view, palette, colour scale. */
static void preamble(FILE *gp, const colour *c, const double *view, const int ax[3], int w, int h) {
  fprintf(gp, "set terminal pngcairo size %d,%d enhanced font ',11'\n", w, h);
  fprintf(gp, "set size ratio -1\nset xrange [%.9g:%.9g]\nset yrange [%.9g:%.9g]\n", view[0], view[1], view[2],
          view[3]);
  fprintf(gp, "set xlabel '%c [m]'\nset ylabel '%c [m]'\nunset key\nset cbrange [%.9g:%.9g]\n", "xyz"[ax[0]],
          "xyz"[ax[1]], c->cr[0] / c->scale, c->cr[1] / c->scale);
  if (c->ncat) { /* steps of the Okabe-Ito colours, a tic with its name at each index */
    static const char *const cat[] = {"#0072b2", "#e69f00", "#009e73", "#cc79a7",
                                      "#56b4e9", "#d55e00", "#f0e442", "#000000"};
    fprintf(gp, "set palette maxcolors %d\nset palette defined (", c->ncat);
    for (int k = 0; k < c->ncat; k++)
      fprintf(gp, "%s%d '%s', %d '%s'", k ? ", " : "", k, cat[k % 8], k + 1, cat[k % 8]);
    fprintf(gp, ")\nset cbtics (");
    for (int k = 0; k < c->ncat; k++) {
      char num[16];
      snprintf(num, sizeof num, "%d", k);
      fprintf(gp, "%s", k ? ", " : "");
      mpgm_gnuplot_quote(gp, k < c->nnames ? c->names[k] : num);
      fprintf(gp, " %d", k);
    }
    fprintf(gp, ") scale 0\nunset mcbtics\n");
  } else {
    fprintf(gp, "set palette defined (0 '#440154', 0.13 '#482878', 0.25 '#3e4989', 0.38 '#31688e', "
                "0.5 '#26828e', 0.63 '#1f9e89', 0.75 '#35b779', 0.88 '#6ece58', 1 '#fde725')\n");
  }
  fprintf(gp, "set cblabel ");
  mpgm_gnuplot_quote(gp, c->label);
  /* the colour bar, its tic labels (at most "-1.234e-12") and its label
   * in a right margin of their own, so that in a sheet nothing reaches
   * into the next panel */
  fprintf(gp, " noenhanced offset 1,0\nset format cb '%%.4g'\nset rmargin 16\nset style fill solid noborder\n");
}

/* The run's collection of point frames into path: points.pvd (.vtu
 * frames), or points.vtk.series when only legacy frames were written
 * (output.format "vtk"); points.pvd when neither is there, for the
 * message. */
static void points_series(const char *run, char *path, size_t cap) {
  snprintf(path, cap, "%s/points.vtk.series", run);
  struct stat st;
  if (stat(path, &st) != 0) snprintf(path, cap, "%s/points.pvd", run);
  else {
    snprintf(path, cap, "%s/points.pvd", run);
    if (stat(path, &st) != 0) snprintf(path, cap, "%s/points.vtk.series", run);
  }
}

/* The pictures (--sheet, or DIR/NAME_tT.png, and --out itself) must not
 * replace what they are drawn from: points.pvd, summary.json, the frames;
 * and gnuplot, which writes them, must not wait on a FIFO there. */
static int refuse_overwrite(mpgm_ctx *ctx, const ropts *o, const char *outdir, const mpgm_pvd_list *pvd,
                            const frame *fr, int nfr) {
  char (*in)[STUDY_PATH + 64] = calloc((size_t)nfr + 2, sizeof *in);
  char (*png)[STUDY_PATH + 96] = calloc((size_t)nfr, sizeof *png);
  const char **inp = calloc((size_t)nfr + 2, sizeof *inp);
  mpgm_write_path *w = calloc((size_t)nfr + 2, sizeof *w);
  int err = in && png && inp && w ? 0 : mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory");
  int n = 0;
  if (!err) {
    points_series(o->run, in[0], sizeof in[0]);
    snprintf(in[1], sizeof in[1], "%s/summary.json", o->run);
    for (int i = 0; i < nfr; i++) snprintf(in[2 + i], sizeof in[2 + i], "%s/%s", o->run, pvd->file[fr[i].index]);
    for (int i = 0; i < nfr + 2; i++) inp[i] = in[i];
    if (o->out) w[n++] = (mpgm_write_path){o->out, MPGM_WRITE_FILE};
    if (o->sheet) w[n++] = (mpgm_write_path){o->sheet, MPGM_WRITE_FILE};
    for (int i = 0; i < nfr && !o->sheet; i++) {
      snprintf(png[i], sizeof png[i], "%s/%s_t%s.png", outdir, o->field, fr[i].token);
      w[n++] = (mpgm_write_path){png[i], MPGM_WRITE_FILE};
    }
    err = mpgm_refuse_overwrite(ctx, w, n, inp, nfr + 2);
    for (int k = o->out ? 1 : 0; k < n && !err; k++) err = mpgm_output_regular(ctx, w[k].path); /* gnuplot's */
  }
  free(in);
  free(png);
  free(inp);
  free(w);
  return err;
}

/* The view's axes: --view, else x across and y up (3-D: up along
 * gravity's largest component, across x, or y when gravity is along x). */
static void view_axes(const ropts *o, const run_info *ri, int ax[3]) {
  if (o->ax[0] >= 0) {
    memcpy(ax, o->ax, sizeof o->ax);
    return;
  }
  int up = 1;
  for (int k = 0; ri->dim == 3 && k < 3; k++)
    if (fabs(ri->g[k]) > fabs(ri->g[up])) up = k;
  ax[0] = up == 0 ? 1 : 0;
  ax[1] = up;
  ax[2] = 3 - ax[0] - ax[1];
}

/* 3-D: f's points from far to near along axis (seen from its positive
 * side), so that gnuplot draws the near ones over the far ones. */
typedef struct depth_pt {
  double z;
  int p;
} depth_pt;
static int by_depth(const void *a, const void *b) {
  const depth_pt *u = a, *v = b;
  return u->z < v->z ? -1 : u->z > v->z ? 1 : u->p - v->p;
}
static int depth_order(mpgm_ctx *ctx, frame *f, int axis) {
  const int n = f->g->npoints;
  depth_pt *d;
  MPGM_ALLOC(ctx, f->order, n);
  MPGM_ALLOC(ctx, d, n);
  for (int p = 0; p < n; p++) d[p] = (depth_pt){f->g->x[3 * p + axis], p};
  qsort(d, (size_t)n, sizeof *d, by_depth);
  for (int i = 0; i < n; i++) f->order[i] = d[i].p;
  free(d);
  return 0;
}

static int render_main(mpgm_ctx *ctx, const ropts *o, mpgm_pvd_list *pvd, frame *fr, int *nfr) {
  char path[STUDY_PATH + 64], outdir[STUDY_PATH];
  MPGM_CALL(mpgm_gnuplot_check(ctx));
  points_series(o->run, path, sizeof path);
  if (mpgm_pvd_read(ctx, path, pvd)) {
    if (ctx->code == MPGM_ERR_IO)
      snprintf(ctx->msg + strlen(ctx->msg), sizeof ctx->msg - strlen(ctx->msg),
               " (not a run folder, or the run wrote no VTK: output.vtk \"none\")");
    return ctx->code;
  }
  MPGM_CHECK(ctx, pvd->n > 0, MPGM_ERR_INPUT, "%s: no frames", path);
  MPGM_CALL(pick_frames(ctx, o, pvd, fr, nfr));
  run_info ri;
  read_info(o->run, &ri);
  int ax[3];
  view_axes(o, &ri, ax);
  MPGM_CHECK(ctx, ri.dim == 3 || (ax[0] < 2 && ax[1] < 2), MPGM_ERR_INPUT,
             "--view: a plane-strain run is drawn in x and y, found --view %c%c", "xyz"[ax[0]], "xyz"[ax[1]]);
  double bbox[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY}, lohi[2] = {NAN, NAN};
  for (int i = 0; i < *nfr; i++) {
    frame *f = &fr[i];
    for (int j = 0; j < i && !f->g; j++) /* equal frames are read once */
      if (fr[j].index == f->index) {
        f->g = fr[j].g;
        f->v = fr[j].v;
        f->r = fr[j].r;
        f->order = fr[j].order;
      }
    if (f->g) continue;
    snprintf(path, sizeof path, "%s/%s", o->run, pvd->file[f->index]);
    f->owner = 1;
    MPGM_CALL(mpgm_vtk_read(ctx, path, &f->g));
    MPGM_ALLOC(ctx, f->v, f->g->npoints);
    MPGM_ALLOC(ctx, f->r, f->g->npoints);
    if (!field_values(f->g, o->field, f->v)) {
      char list[2000];
      field_list(f->g, list, sizeof list);
      MPGM_ERROR(ctx, MPGM_ERR_INPUT, "%s: no field \"%s\"; fields: %s", path, o->field, list[0] ? list : "none");
    }
    for (int p = 0; p < f->g->npoints; p++) {
      bbox[0] = fmin(bbox[0], f->g->x[3 * p + ax[0]]);
      bbox[1] = fmax(bbox[1], f->g->x[3 * p + ax[0]]);
      bbox[2] = fmin(bbox[2], f->g->x[3 * p + ax[1]]);
      bbox[3] = fmax(bbox[3], f->g->x[3 * p + ax[1]]);
    }
    if (ri.dim == 3) MPGM_CALL(depth_order(ctx, f, ax[2]));
  }
  MPGM_CHECK(ctx, bbox[0] <= bbox[1], MPGM_ERR_INPUT, "%s: the frames hold no points", o->run);
  for (int i = 0; i < *nfr; i++)
    if (fr[i].owner) radii(o, &ri, &fr[i], bbox);
  colour col;
  MPGM_CALL(colour_scale(ctx, o, &ri, fr, *nfr, lohi, &col));
  /* view: the domain, grown to hold every point and its disc */
  double view[4] = {bbox[0], bbox[1], bbox[2], bbox[3]};
  for (int k = 0; ri.have_domain && k < 4; k++) { /* the domain's extent along the view's axes */
    const double dk = ri.dom[2 * ax[k / 2] + k % 2];
    view[k] = k % 2 ? fmax(view[k], dk) : fmin(view[k], dk);
  }
  const double pad = 0.02 * fmax(view[1] - view[0], view[3] - view[2]) + 1e-12;
  for (int k = 0; k < 4; k++) view[k] += k % 2 ? pad : -pad;
  if (!isnan(o->xr[0])) view[0] = o->xr[0], view[1] = o->xr[1];
  if (!isnan(o->yr[0])) view[2] = o->yr[0], view[3] = o->yr[1];
  const char *slash = strrchr(o->run, '/');
  char name[STUDY_NAME];
  snprintf(name, sizeof name, "%s", o->title ? o->title : slash && slash[1] ? slash + 1 : o->run);
  snprintf(outdir, sizeof outdir, "%s", o->out ? o->out : o->run);
  if (!o->out) strncat(outdir, "/render", sizeof outdir - strlen(outdir) - 1);
  MPGM_CALL(refuse_overwrite(ctx, o, outdir, pvd, fr, *nfr));
  if (!o->sheet) MPGM_CALL(mpgm_mkdir_p(ctx, outdir));
  /* default sizes: the panel's height follows the view's aspect */
  const double aspect = (view[3] - view[2]) / (view[1] - view[0]);
  const int h1 = (int)fmin(1400, fmax(300, 170 + 740 * aspect)), hp = (int)fmin(1000, fmax(250, 140 + 470 * aspect));
  mpgm_gnuplot gp;
  MPGM_CALL(mpgm_gnuplot_open(ctx, &gp, NULL));
  char title[STUDY_NAME + 300];
  if (o->sheet) {
    const int cols = o->cols ? o->cols : (int)ceil(sqrt((double)*nfr));
    const int rows = o->rows ? o->rows : (*nfr + cols - 1) / cols;
    preamble(gp.in, &col, view, ax, o->w ? o->w : 700 * cols, o->h ? o->h : hp * rows + 40);
    fprintf(gp.in, "set output ");
    mpgm_gnuplot_quote(gp.in, o->sheet);
    snprintf(title, sizeof title, "%s: material points coloured by %s", name, o->field);
    fprintf(gp.in, "\nset multiplot layout %d,%d title ", rows, cols);
    mpgm_gnuplot_quote(gp.in, title);
    fprintf(gp.in, " noenhanced\n");
    for (int i = 0; i < *nfr && i < rows * cols; i++) panel(gp.in, &ri, &fr[i], ax, "", col.scale);
    fprintf(gp.in, "unset multiplot\nunset output\n");
  } else {
    preamble(gp.in, &col, view, ax, o->w ? o->w : 1000, o->h ? o->h : h1);
    for (int i = 0; i < *nfr; i++) {
      snprintf(path, sizeof path, "%s/%s_t%s.png", outdir, o->field, fr[i].token);
      fprintf(gp.in, "set output ");
      mpgm_gnuplot_quote(gp.in, path);
      snprintf(title, sizeof title, "%s: %s", name, o->field);
      fprintf(gp.in, "\n");
      panel(gp.in, &ri, &fr[i], ax, title, col.scale);
      fprintf(gp.in, "unset output\n");
    }
  }
  MPGM_CALL(mpgm_gnuplot_close(ctx, &gp));
  for (int i = 0; i < (o->sheet ? 1 : *nfr); i++) {
    if (o->sheet) snprintf(path, sizeof path, "%s", o->sheet);
    else snprintf(path, sizeof path, "%s/%s_t%s.png", outdir, o->field, fr[i].token);
    MPGM_CALL(mpgm_file_nonempty(ctx, path));
    if (o->sheet) printf("render: %s (%d panels)\n", path, *nfr);
    else printf("render: %s (frame at t = %.9g)\n", path, fr[i].t);
  }
  printf("render: %s from %.6g to %.6g; colour bar from %.6g to %.6g (%s)\n", o->field, lohi[0], lohi[1], col.cr[0],
         col.cr[1], col.how);
  if (ri.dim == 3)
    printf("render: a 3-D run, projected: %c across, %c up, seen from +%c\n", "xyz"[ax[0]], "xyz"[ax[1]],
           "xyz"[ax[2]]);
  return 0;
}

int mpgm_cmd_render(int argc, char **argv) {
  ropts o;
  int rc = parse(argc, argv, &o);
  if (rc) return rc;
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_pvd_list pvd;
  memset(&pvd, 0, sizeof pvd);
  frame *fr = calloc(MAX_TIMES, sizeof *fr);
  int nfr = 0;
  const int err = fr ? render_main(&ctx, &o, &pvd, fr, &nfr) : MPGM_ERR_NOMEM;
  if (err) fprintf(stderr, "mpgm render: %s\n", ctx.msg[0] ? ctx.msg : mpgm_code_str(err));
  for (int i = 0; fr && i < nfr; i++) {
    if (!fr[i].owner) continue;
    mpgm_vtk_grid_destroy(&fr[i].g);
    free(fr[i].v);
    free(fr[i].r);
    free(fr[i].order);
  }
  free(fr);
  mpgm_pvd_list_free(&pvd);
  return mpgm_exit_code(err);
}
