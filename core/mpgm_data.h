/* mpgm_data.h -- the data model every layer shares: material points,
 * nodes, connectivity (the seam between "which method" and "which
 * physics"), and the effects a scene calls for. Arrays are structures of
 * arrays with MPGM_DIM components per vector, MPGM_TENSOR per tensor (F),
 * MPGM_NSTRESS per stress and MPGM_NTANGENT per material tangent
 * (mpgm_base.h). */
#ifndef MPGM_DATA_H
#define MPGM_DATA_H

#include <string.h>

#include "mpgm_base.h"
#include "mpgm_material.h"
#include "mpgm_pool.h"
#include "mpgm_scene.h"
#include "mpgm_shapefn.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Material points (integration points) as structure of arrays; the first
 *  n are material points, the next nprobe are massless tracers (probes)
 *  that are moved exactly as material points but never assembled. */
typedef struct mpgm_points {
  int n;          /**< material points                                 */
  int nprobe;     /**< probes: tracer points after the material points */
  int nsurf;      /**< surface tracers after the probes: points on the
                       bodies' boundaries where contact is enforced
                       (mpgm_cpoints); 0 without contact at points     */
  int nstate;     /**< state doubles per point (max over materials)    */
  double *x;      /**< current position, MPGM_DIM per point [m]        */
  double *x0;     /**< initial position, MPGM_DIM per point [m]        */
  double *u;      /**< total displacement, MPGM_DIM per point [m]      */
  double *v;      /**< velocity, MPGM_DIM per point [m/s]              */
  double *a;      /**< acceleration, MPGM_DIM per point [m/s^2]        */
  double *mass;   /**< mass [kg] (per unit thickness)                  */
  double *vol0;   /**< initial volume [m^3] (per unit thickness)       */
  double *vol;    /**< current volume [m^3]                            */
  double *F;      /**< committed deformation gradient, MPGM_TENSOR per
                       point                                           */
  double *sigma;  /**< committed Cauchy stress {xx, yy, xy, zz} [Pa],
                       MPGM_NSTRESS per point                          */
  double *r0;     /**< initial half-axes r1, r2 (, r3) of the point's
                       domain, MPGM_DIM of MPGM_DIM components each,
                       MPGM_TENSOR per point [m] (a square or cube of the
                       point's volume, or the layout's shape): the
                       parallelogram (parallelepiped) x +- r1 +- r2
                       (+- r3); now F r0 (shape kinds with a domain:
                       CPDI)                                           */
  double *L;      /**< velocity gradient of the last step, MPGM_TENSOR
                       per point [1/s] (kept for CPLS: the velocity at
                       the domain's corners, v_p + L (x_c - x_p))      */
  double *S0;     /**< initial (pre-)stress {xx, yy, xy, zz} [Pa] at the
                       initial configuration, pushed forward with F
                       (MPGM_NSTRESS per point)                        */
  double *state;  /**< committed material state, nstate per point      */
  int *mat;       /**< material index                                  */
  int *body;      /**< body index                                      */
  int *id;        /**< the point's number at creation: points may be
                       reordered (mpgm_points_sort), ids stay          */
  /* trial values of the current Newton iterate (n material points): F_t
   * and dF_t MPGM_TENSOR, sigma_t MPGM_NSTRESS, D_t MPGM_NTANGENT each */
  double *F_t, *sigma_t, *D_t, *state_t, *vol_t, *dF_t;
  int cap;        /**< rows every array above has room for (>= n +
                       nprobe + nsurf): a run on many processes grows
                       them as points arrive (mpgm_points_exchange)    */
} mpgm_points;

/** The current half-axes of point p's domain, r_k = F_p r_k^0 (the sums
 *  in the order the plane code wrote them out). */
static inline void mpgm_point_domain(const mpgm_points *P, int p, double r[MPGM_TENSOR]) {
  const double *F = P->F + MPGM_TENSOR * p, *r0 = P->r0 + MPGM_TENSOR * p;
  for (int c = 0; c < MPGM_DIM; c++)
    for (int i = 0; i < MPGM_DIM; i++) {
      double v = F[MPGM_DIM * i] * r0[MPGM_DIM * c];
      for (int j = 1; j < MPGM_DIM; j++) v += F[MPGM_DIM * i + j] * r0[MPGM_DIM * c + j];
      r[MPGM_DIM * c + i] = v;
    }
}

