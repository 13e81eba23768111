/* pattern.c -- the symbolic side of assembly, redone when the connectivity
 * changes: points grouped by node list, the assembly tasks of the groups
 * (docs/architecture.md, "Threads"), the node graph and the compressed-
 * column pattern of K, and the scatter maps from local matrices into K. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core_impl.h"

/* How many of node I's first n components are numbered (have an
 * equation): the rows of I before its component n in a column of K. */
static inline int numbered(const mpgm_nodes *nd, int I, int n) {
  int c = 0;
  for (int d = 0; d < n; d++) c += nd->dof[MPGM_DIM * I + d] >= 0;
  return c;
}

/* ---- sparsity pattern ------------------------------------------------- */

/* 1 when points p and q are connected to the same nodes in the same order. */
static int same_nodes(const mpgm_conn *C, int p, int q) {
  const int n = C->ptr[p + 1] - C->ptr[p];
  if (n != C->ptr[q + 1] - C->ptr[q]) return 0;
  return memcmp(C->node + C->ptr[p], C->node + C->ptr[q], sizeof(int) * (size_t)n) == 0;
}

/* ---- assembly tasks ---------------------------------------------------- */

/* Task ids: see mpgm_asm_phase (mpgm_core.h). */
#define NCH MPGM_ASM_CHUNKS

/* Each group's range of chunks [glo, ghi] when the group order is cut
 * into NCH chunks of about equal point counts: a node touched by the
 * groups of chunks lo..hi gets the range [lo, hi], a group the union of
 * its nodes' ranges ([NCH, -1]: no nodes). With nch = NCH >> s chunks the
 * ranges are these shifted right by s (chunk c of NCH lies in chunk
 * c >> s of nch: floor(floor(2x) / 2) = floor(x)), so they are found once
 * for every nch tried. */
static void group_ranges(const mpgm_problem *pb, int *lo, int *hi, int *glo, int *ghi) {
  mpgm_linsys *ls = pb->ls;
  const mpgm_conn *C = &pb->conn;
  const int ng = ls->ngroups, np = pb->pts.n, nn = pb->nodes.n;
  for (int i = 0; i < nn; i++) {
    lo[i] = NCH;
    hi[i] = -1;
  }
  for (int g = 0; g < ng; g++) {
    const int c = np ? (int)((long)ls->grp_ptr[g] * NCH / np) : 0, p = ls->order[ls->grp_ptr[g]];
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      if (c < lo[I]) lo[I] = c;
      if (c > hi[I]) hi[I] = c;
    }
  }
  for (int g = 0; g < ng; g++) {
    const int p = ls->order[ls->grp_ptr[g]];
    glo[g] = NCH;
    ghi[g] = -1;
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      if (lo[I] < glo[g]) glo[g] = lo[I];
      if (hi[I] > ghi[g]) ghi[g] = hi[I];
    }
  }
}

/* The task of every group (tid) with NCH >> s chunks; returns how many
 * groups went to the serial task. A group whose range is [c, c] is
 * interior to chunk c; one whose range is [c, c+1] sits on interface c;
 * anything wider goes to the last, serial task. Interiors of different
 * chunks share no node, nor do interfaces c and c' with |c - c'| >= 2:
 * the tasks of one phase write disjoint entries of R and K. Interface c
 * goes to task NCH + c / 2 (c even) or NCH + NCH / 2 + c / 2 (c odd),
 * whatever the chunks, so that the phases stay those of mpgm_asm_phase. */
static int chunk_tasks(int ng, const int *glo, const int *ghi, int s, int *tid) {
  int serial = 0;
  for (int g = 0; g < ng; g++) {
    const int a = glo[g] >> s, b = ghi[g] < 0 ? -1 : ghi[g] >> s;
    int t;
    if (b < 0) t = 0; /* no nodes: nothing to write */
    else if (a == b) t = a;
    else if (b == a + 1) t = a % 2 == 0 ? NCH + a / 2 : NCH + NCH / 2 + a / 2;
    else t = 2 * NCH - 1;
    serial += t == 2 * NCH - 1;
    tid[g] = t;
  }
  return serial;
}

