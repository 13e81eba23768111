/* study.c -- `mpgm study STUDY.json`: run every run of a study as a child
 * process of this binary (`mpgm run SCENE --set ... --out OUT/runs/NAME
 * --quiet`, output to OUT/runs/NAME/log.txt), `jobs` at a time; skip runs
 * complete from an earlier session; gather study.csv after every run; draw
 * the plots at the end (docs/studies.md).
 *
 * Resume: a run is complete when OUT/runs/NAME/summary.json exists (run.c
 * writes it atomically, at the end, also when the run failed) and its
 * resolved scene is the one the study asks for now. The summary is deleted
 * before a run starts, so a run killed mid-way leaves none and runs again.
 */
#define _GNU_SOURCE /* prctl's PR_SET_PDEATHSIG, O_CLOEXEC */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#if defined(__linux__)
#include <sys/prctl.h>
#endif

#include "mpgm_output.h"
#include "mpgm_scene_io.h"
#include "mpgm_scene.h"
#include "mpgm_vtk.h"
#include "study.h"

/* The signal that asks the study to stop (0: none). The only static
 * state: a signal handler has nowhere else to write. */
static volatile sig_atomic_t stop_signal = 0;
static void on_stop(int sig) { stop_signal = sig; }
static void on_child(int sig) { (void)sig; }

typedef struct opts {
  const char *file, *out;
  int jobs, no_plot, rerun_failed, dry_run;
} opts;

static void usage_study(FILE *f) {
  fprintf(f, "usage: mpgm study STUDY.json [--jobs N] [--out DIR] [--no-plot] [--rerun-failed] [--dry-run]\n"
             "  runs every run of the study (docs/studies.md), N at a time (default: the file's\n"
             "  \"jobs\", else 2); runs complete from an earlier session are skipped\n");
}

static int parse(int argc, char **argv, opts *o) {
  memset(o, 0, sizeof *o);
  for (int i = 2; i < argc; i++) {
    const char *s = argv[i];
    if (strcmp(s, "--jobs") == 0 || strcmp(s, "--out") == 0) {
      if (i + 1 >= argc) {
        fprintf(stderr, "mpgm study: %s needs a value\n", s);
        return 2;
      }
      const char *v = argv[++i];
      if (s[2] == 'o') {
        o->out = v;
        continue;
      }
      char *end;
      long n = strtol(v, &end, 10);
      if (end == v || *end || n < 1 || n > 64) {
        fprintf(stderr, "mpgm study: --jobs: expected an integer in [1, 64], found '%s'\n", v);
        return 2;
      }
      o->jobs = (int)n;
    } else if (strcmp(s, "--no-plot") == 0) {
      o->no_plot = 1;
    } else if (strcmp(s, "--rerun-failed") == 0) {
      o->rerun_failed = 1;
    } else if (strcmp(s, "--dry-run") == 0) {
      o->dry_run = 1;
    } else if (s[0] == '-' && s[1] == '-') {
      fprintf(stderr, "mpgm study: unknown option %s\n", s);
      usage_study(stderr);
      return 2;
    } else if (!o->file) {
      o->file = s;
    } else {
      fprintf(stderr, "mpgm study: unexpected argument %s (one study file)\n", s);
      return 2;
    }
  }
  if (!o->file) {
    fprintf(stderr, "mpgm study: no STUDY file given\n");
    usage_study(stderr);
    return 2;
  }
  return 0;
}

enum { MAX_SETS = 2 * STUDY_MAX_KEYS + 1 }; /* "set" keys, run keys, threads */

static void free_sets(char **sets, int n) {
  for (int i = 0; i < n; i++) free(sets[i]);
}

/* The --set arguments of run r ("key=value"; the "set" keys first, then
 * the run's own; "scene" is not an override) into sets[MAX_SETS] (owned
 * by the caller); threads >= 1 adds threads=N. The count, or -1 when out
 * of memory (nothing left to free). */