/** Nodes (degrees of freedom carriers). */
typedef struct mpgm_nodes {
  int n;          /**< nodes in use                                     */
  int cap;        /**< allocated nodes (n <= cap; MPM: the whole grid)  */
  double *mass;   /**< nodal mass projected from the points [kg]
                       (front ends that project; else 0)              */
  double *X;      /**< initial position, MPGM_DIM per node [m]          */
  double *x;      /**< position at the start of the step [m]            */
  double *u;      /**< total displacement at the start of the step [m]  */
  double *du;     /**< displacement increment of the step [m]           */
  double *v, *a;  /**< velocity / acceleration at the start of the step */
  double *v_new, *a_new; /**< Newmark-corrected values of the iterate   */
  unsigned char *fix;    /**< MPGM_DIM per node: 1 when the component is
                              fixed                                     */
  signed char *contact;  /**< per node: 0, or +-(axis + 1) for a node on a
                              unilateral contact plane whose normal is that
                              axis, the body on the + or - side         */
  double *ubar;   /**< MPGM_DIM per node: prescribed total displacement
                       at the end of the run (fixed components; ramped) */
  int *dof;       /**< MPGM_DIM per node: equation number, -1 when fixed */
  int ndof;       /**< free equations                                   */
  const unsigned char *owned; /**< a run on many processes: 1 at the nodes
                       this process owns in the partition (a node shared
                       with others counts on one only), set by the front
                       end each step (its array); NULL on one process  */
} mpgm_nodes;

/** Connectivity in CSR: point p is connected to node[ptr[p] .. ptr[p+1]). */
typedef struct mpgm_conn {
  int np;         /**< points covered (material + tracers)              */
  int cap;        /**< allocated entries                                */
  int pcap;       /**< room of ptr (>= np + 1 once reserved)           */
  int *ptr;       /**< np + 1 offsets                                   */
  int *node;      /**< node ids                                         */
  double *N;      /**< shape function values                            */
  double *dN;     /**< grad N at the start-of-step configuration,
                       MPGM_DIM each                                    */
  double *g;      /**< grad N at the current iterate, MPGM_DIM each
                       (work; formed only by an evaluation of the points
                       for a tangent: the residual reads dN)            */
  int version;    /**< incremented by a front end when the node set,
                       fixity or matrix pattern changes                  */
  int map_version;/**< incremented when only the point -> node lists
                       changed (same nodes, fixity and pattern)          */
  /* optional (NULL: the lists above give the pattern): per material point
   * a superset of its node list that the sparsity pattern is built from
   * (node clouds with a skin, shape.skin), owned by the front end, which
   * increments pversion when it changes them (and version with it) */
  const int *pptr, *pnode;
  int pversion;
  /* optional (NULL: every entry): per entry of the material points, 1 when
   * its node enters the point's tangent terms (node clouds with
   * shape.tangent_radius: the nodes of the point's pattern list), owned
   * by the front end; R always takes every entry */
  const unsigned char *tan;
  /* the transpose, node -> entries of the material points
   * (mpgm_conn_transpose): for node I the entries tk[tptr[I] ..
   * tptr[I + 1]) in increasing order, tp the point of each; a sum over
   * them adds in the order of a loop over the points */
  int tn;         /**< nodes of the transpose (0: none built)            */
  int *tptr, *tk, *tp;
  unsigned char *tc; /**< per transpose entry: 1 when its point continues
                        the run of the point before (mpgm_conn_same),
                        decided once per point for mpgm_run_gather     */
  int tncap, tkcap; /**< room of tptr (nodes), of tk, tp, tc (entries)  */
  /* the runs of the points (mpgm_conn_runs), for the run sums: rc[p] 1
   * when point p continues the run of point p - 1 (mpgm_conn_same), for
   * p < rn; rn 0 when none are known. Whoever changes a material point's
   * list sets rn to 0 (mpgm_conn_par_build, mpgm_light_drop; every step
   * begins with none known) */
  unsigned char *rc;
  int rn, rcap;
} mpgm_conn;

