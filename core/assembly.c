/* assembly.c -- the assembly of residual and tangent (eqs 30-37 of
 * Iaconeta et al. 2017; docs/theory.md) from the points' state that
 * points_eval.c's constitutive update leaves. The pattern and scatter maps
 * they use are built in pattern.c. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core_impl.h"
#include "mpgm_tensor.h"

/* ---- residual and tangent --------------------------------------------- */

/* Newmark: nodal acceleration and velocity of the iterate from du. */
static void newmark_correct(mpgm_problem *pb) {
  mpgm_nodes *nd = &pb->nodes;
  const double dt = pb->dt, b = pb->scene->beta, g = pb->scene->gamma;
  const double c0 = 1.0 / (b * dt * dt), c1 = 1.0 / (b * dt), c2 = 0.5 / b - 1.0;
  for (int i = 0; i < MPGM_DIM * nd->n; i++) {
    nd->a_new[i] = c0 * nd->du[i] - c1 * nd->v[i] - c2 * nd->a[i];
    nd->v_new[i] = nd->v[i] + dt * ((1.0 - g) * nd->a[i] + g * nd->a_new[i]);
  }
}

/* 1 when the block at e is zero. */
static inline int block_zero(const double *e) {
  for (int q = 0; q < MPGM_BLOCK; q++)
    if (e[q] != 0.0) return 0;
  return 1;
}

/* Mark the blocks a cloud writes into its batch: the cloud couples every
 * pair of its nodes (batch slots loc[0..nk)), so each slot's set of
 * coupled slots (mk: MPGM_ASM_WORDS words per slot) gains the cloud's. */
static inline void mark_cloud(uint64_t *mk, const int *loc, int nk) {
  uint64_t set[MPGM_ASM_WORDS] = {0};
  for (int a = 0; a < nk; a++) set[loc[a] >> 6] |= (uint64_t)1 << (loc[a] & 63);
  for (int a = 0; a < nk; a++)
    for (int k = 0; k < MPGM_ASM_WORDS; k++) mk[MPGM_ASM_WORDS * loc[a] + k] |= set[k];
}

/* The place of node I in node J's sorted neighbour list, -1 if absent. */
static inline int nbr_find(const mpgm_problem *pb, int J, int I) {
  mpgm_linsys *ls = pb->ls;
  int lo = ls->nbr_ptr[J], hi = ls->nbr_ptr[J + 1] - 1;
  while (lo <= hi) {
    const int mid = (lo + hi) >> 1, v = ls->nbr[mid];
    if (v < I) lo = mid + 1;
    else if (v > I) hi = mid - 1;
    else return mid;
  }
  return -1;
}

/* Block ab of row node I, column node J, at place t of J's neighbours,
 * added into K (its free components): row i of node I comes after the
 * rows of I's numbered components before i (held ones are numbered but
 * get no terms). */
static inline void add_block(mpgm_problem *pb, int I, int J, int t, const double *ab) {
  mpgm_linsys *ls = pb->ls;
  const int *dof = pb->nodes.dof;
  const unsigned char *fix = pb->nodes.fix;
  double *val = ls->K.val;
  int row[MPGM_DIM], before = 0; /* row i's place after pos0; -1: none */
  for (int i = 0; i < MPGM_DIM; i++) {
    const int numbered = dof[MPGM_DIM * I + i] >= 0;
    row[i] = numbered && !fix[MPGM_DIM * I + i] ? before : -1;
    before += numbered;
  }
  for (int j = 0; j < MPGM_DIM; j++) {
    const int col = dof[MPGM_DIM * J + j];
    if (col < 0 || fix[MPGM_DIM * J + j]) continue;
    const int pos0 = ls->K.colptr[col] + ls->nbr_off[t];
    for (int i = 0; i < MPGM_DIM; i++)
      if (row[i] >= 0) val[pos0 + row[i]] += ab[MPGM_DIM * i + j];
  }
}

/* Block (row slot r, column slot c) of a batch: stored by columns, so
 * the blocks one point adds to a column lie within MPGM_BLOCK x
 * MPGM_ASM_BATCH doubles (4 kB in 2-D). */
static inline double *batch_block(double *kb, int r, int c) {
  return kb + MPGM_BLOCK * ((size_t)MPGM_ASM_BATCH * c + r);
}

/* The batch's block (a, b), kept as the transpose of (b, a) when lower,
 * added into K at place t of column node J's neighbours and zeroed the
 * second time it is read (an upper block is read twice: transposed in
 * column a < b, which comes first, then as itself). */
