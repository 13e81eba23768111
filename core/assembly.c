/* assembly.c -- constitutive update of the points, the sparsity pattern, and
 * the assembly of residual and tangent (eqs 30-37 of Iaconeta et al. 2017;
 * docs/theory.md). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core.h"

/* 2x2 helpers, row major {a00, a01, a10, a11} */
static inline double det2(const double *a) { return a[0] * a[3] - a[1] * a[2]; }
static inline void mul2(const double *a, const double *b, double *c) {
  c[0] = a[0] * b[0] + a[1] * b[2];
  c[1] = a[0] * b[1] + a[1] * b[3];
  c[2] = a[2] * b[0] + a[3] * b[2];
  c[3] = a[2] * b[1] + a[3] * b[3];
}

int mpgm_eval_points(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  mpgm_points *P = &pb->pts;
  const mpgm_conn *C = &pb->conn;
  const mpgm_nodes *nd = &pb->nodes;
  const mpgm_material *mats = pb->scene->mats;
  const int small = !pb->fx.geometric;
  const int ns = P->nstate;
  mpgm_timer_start(ctx, MPGM_T_MATERIAL);
  int err = 0;
  for (int p = 0; p < P->n && !err; p++) {
    /* H = sum_I du_I (x) grad N_I (small: total u) */
    double H[4] = {0, 0, 0, 0};
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      const double ux = nd->du[2 * I] + (small ? nd->u[2 * I] : 0.0);
      const double uy = nd->du[2 * I + 1] + (small ? nd->u[2 * I + 1] : 0.0);
      const double gx = C->dN[2 * k], gy = C->dN[2 * k + 1];
      H[0] += ux * gx; H[1] += ux * gy;
      H[2] += uy * gx; H[3] += uy * gy;
    }
    double *dF = P->dF_t + 4 * p, *F = P->F_t + 4 * p;
    dF[0] = 1.0 + H[0]; dF[1] = H[1]; dF[2] = H[2]; dF[3] = 1.0 + H[3];
    const mpgm_material *m = &mats[P->mat[p]];
    double *st_n = ns ? P->state + (size_t)ns * p : NULL;
    double *st_t = ns ? P->state_t + (size_t)ns * p : NULL;
    if (small) {
      memcpy(F, dF, sizeof(double) * 4);
      P->vol_t[p] = P->vol0[p];
      for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
        C->g[2 * k] = C->dN[2 * k];
        C->g[2 * k + 1] = C->dN[2 * k + 1];
      }
      err = m->type->update(m, MPGM_KIN_SMALL, F, dF, st_n, st_t, P->sigma_t + 4 * p, P->D_t + 9 * p);
    } else {
      const double J = det2(dF);
      if (!(J > 0.0)) {
        err = mpgm_err_set(ctx, MPGM_ERR_JACOBIAN, __FILE__, __LINE__,
                           "point %d at (%g, %g): det(dF) = %g <= 0", p, P->x[2 * p], P->x[2 * p + 1], J);
        break;
      }
      mul2(dF, P->F + 4 * p, F);
      P->vol_t[p] = J * P->vol[p];
      /* gradients at the iterate: g = dN dF^-1 */
      const double i00 = dF[3] / J, i01 = -dF[1] / J, i10 = -dF[2] / J, i11 = dF[0] / J;
      for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
        const double a = C->dN[2 * k], b = C->dN[2 * k + 1];
        C->g[2 * k] = a * i00 + b * i10;
        C->g[2 * k + 1] = a * i01 + b * i11;
      }
      err = m->type->update(m, MPGM_KIN_FINITE, F, dF, st_n, st_t, P->sigma_t + 4 * p, P->D_t + 9 * p);
    }
    if (!err && pb->fx.prestress) { /* sigma += J^-1 F S0 F^T (small: S0) */
      const double *S = P->S0 + 4 * p;
      double *sg = P->sigma_t + 4 * p;
      if (small) {
        for (int c = 0; c < 4; c++) sg[c] += S[c];
      } else {
        const double J = F[0] * F[3] - F[1] * F[2];
        const double A0 = F[0] * S[0] + F[1] * S[2], A1 = F[0] * S[2] + F[1] * S[1];
        const double A2 = F[2] * S[0] + F[3] * S[2], A3 = F[2] * S[2] + F[3] * S[1];
        sg[0] += (A0 * F[0] + A1 * F[1]) / J;
        sg[1] += (A2 * F[2] + A3 * F[3]) / J;
        sg[2] += (A0 * F[2] + A1 * F[3]) / J;
        sg[3] += S[3] / J;
      }
    }
    if (err)
      mpgm_err_set(ctx, err, __FILE__, __LINE__, "point %d at (%g, %g), material \"%s\": %s", p,
                   P->x[2 * p], P->x[2 * p + 1], m->name, mpgm_code_str(err));
  }
  ctx->n_material_calls += P->n;
  mpgm_timer_stop(ctx, MPGM_T_MATERIAL);
  return err;
}