/** The effects a scene calls for, decided when it loads. */
typedef struct mpgm_effects {
  int inertia;        /**< dynamic analysis: mass, Newmark, K_dyn       */
  int gravity;        /**< non-zero gravity: body-force loop            */
  int geometric;      /**< finite kinematics: K_geo and config update   */
  int plasticity;     /**< a plastic material is used                   */
  int prescribed;     /**< non-zero prescribed displacements            */
  int contact;        /**< unilateral contact at grid nodes (active set)  */
  int contact_points; /**< unilateral contact at surface points (penalty,
                           active set; core/contact_points.c)          */
  int prestress;      /**< a body has a geostatic initial stress         */
  int manufactured;   /**< a manufactured solution's body force b(X, t)
                           on every point (scene "manufactured")         */
  int tangent;        /**< an implicit integrator: a tangent is assembled
                           and factorised (explicit schemes: 0)         */
} mpgm_effects;

/** The effects a scene calls for: the one place they are decided (used by
 *  mpgm_problem_create and by `mpgm check`). */
void mpgm_effects_of_scene(const mpgm_scene *s, mpgm_effects *fx);

/** Allocate points (n material, nprobe probes, nsurf surface tracers) with
 *  nstate doubles. */
int mpgm_points_alloc(mpgm_ctx *ctx, mpgm_points *p, int n, int nprobe, int nsurf, int nstate);
/** Material point p of scene body `body` at x with volume vol [m^3]:
 *  position, mass (density x volume), the body's initial velocity,
 *  material, and the material's initial state. */
void mpgm_point_set(mpgm_points *P, int p, const mpgm_scene *s, int body, const double x[MPGM_DIM],
                    double vol);
/** Equivalent plastic strain of the n material points into out (may be
 *  NULL; 0 for points whose material has no plastic_strain operation).
 *  Returns the largest value (0 when there is none). */
double mpgm_points_plastic_strain(const mpgm_points *P, const mpgm_material *mats, double *out);
/** Reorder the material points (not the probes) by key[p] in [0, nkey),
 *  stably (counting sort), so that points that share nodes lie together in
 *  memory: every committed per-point array moves, ids included; the trial
 *  arrays are not moved (they are recomputed before use); the arrays move
 *  on the pool's threads (NULL: the caller's). perm (n ints,
 *  may be NULL) receives the old index of each new position, for the
 *  caller's own per-point arrays. */
int mpgm_points_sort(mpgm_ctx *ctx, mpgm_pool *pool, mpgm_points *p, const int *key, int nkey,
                     int *perm);
/** Doubles in the record of one material point (mpgm_points_pack): every
 *  committed per-point array, ints included (exactly, as doubles). */
int mpgm_point_record_len(const mpgm_points *P);
/** The material points p without keep[p], in order, into out (one record
 *  of mpgm_point_record_len doubles each): returns how many. */
int mpgm_points_pack(const mpgm_points *P, const unsigned char *keep, double *out);
/** The material points a process holds in a run on many: those with
 *  keep[p] and the nin records of in (those that arrived); the probes and
 *  surface tracers stay after them. In place, at a cost of the points that
 *  move, not of all: the arrivals take the rows of the points that left,
 *  then the rows past the end; where more left than arrived, the last
 *  rows fill the others (the order changes: ids travel with the points).
 *  The arrays grow (by an eighth more than needed) when the rows do not
 *  fit. A moved row's trial F, sigma and vol are its committed ones; the
 *  other trial rows stay as they were (a step writes them before use). */
int mpgm_points_exchange(mpgm_ctx *ctx, mpgm_points *p, const unsigned char *keep, int nin,
                         const double *in);