static inline void flush_block(mpgm_problem *pb, const int *nodes, double *kb, int a, int b,
                               int t, int half) {
  const int lower = half && a > b;
  double *e = lower ? batch_block(kb, b, a) : batch_block(kb, a, b);
  if (block_zero(e)) return;
  double ab[MPGM_BLOCK]; /* block (a, b) = e, or the transpose of e */
  for (int i = 0; i < MPGM_DIM; i++)
    for (int c = 0; c < MPGM_DIM; c++)
      ab[MPGM_DIM * i + c] = lower ? e[MPGM_DIM * c + i] : e[MPGM_DIM * i + c];
  add_block(pb, nodes[a], nodes[b], t, ab);
  if (!lower)
    for (int q = 0; q < MPGM_BLOCK; q++) e[q] = 0.0;
}

/* Add the summed matrix of a batch (blocks (a, b) of MPGM_DIM x MPGM_DIM at
 * batch_block(kb, a, b), B = MPGM_ASM_BATCH of them a side, over the union
 * nodes[0..nk), slot[node] its place there) into K without a stored map,
 * and zero it. Only the pairs some point coupled (their bits in mk) are
 * visited: column node J's sorted neighbours, each looked up in slot,
 * give the coupled rows and their entries of K at once. Node clouds (one
 * point per group, 20-60 nodes) would need maps of hundreds of MB (47 000
 * points x 4 x 24^2 ints for LME-MPM on the rolling disk), each used once
 * or twice. A coupled pair missing from the pattern must have a zero
 * block (else pattern_missed). With half (a symmetric tangent) the batch
 * holds the blocks a <= b only, and block (a, b), a > b, is read as the
 * transpose of (b, a): half the writes of the points into the batch. Each
 * K entry gets one addition per batch, so the order of the visits does
 * not change a bit of K. */
static void flush_batch(mpgm_problem *pb, const int *nodes, int nk, double *kb, uint64_t *mk,
                        int half, const int *slot) {
  mpgm_linsys *ls = pb->ls;
  const int B = MPGM_ASM_BATCH, W = MPGM_ASM_WORDS;
  for (int b = 0; b < nk; b++) {
    const int J = nodes[b];
    const uint64_t *m = mk + W * b;
    int found = 0, coupled = 0;
    for (int t = ls->nbr_ptr[J]; t < ls->nbr_ptr[J + 1]; t++) {
      const int a = slot[ls->nbr[t]];
      if (a < 0 || !((m[a >> 6] >> (a & 63)) & 1)) continue;
      found++;
      flush_block(pb, nodes, kb, a, b, t, half);
    }
    for (int k = 0; k < W; k++) coupled += __builtin_popcountll(m[k]);
    if (found == coupled) continue;
    /* coupled pairs outside the pattern: their blocks must be zero */
    for (int k = 0; k < W; k++)
      for (uint64_t bits = m[k]; bits; bits &= bits - 1) {
        const int a = 64 * k + __builtin_ctzll(bits), lower = half && a > b;
        const double *e = lower ? batch_block(kb, b, a) : batch_block(kb, a, b);
        if (nbr_find(pb, J, nodes[a]) < 0 && !block_zero(e)) ls->pattern_missed = 1;
      }
  }
  memset(mk, 0, sizeof(uint64_t) * (size_t)B * W);
}

/* What every assembly task needs. */
typedef struct {
  mpgm_problem *pb;
  int want_K, half, inertia, geo;
  int mass_only; /* K = M, no material or geometric term */
  int lumped;    /* time.mass lumped: M = diag sum_p m_p N_Ip */
  double kdyn;
  double ks;     /* weight of the stress terms: 1 + time.hht_alpha (1) */
  const double *lift, *an;
  int t0; /* first task of the running phase */
} asm_job;

/* The stress of point p on the gradients of the step's start, B =
 * sigma dF^-T, so that its force on node a is v B dN_a = v sigma g_a with
 * g_a = dN_a dF^-1, the gradient at the iterate: the residual reads dN,
 * and the iterate's gradients g are made only for a tangent (eval_range).
 * Small kinematics: g = dN and B = sigma. */
static inline void stress_on_dN(const mpgm_problem *pb, int p, double B[MPGM_TENSOR]) {
  const double *s = pb->pts.sigma_t + MPGM_NSTRESS * p;
  double S[MPGM_TENSOR]; /* the Voigt stress as a tensor */
  for (int k = 0; k < MPGM_NVOIGT; k++) {
    const int i = mpgm_voigt_pair[k][0], j = mpgm_voigt_pair[k][1];
    S[MPGM_DIM * i + j] = S[MPGM_DIM * j + i] = s[k];
  }
  if (!pb->fx.geometric) {
    memcpy(B, S, sizeof S);
    return;
  }
  const double *dF = pb->pts.dF_t + MPGM_TENSOR * p;
  double iF[MPGM_TENSOR];
  mpgm_inv(dF, mpgm_det(dF), iF);
  for (int i = 0; i < MPGM_DIM; i++) /* B = S iF^T */
    for (int j = 0; j < MPGM_DIM; j++) {
      double b = S[MPGM_DIM * i] * iF[MPGM_DIM * j];
      for (int k = 1; k < MPGM_DIM; k++) b += S[MPGM_DIM * i + k] * iF[MPGM_DIM * j + k];
      B[MPGM_DIM * i + j] = b;
    }
}

