/* main.c -- the mpgm command line: run, check, material, bench-solvers;
 * study, plot and render (study.h). Only app/ decides exit codes: 0 success,
 * 1 simulation failed, 2 bad input, 3 I/O error; a run stopped by SIGINT or
 * SIGTERM after a step, 128 + the signal (as the shell reports a signal). */
#define _XOPEN_SOURCE 700
#include <cjson/cJSON.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "bench_solvers.h"
#include "material_driver.h"
#include "exit_code.h"
#include "help.h"
#include "mpgm_checkpoint.h"
#include "mpgm_file.h"
#include "mpgm_json_reader.h"
#include "mpgm_parallel.h"
#include "mpgm_run.h"
#include "mpgm_scene_io.h"
#include "study.h"

static void usage(FILE *f) { mpgm_help_overview(f); }

typedef struct args {
  const char *cmd, *scene, *out, *restart;
  const char **sets;
  int nset, progress;
  int per_iteration, force;
} args;

static int parse_args(int argc, char **argv, args *a) {
  memset(a, 0, sizeof *a);
  a->progress = 1; /* in place on a terminal, plain lines elsewhere (term_logger) */
  a->sets = calloc((size_t)argc, sizeof(char *));
  if (!a->sets) return EXIT_IO;
  a->cmd = argv[1];
  for (int i = 2; i < argc; i++) {
    const char *s = argv[i];
    if (strcmp(s, "--set") == 0 || strcmp(s, "--out") == 0 || strcmp(s, "--restart") == 0) {
      if (i + 1 >= argc) {
        fprintf(stderr, "mpgm: %s needs a value\n", s);
        return EXIT_INPUT;
      }
      if (s[2] == 's') a->sets[a->nset++] = argv[++i];
      else if (s[2] == 'r') a->restart = argv[++i];
      else a->out = argv[++i];
    } else if (strncmp(s, "--set=", 6) == 0) {
      a->sets[a->nset++] = s + 6;
    } else if (strncmp(s, "--out=", 6) == 0) {
      a->out = s + 6;
    } else if (strcmp(s, "--progress") == 0) {
      a->progress = 1;
    } else if (strcmp(s, "--quiet") == 0) {
      a->progress = 0;
    } else if (strcmp(s, "--force") == 0 && strcmp(a->cmd, "run") == 0) {
      a->force = 1;
    } else if (strcmp(s, "--time-split") == 0) {
      a->per_iteration = 1;
    } else if (s[0] == '-' && s[1] == '-') {
      fprintf(stderr, "mpgm: unknown option %s\n", s);
      usage(stderr);
      return EXIT_INPUT;
    } else if (!a->scene) {
      a->scene = s;
    } else {
      fprintf(stderr, "mpgm: unexpected argument %s (one scene per run)\n", s);
      return EXIT_INPUT;
    }
  }
  if (a->restart && strcmp(a->cmd, "run") != 0) {
    fprintf(stderr, "mpgm %s: --restart is an option of mpgm run\n", a->cmd);
    return EXIT_INPUT;
  }
  if (a->restart && a->out && strcmp(a->out, a->restart) != 0) {
    fprintf(stderr, "mpgm run: --restart %s continues in its own folder; --out %s names another\n",
            a->restart, a->out);
    return EXIT_INPUT;
  }
  if (!a->scene && !a->restart) {
    fprintf(stderr, "mpgm %s: no SCENE given\n", a->cmd);
    usage(stderr);
    return EXIT_INPUT;
  }
  return EXIT_OK;
}

/* What reaches the console: warnings (step cuts) and errors on stderr as
 * "mpgm: ...", information (a step's time split) on stdout. Progress goes
 * to stderr: on a terminal one line rewritten in place; otherwise (a file,
 * a pipe, a batch log) a plain line at most every interval seconds and the
 * last one at the run's end (progress_end), with no carriage return and no
 * escape code. */
typedef struct term_log {
  int tty;         /* stderr is a terminal                                */
  int open_line;   /* a progress line is on the terminal, not ended        */
  double interval; /* seconds between plain progress lines                 */
  double last;     /* when the last plain line was printed (-1: none yet)  */
  int pending;     /* line holds a progress line not printed               */
  char line[512];
} term_log;