/** Allocate nodes. */
int mpgm_nodes_alloc(mpgm_ctx *ctx, mpgm_nodes *nd, int n);
/** Make room for nnz connectivity entries over np points. */
int mpgm_conn_reserve(mpgm_ctx *ctx, mpgm_conn *c, int np, int nnz);
/** Make room for at least nnz entries keeping the first `keep` entries of
 *  node, N and dN (a front end filling lists of unknown length); grows
 *  geometrically. */
int mpgm_conn_grow(mpgm_ctx *ctx, mpgm_conn *c, int keep, int nnz);
/** Release the arrays of a connectivity and zero it. */
void mpgm_conn_release(mpgm_conn *c);

/* ---- a connectivity built on the pool's threads (conn_par.c) ---------- */

#define MPGM_CONN_TASKS 64

/** One task of a parallel build: a range of points and the entries it
 *  staged for them. A point function appends with mpgm_conn_task_room and
 *  mpgm_conn_task_push, adds to count[] what a serial loop would add to
 *  the context's counters, and on failure returns the code with the
 *  complete message in msg (it runs on a worker thread: it touches neither
 *  the context nor anything shared). */
typedef struct mpgm_conn_task {
  int p0, p1;                /**< its points [p0, p1)                     */
  int n, cap;                /**< entries staged, room for                */
  int *node;                 /**< staged node ids                         */
  double *N, *dN;            /**< staged values, gradients (MPGM_DIM)      */
  int *len, lcap;            /**< entries of each of its points           */
  int off;                   /**< its first entry in the connectivity     */
  long count[MPGM_C_COUNT];  /**< counters raised                         */
  double t_aside;            /**< seconds to move to another timer        */
  double t_busy;             /**< seconds the task ran                    */
  int err, fail;             /**< first failure: its code and point       */
  int why_nomem;             /**< the failure was the staging's memory    */
  char msg[1536];            /**< the failure's message                   */
  int *iscr;                 /**< the point function's own scratch, kept  */
  size_t iscr_cap;           /**<   between builds (mpgm_conn_task_iscr)  */
} mpgm_conn_task;

/** The staging areas (kept between builds; zero-initialise, free with
 *  mpgm_conn_par_free). */
typedef struct mpgm_conn_par {
  int ntask;
  double t_aside; /**< after a build: the tasks' t_aside as a share of the
                       wall time of the build [s]                          */
  mpgm_conn_task t[MPGM_CONN_TASKS];
} mpgm_conn_par;

/** Append the entries of point p to t->node, N, dN at t->n (room made by
 *  mpgm_conn_task_room); returns 0 or a failure (see mpgm_conn_task). A
 *  task calls it for its points in order, from t->p0 (a function may
 *  prepare the whole range at its first point). */
typedef int (*mpgm_conn_point_fn)(void *arg, int p, mpgm_conn_task *t);

/** Room for `more` entries behind t->n: 0 or MPGM_ERR_NOMEM. */
int mpgm_conn_task_room(mpgm_conn_task *t, int more);
/** Room for n ints in t->iscr, its contents kept: 0 or MPGM_ERR_NOMEM. */
int mpgm_conn_task_iscr(mpgm_conn_task *t, size_t n);
static inline void mpgm_conn_task_push(mpgm_conn_task *t, int node, double N, const double *dN) {
  t->node[t->n] = node;
  t->N[t->n] = N;
  for (int c = 0; c < MPGM_DIM; c++) t->dN[MPGM_DIM * t->n + c] = dN[c];
  t->n++;
}
/** Entries of the points [0, np) of C by fn(arg, p, task) on the pool's
 *  threads, with C->ptr[0..np] (C->ptr has room for np + 1; node, N, dN
 *  grow as needed). The result is that of a serial loop for any number of
 *  threads. On a failure returns its code with the lowest failing point's
 *  task in *failed (its msg, fail); counters are those of the points a
 *  serial loop would have run. */
int mpgm_conn_par_build(mpgm_ctx *ctx, mpgm_pool *pool, mpgm_conn_par *cp, int np, mpgm_conn *C,
                        mpgm_conn_point_fn fn, void *arg, const mpgm_conn_task **failed);