/* Internal (and inertial) force of point p subtracted from R. */
static inline void point_residual(const asm_job *j, int p) {
  const mpgm_problem *pb = j->pb;
  const mpgm_points *P = &pb->pts;
  const mpgm_conn *C = &pb->conn;
  const int *dof = pb->nodes.dof;
  double *R = pb->ls->R;
  const double *an = j->an;
  const double v = j->ks * P->vol_t[p], m = P->mass[p];
  const int k0 = C->ptr[p], nk = C->ptr[p + 1] - k0;
  double s[MPGM_TENSOR];
  stress_on_dN(pb, p, s);
#if MPGM_DIM == 2 /* written out per component: inlined where it is called */
  double ap[MPGM_DIM] = {0};
  if (j->inertia && !j->lumped)
    for (int k = k0; k < k0 + nk; k++) {
      ap[0] += C->N[k] * an[MPGM_DIM * C->node[k]];
      ap[1] += C->N[k] * an[MPGM_DIM * C->node[k] + 1];
    }
  for (int a = 0; a < nk; a++) {
    const int I = C->node[k0 + a];
    const double gx = C->dN[MPGM_DIM * (k0 + a)], gy = C->dN[MPGM_DIM * (k0 + a) + 1];
    double f0 = v * (s[0] * gx + s[1] * gy), f1 = v * (s[2] * gx + s[3] * gy);
    if (j->lumped) { /* m_p N_a a_a: the row sum of the consistent term */
      ap[0] = an[MPGM_DIM * I];
      ap[1] = an[MPGM_DIM * I + 1];
    }
    if (j->inertia) {
      f0 += m * C->N[k0 + a] * ap[0];
      f1 += m * C->N[k0 + a] * ap[1];
    }
    if (dof[MPGM_DIM * I] >= 0) R[dof[MPGM_DIM * I]] -= f0;
    if (dof[MPGM_DIM * I + 1] >= 0) R[dof[MPGM_DIM * I + 1]] -= f1;
  }
#else /* f_i = v (s_i0 g_0 + s_i1 g_1 + s_i2 g_2) + m N_a a_i */
  double ap[MPGM_DIM] = {0};
  if (j->inertia && !j->lumped)
    for (int k = k0; k < k0 + nk; k++)
      for (int i = 0; i < MPGM_DIM; i++) ap[i] += C->N[k] * an[MPGM_DIM * C->node[k] + i];
  for (int a = 0; a < nk; a++) {
    const int I = C->node[k0 + a];
    const double *g = C->dN + MPGM_DIM * (k0 + a);
    double f[MPGM_DIM];
    for (int i = 0; i < MPGM_DIM; i++) {
      double si = s[MPGM_DIM * i] * g[0];
      for (int l = 1; l < MPGM_DIM; l++) si += s[MPGM_DIM * i + l] * g[l];
      f[i] = v * si;
    }
    if (j->lumped) /* m_p N_a a_a: the row sum of the consistent term */
      for (int i = 0; i < MPGM_DIM; i++) ap[i] = an[MPGM_DIM * I + i];
    if (j->inertia)
      for (int i = 0; i < MPGM_DIM; i++) f[i] += m * C->N[k0 + a] * ap[i];
    for (int i = 0; i < MPGM_DIM; i++)
      if (dof[MPGM_DIM * I + i] >= 0) R[dof[MPGM_DIM * I + i]] -= f[i];
  }
#endif
}

/* What the blocks of one point need: its stress, tangent, volume and
 * mass, its connectivity entries k0 .. k0 + nk. */
typedef struct {
  const double *s, *D;
  double v, m;
  int k0, nk;
} pt_blocks;

static inline pt_blocks point_blocks(const asm_job *j, int p) {
  const mpgm_problem *pb = j->pb;
  const mpgm_points *P = &pb->pts;
  const int k0 = pb->conn.ptr[p];
  return (pt_blocks){P->sigma_t + MPGM_NSTRESS * p, P->D_t + MPGM_NTANGENT * p, j->ks * P->vol_t[p],
                     P->mass[p], k0, pb->conn.ptr[p + 1] - k0};
}

/* A point's functions and gradients, copied out once for its columns:
 * the n entries of its cloud that enter the tangent, ix their places in
 * the cloud (all of them, in order, unless conn.tan leaves some out:
 * shape.tangent_radius); g[d] the gradients' component d. */
typedef struct {
  double g[MPGM_DIM][MPGM_SHAPE_MAXNODE], N[MPGM_SHAPE_MAXNODE];
  int ix[MPGM_SHAPE_MAXNODE], n;
} pt_rows;

