/* mpgm_vtu.h -- VTK XML unstructured grids (.vtu), the default frames of a
 * run's series (points.pvd, mesh.pvd), written atomically (temporary name
 * + rename, mpgm_file.h) as the legacy writer's files are.
 *
 * A frame is written from a piece: the points, cells and point data of one
 * part of the body. A run on one process writes one piece per file; a
 * distributed run will write the piece each process owns into its own
 * .vtu and one .pvtu that lists them (the same arrays, declared once), so
 * that only the collection layer learns about ranks, not this writer.
 *
 * The arrays are those of the legacy files, in the same order: points as
 * Float64 x, y, z (z = 0 in plane strain), vectors as 3 components (z = 0
 * in plane strain), the stress as a 9-component tensor (2-D {xx, yy, xy,
 * zz} as [[xx,xy,0],[xy,yy,0],[0,0,zz]], 3-D the six Voigt components as
 * the symmetric 3x3; mpgm_vtk.h's kinds), and the simulation time (time,
 * or load factor in static runs) as the field data TimeValue (Float64, 1
 * value).
 */
#ifndef MPGM_VTU_H
#define MPGM_VTU_H

#include "mpgm_vtk.h"

#ifdef __cplusplus
extern "C" {
#endif

/** How the DataArrays of a .vtu are stored. */
typedef enum {
  MPGM_VTU_ASCII = 0, /**< inline text, "%.17g" (output.vtk "ascii")           */
  MPGM_VTU_RAW = 1,   /**< <AppendedData encoding="raw">: a UInt64 byte count
                           and the little-endian bytes of each array          */
  MPGM_VTU_ZLIB = 2   /**< appended raw, each array in vtkZLibDataCompressor's
                           blocks (output.compress "zlib")                    */
} mpgm_vtu_encoding;

/** One piece of an unstructured grid (borrowed arrays). */
typedef struct mpgm_vtu_piece {
  int npoints;         /**< points                                          */
  const double *x;     /**< MPGM_DIM coordinates per point [m]              */
  int ncells;          /**< cells; 0 with conn == NULL: one VTK_VERTEX per
                            point (a particle cloud)                        */
  const int *cell_ptr; /**< ncells + 1 offsets into conn (CSR)               */
  const int *conn;     /**< point ids of every cell                          */
  const int *cell_type;/**< VTK type of every cell                           */
  int nfields;         /**< point-data arrays                                */
  const mpgm_vtk_field *fields;
} mpgm_vtu_piece;

/** Write one piece as the .vtu path, atomically. encoding: mpgm_vtu_encoding;
 *  time: the TimeValue of the frame (finite). Errors: MPGM_ERR_INPUT (a
 *  piece mpgm_vtk_check refuses), MPGM_ERR_NOMEM, MPGM_ERR_IO (the message
 *  names the file and the reason). */
int mpgm_vtu_write(mpgm_ctx *ctx, const char *path, int encoding, double time,
                   const mpgm_vtu_piece *piece);

/** The index of a frame written in pieces by the n processes of a run
 *  (VTK XML PUnstructuredGrid, .pvtu), atomically: it declares the arrays
 *  of piece p (every process writes the same fields) and lists the
 *  pieces STEM_0.vtu .. STEM_{n-1}.vtu, named relative to path's folder.
 *  Errors: MPGM_ERR_INPUT (n < 1, more than 64 fields), MPGM_ERR_IO. */
int mpgm_pvtu_write(mpgm_ctx *ctx, const char *path, const mpgm_vtu_piece *p, int n,
                    const char *stem);

/** Read a .vtu that mpgm_vtu_write wrote (any encoding) into a new grid as
 *  mpgm_vtk_read gives it (title: "TimeValue = T"; the cells from their
 *  connectivity, offsets and types). mpgm_vtk_read calls it
 *  for a name ending in ".vtu". Errors: MPGM_ERR_IO (cannot read),
 *  MPGM_ERR_INPUT (not our layout: the message names the file and what was
 *  expected), MPGM_ERR_NOMEM. */
int mpgm_vtu_read(mpgm_ctx *ctx, const char *path, mpgm_vtk_grid **out);

#ifdef __cplusplus
}
#endif
#endif
