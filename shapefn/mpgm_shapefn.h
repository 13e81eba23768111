/* mpgm_shapefn.h -- the shape-function plug-in family.
 *
 * Contract shared by every kind: given a material point and its candidate
 * nodes, return N_I and grad N_I (with respect to the configuration the node
 * coordinates are given in), or an error code. Cell-based kinds (FE) also
 * take the cell kind and the point's local coordinates in that cell;
 * meshfree kinds (MLS, LME) take the cloud, a parameter struct and, for LME,
 * the point's Lagrange multiplier as warm start.
 *
 * Errors of eval: 0; recoverable MPGM_ERR_JACOBIAN (inverted FE cell) or
 * MPGM_ERR_SHAPE (singular / ill-conditioned moment matrix or Hessian,
 * point outside the convex hull of its cloud, Newton not converged: the
 * caller may enlarge the cloud and retry, see mpgm_shape_info); fatal
 * MPGM_ERR_INPUT (more than MPGM_SHAPE_MAXNODE nodes, missing length scale).
 * Meshfree kinds never return NaN: on failure N and dN are zero.
 */
#ifndef MPGM_SHAPEFN_H
#define MPGM_SHAPEFN_H

#include "mpgm_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Cell kinds of finite-element connectivity. */
typedef enum {
  MPGM_CELL_T3 = 0, /**< linear triangle, nodes counter-clockwise      */
  MPGM_CELL_Q4 = 1, /**< bilinear quadrilateral, nodes counter-clockwise */
  MPGM_CELL_H8 = 2  /**< trilinear hexahedron: the bottom face (z = -1)
                         counter-clockwise seen from +z, then the top face
                         above it in the same order                      */
} mpgm_cell_kind;

/** Largest number of nodes a point may be connected to by a cell (2-D:
 *  Q4's 4; 3-D: H8's 8). */
#define MPGM_FE_MAXNODE (1 << MPGM_DIM)
/** Most points of a cell's Gauss or sub-cell rule (2-D 3 x 3, 3-D
 *  3 x 3 x 3): the size of a rule's buffers. */
#define MPGM_MAXRULE (MPGM_DIM == 2 ? 9 : 27)
/** Corners of a particle domain (CPDI): a parallelogram's 4, a
 *  parallelepiped's 8. */
#define MPGM_NCORNER (1 << MPGM_DIM)
/** Largest cloud a meshfree kind accepts (stack workspaces are sized by it;
 *  a larger query is MPGM_ERR_INPUT). */
#define MPGM_SHAPE_MAXNODE 128

/** Parameters of the meshfree kinds. A zero field means its default, so a
 *  zero-initialised struct is usable once the length scale is set (h, or
 *  radius for MLS): no length can be defaulted. FE ignores the struct. */
typedef struct mpgm_shape_params {
  double h;           /**< nodal spacing [m]. LME: beta = gamma / h^2 and the
                           scale of lambda and of tol_newton (required, > 0).
                           MLS: support radius = dilation * h when radius = 0 */
  /* LME (Arroyo & Ortiz 2006) */
  double gamma;       /**< dimensionless locality gamma = beta h^2; default 1.8
                           (0.8 spread-out ... 4 near-FE; FE limit as gamma
                           grows; lower tol_support when gamma > -ln(tol)) */
  double tol_support; /**< nodes where exp(-beta r^2) < tol_support are cut
                           off: r_max = h sqrt(-ln(tol_support) / gamma);
                           default 1e-6                                       */
  double tol_newton;  /**< Newton stops when |r| / h < tol_newton (r = grad of
                           log Z = sum N_a (x - x_a) = x - sum N_a x_a);
                           default 1e-10                                      */
  int max_newton;     /**< Newton iteration limit; default 100 (a point on the
                           hull boundary needs ~ln(1/tol_newton) iterations
                           from a cold start)                                 */
  double max_cond;    /**< largest accepted condition number of the LME
                           Hessian J (2-norm) or of the MLS moment matrix M
                           (1-norm, scaled basis); default 1e12 (LME; points
                           on the hull boundary reach ~1/tol_newton) and 1e10
                           (MLS)                                              */
  /* MLS */
  double radius;      /**< support radius R of the weight [m]; default
                           dilation * h                                       */
  double dilation;    /**< R / h when radius = 0; default 2.0                */
  int order;          /**< MLS basis: 1 linear (default, also for 0),
                           2 quadratic                                        */
  /* uGIMP */
  double half_width;  /**< half side lp of a particle's square (3-D: cube) [m] (required,
                           0 < lp <= h / 2; a scene sets h / (2 sqrt(ppc)))  */
  /* CPDI */
  int grid_order;     /**< grid functions: 1 (also 0) the bilinear hats,
                           2 the quadratic B-splines (shape.grid_functions) */
  double grid_lo[MPGM_DIM], grid_hi[MPGM_DIM]; /**< the grid's box [m]: a domain corner
                           beyond it is pulled back onto its edge (the
                           point itself must lie inside); no box when
                           grid_hi <= grid_lo                               */
  /* cloud control of the kinds over node clouds (MLS, LME), read by the
   * front ends (discretisation/clouds.c), not by eval */
  int min_nodes;      /**< smallest cloud: the search radius grows x1.25
                           until it holds this many nodes (0: 6, or 12 for
                           quadratic MLS)                                   */
  int max_enlarge;    /**< cloud enlargements per point and step before the
                           step fails (the scene's default 16; 0: none)     */
} mpgm_shape_params;