static inline void point_rows(const mpgm_conn *C, const pt_blocks *q, pt_rows *r) {
  const unsigned char *tan = C->tan ? C->tan + q->k0 : NULL;
  int n = 0;
  for (int a = 0; a < q->nk; a++) {
    if (tan && !tan[a]) continue;
    for (int d = 0; d < MPGM_DIM; d++) r->g[d][n] = C->g[MPGM_DIM * (q->k0 + a) + d];
    r->N[n] = C->N[q->k0 + a];
    r->ix[n++] = a;
  }
  r->n = n;
}

/* The blocks (a, b) of a point's column b, rows a < na: entry (i, l) of
 * block a is e[MPGM_DIM i + l][a] (row major DIM x DIM), in arrays over a
 * that the loops filling them vectorise. */
typedef struct {
  double e[MPGM_BLOCK][MPGM_SHAPE_MAXNODE];
} col_blocks;

/* The column terms of node b of a point with gradient h: DB = D B_b
 * (NVOIGT x DIM; B_b's column l holds h_m at the Voigt component of (l,
 * m), engineering shear: 2-D B_b = [hx 0; 0 hy; hy hx], 3-D rows xx, yy,
 * zz, xy, yz, xz) and sigma h. */
typedef struct {
  double DB[MPGM_NVOIGT][MPGM_DIM], sh[MPGM_DIM];
} col_terms;

#if MPGM_DIM == 2
/* Plane strain: B_b, sigma h, the blocks of B_a^T D B_b and the geometric
 * term written out, in the floating-point order of the golden results. */
static inline col_terms column_terms(const double hx, const double hy, const pt_blocks *q) {
  const double *D = q->D, *s = q->s;
  col_terms c;
  for (int i = 0; i < MPGM_NVOIGT; i++) {
    c.DB[i][0] = D[MPGM_NVOIGT * i] * hx + D[MPGM_NVOIGT * i + 2] * hy;
    c.DB[i][1] = D[MPGM_NVOIGT * i + 1] * hy + D[MPGM_NVOIGT * i + 2] * hx;
  }
  c.sh[0] = s[0] * hx + s[2] * hy;
  c.sh[1] = s[2] * hx + s[1] * hy;
  return c;
}

/* Material + geometric + dynamic blocks of column b (the lumped mass's
 * diagonal block after the loop). */
static inline void column_stiffness(const asm_job *j, const pt_blocks *q, const pt_rows *r,
                                    int b, int na, col_blocks *k) {
  const col_terms c = column_terms(r->g[0][b], r->g[1][b], q);
  const double d00 = c.DB[0][0], d20 = c.DB[2][0], d01 = c.DB[0][1], d21 = c.DB[2][1];
  const double d10 = c.DB[1][0], d11 = c.DB[1][1], sh0 = c.sh[0], sh1 = c.sh[1];
  const double v = q->v, km = j->kdyn * q->m, Nb = j->lumped ? 1.0 : r->N[b];
  const int geo = j->geo, inertia = j->inertia, lumped = j->lumped;
  const double *gx = r->g[0], *gy = r->g[1], *N = r->N;
  const int consistent = inertia && !lumped;
  for (int a = 0; a < na; a++) {
    double diag = geo ? v * (gx[a] * sh0 + gy[a] * sh1) : 0.0;
    if (consistent) diag += km * N[a] * Nb;
    k->e[0][a] = v * (gx[a] * d00 + gy[a] * d20) + diag;
    k->e[1][a] = v * (gx[a] * d01 + gy[a] * d21);
    k->e[2][a] = v * (gy[a] * d10 + gx[a] * d20);
    k->e[3][a] = v * (gy[a] * d11 + gx[a] * d21) + diag;
  }
  if (inertia && lumped && b < na) {
    const double diag = (geo ? v * (gx[b] * sh0 + gy[b] * sh1) : 0.0) + km * N[b] * Nb;
    k->e[0][b] = v * (gx[b] * d00 + gy[b] * d20) + diag;
    k->e[3][b] = v * (gy[b] * d11 + gx[b] * d21) + diag;
  }
}
#else
/* 3-D: row l of B_b^T holds h_m at the Voigt component voigt_of[l][m]. */
static inline col_terms column_terms(const double h[MPGM_DIM], const pt_blocks *q) {
  const double *D = q->D, *s = q->s;
  col_terms c;
  for (int i = 0; i < MPGM_NVOIGT; i++)
    for (int l = 0; l < MPGM_DIM; l++) {
      const int *o = mpgm_voigt_of[l];
      c.DB[i][l] = D[MPGM_NVOIGT * i + o[0]] * h[0] + D[MPGM_NVOIGT * i + o[1]] * h[1] +
                   D[MPGM_NVOIGT * i + o[2]] * h[2];
    }
  for (int i = 0; i < MPGM_DIM; i++) {
    const int *o = mpgm_voigt_of[i];
    c.sh[i] = s[o[0]] * h[0] + s[o[1]] * h[1] + s[o[2]] * h[2];
  }
  return c;
}

