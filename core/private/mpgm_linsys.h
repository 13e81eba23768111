/* mpgm_linsys.h -- private to core/: the linear system of an implicit
 * run (tangent, its pattern, the point groups and scatter maps that fill
 * it, the residual and step vectors, the solver, Newton's accelerators),
 * one object owned by the implicit integrator (implicit.c creates it,
 * core/linsys.c holds its life cycle). An explicit run has none. */
#ifndef MPGM_LINSYS_H
#define MPGM_LINSYS_H

#include <stdint.h>

#include "mpgm_core.h"

/** solver.contact_rank: a change of the contact springs at surface
 *  points applied to a kept factorisation by the Woodbury identity
 *  (lowrank.c). */
typedef struct mpgm_lowrank {
  int valid;          /**< the set below is of the solver's factorisation  */
  int cap;            /**< columns at most (solver.contact_rank)           */
  int r;              /**< columns now                                     */
  int n;              /**< equations (K.n of the factorisation)            */
  int n_cap;          /**< equations the arrays have room for              */
  int nt;             /**< surface tracers (cp.n)                          */
  unsigned char *held0; /**< per tracer: plane + 1 it was held on in the
                           factorised tangent, 0 free                  */
  int *col_t, *col_t2; /**< per column: its tracer (and of the set being
                           built, update)                             */
  signed char *col_c, *col_c2; /**< per column: its component              */
  double *col_w, *col_w2; /**< per column: the change of stiffness (+
                           caught)                                     */
  int *nnz, *nnz2;    /**< per column: its entries (and of the set being
                           built, update)                             */
  int *idx, *idx2;    /**< per column MPGM_DIM MPGM_SHAPE_MAXNODE slots:
                           equations of its entries                    */
  double *val, *val2; /**< their values, sqrt(|w|) N                       */
  double *Z, *Z2;     /**< per column n values: K0^-1 u                   */
  double *C;          /**< r x r: LU factors of D^-1 + U^T Z               */
  int *perm;          /**< their row exchanges                             */
  double *y;          /**< r: scratch                                      */
  int *src;           /**< cap: scratch of update                          */
  double *W;          /**< per column n values: scratch of update          */
} mpgm_lowrank;

/** solver.newton "bfgs": the pairs (s, y) of the iterations since the
 *  last factorisation (bfgs.c), in a ring of solver.bfgs_pairs. */
typedef struct mpgm_bfgs {
  double *S, *Y;      /**< m vectors of the node capacity each:
                           changes of du and of R                      */
  double rho[MPGM_BFGS_PAIRS_MAX]; /**< 1 / (y^T s) of each pair          */
  int m;              /**< slots of the ring (solver.bfgs_pairs)         */
  int first, k;       /**< the oldest pair's slot; pairs held            */
  int have_prev;      /**< r_prev, du_prev hold the last iterate         */
  double *r_prev;     /**< R where the last correction started           */
  double *du_prev;    /**< du there, over the numbered equations          */
  double *q;          /**< scratch of the two-loop recursion             */
} mpgm_bfgs;

/** Chunks of the threaded assembly; a constant, so that the order of the
 *  sums does not depend on the number of threads. */
#define MPGM_ASM_CHUNKS 16
/* Largest union of node clouds a batch of points may have in the
 * clouds' assembly (assembly.c, assemble_batch); at least the largest
 * cloud, MPGM_SHAPE_MAXNODE. */
#define MPGM_ASM_BATCH 128
/* 64-bit words of a batch's row or column of touched blocks */
#define MPGM_ASM_WORDS (MPGM_ASM_BATCH / 64)

/** First assembly task of phase ph (0..3; 4 gives the end): chunk
 *  interiors 0..C-1, interfaces between chunks c and c+1 with c even, with
 *  c odd, and the rest (one serial task), C = MPGM_ASM_CHUNKS. */
static inline int mpgm_asm_phase(int ph) {
  const int C = MPGM_ASM_CHUNKS, first[5] = {0, C, C + C / 2, 2 * C - 1, 2 * C};
  return first[ph];
}

