/* mpgm_kdtree.h -- kd-tree over 2-D points for neighbour search, in the
 * spirit of nanoflann: an index permutation over BORROWED coordinates, radius
 * and k-nearest queries into caller-provided buffers, cheap refit and rebuild
 * when the points move.
 *
 * Data. The points are an interleaved array xy[2 i], xy[2 i + 1] (stride
 * MPGM_DIM, the layout of mpgm_points.x and mpgm_nodes.x; 2-D only: the
 * tree's boxes, splits and distances are written out in x and y, see
 * kdtree.c). The tree keeps the pointer and never copies or writes the
 * coordinates: the caller keeps the array alive and unchanged while the
 * tree is queried, and calls mpgm_kdtree_refit() or mpgm_kdtree_rebuild()
 * after moving the points.
 *
 * Structure. A binary tree stored as one flat array in depth-first order;
 * every node holds the tight bounding box of its points, a leaf holds a range
 * of the permutation (at most leaf_size points, or any number of identical
 * points). An internal node cuts its widest side at the middle of its box
 * (nanoflann's "middle split"); when that leaves fewer than 1/8 of the points
 * on one side, it cuts at the median instead, so no child holds more than
 * 7/8 of its parent's points and the depth stays below log_{8/7}(n) (161 for
 * n = 2^31) for any input.
 *
 * Results. Distances are squared Euclidean distances computed as
 *   dx = x_j - q_x,  dy = y_j - q_y,  d2 = dx * dx + dy * dy
 * in double precision (the same expression a brute-force loop evaluates, so
 * both give identical numbers; this assumes no contraction into fused
 * multiply-adds, as with the project's -std=c11 under GCC). Results are
 * ordered by (d2, index): ties in distance are broken by the smaller point
 * index, so every query has exactly one answer, independent of the tree's
 * shape, the leaf size, refit or rebuild: the answer of a brute-force search
 * sorted by (d2, index).
 *
 * Threads. Queries take a const tree, keep their state on the stack and
 * allocate nothing: any number of threads may query one tree at the same
 * time. create / rebuild / refit / destroy need exclusive access.
 *
 * Errors. create, rebuild and refit return 0 or a negative mpgm_code
 * recorded in ctx (MPGM_ERR_INPUT for bad arguments or a non-finite
 * coordinate, MPGM_ERR_NOMEM). Queries cannot fail: they return a count.
 */
#ifndef MPGM_KDTREE_H
#define MPGM_KDTREE_H

#include "mpgm_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Default maximum number of points in a leaf. bench/kdtree's leaf-size table
 *  (1e5 uniform points, radius ~24 neighbours, kNN k = 16): query times for
 *  10 to 32 lie within the run-to-run noise (about 5 %) of each other, 4 to 6
 *  are 10-20 % slower; 16 needs 30 % less tree memory than 10 and builds
 *  a little faster. */
#define MPGM_KDTREE_LEAF_SIZE 16

/** Opaque kd-tree (core/kdtree.c). */
typedef struct mpgm_kdtree mpgm_kdtree;

/** Shape of a built tree, for tests and benchmarks. */
typedef struct mpgm_kdtree_stats {
  int n;             /**< points indexed                                   */
  int leaf_size;     /**< maximum points per leaf (except identical points) */
  int nodes;         /**< nodes (internal + leaves)                        */
  int leaves;        /**< leaves                                           */
  int depth;         /**< longest root-to-leaf path in edges (0: one leaf)  */
  int median_splits; /**< internal nodes cut at the median (fallback)  */
  size_t bytes;      /**< memory held by the tree (points not included) [B] */
} mpgm_kdtree_stats;

/** Build a tree over n points xy[2 i], xy[2 i + 1] (borrowed: kept, not
 *  copied; must outlive the tree or the next rebuild).
 *  @param ctx       error context
 *  @param xy        interleaved coordinates, MPGM_DIM n doubles (may be NULL
 *                   if n = 0)
 *  @param n         number of points, >= 0 (an empty tree answers 0 to all)
 *  @param leaf_size maximum points per leaf; <= 0 selects MPGM_KDTREE_LEAF_SIZE
 *  @param out       the new tree (NULL on failure)
 *  @return 0; MPGM_ERR_INPUT (n < 0, xy NULL with n > 0, a NaN or infinite
 *          coordinate); MPGM_ERR_NOMEM. */