/* Material + geometric + dynamic blocks of column b: entry (i, l) of
 * block a is v g_a . w_il + [i = l] (v g_a . sigma h + km N_a N_b), with
 * w_il[m] = (D B_b)[voigt_of[i][m]][l] (B_a^T's row i); one loop over a
 * per entry (the lumped mass: the diagonal block b only). */
static inline void column_stiffness(const asm_job *j, const pt_blocks *q, const pt_rows *r,
                                    int b, int na, col_blocks *k) {
  const double h[MPGM_DIM] = {r->g[0][b], r->g[1][b], r->g[2][b]};
  const col_terms c = column_terms(h, q);
  const double v = q->v, km = j->kdyn * q->m, Nb = j->lumped ? 1.0 : r->N[b];
  const double *g0 = r->g[0], *g1 = r->g[1], *g2 = r->g[2], *N = r->N;
  const int consistent = j->inertia && !j->lumped;
  double diag[MPGM_SHAPE_MAXNODE];
  for (int a = 0; a < na; a++) {
    diag[a] = j->geo ? v * (g0[a] * c.sh[0] + g1[a] * c.sh[1] + g2[a] * c.sh[2]) : 0.0;
    if (consistent) diag[a] += km * N[a] * Nb;
  }
  for (int i = 0; i < MPGM_DIM; i++)
    for (int l = 0; l < MPGM_DIM; l++) {
      const int *o = mpgm_voigt_of[i];
      const double w0 = c.DB[o[0]][l], w1 = c.DB[o[1]][l], w2 = c.DB[o[2]][l];
      double *e = k->e[MPGM_DIM * i + l];
      for (int a = 0; a < na; a++) e[a] = v * (g0[a] * w0 + g1[a] * w1 + g2[a] * w2);
      if (i == l)
        for (int a = 0; a < na; a++) e[a] += diag[a];
    }
  if (j->inertia && j->lumped && b < na)
    for (int i = 0; i < MPGM_DIM; i++) k->e[(MPGM_DIM + 1) * i][b] += km * N[b] * Nb;
}
#endif

/* f += block a of k (f: row major DIM x DIM), or its transpose. In 2-D
 * written out, so that the compiler pairs the four sums in two vector
 * additions, as it does not with the loops unrolled. */
static inline void block_add(double *f, const col_blocks *k, int a) {
#if MPGM_DIM == 2
  f[0] += k->e[0][a]; f[1] += k->e[1][a]; f[2] += k->e[2][a]; f[3] += k->e[3][a];
#else
  for (int c = 0; c < MPGM_BLOCK; c++) f[c] += k->e[c][a];
#endif
}

static inline void block_add_transposed(double *f, const col_blocks *k, int a) {
#if MPGM_DIM == 2
  f[0] += k->e[0][a]; f[1] += k->e[2][a]; f[2] += k->e[1][a]; f[3] += k->e[3][a];
#else
  for (int i = 0; i < MPGM_DIM; i++)
    for (int c = 0; c < MPGM_DIM; c++) f[MPGM_DIM * i + c] += k->e[MPGM_DIM * c + i][a];
#endif
}

/* Column b of a point's blocks (places in r), rows a < na: block (a, b) of
 * the tangent (material + geometric + dynamic, or the mass block with
 * j->mass_only); with a lift, the term of a free row of node a and a
 * fixed column of node b subtracted from R. */
static void point_column(const asm_job *j, const mpgm_conn *C, const pt_blocks *q,
                         const pt_rows *r, int b, int na, col_blocks *k) {
  column_stiffness(j, q, r, b, na, k);
  if (j->mass_only) { /* diag I */
    const double km = j->kdyn * q->m, Nb = j->lumped ? 1.0 : r->N[b], *N = r->N;
    for (int a = 0; a < na; a++) {
      const double diag = (a == b || !j->lumped) && j->inertia ? 0.0 + km * N[a] * Nb : 0.0;
      for (int e = 0; e < MPGM_BLOCK; e++) k->e[e][a] = MPGM_DIAG(e) ? diag : 0.0;
    }
  }
  if (!j->lift) return;
  const int *dof = j->pb->nodes.dof, Ib = C->node[q->k0 + r->ix[b]];
  double *R = j->pb->ls->R;
  for (int a = 0; a < na; a++) { /* free row of node a, fixed column of node b */
    const int Ia = C->node[q->k0 + r->ix[a]];
    for (int i = 0; i < MPGM_DIM; i++)
      for (int jj = 0; jj < MPGM_DIM; jj++)
        if (dof[MPGM_DIM * Ia + i] >= 0 && dof[MPGM_DIM * Ib + jj] < 0)
          R[dof[MPGM_DIM * Ia + i]] -= k->e[MPGM_DIM * i + jj][a] * j->lift[MPGM_DIM * Ib + jj];
  }
}

