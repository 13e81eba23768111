/* bench_solvers.c -- `mpgm bench-solvers DIR`: the linear solver backends
 * on the systems K x = b a run wrote with output.matrices (Matrix Market,
 * core/mpgm_mtx.h). Every backend runs through the mpgm_solver_* wrappers,
 * as in a run: the times are those of the wrappers' timers. */
#define _POSIX_C_SOURCE 200809L
#include "bench_solvers.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "mpgm_file.h"
#include "mpgm_mtx.h"

#define PATH_CAP  4096
#define MAX_TYPES 32

/** A backend with its default options, or one of its presets (PETSc's
 *  KSP and PC choices), named "backend:preset". */
typedef struct config {
  const mpgm_solver_type *type;
  const mpgm_solver_preset *preset; /**< NULL: the default options */
  char name[64];
} config;

/* Held to a tolerance rather than solved to round-off. */
static int iterative(const config *c) {
  return c->type->iterative && !(c->preset && c->preset->direct);
}

/** One backend on one system. */
typedef struct result {
  const config *cfg;
  const char *status;                     /**< ok, not SPD, singular, not converged, not
                                               symmetric (skipped), out of memory, failed  */
  char msg[sizeof(((mpgm_ctx *)0)->msg)]; /**< the backend's message when it failed */
  int solved;                             /**< x holds a solution (or a last iterate)     */
  double t[3];                            /**< best analyse, factor, solve [s]            */
  mpgm_solver_stats st;                   /**< statistics of the last repeat              */
  double residual;                        /**< |A x - b| / |b| (2-norms)                   */
  double diff;                            /**< |x - x_ref| / |x_ref|; NAN without reference */
  double *x;                              /**< solution (n)                                */
} result;

static int is_dir(const char *p) {
  struct stat st;
  return stat(p, &st) == 0 && S_ISDIR(st.st_mode);
}

static int select_k(const struct dirent *e) {
  return mpgm_ends_with(e->d_name, "_K.mtx");
}

/* Status of a failed call of configuration c with code. */
static const char *status_of(const config *c, int code) {
  if (code == MPGM_ERR_SINGULAR)
    return c->type->needs_spd || (c->preset && c->preset->spd_only) ? "not SPD" : "singular";
  if (code == MPGM_ERR_LINEAR) return "not converged";
  if (code == MPGM_ERR_NOMEM) return "out of memory";
  return "failed";
}

/* Append the configuration of backend t with preset p (NULL: its default
 * options). */
static int add_config(mpgm_ctx *ctx, const mpgm_solver_type *t, const mpgm_solver_preset *p,
                      config *cfg, int *n) {
  MPGM_CHECK(ctx, *n < MAX_TYPES, MPGM_ERR_INPUT, "more than %d configurations", MAX_TYPES);
  cfg[*n] = (config){.type = t, .preset = p};
  snprintf(cfg[*n].name, sizeof cfg[*n].name, "%s%s%s", t->name, p ? ":" : "", p ? p->name : "");
  (*n)++;
  return 0;
}

/* The preset of t named `name`. */
static int find_preset(mpgm_ctx *ctx, const mpgm_solver_type *t, const char *name,
                       const mpgm_solver_preset **out) {
  char list[512] = "";
  for (int q = 0; t->presets && t->presets[q].name; q++) {
    if (strcmp(t->presets[q].name, name) == 0) {
      *out = &t->presets[q];
      return 0;
    }
    const size_t l = strlen(list);
    snprintf(list + l, sizeof list - l, "%s%s:%s", q ? ", " : "", t->name, t->presets[q].name);
  }
  MPGM_ERROR(ctx, MPGM_ERR_INPUT, "--only: %s has no preset \"%s\"%s%s%s", t->name, name,
             list[0] ? " (expected one of: " : "", list, list[0] ? ")" : "");
}

/* The configurations to run: every backend (a backend with presets: each
 * preset, its default being one of them), or the comma-separated names of
 * only ("petsc" the default options, "petsc:cg-gamg" a preset). A backend
 * that cannot be loaded (PETSc not built) is left out of "all". */