static int run_sets(const mpgm_study *st, const study_run *r, int threads, char **sets) {
  int n = 0;
  for (int k = 0; k < st->nset + r->nkv; k++) {
    const study_kv *kv = k < st->nset ? &st->set[k] : &r->kv[k - st->nset];
    if (strcmp(kv->key, "scene") == 0) continue;
    const size_t len = strlen(kv->key) + strlen(kv->value) + 2;
    if (!(sets[n] = malloc(len))) {
      free_sets(sets, n);
      return -1;
    }
    snprintf(sets[n++], len, "%s=%s", kv->key, kv->value);
  }
  if (threads > 0) {
    if (!(sets[n] = malloc(32))) {
      free_sets(sets, n);
      return -1;
    }
    snprintf(sets[n++], 32, "threads=%d", threads);
  }
  return n;
}

/* Keep a finished run's summary (without the bulky scene and probes) for
 * study.csv and the progress lines; takes s. */
static void keep_summary(study_run *r, cJSON *s) {
  cJSON_Delete(r->summary);
  static const char *const drop[] = {"scene", "probes", "step_cuts"};
  for (size_t k = 0; s && k < sizeof drop / sizeof *drop; k++) cJSON_DeleteItemFromObjectCaseSensitive(s, drop[k]);
  r->summary = s;
}

/* What of a resolved scene decides whether a run is still valid: all but
 * the description and the loop threads (set by the study; the results do
 * not depend on them). */
static void comparable(cJSON *scene) {
  cJSON_DeleteItemFromObjectCaseSensitive(scene, "description");
  cJSON_DeleteItemFromObjectCaseSensitive(scene, "threads");
}

/* Load every run's scene with its overrides, as `mpgm check` does, so a
 * typo stops the study before anything runs; keep the resolved scenes. */
static int validate(mpgm_ctx *ctx, mpgm_study *st) {
  int bad = 0;
  char *sets[MAX_SETS];
  for (int i = 0; i < st->nrun; i++) {
    study_run *r = &st->runs[i];
    const int n = run_sets(st, r, 0, sets);
    MPGM_CHECK(ctx, n >= 0, MPGM_ERR_NOMEM, "out of memory (study)");
    mpgm_ctx c;
    mpgm_ctx_init(&c);
    mpgm_scene *s = NULL;
    const int err = mpgm_scene_load(&c, r->scene, n, (const char *const *)sets, &s);
    free_sets(sets, n);
    if (MPGM_DIM == 2 && err == MPGM_ERR_DIMENSION) /* a 3-D study: mpgm-3d's (mpgm_handoff) */
      return mpgm_err_set(ctx, err, __FILE__, __LINE__, "%s", c.msg);
    if (err) {
      if (bad++ < 10) fprintf(stderr, "mpgm study: %s: run %d (%s): %s\n", st->file, i + 1, r->name, c.msg);
      if (err != MPGM_ERR_INPUT && !ctx->code) mpgm_err_set(ctx, err, __FILE__, __LINE__, "%s", c.msg);
      continue;
    }
    r->resolved = cJSON_Duplicate((const cJSON *)s->resolved, 1);
    comparable(r->resolved);
    mpgm_scene_destroy(&s);
  }
  if (bad > 10) fprintf(stderr, "mpgm study: ... and %d more runs with bad input\n", bad - 10);
  if (ctx->code) return ctx->code; /* a scene that cannot be read */
  MPGM_CHECK(ctx, !bad, MPGM_ERR_INPUT, "%d of %d runs have bad input (above); nothing was run", bad, st->nrun);
  return 0;
}

/* Last "mpgm: " line of the run's log (its error message), from its last
 * LOG_TAIL bytes: the message is at the end, and a log that grew long
 * (warnings of every step) is not read whole. A log that is no regular
 * file (a FIFO put in its place) gives no message. */
