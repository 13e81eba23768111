/* exit_code.c -- the one table from error codes to exit codes; the
 * hand-off of a 3-D scene's command to mpgm-3d. */
#define _XOPEN_SOURCE 700
#include "exit_code.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "mpgm_base.h"

int mpgm_exit_code(int code) {
  if (code == 0) return EXIT_OK;
  if (code == MPGM_ERR_INPUT || code == MPGM_ERR_DIMENSION) return EXIT_INPUT;
  if (code == MPGM_ERR_IO) return EXIT_IO;
  return EXIT_SIM;
}

int mpgm_handoff(char **argv, const char *scene) {
  char exe[4096];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 16);
  char *slash = n > 0 ? memchr(exe, '/', (size_t)n) : NULL;
  if (slash) {
    exe[n] = '\0';
    snprintf(strrchr(exe, '/') + 1, 16, "mpgm-3d");
    fflush(NULL);
    execv(exe, argv);
  }
  fprintf(stderr, "mpgm: %s is a 3-D scene (mesh.domain has three coordinates), which mpgm-3d runs, "
          "and %s%s could not be started: %s\n", scene ? scene : "the scene", slash ? exe : "mpgm-3d",
          slash ? "" : " (this program's folder is unknown)", strerror(errno));
  return EXIT_INPUT;
}