/* Seconds between the plain progress lines: MPGM_PROGRESS_INTERVAL (for
 * tests: a number in [0, 3600]), else 5. */
#define PROGRESS_INTERVAL 5.0
static double progress_interval(void) {
  const char *v = getenv("MPGM_PROGRESS_INTERVAL");
  char *end;
  const double x = v && *v ? strtod(v, &end) : PROGRESS_INTERVAL;
  return v && *v && (*end || !(x >= 0.0 && x <= 3600.0)) ? PROGRESS_INTERVAL : x;
}

static double mono_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void term_logger(void *user, int level, const char *msg) {
  term_log *t = user;
  if (level == MPGM_LOG_PROGRESS && t->tty) {
    fprintf(stderr, "\r\033[K%s", msg);
    fflush(stderr);
    t->open_line = 1;
    return;
  }
  if (level == MPGM_LOG_PROGRESS) {
    const double now = mono_now();
    snprintf(t->line, sizeof t->line, "%s", msg);
    t->pending = 1;
    if (t->last < 0.0) t->last = now; /* the first line after one interval */
    if (now - t->last >= t->interval) {
      fprintf(stderr, "%s\n", msg);
      fflush(stderr);
      t->last = now;
      t->pending = 0;
    }
    return;
  }
  if (t->open_line && level != MPGM_LOG_INFO) {
    fputc('\n', stderr);
    t->open_line = 0;
  }
  if (level == MPGM_LOG_INFO) printf("%s\n", msg);
  else fprintf(stderr, "mpgm: %s\n", msg);
}

/* The run's end: the terminal's line ended, or the last plain line. */
static void progress_end(term_log *t) {
  if (t->open_line) fputc('\n', stderr);
  else if (t->pending) fprintf(stderr, "%s\n", t->line);
  t->open_line = t->pending = 0;
}

static int report_error(const mpgm_ctx *ctx, int code) {
  if (MPGM_DIM == 2 && code == MPGM_ERR_DIMENSION) return EXIT_HANDOFF; /* a 3-D scene: mpgm-3d's */
  fprintf(stderr, "mpgm: %s\n", ctx->msg[0] ? ctx->msg : mpgm_code_str(code));
  return mpgm_exit_code(code);
}

static int cmd_check(const args *a, mpgm_ctx *ctx) {
  mpgm_scene *s = NULL;
  int err = mpgm_scene_load(ctx, a->scene, a->nset, a->sets, &s);
  /* what PETSc makes of solver.petsc, as mpgm run judges it */
  if (!err) err = mpgm_scene_check_solver(ctx, s);
  if (err) {
    mpgm_scene_destroy(&s);
    return report_error(ctx, err);
  }
  char *text = mpgm_scene_resolved_json(s);
  mpgm_effects fx;
  mpgm_effects_of_scene(s, &fx);
  cJSON *e = mpgm_effects_json(&fx);
  char *et = cJSON_Print(e);
  printf("%s\n", text ? text : "{}");
  printf("effects: %s\n", et ? et : "{}");
  char on[256] = "", off[256] = "";
  for (const cJSON *c = e->child; c; c = c->next) {
    char *l = cJSON_IsTrue(c) ? on : off;
    size_t n = strlen(l);
    snprintf(l + n, 256 - n, "%s%s", n ? ", " : "", c->string);
  }
  printf("effects that will run: %s; absent (cost nothing): %s\n", on[0] ? on : "none", off[0] ? off : "none");
  printf("scene %s is valid: %s, method %s, shape %s, %d material(s), %d body(ies), %d boundary "
         "condition(s), %d probe(s)\n",
         a->scene, MPGM_DIM == 2 ? "plane strain" : "3-D", s->frontend->name, s->shape->name, s->nmat,
         s->nbody, s->nbc, s->nprobe);
  mpgm_size z; /* the loader checked it against what is available */
  mpgm_scene_size(s, &z);
  char est[512];
  const char *what = NULL;
  mpgm_size_format(&z, est, sizeof est);
  const double avail = mpgm_memory_available(&what);
  printf("memory: the run needs %s; %.3g GiB available (%s)\n", est, avail / 1073741824.0, what);
  free(text);
  free(et);
  cJSON_Delete(e);
  mpgm_scene_destroy(&s);
  return EXIT_OK;
}