/* ---- sparsity pattern ------------------------------------------------- */

/* 1 when points p and q are connected to the same nodes in the same order. */
static int same_nodes(const mpgm_conn *C, int p, int q) {
  const int n = C->ptr[p + 1] - C->ptr[p];
  if (n != C->ptr[q + 1] - C->ptr[q]) return 0;
  return memcmp(C->node + C->ptr[p], C->node + C->ptr[q], sizeof(int) * (size_t)n) == 0;
}

/* Group the material points by node list: order them by (first node, hash
 * of the list) with two stable counting sorts, O(points + nodes), then cut
 * the order where the list changes. Equal lists always end up adjacent
 * unless another list with the same first node and hash slot interleaves
 * (then a list forms two groups: correct, only less shared). */
static int group_points(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_conn *C = &pb->conn;
  const int np = pb->pts.n, nn = pb->nodes.n;
  int nslot = 1;
  while (nslot < np) nslot <<= 1;
  const int nb = nslot > nn + 1 ? nslot : nn + 1;
  free(pb->order);
  free(pb->grp_ptr);
  pb->order = malloc(((size_t)np + 1) * sizeof(int));
  pb->grp_ptr = malloc(((size_t)np + 2) * sizeof(int));
  int *key = malloc(((size_t)np + 1) * sizeof(int)), *tmp = malloc(((size_t)np + 1) * sizeof(int));
  int *cnt = malloc(((size_t)nb + 1) * sizeof(int));
  if (!pb->order || !pb->grp_ptr || !key || !tmp || !cnt) {
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
      for (int q = 0; q < np; q++) pb->order[cnt[key[tmp[q]]]++] = tmp[q];
    else
      for (int p = 0; p < np; p++) tmp[cnt[key[p]]++] = p;
  }
  int ng = 0;
  for (int q = 0; q < np; q++)
    if (q == 0 || !same_nodes(C, pb->order[q], pb->order[q - 1])) pb->grp_ptr[ng++] = q;
  pb->grp_ptr[ng] = np;
  pb->ngroups = ng;
  free(key);
  free(tmp);
  free(cnt);
  return 0;
}

static int scatter_maps(mpgm_problem *pb);