enum { LOG_TAIL = 1 << 20 };
static void log_message(const mpgm_study *st, const study_run *r, char *buf, size_t cap) {
  char path[STUDY_PATH + STUDY_NAME + 32], line[1024];
  mpgm_study_run_dir(st, r, "log.txt", path, sizeof path);
  buf[0] = '\0';
  mpgm_ctx quiet;
  mpgm_ctx_init(&quiet);
  FILE *f;
  size_t size, left = LOG_TAIL;
  if (mpgm_fopen_regular(&quiet, path, MPGM_READ_MAX, &f, &size)) return;
  if (size > LOG_TAIL && fseeko(f, (off_t)(size - LOG_TAIL), SEEK_SET) == 0)
    if (fgets(line, sizeof line, f)) left -= strlen(line); /* a line cut by the seek */
  while (left > 0 && fgets(line, sizeof line, f)) {
    const size_t n = strlen(line);
    left = n < left ? left - n : 0;
    line[strcspn(line, "\r\n")] = '\0';
    if (strncmp(line, "mpgm: ", 6) == 0 && !strstr(line, "output written up to")) {
      size_t k = strlen(line + 6);
      if (k >= cap) k = cap - 1;
      memcpy(buf, line + 6, k);
      buf[k] = '\0';
    }
  }
  fclose(f);
}

/* Drop the empty objects of a saved scene: mpgm before 2026-11 wrote an
 * absent optional object (a body's "geostatic") as {}, which does not load. */
static void prune_empty(cJSON *j) {
  cJSON *c = j->child;
  while (c) {
    cJSON *next = c->next;
    if (cJSON_IsObject(c) || cJSON_IsArray(c)) prune_empty(c);
    if (cJSON_IsObject(c) && !c->child) cJSON_Delete(cJSON_DetachItemViaPointer(j, c));
    c = next;
  }
}

/* Does the scene an earlier run wrote (saved, made comparable) describe
 * run r? Equal trees do. Otherwise the saved scene is read again by this
 * mpgm: a key added to the scene format since that run fills in with its
 * default, which is what that run used (a new key's default keeps the old
 * behaviour), so the run stays valid unless a value really differs. */
static int same_scene(const mpgm_study *st, const study_run *r, const cJSON *saved) {
  if (cJSON_Compare(saved, r->resolved, 1)) return 1;
  char name[STUDY_PATH + STUDY_NAME + 32];
  mpgm_study_run_dir(st, r, "summary.json: scene", name, sizeof name);
  mpgm_ctx c;
  mpgm_ctx_init(&c);
  mpgm_scene *s = NULL;
  cJSON *old = cJSON_Duplicate(saved, 1);
  if (!old) return 0;
  prune_empty(old);
  const int err = mpgm_scene_load_json(&c, name, old, &s);
  cJSON_Delete(old);
  if (err) return 0; /* not a scene this mpgm reads: stale */
  cJSON *now = (cJSON *)s->resolved;
  comparable(now);
  const int same = cJSON_Compare(now, r->resolved, 1);
  mpgm_scene_destroy(&s);
  return same;
}

/* Is run r complete from an earlier session? Fills status and message. */
static int complete_earlier(const mpgm_study *st, study_run *r, int rerun_failed, int *stale) {
  *stale = 0;
  cJSON *s = mpgm_study_summary(st, r);
  if (!s) return 0;
  cJSON *scene = cJSON_GetObjectItemCaseSensitive(s, "scene");
  comparable(scene);
  const char *status = cJSON_GetObjectItemCaseSensitive(s, "status")->valuestring;
  const cJSON *msg = cJSON_GetObjectItemCaseSensitive(s, "message");
  int done = 0;
  /* a run whose outputs could not be written (disk full), or that a
   * signal stopped (the study's, or one from outside it: a batch system's
   * time limit), is not a result: it runs again, as a run with no summary
   * would */
  if (!r->resolved || !same_scene(st, r, scene)) *stale = 1;
  else if (strcmp(status, "io_error") == 0 || strcmp(status, "interrupted") == 0) done = 0;
  else if (!rerun_failed || strcmp(status, "completed") == 0) done = 1;
  if (done) {
    snprintf(r->status, sizeof r->status, "%s", status);
    snprintf(r->message, sizeof r->message, "%s", cJSON_IsString(msg) ? msg->valuestring : "");
    r->exit_code = strcmp(status, "completed") == 0 ? 0 : 1;
    keep_summary(r, s);
  } else {
    cJSON_Delete(s);
  }
  return done;
}