static int cmd_material(const args *a, mpgm_ctx *ctx) {
  if (a->nset) {
    fprintf(stderr, "mpgm material: --set is not supported; edit %s\n", a->scene);
    return EXIT_INPUT;
  }
  char csv[4096];
  if (a->out) {
    snprintf(csv, sizeof csv, "%s", a->out);
  } else {
    const char *base = strrchr(a->scene, '/');
    snprintf(csv, sizeof csv, "%s", base ? base + 1 : a->scene);
    char *dot = strrchr(csv, '.');
    if (dot && dot != csv) *dot = '\0';
    strncat(csv, ".csv", sizeof csv - strlen(csv) - 1);
  }
  /* the CSV must not replace the input: --out naming it, a hard link of
   * it, or an input named like the default */
  const mpgm_write_path out = {csv, MPGM_WRITE_FILE};
  int err = mpgm_refuse_overwrite(ctx, &out, 1, &a->scene, 1);
  if (err && !a->out)
    snprintf(ctx->msg + strlen(ctx->msg), sizeof ctx->msg - strlen(ctx->msg),
             " (%s is the default output: the input's name with .csv, in the current folder; "
             "give --out FILE.csv)", csv);
  if (!err) err = mpgm_material_driver(ctx, a->scene, csv);
  if (err) {
    const int rc = report_error(ctx, err);
    if (rc == EXIT_SIM) fprintf(stderr, "mpgm: the increments before the failure are in %s\n", csv);
    return rc;
  }
  printf("results: %s\n", csv);
  return EXIT_OK;
}

/* The first path at which two JSON values differ, into path (n bytes);
 * 0 when they are equal. */
static int first_difference(const cJSON *x, const cJSON *y, const char *at, char *path, size_t n) {
  if (cJSON_Compare(x, y, 1)) return 0;
  if (cJSON_IsObject(x) && cJSON_IsObject(y)) {
    for (const cJSON *c = x->child; c; c = c->next) {
      char sub[1024];
      snprintf(sub, sizeof sub, "%s%s%s", at, at[0] ? "." : "", c->string);
      if (first_difference(c, cJSON_GetObjectItemCaseSensitive(y, c->string), sub, path, n)) return 1;
    }
    for (const cJSON *c = y->child; c; c = c->next)
      if (!cJSON_GetObjectItemCaseSensitive(x, c->string)) {
        snprintf(path, n, "%s%s%s", at, at[0] ? "." : "", c->string);
        return 1;
      }
  }
  snprintf(path, n, "%s", at[0] ? at : "(root)");
  return 1;
}

/* mpgm run --restart DIR [SCENE]: the checkpoint, and the scene it
 * continues (SCENE, or the checkpoint's own, with the --set overrides),
 * which must be the scene the checkpoint was written for, but for the
 * keys that cannot change a result (RESTART_FREE). */
static const char *const RESTART_FREE[] = {
    "threads", /* mpgm's loops give the same bits on any number of threads */
};

static int restart_scene(const args *a, mpgm_ctx *ctx, mpgm_checkpoint *ck, mpgm_scene **s) {
  MPGM_CALL(mpgm_checkpoint_read(ctx, a->restart, ck));
  if (a->scene) MPGM_CALL(mpgm_scene_load(ctx, a->scene, a->nset, a->sets, s));
  else MPGM_CALL(mpgm_scene_load_text(ctx, ck->file, ck->scene_json, strlen(ck->scene_json), a->nset,
                                      a->sets, s));
  char *text = mpgm_scene_resolved_json(*s);
  cJSON *now = text ? cJSON_Parse(text) : NULL, *then = cJSON_Parse(ck->scene_json);
  for (size_t i = 0; i < sizeof RESTART_FREE / sizeof *RESTART_FREE; i++) {
    cJSON_DeleteItemFromObjectCaseSensitive(now, RESTART_FREE[i]);
    cJSON_DeleteItemFromObjectCaseSensitive(then, RESTART_FREE[i]);
  }
  char path[1024] = "";
  const int differ = !now || !then || first_difference(then, now, "", path, sizeof path);
  free(text);
  cJSON_Delete(now);
  cJSON_Delete(then);
  MPGM_CHECK(ctx, !differ, MPGM_ERR_INPUT, "%s: written for another scene (%s differs): restart "
             "with the scene and --set the run was started with, or with no scene", ck->path, path);
  return 0;
}

