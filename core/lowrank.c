/* lowrank.c -- a change of the contact springs applied to a kept
 * factorisation (solver.contact_rank; docs/theory.md, "Contact changes
 * without refactorising").
 *
 * A surface point that is caught by a plane, or let go, adds or removes
 * its spring k N N^T in each component: a change of rank two per point.
 * Modified Newton keeps a factorisation of an earlier tangent K0 for as
 * long as Newton converges well with it, but a contact change used to
 * throw it away, because K0 without a new spring is a poor model of the
 * tangent (the step then needs many more iterations). With the change
 * written as K0 + U D U^T (U: the columns sqrt(|w|) N of the changed
 * springs, one per point and component; D: their signs, + caught, -
 * let go), the Woodbury identity solves with the corrected matrix at the
 * price of one solve per column, once:
 *
 *   (K0 + U D U^T)^-1 b = x - Z C^-1 U^T x,  x = K0^-1 b,  Z = K0^-1 U,
 *   C = D^-1 + U^T Z  (r x r, r = the columns).
 *
 * The set of columns is the difference between the springs held now and
 * those in the factorised tangent; it is rebuilt at every contact change
 * and emptied at every factorisation. A column kept from an earlier change
 * keeps its vector and Z: N of a moving point (node clouds keep a
 * factorisation across steps) is then that of the configuration the
 * column was made in, like the kept tangent itself. More than solver.contact_rank columns, or a C too close
 * to singular, and the tangent is factorised again as before.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core_impl.h"

/* Spring stiffness of tracer t in the state held[] describes (0: free). */
static double spring(const mpgm_problem *pb, int plane_plus1) {
  return plane_plus1 > 0 ? pb->scene->bcs[plane_plus1 - 1].penalty : 0.0;
}

/* What the tracer holds now, in the form of held0: plane + 1, 0 free. */
static int held_now(const mpgm_cpoints *cp, int t) {
  return cp->plane[t] >= 0 && !cp->off[t] ? cp->plane[t] + 1 : 0;
}

void mpgm_lowrank_free(mpgm_lowrank *lr) {
  void *arr[] = {lr->held0, lr->col_t, lr->col_c, lr->col_w, lr->col_t2, lr->col_c2,
                 lr->col_w2, lr->nnz, lr->nnz2, lr->idx, lr->val, lr->idx2, lr->val2,
                 lr->Z, lr->Z2, lr->C, lr->perm, lr->y, lr->src, lr->W};
  for (size_t i = 0; i < sizeof arr / sizeof arr[0]; i++) free(arr[i]);
  memset(lr, 0, sizeof *lr);
}

/* Arrays for cap columns of n equations and nt tracers. */
static int lowrank_alloc(mpgm_problem *pb, int n) {
  mpgm_ctx *ctx = pb->ctx;
  mpgm_lowrank *lr = &pb->ls->lr;
  const int cap = pb->scene->contact_rank, m = MPGM_DIM * MPGM_SHAPE_MAXNODE;
  if (lr->held0 && lr->n_cap >= n && lr->nt == pb->cp.n) return 0;
  mpgm_lowrank_free(lr);
  lr->cap = cap;
  lr->nt = pb->cp.n;
  lr->n_cap = n;
  MPGM_ALLOC(ctx, lr->held0, lr->nt);
  MPGM_ALLOC(ctx, lr->col_t, cap);
  MPGM_ALLOC(ctx, lr->col_c, cap);
  MPGM_ALLOC(ctx, lr->col_w, cap);
  MPGM_ALLOC(ctx, lr->col_t2, cap);
  MPGM_ALLOC(ctx, lr->col_c2, cap);
  MPGM_ALLOC(ctx, lr->col_w2, cap);
  MPGM_ALLOC(ctx, lr->nnz, cap);
  MPGM_ALLOC(ctx, lr->nnz2, cap);
  MPGM_ALLOC(ctx, lr->idx, (size_t)cap * m);
  MPGM_ALLOC(ctx, lr->val, (size_t)cap * m);
  MPGM_ALLOC(ctx, lr->idx2, (size_t)cap * m);
  MPGM_ALLOC(ctx, lr->val2, (size_t)cap * m);
  MPGM_ALLOC(ctx, lr->Z, (size_t)cap * n);
  MPGM_ALLOC(ctx, lr->Z2, (size_t)cap * n);
  MPGM_ALLOC(ctx, lr->C, (size_t)cap * cap);
  MPGM_ALLOC(ctx, lr->perm, cap);
  MPGM_ALLOC(ctx, lr->y, cap);
  MPGM_ALLOC(ctx, lr->src, cap);
  MPGM_ALLOC(ctx, lr->W, (size_t)cap * n);
  return 0;
}