int mpgm_pattern_build(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_conn *C = &pb->conn;
  const mpgm_nodes *nd = &pb->nodes;
  const int np = pb->pts.n, nn = nd->n;
  mpgm_timer_start(ctx, MPGM_T_ANALYSE); /* symbolic work, once per pattern */
  int gerr = group_points(pb);
  if (gerr) {
    mpgm_timer_stop(ctx, MPGM_T_ANALYSE);
    return gerr;
  }
  /* node graph: the neighbours of node J are the nodes of every group
   * connected to J (one point stands for its group); built through the
   * node -> groups transpose with a marker per node (O(entries)), each
   * list sorted (they are short) */
  const int ng = pb->ngroups;
  int *tptr = calloc((size_t)nn + 2, sizeof(int)), *nptr = calloc((size_t)nn + 1, sizeof(int));
  int *mark = malloc(((size_t)nn + 1) * sizeof(int));
  int *tpt = malloc(((size_t)C->ptr[np] + 1) * sizeof(int)); /* representative points */
  int *pair = NULL;                                          /* neighbour lists, CSR over nptr */
  if (!tptr || !nptr || !mark || !tpt) goto oom;
  for (int g = 0; g < ng; g++) {
    const int p = pb->order[pb->grp_ptr[g]];
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) tptr[C->node[k] + 2]++;
  }
  for (int i = 0; i < nn; i++) tptr[i + 2] += tptr[i + 1];
  for (int g = 0; g < ng; g++) {
    const int p = pb->order[pb->grp_ptr[g]];
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) tpt[tptr[C->node[k] + 1]++] = p;
  }
  for (int pass = 0; pass < 2; pass++) {
    for (int i = 0; i < nn; i++) mark[i] = -1;
    for (int J = 0; J < nn; J++) {
      int cnt = 0, *list = pass ? pair + nptr[J] : NULL;
      for (int t = tptr[J]; t < tptr[J + 1]; t++)
        for (int k = C->ptr[tpt[t]]; k < C->ptr[tpt[t] + 1]; k++) {
          const int I = C->node[k];
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
      if (!pass) nptr[J + 1] = cnt;
    }
    if (!pass) {
      for (int i = 0; i < nn; i++) nptr[i + 1] += nptr[i];
      pair = malloc(((size_t)nptr[nn] + 1) * sizeof(int));
      if (!pair) goto oom;
    }
  }
  free(tptr);
  free(mark);
  free(tpt);
  tptr = mark = tpt = NULL;
  /* count entries */
  const int n = nd->ndof;
  mpgm_csc *K = &pb->K;
  free(K->colptr);
  free(K->rowind);
  free(K->val);
  K->colptr = calloc((size_t)n + 1, sizeof(int));
  size_t nnz = 0;
  for (int J = 0; J < nn; J++)
    for (int j = 0; j < 2; j++) {
      if (nd->dof[2 * J + j] < 0) continue;
      for (int t = nptr[J]; t < nptr[J + 1]; t++) {
        const int I = pair[t];
        nnz += (nd->dof[2 * I] >= 0) + (nd->dof[2 * I + 1] >= 0);
      }
    }
  K->rowind = malloc((nnz ? nnz : 1) * sizeof(int));
  K->val = calloc(nnz ? nnz : 1, sizeof(double));
  if (!K->colptr || !K->rowind || !K->val || nnz > INT32_MAX) {
    free(pair);
    free(nptr);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (matrix with %zu entries)", nnz);
  }
  size_t e = 0;
  for (int J = 0; J < nn; J++)
    for (int j = 0; j < 2; j++) {
      const int col = nd->dof[2 * J + j];
      if (col < 0) continue;
      for (int t = nptr[J]; t < nptr[J + 1]; t++) {
        const int I = pair[t];
        for (int i = 0; i < 2; i++)
          if (nd->dof[2 * I + i] >= 0) K->rowind[e++] = nd->dof[2 * I + i];
      }
      K->colptr[col + 1] = (int)e;
    }
  K->n = n;
  K->nnz = (int)nnz;
  K->symmetric = pb->symmetric;
  /* kept for the scatter maps: node I's rows in a column of node J start
   * nbr_off[t] entries into the column, t the place of I in J's list */
  int *off = malloc(((size_t)nptr[nn] + 1) * sizeof(int));
  if (!off) {
    free(pair);
    free(nptr);
    MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (sparsity pattern)");
  }
  for (int J = 0; J < nn; J++)
    for (int t = nptr[J], c = 0; t < nptr[J + 1]; t++) {
      off[t] = c;
      c += (nd->dof[2 * pair[t]] >= 0) + (nd->dof[2 * pair[t] + 1] >= 0);
    }
  free(pb->nbr);
  free(pb->nbr_ptr);
  free(pb->nbr_off);
  pb->nbr = pair;
  pb->nbr_ptr = nptr;
  pb->nbr_off = off;
  pb->pattern_version = C->version;
  pb->solver->analysed = 0;
  if (pb->solver_alt) pb->solver_alt->analysed = 0;
  pb->factor_valid = 0;
  mpgm_timer_stop(ctx, MPGM_T_ANALYSE);
  return scatter_maps(pb);
oom:
  free(tptr);
  free(nptr);
  free(mark);
  free(tpt);
  free(pair);
  MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory (sparsity pattern)");
}

/* One scatter map per group: the position in K.val of every (a, b, i, j)
 * entry of the group's node list (-1 where a component is fixed). */