/* A resolved scene without what cannot change a run's result. */
static void comparable(cJSON *j) {
  cJSON_DeleteItemFromObjectCaseSensitive(j, "description");
  for (size_t i = 0; i < sizeof RESTART_FREE / sizeof *RESTART_FREE; i++)
    cJSON_DeleteItemFromObjectCaseSensitive(j, RESTART_FREE[i]);
  cJSON_DeleteItemFromObjectCaseSensitive(cJSON_GetObjectItemCaseSensitive(j, "output"), "dir");
}

/* A new run into a folder that holds a run (DIR/summary.json): the same
 * scene (its resolved form, but for the keys that cannot change a result
 * and the folder itself) runs again in place, said on stderr, as a
 * deterministic repeat loses nothing; a run of another scene is refused
 * (exit 2) unless --force, naming the folder, what it holds and the ways
 * on. 0 to go on, else the exit code. */
static int earlier_run(const args *a, const mpgm_scene *s, const char *dir) {
  char path[4200];
  snprintf(path, sizeof path, "%s/summary.json", dir);
  if (access(path, F_OK) != 0) return EXIT_OK;
  mpgm_ctx quiet;
  mpgm_ctx_init(&quiet);
  cJSON *doc = NULL;
  if (jr_parse_file(&quiet, path, &doc)) { /* not a summary mpgm wrote: nothing to keep */
    cJSON_Delete(doc);
    return EXIT_OK;
  }
  const cJSON *st = cJSON_GetObjectItemCaseSensitive(doc, "status");
  const cJSON *file = cJSON_GetObjectItemCaseSensitive(doc, "scene_file");
  cJSON *then = cJSON_DetachItemFromObjectCaseSensitive(doc, "scene");
  if (!cJSON_IsObject(then)) { /* no resolved scene: not a run mpgm recorded, nothing to keep */
    cJSON_Delete(then);
    cJSON_Delete(doc);
    return EXIT_OK;
  }
  char *text = mpgm_scene_resolved_json(s);
  cJSON *now = text ? cJSON_Parse(text) : NULL;
  free(text);
  comparable(then);
  comparable(now);
  char differ[1024] = "";
  const int other = !then || !now || first_difference(then, now, "", differ, sizeof differ);
  const char *status = cJSON_IsString(st) ? st->valuestring : "unknown";
  const char *of = cJSON_IsString(file) ? file->valuestring : "an unknown scene";
  char ck[4200];
  snprintf(ck, sizeof ck, "%s/checkpoint.mpgm", dir);
  const int resumable = strcmp(status, "interrupted") == 0 && access(ck, F_OK) == 0;
  int rc = EXIT_OK;
  if (!other)
    fprintf(stderr, "mpgm: %s holds a %s run of this scene (%s): running it again in place\n", dir,
            status, of);
  else if (a->force)
    fprintf(stderr, "mpgm: %s holds a %s run of another scene (%s; %s differs): replacing it (--force)\n",
            dir, status, of, differ[0] ? differ : "the scene");
  else {
    fprintf(stderr, "mpgm: %s holds a %s run of another scene (%s; %s differs): not replaced; give "
            "--force to replace it, or --out another folder%s%s\n", dir, status, of,
            differ[0] ? differ : "the scene", resumable ? ", or continue it with mpgm run --restart " : "",
            resumable ? dir : "");
    rc = EXIT_INPUT;
  }
  cJSON_Delete(then);
  cJSON_Delete(now);
  cJSON_Delete(doc);
  return rc;
}

