/* mpgm_discretisation.h -- what the front ends share to make nodes and
 * points: bodies filled on a grid, meshes of FE cells, boundaries applied
 * to nodes, points on the bodies' surfaces. The background grid
 * (mpgm_grid.h) and the kd-tree (mpgm_kdtree.h) have headers of their
 * own. */
#ifndef MPGM_DISCRETISATION_H
#define MPGM_DISCRETISATION_H

#include "mpgm_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Material points of bodies filled on a grid: the rule of MPM's particles
 *  and of GMM's grid-filled bodies (one function, so both
 *  put their points at the same places). For each of ncell cells of kind
 *  `cell` (mpgm_cell_kind), whose node coordinates (counter-clockwise) the
 *  caller's xy(grid, c, xn) gives, the Gauss points of the rule of s->ppc
 *  are taken in order; a point belongs to the first body of s that contains
 *  it (mpgm_body_contains), or to none. Outputs, entry k = c * s->ppc + q:
 *  owner (may be NULL) the body or -1; x (may be NULL) the position,
 *  MPGM_DIM per entry [m]; *count the entries that belong to a body.
 *  Returns 0, or MPGM_ERR_INPUT when the cell kind has no rule of s->ppc
 *  points. */
/** Where a cell's points lie, in local coordinates, with their weights:
 *  the Gauss rule of mesh.ppc points, or (mesh.layout "centres", quads)
 *  the centres of ppc equal sub-squares. 0 or MPGM_ERR_INPUT. */
int mpgm_points_rule(const mpgm_scene *s, int cell, double *xi, double *w);
int mpgm_bodies_fill(const mpgm_scene *s, int cell, int ncell,
                     void (*xy)(const void *grid, int c, double *xn), const void *grid,
                     int *owner, double *x, int *count);

/** Surface tracers of the scene's bodies (contact at points; 0 without):
 *  how many, and their positions, bodies and initial velocities into the
 *  last P->nsurf points of P (after the probes). The front ends call both
 *  (mpm.c, gmm_grid.c). */
int mpgm_surface_tracers_count(const mpgm_scene *s);
/** Probes and surface points that have no functions in this step (their
 *  evaluation failed, they lost every node to the light-node rule, no cell
 *  holds material near them) still move with the material: each takes the
 *  functions of its nearest material point (counted: probes_carried,
 *  surface_points_carried). A surface point stays unenforced for the step. c: the connectivity of every point
 *  (compacted); scratch: a connectivity the caller keeps; the two swap
 *  their arrays when a tracer is carried. skip (NULL: none), one per
 *  tracer from the first probe: a tracer another process moves in a run
 *  on many (its values come from there) keeps the lists it has, empty
 *  ones too, and is not counted. */
int mpgm_tracers_carry(const mpgm_fe_view *v, mpgm_conn *c, mpgm_conn *scratch,
                       const unsigned char *skip);
/** Their initial positions into x (MPGM_DIM per tracer; NULL: count only);
 *  returns how many. */
int mpgm_surface_tracers_xy(const mpgm_scene *s, double *x);
void mpgm_surface_tracers_fill(mpgm_points *P, const mpgm_scene *s);
/** Points on the boundary of body b at most `spacing` apart (a disk: from
 *  its lowest point, counter-clockwise; rectangles and polygons: every
 *  vertex and equal divisions of every edge). x == NULL: only count.
 *  Returns the number of points, MPGM_DIM doubles each in x (2-D only: the
 *  boundary of a disk, rectangle or polygon of the plane). */
int mpgm_body_surface(const mpgm_scene_body *b, double spacing, double *x);

/** A conforming mesh of FE cells, as a mesher (or a test) makes it. */
typedef struct mpgm_fem_mesh {
  int cell;         /**< mpgm_cell_kind of every cell                     */
  int nnode;        /**< nodes                                            */
  const double *X;  /**< initial node positions, MPGM_DIM per node [m]    */
  int ncell;        /**< cells                                            */
  const int *cnode; /**< mpgm_fe_nnode(cell) node ids per cell, counter-
                         clockwise                                        */
  const int *cbody; /**< scene body of every cell (material, velocity)     */
} mpgm_fem_mesh;

struct mpgm_grid;

/** The Gauss points of a grid's cells that lie in a body (mpgm_grid_fill):
 *  entry k = c ppc + q for Gauss point q of cell c. */