/** The linear system (pb->ls). */
typedef struct mpgm_linsys {
  mpgm_csc K;
  mpgm_dof_layout K_layout; /**< K's equations: nodes.dof and nodes.x, set
                          before each analyse (mpgm_problem_analyse)    */
  int pattern_version; /**< conn.version the pattern was built for      */
  int graph_version; /**< conn.version the groups and node graph are of */
  int map_version;   /**< conn.map_version the scatter maps were built for */
  int factor_valid;  /**< the solver holds a factorisation of this pattern
                          (modified Newton may reuse it across steps)    */
  unsigned char *fix_factored; /**< nodes.fix when it was factorised: held
                          contact components have identity rows, so
                          a different held set is a different matrix    */
  /* points grouped by node list: the points of a group have identical
   * lists (the particles in one grid cell, the Gauss points of one
   * element), so they share a scatter map and one local matrix */
  int ngroups;
  int *order;        /**< material points, group after group            */
  int *grp_ptr;      /**< ngroups + 1 offsets into order                 */
  int *scatter;      /**< per group: MPGM_BLOCK n_p^2 positions in K.val
                          (-1: fixed component)                         */
  int *scatter_ptr;  /**< ngroups + 1 offsets of the groups' maps        */
  size_t scatter_cap; /**< allocated entries of scatter                 */
  int nomap;         /**< node clouds: K assembled by merging each column's
                          node list, no stored maps (assembly.c)        */
  int *nbr_ptr, *nbr; /**< node graph of the pattern: sorted neighbours  */
  int *nbr_off;      /**< per neighbour entry: offset of its rows in the
                          owner's columns                               */
  int *node_order;   /**< solver.ordering geometric: nodes in nested-
                          dissection order (of the graph version)       */
  int *perm;         /**< the equations in that order (K.n), handed to
                          the solver's analysis; NULL: its own order    */
  double *kloc;      /**< local matrices of the groups, one per thread
                          (kloc_size doubles each)                      */
  int kloc_size;     /**< MPGM_BLOCK max n_p^2                           */
  double *kbatch;    /**< node clouds: per thread, the summed local matrix
                          of a batch of nearby points over the union of
                          their clouds (MPGM_BLOCK MPGM_ASM_BATCH^2
                          doubles, zero between batches), merged into K
                          once (assembly.c)                              */
  uint64_t *kmask;   /**< node clouds: per thread and batch slot, the
                          slots its points coupled it with (MPGM_ASM_WORDS
                          words each; zero between batches): the merge
                          into K visits only those pairs              */
  int *kslot;        /**< node clouds: per thread and node, its place in
                          the batch's union (-1: none); kslot_n each     */
  int kslot_n;       /**< nodes kslot has room for, per thread           */
  int pattern_missed; /**< node clouds: set by an assembly task that found
                          a nonzero block outside the pattern          */
  /* threads (docs/architecture.md, "Threads"): the groups are cut into
   * MPGM_ASM_CHUNKS chunks along the group order; the assembly runs as
   * tasks over groups that share no node with another task of the same
   * phase, so tasks of a phase may run at once and every entry of R and K
   * receives its terms in one fixed order, whatever the number of
   * threads */
  int task_ptr[2 * MPGM_ASM_CHUNKS + 1]; /**< offsets into task_grp       */
  int *task_grp;     /**< groups, task after task, ascending in a task   */
  int tpt_ptr[2 * MPGM_ASM_CHUNKS + 1]; /**< offsets into task_pts        */
  int *task_pts;     /**< the tasks' points (their groups' points)       */
  double *R, *fext, *delta;
  double *fint_n;    /**< time.hht_alpha: f_ext - R at the start of the
                          step (du = 0): the internal force at t_n on this
                          step's nodes, weighted -alpha in R (NULL: Newmark) */
  double *dubar;     /**< MPGM_DIM per node: prescribed increment of the
                          step                                          */
  const double *lift; /**< when set (first iteration), assembly adds
                           -K_free,fixed * lift to R: the prescribed increment
                           enters Newton linearly, not as a jump of the
                           boundary nodes alone                           */
  mpgm_solver *solver;
  int symmetric;     /**< all tangents symmetric (static or dynamic)    */
  double *react;     /**< MPGM_DIM per node: support force on the body
                          at fixed components (mpgm_reactions)          */
  double step_ref;     /**< the step's reference norm of the residual (newton.c) */
  unsigned char *cflip; /**< per node: contact state changed in this step */
  mpgm_lowrank lr;   /**< contact changes on the kept factorisation      */
  mpgm_bfgs bfgs;    /**< solver.newton "bfgs": the updates since it      */
} mpgm_linsys;

/** The linear system of problem pb, sized by its node capacity, with its
 *  solver (the scene's backend, or the composite of Newton-Krylov or a
 *  fallback), Newton's BFGS arrays when it uses them; into pb->ls. */
int mpgm_linsys_create(struct mpgm_problem *pb);
/** Release it (accepts NULL). */
void mpgm_linsys_destroy(mpgm_linsys *ls);

#endif