/* The summary line, the last line of a run's console output (stdout):
 * status, steps, step cuts, the main metrics (mpgm_run_outcome), the time
 * reached when the run did not complete, wall time, the results folder. */
static void summary_line(const mpgm_run_outcome *oc, const mpgm_scene *s, const char *dir) {
  char abs[4096];
  const int done = strcmp(oc->status, "completed") == 0;
  printf("summary: %s, %ld step%s, %ld step cut%s", oc->status, oc->steps, oc->steps == 1 ? "" : "s",
         oc->step_cuts, oc->step_cuts == 1 ? "" : "s");
  if (!done) printf(", stopped at %s %.6g", s->analysis == MPGM_ANALYSIS_STATIC ? "load" : "t =", oc->t);
  for (int i = 0; i < oc->nmetric; i++)
    printf("%s %s = %.6g", i ? "," : (done ? ", metrics:" : ", metrics at the stop:"), oc->metric[i].name,
           oc->metric[i].value);
  printf(", wall %.3g s, results %s\n", oc->wall, realpath(dir, abs) ? abs : dir);
  fflush(stdout);
}

/* The signal that asked `mpgm run` to stop (0: none). Once the run is set
 * up (run_running, mpgm_run_opts.running) it stops at the next Newton
 * iteration or step and writes its records (mpgm_run_opts.stop); before,
 * in the set-up (the bodies filled, the nodes and points made: nothing of
 * the run is written yet, and it may take seconds), the process ends at
 * once, by the signal's own action.
 * The handler resets itself, so a second signal ends the process at once. */
static volatile sig_atomic_t run_stop = 0, run_running = 0;
static void on_run_stop(int sig) {
  static const char msg[] = "\nmpgm: stopping at the next Newton iteration or step (again to stop at once)\n";
  static const char now[] = "\nmpgm: stopped during the set-up: nothing of the run was written\n";
  if (!run_running) {
    if (write(STDERR_FILENO, now, sizeof now - 1) < 0) { /* nothing to do */ }
    signal(sig, SIG_DFL);
    raise(sig);
    return;
  }
  run_stop = sig;
  if (write(STDERR_FILENO, msg, sizeof msg - 1) < 0) { /* nothing to do */ }
}

static void run_signals(int on) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on ? on_run_stop : SIG_DFL;
  sa.sa_flags = on ? (int)SA_RESETHAND : 0;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
}

static int cmd_run(const args *a, mpgm_ctx *ctx) {
  mpgm_scene *s = NULL;
  mpgm_checkpoint ck = {0};
  int err = a->restart ? restart_scene(a, ctx, &ck, &s) : mpgm_scene_load(ctx, a->scene, a->nset, a->sets, &s);
  if (err) {
    mpgm_checkpoint_free(&ck);
    mpgm_scene_destroy(&s);
    return report_error(ctx, err);
  }
  const char *dir = a->restart ? a->restart : a->out ? a->out : s->out_dir;
  /* the scene kept in its results folder under a name the run writes is
   * refused (a restart's checkpoint.mpgm is read whole before it is
   * rewritten, so it is no input here) */
  err = mpgm_refuse_run_overwrite(ctx, dir, &a->scene, 1);
  const int held = err || a->restart ? EXIT_OK : earlier_run(a, s, dir);
  if (err || held) {
    mpgm_checkpoint_free(&ck);
    mpgm_scene_destroy(&s);
    return err ? report_error(ctx, err) : held;
  }
  mpgm_run_outcome oc = {0};
  mpgm_run_opts opts = {.out_dir = dir, .per_iteration = a->per_iteration,
                        .restart = a->restart ? &ck : NULL, .stop = &run_stop, .running = &run_running,
                        .outcome = &oc};
  term_log tl = {.tty = isatty(STDERR_FILENO), .interval = progress_interval(), .last = -1.0};
  mpgm_ctx_set_logger(ctx, term_logger, &tl, a->progress ? MPGM_LOG_PROGRESS : MPGM_LOG_INFO);
  run_signals(1);
  err = mpgm_run(ctx, s, &opts);
  run_signals(0);
  progress_end(&tl);
  int rc;
  if (err == MPGM_ERR_INTERRUPTED) { /* the shell's code of a signal's end */
    fprintf(stderr, "mpgm: %s\n", ctx->msg);
    rc = 128 + (run_stop ? run_stop : SIGTERM); /* MPGM_TEST_FAULT interrupt: as SIGTERM */
  } else if (err) {
    rc = report_error(ctx, err);
    /* only when the run wrote its summary: a run that failed before its
     * first output (the set-up ran out of memory) has none to point to */
    char sum[4200];
    snprintf(sum, sizeof sum, "%s/summary.json", dir);
    if (rc == EXIT_SIM && access(sum, F_OK) == 0)
      fprintf(stderr, "mpgm: output written up to the last completed step is in %s "
              "(summary.json says where the run stopped)\n", dir);
    else if (rc == EXIT_SIM)
      fprintf(stderr, "mpgm: the run stopped before writing any output (no summary.json in %s)\n", dir);
  } else {
    char abs[4096], series[256];
    printf("results: %s (summary.json, probes.csv, steps.csv%s)\n", realpath(dir, abs) ? abs : dir,
           mpgm_output_series_names(s, s->frontend->cells != NULL, series, sizeof series));
    rc = EXIT_OK;
  }
  if (oc.set) summary_line(&oc, s, dir); /* the last line, whatever happened */
  mpgm_checkpoint_free(&ck);
  mpgm_scene_destroy(&s);
  return rc;
}