typedef struct session {
  mpgm_study *st;
  char exe[STUDY_PATH]; /**< this binary                            */
  int threads;          /**< loop threads of each run (0: the study's
                             own keys set them)                     */
  int width;            /**< digits of the run count                */
  sigset_t orig;        /**< signal mask to restore in the children */
  int running;          /**< children alive                          */
  int csv_err;          /**< first failure to write study.csv        */
  char csv_msg[1024];
} session;

/* "[ 3/12] what      NAME" followed by the printf text. */
#if defined(__GNUC__)
__attribute__((format(printf, 4, 5)))
#endif
static void progress(const session *ss, int i, const char *what, const char *fmt, ...) {
  fprintf(stderr, "[%*d/%d] %-9s %s", ss->width, i + 1, ss->st->nrun, what, ss->st->runs[i].name);
  va_list ap;
  va_start(ap, fmt);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fputc('\n', stderr);
}

/* ", error 1.23e-04" when the run's summary has the study's metric. */
static void metric_note(const mpgm_study *st, const study_run *r, char *buf, size_t cap) {
  buf[0] = '\0';
  const double m = r->summary ? mpgm_study_metric(st, r->summary) : NAN;
  if (isfinite(m)) snprintf(buf, cap, ", %s %.3e", st->metric, m);
}

/* Write the command line of a run to its log (shell-quoted where needed). */
static void log_command(int fd, char *const *argv) {
  dprintf(fd, "#");
  for (int i = 0; argv[i]; i++) {
    const char *a = i == 0 ? "mpgm" : argv[i];
    if (strpbrk(a, " \"'$`\\*?[]{}()<>|&;#~!") || !*a) {
      dprintf(fd, " '");
      for (const char *c = a; *c; c++) dprintf(fd, *c == '\'' ? "'\\''" : "%c", *c);
      dprintf(fd, "'");
    } else {
      dprintf(fd, " %s", a);
    }
  }
  dprintf(fd, "\n");
}

/* Start run i as a child process; a failure to start is its row. */
static void start_run(session *ss, int i) {
  mpgm_study *st = ss->st;
  study_run *r = &st->runs[i];
  char dir[STUDY_PATH + STUDY_NAME + 16], path[STUDY_PATH + STUDY_NAME + 32];
  mpgm_study_run_dir(st, r, NULL, dir, sizeof dir);
  mpgm_ctx c;
  mpgm_ctx_init(&c);
  r->state = RUN_DONE;
  r->t0 = mpgm_wtime();
  snprintf(path, sizeof path, "%s/summary.json", dir);
  int fd = -1;
  if (!mpgm_mkdir_p(&c, dir)) {
    if (unlink(path) != 0 && errno != ENOENT)
      mpgm_err_set(&c, MPGM_ERR_IO, __FILE__, __LINE__, "%s: cannot remove: %s", path, strerror(errno));
    snprintf(path, sizeof path, "%s/log.txt", dir);
    if (!c.code) mpgm_open_write(&c, path, &fd);
  }
  char *sets[MAX_SETS];
  int n = c.code ? 0 : run_sets(st, r, ss->threads, sets);
  if (n < 0) {
    n = 0;
    mpgm_err_set(&c, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory");
  }
  char *argv[2 * MAX_SETS + 8];
  int a = 0;
  argv[a++] = ss->exe;
  argv[a++] = "run";
  argv[a++] = r->scene;
  for (int k = 0; k < n; k++) {
    argv[a++] = "--set";
    argv[a++] = sets[k];
  }
  argv[a++] = "--out";
  argv[a++] = dir;
  argv[a++] = "--quiet";
  argv[a] = NULL;
  pid_t pid = -1;
  if (!c.code) {
    log_command(fd, argv);
    const pid_t parent = getpid();
    pid = fork();
    if (pid == 0) {
      struct sigaction dfl;
      memset(&dfl, 0, sizeof dfl);
      dfl.sa_handler = SIG_DFL;
      const int sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGCHLD};
      for (size_t k = 0; k < sizeof sigs / sizeof *sigs; k++) sigaction(sigs[k], &dfl, NULL);
      sigprocmask(SIG_SETMASK, &ss->orig, NULL);
      const int in = open("/dev/null", O_RDONLY);
      if (in >= 0) dup2(in, STDIN_FILENO);
      dup2(fd, STDOUT_FILENO);
      dup2(fd, STDERR_FILENO);
#if defined(__linux__)
      prctl(PR_SET_PDEATHSIG, SIGKILL); /* the study killed: its runs go too */
      if (getppid() != parent) _exit(128 + SIGKILL);
#endif
      execv(ss->exe, argv);
      fprintf(stderr, "mpgm: cannot execute %s: %s\n", ss->exe, strerror(errno));
      _exit(127);
    }
    if (pid < 0) mpgm_err_set(&c, MPGM_ERR_IO, __FILE__, __LINE__, "cannot start a run: %s", strerror(errno));
  }
  if (fd >= 0) close(fd);
  free_sets(sets, n);
  if (c.code) { /* not started: the row says why */
    snprintf(r->status, sizeof r->status, "io error");
    snprintf(r->message, sizeof r->message, "%.500s", c.msg);
    r->exit_code = 3;
    r->wall = 0.0;
    progress(ss, i, "io error", ": %s", c.msg);
    return;
  }
  r->pid = (int)pid;
  r->state = RUN_RUNNING;
  ss->running++;
  progress(ss, i, "running", "%s", "");
}