static int pick_configs(mpgm_ctx *ctx, const char *only, config *cfg, int *nc) {
  const mpgm_solver_type *const *all = mpgm_solver_types();
  *nc = 0;
  if (!only) {
    for (int i = 0; all[i]; i++) {
      char why[512];
      if (!mpgm_solver_usable(all[i]->name, why, sizeof why)) {
        fprintf(stderr, "bench-solvers: %s left out: %s\n", all[i]->name, why);
        continue;
      }
      if (!all[i]->presets) MPGM_CALL(add_config(ctx, all[i], NULL, cfg, nc));
      for (int k = 0; all[i]->presets && all[i]->presets[k].name; k++)
        MPGM_CALL(add_config(ctx, all[i], &all[i]->presets[k], cfg, nc));
    }
    return 0;
  }
  const char *p = only;
  while (*p) {
    const size_t l = strcspn(p, ",");
    char name[64];
    snprintf(name, sizeof name, "%.*s", (int)(l < 63 ? l : 63), p);
    char *colon = strchr(name, ':');
    if (colon) *colon = '\0';
    const mpgm_solver_type *t = mpgm_solver_type_find(name);
    if (!t) {
      char list[512] = "";
      for (int i = 0; all[i]; i++) {
        const size_t n = strlen(list);
        snprintf(list + n, sizeof list - n, "%s%s", i ? ", " : "", all[i]->name);
      }
      MPGM_ERROR(ctx, MPGM_ERR_INPUT,
                 "--only: unknown backend \"%s\" (expected a comma-separated "
                 "list of: %s; a backend with presets also as NAME:PRESET)",
                 name, list);
    }
    char why[512];
    MPGM_CHECK(ctx, mpgm_solver_usable(t->name, why, sizeof why), MPGM_ERR_INPUT,
               "--only: %s cannot be used: %s", t->name, why);
    const mpgm_solver_preset *pre = NULL;
    if (colon) MPGM_CALL(find_preset(ctx, t, colon + 1, &pre));
    MPGM_CALL(add_config(ctx, t, pre, cfg, nc));
    p += l;
    if (*p == ',') p++;
  }
  MPGM_CHECK(ctx, *nc > 0, MPGM_ERR_INPUT, "--only: expected backend names, found \"%s\"", only);
  return 0;
}

/* |A x - b| / |b| (2-norms; |A x - b| when b = 0). r: scratch (n). */
static double rel_residual(const mpgm_csc *A, const double *x, const double *b, double *r) {
  memset(r, 0, (size_t)A->n * sizeof(double));
  for (int j = 0; j < A->n; j++)
    for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) r[A->rowind[p]] += A->val[p] * x[j];
  double rr = 0.0, bb = 0.0;
  for (int i = 0; i < A->n; i++) {
    rr += (r[i] - b[i]) * (r[i] - b[i]);
    bb += b[i] * b[i];
  }
  return bb > 0.0 ? sqrt(rr / bb) : sqrt(rr);
}

/* One configuration on A x = b, o->repeat times on fresh instances. */
static void run_backend(const mpgm_bench_opts *o, const mpgm_csc *A, const double *b, result *r) {
  const config *cf = r->cfg;
  r->status = "ok";
  r->msg[0] = '\0';
  r->solved = 0;
  for (int k = 0; k < 3; k++) r->t[k] = INFINITY;
  if ((cf->type->needs_spd || (cf->preset && cf->preset->spd_only)) && !A->symmetric) {
    r->status = "not symmetric";
    return;
  }
  mpgm_solver_opts so = o->solver;
  so.symmetric = A->symmetric;
  if (cf->preset) snprintf(so.petsc, sizeof so.petsc, "%s", cf->preset->options);
  for (int rep = 0; rep < o->repeat; rep++) {
    mpgm_ctx c;
    mpgm_ctx_init(&c);
    mpgm_solver *s = NULL;
    int err = mpgm_solver_create(&c, cf->type, &so, &s);
    if (!err) err = mpgm_solver_analyse(s, &c, A, NULL);
    if (!err) err = mpgm_solver_factor(s, &c, A);
    int solved = 0;
    if (!err) {
      err = mpgm_solver_solve(s, &c, b, r->x);
      solved = !err || err == MPGM_ERR_LINEAR; /* an iterative backend leaves its last iterate */
    }
    if (s) mpgm_solver_get_stats(s, &r->st);
    mpgm_solver_destroy(&s);
    const int ids[3] = {MPGM_T_ANALYSE, MPGM_T_FACTOR, MPGM_T_SOLVE};
    for (int k = 0; k < 3; k++)
      if (c.t[ids[k]] > 0.0 && c.t[ids[k]] < r->t[k]) r->t[k] = c.t[ids[k]];
    r->solved = solved;
    if (err) {
      r->status = status_of(cf, err);
      snprintf(r->msg, sizeof r->msg, "%s", c.msg[0] ? c.msg : mpgm_code_str(err));
      return;
    }
  }
}