/* The assembly tasks (task_ptr, task_grp, task_pts): NCH chunks, or fewer
 * and wider ones when a group's nodes reach further in the group order
 * than a chunk is long (node clouds: a cloud spans several rows of the
 * nodes' numbering), which would put most groups in the serial task. The
 * chunks are halved until at most an eighth of the groups is serial. The
 * choice depends on the clouds only, not on the number of threads, so
 * neither does the order of the sums. */
static int assembly_tasks(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  const int ng = ls->ngroups, np = pb->pts.n, nn = pb->nodes.n;
  free(ls->task_grp);
  free(ls->task_pts);
  ls->task_grp = malloc(((size_t)ng + 1) * sizeof(int));
  ls->task_pts = malloc(((size_t)np + 1) * sizeof(int));
  int *lo = malloc(((size_t)nn + 1) * sizeof(int)), *hi = malloc(((size_t)nn + 1) * sizeof(int));
  int *tid = malloc(3 * ((size_t)ng + 1) * sizeof(int));
  if (!ls->task_grp || !ls->task_pts || !lo || !hi || !tid) {
    free(lo);
    free(hi);
    free(tid);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (assembly tasks of %d groups)", ng);
  }
  int *glo = tid + ng + 1, *ghi = glo + ng + 1;
  group_ranges(pb, lo, hi, glo, ghi);
  for (int s = 0; NCH >> s >= 2; s++)
    if (chunk_tasks(ng, glo, ghi, s, tid) <= ng / 8 || NCH >> s == 2) break;
  memset(ls->task_ptr, 0, sizeof ls->task_ptr);
  for (int g = 0; g < ng; g++) ls->task_ptr[tid[g] + 1]++;
  for (int t = 0; t < 2 * NCH; t++) ls->task_ptr[t + 1] += ls->task_ptr[t];
  int fill[2 * NCH];
  memcpy(fill, ls->task_ptr, sizeof fill);
  for (int g = 0; g < ng; g++) ls->task_grp[fill[tid[g]]++] = g;
  /* the same as flat point lists (residual-only assembly) */
  int q = 0;
  ls->tpt_ptr[0] = 0;
  for (int t = 0; t < 2 * NCH; t++) {
    for (int i = ls->task_ptr[t]; i < ls->task_ptr[t + 1]; i++)
      for (int u = ls->grp_ptr[ls->task_grp[i]]; u < ls->grp_ptr[ls->task_grp[i] + 1]; u++)
        ls->task_pts[q++] = ls->order[u];
    ls->tpt_ptr[t + 1] = q;
  }
  free(lo);
  free(hi);
  free(tid);
  return 0;
}

/* Group the material points by node list: order them by (first node, hash
 * of the list) with two stable counting sorts, O(points + nodes), then cut
 * the order where the list changes. Equal lists always end up adjacent
 * unless another list with the same first node and hash slot interleaves
 * (then a list forms two groups: correct, only less shared). */
static int group_points(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_conn *C = &pb->conn;
  const int np = pb->pts.n, nn = pb->nodes.n;
  int nslot = 1;
  while (nslot < np) nslot <<= 1;
  const int nb = nslot > nn + 1 ? nslot : nn + 1;
  free(ls->order);
  free(ls->grp_ptr);
  ls->order = malloc(((size_t)np + 1) * sizeof(int));
  ls->grp_ptr = malloc(((size_t)np + 2) * sizeof(int));
  int *key = malloc(((size_t)np + 1) * sizeof(int)), *tmp = malloc(((size_t)np + 1) * sizeof(int));
  int *cnt = malloc(((size_t)nb + 1) * sizeof(int));
  if (!ls->order || !ls->grp_ptr || !key || !tmp || !cnt) {
    free(key);
    free(tmp);
    free(cnt);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (grouping %d points)", np);
  }
  for (int pass = 0; pass < 2; pass++) {
    /* pass 0: by hash slot (all points); pass 1: stable, by first node */
    const int nk = pass ? nn + 1 : nslot;
    for (int p = 0; p < np; p++) {
      if (pass)
        key[p] = C->ptr[p + 1] > C->ptr[p] ? C->node[C->ptr[p]] + 1 : 0;
      else {
        unsigned h = 2166136261u;
        for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) h = (h ^ (unsigned)C->node[k]) * 16777619u;
        key[p] = (int)(h & (unsigned)(nslot - 1));
      }
    }
    memset(cnt, 0, ((size_t)nk + 1) * sizeof(int));
    for (int p = 0; p < np; p++) cnt[key[p] + 1]++;
    for (int k = 0; k < nk; k++) cnt[k + 1] += cnt[k];
    if (pass)
      for (int q = 0; q < np; q++) ls->order[cnt[key[tmp[q]]]++] = tmp[q];
    else
      for (int p = 0; p < np; p++) tmp[cnt[key[p]]++] = p;
  }
  int ng = 0;
  for (int q = 0; q < np; q++)
    if (q == 0 || !same_nodes(C, ls->order[q], ls->order[q - 1])) ls->grp_ptr[ng++] = q;
  ls->grp_ptr[ng] = np;
  ls->ngroups = ng;
  free(key);
  free(tmp);
  free(cnt);
  return assembly_tasks(pb);
}