/* Residual and tangent terms of one group, added into R and K through the
 * group's scatter map; kl is the thread's local matrix. */
static void assemble_group(const asm_job *j, int g, double *kl) {
  mpgm_problem *pb = j->pb;
  mpgm_linsys *ls = pb->ls;
  const mpgm_conn *C = &pb->conn;
  const int half = j->half;
  const int t0 = ls->grp_ptr[g], t1 = ls->grp_ptr[g + 1];
  const int nkg = C->ptr[ls->order[t0] + 1] - C->ptr[ls->order[t0]];
  memset(kl, 0, sizeof(double) * MPGM_BLOCK * (size_t)nkg * nkg);
  for (int t = t0; t < t1; t++) {
    const int p = ls->order[t];
    point_residual(j, p);
    const pt_blocks q = point_blocks(j, p);
    pt_rows rw;
    col_blocks k;
    point_rows(C, &q, &rw);
    for (int b = 0; b < rw.n; b++) {
      const int na = half ? b + 1 : rw.n;
      point_column(j, C, &q, &rw, b, na, &k);
      for (int a = 0; a < na; a++) block_add(kl + MPGM_BLOCK * (rw.ix[a] * nkg + rw.ix[b]), &k, a);
    }
  }
  if (half) /* lower blocks: transposes of the upper ones */
    for (int b = 0; b < nkg; b++)
      for (int a = b + 1; a < nkg; a++) {
        double *lo = kl + MPGM_BLOCK * (a * nkg + b);
        const double *up = kl + MPGM_BLOCK * (b * nkg + a);
        for (int i = 0; i < MPGM_DIM; i++)
          for (int c = 0; c < MPGM_DIM; c++) lo[MPGM_DIM * i + c] = up[MPGM_DIM * c + i];
      }
  if (ls->nomap) return; /* summed into the batch by assemble_batch */
  const int *sc = ls->scatter + ls->scatter_ptr[g];
  double *val = ls->K.val;
  for (int r = 0; r < MPGM_BLOCK * nkg * nkg; r++)
    if (sc[r] >= 0) val[sc[r]] += kl[r];
}

/* A group of one point (node clouds: nearly every group) added straight
 * into the batch kb at the slots loc of its nodes: the same sums as
 * assemble_group's local matrix added into the batch, without it (with a
 * symmetric tangent, each pair's one block a <= b of the batch, see
 * flush_batch). */
static void assemble_point_batch(const asm_job *j, int p, const int *loc_all, double *kb,
                                 uint64_t *mk) {
  const mpgm_conn *C = &j->pb->conn;
  const int half = j->half;
  point_residual(j, p);
  const pt_blocks q = point_blocks(j, p);
  pt_rows rw;
  col_blocks k;
  point_rows(C, &q, &rw);
  int loc[MPGM_SHAPE_MAXNODE]; /* the slots of the entries in the tangent */
  for (int a = 0; a < rw.n; a++) loc[a] = loc_all[rw.ix[a]];
  mark_cloud(mk, loc, rw.n);
  for (int b = 0; b < rw.n; b++) {
    const int na = half ? b + 1 : rw.n;
    point_column(j, C, &q, &rw, b, na, &k);
    for (int a = 0; a < na; a++) {
      if (half && loc[a] > loc[b]) /* kept as block (b, a) = (a, b)^T */
        block_add_transposed(batch_block(kb, loc[b], loc[a]), &k, a);
      else
        block_add(batch_block(kb, loc[a], loc[b]), &k, a);
    }
  }
}

_Static_assert(MPGM_ASM_BATCH >= MPGM_SHAPE_MAXNODE, "a batch holds at least one cloud");

/* Node clouds: the groups of task t in batches of consecutive groups
 * (near one another: the group order is by first node) whose clouds' union
 * has at most MPGM_ASM_BATCH nodes. Each group's local matrix is summed
 * into the batch's, and the batch is merged into K once: points of one
 * neighbourhood share most of their nodes, so K's entries (the cache
 * misses of the merge) are written once per batch, not once per point. */
