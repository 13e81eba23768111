/* mpgm_output.h -- the results folder of a run: VTK and .pvd files, the
 * probe and step histories (CSV), the linear systems (output.matrices). */
#ifndef MPGM_OUTPUT_H
#define MPGM_OUTPUT_H

#include "mpgm_core.h"
#include "mpgm_file.h"

typedef struct mpgm_output {
  char dir[MPGM_PATH_LEN];
  char matrices_dir[MPGM_PATH_LEN + 16]; /**< output.matrices: DIR/matrices
                     (emptied of earlier systems when opened); "" if none */
  const mpgm_scene *scene; /**< the run's scene (borrowed)         */
  int mtx_on;     /**< output.matrices lists the current step      */
  int mtx_system; /**< systems written in the current step          */
  long mtx_written; /**< systems written in the run                */
  struct mpgm_pvd *series[2][3]; /**< the collections of the frames:
                     [format: 0 .vtu (points.pvd, mesh.pvd, grid.pvd), 1
                     legacy .vtk (points.vtk.series, ...)][kind: 0 points,
                     1 mesh, 2 background grid]; NULL where the scene
                     writes none                                         */
  double *grid_x; /**< output.grid: the grid's node positions, and its    */
  int *grid_ptr, *grid_node, *grid_type; /**< cells (NULL: no grid series) */
  int grid_nnode, grid_ncell;
  struct mpgm_xdmf *xdmf; /**< output.format "xdmf": results.h5 and its
                     indices (mpgm_xdmf.h); NULL where the scene writes none */
  int rank, nproc; /**< this process and the run's (mpgm_ctx): on many,
                     each writes its points' .vtu piece of a frame, and
                     the first the rest (the .pvtu, the series, the
                     histories)                                      */
  int nvtk;       /**< VTK outputs written (index of the next one) */
  int files;      /**< VTK files written (every format; on many
                       processes every piece and index)            */
  int ncol;       /**< probe columns: MPGM_DIM of u per probe (u of
                       probe k component c at mpgm_ref_column(k, c)),
                       dynamic runs MPGM_DIM of v per probe after them */
  int nrow, caprow;
  double *hist;   /**< probe history rows: step, time, columns     */
  int nstep, capstep;
  double *steps;  /**< per converged step: STEP_COLS values         */
  int nimb, capimb;
  double *imb;    /**< many processes: per converged step, the points'
                       imbalance after it (most on a process / mean),
                       steps.csv's last column                        */
  double ref_acc[MPGM_REF_MAXACC]; /**< what the scene's reference kind
                     keeps of the points (its observe)               */
} mpgm_output;

/** Open the results folder dir of problem pb: DIR/vtk (emptied of earlier
 *  VTK files), the collections of every output.format (vtu: points.pvd,
 *  and mesh.pvd when the front end has cells; vtk: points.vtk.series,
 *  mesh.vtk.series; the earlier run's collections removed),
 *  DIR/matrices (output.matrices). Errors: MPGM_ERR_IO. */
int mpgm_output_open(mpgm_ctx *ctx, mpgm_output *o, const mpgm_problem *pb, const char *dir);
/** ", points.pvd, mesh.pvd, ...": the series files a run of scene s
 *  writes (by output.format, has_cells: the front end's cells, and
 *  output.grid; "" with output.vtk "none") into buf; returns buf. */
const char *mpgm_output_series_names(const mpgm_scene *s, int has_cells, char *buf, size_t n);
void mpgm_output_close(mpgm_output *o);
/** Checkpoints: the output's state (VTK outputs and files written, the
 *  probe and step histories, the .pvd entries) into b. */
int mpgm_output_save(const mpgm_output *o, mpgm_ctx *ctx, mpgm_blob *b);
/** A run restarted from a checkpoint, in two parts. First the state saved
 *  by mpgm_output_save, read from b into o for the results folder dir of
 *  pb (restored from the same checkpoint): its counts checked against pb's
 *  step and scene, its histories row by row; nothing is written, so that
 *  a checkpoint refused later leaves the folder as it was. Errors:
 *  MPGM_ERR_INPUT (another layout, a damaged section), MPGM_ERR_NOMEM. */
int mpgm_output_restore(mpgm_ctx *ctx, mpgm_output *o, const mpgm_problem *pb, const char *dir,
                        mpgm_blob *b);
/** Then, once the whole checkpoint is read, the folder: VTK files written
 *  after the checkpoint (and temporaries) are removed, summary.json too,
 *  the .pvd collections and the CSV histories rewritten as they were at
 *  the checkpoint. Errors: MPGM_ERR_IO. */
int mpgm_output_resume(mpgm_ctx *ctx, mpgm_output *o);
/** output.matrices: make the output an observer of pb that writes the
 *  systems of the listed steps (Matrix Market, DIR/matrices/stepSSSS_itII_
 *  K.mtx and _b.mtx, II counting the systems of the step from 0; a retried
 *  step writes afresh). Nothing when the scene lists no step. */
int mpgm_output_observe(mpgm_ctx *ctx, mpgm_output *o, mpgm_problem *pb);
/** The points (and the mesh) now as the next VTK files of the series. */
int mpgm_output_vtk(mpgm_ctx *ctx, mpgm_output *o, const mpgm_problem *pb);
/** The probes' displacements now (and velocities, dynamic runs), as a row
 *  of the probe history; probes.csv's header names them NAME_ux, NAME_uy
 *  (3-D NAME_uz), then NAME_vx, ... */
int mpgm_output_probes_record(mpgm_ctx *ctx, mpgm_output *o, const mpgm_problem *pb);
/** DIR/probes.csv: the probe history so far. */
int mpgm_output_probes_write(mpgm_ctx *ctx, mpgm_output *o);
/** Newton record of the step just converged (wall: its wall time [s]). */
int mpgm_output_step_record(mpgm_ctx *ctx, mpgm_output *o, const mpgm_problem *pb, double wall);
/** DIR/steps.csv: one row per converged step with its Newton norms. */
int mpgm_output_steps_write(mpgm_ctx *ctx, mpgm_output *o);
/** Over the recorded steps (dynamic runs): the largest difference between
 *  the points' and the nodes' momentum [kg m/s], and the largest kinetic
 *  energy of the points [J]. */
void mpgm_output_momentum_gap(const mpgm_output *o, double *gap, double *kmax);

#endif
