/* output.c -- VTK series of points and mesh (VTK XML .vtu in .pvd
 * collections, legacy .vtk in .vtk.series), probes history, summary.json.
 * A frame's fields are gathered once (frame_gather) and then written in
 * every format output.format names (frame_write). */
#define _POSIX_C_SOURCE 200809L
#include "mpgm_output.h"

#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "mpgm_file.h"
#include "mpgm_frontend.h"
#include "mpgm_grid.h"
#include "mpgm_mtx.h"
#include "mpgm_scene_io.h"
#include "mpgm_vtk.h"
#include "mpgm_vtu.h"
#include "mpgm_xdmf.h"
/* det F of the points' J: core's DIM x DIM determinant (header only) */
#include "mpgm_tensor.h"

/* steps.csv: 9 columns, and in dynamic runs 4 of energy and the MPGM_DIM
 * components of the points' and the nodes' momentum (2-D 8, 3-D 10; all
 * are kept in memory) */
enum { STEP_BASE = 9, STEP_COLS = STEP_BASE + 4 + 2 * MPGM_DIM };
static const char axis[3] = {'x', 'y', 'z'};

/* The series: o->series[format][kind], format 0 .vtu and 1 legacy .vtk,
 * kind 0 points, 1 mesh and 2 background grid; their collections, and the
 * checkpoint sections of their entries. */
enum { SERIES_FORMATS = 2, SERIES_KINDS = 3 };
static const char *const kind_name[SERIES_KINDS] = {"points", "mesh", "grid"};
static const char *const series_file[SERIES_FORMATS][SERIES_KINDS] = {
    {"points.pvd", "mesh.pvd", "grid.pvd"}, {"points.vtk.series", "mesh.vtk.series", "grid.vtk.series"}};
static const char *const series_tag[SERIES_FORMATS][SERIES_KINDS] = {
    {"out.vtu_points", "out.vtu_mesh", "out.vtu_grid"}, {"out.vtk_points", "out.vtk_mesh", "out.vtk_grid"}};
static const unsigned series_format[SERIES_FORMATS] = {MPGM_FORMAT_VTU, MPGM_FORMAT_VTK};

/* Append a row of width doubles to a growable table; *row points to it. */
static int table_push(mpgm_ctx *ctx, double **buf, int *n, int *cap, int width, double **row) {
  if (*n == *cap) {
    const int c = *cap ? 2 * *cap : 256;
    double *h = realloc(*buf, sizeof(double) * (size_t)width * c);
    MPGM_CHECK(ctx, h, MPGM_ERR_NOMEM, "out of memory (history of %d rows)", c);
    *buf = h;
    *cap = c;
  }
  *row = *buf + (size_t)width * (*n)++;
  return 0;
}

/* Remove the VTK files of DIR/vtk numbered keep or later (and temporaries
 * a stopped run left): a new run keeps none, a restarted one those written
 * before its checkpoint. */
static void remove_vtk_from(const char *path, int keep) {
  DIR *dd = opendir(path);
  if (!dd) return;
  struct dirent *e;
  while ((e = readdir(dd))) {
    int idx = -1, kind = -1;
    for (int k = 0; k < SERIES_KINDS; k++) {
      const size_t len = strlen(kind_name[k]);
      if (strncmp(e->d_name, kind_name[k], len) == 0 && e->d_name[len] == '_' &&
          sscanf(e->d_name + len + 1, "%d", &idx) == 1)
        kind = k;
    }
    if (kind < 0) continue;
    if ((!strstr(e->d_name, ".vtk") && !strstr(e->d_name, ".vtu")) ||
        (idx < keep && !strstr(e->d_name, ".tmp")))
      continue;
    char f[MPGM_PATH_LEN + 400];
    snprintf(f, sizeof f, "%s/%s", path, e->d_name);
    remove(f);
  }
  closedir(dd);
}

const char *mpgm_output_series_names(const mpgm_scene *s, int has_cells, char *buf, size_t n) {
  const int has[SERIES_KINDS] = {1, has_cells, s->grid};
  size_t len = 0;
  buf[0] = '\0';
  for (int f = 0; s->vtk != MPGM_VTK_NONE && f < SERIES_FORMATS; f++)
    for (int k = 0; (s->formats & series_format[f]) && k < SERIES_KINDS; k++)
      if (has[k]) len += (size_t)snprintf(buf + len, len < n ? n - len : 0, ", %s", series_file[f][k]);
  if (s->vtk != MPGM_VTK_NONE && (s->formats & MPGM_FORMAT_XDMF)) /* the grid is not in XDMF */
    snprintf(buf + len, len < n ? n - len : 0, ", points.xdmf%s, results.h5", has_cells ? ", mesh.xdmf" : "");
  return buf;
}

/* output.grid: the background grid's nodes and cells (they do not move),
 * made once for every frame of the grid series. */
