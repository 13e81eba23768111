/* ordering.c -- fill-reducing ordering of the node graph by geometric
 * nested dissection (George 1973; the coordinate-bisection variant of
 * Miller, Teng, Thurston & Vavasis).
 *
 * Every front end has node coordinates and a node graph (two nodes are
 * neighbours when a point's shape functions couple them), so the ordering
 * needs no graph partitioner: a set of nodes is cut at the median of its
 * coordinate along the longer side of its bounding box; the nodes of one
 * half that touch the other half form the separator, numbered after both
 * halves, which are ordered the same way, recursively, down to small
 * leaves. On the planar, grid-like graphs of MPM, GMM and FEM this is the
 * classical nested dissection (fill O(n log n), work O(n^1.5) for a 2-D
 * grid), computed in O(n log n) time -- a few percent of what a minimum-
 * degree ordering (AMD) costs on the same matrix, which matters when the
 * pattern changes at every step (MPM). docs/theory.md, "Ordering". */
#include "mpgm_core_impl.h"

#include <math.h>
#include <stdlib.h>


/* Leaves: at most this many nodes are numbered as they come (their block
 * of L is small and dense whatever their order). */
#define ND_LEAF 4

typedef struct nd_work {
  const int *ptr, *adj;
  const double *x;  /* MPGM_DIM per node */
  int *side;        /* per node: -1 outside the current set, 0 / 1 half,
                       2 separator                                        */
  int *cnt;         /* per node: cut edges not yet covered                */
  int *key;         /* per node: cnt when last pushed on the heap         */
  int *heap;        /* max-heap of nodes by (key, left first, index)      */
  int *perm;        /* output: node at each position                      */
} nd_work;

/* Heap order: more uncovered cut edges first, then the left half, then
 * the lower index (deterministic). */
static int heap_before(const nd_work *w, int a, int b) {
  if (w->key[a] != w->key[b]) return w->key[a] > w->key[b];
  if (w->side[a] != w->side[b]) return w->side[a] < w->side[b];
  return a < b;
}

static void heap_push(nd_work *w, int *nh, int I) {
  w->key[I] = w->cnt[I];
  int k = (*nh)++;
  while (k > 0 && heap_before(w, I, w->heap[(k - 1) / 2])) {
    w->heap[k] = w->heap[(k - 1) / 2];
    k = (k - 1) / 2;
  }
  w->heap[k] = I;
}

static int heap_pop(nd_work *w, int *nh) {
  const int top = w->heap[0], last = w->heap[--(*nh)];
  int k = 0;
  for (;;) {
    int c = 2 * k + 1;
    if (c >= *nh) break;
    if (c + 1 < *nh && heap_before(w, w->heap[c + 1], w->heap[c])) c++;
    if (!heap_before(w, w->heap[c], last)) break;
    w->heap[k] = w->heap[c];
    k = c;
  }
  if (*nh) w->heap[k] = last;
  return top;
}

/* Rearrange v[0..m) so that v[k] has the k-th smallest coordinate c
 * (quickselect, Hoare partition; expected O(m)). */
static void select_kth(const double *x, int c, int *v, int m, int k) {
  int lo = 0, hi = m - 1;
  while (lo < hi) {
    const double pivot = x[MPGM_DIM * v[(lo + hi) / 2] + c];
    int i = lo, j = hi;
    while (i <= j) {
      while (x[MPGM_DIM * v[i] + c] < pivot) i++;
      while (x[MPGM_DIM * v[j] + c] > pivot) j--;
      if (i <= j) {
        const int t = v[i];
        v[i] = v[j];
        v[j] = t;
        i++;
        j--;
      }
    }
    if (k <= j) hi = j;
    else if (k >= i) lo = i;
    else return;
  }
}

