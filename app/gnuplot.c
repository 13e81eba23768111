/* gnuplot.c -- a gnuplot process fed through a pipe (gnuplot.h). */
#define _POSIX_C_SOURCE 200809L
#include "gnuplot.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

int mpgm_gnuplot_find(char *buf, size_t cap) {
  const char *path = getenv("PATH");
  if (!path) return 0;
  for (const char *p = path;;) {
    const char *e = strchr(p, ':');
    const size_t n = e ? (size_t)(e - p) : strlen(p);
    if (n == 0) snprintf(buf, cap, "./gnuplot"); /* an empty entry is the current folder */
    else snprintf(buf, cap, "%.*s/gnuplot", (int)n, p);
    struct stat st;
    if (stat(buf, &st) == 0 && S_ISREG(st.st_mode) && access(buf, X_OK) == 0) return 1;
    if (!e) return 0;
    p = e + 1;
  }
}

int mpgm_gnuplot_check(mpgm_ctx *ctx) {
  char exe[4096];
  MPGM_CHECK(ctx, mpgm_gnuplot_find(exe, sizeof exe), MPGM_ERR_IO,
             "gnuplot not found on PATH (Debian: apt-get install gnuplot-nox)");
  return 0;
}

int mpgm_gnuplot_open(mpgm_ctx *ctx, mpgm_gnuplot *g, const char *cwd) {
  memset(g, 0, sizeof *g);
  g->pid = -1;
  char exe[4096];
  MPGM_CALL(mpgm_gnuplot_check(ctx));
  mpgm_gnuplot_find(exe, sizeof exe);
  snprintf(g->errfile, sizeof g->errfile, "/tmp/mpgm_gnuplot_XXXXXX");
  const int efd = mkstemp(g->errfile);
  MPGM_CHECK(ctx, efd >= 0, MPGM_ERR_IO, "cannot create a temporary file for gnuplot: %s", strerror(errno));
  int fd[2];
  if (pipe(fd) != 0) {
    close(efd);
    unlink(g->errfile);
    MPGM_ERROR(ctx, MPGM_ERR_IO, "cannot start gnuplot: %s", strerror(errno));
  }
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(fd[0], STDIN_FILENO);
    dup2(efd, STDOUT_FILENO);
    dup2(efd, STDERR_FILENO);
    close(fd[0]);
    close(fd[1]);
    close(efd);
    if (cwd && chdir(cwd) != 0) {
      fprintf(stderr, "error: cannot enter %s: %s\n", cwd, strerror(errno));
      _exit(126);
    }
    execl(exe, "gnuplot", (char *)NULL);
    fprintf(stderr, "error: cannot execute %s: %s\n", exe, strerror(errno));
    _exit(127);
  }
  close(fd[0]);
  close(efd);
  if (pid < 0) {
    close(fd[1]);
    unlink(g->errfile);
    MPGM_ERROR(ctx, MPGM_ERR_IO, "cannot start gnuplot: %s", strerror(errno));
  }
  g->pid = (int)pid;
  g->in = fdopen(fd[1], "w");
  if (!g->in) {
    close(fd[1]);
    return mpgm_gnuplot_close(ctx, g);
  }
  /* a gnuplot that dies early must not kill us with SIGPIPE: the write
   * fails instead and its exit status says why */
  struct sigaction ign;
  memset(&ign, 0, sizeof ign);
  ign.sa_handler = SIG_IGN;
  sigaction(SIGPIPE, &ign, &g->old_pipe);
  return 0;
}

int mpgm_gnuplot_close(mpgm_ctx *ctx, mpgm_gnuplot *g) {
  int werr = 0;
  if (g->in) {
    werr = fclose(g->in) != 0;
    g->in = NULL;
    sigaction(SIGPIPE, &g->old_pipe, NULL);
  }
  int status = 0;
  if (g->pid > 0)
    while (waitpid((pid_t)g->pid, &status, 0) < 0 && errno == EINTR) {}
  g->pid = -1;
  char msg[600] = "";
  FILE *ef = fopen(g->errfile, "r");
  if (ef) { /* the first lines that say what went wrong */
    char line[256];
    size_t n = 0;
    while (fgets(line, sizeof line, ef) && n + 1 < sizeof msg) {
      if (!strstr(line, "rror") && !strstr(line, "line ") && !strstr(line, "arning")) continue;
      line[strcspn(line, "\n")] = '\0';
      n += (size_t)snprintf(msg + n, sizeof msg - n, "%s%s", n ? " | " : "", line);
    }
    fclose(ef);
  }
  unlink(g->errfile);
  const int ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && !werr;
  MPGM_CHECK(ctx, ok, MPGM_ERR_IO, "gnuplot failed (%s %d)%s%s",
             WIFEXITED(status) ? "exit status" : "signal",
             WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? WTERMSIG(status) : -1,
             msg[0] ? ": " : "", msg);
  return 0;
}

void mpgm_gnuplot_quote(FILE *f, const char *s) {
  fputc('\'', f);
  for (; *s; s++) {
    if (*s == '\'') fputc('\'', f);
    if (*s != '\n' && *s != '\r') fputc(*s, f);
  }
  fputc('\'', f);
}

int mpgm_file_nonempty(mpgm_ctx *ctx, const char *path) {
  struct stat st;
  MPGM_CHECK(ctx, stat(path, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0, MPGM_ERR_IO,
             "%s: gnuplot did not write it", path);
  return 0;
}