static void assemble_batch(const asm_job *j, int t, int tid) {
  mpgm_problem *pb = j->pb;
  mpgm_linsys *ls = pb->ls;
  const mpgm_conn *C = &pb->conn;
  const int B = MPGM_ASM_BATCH;
  double *kl = ls->kloc + (size_t)tid * (size_t)ls->kloc_size;
  double *kb = ls->kbatch + (size_t)tid * MPGM_BLOCK * B * B;
  int *slot = ls->kslot + (size_t)tid * (size_t)ls->kslot_n;
  uint64_t *mk = ls->kmask + (size_t)tid * MPGM_ASM_BATCH * MPGM_ASM_WORDS;
  int bn[MPGM_ASM_BATCH], loc[MPGM_SHAPE_MAXNODE], nb = 0;
  for (int i = ls->task_ptr[t]; i < ls->task_ptr[t + 1]; i++) {
    const int g = ls->task_grp[i], p = ls->order[ls->grp_ptr[g]];
    const int *nodes = C->node + C->ptr[p], nk = C->ptr[p + 1] - C->ptr[p];
    int fresh = 0;
    for (int a = 0; a < nk; a++) fresh += slot[nodes[a]] < 0;
    if (nb + fresh > B) {
      flush_batch(pb, bn, nb, kb, mk, j->half, slot);
      for (int q = 0; q < nb; q++) slot[bn[q]] = -1;
      nb = 0;
    }
    for (int a = 0; a < nk; a++) {
      if (slot[nodes[a]] < 0) {
        slot[nodes[a]] = nb;
        bn[nb++] = nodes[a];
      }
      loc[a] = slot[nodes[a]];
    }
    if (ls->grp_ptr[g + 1] - ls->grp_ptr[g] == 1) {
      assemble_point_batch(j, p, loc, kb, mk);
      continue;
    }
    assemble_group(j, g, kl);
    mark_cloud(mk, loc, nk);
    for (int a = 0; a < nk; a++)
      for (int b = 0; b < nk; b++) {
        if (j->half && loc[a] > loc[b]) continue; /* the batch's upper blocks only */
        const double *e = kl + MPGM_BLOCK * (a * nk + b);
        double *f = batch_block(kb, loc[a], loc[b]);
        for (int q = 0; q < MPGM_BLOCK; q++) f[q] += e[q];
      }
  }
  if (nb == 0) return;
  flush_batch(pb, bn, nb, kb, mk, j->half, slot);
  for (int q = 0; q < nb; q++) slot[bn[q]] = -1;
}

static void assemble_task(void *arg, int task, int tid) {
  const asm_job *j = arg;
  const mpgm_problem *pb = j->pb;
  mpgm_linsys *ls = pb->ls;
  const int t = j->t0 + task;
  if (j->want_K && ls->nomap) {
    assemble_batch(j, t, tid);
  } else if (j->want_K) {
    double *kl = ls->kloc + (size_t)tid * (size_t)ls->kloc_size;
    for (int i = ls->task_ptr[t]; i < ls->task_ptr[t + 1]; i++)
      assemble_group(j, ls->task_grp[i], kl);
  } else { /* residual only: the task's points as one flat list, in the
            * same order as above (so R is the same to the last bit) */
    for (int i = ls->tpt_ptr[t]; i < ls->tpt_ptr[t + 1]; i++) point_residual(j, ls->task_pts[i]);
  }
}

/* R = f_ext - f_int - f_inertia and (want_K) K; mass_only: R = f_ext -
 * f_int and K = M (mpgm_assemble_mass; want_K 0: R only). With
 * time.hht_alpha a: R = f_ext - (1 + a) f_int - M a_n+1 + a f_int(t_n) and
 * K = (1 + a) K_T + M / (beta dt^2) (Hilber, Hughes and Taylor 1977; the
 * stress terms weighted through the points' volume). */
static int assemble(mpgm_problem *pb, int want_K, int mass_only) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  const double alpha = mass_only ? 0.0 : pb->scene->hht_alpha;
  asm_job j = {.pb = pb, .want_K = want_K, .inertia = pb->fx.inertia, .geo = pb->fx.geometric,
               .lumped = pb->scene->lumped_mass, .ks = 1.0 + alpha};
  if (mass_only) {
    /* the inertia term of R vanishes with a = 0; the mass term of K is
     * kept with unit weight */
    j.mass_only = 1;
    j.geo = 0;
    j.kdyn = 1.0;
    memset(pb->nodes.a_new, 0, sizeof(double) * MPGM_DIM * (size_t)pb->nodes.n);
  } else if (j.inertia) {
    mpgm_timer_start(ctx, MPGM_T_MASS);
    newmark_correct(pb);
    j.kdyn = 1.0 / (pb->scene->beta * pb->dt * pb->dt);
    mpgm_count(ctx, MPGM_C_MASS, 1);
    mpgm_timer_stop(ctx, MPGM_T_MASS);
  }
  mpgm_timer_start(ctx, MPGM_T_ASSEMBLY);
  memcpy(ls->R, ls->fext, sizeof(double) * (size_t)pb->nodes.ndof);
  if (alpha != 0.0)
    for (int i = 0; i < pb->nodes.ndof; i++) ls->R[i] += alpha * ls->fint_n[i];
  if (want_K) memset(ls->K.val, 0, sizeof(double) * (size_t)ls->K.nnz);
  j.an = pb->nodes.a_new;
  j.lift = want_K && !mass_only ? ls->lift : NULL;
  /* symmetric tangent (every material's, K_geo and the mass term are):
   * only the blocks a <= b are computed; not with a lift, which needs the
   * free-fixed blocks of both sides */
  j.half = ls->symmetric && !j.lift;
  /* phase by phase; the tasks of a phase touch disjoint entries */
  for (int ph = 0; ph < 4; ph++) {
    j.t0 = mpgm_asm_phase(ph);
    mpgm_pool_run(pb->pool, mpgm_asm_phase(ph + 1) - mpgm_asm_phase(ph), assemble_task, &j);
  }
  /* a coupling of the clouds outside the pattern (an error of the code
   * that built it: the lists of a pattern skin, shape.skin) */
  if (ls->pattern_missed) {
    mpgm_timer_stop(ctx, MPGM_T_ASSEMBLY);
    MPGM_ERROR(ctx, MPGM_ERR_INTERNAL,
               "step %ld: the sparsity pattern misses a coupling of the node clouds", pb->step + 1);
  }