static int grid_geometry(mpgm_ctx *ctx, mpgm_output *o, const mpgm_background *bg) {
  const mpgm_grid *g = bg->grid;
  const int nn = g->nn;
  MPGM_ALLOC(ctx, o->grid_x, MPGM_DIM * (size_t)g->nnode);
  MPGM_ALLOC(ctx, o->grid_ptr, (size_t)g->ncell + 1);
  MPGM_ALLOC(ctx, o->grid_node, (size_t)nn * g->ncell);
  MPGM_ALLOC(ctx, o->grid_type, (size_t)g->ncell);
  for (int i = 0; i < g->nnode; i++) mpgm_grid_node(g, i, o->grid_x + MPGM_DIM * i);
  for (int c = 0; c <= g->ncell; c++) o->grid_ptr[c] = nn * c;
  for (int c = 0; c < g->ncell; c++) {
    mpgm_grid_cell(g, c, o->grid_node + (size_t)nn * c, NULL);
    o->grid_type[c] = nn == 3 ? MPGM_VTK_TRIANGLE : nn == 4 ? MPGM_VTK_QUAD : MPGM_VTK_HEXAHEDRON;
  }
  o->grid_nnode = g->nnode, o->grid_ncell = g->ncell;
  return 0;
}

/* The output of problem pb into dir, in memory: nothing is written. */
static int output_init(mpgm_ctx *ctx, mpgm_output *o, const mpgm_problem *pb, const char *dir) {
  const mpgm_scene *scene = mpgm_problem_scene(pb);
  mpgm_cells cells;
  mpgm_background bg;
  const int has[SERIES_KINDS] = {1, mpgm_problem_cells(pb, &cells),
                                 scene->grid && mpgm_problem_background(pb, &bg)};
  memset(o, 0, sizeof *o);
  snprintf(o->dir, sizeof o->dir, "%s", dir);
  o->rank = mpgm_ctx_rank(ctx);
  o->nproc = mpgm_ctx_size(ctx);
  char path[MPGM_PATH_LEN + 64];
  for (int f = 0; scene->vtk != MPGM_VTK_NONE && f < SERIES_FORMATS; f++)
    for (int k = 0; (scene->formats & series_format[f]) && k < SERIES_KINDS; k++)
      if (has[k]) {
        snprintf(path, sizeof path, "%s/%s", dir, series_file[f][k]);
        MPGM_CALL(mpgm_pvd_create(ctx, path, &o->series[f][k]));
      }
  if (o->series[0][2] || o->series[1][2]) MPGM_CALL(grid_geometry(ctx, o, &bg));
  const int has_cells = has[1];
  if (scene->vtk != MPGM_VTK_NONE && (scene->formats & MPGM_FORMAT_XDMF))
    MPGM_CALL(mpgm_xdmf_create(ctx, dir, scene->compress == MPGM_COMPRESS_ZLIB, has_cells, &o->xdmf));
  if (scene->nmatrices > 0) /* output.matrices */
    snprintf(o->matrices_dir, sizeof o->matrices_dir, "%s/matrices", dir);
  /* the MPGM_DIM components of u of every probe (mpgm_ref_column);
   * dynamic runs add those of v of every probe after them */
  o->ncol = (scene->analysis == MPGM_ANALYSIS_STATIC ? 1 : 2) * MPGM_DIM * mpgm_problem_points(pb)->nprobe;
  o->scene = scene;
  return 0;
}

/* The results folder made ready for the output o, keeping its first
 * `keep` VTK outputs (a restart): the first writes into it. */
static int output_folder(mpgm_ctx *ctx, const mpgm_output *o, int keep) {
  const char *dir = o->dir;
  MPGM_CALL(mpgm_mkdir_p(ctx, dir));
  char path[MPGM_PATH_LEN + 64];
  /* an earlier run's summary.json must not stand for this run's should it
   * stop before writing its own (killed, disk full) */
  snprintf(path, sizeof path, "%s/summary.json", dir);
  MPGM_CHECK(ctx, remove(path) == 0 || errno == ENOENT, MPGM_ERR_IO, "%s: cannot remove: %s", path,
             strerror(errno));
  if (o->scene->vtk != MPGM_VTK_NONE) {
    snprintf(path, sizeof path, "%s/vtk", dir);
    MPGM_CALL(mpgm_mkdir_p(ctx, path));
    /* stale files of an earlier run in the same folder would mix series */
    remove_vtk_from(path, keep);
    /* an earlier run's collections (of other formats too) would list
     * frames that are gone; this run's are written with its first frame,
     * a restart's at once */
    for (int f = 0; f < SERIES_FORMATS; f++)
      for (int k = 0; k < SERIES_KINDS; k++) {
        snprintf(path, sizeof path, "%s/%s", dir, series_file[f][k]);
        remove(path);
      }
    MPGM_CALL(mpgm_xdmf_open(o->xdmf, ctx, dir, keep));
  }
  if (o->matrices_dir[0]) { /* no systems of an earlier run */
    MPGM_CALL(mpgm_mkdir_p(ctx, o->matrices_dir));
    if (keep == 0) MPGM_CALL(mpgm_remove_files(ctx, o->matrices_dir, "step", ".mtx"));
  }
  return 0;
}

