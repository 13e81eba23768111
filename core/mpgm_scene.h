/* mpgm_scene.h -- a scene: the validated, typed content of a scene file
 * (docs/scene-format.md) after --set overrides and defaults.
 *
 * Loading validates every key: unknown keys, wrong types, out-of-range
 * values, undefined names and bodies outside the domain are MPGM_ERR_INPUT
 * with the message "FILE: json.path: what was expected, what was found".
 */
#ifndef MPGM_SCENE_H
#define MPGM_SCENE_H

#include <math.h>

#include "mpgm_base.h"
#include "mpgm_integrator.h"
#include "mpgm_material.h"
#include "mpgm_mms.h"
#include "mpgm_reference.h"
#include "mpgm_shapefn.h"
#include "mpgm_solver.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MPGM_POLYGON_MAX 256 /**< most vertices of a polygon body */
#define MPGM_MATRICES_MAX 64 /**< most steps in output.matrices */
#define MPGM_BFGS_PAIRS_MAX 64 /**< most pairs of solver.newton "bfgs" */
/** The smallest time.cfl: a thousandth of the stability limit h / c, 100
 *  times more steps than the default 0.1 (docs/scene-format.md, "Runs are
 *  sized and bounded"). */
#define MPGM_CFL_MIN 1e-3
/** time.max_steps when the scene gives none. */
#define MPGM_MAX_STEPS_DEFAULT 10000000

typedef enum {
  MPGM_ANALYSIS_STATIC = 0,  /**< load steps, no inertia                   */
  MPGM_ANALYSIS_DYNAMIC = 1, /**< implicit Newmark                         */
  MPGM_ANALYSIS_EXPLICIT = 2 /**< explicit schemes (time.scheme)            */
} mpgm_analysis;
typedef enum { MPGM_VTK_NONE = 0, MPGM_VTK_OUT_ASCII = 1, MPGM_VTK_OUT_BINARY = 2 } mpgm_vtk_mode;
/** output.format: the files of the point and mesh series (bit mask). */
typedef enum {
  MPGM_FORMAT_VTU = 1u << 0,  /**< VTK XML .vtu frames, .pvd series (the default) */
  MPGM_FORMAT_VTK = 1u << 1,  /**< legacy .vtk frames, .vtk.series (ParaView's JSON) */
  MPGM_FORMAT_XDMF = 1u << 2  /**< one HDF5 file of every frame, an .xdmf index */
} mpgm_format;
/** output.compress: how VTK XML and HDF5 arrays are stored. */
typedef enum { MPGM_COMPRESS_NONE = 0, MPGM_COMPRESS_ZLIB = 1 } mpgm_compress;
/** Body geometries. The same kind is the plane figure in 2-D and the solid
 *  in 3-D: a rectangle is a box, a disk a ball, a polygon the prism of the
 *  polygon extruded along z. */
typedef enum {
  MPGM_GEOM_RECTANGLE = 0, /**< 2-D rectangle, 3-D box ("box")             */
  MPGM_GEOM_DISK = 1,      /**< 2-D disk, 3-D ball ("sphere")              */
  MPGM_GEOM_POLYGON = 2,   /**< 2-D polygon, 3-D the polygon x [z0, z1]     */
  MPGM_GEOM_RING = 3, /**< an annulus or a sector of one, filled in polar
                           sectors (2-D only)                           */
  MPGM_GEOM_CYLINDER = 4   /**< 3-D only: a circular cylinder about any axis */
} mpgm_geometry;
#define MPGM_GEOM_BOX MPGM_GEOM_RECTANGLE
#define MPGM_GEOM_SPHERE MPGM_GEOM_DISK
/** A boundary's selector: a plane normal to an axis (its value the axis
 *  index, so bodies' boxes can be indexed by it; z in 3-D only) or a box. */
typedef enum { MPGM_SELECT_X = 0, MPGM_SELECT_Y = 1, MPGM_SELECT_Z = 2, MPGM_SELECT_BOX = 3 } mpgm_select;
/** The scene key of a selector: "x", "y", "z" or "box". */
static inline const char *mpgm_select_key(int select) {
  static const char *const key[] = {"x", "y", "z", "box"};
  return select >= 0 && select <= MPGM_SELECT_BOX ? key[select] : "?";
}
/** How a boundary's fixed components were given. */
typedef enum {
  MPGM_COND_FIX = 0,   /**< explicit "fix": [...] list                  */
  MPGM_COND_STICK = 1, /**< "condition": "stick": both components       */
  MPGM_COND_SLIP = 2,  /**< "condition": "slip": the plane's normal only */
  MPGM_COND_CONTACT = 3 /**< "condition": "contact": no slip while the body
                             presses on the plane, released where it would
                             be pulled (unilateral)                     */
} mpgm_condition;