/* Parse a whole argument as a number in [lo, hi]; 0 or -1. */
static int parse_num(const char *s, double lo, double hi, double *out) {
  char *end;
  errno = 0;
  const double v = strtod(s, &end);
  if (end == s || *end != '\0' || errno || !(v >= lo && v <= hi)) return -1;
  *out = v;
  return 0;
}

static int cmd_bench_solvers(int argc, char **argv) {
  mpgm_bench_opts o = {.repeat = 3, .solver = mpgm_solver_opts_default()};
  for (int i = 2; i < argc; i++) {
    const char *s = argv[i];
    if (s[0] == '-' && s[1] == '-') {
      const char *v = i + 1 < argc ? argv[i + 1] : NULL;
      double x = 0.0;
      int ok = v != NULL;
      if (strcmp(s, "--out") == 0) {
        o.csv = v;
      } else if (strcmp(s, "--only") == 0) {
        o.only = v;
      } else if (strcmp(s, "--repeat") == 0) {
        ok = ok && parse_num(v, 1, 1000, &x) == 0 && x == (int)x;
        o.repeat = (int)x;
      } else if (strcmp(s, "--tol") == 0) {
        ok = ok && parse_num(v, 0, 1, &x) == 0 && x > 0.0 && x < 1.0;
        o.solver.tol = x;
      } else if (strcmp(s, "--restart") == 0) {
        ok = ok && parse_num(v, 1, 1000, &x) == 0 && x == (int)x;
        o.solver.restart = (int)x;
      } else if (strcmp(s, "--max-iterations") == 0) {
        ok = ok && parse_num(v, 1, 1e7, &x) == 0 && x == (int)x;
        o.solver.max_iter = (int)x;
      } else {
        fprintf(stderr, "mpgm bench-solvers: unknown option %s\n", s);
        usage(stderr);
        return EXIT_INPUT;
      }
      if (!ok) {
        fprintf(stderr, "mpgm bench-solvers: %s: expected %s, found %s\n", s,
                strcmp(s, "--out") == 0    ? "a file name"
                : strcmp(s, "--only") == 0 ? "a comma-separated list of backends"
                : strcmp(s, "--tol") == 0  ? "a number in (0, 1)"
                : strcmp(s, "--repeat") == 0 || strcmp(s, "--restart") == 0 ? "an integer in [1, 1000]"
                                                                           : "an integer in [1, 1e7]",
                v ? v : "nothing");
        return EXIT_INPUT;
      }
      i++;
    } else if (!o.dir) {
      o.dir = s;
    } else {
      fprintf(stderr, "mpgm bench-solvers: unexpected argument %s (one folder)\n", s);
      return EXIT_INPUT;
    }
  }
  if (!o.dir) {
    fprintf(stderr, "mpgm bench-solvers: no DIR given\n");
    usage(stderr);
    return EXIT_INPUT;
  }
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  const int err = mpgm_bench_solvers(&ctx, &o, stdout);
  return err ? report_error(&ctx, err) : EXIT_OK;
}