static int scatter_maps(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_conn *C = &pb->conn;
  const mpgm_nodes *nd = &pb->nodes;
  const mpgm_csc *K = &pb->K;
  const int ng = pb->ngroups;
  mpgm_timer_start(ctx, MPGM_T_ANALYSE);
  free(pb->scatter);
  free(pb->scatter_ptr);
  free(pb->kloc);
  pb->scatter = NULL;
  pb->kloc = NULL;
  pb->scatter_ptr = malloc(((size_t)ng + 1) * sizeof(int));
  MPGM_CHECK(ctx, pb->scatter_ptr, MPGM_ERR_NOMEM, "out of memory (scatter map)");
  size_t ns = 0;
  int maxk = 1;
  for (int g = 0; g < ng; g++) {
    const int p = pb->order[pb->grp_ptr[g]], k = C->ptr[p + 1] - C->ptr[p];
    if (k > maxk) maxk = k;
    ns += 4 * (size_t)k * k;
  }
  MPGM_CHECK(ctx, ns <= INT32_MAX, MPGM_ERR_NOMEM, "scatter map of %zu entries", ns);
  pb->scatter = malloc((ns ? ns : 1) * sizeof(int));
  pb->kloc = malloc(4 * (size_t)maxk * maxk * sizeof(double));
  MPGM_CHECK(ctx, pb->scatter && pb->kloc, MPGM_ERR_NOMEM, "out of memory (scatter map)");
  size_t s = 0;
  const int *dof = nd->dof;
  for (int g = 0; g < ng; g++) {
    const int p = pb->order[pb->grp_ptr[g]], k0 = C->ptr[p], nk = C->ptr[p + 1] - k0;
    pb->scatter_ptr[g] = (int)s;
    for (int a = 0; a < nk; a++) {
      const int I = C->node[k0 + a];
      for (int b = 0; b < nk; b++) {
        const int J = C->node[k0 + b];
        /* I in J's sorted neighbour list */
        int lo = pb->nbr_ptr[J], hi = pb->nbr_ptr[J + 1] - 1, t = -1;
        while (lo <= hi) {
          const int mid = (lo + hi) / 2;
          if (pb->nbr[mid] < I) lo = mid + 1;
          else if (pb->nbr[mid] > I) hi = mid - 1;
          else { t = mid; break; }
        }
        MPGM_CHECK(ctx, t >= 0, MPGM_ERR_INTERNAL, "pattern misses node %d in the list of node %d", I, J);
        for (int i = 0; i < 2; i++)
          for (int j = 0; j < 2; j++) {
            const int row = dof[2 * I + i], col = dof[2 * J + j];
            int pos = -1;
            if (row >= 0 && col >= 0) {
              pos = K->colptr[col] + pb->nbr_off[t] + (i == 1 && dof[2 * I] >= 0);
              MPGM_CHECK(ctx, K->rowind[pos] == row, MPGM_ERR_INTERNAL, "scatter map: entry (%d, %d) misplaced", row, col);
            }
            pb->scatter[s++] = pos;
          }
      }
    }
  }
  pb->scatter_ptr[ng] = (int)s;
  pb->map_version = C->map_version;
  mpgm_timer_stop(ctx, MPGM_T_ANALYSE);
  return 0;
}

int mpgm_scatter_build(mpgm_problem *pb) {
  mpgm_timer_start(pb->ctx, MPGM_T_ANALYSE);
  int err = group_points(pb);
  mpgm_timer_stop(pb->ctx, MPGM_T_ANALYSE);
  return err ? err : scatter_maps(pb);
}

/* ---- external force --------------------------------------------------- */

int mpgm_body_force(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  const int n = pb->nodes.ndof;
  memset(pb->fext, 0, sizeof(double) * (size_t)n);
  if (!pb->fx.gravity) return 0;
  mpgm_timer_start(ctx, MPGM_T_BODYFORCE);
  /* static: gravity grows with the load factor; dynamic: it acts in full
   * from the start (only prescribed displacements are ramped in time) */
  const double f = pb->fx.inertia ? 1.0 : pb->lambda;
  const double gx = f * pb->scene->gravity[0];
  const double gy = f * pb->scene->gravity[1];
  const mpgm_conn *C = &pb->conn;
  const int *dof = pb->nodes.dof;
  for (int p = 0; p < pb->pts.n; p++) {
    const double m = pb->pts.mass[p];
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      const double w = m * C->N[k];
      if (dof[2 * I] >= 0) pb->fext[dof[2 * I]] += w * gx;
      if (dof[2 * I + 1] >= 0) pb->fext[dof[2 * I + 1]] += w * gy;
    }
  }
  ctx->n_body_force++;
  mpgm_timer_stop(ctx, MPGM_T_BODYFORCE);
  return 0;
}