/** Where a "contact" boundary is enforced. */
typedef enum {
  MPGM_ENFORCE_NODES = 0, /**< grid nodes on the plane are held/released  */
  MPGM_ENFORCE_POINTS = 1 /**< points on the bodies' surfaces are held by
                               a penalty where they reach the plane; the
                               grid nodes stay free                      */
} mpgm_enforce;

/** Output fields of material points (bit mask). */
typedef enum {
  MPGM_FIELD_DISPLACEMENT = 1 << 0,
  MPGM_FIELD_VELOCITY = 1 << 1,
  MPGM_FIELD_STRESS = 1 << 2,
  MPGM_FIELD_MASS = 1 << 3,
  MPGM_FIELD_VOLUME = 1 << 4,
  MPGM_FIELD_J = 1 << 5,
  MPGM_FIELD_MATERIAL = 1 << 6,
  MPGM_FIELD_ACCELERATION = 1 << 7,
  MPGM_FIELD_ID = 1 << 8,
  MPGM_FIELD_EPS_P = 1 << 9, /**< equivalent plastic strain; written only
                                  when a material of the scene is plastic */
  MPGM_FIELD_ALL = (1 << 10) - 1, /**< the default set: every field above */
  MPGM_FIELD_BODY = 1 << 10  /**< the body's index in scene order (from 0),
                                  for categorical colours; written only
                                  when listed (not in the default set, so
                                  that the default files stay as they were) */
} mpgm_field;

/** A body: one material, one reference geometry, an initial velocity.
 *  Whatever the geometry, min/max hold its bounding box (the rectangle
 *  itself for MPGM_GEOM_RECTANGLE); mpgm_body_contains relies on it. */
typedef struct mpgm_scene_body {
  char name[MPGM_NAME_LEN];
  int material;        /**< index into scene materials               */
  int geometry;        /**< mpgm_geometry                            */
  double min[MPGM_DIM], max[MPGM_DIM]; /**< bounding box (rectangle: its
                            corners) [m]                            */
  double centre[MPGM_DIM]; /**< disk, sphere: centre; cylinder: the
                            centre of one end [m]                    */
  double axis[MPGM_DIM]; /**< cylinder: from the centre of one end to
                            the centre of the other [m]              */
  double radius;       /**< disk, sphere, cylinder, ring: (outer)
                            radius [m]                               */
  double radius_in;    /**< ring: inner radius [m]                   */
  double angle[2];     /**< ring: the sector from angle[0] to angle[1]
                            [rad], counter-clockwise from +x          */
  int npoints;         /**< polygon: vertices (3..MPGM_POLYGON_MAX)   */
  double points[2 * MPGM_POLYGON_MAX]; /**< polygon: x0, y0, x1, y1, ...
                            in the order given (either orientation);
                            simple, no repeated vertex [m] (a polygon
                            of the x-y plane, (x, y) pairs; in 3-D
                            extruded over z)                        */
  double z[2];         /**< polygon in 3-D: the extrusion z0 < z1 [m] */
  double velocity[MPGM_DIM]; /**< initial velocity [m/s]             */
  int geostatic;       /**< 1: geostatic initial stress is given       */
  double surface;      /**< geostatic: the free surface's coordinate
                            along the vertical (mpgm_scene_vertical) [m] */
  double k0;           /**< geostatic: each horizontal normal stress is
                            k0 times the vertical one                  */
} mpgm_scene_body;

typedef struct mpgm_scene_boundary {
  char name[MPGM_NAME_LEN];
  int select;          /**< mpgm_select                              */
  double value;        /**< x, y (or z) of the selecting line (plane)
                            [m]                                      */
  double min[MPGM_DIM], max[MPGM_DIM]; /**< box [m]                  */
  double tol;          /**< selection tolerance [m]                  */
  int condition;       /**< mpgm_condition (how fix was given)        */
  int fix[MPGM_DIM];   /**< 1: component fixed (after condition)      */
  int side;            /**< contact: +1 body on the + side of the plane
                            (a floor or left wall), -1 on the - side    */
  double displacement[MPGM_DIM]; /**< prescribed value of fixed components at
                               the end of the run [m] (ramped)        */
  int enforce;         /**< contact: MPGM_ENFORCE_NODES or _POINTS     */
  double penalty;      /**< contact at points: stiffness per point per
                            unit thickness [Pa] (scene: a multiple of
                            the largest Young's modulus, resolved here) */
  double spacing;      /**< contact at points: spacing of the surface
                            points along the bodies' boundaries [m]     */
} mpgm_scene_boundary;

