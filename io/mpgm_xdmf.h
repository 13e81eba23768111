/* mpgm_xdmf.h -- XDMF 3 + HDF5 frames (output.format "xdmf"): every frame
 * of a run's point and mesh series in one HDF5 file, DIR/results.h5,
 * indexed by DIR/points.xdmf and DIR/mesh.xdmf (temporal collections that
 * ParaView's XDMF reader opens; each index rewritten atomically after
 * every frame, the HDF5 file flushed first, so that a run killed between
 * frames leaves a readable file and an index of the frames written).
 *
 * The layout of results.h5 (docs/scene-format.md, "Results folder"):
 *   /points/NNNNNN   frame NNNNNN of the points (from 000000); attributes
 *                    time (float64: time, or load factor in static runs)
 *                    and step (int64)
 *     geometry       npoints x 3 float64 (z = 0 in plane strain)
 *     FIELD          every point-data array of the VTK frames, same name,
 *                    same numbers: npoints (scalar), npoints x 3 (a vector,
 *                    z = 0 in plane strain) or npoints x 9 (the stress as
 *                    a 3x3 tensor, row major: 2-D [[xx,xy,0],[xy,yy,0],
 *                    [0,0,zz]], 3-D the symmetric tensor of the six Voigt
 *                    components) float64
 *   /mesh/NNNNNN     the same for the mesh of fem / gmm (nodes, node
 *                    displacement), with topology (int32: XDMF's mixed
 *                    list, each cell's XDMF type, 4 triangle, 5
 *                    quadrilateral or 9 hexahedron, then its node ids in
 *                    VTK's order, which is XDMF's) and the attribute cells
 *                    (int32)
 *   /vertices/N      int32 0 .. N-1: the topology of a cloud of N points
 *                    (one vertex per point), written once per count
 * output.compress "zlib": the datasets are chunked and deflated (HDF5's
 * shuffle filter, then zlib's default level, as the .vtu arrays).
 *
 * HDF5 is Debian's Open MPI build (the one PETSc links), used with its
 * default file driver: no MPI call. HDF5 never prints here: its errors
 * become the context's (the message names the file and HDF5's reason).
 */
#ifndef MPGM_XDMF_H
#define MPGM_XDMF_H

#include "mpgm_blob.h"
#include "mpgm_vtu.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mpgm_xdmf mpgm_xdmf;

/** The XDMF output of a run into folder dir, in memory (nothing written):
 *  deflate 1 for deflated datasets, has_mesh 1 when the front end has cells
 *  (mesh.xdmf, /mesh). Errors: MPGM_ERR_NOMEM. */
int mpgm_xdmf_create(mpgm_ctx *ctx, const char *dir, int deflate, int has_mesh, mpgm_xdmf **out);
/** The files of folder dir made ready. keep == 0 (a new run): results.h5
 *  created afresh and the indices of an earlier run removed; x NULL (the
 *  scene writes no XDMF): results.h5 and the indices of an earlier run
 *  removed only. keep > 0 (a restart, after mpgm_xdmf_restore read keep
 *  frames): results.h5 opened, its frames from keep on dropped, the
 *  indices rewritten with the frames kept. Errors: MPGM_ERR_IO. */
int mpgm_xdmf_open(mpgm_xdmf *x, mpgm_ctx *ctx, const char *dir, int keep);
/** The next frame: the points' piece, and the mesh's (NULL without
 *  cells), at time (finite) of step. Written, flushed, then the indices
 *  rewritten. Errors: MPGM_ERR_INPUT (a piece mpgm_vtk_check refuses, a
 *  cell type without an XDMF one), MPGM_ERR_NOMEM, MPGM_ERR_IO. */
int mpgm_xdmf_frame(mpgm_xdmf *x, mpgm_ctx *ctx, double time, long step,
                    const mpgm_vtu_piece *points, const mpgm_vtu_piece *mesh);
/** Checkpoints: the frames' times as section tag (x NULL: nothing). */
int mpgm_xdmf_save(const mpgm_xdmf *x, mpgm_ctx *ctx, mpgm_blob *b, const char *tag);
/** Read back into a new x: section tag must hold the times of nframes
 *  frames (finite), and results.h5 those frames with those times, each of
 *  the layout above (its counts range-checked); their index entries are
 *  rebuilt from the file. Nothing is written (mpgm_xdmf_open does, once
 *  the whole checkpoint is known good). x NULL: nothing. Errors:
 *  MPGM_ERR_INPUT (a damaged section, a file that does not hold the
 *  frames), MPGM_ERR_IO (results.h5 cannot be read), MPGM_ERR_NOMEM. */
int mpgm_xdmf_restore(mpgm_xdmf *x, mpgm_ctx *ctx, mpgm_blob *b, const char *tag, int nframes);
/** Frames written (NULL: 0). */
int mpgm_xdmf_count(const mpgm_xdmf *x);
/** Close results.h5 and free (accepts NULL, nulls the pointer). */
void mpgm_xdmf_destroy(mpgm_xdmf **x);

#ifdef __cplusplus
}
#endif
#endif