/* ---- residual and tangent --------------------------------------------- */

/* Newmark: nodal acceleration and velocity of the iterate from du. */
static void newmark_correct(mpgm_problem *pb) {
  mpgm_nodes *nd = &pb->nodes;
  const double dt = pb->dt, b = pb->scene->beta, g = pb->scene->gamma;
  const double c0 = 1.0 / (b * dt * dt), c1 = 1.0 / (b * dt), c2 = 0.5 / b - 1.0;
  for (int i = 0; i < 2 * nd->n; i++) {
    nd->a_new[i] = c0 * nd->du[i] - c1 * nd->v[i] - c2 * nd->a[i];
    nd->v_new[i] = nd->v[i] + dt * ((1.0 - g) * nd->a[i] + g * nd->a_new[i]);
  }
}

/* Add the local matrix of a run of points into K through its scatter map. */
/* Add a group's local matrix into K through its scatter map. */
static void flush_group(mpgm_problem *pb, int g, int n) {
  const int *sc = pb->scatter + pb->scatter_ptr[g];
  double *val = pb->K.val;
  for (int q = 0; q < n; q++)
    if (sc[q] >= 0) val[sc[q]] += pb->kloc[q];
}

int mpgm_assemble(mpgm_problem *pb, int want_K) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_points *P = &pb->pts;
  const mpgm_conn *C = &pb->conn;
  const int *dof = pb->nodes.dof;
  const int inertia = pb->fx.inertia, geo = pb->fx.geometric;
  double *R = pb->R;
  const int n = pb->nodes.ndof;
  double kdyn = 0.0;
  if (inertia) {
    mpgm_timer_start(ctx, MPGM_T_MASS);
    newmark_correct(pb);
    kdyn = 1.0 / (pb->scene->beta * pb->dt * pb->dt);
    ctx->n_mass++;
    mpgm_timer_stop(ctx, MPGM_T_MASS);
  }
  mpgm_timer_start(ctx, MPGM_T_ASSEMBLY);
  memcpy(R, pb->fext, sizeof(double) * (size_t)n);
  if (want_K) memset(pb->K.val, 0, sizeof(double) * (size_t)pb->K.nnz);
  const double *an = pb->nodes.a_new;
  const double *lift = want_K ? pb->lift : NULL;
  double *kl = pb->kloc;
  /* symmetric tangent (every material's, K_geo and the mass term are):
   * only the blocks a <= b are computed; not with a lift, which needs the
   * free-fixed blocks of both sides */
  const int half = pb->symmetric && !lift;
  /* with K: group by group (one local matrix and one scatter per group);
   * residual only: in memory order */
  const int ng = want_K ? pb->ngroups : 1;
  for (int g = 0; g < ng; g++) {
    const int t0 = want_K ? pb->grp_ptr[g] : 0, t1 = want_K ? pb->grp_ptr[g + 1] : P->n;
    const int p0 = want_K ? pb->order[t0] : 0, nkg = C->ptr[p0 + 1] - C->ptr[p0];
    if (want_K) memset(kl, 0, sizeof(double) * 4 * (size_t)nkg * nkg);
    for (int t = t0; t < t1; t++) {
      const int p = want_K ? pb->order[t] : t;
      const double *s = P->sigma_t + 4 * p, *D = P->D_t + 9 * p;
      const double v = P->vol_t[p], m = P->mass[p];
      const int k0 = C->ptr[p], nk = C->ptr[p + 1] - k0;
      double ap[2] = {0, 0};
      if (inertia)
        for (int k = k0; k < k0 + nk; k++) {
          ap[0] += C->N[k] * an[2 * C->node[k]];
          ap[1] += C->N[k] * an[2 * C->node[k] + 1];
        }
      for (int a = 0; a < nk; a++) {
        const int I = C->node[k0 + a];
        const double gx = C->g[2 * (k0 + a)], gy = C->g[2 * (k0 + a) + 1];
        double f0 = v * (s[0] * gx + s[2] * gy), f1 = v * (s[2] * gx + s[1] * gy);
        if (inertia) {
          f0 += m * C->N[k0 + a] * ap[0];
          f1 += m * C->N[k0 + a] * ap[1];
        }
        if (dof[2 * I] >= 0) R[dof[2 * I]] -= f0;
        if (dof[2 * I + 1] >= 0) R[dof[2 * I + 1]] -= f1;
      }
      if (!want_K) continue;
      for (int b = 0; b < nk; b++) {
        const double hx = C->g[2 * (k0 + b)], hy = C->g[2 * (k0 + b) + 1];
        /* DB = D B_b (3 x 2) */
        double DB[3][2];
        for (int i = 0; i < 3; i++) {
          DB[i][0] = D[3 * i] * hx + D[3 * i + 2] * hy;
          DB[i][1] = D[3 * i + 1] * hy + D[3 * i + 2] * hx;
        }
        const double sh0 = s[0] * hx + s[2] * hy, sh1 = s[2] * hx + s[1] * hy;
        const int Ib = C->node[k0 + b];
        for (int a = 0; a < (half ? b + 1 : nk); a++) {
          const double gx = C->g[2 * (k0 + a)], gy = C->g[2 * (k0 + a) + 1];
          double diag = geo ? v * (gx * sh0 + gy * sh1) : 0.0;
          if (inertia) diag += kdyn * m * C->N[k0 + a] * C->N[k0 + b];
          const double kab[4] = {
              v * (gx * DB[0][0] + gy * DB[2][0]) + diag, v * (gx * DB[0][1] + gy * DB[2][1]),
              v * (gy * DB[1][0] + gx * DB[2][0]), v * (gy * DB[1][1] + gx * DB[2][1]) + diag};
          double *e = kl + 4 * (a * nk + b);
          for (int q = 0; q < 4; q++) e[q] += kab[q];
          if (lift) { /* free row of node a, fixed column of node b */
            const int Ia = C->node[k0 + a];
            for (int i = 0; i < 2; i++)
              for (int j = 0; j < 2; j++)
                if (dof[2 * Ia + i] >= 0 && dof[2 * Ib + j] < 0)
                  R[dof[2 * Ia + i]] -= kab[2 * i + j] * lift[2 * Ib + j];
          }
        }
      }
    }
    if (want_K && half) /* lower blocks: transposes of the upper ones */
      for (int b = 0; b < nkg; b++)
        for (int a = b + 1; a < nkg; a++) {
          double *lo = kl + 4 * (a * nkg + b);
          const double *up = kl + 4 * (b * nkg + a);
          lo[0] = up[0]; lo[1] = up[2]; lo[2] = up[1]; lo[3] = up[3];
        }
    if (want_K) flush_group(pb, g, 4 * nkg * nkg);
  }
  mpgm_timer_stop(ctx, MPGM_T_ASSEMBLY);
  return 0;
}