/** 1 when boundary bc is a contact enforced at the bodies' surface points
 *  (condition "contact", "enforce": "points"; core/contact_points.c). */
static inline int mpgm_bc_at_points(const mpgm_scene_boundary *bc) {
  return bc->condition == MPGM_COND_CONTACT && bc->enforce == MPGM_ENFORCE_POINTS;
}

/** A rigid obstacle (front ends with the obstacles trait): layers of fixed nodes (no material
 *  points) beyond a plane x = value or y = value, spacing mesh.h, aligned
 *  with the grid over mesh.domain and spanning its extent along the plane
 *  (docs/scene-format.md, "obstacles"). */
typedef struct mpgm_scene_obstacle {
  char name[MPGM_NAME_LEN];
  int axis;            /**< 0: plane x = value; 1: plane y = value    */
  double value;        /**< the plane [m]; on a grid line              */
  int side;            /**< -1: the nodes lie on the - side (below, left)
                            of the plane, +1 on the + side (above, right) */
  int gap;             /**< the first layer lies gap h beyond the plane */
  int layers;          /**< node layers: at value + side (gap + l) h,
                            l = 0 .. layers - 1                          */
} mpgm_scene_obstacle;

typedef struct mpgm_scene_probe {
  char name[MPGM_NAME_LEN];
  double x[MPGM_DIM];  /**< reference position [m]                   */
} mpgm_scene_probe;

/** How persistent nodes move with a step (mesh.node_motion): with their
 *  own coefficient's increment, or with the increment of the displacement
 *  field at their position, sum_J N_J(x_I) du_J (GMM, finite strain). */
typedef enum { MPGM_NODES_COEFFICIENT = 0, MPGM_NODES_INTERPOLATED } mpgm_node_motion;

/** The keys of "shape" a front end declares (mpgm_frontend_type.
 *  shape_keys): method gmm's sparsity pattern and tangent over node
 *  clouds (docs/scene-format.md, "shape"); zero for the other methods. */
typedef struct mpgm_pattern_opts {
  double skin;           /**< the pattern's skin, a multiple of mesh.h (0:
                              a pattern per change of the clouds;
                              discretisation/skin.c)                    */
  double tangent_radius; /**< the tangent couples the nodes within this
                              radius (a multiple of mesh.h; and the skin)
                              of each point only; 0: the clouds'        */
  double tangent_tol;    /**< the tangent's radius where the kind's weight
                              falls to this value (0: tangent_radius or
                              none; gmm/gmm.c makes it a radius)       */
} mpgm_pattern_opts;

/** The keys of "mesh" a front end declares (mpgm_frontend_type.
 *  mesh_keys): the rules for its nodes (docs/scene-format.md, "mesh");
 *  zero for a key the scene's method does not declare. */
typedef struct mpgm_mesh_params {
  double min_node_mass;     /**< mpm, gmm on the grid: nodes lighter than
                                 this fraction of the step's heaviest node
                                 get no equations                        */
  double min_node_distance; /**< gmm on the grid: a free node closer than
                                 this times h to a lower-numbered free
                                 node is left out of the step (0: off)  */
  int node_motion;          /**< mpgm_node_motion (gmm, finite strain)  */
} mpgm_mesh_params;

/** The keys of "time" a time scheme declares (mpgm_integrator_type.
 *  keys): the explicit npc's (docs/scene-format.md, "Explicit schemes");
 *  zero for the other schemes. */
typedef struct mpgm_scheme_params {
  double npc_gamma; /**< gamma of the predictor and corrector (003 eqs
                         30-31)                                          */
  int npc_eq34;     /**< 1: the points move by 003's eq 34, dt V + dt^2 A
                         / 2 with the corrected V; 0 ("newmark"): by dt
                         v_pred, the displacement their strain used     */
} mpgm_scheme_params;

