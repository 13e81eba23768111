/* overwrite.c -- no command writes over its own input (mpgm_file.h).
 *
 * Every command that writes files names what it writes and what it reads,
 * and is refused before it writes anything when one is the other: the same
 * file under the same name, through a symbolic link, or as a hard link of
 * it (the same device and inode), or an input inside a folder whose files
 * the command writes and removes (a run's vtk/ and matrices/). A path not
 * there yet is compared by its resolved name (its folder's real path and
 * its own name). Inputs that do not exist are passed over: their reader
 * reports them.
 */
#define _XOPEN_SOURCE 700 /* realpath */
#include "mpgm_file.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* A path as the file system sees it. */
typedef struct ident {
  int exists;
  dev_t dev;
  ino_t ino;
  char *real; /* resolved absolute path (malloc'd); NULL when unknown */
} ident;

/* The resolved name of path: realpath of the path, or, when it is not
 * there, of its folder with its own name after it. NULL when neither can
 * be resolved (its folder does not exist either: nothing is there). */
static char *resolve(const char *path) {
  char *r = realpath(path, NULL);
  if (r || !*path) return r;
  const char *slash = strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  char dir[PATH_MAX];
  if (!slash) snprintf(dir, sizeof dir, ".");
  else if (slash == path) snprintf(dir, sizeof dir, "/");
  else snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
  if (!*base || !strcmp(base, ".") || !strcmp(base, "..")) return NULL;
  char *d = realpath(dir, NULL);
  if (!d) return NULL;
  const size_t n = strlen(d) + strlen(base) + 2;
  char *out = malloc(n);
  if (out) snprintf(out, n, "%s%s%s", d, strcmp(d, "/") ? "/" : "", base);
  free(d);
  return out;
}

static void identify(const char *path, ident *id) {
  struct stat st;
  memset(id, 0, sizeof *id);
  if (stat(path, &st) == 0) {
    id->exists = 1;
    id->dev = st.st_dev;
    id->ino = st.st_ino;
  }
  id->real = resolve(path);
}

/* Is output o (identified as oid) the input in (iid)? Records the refusal. */
static int same(mpgm_ctx *ctx, const char *o, const ident *oid, const char *in, const ident *iid,
                const char *what) {
  const int inode = oid->exists && iid->exists && oid->dev == iid->dev && oid->ino == iid->ino;
  const int name = oid->real && iid->real && strcmp(oid->real, iid->real) == 0;
  if (!inode && !name) return 0;
  MPGM_ERROR(ctx, MPGM_ERR_INPUT,
             "%s: %s %s the input %s%s; refused, nothing was written",
             o, what, name ? "would overwrite" : "is a hard link of", in,
             name ? "" : " (the same file)");
}

/* Does folder fid (resolved) hold the input iid? */
static int holds(const ident *fid, const ident *iid) {
  if (!fid->real || !iid->real) return 0;
  const size_t n = strlen(fid->real);
  return strncmp(iid->real, fid->real, n) == 0 && (iid->real[n] == '/' || !strcmp(fid->real, "/"));
}

/* Check output o against every input (resolved in iid). */
static int check_output(mpgm_ctx *ctx, const mpgm_write_path *o, const char *const *in,
                        const ident *iid, int nin) {
  ident oid;
  identify(o->path, &oid);
  int err = 0;
  for (int i = 0; i < nin && !err; i++) {
    if (!iid[i].exists) continue;
    err = same(ctx, o->path, &oid, in[i], &iid[i], "the output");
    if (!err && o->kind == MPGM_WRITE_FOLDER && holds(&oid, &iid[i]))
      err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__,
                         "%s: holds the input %s, and the files of this folder are written and "
                         "removed by the command; refused, nothing was written", o->path, in[i]);
  }
  free(oid.real);
  if (err || o->kind != MPGM_WRITE_ATOMIC) return err;
  /* the temporary it is written through, PATH.tmp */
  char t[PATH_MAX + 8];
  if (snprintf(t, sizeof t, "%s.tmp", o->path) >= (int)sizeof t) return 0;
  identify(t, &oid);
  for (int i = 0; i < nin && !err; i++)
    if (iid[i].exists) err = same(ctx, t, &oid, in[i], &iid[i], "the temporary of an output");
  free(oid.real);
  return err;
}

int mpgm_refuse_overwrite(mpgm_ctx *ctx, const mpgm_write_path *out, int nout, const char *const *in,
                          int nin) {
  if (nin <= 0 || nout <= 0) return 0;
  ident *iid = calloc((size_t)nin, sizeof *iid);
  MPGM_CHECK(ctx, iid, MPGM_ERR_NOMEM, "out of memory (%d inputs)", nin);
  for (int i = 0; i < nin; i++)
    if (in[i]) identify(in[i], &iid[i]);
  int err = 0;
  for (int k = 0; k < nout && !err; k++)
    if (out[k].path && out[k].path[0]) err = check_output(ctx, &out[k], in, iid, nin);
  for (int i = 0; i < nin; i++) free(iid[i].real);
  free(iid);
  return err;
}

int mpgm_refuse_run_overwrite(mpgm_ctx *ctx, const char *dir, const char *const *in, int nin) {
  /* the results folder as docs/scene-format.md lists it (output.c, run.c,
   * checkpoint.c write these) */
  static const char *const files[] = {"summary.json",      "probes.csv",      "steps.csv",
                                      "points.pvd",        "mesh.pvd",        "grid.pvd",
                                      "points.vtk.series", "mesh.vtk.series", "grid.vtk.series",
                                      "points.xdmf",       "mesh.xdmf",       "results.h5",
                                      "checkpoint.mpgm"};
  static const char *const folders[] = {"vtk", "matrices"};
  enum { NF = sizeof files / sizeof *files, ND = sizeof folders / sizeof *folders };
  char buf[NF + ND][MPGM_PATH_LEN + 32];
  mpgm_write_path out[1 + NF + ND];
  out[0] = (mpgm_write_path){dir, MPGM_WRITE_FILE}; /* --out naming the scene itself */
  for (int k = 0; k < NF + ND; k++) {
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, k < NF ? files[k] : folders[k - NF]);
    out[1 + k] = (mpgm_write_path){buf[k], k < NF ? MPGM_WRITE_ATOMIC : MPGM_WRITE_FOLDER};
  }
  return mpgm_refuse_overwrite(ctx, out, 1 + NF + ND, in, nin);
}