int mpgm_output_open(mpgm_ctx *ctx, mpgm_output *o, const mpgm_problem *pb, const char *dir) {
  MPGM_CALL(mpgm_agree(ctx, output_init(ctx, o, pb, dir)));
  /* many processes: the first makes the folder, the others wait for it */
  return mpgm_agree(ctx, o->rank == 0 ? output_folder(ctx, o, 0) : 0);
}

/* The tallies, the histories and the .pvd entries. */
int mpgm_output_save(const mpgm_output *o, mpgm_ctx *ctx, mpgm_blob *b) {
  const int n[5] = {o->nvtk, o->files, o->nrow, o->nstep, 2 + o->ncol};
  MPGM_CALL(mpgm_blob_put(ctx, b, "out.counts", n, sizeof n));
  MPGM_CALL(mpgm_blob_put(ctx, b, "out.mtx", &o->mtx_written, sizeof o->mtx_written));
  MPGM_CALL(mpgm_blob_put(ctx, b, "out.ref_acc", o->ref_acc, sizeof o->ref_acc));
  MPGM_CALL(mpgm_blob_put(ctx, b, "out.probes", o->hist, sizeof(double) * (size_t)(o->nrow * n[4])));
  MPGM_CALL(mpgm_blob_put(ctx, b, "out.steps", o->steps, sizeof(double) * (size_t)(o->nstep * STEP_COLS)));
  for (int f = 0; f < SERIES_FORMATS; f++)
    for (int k = 0; k < SERIES_KINDS; k++)
      MPGM_CALL(mpgm_pvd_save(o->series[f][k], ctx, b, series_tag[f][k]));
  return mpgm_xdmf_save(o->xdmf, ctx, b, "out.xdmf");
}

/* A history read back: rows rows of width doubles, section tag, into a
 * table (its size checked against the section's before it is made); row
 * r is of step r + first. */
static int table_restore(mpgm_ctx *ctx, mpgm_blob *b, const char *tag, int rows, int width,
                         int first, double **buf, int *n, int *cap) {
  size_t len;
  MPGM_CALL(mpgm_blob_peek(ctx, b, tag, &len));
  MPGM_CHECK(ctx, len == sizeof(double) * (size_t)rows * (size_t)width, MPGM_ERR_INPUT,
             "checkpoint: section '%s' holds %zu bytes; %d rows of %d numbers are %zu", tag, len,
             rows, width, sizeof(double) * (size_t)rows * (size_t)width);
  double *row;
  for (int i = 0; i < rows; i++) MPGM_CALL(table_push(ctx, buf, n, cap, width, &row));
  MPGM_CALL(mpgm_blob_get(ctx, b, tag, *buf, len));
  for (int i = 0; i < rows; i++) /* the step first: written as an integer */
    MPGM_CHECK(ctx, (*buf)[(size_t)width * i] == (double)(i + first), MPGM_ERR_INPUT,
               "checkpoint: section '%s': row %d is of step %g, not %d", tag, i,
               (*buf)[(size_t)width * i], i + first);
  return 0;
}