/* MPGM_TEST_FAULT=KIND:STEP:TIMES (tests/scripts/failure_kinds.sh): make
 * one kind of recoverable failure on purpose (mpgm_fault). Returns 0, or
 * EXIT_INPUT with a message when the variable is malformed. */
static int test_fault(mpgm_ctx *ctx) {
  const char *v = getenv("MPGM_TEST_FAULT");
  if (!v || !*v) return 0;
  static const struct { const char *name; int code; } kinds[] = {
      {"return_map", MPGM_ERR_RETURN_MAP}, {"jacobian", MPGM_ERR_JACOBIAN},
      {"shape", MPGM_ERR_SHAPE}, {"not_converged", MPGM_ERR_NOT_CONVERGED}, {"nan", MPGM_ERR_NAN},
      {"interrupt", MPGM_ERR_INTERRUPTED}};
  char kind[32];
  long step;
  int times, used = 0;
  if (sscanf(v, "%31[a-z_]:%ld:%d%n", kind, &step, &times, &used) == 3 && v[used] == '\0' &&
      step >= 1 && times >= 0)
    for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++)
      if (strcmp(kind, kinds[i].name) == 0) {
        ctx->fault = (mpgm_fault){.code = kinds[i].code, .step = step, .times = times};
        return 0;
      }
  fprintf(stderr, "mpgm: MPGM_TEST_FAULT=%s: expected KIND:STEP:TIMES with KIND one of return_map, "
          "jacobian, shape, not_converged, nan, interrupt, STEP >= 1 and TIMES >= 0\n", v);
  return EXIT_INPUT;
}

/* Started as one of several processes by an MPI launcher (mpiexec -n 2,
 * srun with PMI; mpgm_parallel_launched): run and check run on them all;
 * the other commands run on one process, and copies of them would write
 * the same files: refused before anything is read (rank 0 says why; the
 * others exit quietly). */
static int one_process_only(const char *cmd, int *many) {
  int rank;
  const char *var;
  const int n = mpgm_parallel_launched(&rank, &var);
  *many = n > 1 ? n : 0;
  if (n == 1 || strcmp(cmd, "run") == 0 || strcmp(cmd, "check") == 0) return EXIT_OK;
  if (rank == 0)
    fprintf(stderr, "mpgm %s: started as one of %d processes (%s=%d): mpgm %s runs on one "
            "process, and the copies would write the same files; run it without mpiexec (or "
            "with -n 1); mpgm run and check run on many\n", cmd, n, var, n, cmd);
  return EXIT_INPUT;
}

/* The processes of a run under a launcher: MPI and PETSc started and the
 * context's communicator set, once the scene is known to be this build's
 * dimension (a process that has started MPI cannot become mpgm-3d:
 * EXIT_HANDOFF before, with nothing started). Every process but rank 0
 * writes nothing to the terminal. */
static int start_processes(const args *a, mpgm_ctx *ctx, int launched) {
  if (MPGM_DIM == 2 && a->scene && !a->restart) {
    mpgm_ctx quiet;
    mpgm_ctx_init(&quiet);
    mpgm_scene *s = NULL;
    const int err = mpgm_scene_load(&quiet, a->scene, a->nset, a->sets, &s);
    mpgm_scene_destroy(&s);
    if (err == MPGM_ERR_DIMENSION) return EXIT_HANDOFF;
  }
  char msg[1024];
  const mpgm_comm *comm = NULL;
  const int err = mpgm_parallel_start(&comm, msg, sizeof msg);
  atexit(mpgm_parallel_finalize); /* before the solvers' end: PETSc ends here */
  if (err) {
    fprintf(stderr, "mpgm %s: started by an MPI launcher, and MPI could not start: %s\n", a->cmd,
            msg);
    return EXIT_SIM;
  }
  if (comm->size != launched) { /* say, MPICH's mpiexec starting copies of an Open MPI program */
    int rank;
    const char *var;
    mpgm_parallel_launched(&rank, &var);
    if (rank == 0)
      fprintf(stderr, "mpgm %s: the launcher started %d processes (%s=%d), and MPI sees %d: the "
              "launcher is not of the MPI mpgm was built with (Debian's Open MPI: its mpiexec), "
              "and the copies would write the same results\n", a->cmd, launched, var, launched,
              comm->size);
    return EXIT_INPUT;
  }
  ctx->comm = comm;
  if (comm->rank != 0 && (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)))
    return EXIT_IO;
  return EXIT_OK;
}