/** The smallest cloud of par: min_nodes, or by default twice the basis
 *  (12 for a quadratic basis, else 6). */
static inline int mpgm_shape_min_nodes(const mpgm_shape_params *par) {
  return par->min_nodes > 0 ? par->min_nodes : par->order == 2 ? 12 : 6;
}

/** Why an evaluation failed (mpgm_shape_info.reason). */
typedef enum {
  MPGM_SHAPE_OK = 0,
  MPGM_SHAPE_BAD_INPUT,     /**< n out of range, no length scale, bad cell   */
  MPGM_SHAPE_INVERTED,      /**< FE cell with det J <= 0                     */
  MPGM_SHAPE_TOO_FEW,       /**< fewer nodes in the support than the basis
                                 needs (MLS: 3 or 6; LME: 3)                   */
  MPGM_SHAPE_ILL_COND,      /**< moment matrix / Hessian singular or its
                                 condition number > max_cond                  */
  MPGM_SHAPE_OUTSIDE_HULL,  /**< LME: point outside the convex hull of the
                                 nodes in its support                         */
  MPGM_SHAPE_NOT_CONVERGED, /**< LME: Newton on lambda hit max_newton or the
                                 line search stalled                           */
  MPGM_SHAPE_OFF_GRID       /**< uGIMP, CPDI: the weights do not sum to 1:
                                 nodes within h + lp of the point (of a
                                 domain corner) are missing (the grid ends
                                 there)                                       */
} mpgm_shape_reason;

/** Short fixed description of a reason ("point outside the convex hull of
 *  its cloud", ...). */
const char *mpgm_shape_reason_str(int reason);

/** Optional detail of one evaluation (filled on success and on failure).
 *  Callers count cloud enlargements and Newton iterations from it. */
typedef struct mpgm_shape_info {
  int reason;     /**< mpgm_shape_reason; MPGM_SHAPE_OK on success         */
  const char *msg;/**< static text of the reason (never NULL once filled)  */
  int iterations; /**< LME Newton iterations (0: the start was converged)  */
  int nsupport;   /**< nodes inside the support (N may be non-zero)        */
  double cond;    /**< condition number of J (LME) or M (MLS); 0 for FE    */
  double residual;/**< LME: final |r| / h                                  */
  int clamped;    /**< CPDI: domain corners pulled back onto the grid box  */
} mpgm_shape_info;

/* Failure handling by the caller (the GMM front end; Iaconeta et al. 2017,
 * section 5.3): on MPGM_ERR_SHAPE from a meshfree kind, add the nearest node
 * not yet in the cloud and evaluate again (keeping lambda as the start),
 * until it succeeds or the cloud reaches MPGM_SHAPE_MAXNODE; count the
 * enlargements (and Newton iterations) from mpgm_shape_info. The kinds
 * never change the cloud themselves. See docs/theory.md, section 12. */

/** One evaluation request. Use designated initialisers: fields left out are
 *  zero, which keeps FE callers unchanged. */
typedef struct mpgm_shape_query {
  int n;            /**< number of candidate nodes (<= MPGM_SHAPE_MAXNODE) */
  const double *xn; /**< their coordinates, MPGM_DIM per node [m]        */
  double xp[MPGM_DIM]; /**< point position [m]                           */
  int cell;         /**< mpgm_cell_kind for cell-based kinds, else -1    */
  double xi[MPGM_DIM]; /**< local coordinates of the point in the cell   */
  const mpgm_shape_params *par; /**< meshfree parameters (borrowed); NULL
                                     is MPGM_ERR_INPUT for meshfree kinds */
  double *lambda;   /**< LME per-point state in/out, MPGM_DIM values [1/m]: start
                         of Newton on entry (NULL or non-finite: zero),
                         converged multiplier on success (untouched on
                         failure). Ignored by other kinds.                */
  mpgm_shape_info *info; /**< optional out: reason and counters          */
  const double *domain;  /**< kinds with a particle domain (cpdi): its
                              MPGM_DIM half-axes r1, r2 (, r3), MPGM_DIM
                              components each [m]: the parallelogram
                              (parallelepiped) xp + sum_k s_k r_k,
                              |s_k| <= 1; NULL: a point without domain (a
                              tracer)                                     */
} mpgm_shape_query;