int mpgm_output_restore(mpgm_ctx *ctx, mpgm_output *o, const mpgm_problem *pb, const char *dir,
                        mpgm_blob *b) {
  MPGM_CALL(output_init(ctx, o, pb, dir));
  int n[5];
  MPGM_CALL(mpgm_blob_get(ctx, b, "out.counts", n, sizeof n));
  mpgm_report r;
  mpgm_problem_report(pb, &r);
  /* a row of probes at the start and after every step, a row of steps
   * after every step; a VTK output at most at each of those rows, a file
   * of each series (points, and mesh when there are cells, in each
   * format; XDMF frames are not files, and may be the only output) */
  int per = 0;
  for (int f = 0; f < SERIES_FORMATS; f++)
    for (int k = 0; k < SERIES_KINDS; k++) per += o->series[f][k] != NULL;
  MPGM_CHECK(ctx, n[4] == 2 + o->ncol, MPGM_ERR_INPUT,
             "checkpoint: output of %d probe columns, this scene has %d", n[4] - 2, o->ncol);
  MPGM_CHECK(ctx, (long)n[2] == r.step + 1 && (long)n[3] == r.step, MPGM_ERR_INPUT,
             "checkpoint: "
             "section 'out.counts': %d rows of probes and %d of steps after step %ld",
             n[2], n[3], r.step);
  MPGM_CHECK(ctx,
             n[0] >= 0 && n[0] <= n[2] && (per || o->xdmf ? 1 : n[0] == 0) &&
                 (long)n[1] == (long)per * n[0],
             MPGM_ERR_INPUT,
             "checkpoint: section "
             "'out.counts': %d VTK outputs of %d files (%d files each) over %d rows",
             n[0], n[1], per, n[2]);
  o->nvtk = n[0], o->files = n[1];
  MPGM_CALL(mpgm_blob_get(ctx, b, "out.mtx", &o->mtx_written, sizeof o->mtx_written));
  MPGM_CHECK(ctx, o->mtx_written >= 0 && o->mtx_written <= LONG_MAX / 2, MPGM_ERR_INPUT,
             "checkpoint: section 'out.mtx': %ld "
             "systems written",
             o->mtx_written);
  MPGM_CALL(mpgm_blob_get(ctx, b, "out.ref_acc", o->ref_acc, sizeof o->ref_acc));
  MPGM_CALL(table_restore(ctx, b, "out.probes", n[2], n[4], 0, &o->hist, &o->nrow, &o->caprow));
  MPGM_CALL(
      table_restore(ctx, b, "out.steps", n[3], STEP_COLS, 1, &o->steps, &o->nstep, &o->capstep));
  for (int f = 0; f < SERIES_FORMATS; f++)
    for (int k = 0; k < SERIES_KINDS; k++) {
      MPGM_CALL(mpgm_pvd_restore(o->series[f][k], ctx, b, series_tag[f][k]));
      MPGM_CHECK(ctx, mpgm_pvd_count(o->series[f][k]) == (o->series[f][k] ? o->nvtk : 0),
                 MPGM_ERR_INPUT, "checkpoint: section '%s': %d entries of %s for %d VTK outputs",
                 series_tag[f][k], mpgm_pvd_count(o->series[f][k]), series_file[f][k], o->nvtk);
    }
  return mpgm_xdmf_restore(o->xdmf, ctx, b, "out.xdmf", o->nvtk);
}

int mpgm_output_resume(mpgm_ctx *ctx, mpgm_output *o) {
  MPGM_CALL(output_folder(ctx, o, o->nvtk));
  /* the collections as the checkpoint has them */
  for (int f = 0; f < SERIES_FORMATS; f++)
    for (int k = 0; k < SERIES_KINDS; k++) MPGM_CALL(mpgm_pvd_write(o->series[f][k], ctx));
  /* the histories as the checkpoint has them: rows a stopped run wrote
   * after it are gone */
  MPGM_CALL(mpgm_output_probes_write(ctx, o));
  return mpgm_output_steps_write(ctx, o);
}

/* A step begins: is it listed (remove what a retried step wrote)? */
static int mtx_step_begin(void *user, mpgm_ctx *ctx, long step) {
  mpgm_output *o = user;
  o->mtx_on = 0;
  o->mtx_system = 0;
  for (int i = 0; i < o->scene->nmatrices; i++) o->mtx_on |= o->scene->matrices[i] == step;
  if (!o->mtx_on) return 0;
  char prefix[32];
  snprintf(prefix, sizeof prefix, "step%04ld_", step);
  return mpgm_remove_files(ctx, o->matrices_dir, prefix, ".mtx");
}

/* The system K delta = R about to be solved, as DIR/matrices/stepSSSS_
 * itII_K.mtx and _b.mtx (II counts the Newton iterations of the step from
 * 0, across contact re-solves). */
static int mtx_system(void *user, mpgm_ctx *ctx, long step, const mpgm_csc *K, const double *R) {
  mpgm_output *o = user;
  if (!o->mtx_on) return 0;
  char path[MPGM_PATH_LEN + 64], what[MPGM_PATH_LEN + 128];
  const int len = snprintf(path, sizeof path, "%s/step%04ld_it%02d_", o->matrices_dir, step, o->mtx_system);
  MPGM_CHECK(ctx, len > 0 && (size_t)len + 6 < sizeof path, MPGM_ERR_IO, "%s: path too long",
             o->matrices_dir);
  mpgm_timer_start(ctx, MPGM_T_OUTPUT);
  snprintf(what, sizeof what, "mpgm: tangent K of step %ld, system %d (K delta = b), scene %s", step,
           o->mtx_system, o->scene->file);
  strcat(path, "K.mtx");
  int err = mpgm_mtx_write_csc(ctx, path, K, what);
  snprintf(what, sizeof what, "mpgm: right-hand side b (residual R) of step %ld, system %d, scene %s",
           step, o->mtx_system, o->scene->file);
  strcpy(path + len, "b.mtx");
  if (!err) err = mpgm_mtx_write_vec(ctx, path, R, K->n, what);
  mpgm_timer_stop(ctx, MPGM_T_OUTPUT);
  MPGM_CALL(err);
  o->mtx_system++;
  o->mtx_written++;
  return MPGM_OK;
}