#if MPGM_DIM == 2 /* contact at surface points is plane strain (contact_points.c) */
  if (pb->fx.contact_points) mpgm_cpoints_assemble(pb, want_K, mass_only);
#endif
  /* held contact components: equation delta = 0 (identity row, R = 0) */
  if (pb->fx.contact) {
    const mpgm_nodes *nd = &pb->nodes;
    for (int i = 0; i < MPGM_DIM * nd->n; i++) {
      const int e = nd->dof[i];
      if (e < 0 || !nd->fix[i]) continue;
      ls->R[e] = 0.0;
      if (!want_K) continue;
      const mpgm_csc *K = &ls->K;
      int lo = K->colptr[e], hi = K->colptr[e + 1] - 1;
      while (lo < hi) { /* rows of a column are sorted */
        const int mid = (lo + hi) / 2;
        if (K->rowind[mid] < e) lo = mid + 1;
        else hi = mid;
      }
      if (lo <= hi && K->rowind[lo] == e) K->val[lo] = 1.0;
    }
  }
  mpgm_timer_stop(ctx, MPGM_T_ASSEMBLY);
  return 0;
}

int mpgm_assemble(mpgm_problem *pb, int want_K) { return assemble(pb, want_K, 0); }

int mpgm_assemble_mass(mpgm_problem *pb) { return assemble(pb, 1, 1); }

int mpgm_assemble_static(mpgm_problem *pb) { return assemble(pb, 0, 1); }

int mpgm_reactions(mpgm_problem *pb, double *r) {
  const mpgm_points *P = &pb->pts;
  const mpgm_conn *C = &pb->conn;
  const mpgm_nodes *nd = &pb->nodes;
  const int inertia = pb->fx.inertia, lumped = pb->scene->lumped_mass;
  const double f = mpgm_gravity_factor(pb, pb->t + pb->dt);
  double g[MPGM_DIM]; /* per component as in point_residual */
  for (int i = 0; i < MPGM_DIM; i++) g[i] = pb->fx.gravity ? f * pb->scene->gravity[i] : 0.0;
  memset(r, 0, sizeof(double) * MPGM_DIM * (size_t)nd->n);
  for (int p = 0; p < P->n; p++) {
    const double v = P->vol_t[p], m = P->mass[p];
    double s[MPGM_TENSOR], ap[MPGM_DIM] = {0};
    stress_on_dN(pb, p, s);
    if (inertia && !lumped)
      for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++)
        for (int i = 0; i < MPGM_DIM; i++) ap[i] += C->N[k] * nd->a_new[MPGM_DIM * C->node[k] + i];
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      int fixed = 0;
      for (int i = 0; i < MPGM_DIM; i++) fixed |= nd->fix[MPGM_DIM * I + i];
      if (!fixed) continue;
      if (inertia && lumped)
        for (int i = 0; i < MPGM_DIM; i++) ap[i] = nd->a_new[MPGM_DIM * I + i];
      const double *dN = C->dN + MPGM_DIM * k, mN = m * C->N[k];
      for (int i = 0; i < MPGM_DIM; i++) {
        double si = s[MPGM_DIM * i] * dN[0];
        for (int l = 1; l < MPGM_DIM; l++) si += s[MPGM_DIM * i + l] * dN[l];
        r[MPGM_DIM * I + i] += v * si + mN * (ap[i] - g[i]);
      }
    }
  }
  for (int i = 0; i < MPGM_DIM * nd->n; i++)
    if (!nd->fix[i]) r[i] = 0.0;
  return 0;
}
