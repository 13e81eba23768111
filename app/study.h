/* study.h -- `mpgm study`, `mpgm plot`, `mpgm render` (docs/studies.md).
 * Private to app/.
 *
 * A study file names a base scene and the --set overrides of each run:
 * the cartesian product of its "axes", times its explicit "runs" list,
 * plus fixed "set" overrides. study_file.c reads it, study.c runs it (child
 * processes of this binary), study_csv.c gathers the runs' summary.json
 * into study.csv, plot.c draws study.csv with gnuplot, render.c draws a
 * run's material points coloured by a field.
 */
#ifndef MPGM_STUDY_H
#define MPGM_STUDY_H

#include <cjson/cJSON.h>

#include "exit_code.h"
#include "mpgm_base.h"
#include "mpgm_file.h"
#include "table.h"

enum { STUDY_PATH = 4096, STUDY_NAME = 256, STUDY_MAX_RUNS = 10000, STUDY_MAX_KEYS = 32 };

/** One override: a scene path and its value as --set takes it. */
typedef struct study_kv {
  char *key;   /**< dotted scene path, or "scene" (the run's scene file) */
  char *value; /**< text after '=' (numbers in their shortest exact form) */
} study_kv;

/** What became of a run. */
typedef enum {
  RUN_PENDING = 0, /**< not run (yet)                                  */
  RUN_RUNNING,     /**< child process alive                             */
  RUN_DONE,        /**< finished in this session                         */
  RUN_SKIPPED      /**< complete from an earlier session                 */
} study_state;

typedef struct study_run {
  int nkv;
  study_kv *kv;             /**< the run's own keys: its "runs" entry,
                                 then the axes (owned)                 */
  char name[STUDY_NAME];    /**< folder name, from the keys            */
  char scene[STUDY_PATH];   /**< scene file of this run                */
  cJSON *resolved;          /**< the resolved scene (check), for resume */
  cJSON *summary;           /**< its summary.json without the scene and
                                 probes, once finished (NULL: none)     */
  /* state of this session */
  int state;                /**< study_state                           */
  int pid;                  /**< child while running                   */
  double t0, wall;          /**< start stamp, wall time of this session [s] */
  int exit_code;            /**< 0..3 as `mpgm run`; 128+sig if killed;
                                 -1 not known                          */
  char status[32];          /**< completed, failed, bad input, ...     */
  char message[512];        /**< failure message                       */
} study_run;

typedef struct mpgm_study {
  char file[STUDY_PATH];    /**< study file as given                   */
  char stem[STUDY_NAME];    /**< its name without folder and .json     */
  char scene[STUDY_PATH];   /**< base scene (resolved path)            */
  char out[STUDY_PATH];     /**< results folder                        */
  int jobs;                 /**< runs at a time                        */
  int nset;
  study_kv *set;            /**< fixed overrides of every run          */
  int nkey;
  char **keys;              /**< run keys in column order (borrowed from
                                 the runs)                             */
  int nrun;
  study_run *runs;
  char metric[128];         /**< the error the plots and progress show  */
  int has_ref;              /**< "reference" given                      */
  char ref_metric[128];     /**< its metric (a summary metrics entry)   */
  double ref_value;         /**< its reference value                    */
  cJSON *record;            /**< the study as resolved, for study.json  */
} mpgm_study;

/** Read and validate a study file ("FILE: json.path: expected ..., found
 *  ..." on MPGM_ERR_INPUT; MPGM_ERR_IO when it cannot be read). out_dir,
 *  when not NULL, replaces the file's "out"; jobs > 0 its "jobs". */
int mpgm_study_load(mpgm_ctx *ctx, const char *file, const char *out_dir, int jobs, mpgm_study *st);
/** Free a study (accepts a zeroed one). */
void mpgm_study_free(mpgm_study *st);

/** study.csv from the runs: the run keys, the "set" keys, status,
 *  message, exit_code, dir, then every scalar of each run's summary
 *  (study_run.summary, flattened with dotted names), union over the runs
 *  in run order. Written atomically to OUT/study.csv. */
int mpgm_study_write_csv(mpgm_ctx *ctx, const mpgm_study *st);
/** Read RUN/summary.json; NULL when absent, unreadable or without a
 *  "status" (not written by run.c). */
cJSON *mpgm_study_summary(const mpgm_study *st, const study_run *r);
/** The study's error metric of a summary (NAN when absent). */
double mpgm_study_metric(const mpgm_study *st, const cJSON *summary);
/** Folder of run r, OUT/runs/NAME, or with leaf a path in it: OUT/runs/NAME/LEAF. */
void mpgm_study_run_dir(const mpgm_study *st, const study_run *r, const char *leaf, char *buf,
                        size_t cap);

/** Plot options (NULL / 0: from OUT/study.json beside the CSV, else the
 *  defaults). */
typedef struct mpgm_plot_opts {
  const char *metric; /**< column of the error (or metrics.NAME)        */
  const char *x;      /**< key of the convergence plot (mesh.h)          */
  const char *series; /**< comma-separated keys that make the series     */
  const char *out;    /**< folder of the pictures (the CSV's)            */
  const char *title;  /**< title prefix (the study's name)               */
  const char *xscale; /**< x axis of the key plot: "linear", "log" (NULL: log) */
  const char *yscale; /**< its y axis: "linear", "log", "signed" (NULL: log) */
} mpgm_plot_opts;

/** Draw study_error_<x>.png/.svg and study_error_time.png/.svg from a
 *  study.csv. Errors: MPGM_ERR_INPUT (no such metric, nothing to plot),
 *  MPGM_ERR_IO (gnuplot missing or failing). */
int mpgm_plot(mpgm_ctx *ctx, const char *csv, const mpgm_plot_opts *o);

/** The files `mpgm plot` writes into dir when its x key is x:
 *  study_error_<last part of x> and study_error_time, each as .gp (written
 *  atomically), .png and .svg; their paths into names, the entries of
 *  mpgm_refuse_overwrite into w. */
enum { STUDY_PLOT_FILES = 6 };
void mpgm_plot_outputs(const char *dir, const char *x, char names[][STUDY_PATH + 96], mpgm_write_path *w);

/** Command entries: argv as main's; they return the exit code. */
int mpgm_cmd_study(int argc, char **argv);
int mpgm_cmd_plot(int argc, char **argv);
int mpgm_cmd_render(int argc, char **argv);

#endif