int mpgm_output_observe(mpgm_ctx *ctx, mpgm_output *o, mpgm_problem *pb) {
  (void)ctx;
  if (!o->matrices_dir[0]) return 0;
  const mpgm_observer obs = {.user = o, .step_begin = mtx_step_begin, .system = mtx_system};
  return mpgm_problem_observe(pb, &obs);
}

void mpgm_output_close(mpgm_output *o) {
  for (int f = 0; f < SERIES_FORMATS; f++)
    for (int k = 0; k < SERIES_KINDS; k++) mpgm_pvd_destroy(&o->series[f][k]);
  mpgm_xdmf_destroy(&o->xdmf);
  free(o->grid_x);
  free(o->grid_ptr);
  free(o->grid_node);
  free(o->grid_type);
  free(o->hist);
  free(o->steps);
  free(o->imb);
  o->hist = NULL;
  o->steps = NULL;
  o->imb = NULL;
  o->grid_x = NULL;
  o->grid_ptr = o->grid_node = o->grid_type = NULL;
}

int mpgm_output_step_record(mpgm_ctx *ctx, mpgm_output *o, const mpgm_problem *pb, double wall) {
  double *row = NULL;
  MPGM_CALL(table_push(ctx, &o->steps, &o->nstep, &o->capstep, STEP_COLS, &row));
  mpgm_report r;
  mpgm_problem_report(pb, &r);
  const mpgm_newton_info *n = &r.last;
  row[0] = (double)r.step;
  row[1] = o->scene->analysis == MPGM_ANALYSIS_STATIC ? r.lambda : r.t;
  row[2] = n->iterations;
  row[3] = n->res0;
  row[4] = n->res;
  row[5] = n->res_rel;
  row[6] = n->du_rel;
  row[7] = r.dt;
  row[8] = wall;
  mpgm_energy e;
  mpgm_problem_energy(pb, &e);
  const double en[4] = {e.kinetic, e.work_int, e.work_ext, e.total};
  memcpy(row + STEP_BASE, en, sizeof en);
  memcpy(row + STEP_BASE + 4, e.momentum, sizeof(double) * MPGM_DIM);
  memcpy(row + STEP_BASE + 4 + MPGM_DIM, e.node_momentum, sizeof(double) * MPGM_DIM);
  if (o->nproc == 1) return 0;
  /* many processes: how evenly the points are spread after the step */
  double imb;
  MPGM_CALL(mpgm_imbalance(ctx, mpgm_problem_points(pb)->n, &imb));
  MPGM_CALL(table_push(ctx, &o->imb, &o->nimb, &o->capimb, 1, &row));
  row[0] = imb;
  return 0;
}

/* Write a history table to DIR/name atomically: the header line, then one
 * line per row of width numbers (the step first, as an integer). */
static int write_table(mpgm_ctx *ctx, const mpgm_output *o, const char *name,
                       const char *header, const double *rows, int nrow, int stride, int width) {
  if (o->rank > 0) return 0; /* many processes: the first writes the histories */
  char path[MPGM_PATH_LEN + 64];
  snprintf(path, sizeof path, "%s/%s", o->dir, name);
  void *fv;
  MPGM_CALL(mpgm_atomic_open(ctx, path, &fv));
  FILE *f = fv;
  fputs(header, f);
  for (int r = 0; r < nrow; r++) {
    const double *row = rows + (size_t)stride * r;
    fprintf(f, "%ld", (long)row[0]);
    for (int c = 1; c < width; c++) fprintf(f, ",%.17g", row[c]);
    fputc('\n', f);
  }
  return mpgm_atomic_close(ctx, path, f);
}

int mpgm_output_steps_write(mpgm_ctx *ctx, mpgm_output *o) {
  const int st = o->scene->analysis == MPGM_ANALYSIS_STATIC;
  char header[512];
  int n = snprintf(header, sizeof header,
                   "step,%s,newton_iterations,residual_initial,residual,residual_relative,"
                   "increment_relative,%s,wall_s%s", st ? "load_factor" : "time",
                   st ? "load_increment" : "dt",
                   st ? "" : ",kinetic_energy,internal_work,external_work,energy_total");
  for (int m = 0; !st && m < 2; m++) /* momentum_x, _y(, _z), then the nodes' */
    for (int c = 0; c < MPGM_DIM; c++)
      n += snprintf(header + n, sizeof header - (size_t)n, ",%smomentum_%c", m ? "node_" : "", axis[c]);
  const int width = st ? STEP_BASE : STEP_COLS;
  if (o->nproc == 1 || o->nimb != o->nstep) {
    snprintf(header + n, sizeof header - (size_t)n, "\n");
    return write_table(ctx, o, "steps.csv", header, o->steps, o->nstep, STEP_COLS, width);
  }
  /* many processes: the imbalance after each step as a last column */
  snprintf(header + n, sizeof header - (size_t)n, ",imbalance\n");
  double *t = malloc(sizeof(double) * ((size_t)o->nstep * (width + 1) + 1));
  MPGM_CHECK(ctx, t, MPGM_ERR_NOMEM, "out of memory (steps.csv of %d rows)", o->nstep);
  for (int r = 0; r < o->nstep; r++) {
    memcpy(t + (size_t)(width + 1) * r, o->steps + (size_t)STEP_COLS * r, sizeof(double) * (size_t)width);
    t[(size_t)(width + 1) * r + width] = o->imb[r];
  }
  const int err = write_table(ctx, o, "steps.csv", header, t, o->nstep, width + 1, width + 1);
  free(t);
  return err;
}