typedef struct mpgm_scene {
  char file[MPGM_PATH_LEN]; /**< scene file as given                  */
  char stem[MPGM_NAME_LEN]; /**< file name without folder and .json    */
  const struct mpgm_frontend_type *frontend; /**< "method": the front end
                                 (frontends/, resolved by name)         */
  const mpgm_shapefn_type *shape;
  mpgm_shape_params shape_par; /**< meshfree kinds: shape.gamma, radius,
                                 dilation, tol_support, max_cond, order,
                                 grid_order, min_nodes, max_enlarge:
                                 the kind's keys (mpgm_shapefn_type.
                                 keys); h = mesh.h (all zero for "fe") */
  mpgm_pattern_opts pattern; /**< the front end's keys of "shape" (gmm:
                                 the pattern skin, the tangent radius)  */
  /* mesh */
  double h;                 /**< cell size [m]                         */
  int cell;                 /**< mpgm_cell_kind                        */
  int ppc;                  /**< points per cell                       */
  mpgm_mesh_params mesh_par; /**< the front end's keys of "mesh" (the
                                 light-node and close-node rules, the
                                 nodes' motion)                         */
  int layout_centres;       /**< mesh.layout: 1 "centres" (points at the
                                 centres of ppc equal sub-cells of a quad,
                                 as uGIMP wants), 0 "gauss" (the Gauss
                                 points)                                 */
  double dom_min[MPGM_DIM], dom_max[MPGM_DIM]; /**< domain box [m]     */
  /* kinematics and time */
  int kinematics;           /**< mpgm_kinematics                       */
  int analysis;             /**< mpgm_analysis                         */
  double dt, t_end;         /**< dynamic: step and end time [s]        */
  int load_steps;           /**< static: number of load steps          */
  double beta, gamma;       /**< Newmark parameters                    */
  double hht_alpha;         /**< HHT's alpha in [-1/3, 0]: forces weighted
                                 (1 + alpha) at t_n+1, -alpha at t_n; 0:
                                 Newmark (newton.c, assembly.c)         */
  int max_cuts;             /**< step control: a step that fails
                                 recoverably is retried with half the
                                 step, down to the scene's step / 2^
                                 max_cuts (0: the run stops at once)   */
  int grow_after;           /**< step control: after this many steps
                                 in a row converge at a cut size, the
                                 step doubles back (up to dt or
                                 1 / load_steps)                       */
  int grow_backoff;         /**< step control (default 0): a step that fails at
                                 once after growing doubles the easy
                                 steps the next growth waits for (back
                                 to grow_after when a grown step
                                 converges)                            */
  int lumped_mass;          /**< dynamic: 1: the inertia of the implicit
                                 Newmark step with the row-sum (lumped)
                                 mass, diag sum_p m_p N_Ip, as the explicit
                                 schemes; 0: the consistent mass        */
  int initial_accel;        /**< dynamic: 1: a_0 from M a_0 = f_ext -
                                 f_int(sigma_0) before the first step;
                                 0: a_0 = 0                          */
  int predictor_velocity;   /**< dynamic: Newton starts from du = dt v
                                 (free components) instead of du = 0  */
  const mpgm_integrator_type *integrator; /**< how a step is solved: from
                                 time.analysis (static, dynamic: the
                                 implicit Newmark integrator; explicit:
                                 time.scheme)                          */
  double cfl;               /**< explicit without time.dt: dt = cfl h /
                                 max(max |v_p|, max c_p) each step
                                 (at least MPGM_CFL_MIN)                */
  int allow_unstable_dt;    /**< explicit with time.dt: 1: a time.dt above
                                 the stability limit h / max speed is
                                 warned about once and taken; 0 (the
                                 default): the run fails at that step   */
  int max_steps;            /**< most steps of a run (time.max_steps):
                                 fixed steps beyond it are refused at
                                 load, a run that reaches it before its
                                 end fails (core/run.c)                 */
  double local_damping;     /**< explicit: Cundall's local damping factor
                                 alpha in [0, 1): each free nodal force
                                 component loses alpha |f| against the
                                 node's velocity (0: none)              */
  int kinetic_damping;      /**< explicit: 1: every point's velocity and
                                 acceleration are set to zero when the
                                 kinetic energy has passed a peak (a
                                 dynamic relaxation to rest)            */
  mpgm_scheme_params scheme; /**< the time scheme's own keys of "time"
                                 (mpgm_integrator_type.keys)            */
  /* solver */
  const mpgm_solver_type *solver; /**< solver.linear ("auto": the composite
                                 Cholesky / LU backend)               */
  double rtol, atol, dtol;  /**< Newton: relative and absolute residual,
                                 relative displacement increment       */
  int max_iter;             /**< Newton iteration limit                */
  int newton_modified;      /**< 1: keep the factorisation while Newton
                                 converges fast enough (reuse_ratio)    */
  int newton_bfgs;          /**< 1: modified Newton with BFGS updates of
                                 the kept factorisation (core/bfgs.c)   */
  int bfgs_pairs;           /**< newton bfgs: the newest pairs kept
                                 (at most MPGM_BFGS_PAIRS_MAX)          */
  double reuse_ratio;       /**< modified Newton: refactorise when
                                 |R_k| > reuse_ratio |R_k-1|             */
  int newton_krylov;        /**< 1: Newton-Krylov: GMRES on every
                                 iteration's tangent, preconditioned by
                                 the last factorisation of `solver`
                                 (solvers/reuse.c; refactor_iterations in
                                 solver_opts)                           */
  double relaxation;        /**< Newton found stalled (|R| repeating
                                 every other iteration): the factor on
                                 its corrections until |R| falls tenfold
                                 (1: never; newton.c)                   */
  int stagnation;           /**< Newton ends (not converged) when its
                                 best |R| of the last `stagnation`
                                 iterates is not half the best before
                                 them (0: never; newton.c)              */
  int line_search;          /**< most backtracks along a correction of
                                 the current tangent while |R| does not
                                 fall (0: full corrections; newton.c)   */
  int contact_rank;         /**< modified Newton with contact at points:
                                 spring changes applied to the kept
                                 factorisation, up to this many rank-one
                                 terms (0: refactorise; lowrank.c)      */
  int forcing_ew;           /**< 1: the linear tolerance of each Newton
                                 iteration by Eisenstat and Walker
                                 (iterative solves only); 0: linear_tol */
  double contact_check;     /**< contact: check the active set once
                                 |R| <= contact_check ref (0: only at
                                 convergence); default 1e-6 with contact
                                 at points, 1e-3 otherwise             */
  int ordering_nd;          /**< 1: fill-reducing order by geometric
                                 nested dissection of the node graph
                                 (core/ordering.c); 0: the backend's own
                                 (AMD)                                 */
  int threads;              /**< threads of BLAS under the solvers (0:
                                 the libraries' defaults)              */
  mpgm_solver_opts solver_opts; /**< iterative backends: solver.linear_tol
                                 (1e-10), linear_restart (100),
                                 linear_max_iterations (5000)          */
  int loop_threads;         /**< threads of mpgm's point and assembly
                                 loops (0: one per online core)       */
  /* physics */
  int nmat;
  mpgm_material *mats;
  int nbody;
  mpgm_scene_body *bodies;
  int nbc;
  mpgm_scene_boundary *bcs;
  int nobstacle;
  mpgm_scene_obstacle *obstacles; /**< rigid node layers                */
  int nprobe;
  mpgm_scene_probe *probes;
  double gravity[MPGM_DIM]; /**< [m/s^2]                               */
  double gravity_ramp;      /**< dynamic: period T [s] of the ramp of
                                 Molinos et al. 2021 eq 45, gravity times
                                 (1 - cos(2 pi t / T)) / 2 until T/2, then
                                 in full (0: in full from t = 0)       */
  int manufactured;         /**< "manufactured": a manufactured solution
                                 drives the run (body force b(X, t) on
                                 every point, initial velocity) and is
                                 the reference of its errors           */
  mpgm_mms mms;             /**< its parameters (E, nu, rho0 from the
                                 scene's one material)                 */
  mpgm_reference reference; /**< reference solution; type NULL if none  */
  /* output */
  char out_dir[MPGM_PATH_LEN];
  int from_file;            /**< 1: loaded from a scene file (its
                                 output.dir must stay below the current
                                 folder); 0: from a run's own record (the
                                 resolved scene of a checkpoint or a
                                 summary.json)                         */
  int every;                /**< write VTK every n steps                */
  int grid;                 /**< output.grid: the background grid series */
  int checkpoint_every;     /**< write a checkpoint every n steps (0: never) */
  int ntimes;               /**< output.times: entries of times         */
  double times[64];         /**< output.times: steps end exactly at these
                                 times (load factors, static) and VTK is
                                 written there; increasing              */
  int vtk;                  /**< mpgm_vtk_mode: none (no series at all),
                                 ascii or binary (the encoding of .vtu and
                                 .vtk frames)                          */
  unsigned formats;         /**< mpgm_format mask (output.format)        */
  int compress;             /**< mpgm_compress (output.compress)         */
  int nmatrices;            /**< output.matrices: entries of matrices   */
  long matrices[MPGM_MATRICES_MAX]; /**< output.matrices: steps (from 1)
                                 whose tangents and right-hand sides are
                                 written to DIR/matrices (Matrix Market);
                                 increasing                             */
  unsigned fields;          /**< mpgm_field mask                        */
  void *resolved;           /**< cJSON tree of every resolved value     */
} mpgm_scene;