static int scatter_maps(mpgm_problem *pb);

/* The lists the node graph is made of: one per group (a point stands for
 * its group), or the front end's pattern lists of every material point
 * (conn.pptr, node clouds with a skin). List l's nodes and their count. */
static inline int graph_lists(const mpgm_problem *pb) {
  return pb->conn.pptr ? pb->pts.n : pb->ls->ngroups;
}

static inline const int *graph_list(const mpgm_problem *pb, int l, int *len) {
  mpgm_linsys *ls = pb->ls;
  const mpgm_conn *C = &pb->conn;
  if (C->pptr) {
    *len = C->pptr[l + 1] - C->pptr[l];
    return C->pnode + C->pptr[l];
  }
  const int p = ls->order[ls->grp_ptr[l]];
  *len = C->ptr[p + 1] - C->ptr[p];
  return C->node + C->ptr[p];
}

/* The node graph of the pattern: the neighbours of node J are the nodes of
 * every list holding J (graph_lists); built through the node -> lists
 * transpose with a marker per node (O(entries)), each list sorted (they
 * are short). Into pb->ls->nbr_ptr, pb->ls->nbr; with solver.ordering geometric,
 * the nodes' nested-dissection order (it depends on the graph only: a
 * contact node held or released keeps it). */
static int node_graph(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_conn *C = &pb->conn;
  const int nn = pb->nodes.n, nl = graph_lists(pb);
  size_t total = 0;
  for (int l = 0; l < nl; l++) {
    int len;
    graph_list(pb, l, &len);
    total += (size_t)len;
  }
  int *tptr = calloc((size_t)nn + 2, sizeof(int));
  int *nptr = calloc((size_t)nn + 1, sizeof(int)), *pair = NULL;
  int *mark = malloc(((size_t)nn + 1) * sizeof(int));
  int *tl = malloc((total + 1) * sizeof(int)); /* lists holding each node */
  int ok = tptr && nptr && mark && tl;
  for (int l = 0; l < nl && ok; l++) {
    int len;
    const int *nodes = graph_list(pb, l, &len);
    for (int k = 0; k < len; k++) tptr[nodes[k] + 2]++;
  }
  for (int i = 0; i < nn && ok; i++) tptr[i + 2] += tptr[i + 1];
  for (int l = 0; l < nl && ok; l++) {
    int len;
    const int *nodes = graph_list(pb, l, &len);
    for (int k = 0; k < len; k++) tl[tptr[nodes[k] + 1]++] = l;
  }
  for (int pass = 0; pass < 2 && ok; pass++) {
    for (int i = 0; i < nn; i++) mark[i] = -1;
    for (int J = 0; J < nn; J++) {
      int cnt = 0, *list = pass ? pair + nptr[J] : NULL;
      for (int t = tptr[J]; t < tptr[J + 1]; t++) {
        int len;
        const int *nodes = graph_list(pb, tl[t], &len);
        for (int k = 0; k < len; k++) {
          const int I = nodes[k];
          if (mark[I] == J) continue;
          mark[I] = J;
          if (pass) { /* insertion into the sorted list */
            int w = cnt;
            while (w > 0 && list[w - 1] > I) {
              list[w] = list[w - 1];
              w--;
            }
            list[w] = I;
          }
          cnt++;
        }
      }
      if (!pass) nptr[J + 1] = cnt;
    }
    if (!pass) {
      for (int i = 0; i < nn; i++) nptr[i + 1] += nptr[i];
      ok = (pair = malloc(((size_t)nptr[nn] + 1) * sizeof(int))) != NULL;
    }
  }
  free(tptr);
  free(mark);
  free(tl);
  if (!ok) {
    free(nptr);
    free(pair);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (sparsity pattern)");
  }
  free(ls->nbr);
  free(ls->nbr_ptr);
  ls->nbr = pair;
  ls->nbr_ptr = nptr;
  ls->graph_version = C->pptr ? C->pversion : C->version;
  if (!pb->scene->ordering_nd) return 0;
  free(ls->node_order);
  ls->node_order = malloc(((size_t)nn + 1) * sizeof(int));
  MPGM_CHECK(ctx, ls->node_order, MPGM_ERR_NOMEM, "out of memory (ordering)");
  return mpgm_order_nodes(ctx, nn, nptr, pair, pb->nodes.x, ls->node_order);
}