int mpgm_output_probes_record(mpgm_ctx *ctx, mpgm_output *o, const mpgm_problem *pb) {
  double *row = NULL;
  MPGM_CALL(table_push(ctx, &o->hist, &o->nrow, &o->caprow, 2 + o->ncol, &row));
  mpgm_report r;
  mpgm_problem_report(pb, &r);
  const mpgm_points *P = mpgm_problem_points(pb);
  row[0] = (double)r.step;
  row[1] = o->scene->analysis == MPGM_ANALYSIS_STATIC ? r.lambda : r.t;
  mpgm_reference_observe(o->scene, row[1], r.step ? r.dt : 0.0, P, o->ref_acc);
  /* u of probe k at mpgm_ref_column(k, c), v after the whole u block */
  const int p0 = P->n, nu = MPGM_DIM * P->nprobe;
  for (int k = 0; k < P->nprobe; k++)
    for (int c = 0; c < MPGM_DIM; c++) {
      row[mpgm_ref_column(k, c)] = P->u[MPGM_DIM * (p0 + k) + c];
      if (o->ncol > nu) row[nu + mpgm_ref_column(k, c)] = P->v[MPGM_DIM * (p0 + k) + c];
    }
  return 0;
}

int mpgm_output_probes_write(mpgm_ctx *ctx, mpgm_output *o) {
  const mpgm_scene *sc = o->scene;
  const size_t cap = 64 + 2 * MPGM_DIM * (MPGM_NAME_LEN + 8) * (size_t)sc->nprobe;
  char *header;
  MPGM_ALLOC(ctx, header, cap);
  size_t n = (size_t)snprintf(header, cap, "step,%s",
                              sc->analysis == MPGM_ANALYSIS_STATIC ? "load_factor" : "time");
  /* NAME_ux, NAME_uy(, NAME_uz) of every probe, then NAME_vx, ... */
  for (int m = 0; m < (o->ncol > MPGM_DIM * sc->nprobe ? 2 : 1); m++)
    for (int k = 0; k < sc->nprobe; k++)
      for (int c = 0; c < MPGM_DIM && n < cap; c++)
        n += (size_t)snprintf(header + n, cap - n, ",%s_%c%c", sc->probes[k].name, m ? 'v' : 'u',
                              axis[c]);
  if (n < cap - 1) strcat(header, "\n");
  const int err = write_table(ctx, o, "probes.csv", header, o->hist, o->nrow, 2 + o->ncol, 2 + o->ncol);
  free(header);
  return err;
}

/* A frame's data, gathered once from the problem and written in every
 * format the scene asks for (output.format): the points' piece, the
 * mesh's (front ends with cells), the grid's (output.grid), the time and
 * the legacy titles. */
typedef struct frame {
  double time;
  long step;
  mpgm_vtu_piece points, mesh, grid;
  int has_mesh;
  mpgm_vtk_field pf[12], mf[1], gf[4];
  double *scratch; /* J, material, id, eps_p, body of every point (owned) */
  double *gscratch; /* active, mass, velocity, du of every grid node (owned) */
} frame;

/* The grid's piece: every grid node and cell, with the values of the
 * nodes of the last step (0 at the others): active (1 where the step had a
 * node), the nodal mass, the node velocity at the step's end and the
 * step's displacement increment. */
static int frame_grid(mpgm_ctx *ctx, const mpgm_output *o, const mpgm_problem *pb, frame *fr) {
  mpgm_background bg;
  mpgm_problem_background(pb, &bg);
  const mpgm_nodes *nd = mpgm_problem_nodes(pb);
  const size_t n = (size_t)o->grid_nnode;
  MPGM_ALLOC(ctx, fr->gscratch, (2 + 2 * MPGM_DIM) * n);
  double *act = fr->gscratch, *mass = act + n, *vel = mass + n, *du = vel + MPGM_DIM * n;
  const int nk = bg.n < nd->n ? bg.n : nd->n;
  for (int k = 0; k < nk; k++) {
    const int i = bg.lglob[k];
    if (i < 0 || (size_t)i >= n) continue;
    act[i] = 1.0;
    mass[i] = nd->mass[k];
    for (int c = 0; c < MPGM_DIM; c++) {
      vel[MPGM_DIM * i + c] = nd->v_new[MPGM_DIM * k + c];
      du[MPGM_DIM * i + c] = nd->du[MPGM_DIM * k + c];
    }
  }
  fr->gf[0] = (mpgm_vtk_field){"active", MPGM_VTK_SCALAR, act};
  fr->gf[1] = (mpgm_vtk_field){"mass", MPGM_VTK_SCALAR, mass};
  fr->gf[2] = (mpgm_vtk_field){"velocity", MPGM_VTK_VECTOR, vel};
  fr->gf[3] = (mpgm_vtk_field){"displacement_increment", MPGM_VTK_VECTOR, du};
  fr->grid = (mpgm_vtu_piece){o->grid_nnode, o->grid_x, o->grid_ncell, o->grid_ptr,
                              o->grid_node, o->grid_type, 4, fr->gf};
  return 0;
}