/* Record how run r ended (wait status ws). interrupted: the study stopped
 * it; it is pending again. */
static void finish_run(session *ss, int i, int ws, int interrupted) {
  const mpgm_study *st = ss->st;
  study_run *r = &st->runs[i];
  r->wall = mpgm_wtime() - r->t0;
  r->pid = 0;
  ss->running--;
  cJSON *s = mpgm_study_summary(st, r);
  const cJSON *sum_status = s ? cJSON_GetObjectItemCaseSensitive(s, "status") : NULL;
  const int stopped = cJSON_IsString(sum_status) && strcmp(sum_status->valuestring, "interrupted") == 0;
  if (interrupted && (!s || stopped)) { /* stopped by the study: not a result */
    cJSON_Delete(s);
    r->state = RUN_PENDING;
    r->exit_code = -1;
    r->status[0] = r->message[0] = '\0';
    progress(ss, i, "stopped", " after %.1f s (runs again when the study is resumed)", r->wall);
    return;
  }
  r->state = RUN_DONE;
  r->exit_code = WIFEXITED(ws) ? WEXITSTATUS(ws) : 128 + WTERMSIG(ws);
  const cJSON *sm = s ? cJSON_GetObjectItemCaseSensitive(s, "message") : NULL;
  const char *smsg = cJSON_IsString(sm) && sm->valuestring[0] ? sm->valuestring : NULL;
  char lmsg[512];
  log_message(st, r, lmsg, sizeof lmsg);
  const char *status = "error", *msg = smsg ? smsg : lmsg;
  if (WIFSIGNALED(ws)) {
    status = "crashed";
    snprintf(lmsg, sizeof lmsg, "killed by signal %d (%s)", WTERMSIG(ws), strsignal(WTERMSIG(ws)));
    msg = lmsg;
  } else if (stopped) { /* by a signal from outside the study */
    status = "interrupted";
  } else if (r->exit_code == 0) {
    status = s ? cJSON_GetObjectItemCaseSensitive(s, "status")->valuestring : "error";
    if (!s) msg = "exit status 0 but no summary.json";
  } else if (r->exit_code == 1) {
    status = "failed";
  } else if (r->exit_code == 2) {
    status = "bad input";
  } else if (r->exit_code == 3) {
    status = "io error";
  }
  snprintf(r->status, sizeof r->status, "%s", status);
  snprintf(r->message, sizeof r->message, "%s", msg);
  keep_summary(r, s); /* status and msg may point into it: copied first */
  if (strcmp(r->status, "completed") == 0) {
    char note[160];
    metric_note(st, r, note, sizeof note);
    progress(ss, i, r->status, ": %.1f s%s", r->wall, note);
  } else {
    progress(ss, i, r->status, ": %.1f s: %s (runs/%s/log.txt)", r->wall, r->message, r->name);
  }
}

static void write_csv(session *ss) {
  mpgm_ctx c;
  mpgm_ctx_init(&c);
  if (mpgm_study_write_csv(&c, ss->st) && !ss->csv_err) {
    ss->csv_err = c.code;
    snprintf(ss->csv_msg, sizeof ss->csv_msg, "%s", c.msg);
  }
}

