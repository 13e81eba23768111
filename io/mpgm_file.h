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

#ifdef __cplusplus
}
#endif
#endif