/** Free the staging areas. NULL-safe. */
void mpgm_conn_par_free(mpgm_conn_par *cp);
/** Free one task's arrays (a caller's own staging of single points). */
void mpgm_conn_task_free(mpgm_conn_task *t);
/** The transpose of the lists of the points [0, np) of c over nnode
 *  nodes (c->tptr, tk, tp): each node's sums can then be gathered on its
 *  own, by the node ranges of mpgm_node_ranges, to the same bits as a
 *  scatter loop over the points. */
int mpgm_conn_transpose(mpgm_ctx *ctx, mpgm_conn *c, int np, int nnode);
/** The runs of points [0, np) into c->rc (nothing to do when c->rn is np
 *  already): one comparison of lists per point for every run sum of the
 *  step. */
int mpgm_conn_runs(mpgm_ctx *ctx, mpgm_conn *c, int np);
/** Whether the nodal sums over the lists of the points [0, np) of c are
 *  best gathered node by node through the transpose on the pool's threads
 *  (more than one thread and compact lists: at most 16 nodes per point on
 *  average) or scattered by one loop over the points (one thread, or wide
 *  meshfree clouds, whose gathers miss the cache: LME gamma 1.8 took 4x
 *  longer). Both give the same bits. */
static inline int mpgm_conn_gathers(const mpgm_pool *pool, const mpgm_conn *c, int np) {
  return mpgm_pool_size(pool) > 1 && c->ptr[np] <= 16L * np;
}
/* ---- run sums (3-D): the points of one cell follow one another in
 * memory (the MPM front end keeps them in cell order) and share its node
 * list. A nodal sum over such a run of points adds the run's values up
 * first and reaches each node once per run, not once per point: 8 points
 * per H8 cell make 8 times fewer read-modify-writes of the nodal arrays.
 * The scatter (one loop over the points) and the gather (node by node
 * through the transpose, on the pool's threads) add in the same order and
 * give the same bits. The plane-strain loops keep their point-by-point
 * sums, whose bits the 2-D golden records hold. */
#define MPGM_RUN_NODES 32 /**< longest list a run may have (more: runs of 1)   */
#define MPGM_RUN_VALUES 8 /**< most values an entry may bring to its node      */
/* the sums are inlined into each caller, with its entry function */
#if defined(__GNUC__)
#define MPGM_RUN_INLINE static inline __attribute__((always_inline))
#else
#define MPGM_RUN_INLINE static inline
#endif
/** The values (w of them) that entry k of point p brings to its node. */
typedef void (*mpgm_entry_fn)(const void *job, int p, int k, double *val);
/** Whether point p (> 0) continues the run of point p - 1: the same nodes
 *  in the same order, at most MPGM_RUN_NODES of them. */
MPGM_RUN_INLINE int mpgm_conn_same(const mpgm_conn *c, int p) {
  const int k = c->ptr[p], n = c->ptr[p + 1] - k;
  return n <= MPGM_RUN_NODES && n == k - c->ptr[p - 1] &&
         memcmp(c->node + k, c->node + k - n, sizeof(int) * (size_t)n) == 0;
}
/** Whether point p (> 0) continues the run of p - 1, from the runs of
 *  mpgm_conn_runs when they are known for [0, np), else by comparison. */
MPGM_RUN_INLINE int mpgm_conn_continues(const mpgm_conn *c, int np, int p) {
  return c->rn >= np ? c->rc[p] : mpgm_conn_same(c, p);
}
/** out[w I + i] += the sums over the points [0, np) of fn's values at
 *  each node I (out zeroed by the caller), by runs. */