int main(int argc, char **argv) {
#if defined(__GLIBC__)
  /* MPM rebuilds its pattern, maps and factor every step: keep freed memory
   * in the process instead of returning it to the system and faulting in
   * fresh zeroed pages the next step (2-3 % of the rolling disk's time) */
  mallopt(M_MMAP_THRESHOLD, 32 << 20); /* glibc's largest */
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
  atexit(mpgm_solver_finalize); /* PETSc and MPI, if a run started them */
  if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 ||
      (strcmp(argv[1], "help") == 0 && argc == 2)) {
    usage(argc < 2 ? stderr : stdout);
    return argc < 2 ? EXIT_INPUT : EXIT_OK;
  }
  /* mpgm help COMMAND, mpgm COMMAND --help / -h: answered here, before the
   * command reads its arguments (help.c holds every command's text) */
  const int help = strcmp(argv[1], "help") == 0;
  if (help || mpgm_help_asked(argc, argv)) {
    const char *cmd = help && !mpgm_help_asked(argc, argv) ? argv[2] : argv[1];
    if (mpgm_help_command(stdout, cmd) == 0) return EXIT_OK;
    fprintf(stderr, "mpgm help: unknown command '%s'\n", cmd);
    usage(stderr);
    return EXIT_INPUT;
  }
  if (strcmp(argv[1], "version") == 0 || strcmp(argv[1], "--version") == 0) {
    printf("mpgm %s\n", mpgm_version()); /* what a checkpoint records */
    return EXIT_OK;
  }
  int many = 0;
  const int launched = one_process_only(argv[1], &many);
  if (launched != EXIT_OK) return launched;
  if (strcmp(argv[1], "study") == 0) return mpgm_cmd_study(argc, argv);
  if (strcmp(argv[1], "plot") == 0) return mpgm_cmd_plot(argc, argv);
  if (strcmp(argv[1], "render") == 0) return mpgm_cmd_render(argc, argv);
  if (strcmp(argv[1], "bench-solvers") == 0) return cmd_bench_solvers(argc, argv);
  if (strcmp(argv[1], "run") != 0 && strcmp(argv[1], "check") != 0 &&
      strcmp(argv[1], "material") != 0) {
    fprintf(stderr, "mpgm: unknown command '%s'\n", argv[1]);
    usage(stderr);
    return EXIT_INPUT;
  }
  args a;
  int rc = parse_args(argc, argv, &a);
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  if (rc == EXIT_OK) {
    rc = test_fault(&ctx);
    if (rc == EXIT_OK && many) rc = start_processes(&a, &ctx, many);
    if (rc == EXIT_OK)
      rc = strcmp(a.cmd, "run") == 0      ? cmd_run(&a, &ctx)
           : strcmp(a.cmd, "material") == 0 ? cmd_material(&a, &ctx)
                                            : cmd_check(&a, &ctx);
  }
  free(a.sets);
  if (rc == EXIT_HANDOFF && ctx.comm) { /* a 3-D checkpoint, met once MPI had started */
    fprintf(stderr, "mpgm: %s holds a 3-D run, which mpgm-3d continues: start mpgm-3d under "
            "the launcher\n", a.restart ? a.restart : a.scene);
    return EXIT_INPUT;
  }
  /* the whole command again, by the program built for the scene's
   * dimension (nothing was written: the scene is read first) */
  if (rc == EXIT_HANDOFF) rc = mpgm_handoff(argv, a.scene);
  return rc;
}