/* K's pattern from the node graph and the equation numbers: every free
 * component of node J couples with every free component of J's
 * neighbours; the equations in the nodes' order (solver.ordering
 * geometric); where node I's rows start in a column of node J
 * (pb->ls->nbr_off, for the scatter maps). */
static int matrix_pattern(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_nodes *nd = &pb->nodes;
  const int nn = nd->n, n = nd->ndof, *nptr = ls->nbr_ptr, *pair = ls->nbr;
  mpgm_csc *K = &ls->K;
  free(K->colptr);
  free(K->rowind);
  free(K->val);
  K->colptr = calloc((size_t)n + 1, sizeof(int));
  size_t nnz = 0;
  for (int J = 0; J < nn; J++)
    for (int j = 0; j < MPGM_DIM; j++) {
      if (nd->dof[MPGM_DIM * J + j] < 0) continue;
      for (int t = nptr[J]; t < nptr[J + 1]; t++) {
        const int I = pair[t];
        nnz += numbered(nd, I, MPGM_DIM);
      }
    }
  K->rowind = malloc((nnz ? nnz : 1) * sizeof(int));
  K->val = calloc(nnz ? nnz : 1, sizeof(double));
  MPGM_CHECK(ctx, K->colptr && K->rowind && K->val && nnz <= INT32_MAX, MPGM_ERR_NOMEM,
             "out of memory (matrix with %zu entries)", nnz);
  size_t e = 0;
  for (int J = 0; J < nn; J++)
    for (int j = 0; j < MPGM_DIM; j++) {
      const int col = nd->dof[MPGM_DIM * J + j];
      if (col < 0) continue;
      for (int t = nptr[J]; t < nptr[J + 1]; t++) {
        const int I = pair[t];
        for (int i = 0; i < MPGM_DIM; i++)
          if (nd->dof[MPGM_DIM * I + i] >= 0) K->rowind[e++] = nd->dof[MPGM_DIM * I + i];
      }
      K->colptr[col + 1] = (int)e;
    }
  K->n = n;
  K->nnz = (int)nnz;
  K->symmetric = ls->symmetric;
  if (ls->node_order) { /* the equations in the nodes' order */
    free(ls->perm);
    ls->perm = malloc(((size_t)n + 1) * sizeof(int));
    MPGM_CHECK(ctx, ls->perm, MPGM_ERR_NOMEM, "out of memory (ordering)");
    int k = 0;
    for (int t = 0; t < nn; t++)
      for (int j = 0; j < MPGM_DIM; j++) {
        const int eq = nd->dof[MPGM_DIM * ls->node_order[t] + j];
        if (eq >= 0) ls->perm[k++] = eq;
      }
    MPGM_CHECK(ctx, k == n, MPGM_ERR_INTERNAL, "ordering: %d of %d equations placed", k, n);
  }
  /* node I's rows in a column of node J start nbr_off[t] entries into the
   * column, t the place of I in J's list */
  int *off = malloc(((size_t)nptr[nn] + 1) * sizeof(int));
  MPGM_CHECK(ctx, off, MPGM_ERR_NOMEM, "out of memory (sparsity pattern)");
  for (int J = 0; J < nn; J++)
    for (int t = nptr[J], c = 0; t < nptr[J + 1]; t++) {
      off[t] = c;
      c += numbered(nd, pair[t], MPGM_DIM);
    }
  free(ls->nbr_off);
  ls->nbr_off = off;
  return 0;
}