/** 1 when the reference position x [m] lies inside body b or on its
 *  boundary within 1e-12 of the body's size (the sum of its bounding box's
 *  sides; for a disk or sphere, its diameter), else 0. Needs b->min/max to hold the
 *  bounding box (the loader fills them; see mpgm_body_bbox). Polygons: a
 *  crossing-number test with the half-open rule, after a distance test
 *  against every edge near x, so vertices and edges count as inside.
 *  No allocation; safe to call from per-point loops. */
int mpgm_body_contains(const mpgm_scene_body *b, const double x[MPGM_DIM]);
/** Bounding box [m] of body b, computed from its geometry data (rectangle
 *  corners, disk centre and radius, polygon vertices). */
void mpgm_body_bbox(const mpgm_scene_body *b, double min[MPGM_DIM], double max[MPGM_DIM]);

/** Measure (2-D area [m^2], 3-D volume [m^3]), the measure of its boundary
 *  (2-D perimeter [m], 3-D surface area [m^2]) and narrowest extent [m]
 *  (the diameter of a disk or sphere, the radial width of a ring, the
 *  smaller of a cylinder's diameter and length, the shortest side of the
 *  bounding box otherwise) of body b, from its geometry data (the memory
 *  estimate, io/scene_size.c). */
double mpgm_body_area(const mpgm_scene_body *b);
double mpgm_body_perimeter(const mpgm_scene_body *b);
double mpgm_body_width(const mpgm_scene_body *b);