int mpgm_kdtree_create(mpgm_ctx *ctx, const double *xy, int n, int leaf_size, mpgm_kdtree **out);

/** Rebuild the tree over (possibly other) points, reusing its memory: no
 *  allocation unless the tree needs more than at any build before (more
 *  points, or a distribution that needs more nodes). When xy has the same n
 *  as before, the old permutation is the starting order: for points that
 *  moved little most partitions are then already in place (bench/kdtree,
 *  points moved by a quarter of their spacing: 1.8-2.6x faster than create).
 *  Same arguments and errors as mpgm_kdtree_create (the leaf size stays);
 *  on error the tree is empty (queries return 0) but can be rebuilt or
 *  destroyed. */
int mpgm_kdtree_rebuild(mpgm_ctx *ctx, mpgm_kdtree *t, const double *xy, int n);

/** Refit after the points moved: keep the tree's structure (permutation and
 *  nodes) and recompute every bounding box bottom-up, O(n), no allocation.
 *  Queries stay exact for any displacement; they only get slower as the
 *  boxes start to overlap, which is the time to rebuild.
 *  @param xy the moved points, same n and numbering as at the last build;
 *            NULL keeps the borrowed pointer (moved in place)
 *  @return 0; MPGM_ERR_INPUT for a non-finite coordinate (the tree is then
 *          empty until the next successful refit or rebuild). */
int mpgm_kdtree_refit(mpgm_ctx *ctx, mpgm_kdtree *t, const double *xy);

/** Free the tree (never the points); accepts NULL and *t == NULL, sets *t to
 *  NULL. */
void mpgm_kdtree_destroy(mpgm_kdtree **t);

/** Radius search: every point j with d2_j <= radius * radius (closed ball).
 *  @param t      tree
 *  @param q      query point (not necessarily one of the points)
 *  @param radius search radius [same unit as xy]; < 0, NaN or a non-finite q
 *                give 0; radius = 0 finds the copies of q; INFINITY finds all
 *  @param cap    capacity of idx and d2 (>= 0; with cap = 0 both may be NULL
 *                and the call only counts)
 *  @param idx    out: point indices, ordered by (d2, index)
 *  @param d2     out: their squared distances
 *  @return the number m of points in the ball, also when m > cap: then the
 *          buffers hold the cap nearest of them, in order, so the caller can
 *          grow its buffers to m and repeat. */
int mpgm_kdtree_radius(const mpgm_kdtree *t, const double q[MPGM_DIM], double radius, int cap,
                       int *idx, double *d2);

/** The same ball as mpgm_kdtree_radius, for callers that order the points
 *  themselves (node clouds sort them by index): when m <= cap, idx and d2
 *  hold them in no particular order (the tree's); when m > cap, the cap
 *  nearest, ordered by (d2, index), as mpgm_kdtree_radius gives them. The
 *  sort it leaves out is most of the search's cost at clouds of 50 nodes. */
int mpgm_kdtree_radius_set(const mpgm_kdtree *t, const double q[MPGM_DIM], double radius, int cap,
                           int *idx, double *d2);

/** k nearest points, ordered by (d2, index): the first k of a brute-force
 *  list sorted by (d2, index), ties at the k-th distance included.
 *  @param t   tree
 *  @param q   query point; non-finite coordinates give 0
 *  @param k   wanted neighbours (k <= 0 gives 0)
 *  @param idx out: min(k, n) point indices
 *  @param d2  out: their squared distances
 *  @return min(k, n). */
int mpgm_kdtree_knn(const mpgm_kdtree *t, const double q[MPGM_DIM], int k, int *idx, double *d2);

/** Number of points indexed. */
int mpgm_kdtree_size(const mpgm_kdtree *t);

/** The borrowed coordinate array (as given to the last create, rebuild or
 *  refit). */
const double *mpgm_kdtree_points(const mpgm_kdtree *t);

/** Shape and memory of the tree. */
void mpgm_kdtree_get_stats(const mpgm_kdtree *t, mpgm_kdtree_stats *s);

#ifdef __cplusplus
}
#endif
#endif