int mpgm_pattern_build(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  mpgm_timer_start(ctx, MPGM_T_ANALYSE); /* symbolic work, once per pattern */
  int err = 0;
  /* the same connectivity with new equation numbers (a contact node held
   * or released): the groups and the node graph stand. With pattern lists
   * (conn.pptr) the graph is theirs, and stands while they do; the node
   * lists, and so the groups, may have changed with the equations */
  const mpgm_conn *C = &pb->conn;
  if (ls->graph_version != (C->pptr ? C->pversion : C->version) || !ls->nbr_ptr) {
    err = group_points(pb);
    if (!err) err = node_graph(pb);
  } else if (C->pptr) {
    err = group_points(pb);
  }
  if (!err) err = matrix_pattern(pb);
  mpgm_timer_stop(ctx, MPGM_T_ANALYSE);
  MPGM_CALL(err);
  ls->pattern_version = pb->conn.version;
  if (ls->solver) ls->solver->analysed = 0; /* explicit runs have none */
  ls->factor_valid = 0;
  return scatter_maps(pb);
}

/* The memory of the scatter maps (ns entries over the groups, the largest
 * of maxk nodes) and of the local matrices; node clouds (meshfree kinds)
 * keep no maps: K is merged in batches (assembly.c, assemble_batch;
 * MPGM_ASM_BATCH >= MPGM_SHAPE_MAXNODE). */
static int map_buffers(mpgm_problem *pb, int *maxk_out) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_conn *C = &pb->conn;
  const int ng = ls->ngroups, nn = pb->nodes.n;
  free(ls->scatter_ptr);
  free(ls->kloc);
  ls->kloc = NULL;
  ls->scatter_ptr = malloc(((size_t)ng + 1) * sizeof(int));
  MPGM_CHECK(ctx, ls->scatter_ptr, MPGM_ERR_NOMEM, "out of memory (scatter map)");
  size_t ns = 0;
  int maxk = 1;
  for (int g = 0; g < ng; g++) {
    const int p = ls->order[ls->grp_ptr[g]], k = C->ptr[p + 1] - C->ptr[p];
    if (k > maxk) maxk = k;
    ns += MPGM_BLOCK * (size_t)k * k;
  }
  MPGM_CHECK(ctx, ns <= INT32_MAX, MPGM_ERR_NOMEM, "scatter map of %zu entries", ns);
  ls->nomap = !pb->scene->shape->needs_cell && maxk <= MPGM_SHAPE_MAXNODE;
  const size_t nt = (size_t)mpgm_pool_size(pb->pool);
  if (ls->nomap) {
    ns = 0;
    /* the batches' buffers, kept from step to step (zero between batches) */
    if (!ls->kbatch)
      ls->kbatch = calloc(nt * MPGM_BLOCK * MPGM_ASM_BATCH * MPGM_ASM_BATCH, sizeof(double));
    if (!ls->kmask) ls->kmask = calloc(nt * MPGM_ASM_BATCH * MPGM_ASM_WORDS, sizeof(uint64_t));
    if (ls->kslot_n < nn) {
      free(ls->kslot);
      ls->kslot = malloc(nt * (size_t)nn * sizeof(int));
      ls->kslot_n = ls->kslot ? nn : 0;
      if (ls->kslot)
        for (size_t i = 0; i < nt * (size_t)nn; i++) ls->kslot[i] = -1;
    }
    MPGM_CHECK(ctx, ls->kbatch && ls->kmask && ls->kslot, MPGM_ERR_NOMEM,
               "out of memory (assembly batches)");
  }
  /* the map is rebuilt every step by MPM and GMM: keep its memory and grow
   * it, rather than fault in fresh pages each time */
  if (ns > ls->scatter_cap || !ls->scatter) {
    free(ls->scatter);
    const size_t cap = ns + ns / 4 + 1;
    ls->scatter = malloc(cap * sizeof(int));
    ls->scatter_cap = ls->scatter ? cap : 0;
  }
  ls->kloc_size = MPGM_BLOCK * maxk * maxk;
  ls->kloc = malloc(nt * (size_t)ls->kloc_size * sizeof(double));
  MPGM_CHECK(ctx, ls->scatter && ls->kloc, MPGM_ERR_NOMEM, "out of memory (scatter map)");
  *maxk_out = maxk;
  return 0;
}