/* Reap every child that has ended. */
static void reap(session *ss, int interrupted) {
  int ws;
  pid_t pid;
  while ((pid = waitpid(-1, &ws, interrupted ? 0 : WNOHANG)) > 0) {
    for (int i = 0; i < ss->st->nrun; i++)
      if (ss->st->runs[i].state == RUN_RUNNING && ss->st->runs[i].pid == (int)pid) {
        finish_run(ss, i, ws, interrupted);
        write_csv(ss);
      }
    if (interrupted && ss->running == 0) break;
  }
}

/* Run the pending runs, jobs at a time, until done or a signal. */
static void run_all(session *ss) {
  struct sigaction stop, child, old[4];
  memset(&stop, 0, sizeof stop);
  memset(&child, 0, sizeof child);
  stop.sa_handler = on_stop;
  child.sa_handler = on_child;
  sigset_t block, wait_mask;
  sigemptyset(&block);
  const int sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGCHLD};
  for (int k = 0; k < 4; k++) sigaddset(&block, sigs[k]);
  sigprocmask(SIG_BLOCK, &block, &ss->orig);
  for (int k = 0; k < 4; k++) sigaction(sigs[k], k < 3 ? &stop : &child, &old[k]);
  wait_mask = ss->orig;
  for (int k = 0; k < 4; k++) sigdelset(&wait_mask, sigs[k]);
  int next = 0;
  for (;;) {
    reap(ss, 0);
    if (stop_signal) break;
    while (ss->running < ss->st->jobs && next < ss->st->nrun)
      if (ss->st->runs[next++].state == RUN_PENDING) start_run(ss, next - 1);
    if (ss->running == 0 && next >= ss->st->nrun) break;
    sigsuspend(&wait_mask); /* until a child ends or a signal asks to stop */
  }
  if (stop_signal) {
    fprintf(stderr, "mpgm study: %s received: stopping %d running run(s) after their steps in progress\n", strsignal(stop_signal), ss->running);
    for (int i = 0; i < ss->st->nrun; i++)
      if (ss->st->runs[i].state == RUN_RUNNING) kill((pid_t)ss->st->runs[i].pid, SIGTERM);
    if (ss->running) reap(ss, 1);
  }
  for (int k = 0; k < 4; k++) sigaction(sigs[k], &old[k], NULL);
  sigprocmask(SIG_SETMASK, &ss->orig, NULL);
}

/* OUT/.lock held while the study runs: two studies writing the same
 * folder would run the same runs twice. Returns the descriptor or -1. */
static int lock_out(mpgm_ctx *ctx, const char *out) {
  char path[STUDY_PATH + 16];
  snprintf(path, sizeof path, "%s/.lock", out);
  const int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (fd < 0) {
    mpgm_err_set(ctx, MPGM_ERR_IO, __FILE__, __LINE__, "%s: %s", path, strerror(errno));
    return -1;
  }
  struct flock fl;
  memset(&fl, 0, sizeof fl);
  fl.l_type = F_WRLCK;
  fl.l_whence = SEEK_SET;
  if (fcntl(fd, F_SETLK, &fl) != 0) {
    close(fd);
    mpgm_err_set(ctx, MPGM_ERR_IO, __FILE__, __LINE__,
                 "%s: another `mpgm study` is running with its results in this folder", out);
    return -1;
  }
  return fd;
}

/* The runs complete from an earlier session (skipped), the stale ones. */
static void mark_done(session *ss, int rerun_failed, int dry) {
  for (int i = 0; i < ss->st->nrun; i++) {
    study_run *r = &ss->st->runs[i];
    int stale;
    if (complete_earlier(ss->st, r, rerun_failed, &stale)) {
      char note[160] = "";
      metric_note(ss->st, r, note, sizeof note);
      r->state = RUN_SKIPPED;
      progress(ss, i, "skip", ": %s earlier%s", r->status, note);
    } else if (stale) {
      progress(ss, i, "stale", ": its summary.json is of another scene or other values; runs again");
    } else if (dry) {
      char *sets[MAX_SETS];
      const int n = run_sets(ss->st, r, ss->threads, sets);
      progress(ss, i, "to run", ":");
      char dir[STUDY_PATH + STUDY_NAME + 16];
      mpgm_study_run_dir(ss->st, r, NULL, dir, sizeof dir);
      fprintf(stderr, "        mpgm run %s", r->scene);
      for (int k = 0; k < n; k++) fprintf(stderr, " --set '%s'", sets[k]);
      fprintf(stderr, " --out '%s' --quiet\n", dir);
      free_sets(sets, n);
    }
  }
}