typedef struct mpgm_fill {
  size_t ngauss;   /**< cells x ppc                                       */
  int ppc;         /**< Gauss points per cell (mesh.ppc)                   */
  int count;       /**< of them inside a body: the material points         */
  int *owner;      /**< per Gauss point: its body, or -1                   */
  double *x;       /**< per Gauss point: its position, MPGM_DIM each [m]    */
  double vol[MPGM_MAXRULE]; /**< volume of a point at Gauss point q of a
                        cell [m^3] (cell measure x weight / reference
                        measure)                                          */
  /* ring bodies: points at the centres of polar sectors, after the grid's
   * (count includes them) */
  int nring;       /**< their number                                      */
  int *rowner;     /**< body of each                                      */
  double *rx, *rvol, *rr0; /**< position (MPGM_DIM), volume, domain half-axes
                        (2 MPGM_DIM: radial, tangential) of each           */
} mpgm_fill;

/** The bodies of scene s filled on the grid g (mpgm_bodies_fill): MPM's
 *  particles and the points of GMM's grid-filled bodies. Errors:
 *  MPGM_ERR_INPUT (no Gauss rule of mesh.ppc points; no point in any body),
 *  MPGM_ERR_NOMEM. Free with mpgm_fill_free (also after a failure). */
int mpgm_grid_fill(mpgm_ctx *ctx, const struct mpgm_grid *g, const mpgm_scene *s, mpgm_fill *f);
/** Material points 0 .. f->count - 1 of P from the fill, in Gauss-point
 *  order (mpgm_point_set: body, material, mass, initial velocity). */
void mpgm_fill_points(const mpgm_fill *f, const mpgm_scene *s, mpgm_points *P);
void mpgm_fill_free(mpgm_fill *f);

/** State doubles per point: the most any material of the scene needs. */
int mpgm_scene_nstate(const mpgm_scene *s);
/** The probes at their reference positions (points P->n .. P->n +
 *  nprobe - 1), with the initial velocity of the first body holding each. */
void mpgm_probes_place(mpgm_points *P, const mpgm_scene *s);

/** The light-node rule's key of "mesh" (mpgm_frontend_type.mesh_keys), for
 *  the front ends that apply it (mpm; gmm on the grid): the fraction of the
 *  step's heaviest node at or below which a node gets no equation. */
#define MPGM_LIGHT_NODE_KEY                                                                       \
  {.name = "min_node_mass", .type = MPGM_KEY_REAL,                                                \
   .offset = offsetof(mpgm_mesh_params, min_node_mass), .def = 1e-2, .lo = 0.0, .hi = 0.5,        \
   .hi_open = 1, .unit = "-",                                                                     \
   .doc = "a node of at most this fraction of the heaviest node's mass gets no equation"}

/** The light-node rule, 1: the mass m_I = sum_p N_Ip m_p of each of the
 *  nnode nodes from the functions c of the np material points (masses
 *  pmass) into mass; among the nodes eligible (NULL: all) a node is light
 *  when m_I <= min_node_mass max_J m_J, or when light[I] is set on entry (a
 *  node the front end wants out, e.g. beyond an obstacle); light[I] = 0
 *  for the others. Returns the light nodes. */
int mpgm_light_nodes(const mpgm_conn *c, int np, const double *pmass, int nnode,
                     const unsigned char *eligible, double min_node_mass, double *mass,
                     unsigned char *light);
/** The light-node rule, 2: the light nodes dropped from the lists of the m
 *  points of c (compacted in place), and the functions of every point that
 *  lost one renormalised over its other nodes (Shepard: sum N = 1 and
 *  sum grad N = 0 still hold, so rigid motions cause no strain). A surface
 *  point (after the probes) not enforced in this step (cp) keeps no
 *  functions; one that lost every node is not enforced. Errors:
 *  MPGM_ERR_SHAPE (recoverable) when another point lost every node. */
int mpgm_light_drop(mpgm_ctx *ctx, mpgm_conn *c, int m, const unsigned char *light,
                    const mpgm_points *P, mpgm_cpoints *cp, long step, double min_node_mass);

/** Node clouds and their meshfree shape functions (clouds.c; docs/theory.md,
 *  section 13), for the front ends that connect points to nodes by
 *  clouds. */