/** The signs (s1, s2, s3) of corner c of a particle domain, in the order
 *  of the cell's nodes (Q4, H8): -1, +1, +1, -1 in s1 around the face,
 *  -1, -1, +1, +1 in s2, and in 3-D the face s3 = -1 before s3 = +1. */
static inline double mpgm_corner_sign(int c, int k) {
  const int bit = k == 0 ? ((c & 1) ^ ((c >> 1) & 1)) : (c >> k) & 1;
  return bit ? 1.0 : -1.0;
}

/** The offsets of a particle domain's corners from its point, in the order
 *  of mpgm_corner_sign (2-D counter-clockwise: -r1 - r2, r1 - r2, r1 + r2,
 *  -r1 + r2). r: the MPGM_DIM half-axes, MPGM_DIM components each. */
static inline void mpgm_domain_corners(const double r[MPGM_TENSOR],
                                       double off[MPGM_NCORNER][MPGM_DIM]) {
  for (int c = 0; c < MPGM_NCORNER; c++)
    for (int d = 0; d < MPGM_DIM; d++) {
      double o = 0.0;
      for (int k = 0; k < MPGM_DIM; k++) o += mpgm_corner_sign(c, k) * r[MPGM_DIM * k + d];
      off[c][d] = o;
    }
}

/** A shape-function kind. */
typedef struct mpgm_shapefn_type {
  const char *name; /**< scene name: "fe", "mls", "lme"                   */
  const char *doc;  /**< one line for docs                                */
  int needs_cell;   /**< 1: connectivity comes from cells (FEM, MPM only);
                         0: meshfree, the caller gives a cloud of nodes
                         within mpgm_shape_support_radius of the point     */
  int grid_only;    /**< 1: the nodes must be a regular grid of spacing
                         h (uGIMP, CPDI: the background grid of MPM)     */
  int velocity_ls;  /**< 1: the nodal velocities are reconstructed by least
                         squares from the points' centres and domain
                         corners (CPLS), not projected                   */
  int domain;       /**< 1: the kind averages over the particle's domain
                         (q->domain; CPDI): the caller gives the nodes
                         within h of the domain's bounding box           */
  /** N (q->n values) and dN (MPGM_DIM per node: d/dx, d/dy (, d/dz)) at
   *  the point.
   *  Returns 0, MPGM_ERR_JACOBIAN (inverted cell), MPGM_ERR_SHAPE
   *  (recoverable; reason in q->info) or MPGM_ERR_INPUT. Nodes outside the
   *  support get N = 0, dN = 0. */
  int (*eval)(const mpgm_shape_query *q, double *N, double *dN);
  /** Optional (NULL for cell-based kinds): radius [m] of the node search
   *  around a point. Returns 0 or MPGM_ERR_INPUT (no length scale). */
  int (*support_radius)(const mpgm_shape_params *par, double *radius);
  /** Optional (NULL for kinds without a weight that falls with distance):
   *  the distance [m] at which the kind's weight falls to w (0 < w < 1) of
   *  its value at the point; LME h sqrt(-ln w / gamma). Returns 0 or
   *  MPGM_ERR_INPUT. shape.tangent_tol sets the tangent's radius by it. */
  int (*weight_radius)(const mpgm_shape_params *par, double w, double *radius);
  /** The kind's keys of the scene's "shape" section besides "kind", read
   *  into mpgm_shape_params (nkeys of them; none for "fe" and "ugimp"): a
   *  key another kind declares is refused with a message naming that
   *  kind (io/scene_keys.c). */
  const mpgm_key_spec *keys;
  int nkeys;
} mpgm_shapefn_type;

/** Radius [m] within which a meshfree kind needs the nodes of a point (the
 *  caller's radius search): LME h sqrt(-ln(tol_support) / gamma), MLS the
 *  weight's support radius. MPGM_ERR_UNSUPPORTED for kinds without it (FE),
 *  MPGM_ERR_INPUT without a length scale. */
int mpgm_shape_support_radius(const mpgm_shapefn_type *t, const mpgm_shape_params *par,
                              double *radius);

/** Cloud control shared by the front ends: a search radius holding fewer
 *  than shape.min_nodes nodes grows by MPGM_SHAPE_GROWTH; an enlargement
 *  after a failed evaluation sets the radius to MPGM_SHAPE_ENLARGE times the
 *  distance of the next-nearest node, so that node sits at 0.75 of the
 *  support: an MLS weight of w(0.75) = 1/32 (a node at the edge of the
 *  support would carry no weight) and well inside the LME cut-off. */