/* The frame of pb now into fr (fr->scratch owned by it: frame_free). */
static int frame_gather(mpgm_ctx *ctx, const mpgm_output *o, const mpgm_problem *pb, frame *fr) {
  const mpgm_scene *s = o->scene;
  mpgm_report r;
  mpgm_problem_report(pb, &r);
  memset(fr, 0, sizeof *fr);
  fr->time = s->analysis == MPGM_ANALYSIS_STATIC ? r.lambda : r.t;
  fr->step = r.step;
  const mpgm_points *P = mpgm_problem_points(pb);
  const size_t n = (size_t)P->n;
  MPGM_ALLOC(ctx, fr->scratch, 5 * n);
  double *J = fr->scratch, *matid = J + n, *id = matid + n, *epsp = id + n, *body = epsp + n;
  /* eps_p: only when a material is plastic (elastic runs keep their files) */
  const int with_epsp = (s->fields & MPGM_FIELD_EPS_P) && mpgm_problem_effects(pb)->plasticity;
  for (size_t p = 0; p < n; p++) {
    J[p] = mpgm_det(P->F + MPGM_TENSOR * p);
    matid[p] = P->mat[p];
    id[p] = P->id[p];
    body[p] = P->body[p];
  }
  if (with_epsp) mpgm_points_plastic_strain(P, s->mats, epsp);
  mpgm_vtk_field *f = fr->pf;
  int nf = 0;
  const unsigned m = s->fields;
  if (m & MPGM_FIELD_DISPLACEMENT) f[nf++] = (mpgm_vtk_field){"displacement", MPGM_VTK_VECTOR, P->u};
  if (m & MPGM_FIELD_VELOCITY) f[nf++] = (mpgm_vtk_field){"velocity", MPGM_VTK_VECTOR, P->v};
  if (m & MPGM_FIELD_ACCELERATION) f[nf++] = (mpgm_vtk_field){"acceleration", MPGM_VTK_VECTOR, P->a};
  if (m & MPGM_FIELD_STRESS) f[nf++] = (mpgm_vtk_field){"stress", MPGM_VTK_STRESS, P->sigma};
  if (m & MPGM_FIELD_MASS) f[nf++] = (mpgm_vtk_field){"mass", MPGM_VTK_SCALAR, P->mass};
  if (m & MPGM_FIELD_VOLUME) f[nf++] = (mpgm_vtk_field){"volume", MPGM_VTK_SCALAR, P->vol};
  if (m & MPGM_FIELD_J) f[nf++] = (mpgm_vtk_field){"J", MPGM_VTK_SCALAR, J};
  if (m & MPGM_FIELD_MATERIAL) f[nf++] = (mpgm_vtk_field){"material", MPGM_VTK_SCALAR, matid};
  if (m & MPGM_FIELD_ID) f[nf++] = (mpgm_vtk_field){"id", MPGM_VTK_SCALAR, id};
  if (with_epsp) f[nf++] = (mpgm_vtk_field){"eps_p", MPGM_VTK_SCALAR, epsp};
  if (m & MPGM_FIELD_BODY) f[nf++] = (mpgm_vtk_field){"body", MPGM_VTK_SCALAR, body};
  fr->points = (mpgm_vtu_piece){P->n, P->x, 0, NULL, NULL, NULL, nf, f};
  mpgm_cells c;
  fr->has_mesh = mpgm_problem_cells(pb, &c);
  if (fr->has_mesh) {
    const mpgm_nodes *nd = mpgm_problem_nodes(pb);
    fr->mf[0] = (mpgm_vtk_field){"displacement", MPGM_VTK_VECTOR, nd->u};
    fr->mesh = (mpgm_vtu_piece){nd->n, nd->x, c.n, c.ptr, c.node, c.type, 1, fr->mf};
  }
  return o->grid_x ? frame_grid(ctx, o, pb, fr) : 0;
}

/* A run on many processes: the frame as one piece per process, each
 * process's points (vtk/points_NNNNNN_R.vtu, R its rank), and the first
 * process's vtk/points_NNNNNN.pvtu that lists them, the entry of the
 * series. Each step is agreed, so that a piece that could not be written
 * fails the frame on every process. */
