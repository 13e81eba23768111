/* mpgm_vtk.h -- in-tree VTK legacy writer (unstructured grid) and .pvd
 * time-series collections, written atomically (temporary name + rename).
 *
 * Binary files follow the legacy format's rule: big-endian numbers.
 * Points and vectors hold MPGM_DIM components in memory and 3 in the
 * files: a plane-strain build writes them with z = 0, a 3-D build (MPGM_DIM
 * 3) as they are. The stress is written as the full symmetric 3x3 tensor.
 */
#ifndef MPGM_VTK_H
#define MPGM_VTK_H

#include "mpgm_base.h"
#include "mpgm_blob.h"

#ifdef __cplusplus
extern "C" {
#endif

/** How a field's per-point data are laid out in memory; the value is the
 *  doubles per point. */
typedef enum {
  MPGM_VTK_SCALAR = 1,            /**< 1 double -> SCALARS name double 1     */
  MPGM_VTK_VECTOR = MPGM_DIM,     /**< MPGM_DIM doubles -> VECTORS (2-D: z =
                                       0)                                   */
  MPGM_VTK_STRESS = MPGM_NSTRESS  /**< the stress as mpgm stores it (2-D
                                       {xx, yy, xy, zz}, 3-D Voigt {xx, yy,
                                       zz, xy, yz, xz}) -> TENSORS 3x3 sym. */
} mpgm_vtk_kind;

/** One point-data field (borrowed array). */
typedef struct mpgm_vtk_field {
  const char *name;   /**< field name as ParaView shows it (no spaces) */
  int kind;           /**< mpgm_vtk_kind                              */
  const double *data; /**< npoints * kind doubles                      */
} mpgm_vtk_field;

/** Components per point of a field of kind as VTK files and results.h5
 *  hold it: 1 (scalar), 3 (a vector; z = 0 in 2-D) or 9 (the stress as a
 *  3x3 tensor). */
int mpgm_vtk_ncomp(int kind);
/** Components [k0, k0 + n) of a field of kind with data in memory (of
 *  layout kind) as those files hold them, ncomp per point: a vector's x,
 *  y, z (2-D: z = 0), the stress as the row-major 3x3 tensor, 2-D {xx, yy,
 *  xy, zz} as [[xx,xy,0],[xy,yy,0],[0,0,zz]], 3-D entry (i, j) the Voigt
 *  component mpgm_voigt_of[i][j]; into out (n doubles). The one place the
 *  writers expand a field. */
void mpgm_vtk_components(int kind, const double *data, size_t k0, size_t n, double *out);

/** VTK cell type numbers used by mpgm (the H8 of shapefn/, the 3-D grid's
 *  and meshes' cells, has VTK_HEXAHEDRON's node order: the bottom face
 *  counter-clockwise, then the top one above it). */
enum { MPGM_VTK_VERTEX = 1, MPGM_VTK_TRIANGLE = 5, MPGM_VTK_QUAD = 9, MPGM_VTK_HEXAHEDRON = 12 };

/** Write an unstructured grid in legacy format, atomically.
 *  path      : final file name (written to a temporary name, then renamed)
 *  binary    : 1 binary (big-endian), 0 ASCII
 *  title     : header line (truncated to 255 chars, newlines removed)
 *  npoints, x: point coordinates, MPGM_DIM doubles per point
 *  ncells    : number of cells; 0 with conn == NULL writes one VTK_VERTEX
 *              cell per point (a particle cloud)
 *  cell_ptr  : ncells + 1 offsets into conn (CSR)
 *  conn      : point ids of every cell
 *  cell_type : VTK type of every cell (MPGM_VTK_TRIANGLE, ...)
 *  nfields, fields : point data
 *  Errors: MPGM_ERR_IO (message names the file and the reason). */
int mpgm_vtk_write(mpgm_ctx *ctx, const char *path, int binary,
                   const char *title, int npoints, const double *x,
                   int ncells, const int *cell_ptr, const int *conn,
                   const int *cell_type, int nfields,
                   const mpgm_vtk_field *fields);

/** The arguments of mpgm_vtk_write checked (the VTK XML writer, vtu.c,
 *  takes the same piece and checks it here too): points, cells that refer
 *  to points, fields with a name without blanks and a known kind.
 *  Errors: MPGM_ERR_INPUT naming path. */
int mpgm_vtk_check(mpgm_ctx *ctx, const char *path, int npoints, const double *x, int ncells,
                   const int *cell_ptr, const int *conn, const int *cell_type, int nfields,
                   const mpgm_vtk_field *fields);

/** A collection of frames: (time, file) entries, rewritten atomically on
 *  add. A path ending in ".series" is written as ParaView's JSON series of
 *  legacy files ({"file-series-version": "1.0", "files": [{"name": ...,
 *  "time": ...}]}), any other as a .pvd (VTK XML Collection, the time as
 *  each DataSet's timestep). */
typedef struct mpgm_pvd mpgm_pvd;

/** Create a collection that will be written to path (nothing written yet). */
int mpgm_pvd_create(mpgm_ctx *ctx, const char *path, mpgm_pvd **out);
/** Append (time, file) and rewrite the collection. file is written as given
 *  (relative to the .pvd's folder). */
int mpgm_pvd_add(mpgm_pvd *pvd, mpgm_ctx *ctx, double time, const char *file);
/** Free (accepts NULL, nulls the pointer). */
void mpgm_pvd_destroy(mpgm_pvd **pvd);
/** Checkpoints: the entries of a collection (NULL: none) as sections
 *  TAG.n, TAG.time, TAG.file / read back into an empty collection (not
 *  written: mpgm_pvd_write, once the whole checkpoint is known good). The
 *  entries read back are checked: their count that of their times and
 *  names, finite times, names not empty. Errors: MPGM_ERR_INPUT. */
int mpgm_pvd_save(const mpgm_pvd *pvd, mpgm_ctx *ctx, mpgm_blob *b, const char *tag);
int mpgm_pvd_restore(mpgm_pvd *pvd, mpgm_ctx *ctx, mpgm_blob *b, const char *tag);
/** Write the collection as it is (NULL: nothing). Errors: MPGM_ERR_IO. */
int mpgm_pvd_write(mpgm_pvd *pvd, mpgm_ctx *ctx);
/** Its entries (NULL: 0). */
int mpgm_pvd_count(const mpgm_pvd *pvd);

/** One point-data array read back from a legacy file. */
typedef struct mpgm_vtk_array {
  char name[256]; /**< field name                                     */
  int ncomp;      /**< 1 (SCALARS), 3 (VECTORS, z last), 9 (TENSORS,
                       row major 3x3)                                  */
  double *v;      /**< npoints * ncomp values (owned)                  */
} mpgm_vtk_array;

/** An unstructured grid as mpgm_vtk_write (or mpgm_vtu_write) writes it:
 *  points, cells and point data. */
typedef struct mpgm_vtk_grid {
  char title[256];         /**< header line                          */
  int npoints;             /**< points                               */
  double *x;               /**< 3 coordinates per point (owned)      */
  int ncells;              /**< cells in the file                    */
  int *cell_ptr;           /**< ncells + 1 offsets into conn (owned)  */
  int *conn;               /**< point ids of every cell (owned)      */
  int *cell_type;          /**< VTK type of every cell (owned)       */
  int narray;              /**< point-data arrays, in file order     */
  mpgm_vtk_array *arrays;  /**< (owned)                              */
} mpgm_vtk_grid;

/** Read a legacy file written by mpgm_vtk_write (ASCII or binary) into a
 *  new grid (every cell of at least one point, its ids those of points); a name ending in ".vtu" is read by mpgm_vtu_read (mpgm_vtu.h)
 *  into the same kind of grid. Errors: MPGM_ERR_IO (cannot read), MPGM_ERR_INPUT (not our
 *  format; the message names the file and the line found),
 *  MPGM_ERR_NOMEM. */
int mpgm_vtk_read(mpgm_ctx *ctx, const char *path, mpgm_vtk_grid **out);
/** The array called name, or NULL. */
const mpgm_vtk_array *mpgm_vtk_array_find(const mpgm_vtk_grid *g, const char *name);
/** Free (accepts NULL, nulls the pointer). */
void mpgm_vtk_grid_destroy(mpgm_vtk_grid **g);

/** The entries of a .pvd collection, in file order. */
typedef struct mpgm_pvd_list {
  int n;        /**< entries                                   */
  double *time; /**< timestep of each (time, or load factor)    */
  char **file;  /**< file of each, relative to the .pvd's folder */
} mpgm_pvd_list;

/** Read a collection as mpgm_pvd_add writes it: a .pvd, or a .vtk.series
 *  (a name ending in ".series"). Every file named must lie below the
 *  collection's folder (mpgm_path_below). Errors as mpgm_vtk_read. */
int mpgm_pvd_read(mpgm_ctx *ctx, const char *path, mpgm_pvd_list *out);
/** Free the entries (accepts an empty list). */
void mpgm_pvd_list_free(mpgm_pvd_list *l);

#ifdef __cplusplus
}
#endif
#endif