/* A CSV field: the message without commas, quotes or newlines. */
static void csv_text(FILE *f, const char *s) {
  fputc('"', f);
  for (; *s; s++) fputc(*s == '"' ? '\'' : (*s == '\n' ? ' ' : *s), f);
  fputc('"', f);
}

static void csv_num(FILE *f, double v, const char *fmt) {
  fputc(',', f);
  if (isfinite(v)) fprintf(f, fmt, v);
}

static void write_rows(FILE *csv, FILE *table, const char *name, const mpgm_csc *A,
                       const result *res, int nt) {
  for (int k = 0; k < nt; k++) {
    const result *r = &res[k];
    const int ran = strcmp(r->status, "not symmetric") != 0;
    const double fill = r->st.nnz_factor > 0 ? r->st.nnz_factor / A->nnz : NAN;
    fprintf(csv, "%s,%d,%d,%d,%s,%s", name, A->n, A->nnz, A->symmetric, r->cfg->name, r->status);
    for (int p = 0; p < 3; p++) csv_num(csv, ran ? 1e3 * r->t[p] : NAN, "%.6f");
    csv_num(csv, ran && r->st.nnz_factor > 0 ? r->st.nnz_factor : NAN, "%.0f");
    csv_num(csv, ran ? fill : NAN, "%.4f");
    csv_num(csv, ran && r->st.flops > 0 ? r->st.flops : NAN, "%.6g");
    csv_num(csv, ran && r->st.mem_peak > 0 ? r->st.mem_peak : NAN, "%.0f");
    csv_num(csv, iterative(r->cfg) && r->solved ? r->st.iterations : NAN, "%.0f");
    csv_num(csv, r->solved ? r->residual : NAN, "%.6e");
    csv_num(csv, r->solved ? r->diff : NAN, "%.6e");
    fputc(',', csv);
    csv_text(csv, r->msg);
    fputc('\n', csv);

    char t[3][32], its[16] = "", res_s[32] = "", dif[32] = "", mem[32] = "", fl[32] = "",
                   nf[32] = "";
    for (int p = 0; p < 3; p++) {
      if (ran && isfinite(r->t[p]))
        snprintf(t[p], sizeof t[p], "%.3f", 1e3 * r->t[p]);
      else
        t[p][0] = '\0';
    }
    if (ran && r->st.nnz_factor > 0) {
      snprintf(nf, sizeof nf, "%.0f", r->st.nnz_factor);
      snprintf(fl, sizeof fl, "%.2f", fill);
    }
    if (ran && r->st.mem_peak > 0) snprintf(mem, sizeof mem, "%.2f", r->st.mem_peak / 1048576.0);
    if (iterative(r->cfg) && r->solved) snprintf(its, sizeof its, "%d", r->st.iterations);
    if (r->solved) snprintf(res_s, sizeof res_s, "%.1e", r->residual);
    if (r->solved && isfinite(r->diff)) snprintf(dif, sizeof dif, "%.1e", r->diff);
    fprintf(table, "| %s | %d | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n",
            name, A->n, A->nnz, r->cfg->name, r->status, t[0], t[1], t[2], nf, fl, mem, its, res_s,
            dif);
  }
}

