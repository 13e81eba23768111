/* mpgm_scene_io.h -- loading a scene: the scene file (docs/scene-format.md)
 * read, validated (each family checks its own part) and resolved into an
 * mpgm_scene (core/mpgm_scene.h), with --set overrides and defaults.
 *
 * Loading validates every key: unknown keys, wrong types, out-of-range
 * values, undefined names and bodies outside the domain are MPGM_ERR_INPUT
 * with the message "FILE: json.path: what was expected, what was found".
 */
#ifndef MPGM_SCENE_IO_H
#define MPGM_SCENE_IO_H

#include "mpgm_data.h"
#include "mpgm_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Load and validate a scene file with overrides ("dotted.path=value").
 *  On error returns MPGM_ERR_INPUT (or MPGM_ERR_IO when the file cannot be
 *  read) with the message in ctx; *out is NULL then. */
int mpgm_scene_load(mpgm_ctx *ctx, const char *file, int nset,
                    const char *const *sets, mpgm_scene **out);
/** Load and validate a scene given as JSON text[0, len) (not necessarily
 *  NUL-terminated; the fuzz target's entry): name stands for the file in
 *  messages. Errors as mpgm_scene_load. */
int mpgm_scene_load_text(mpgm_ctx *ctx, const char *name, const char *text, size_t len, int nset,
                         const char *const *sets, mpgm_scene **out);
/** Load and validate a scene given as a cJSON object (borrowed, not
 *  changed), e.g. the resolved scene an earlier run wrote into its
 *  summary.json; name stands for the file in messages. Errors as
 *  mpgm_scene_load. */
int mpgm_scene_load_json(mpgm_ctx *ctx, const char *name, const void *json, mpgm_scene **out);
/** Read one material as a scene's "materials" entry describes it (type,
 *  density, the type's parameters; then its setup) from the cJSON object
 *  json (borrowed); file and path (e.g. "material") name it in messages.
 *  mat->name is left as it is. Returns 0 or MPGM_ERR_INPUT with
 *  "FILE: path.key: expected ..., found ..." in ctx. */
int mpgm_material_load(mpgm_ctx *ctx, const char *file, const char *path, const void *json,
                       mpgm_material *mat);
/** The options of the scene's linear solver judged as its first
 *  factorisation would judge them, before a run writes anything: for
 *  solver.linear "petsc" (also with a linear_fallback) in an implicit
 *  analysis, PETSc's KSP and PC set up once on a test system with the
 *  symmetry of the scene's tangent (mpgm_solver_check: this loads and
 *  starts PETSc and MPI); 0 at once otherwise. The loader itself holds
 *  solver.petsc to mpgm's policy only, without PETSc. Errors:
 *  MPGM_ERR_INPUT "FILE: solver.petsc: ..." (an option PETSc refuses or
 *  does not use), or the backend's code when it cannot start. */
int mpgm_scene_check_solver(mpgm_ctx *ctx, const mpgm_scene *s);
/** Free a scene (accepts NULL, nulls the pointer). */
/** The parts of a run's memory (mpgm_size.bytes). */
enum { MPGM_SIZE_POINTS, MPGM_SIZE_CONN, MPGM_SIZE_NODES, MPGM_SIZE_MATRIX, MPGM_SIZE_FACTOR,
       MPGM_SIZE_HISTORY, MPGM_SIZE_LIBRARY, MPGM_SIZE_PARTS };
/** The memory a scene's run needs, estimated before it starts
 *  (scene_size.c; docs/scene-format.md, "Runs are sized and bounded"): the
 *  counts, and the bytes of each part, a lower bound of what the run fills. */
typedef struct mpgm_size {
  double points, nodes, grid_nodes; /**< material points; the bodies' nodes;
                                     MPM's background grid                */
  double entries;    /**< point-node entries of the connectivity           */
  double nnz;        /**< nonzeros of the tangent (implicit runs)           */
  double factor;     /**< nonzeros of a direct factorisation                */
  double history;    /**< numbers of steps.csv and probes.csv (fixed steps) */
  double bytes[MPGM_SIZE_PARTS];
  double total;      /**< [B]                                               */
} mpgm_size;
void mpgm_scene_size(const mpgm_scene *s, mpgm_size *z);
/** The estimate as "about 1.2 GiB (N points, ...: points X, ...)". */
void mpgm_size_format(const mpgm_size *z, char *buf, size_t n);
/** The memory this process can still have [B]: the least of the physical
 *  memory available, the room under a cgroup's limit and under RLIMIT_AS /
 *  RLIMIT_DATA; *what names the one that binds. INFINITY when none is
 *  known. */
double mpgm_memory_available(const char **what);
/** MPGM_ERR_INPUT, naming mesh.h (or the key of the largest part) with the
 *  estimate, what is available and what to change, when the run's estimate
 *  exceeds mpgm_memory_available; else 0. Called by the scene loader. */
int mpgm_scene_size_check(mpgm_ctx *ctx, const mpgm_scene *s);

void mpgm_scene_destroy(mpgm_scene **s);
/** The resolved scene as indented JSON (caller frees with free()). */
char *mpgm_scene_resolved_json(const mpgm_scene *s);
/** Metrics of the scene's reference (none when s has no reference block).
 *  nrow, ncol, hist: the probe history (layout above; ncol = 2 + 2 nprobe).
 *  acc: what the kind's observe kept (MPGM_REF_MAXACC doubles; may be
 *  NULL). metrics_cjson: the cJSON object the metrics are added to.
 *  Returns 0; MPGM_ERR_INPUT (nothing added) when the history is empty or
 *  narrower than the reference's probe columns. */
int mpgm_reference_metrics(const mpgm_scene *s, int nrow, int ncol, const double *hist,
                           const double *acc, void *metrics_cjson);
/** The material points P at time t after a step of dt (t = 0: dt = 0), for
 *  a reference kind that observes them (no-op otherwise): into acc. */
void mpgm_reference_observe(const mpgm_scene *s, double t, double dt, const mpgm_points *P,
                            double *acc);

#ifdef __cplusplus
}
#endif
#endif
