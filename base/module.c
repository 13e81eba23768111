/* module.c -- finding and loading mpgm's modules (mpgm_module.h). */
#define _GNU_SOURCE /* dladdr-free: readlink of /proc/self/exe */
#include "mpgm_module.h"

#include <dlfcn.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef MPGM_PLUGIN_DIR_BUILT
#define MPGM_PLUGIN_DIR_BUILT ""
#endif

/* The folder of the running executable into dir ("" if unknown). */
static void exe_dir(char *dir, size_t len) {
  const ssize_t l = readlink("/proc/self/exe", dir, len - 1);
  dir[l > 0 ? l : 0] = '\0';
  char *slash = strrchr(dir, '/');
  if (slash) *slash = '\0';
}

/* dlopen dir/file: the handle, NULL when there is no such file or it does
 * not load (then, with msg, dlopen's reason). */
static void *open_in(const char *dir, const char *file, char *msg, size_t len) {
  if (!dir || !*dir) return NULL;
  char path[PATH_MAX + 64];
  snprintf(path, sizeof path, "%s/%s", dir, file);
  if (access(path, R_OK) != 0) return NULL;
  void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
  if (!h && msg) {
    const char *e = dlerror();
    snprintf(msg, len, "%.*s: %.400s", PATH_MAX, path, e ? e : "dlopen failed");
  }
  return h;
}

/* The places a module is looked for, in order. */
static void places(const char *where[3], char *exe, size_t len) {
  exe_dir(exe, len);
  where[0] = getenv("MPGM_PLUGIN_DIR");
  where[1] = exe;
  where[2] = MPGM_PLUGIN_DIR_BUILT;
}

void *mpgm_module_open(const char *file) {
  char exe[PATH_MAX];
  const char *where[3];
  places(where, exe, sizeof exe);
  void *h = NULL;
  for (int i = 0; i < 3 && !h; i++) h = open_in(where[i], file, NULL, 0);
  return h;
}

void mpgm_module_why_not(const char *file, const char *what, char *msg, size_t len) {
  char exe[PATH_MAX];
  const char *where[3];
  places(where, exe, sizeof exe);
  msg[0] = '\0';
  for (int i = 0; i < 3; i++) {
    void *h = open_in(where[i], file, msg, len);
    if (h) { /* the file appeared after the first attempt */
      dlclose(h);
      snprintf(msg, len, "%s in %s loads now but did not when first asked: run again", file,
               where[i]);
    }
    if (msg[0]) return;
  }
  snprintf(msg, len, "%s not found in $MPGM_PLUGIN_DIR, %s or %s (mpgm was built without "
           "%s: install petsc-dev, as scripts/setup.sh does, and build again)", file,
           exe[0] ? exe : "the executable's folder",
           *MPGM_PLUGIN_DIR_BUILT ? MPGM_PLUGIN_DIR_BUILT : "the build folder", what);
}