/* Group g's map at pb->ls->scatter + *s: the position in K.val of every
 * (a, b, i, j) entry of its node list (-1 where a component is fixed or
 * held). srt, tpos: workspaces of maxk and maxk^2 ints. */
static int group_map(mpgm_problem *pb, int g, int *srt, int *tpos, size_t *s) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_conn *C = &pb->conn;
  const mpgm_nodes *nd = &pb->nodes;
  const mpgm_csc *K = &ls->K;
  const int *dof = nd->dof;
  const int p = ls->order[ls->grp_ptr[g]], k0 = C->ptr[p], nk = C->ptr[p + 1] - k0;
  const int *nodes = C->node + k0;
  /* place of node a of the group in the neighbour list of its node b,
   * found by one merge of the sorted list with the group's nodes in
   * increasing order: O(nk + degree) per b (clouds are long) */
  mpgm_argsort_nodes(nodes, nk, srt); /* local indices by node number */
  for (int b = 0; b < nk; b++) {
    const int J = nodes[b], tend = ls->nbr_ptr[J + 1];
    int t = ls->nbr_ptr[J];
    for (int q = 0; q < nk; q++) {
      const int a = srt[q], I = nodes[a];
      while (t < tend && ls->nbr[t] < I) t++;
      MPGM_CHECK(ctx, t < tend && ls->nbr[t] == I, MPGM_ERR_INTERNAL,
                 "pattern misses node %d in the list of node %d", I, J);
      tpos[a * nk + b] = t;
    }
  }
  for (int a = 0; a < nk; a++) {
    const int I = nodes[a];
    for (int b = 0; b < nk; b++) {
      const int J = nodes[b], t = tpos[a * nk + b];
      for (int i = 0; i < MPGM_DIM; i++)
        for (int j = 0; j < MPGM_DIM; j++) {
          const int row = dof[MPGM_DIM * I + i], col = dof[MPGM_DIM * J + j];
          int pos = -1;
          /* held contact components are numbered but get no terms */
          if (row >= 0 && col >= 0 && !nd->fix[MPGM_DIM * I + i] && !nd->fix[MPGM_DIM * J + j]) {
            /* after the rows of I's numbered components before i */
            pos = K->colptr[col] + ls->nbr_off[t] + numbered(nd, I, i);
            /* a broken invariant, checked on every 16th group: the read is
             * a cache miss (a third of the maps' cost on clouds) */
            MPGM_CHECK(ctx, (g & 15) != 0 || K->rowind[pos] == row, MPGM_ERR_INTERNAL,
                       "scatter map: entry (%d, %d) misplaced", row, col);
          }
          ls->scatter[(*s)++] = pos;
        }
    }
  }
  return 0;
}

/* One scatter map per group (none for node clouds). */
static int scatter_maps(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  const int ng = ls->ngroups;
  mpgm_timer_start(ctx, MPGM_T_ANALYSE);
  int maxk = 1, err = map_buffers(pb, &maxk);
  int *srt = malloc(sizeof(int) * (size_t)maxk), *tpos = malloc(sizeof(int) * (size_t)maxk * maxk);
  if (!err && (!srt || !tpos))
    err = mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory (scatter map)");
  size_t s = 0;
  for (int g = 0; g < ng && !err; g++) {
    ls->scatter_ptr[g] = (int)s;
    if (!ls->nomap) err = group_map(pb, g, srt, tpos, &s);
  }
  free(srt);
  free(tpos);
  if (!err) {
    ls->scatter_ptr[ng] = (int)s;
    ls->map_version = pb->conn.map_version;
  }
  mpgm_timer_stop(ctx, MPGM_T_ANALYSE);
  return err;
}

int mpgm_scatter_maps(mpgm_problem *pb) { return scatter_maps(pb); }

int mpgm_scatter_build(mpgm_problem *pb) {
  mpgm_timer_start(pb->ctx, MPGM_T_ANALYSE);
  int err = group_points(pb);
  mpgm_timer_stop(pb->ctx, MPGM_T_ANALYSE);
  return err ? err : scatter_maps(pb);
}