MPGM_RUN_INLINE void mpgm_run_scatter(const mpgm_conn *c, int np, int w, mpgm_entry_fn fn,
                                    const void *job, double *out) {
  double sum[MPGM_RUN_NODES * MPGM_RUN_VALUES], v[MPGM_RUN_VALUES];
  for (int p = 0; p < np;) {
    const int k0 = c->ptr[p], n = c->ptr[p + 1] - k0;
    if (n > MPGM_RUN_NODES) { /* a run of one */
      for (int k = k0; k < k0 + n; k++) {
        fn(job, p, k, v);
        for (int i = 0; i < w; i++) out[w * c->node[k] + i] += v[i];
      }
      p++;
      continue;
    }
    memset(sum, 0, sizeof(double) * (size_t)(w * n));
    int q = p;
    do {
      for (int a = 0; a < n; a++) {
        fn(job, q, c->ptr[q] + a, v);
        for (int i = 0; i < w; i++) sum[w * a + i] += v[i];
      }
      q++;
    } while (q < np && mpgm_conn_continues(c, np, q));
    for (int a = 0; a < n; a++)
      for (int i = 0; i < w; i++) out[w * c->node[k0 + a] + i] += sum[w * a + i];
    p = q;
  }
}
/** The run sums of mpgm_run_scatter one point at a time, in point order
 *  (a caller that computes each point's values just before, in the same
 *  loop): mpgm_run_add for p = 0, 1, ... np - 1, then mpgm_run_end; the
 *  same additions in the same order, so the same bits. */
typedef struct mpgm_run_acc {
  double sum[MPGM_RUN_NODES * MPGM_RUN_VALUES];
  int k0, n; /**< the open run's first point's list; n 0: none open */
} mpgm_run_acc;
MPGM_RUN_INLINE void mpgm_run_end(const mpgm_conn *c, mpgm_run_acc *r, int w, double *out) {
  for (int a = 0; a < r->n; a++)
    for (int i = 0; i < w; i++) out[w * c->node[r->k0 + a] + i] += r->sum[w * a + i];
  r->n = 0;
}
MPGM_RUN_INLINE void mpgm_run_add(const mpgm_conn *c, mpgm_run_acc *r, int np, int p, int w,
                                  mpgm_entry_fn fn, const void *job, double *out) {
  double v[MPGM_RUN_VALUES];
  const int k0 = c->ptr[p], n = c->ptr[p + 1] - k0;
  if (!(r->n > 0 && mpgm_conn_continues(c, np, p))) { /* a new run */
    mpgm_run_end(c, r, w, out);
    if (n > MPGM_RUN_NODES) { /* a run of one */
      for (int k = k0; k < k0 + n; k++) {
        fn(job, p, k, v);
        for (int i = 0; i < w; i++) out[w * c->node[k] + i] += v[i];
      }
      return;
    }
    memset(r->sum, 0, sizeof(double) * (size_t)(w * n));
    r->k0 = k0;
    r->n = n;
  }
  for (int a = 0; a < n; a++) {
    fn(job, p, k0 + a, v);
    for (int i = 0; i < w; i++) r->sum[w * a + i] += v[i];
  }
}
/** The same sums at node I alone, through the transpose (out: w values). */
MPGM_RUN_INLINE void mpgm_run_gather(const mpgm_conn *c, int I, int w, mpgm_entry_fn fn,
                                   const void *job, double *out) {
  double part[MPGM_RUN_VALUES] = {0}, v[MPGM_RUN_VALUES];
  for (int i = 0; i < w; i++) out[i] = 0.0;
  for (int e = c->tptr[I]; e < c->tptr[I + 1]; e++) {
    /* a point that continues a run has its predecessor, with the same
     * nodes, just before it here */
    if (e > c->tptr[I] && !c->tc[e]) /* a new run */
      for (int i = 0; i < w; i++) {
        out[i] += part[i];
        part[i] = 0.0;
      }
    fn(job, c->tp[e], c->tk[e], v);
    for (int i = 0; i < w; i++) part[i] += v[i];
  }
  for (int i = 0; i < w; i++) out[i] += part[i];
}
/** Tasks for n items in ranges of at least `chunk` (at most
 *  MPGM_CONN_TASKS); task t has [n t / ntask, n (t + 1) / ntask). */
static inline int mpgm_ntask(int n, int chunk) {
  const int t = n / chunk;
  return t < 1 ? 1 : t > MPGM_CONN_TASKS ? MPGM_CONN_TASKS : t;
}
static inline int mpgm_task_begin(int n, int ntask, int t) { return (int)((long)n * t / ntask); }
#ifdef __cplusplus
}
#endif
#endif