/** Signed area of the polygon p (n points x0, y0, x1, y1, ...) [m^2];
 *  > 0 when counter-clockwise. */
double mpgm_polygon_area(const double *p, int n);

/** 0 when p (n points) is an admissible polygon body: 3 to
 *  MPGM_POLYGON_MAX points, no two consecutive points equal (the last one
 *  is joined to the first), non-zero area, no two edges that cross, touch
 *  or overlap. Otherwise 1, with what is wrong in msg. Tolerances are
 *  1e-12 of the bounding box (width + height). */
int mpgm_polygon_check(const double *p, int n, char *msg, size_t len);

/** 1 when body b (bounding box in b->min/max) meets the closed box
 *  [lo, hi] (touching counts), else 0. Exact for every kind but the
 *  cylinder, which is taken to meet every box its bounding box meets (the
 *  callers check selectors, whose exact node selection a front end checks
 *  again). */
int mpgm_body_meets_box(const mpgm_scene_body *b, const double lo[MPGM_DIM],
                        const double hi[MPGM_DIM]);

/** The vertical axis of a scene: that of gravity's largest component
 *  (the last of equal ones; y, or z in 3-D, without gravity). Geostatic
 *  stress and its free surface are measured along it. */
static inline int mpgm_scene_vertical(const mpgm_scene *s) {
  int v = MPGM_DIM - 1;
  for (int d = MPGM_DIM - 2; d >= 0; d--)
    if (fabs(s->gravity[d]) > fabs(s->gravity[v])) v = d;
  return v;
}

/** 1 when some boundary of s is a contact at surface points. */
static inline int mpgm_scene_contact_at_points(const mpgm_scene *s) {
  for (int i = 0; i < s->nbc; i++)
    if (mpgm_bc_at_points(&s->bcs[i])) return 1;
  return 0;
}

/** 1 when a scene boundary selects the node at X (plane within tol, or box). */
int mpgm_boundary_selects(const mpgm_scene_boundary *bc, const double X[MPGM_DIM]);

/** The factor of gravity at time t of a dynamic run: the ramp of
 *  gravity_ramp (eq 45 of Molinos et al. 2021), 1 without one. */
static inline double mpgm_gravity_ramp(const mpgm_scene *s, double t) {
  const double T = s->gravity_ramp;
  if (!(T > 0.0) || t >= 0.5 * T) return 1.0;
  return 0.5 * (1.0 - cos(6.283185307179586 * t / T));
}

#ifdef __cplusplus
}
#endif
#endif