static int count(const mpgm_study *st, int state, const char *status) {
  int n = 0;
  for (int i = 0; i < st->nrun; i++)
    n += (state < 0 || st->runs[i].state == state) && (!status || strcmp(st->runs[i].status, status) == 0);
  return n;
}

/* The closing lines; the exit code of the runs (0 all completed, 1 not). */
static int report(const session *ss, double t0) {
  const mpgm_study *st = ss->st;
  const int done = count(st, RUN_DONE, "completed"), skip = count(st, RUN_SKIPPED, "completed");
  fprintf(stderr, "study %s: %d runs: %d completed (%d now, %d earlier)", st->stem, st->nrun, done + skip, done,
          skip);
  static const char *const other[] = {"failed", "bad input", "io error", "crashed", "error"};
  for (size_t k = 0; k < sizeof other / sizeof *other; k++) {
    const int n = count(st, -1, other[k]);
    if (n) fprintf(stderr, ", %d %s", n, other[k]);
  }
  const int pending = count(st, RUN_PENDING, NULL);
  if (pending) fprintf(stderr, ", %d not run", pending);
  fprintf(stderr, "; %.1f s\n", mpgm_wtime() - t0);
  return done + skip == st->nrun ? 0 : 1;
}

/* Nothing the study writes may replace its inputs, the study file and the
 * scenes: OUT itself, study.json, study.csv, .lock, the plots, and the
 * run folders under OUT/runs, whose log.txt and summary.json the study
 * replaces before each run (the runs check their own outputs). */
static int refuse_overwrite(mpgm_ctx *ctx, const mpgm_study *st) {
  const char **in = calloc((size_t)st->nrun + 2, sizeof *in);
  MPGM_CHECK(ctx, in, MPGM_ERR_NOMEM, "out of memory (study)");
  int nin = 0;
  in[nin++] = st->file;
  in[nin++] = st->scene;
  for (int i = 0; i < st->nrun; i++) { /* each scene once */
    int seen = 0;
    for (int k = 0; k < nin && !seen; k++) seen = strcmp(in[k], st->runs[i].scene) == 0;
    if (!seen) in[nin++] = st->runs[i].scene;
  }
  static const char *const files[] = {"study.json", "study.csv", ".lock", "runs"};
  char names[4 + STUDY_PLOT_FILES][STUDY_PATH + 96];
  mpgm_write_path w[5 + STUDY_PLOT_FILES];
  w[0] = (mpgm_write_path){st->out, MPGM_WRITE_FILE};
  for (int k = 0; k < 4; k++) {
    snprintf(names[k], sizeof names[k], "%s/%s", st->out, files[k]);
    w[1 + k] = (mpgm_write_path){names[k], k < 2 ? MPGM_WRITE_ATOMIC : k == 2 ? MPGM_WRITE_FILE : MPGM_WRITE_FOLDER};
  }
  const char *x = cJSON_GetStringValue(
      cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(st->record, "plot"), "x"));
  mpgm_plot_outputs(st->out, x ? x : "mesh.h", names + 4, w + 5);
  const int err = mpgm_refuse_overwrite(ctx, w, 5 + STUDY_PLOT_FILES, in, nin);
  free(in);
  return err;
}

/* The study: load, check, run, gather, draw. Returns 0 or an error code
 * (message in ctx); *rc: 0 every run completed, 1 not, 128 + signal when
 * a signal stopped it. */
