/* mpgm_file.h -- files and folders of the results: files are written to
 * "PATH.tmp" and renamed when complete, so a reader (or a run killed half
 * way) never leaves half a file behind. */
#ifndef MPGM_FILE_H
#define MPGM_FILE_H

#include "mpgm_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Open a temporary file next to path for writing ("path.tmp"). */
int mpgm_atomic_open(mpgm_ctx *ctx, const char *path, void **fp_out);
/** Close the temporary and rename it to path (fp is a FILE *). On error the
 *  temporary is removed and MPGM_ERR_IO returned. */
int mpgm_atomic_close(mpgm_ctx *ctx, const char *path, void *fp);
/** Close and delete the temporary after a failure (errors ignored: the
 *  first one has been recorded already). */
void mpgm_atomic_discard(const char *path, void *fp);
/** Write a cJSON tree (indented) atomically. */
int mpgm_write_json(mpgm_ctx *ctx, const char *path, const void *json);
/** mkdir -p (MPGM_ERR_IO naming the part that failed). */
int mpgm_mkdir_p(mpgm_ctx *ctx, const char *dir);
/** Remove the files of folder dir whose names start with prefix and end
 *  with suffix (a folder that does not exist holds none). Errors:
 *  MPGM_ERR_IO (a file that cannot be removed). */
int mpgm_remove_files(mpgm_ctx *ctx, const char *dir, const char *prefix, const char *suffix);

/** Open path for writing (created, truncated) without blocking: a FIFO
 *  that nobody reads is an error at once instead of a wait for ever.
 *  *fd receives the descriptor (blocking again). Errors: MPGM_ERR_IO
 *  ("PATH: cannot write: REASON"). */
int mpgm_open_write(mpgm_ctx *ctx, const char *path, int *fd);
/** mpgm_open_write as a stdio stream, *f. */
int mpgm_fopen_write(mpgm_ctx *ctx, const char *path, FILE **f);

/** An output another program writes (gnuplot's pictures), which cannot be
 *  opened here without blocking, must be absent or a regular file: a FIFO
 *  there would make that program wait for ever. Errors: MPGM_ERR_IO
 *  ("PATH: is a pipe or FIFO, not a regular file: ..."). */
int mpgm_output_regular(mpgm_ctx *ctx, const char *path);

/** How a command writes at a path (mpgm_refuse_overwrite). */
typedef enum {
  MPGM_WRITE_FILE = 0, /**< the path itself, written in place (or a folder
                            made there: only the name is compared)     */
  MPGM_WRITE_ATOMIC,   /**< a file written through PATH.tmp: both       */
  MPGM_WRITE_FOLDER    /**< a folder whose files the command writes and
                            removes: itself and anything inside it      */
} mpgm_write_kind;

/** One path a command writes. */
typedef struct mpgm_write_path {
  const char *path; /**< NULL or "": none                                */
  int kind;         /**< mpgm_write_kind                                  */
} mpgm_write_path;

/** Refuse a command that would write over one of its inputs, before it
 *  writes anything (overwrite.c): an output that is an input (the same
 *  name, resolved through symbolic links, or a hard link of it: the same
 *  device and inode), an atomic output whose PATH.tmp is one, or a folder
 *  output that holds one. Outputs not there yet are compared by resolved
 *  name; inputs that do not exist (NULL entries too) are passed over.
 *  Errors: MPGM_ERR_INPUT, naming the output and the input;
 *  MPGM_ERR_NOMEM. */
int mpgm_refuse_overwrite(mpgm_ctx *ctx, const mpgm_write_path *out, int nout,
                          const char *const *in, int nin);
/** mpgm_refuse_overwrite for a run into results folder dir: dir itself,
 *  its summary.json, probes.csv, steps.csv, points.pvd, mesh.pvd and
 *  checkpoint.mpgm, and the folders vtk/ and matrices/. */
int mpgm_refuse_run_overwrite(mpgm_ctx *ctx, const char *dir, const char *const *in, int nin);

#ifdef __cplusplus
}
#endif
#endif