#define MPGM_SHAPE_GROWTH 1.25
#define MPGM_SHAPE_ENLARGE (4.0 / 3.0)

/** Parameters whose support radius is r (r >= r0, the radius of base; at
 *  r0 or below, base itself): MLS takes radius = r, LME the cut-off
 *  tol_support = exp(-gamma (r / h)^2). A front end that grows a point's
 *  search radius or enlarges its cloud widens the kind's support with it:
 *  a kind ignores nodes beyond its own support, so a larger cloud alone
 *  would change nothing. */
void mpgm_shape_params_for_radius(const mpgm_shape_params *base, double r0, double r,
                                  mpgm_shape_params *out);

/** t->eval(q, N, dN), and once more from lambda = 0 when a warm-started LME
 *  evaluation fails recoverably (a multiplier kept from a boundary position
 *  whose face has turned since can stall Newton; a cold start converges).
 *  *cold (may be NULL) is incremented on that retry. */
int mpgm_shape_eval_retry(const mpgm_shapefn_type *t, const mpgm_shape_query *q, double *N,
                          double *dN, long *cold);

/** Find a kind by scene name; NULL if none. */
const mpgm_shapefn_type *mpgm_shapefn_type_find(const char *name);
/** All kinds, NULL-terminated. */
const mpgm_shapefn_type *const *mpgm_shapefn_types(void);

/* ---- finite-element reference elements (used by the "fe" kind and by the
 *      front ends to place points and probes) ---------------------------- */

/* The cells of a build: T3 and Q4 in 2-D, H8 in 3-D; another kind is
 * MPGM_ERR_INPUT (eval, gauss) or 0 (nnode). Local coordinates and node
 * coordinates have MPGM_DIM components. */

/** Nodes of a cell kind (3, 4 or 8); 0 for a kind this build lacks. */
int mpgm_fe_nnode(int cell);
/** Reference shape functions and their derivatives d/dxi_k at xi
 *  (MPGM_DIM per node). T3: xi in the unit triangle (N = 1 - xi - eta, xi,
 *  eta); Q4: xi in [-1, 1]^2, nodes (-1,-1), (1,-1), (1,1), (-1,1); H8: xi
 *  in [-1, 1]^3, the Q4's nodes at zeta = -1, then at zeta = +1. */
void mpgm_fe_ref(int cell, const double xi[MPGM_DIM], double *N, double *dNdxi);
/** Gauss rule with npts points: T3: 1 or 3; Q4: 1, 4 or 9 (n x n); H8: 1,
 *  8 or 27 (n x n x n). xi: MPGM_DIM per point; w: weights (sum = the
 *  reference measure: 1/2, 4 or 8). Returns 0 or MPGM_ERR_INPUT for an
 *  unsupported count. */
int mpgm_fe_gauss(int cell, int npts, double *xi, double *w);
/** Sub-cell centres of the build's quadrilateral cell (Q4, H8): npts = n^DIM
 *  (n = 1, 2, 3) points at the centres of the n^DIM equal sub-cells, weight
 *  2^DIM / npts each (the midpoint rule on the sub-cells). Returns 0 or
 *  MPGM_ERR_INPUT for other counts. */
int mpgm_fe_centres(int npts, double *xi, double *w);
/** N and spatial gradients at local xi of a cell with node coordinates xn;
 *  detJ (may be NULL) receives det(dx/dxi). MPGM_ERR_JACOBIAN if detJ <= 0. */
int mpgm_fe_eval(int cell, const double *xn, const double xi[MPGM_DIM], double *N,
                 double *dN, double *detJ);
#if MPGM_DIM == 3
/** The H8 functions at xi of an axis-aligned cube of side h (a cell of the
 *  structured grid): the N of mpgm_fe_ref and grad N = (2 / h) dN/dxi,
 *  what mpgm_fe_eval gives on that cube (to round-off) without forming
 *  and inverting its Jacobian. */
void mpgm_fe_cube(const double xi[3], double h, double *N, double *dN);
#endif
/** Local coordinates of point x in a cell (Newton for Q4 and H8, exact for
 *  T3). Returns 0, or MPGM_ERR_SHAPE if the inversion does not converge. */
int mpgm_fe_local(int cell, const double *xn, const double x[MPGM_DIM], double xi[MPGM_DIM]);
/** 1 when local coordinates xi lie in the reference cell (with slack tol). */
int mpgm_fe_inside(int cell, const double xi[MPGM_DIM], double tol);

#ifdef __cplusplus
}
#endif
#endif