typedef struct mpgm_clouds mpgm_clouds;
struct mpgm_kdtree;

/** Clouds of the scene's meshfree kind (warm starts kept per point, sized
 *  by the first build). Errors: MPGM_ERR_INPUT (a kind without a support
 *  radius), MPGM_ERR_NOMEM. Free with mpgm_clouds_destroy (also after a
 *  failure). */
int mpgm_clouds_create(mpgm_ctx *ctx, const mpgm_scene *s, mpgm_clouds **out);
void mpgm_clouds_destroy(mpgm_clouds *c);
/** The kind's support radius r0 [m] (at mesh.h). */
double mpgm_clouds_radius(const mpgm_clouds *c);
/** Checkpoints: the warm starts (LME multipliers) of every point into b /
 *  back (mpgm_blob.h); the clouds themselves are rebuilt every step. The
 *  warm starts read back are of all m points (or none: written before the
 *  first build) and finite. Errors: MPGM_ERR_INPUT, MPGM_ERR_NOMEM. */
int mpgm_clouds_save(const mpgm_clouds *c, mpgm_ctx *ctx, mpgm_blob *b);
int mpgm_clouds_restore(mpgm_clouds *c, mpgm_ctx *ctx, mpgm_blob *b, int m);
/** The functions N of the clouds' kind at one position x, over the nodes
 *  of tree (skip: left out) within r0 (grown while fewer than min_nodes),
 *  without warm start: into idx and N (MPGM_SHAPE_MAXNODE each), *n of
 *  them. Errors: MPGM_ERR_SHAPE (no node, too many, the evaluation
 *  failed; nothing recorded in ctx beyond what the kind records). */
int mpgm_clouds_eval_at(mpgm_clouds *c, mpgm_ctx *ctx, const struct mpgm_kdtree *tree,
                        const unsigned char *skip, const double x[MPGM_DIM], int *idx, double *N,
                        int *n);
/** The first n points were reordered (new point i is old perm[i]): their
 *  warm starts move along (scratch: MPGM_DIM n doubles). */
void mpgm_clouds_permute(mpgm_clouds *c, const int *perm, int n, double *scratch);
/** The cloud and the shape functions of every point of v->pts (material
 *  points, probes, surface points) at its position: candidates are the
 *  points of tree (their coordinates: mpgm_kdtree_points), those with
 *  skip[i] (NULL: none) left out. The search radius starts at r0 and grows
 *  x MPGM_SHAPE_GROWTH while the cloud holds fewer than shape.min_nodes
 *  (counted: radius_growths); a failed evaluation adds the next-nearest
 *  candidates (MPGM_SHAPE_ENLARGE, up to shape.max_enlarge: cloud_
 *  enlargements). Into out: a point's entries by increasing node id,
 *  N = 0 and grad N = 0 left out; a surface point whose evaluation fails
 *  gets none and is left unenforced (v->cp). Search time moves from the
 *  "shape" to the "search" timer. Errors: MPGM_ERR_SHAPE (recoverable),
 *  MPGM_ERR_INPUT (a cloud of more than MPGM_SHAPE_MAXNODE nodes). */
int mpgm_clouds_build(mpgm_clouds *c, const mpgm_fe_view *v, const struct mpgm_kdtree *tree,
                      const unsigned char *skip, mpgm_conn *out);

/** Sort a short list of ints in place, increasing (the clouds' and the
 *  skin's node lists): distinct values within a range of 8192 through a
 *  bitmap, others by insertion. */
void mpgm_sort_ints(int *a, int n);

/** The search radius [m] each point's cloud had at the last
 *  mpgm_clouds_build (grown or enlarged, else r0), material points first;
 *  NULL before the first build. */
const double *mpgm_clouds_radii(const mpgm_clouds *c);

/** Sparsity patterns that outlive a step for node clouds (shape.skin,
 *  discretisation/skin.c): per material point the nodes within its search
 *  radius plus the skin, kept while they hold every cloud. */
typedef struct mpgm_skin mpgm_skin;
/** A skin of `skin` metres (> 0); rt > 0: the lists and the tangent
 *  stop at the tangent radius rt [m] (shape.tangent_radius; 0: the
 *  clouds'). Errors: MPGM_ERR_INPUT, MPGM_ERR_NOMEM. */