int mpgm_lowrank_reset(mpgm_problem *pb) {
  mpgm_linsys *ls = pb->ls;
  const mpgm_scene *sc = pb->scene;
  if (!pb->fx.contact_points || sc->contact_rank <= 0 || !sc->newton_modified) return 0;
  MPGM_CALL(lowrank_alloc(pb, ls->K.n));
  mpgm_lowrank *lr = &ls->lr;
  for (int t = 0; t < lr->nt; t++) lr->held0[t] = (unsigned char)held_now(&pb->cp, t);
  lr->r = 0;
  lr->n = ls->K.n;
  lr->valid = 1;
  return 0;
}

/* The vector of column (t, c): sqrt(|w|) N of tracer t on the free
 * equations of component c, into idx/val; returns its entries. */
static int column(const mpgm_problem *pb, int t, int c, double w, int *idx, double *val) {
  const mpgm_conn *C = &pb->conn;
  const mpgm_nodes *nd = &pb->nodes;
  const int p = pb->cp.first + t;
  const double s = sqrt(fabs(w));
  int k = 0;
  for (int a = C->ptr[p]; a < C->ptr[p + 1]; a++) {
    const int i = MPGM_DIM * C->node[a] + c, e = nd->dof[i];
    if (e < 0 || nd->fix[i] || C->N[a] == 0.0) continue;
    idx[k] = e;
    val[k++] = s * C->N[a];
  }
  return k;
}

/* Column j of the old set for the same spring change (t, c, w), or -1. */
static int old_column(const mpgm_lowrank *lr, int r_old, int t, int c, double w) {
  for (int j = 0; j < r_old; j++)
    if (lr->col_t[j] == t && lr->col_c[j] == c && lr->col_w[j] == w) return j;
  return -1;
}

/* LU with partial pivoting of the r x r row-major a in place, rows
 * exchanged as piv records; 0 when a pivot is below tol. Written out
 * rather than through a library: the result must not depend on which
 * BLAS a library resolves at run time (GSL's LU calls CBLAS, and the
 * program links OpenBLAS and GSL's own, in an order that differs between
 * builds), since the goldens compare runs to the bit. */
static int lu_small(double *a, int r, int *piv, double tol) {
  for (int k = 0; k < r; k++) {
    int p = k;
    for (int i = k + 1; i < r; i++)
      if (fabs(a[i * r + k]) > fabs(a[p * r + k])) p = i;
    piv[k] = p;
    if (!(fabs(a[p * r + k]) > tol)) return 0;
    if (p != k)
      for (int j = 0; j < r; j++) {
        const double t = a[k * r + j];
        a[k * r + j] = a[p * r + j];
        a[p * r + j] = t;
      }
    for (int i = k + 1; i < r; i++) {
      const double l = a[i * r + k] / a[k * r + k];
      a[i * r + k] = l;
      for (int j = k + 1; j < r; j++) a[i * r + j] -= l * a[k * r + j];
    }
  }
  return 1;
}

/* y = C^-1 y with the factors of lu_small. */
static void lu_solve_small(const double *a, int r, const int *piv, double *y) {
  for (int k = 0; k < r; k++) {
    const double t = y[k];
    y[k] = y[piv[k]];
    y[piv[k]] = t;
    for (int i = k + 1; i < r; i++) y[i] -= a[i * r + k] * y[k];
  }
  for (int k = r - 1; k >= 0; k--) {
    for (int j = k + 1; j < r; j++) y[k] -= a[k * r + j] * y[j];
    y[k] /= a[k * r + k];
  }
}

/* C = D^-1 + U^T Z and its LU factors; 0 when a pivot is too small
 * against the largest entry (then the caller refactorises). */
static int capacitance(mpgm_lowrank *lr) {
  const int r = lr->r, m = MPGM_DIM * MPGM_SHAPE_MAXNODE;
  double big = 0.0;
  for (int i = 0; i < r; i++)
    for (int j = 0; j < r; j++) {
      const int *idx = lr->idx + (size_t)i * m;
      const double *val = lr->val + (size_t)i * m, *z = lr->Z + (size_t)j * lr->n;
      double s = i == j ? (lr->col_w[i] > 0.0 ? 1.0 : -1.0) : 0.0;
      for (int k = 0; k < lr->nnz[i]; k++) s += val[k] * z[idx[k]];
      lr->C[i * r + j] = s;
      big = fmax(big, fabs(s));
    }
  return lu_small(lr->C, r, lr->perm, 1e-10 * big);
}

/* The springs that differ from the factorised tangent's, tracer by
 * tracer, as columns (t, c, w) into the second list (col_t2, col_c2,
 * col_w2); 0 when there are more than cap. */