static int study_main(mpgm_ctx *ctx, const opts *o, mpgm_study *st, int *rc) {
  const double t0 = mpgm_wtime();
  *rc = 0;
  MPGM_CALL(mpgm_study_load(ctx, o->file, o->out, o->jobs, st));
  MPGM_CHECK(ctx, strlen(st->out) + STUDY_NAME + 64 < MPGM_PATH_LEN, MPGM_ERR_INPUT,
             "%s: out: the results folder's name is too long (%zu characters)", o->file, strlen(st->out));
  MPGM_CALL(validate(ctx, st));
  MPGM_CALL(refuse_overwrite(ctx, st));
  session ss;
  memset(&ss, 0, sizeof ss);
  ss.st = st;
  for (int n = st->nrun; n; n /= 10) ss.width++;
  int own_threads = 0;
  for (int k = 0; k < st->nkey; k++) own_threads |= strcmp(st->keys[k], "threads") == 0;
  for (int k = 0; k < st->nset; k++) own_threads |= strcmp(st->set[k].key, "threads") == 0;
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
  ss.threads = own_threads ? 0 : cores / st->jobs > 1 ? (int)(cores / st->jobs) : 1;
  fprintf(stderr, "study %s: %d runs, %d at a time, results in %s\n", st->stem, st->nrun, st->jobs, st->out);
  if (o->dry_run) {
    mark_done(&ss, o->rerun_failed, 1);
    fprintf(stderr, "dry run: %d to run, %d complete; nothing was run\n", count(st, RUN_PENDING, NULL),
            count(st, RUN_SKIPPED, NULL));
    return 0;
  }
  char path[STUDY_PATH + 32];
  snprintf(path, sizeof path, "%s/runs", st->out);
  MPGM_CALL(mpgm_mkdir_p(ctx, path));
  const int lock = lock_out(ctx, st->out);
  if (lock < 0) return ctx->code;
  snprintf(path, sizeof path, "%s/study.json", st->out);
  int err = mpgm_write_json(ctx, path, st->record);
  const ssize_t len = err ? -1 : readlink("/proc/self/exe", ss.exe, sizeof ss.exe - 1);
  if (!err && len <= 0)
    err = mpgm_err_set(ctx, MPGM_ERR_IO, __FILE__, __LINE__, "cannot find this program's file (/proc/self/exe): %s",
                       strerror(errno));
  if (err) {
    close(lock);
    return err;
  }
  ss.exe[len] = '\0';
  mark_done(&ss, o->rerun_failed, 0);
  write_csv(&ss);
  run_all(&ss);
  write_csv(&ss);
  close(lock);
  *rc = report(&ss, t0);
  MPGM_CHECK(ctx, !ss.csv_err, ss.csv_err, "%s", ss.csv_msg);
  snprintf(path, sizeof path, "%s/study.csv", st->out);
  printf("results: %s\n", path);
  if (stop_signal) {
    fprintf(stderr, "mpgm study: stopped by %s; run the same command again to finish the study\n",
            strsignal(stop_signal));
    *rc = 128 + stop_signal;
    return 0;
  }
  if (o->no_plot) return 0;
  if (count(st, -1, "completed") == 0) {
    fprintf(stderr, "mpgm study: no run completed: no plots\n");
    return 0;
  }
  mpgm_plot_opts po;
  memset(&po, 0, sizeof po);
  err = mpgm_plot(ctx, path, &po);
  if (err) fprintf(stderr, "mpgm study: study.csv is complete; draw the plots with `mpgm plot %s`\n", path);
  return err;
}

int mpgm_cmd_study(int argc, char **argv) {
  opts o;
  int rc = parse(argc, argv, &o);
  if (rc) return rc;
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  mpgm_study st;
  memset(&st, 0, sizeof st);
  const int err = study_main(&ctx, &o, &st, &rc);
  if (MPGM_DIM == 2 && err == MPGM_ERR_DIMENSION) {
    mpgm_study_free(&st);
    return mpgm_handoff(argv, o.file); /* nothing was run or written */
  }
  if (err) {
    fprintf(stderr, "mpgm study: %s\n", ctx.msg[0] ? ctx.msg : mpgm_code_str(err));
    rc = mpgm_exit_code(err);
  }
  mpgm_study_free(&st);
  return rc;
}