/* All backends on the system `base`_K.mtx / _b.mtx of folder dir. */
static int bench_one(mpgm_ctx *ctx, const mpgm_bench_opts *o, const char *dir, const char *kname,
                     const config *cfg, int nt, FILE *csv, FILE *table) {
  char kpath[PATH_CAP], bpath[PATH_CAP], name[PATH_CAP];
  const size_t stem = strlen(kname) - strlen("_K.mtx");
  snprintf(name, sizeof name, "%.*s", (int)stem, kname);
  const int lk = snprintf(kpath, sizeof kpath, "%s/%s", dir, kname);
  const int lb = snprintf(bpath, sizeof bpath, "%s/%s_b.mtx", dir, name);
  MPGM_CHECK(ctx, lk > 0 && lb > 0 && lk < PATH_CAP && lb < PATH_CAP, MPGM_ERR_INPUT,
             "%s/%s: path too long", dir, kname);
  mpgm_csc A = {0};
  double *b = NULL, *scratch = NULL;
  int nb = 0, err;
  result res[MAX_TYPES];
  memset(res, 0, sizeof res);
  err = mpgm_mtx_read_csc(ctx, kpath, &A);
  if (!err) {
    struct stat st;
    if (stat(bpath, &st) != 0)
      err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                         "%s: no right-hand side %s beside it", kpath, bpath);
  }
  if (!err) err = mpgm_mtx_read_vec(ctx, bpath, &b, &nb);
  if (!err && nb != A.n)
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                       "%s: expected %d values (the order of "
                       "%s), found %d",
                       bpath, A.n, kpath, nb);
  if (!err) {
    scratch = malloc((size_t)A.n * sizeof(double));
    for (int k = 0; k < nt && scratch; k++) {
      res[k].cfg = &cfg[k];
      res[k].x = calloc((size_t)A.n, sizeof(double));
      if (!res[k].x) break;
    }
    for (int k = 0; k < nt; k++)
      if (!scratch || !res[k].x) {
        err = mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__,
                           "out of memory (%d solutions of %d)", nt, A.n);
        break;
      }
  }
  if (!err) {
    fprintf(stderr, "bench-solvers: %s: n = %d, %d entries, %s\n", name, A.n, A.nnz,
            A.symmetric ? "symmetric" : "unsymmetric");
    const double *xref = NULL;
    for (int k = 0; k < nt; k++) {
      run_backend(o, &A, b, &res[k]);
      if (res[k].solved) res[k].residual = rel_residual(&A, res[k].x, b, scratch);
      if (strcmp(cfg[k].name, "umfpack") == 0 && strcmp(res[k].status, "ok") == 0)
        xref = res[k].x;
    }
    if (!xref) { /* UMFPACK not run or failed: the first direct backend that worked */
      for (int k = 0; k < nt && !xref; k++)
        if (!iterative(&cfg[k]) && strcmp(res[k].status, "ok") == 0) xref = res[k].x;
    }
    double nref = 0.0;
    for (int i = 0; xref && i < A.n; i++) nref += xref[i] * xref[i];
    for (int k = 0; k < nt; k++) {
      res[k].diff = NAN;
      if (!xref || !res[k].solved) continue;
      double dd = 0.0;
      for (int i = 0; i < A.n; i++) dd += (res[k].x[i] - xref[i]) * (res[k].x[i] - xref[i]);
      res[k].diff = nref > 0.0 ? sqrt(dd / nref) : sqrt(dd);
    }
    write_rows(csv, table, name, &A, res, nt);
  }
  for (int k = 0; k < nt; k++) free(res[k].x);
  free(scratch);
  free(b);
  mpgm_mtx_free_csc(&A);
  return err;
}

/* The CSV must not replace a system it reads (--out naming one, or a hard
 * link of one). */