static int changed_springs(const mpgm_problem *pb, mpgm_lowrank *lr, int *r) {
  const mpgm_cpoints *cp = &pb->cp;
  *r = 0;
  for (int t = 0; t < cp->n; t++) {
    const double w = spring(pb, held_now(cp, t)) - spring(pb, lr->held0[t]);
    if (w == 0.0) continue;
    if (*r + MPGM_DIM > lr->cap) return 0;
    for (int c = 0; c < MPGM_DIM; c++, (*r)++) {
      lr->col_t2[*r] = t;
      lr->col_c2[*r] = (signed char)c;
      lr->col_w2[*r] = w;
    }
  }
  return 1;
}

/* The vectors and Z of the r columns of the second list into the second
 * buffers: a column of the current set keeps its vector and Z, new ones
 * are written as full vectors into W and solved for together (one solve
 * with several right-hand sides). */
static int build_columns(mpgm_problem *pb, mpgm_lowrank *lr, int r) {
  const int m = MPGM_DIM * MPGM_SHAPE_MAXNODE, n = lr->n;
  int nnew = 0;
  for (int q = 0; q < r; q++) {
    const int t = lr->col_t2[q], c = lr->col_c2[q];
    const double w = lr->col_w2[q];
    int *idx = lr->idx2 + (size_t)q * m;
    double *val = lr->val2 + (size_t)q * m;
    const int j = old_column(lr, lr->r, t, c, w);
    if (j >= 0) { /* kept with its vector and Z */
      const int k = lr->nnz[j];
      memcpy(idx, lr->idx + (size_t)j * m, sizeof(int) * (size_t)k);
      memcpy(val, lr->val + (size_t)j * m, sizeof(double) * (size_t)k);
      memcpy(lr->Z2 + (size_t)q * n, lr->Z + (size_t)j * n, sizeof(double) * (size_t)n);
      lr->nnz2[q] = k;
      lr->src[q] = -1;
      continue;
    }
    const int k = column(pb, t, c, w, idx, val);
    lr->nnz2[q] = k;
    lr->src[q] = nnew;
    double *u = lr->W + (size_t)nnew++ * n;
    memset(u, 0, sizeof(double) * (size_t)n);
    for (int e = 0; e < k; e++) u[idx[e]] = val[e];
  }
  if (nnew) {
    MPGM_CALL(mpgm_solver_solve_many(pb->ls->solver, pb->ctx, n, nnew, lr->W, lr->W));
    for (int q = 0; q < r; q++)
      if (lr->src[q] >= 0)
        memcpy(lr->Z2 + (size_t)q * n, lr->W + (size_t)lr->src[q] * n, sizeof(double) * (size_t)n);
  }
  return 0;
}

#define SWAP(T, a, b) do { T sw_ = (a); (a) = (b); (b) = sw_; } while (0)

int mpgm_lowrank_update(mpgm_problem *pb, int *applied) {
  mpgm_linsys *ls = pb->ls;
  mpgm_lowrank *lr = &ls->lr;
  *applied = 0;
  if (!lr->valid || lr->n != ls->K.n || lr->nt != pb->cp.n) return 0;
  int r;
  if (!changed_springs(pb, lr, &r)) {
    lr->valid = 0;
    return 0;
  }
  MPGM_CALL(build_columns(pb, lr, r));
  /* the new set becomes the current one */
  lr->r = r;
  SWAP(int *, lr->col_t, lr->col_t2);
  SWAP(signed char *, lr->col_c, lr->col_c2);
  SWAP(double *, lr->col_w, lr->col_w2);
  SWAP(int *, lr->nnz, lr->nnz2);
  SWAP(double *, lr->Z, lr->Z2);
  SWAP(int *, lr->idx, lr->idx2);
  SWAP(double *, lr->val, lr->val2);
  if (r > 0 && !capacitance(lr)) {
    lr->valid = 0;
    return 0;
  }
  *applied = 1;
  return 0;
}

void mpgm_lowrank_apply(mpgm_problem *pb, double *x) {
  mpgm_lowrank *lr = &pb->ls->lr;
  const int r = lr->r, m = MPGM_DIM * MPGM_SHAPE_MAXNODE;
  if (!lr->valid || r == 0) return;
  for (int i = 0; i < r; i++) {
    const int *idx = lr->idx + (size_t)i * m;
    const double *val = lr->val + (size_t)i * m;
    double s = 0.0;
    for (int k = 0; k < lr->nnz[i]; k++) s += val[k] * x[idx[k]];
    lr->y[i] = s;
  }
  lu_solve_small(lr->C, r, lr->perm, lr->y);
  for (int j = 0; j < r; j++) {
    const double *z = lr->Z + (size_t)j * lr->n, yj = lr->y[j];
    for (int i = 0; i < lr->n; i++) x[i] -= z[i] * yj;
  }
}