int mpgm_reactions(mpgm_problem *pb, double *r) {
  const mpgm_points *P = &pb->pts;
  const mpgm_conn *C = &pb->conn;
  const mpgm_nodes *nd = &pb->nodes;
  const int inertia = pb->fx.inertia;
  const double f = inertia ? 1.0 : pb->lambda;
  const double g[2] = {pb->fx.gravity ? f * pb->scene->gravity[0] : 0.0,
                       pb->fx.gravity ? f * pb->scene->gravity[1] : 0.0};
  memset(r, 0, sizeof(double) * 2 * (size_t)nd->n);
  for (int p = 0; p < P->n; p++) {
    const double *s = P->sigma_t + 4 * p, v = P->vol_t[p], m = P->mass[p];
    double ap[2] = {0, 0};
    if (inertia)
      for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
        ap[0] += C->N[k] * nd->a_new[2 * C->node[k]];
        ap[1] += C->N[k] * nd->a_new[2 * C->node[k] + 1];
      }
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      if (!nd->fix[2 * I] && !nd->fix[2 * I + 1]) continue;
      const double gx = C->g[2 * k], gy = C->g[2 * k + 1], mN = m * C->N[k];
      r[2 * I] += v * (s[0] * gx + s[2] * gy) + mN * (ap[0] - g[0]);
      r[2 * I + 1] += v * (s[2] * gx + s[1] * gy) + mN * (ap[1] - g[1]);
    }
  }
  for (int i = 0; i < 2 * nd->n; i++)
    if (!nd->fix[i]) r[i] = 0.0;
  return 0;
}