/* Order the m nodes of v (scratch, rearranged) into perm[pos .. pos+m). */
static void dissect(nd_work *w, int *v, int m, int pos) {
  const double *x = w->x;
  if (m <= ND_LEAF) {
    for (int k = 0; k < m; k++) w->perm[pos + k] = v[k];
    return;
  }
  double lo[MPGM_DIM], hi[MPGM_DIM];
  for (int c = 0; c < MPGM_DIM; c++) lo[c] = INFINITY, hi[c] = -INFINITY;
  for (int k = 0; k < m; k++)
    for (int c = 0; c < MPGM_DIM; c++) {
      lo[c] = fmin(lo[c], x[MPGM_DIM * v[k] + c]);
      hi[c] = fmax(hi[c], x[MPGM_DIM * v[k] + c]);
    }
  int c = 0; /* the longest side (the first of equal ones) */
  for (int d = 1; d < MPGM_DIM; d++)
    if (hi[d] - lo[d] > hi[c] - lo[c]) c = d;
  select_kth(x, c, v, m, m / 2);
  /* left: coordinate below the median value (a grid line of nodes at the
   * median goes whole to the right half) */
  const double cut = x[MPGM_DIM * v[m / 2] + c];
  int nl = 0;
  for (int k = 0; k < m; k++) {
    const int left = x[MPGM_DIM * v[k] + c] < cut;
    w->side[v[k]] = !left;
    if (left) {
      const int t = v[nl];
      v[nl++] = v[k];
      v[k] = t;
    }
  }
  if (nl == 0) { /* all on the median line (degenerate): order as a leaf */
    for (int k = 0; k < m; k++) {
      w->side[v[k]] = -1;
      w->perm[pos + k] = v[k];
    }
    return;
  }
  /* separator: a vertex cover of the edges between the halves, so that
   * the rest of the halves share no edge; greedy (the node covering most
   * uncovered cut edges first, left before right on ties), which on a
   * grid takes one line of nodes and on node clouds a thinner band than
   * one half's whole boundary */
  int nh = 0;
  for (int k = 0; k < m; k++) {
    const int I = v[k], s = w->side[I];
    int ncut = 0;
    for (int t = w->ptr[I]; t < w->ptr[I + 1]; t++) ncut += w->side[w->adj[t]] == 1 - s;
    w->cnt[I] = ncut;
    if (ncut) heap_push(w, &nh, I);
  }
  while (nh) {
    const int I = heap_pop(w, &nh);
    if (w->side[I] == 2 || w->cnt[I] == 0) continue;
    if (w->cnt[I] != w->key[I]) { /* stale entry: back with its count */
      heap_push(w, &nh, I);
      continue;
    }
    const int s = w->side[I];
    w->side[I] = 2;
    for (int t = w->ptr[I]; t < w->ptr[I + 1]; t++) {
      const int J = w->adj[t];
      if (w->side[J] == 1 - s) w->cnt[J]--;
    }
  }
  /* perm[pos ..] = [left rest | right rest | separator], copied back to v
   * for the recursion */
  int na = 0, nb = 0;
  for (int k = 0; k < m; k++) {
    na += w->side[v[k]] == 0;
    nb += w->side[v[k]] == 1;
  }
  int ia = 0, ib = na, is = na + nb;
  for (int k = 0; k < m; k++) {
    const int I = v[k];
    w->perm[pos + (w->side[I] == 0 ? ia++ : w->side[I] == 1 ? ib++ : is++)] = I;
  }
  for (int k = 0; k < m; k++) {
    v[k] = w->perm[pos + k];
    w->side[v[k]] = -1;
  }
  if (na + nb == 0) return; /* everything in the separator */
  dissect(w, v, na, pos);
  dissect(w, v + na, nb, pos + na);
}

/** Nested-dissection order of the n nodes of a graph (CSR ptr/adj, the
 *  lists may include the node itself) with coordinates x (MPGM_DIM per node):
 *  perm[k] = the node numbered k. Errors: MPGM_ERR_NOMEM. */
int mpgm_order_nodes(mpgm_ctx *ctx, int n, const int *ptr, const int *adj, const double *x,
                     int *perm) {
  int *v = malloc(((size_t)n + 1) * sizeof(int));
  int *side = malloc(((size_t)n + 1) * sizeof(int));
  int *cnt = malloc(((size_t)n + 1) * sizeof(int));
  int *key = malloc(((size_t)n + 1) * sizeof(int));
  /* pushes: one per node with a cut edge plus one per stale pop, which
   * follows a decrement: at most n + entries */
  int *heap = malloc(((size_t)n + ptr[n] + 1) * sizeof(int));
  if (!v || !side || !cnt || !key || !heap) {
    free(v);
    free(side);
    free(cnt);
    free(key);
    free(heap);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (ordering of %d nodes)", n);
  }
  for (int i = 0; i < n; i++) {
    v[i] = i;
    side[i] = -1;
  }
  nd_work w = {.ptr = ptr, .adj = adj, .x = x, .side = side, .cnt = cnt, .key = key,
               .heap = heap, .perm = perm};
  dissect(&w, v, n, 0);
  free(v);
  free(side);
  free(cnt);
  free(key);
  free(heap);
  return MPGM_OK;
}