static int frame_pieces(mpgm_ctx *ctx, mpgm_output *o, const frame *fr, int k, int enc) {
  MPGM_CHECK(ctx, k == 0, MPGM_ERR_INTERNAL, "a %s series on many processes", kind_name[k]);
  char stem[64], path[MPGM_PATH_LEN + 128];
  snprintf(stem, sizeof stem, "%s_%06d", kind_name[k], o->nvtk);
  snprintf(path, sizeof path, "%s/vtk/%s_%d.vtu", o->dir, stem, o->rank);
  MPGM_CALL(mpgm_agree(ctx, mpgm_vtu_write(ctx, path, enc, fr->time, &fr->points)));
  int err = 0;
  if (o->rank == 0) {
    snprintf(path, sizeof path, "%s/vtk/%s.pvtu", o->dir, stem);
    err = mpgm_pvtu_write(ctx, path, &fr->points, o->nproc, stem);
    char rel[80];
    snprintf(rel, sizeof rel, "vtk/%s.pvtu", stem);
    if (!err) err = mpgm_pvd_add(o->series[0][k], ctx, fr->time, rel);
  }
  MPGM_CALL(mpgm_agree(ctx, err));
  o->files += 1 + o->nproc; /* the pieces and their index */
  return 0;
}

/* The frame as the next file of series (format f, kind k: points, mesh,
 * grid) and its entry. */
static int frame_write(mpgm_ctx *ctx, mpgm_output *o, const frame *fr, int f, int k) {
  const mpgm_scene *s = o->scene;
  const mpgm_vtu_piece *p = k == 2 ? &fr->grid : k ? &fr->mesh : &fr->points;
  static const char *const title_kind[SERIES_KINDS] = {"material points", "mesh", "background grid"};
  char rel[64], path[MPGM_PATH_LEN + 128], title[256];
  snprintf(rel, sizeof rel, "vtk/%s_%06d.%s", kind_name[k], o->nvtk, f ? "vtk" : "vtu");
  snprintf(path, sizeof path, "%s/%s", o->dir, rel);
  const int enc = s->vtk == MPGM_VTK_OUT_ASCII ? MPGM_VTU_ASCII
                  : s->compress == MPGM_COMPRESS_ZLIB ? MPGM_VTU_ZLIB : MPGM_VTU_RAW;
  if (o->nproc > 1) return frame_pieces(ctx, o, fr, k, enc); /* (only .vtu points: frontend_check) */
  if (f == 0) {
    MPGM_CALL(mpgm_vtu_write(ctx, path, enc, fr->time, p));
  } else {
    snprintf(title, sizeof title, "mpgm %s %s, step %ld, t = %.9g", s->stem,
             title_kind[k], fr->step, fr->time);
    MPGM_CALL(mpgm_vtk_write(ctx, path, s->vtk == MPGM_VTK_OUT_BINARY, title, p->npoints, p->x,
                             p->ncells, p->cell_ptr, p->conn, p->cell_type, p->nfields, p->fields));
  }
  MPGM_CALL(mpgm_pvd_add(o->series[f][k], ctx, fr->time, rel));
  o->files++;
  return 0;
}

int mpgm_output_vtk(mpgm_ctx *ctx, mpgm_output *o, const mpgm_problem *pb) {
  if (o->scene->vtk == MPGM_VTK_NONE) return 0;
  frame fr;
  int err = mpgm_agree(ctx, frame_gather(ctx, o, pb, &fr));
  /* every format of the frame from the same gathered data */
  for (int f = 0; !err && f < SERIES_FORMATS; f++)
    for (int k = 0; !err && k < SERIES_KINDS; k++)
      if (o->series[f][k]) err = frame_write(ctx, o, &fr, f, k);
  if (!err && o->xdmf)
    err = mpgm_xdmf_frame(o->xdmf, ctx, fr.time, fr.step, &fr.points, fr.has_mesh ? &fr.mesh : NULL);
  free(fr.scratch);
  free(fr.gscratch);
  MPGM_CALL(err);
  o->nvtk++;
  return 0;
}

void mpgm_output_momentum_gap(const mpgm_output *o, double *gap, double *kmax) {
  *gap = *kmax = 0.0;
  for (int k = 0; k < o->nstep; k++) { /* kinetic energy, ...; the points' momentum, the nodes' */
    const double *r = o->steps + (size_t)STEP_COLS * k + STEP_BASE;
    double g = 0.0; /* 2-D: hypot(0, dx) = |dx|, then hypot(dx, dy) as before */
    for (int c = 0; c < MPGM_DIM; c++) g = hypot(g, r[4 + c] - r[4 + MPGM_DIM + c]);
    *gap = fmax(*gap, g);
    *kmax = fmax(*kmax, r[0]);
  }
}