static int refuse_overwrite(mpgm_ctx *ctx, const char *dir, struct dirent **list, int nk,
                            const char *csvpath) {
  char (*path)[PATH_CAP + 256] = calloc((size_t)(2 * nk), sizeof *path);
  const char **in = calloc((size_t)(2 * nk), sizeof *in);
  int err = path && in ? 0 : mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory");
  for (int i = 0; i < nk && !err; i++) {
    const char *k = list[i]->d_name;
    snprintf(path[2 * i], sizeof path[2 * i], "%s/%s", dir, k);
    snprintf(path[2 * i + 1], sizeof path[2 * i + 1], "%s/%.*s_b.mtx", dir, (int)(strlen(k) - strlen("_K.mtx")), k);
    in[2 * i] = path[2 * i];
    in[2 * i + 1] = path[2 * i + 1];
  }
  const mpgm_write_path out = {csvpath, MPGM_WRITE_FILE};
  if (!err) err = mpgm_refuse_overwrite(ctx, &out, 1, in, 2 * nk);
  free(path);
  free(in);
  return err;
}

int mpgm_bench_solvers(mpgm_ctx *ctx, const mpgm_bench_opts *o, FILE *table) {
  MPGM_CHECK(ctx, o && o->dir && o->repeat >= 1, MPGM_ERR_INPUT, "bench-solvers: bad arguments");
  char dir[PATH_CAP];
  MPGM_CHECK(ctx, is_dir(o->dir), MPGM_ERR_INPUT,
             "%s: not a folder (expected a run folder holding "
             "matrices/, or a matrices folder)",
             o->dir);
  MPGM_CHECK(ctx, strlen(o->dir) + 64 < PATH_CAP, MPGM_ERR_INPUT, "%.64s...: path too long",
             o->dir);
  snprintf(dir, sizeof dir, "%s/matrices", o->dir);
  if (!is_dir(dir)) snprintf(dir, sizeof dir, "%s", o->dir);
  config cfg[MAX_TYPES];
  int nt = 0;
  MPGM_CALL(pick_configs(ctx, o->only, cfg, &nt));
  struct dirent **list = NULL;
  const int nk = scandir(dir, &list, select_k, alphasort);
  MPGM_CHECK(ctx, nk >= 0, MPGM_ERR_IO, "%s: cannot list: %s", dir, strerror(errno));
  int err = 0;
  if (nk == 0)
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                       "%s: no systems NAME_K.mtx / NAME_b.mtx "
                       "(write them with mpgm run SCENE --set output.matrices=STEP)",
                       dir);
  char csvpath[PATH_CAP + 32];
  if (o->csv)
    snprintf(csvpath, sizeof csvpath, "%.*s", PATH_CAP, o->csv);
  else
    snprintf(csvpath, sizeof csvpath, "%s/bench_solvers.csv", dir);
  FILE *csv = NULL;
  if (!err) err = refuse_overwrite(ctx, dir, list, nk, csvpath);
  if (!err) err = mpgm_fopen_write(ctx, csvpath, &csv);
  if (!err) {
    /* the runs' default (solver.threads = 1); says which BLAS runs */
    const int applied = mpgm_solver_threads(1);
    fprintf(stderr, "bench-solvers: BLAS: %s\n",
            applied & 1 ? "OpenBLAS, 1 thread" : "not OpenBLAS (the reference BLAS or another)");
    fputs("matrix,n,nnz,symmetric,backend,status,analyse_ms,factor_ms,solve_ms,nnz_factor,fill,"
          "factor_flops,memory_bytes,iterations,residual,diff_ref,message\n",
          csv);
    fprintf(table,
            "| matrix | n | nnz | backend | status | analyse [ms] | factor [ms] | solve [ms] | "
            "nnz(factor) | fill | memory [MB] | iterations | residual | diff |\n");
    fprintf(table, "|---|---:|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  }
  for (int i = 0; i < nk && !err; i++)
    err = bench_one(ctx, o, dir, list[i]->d_name, cfg, nt, csv, table);
  for (int i = 0; i < nk; i++) free(list[i]);
  free(list);
  if (csv && fclose(csv) != 0 && !err)
    err = mpgm_err_set(ctx, MPGM_ERR_IO, __FILE__, __LINE__, "%s: cannot write: %s", csvpath,
                       strerror(errno));
  if (!err) fprintf(stderr, "bench-solvers: results: %s\n", csvpath);
  return err;
}