int mpgm_skin_create(mpgm_ctx *ctx, double skin, double rt, mpgm_skin **out);
void mpgm_skin_destroy(mpgm_skin *s);
/** After the step's clouds C (np material points at xp with search radii
 *  rp, lists by increasing node id; the nodes of tree at their
 *  positions xn): keep the lists while every cloud (with a tangent
 *  radius: its nodes within rt) is within its point's list, else build
 *  them again (*rebuilt = 1). With a tangent radius and tan not NULL,
 *  tan[k] = 1 for the entries k of C in the lists, else 0 (valid while
 *  mpgm_skin_ptr is not NULL). wide: this step takes whole clouds (the
 *  tangent radius is not applied, tan is not written; lists built so are
 *  built again at the first update without wide). Errors: MPGM_ERR_NOMEM. */
int mpgm_skin_update(mpgm_skin *s, mpgm_ctx *ctx, int np, const double *xp, const double *rp,
                     const double *xn, const mpgm_conn *C, const struct mpgm_kdtree *tree,
                     int wide, unsigned char *tan, int *rebuilt);
/** The lists (np + 1 offsets, the nodes), or NULL when a list would have
 *  exceeded 4 MPGM_SHAPE_MAXNODE nodes at the last build (no skin then). */
const int *mpgm_skin_ptr(const mpgm_skin *s);
const int *mpgm_skin_node(const mpgm_skin *s);
/** Checkpoints: the lists. Those read back must be of np material points,
 *  each list of increasing node numbers below nnode (what the next update
 *  indexes with). Errors: MPGM_ERR_INPUT, MPGM_ERR_NOMEM. */
int mpgm_skin_save(const mpgm_skin *s, mpgm_ctx *ctx, mpgm_blob *b);
int mpgm_skin_restore(mpgm_skin *s, mpgm_ctx *ctx, mpgm_blob *b, int np, int nnode);

/** FE cells of a problem (the mesh of UL-FEM, of GMM for rectangle
 *  bodies): the cells and every point's cell and local coordinates. */
typedef struct mpgm_fem_cells mpgm_fem_cells;

/** The persistent-node FE problem of a mesh (arrays are copied) into
 *  v->nodes, v->pts, v->conn: nodes with the initial velocity of their
 *  body, material points at the Gauss points of every cell (scene
 *  mesh.ppc; volume w det J, mass density * volume), probes located in the
 *  cell holding them, scene boundaries applied to the nodes, and the
 *  connectivity (point -> its cell's nodes); *out receives the cells (free
 *  with mpgm_fem_cells_destroy, also after a failure). Errors:
 *  MPGM_ERR_INPUT (probe outside the mesh, boundary selecting no node),
 *  MPGM_ERR_JACOBIAN (inverted cell), MPGM_ERR_NOMEM. */
int mpgm_fem_cells_create(const mpgm_fe_view *v, const mpgm_fem_mesh *m, mpgm_fem_cells **out);

/** Each rectangle body of the scene meshed by a structured grid of Q4
 *  cells (or two T3 per square) of size <= mesh.h, and the problem built
 *  on that mesh by mpgm_fem_cells_create. Errors: MPGM_ERR_INPUT (mesh
 *  too large), those of mpgm_fem_cells_create. */
int mpgm_fem_rectangles(const mpgm_fe_view *v, mpgm_fem_cells **out);

/** N and grad N of every point (material and probe) in its cell at the
 *  start-of-step node positions, into v->conn. Errors: MPGM_ERR_JACOBIAN
 *  (an inverted cell of a material point). */
int mpgm_fem_cells_shape(const mpgm_fem_cells *c, const mpgm_fe_view *v);
/** The cells for output. */
int mpgm_fem_cells_output(const mpgm_fem_cells *c, mpgm_cells *out);
/** Free (accepts NULL). */
void mpgm_fem_cells_destroy(mpgm_fem_cells *c);

/** The scene's boundaries applied to the nodes: every node a boundary
 *  selects (mpgm_boundary_selects) gets its fixed components and their
 *  prescribed values (contact at surface points acts on points, not nodes:
 *  skipped). Errors: MPGM_ERR_INPUT naming a boundary that selects no
 *  node. */
int mpgm_nodes_apply_boundaries(mpgm_ctx *ctx, const mpgm_scene *s, mpgm_nodes *nd);

#ifdef __cplusplus
}
#endif
#endif
