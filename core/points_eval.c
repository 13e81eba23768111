/* points_eval.c -- the constitutive update of the points (their
 * kinematics from the nodes' increments, the materials, the prestress) and
 * the external force of gravity and body forces: what every integrator
 * needs of the points, implicit (before assembly.c's residual and tangent)
 * and explicit alike. Written for both dimensions, in the plane code's
 * order of sums. */
#include <math.h>
#include <string.h>

#include "mpgm_core_impl.h"
#include "mpgm_tensor.h"

/* sigma += J^-1 F S0 F^T: the initial stress pushed forward with F. */
static void push_prestress(const double *F, const double *S, double *sg) {
#if MPGM_DIM == 2 /* written out; zz is out of plane (F33 = 1) */
  const double J = mpgm_det(F);
  const double A0 = F[0] * S[0] + F[1] * S[2], A1 = F[0] * S[2] + F[1] * S[1];
  const double A2 = F[2] * S[0] + F[3] * S[2], A3 = F[2] * S[2] + F[3] * S[1];
  sg[0] += (A0 * F[0] + A1 * F[1]) / J;
  sg[1] += (A2 * F[2] + A3 * F[3]) / J;
  sg[2] += (A0 * F[2] + A1 * F[3]) / J;
  sg[3] += S[3] / J;
#else /* S0 as a tensor, F S0 F^T, back to Voigt */
  const double J = mpgm_det(F);
  double T[MPGM_TENSOR], A[MPGM_TENSOR], Ft[MPGM_TENSOR], B[MPGM_TENSOR];
  for (int k = 0; k < MPGM_NVOIGT; k++) {
    const int i = mpgm_voigt_pair[k][0], j = mpgm_voigt_pair[k][1];
    T[MPGM_DIM * i + j] = T[MPGM_DIM * j + i] = S[k];
  }
  for (int i = 0; i < MPGM_DIM; i++)
    for (int j = 0; j < MPGM_DIM; j++) Ft[MPGM_DIM * i + j] = F[MPGM_DIM * j + i];
  mpgm_mul(F, T, A);
  mpgm_mul(A, Ft, B);
  for (int k = 0; k < MPGM_NVOIGT; k++)
    sg[k] += B[MPGM_DIM * mpgm_voigt_pair[k][0] + mpgm_voigt_pair[k][1]] / J;
#endif
}

/* Kinematics and constitutive update of points [p0, p1), with their
 * tangents D when want_D. Returns 0 or the first failure's code with its
 * point in *fail and, for det(dF) <= 0, the determinant in *fail_J; no
 * message here (tasks run on worker threads). */
static int eval_range(mpgm_problem *pb, int want_D, int p0, int p1, int *fail, double *fail_J,
                      void (*each)(void *job, int p, const double *dF), void *job) {
  mpgm_points *P = &pb->pts;
  const mpgm_conn *C = &pb->conn;
  const mpgm_nodes *nd = &pb->nodes;
  const mpgm_material *mats = pb->scene->mats;
  const int small = !pb->fx.geometric;
  const int ns = P->nstate;
  double *D_t = want_D ? P->D_t : NULL;
  for (int p = p0; p < p1; p++) {
    int err;
    /* H = sum_I du_I (x) grad N_I, the gradient of the step's increment,
     * and dF = I + H */
    double H[MPGM_TENSOR] = {0};
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const double *u = nd->du + MPGM_DIM * C->node[k], *g = C->dN + MPGM_DIM * k;
      for (int i = 0; i < MPGM_DIM; i++)
        for (int j = 0; j < MPGM_DIM; j++) H[MPGM_DIM * i + j] += u[i] * g[j];
    }
#if MPGM_DIM == 3
    /* with each (the explicit fused pass): the increment stays on the
     * stack, handed to each, and is not stored (a pass less over the
     * memory) */
    double dF_here[MPGM_TENSOR];
    double *dF = each ? dF_here : P->dF_t + MPGM_TENSOR * p, *F = P->F_t + MPGM_TENSOR * p;
#else /* the plane code as it was (the choice cost its loop 4 % of instructions) */
    double *dF = P->dF_t + MPGM_TENSOR * p, *F = P->F_t + MPGM_TENSOR * p;
#endif
    for (int c = 0; c < MPGM_TENSOR; c++) dF[c] = MPGM_DIAG(c) ? 1.0 + H[c] : H[c];
    const mpgm_material *m = &mats[P->mat[p]];
    double *st_n = ns ? P->state + (size_t)ns * p : NULL;
    double *st_t = ns ? P->state_t + (size_t)ns * p : NULL;
    if (small) {
      /* the strain accumulated at the point, step by step: F = I + grad u
       * is the last step's plus this step's increment. The nodes need not
       * keep the total displacement (MPM's grid is reset every step) */
      for (int c = 0; c < MPGM_TENSOR; c++) F[c] = P->F[MPGM_TENSOR * p + c] + H[c];
      P->vol_t[p] = P->vol0[p];
      if (want_D) /* g = dN, for the tangent */
        for (int i = MPGM_DIM * C->ptr[p]; i < MPGM_DIM * C->ptr[p + 1]; i++) C->g[i] = C->dN[i];
      err = m->type->update(m, MPGM_KIN_SMALL, F, dF, st_n, st_t, P->sigma_t + MPGM_NSTRESS * p,
                            D_t ? D_t + MPGM_NTANGENT * p : NULL);
    } else {
      double J = mpgm_det(dF);
      if (p == 0 && mpgm_fault_due(pb->ctx, MPGM_ERR_JACOBIAN, pb->step + 1)) J = -J; /* tests */
      if (!(J > 0.0)) {
        *fail = p;
        *fail_J = J;
        return MPGM_ERR_JACOBIAN;
      }
      mpgm_mul(dF, P->F + MPGM_TENSOR * p, F);
      P->vol_t[p] = J * P->vol[p];
      /* gradients at the iterate, g = dN dF^-1, for the tangent only (the
       * residual takes dN, see stress_on_dN) */
      if (want_D) {
        double iF[MPGM_TENSOR];
        mpgm_inv(dF, J, iF);
        for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
          const double *a = C->dN + MPGM_DIM * k;
          for (int j = 0; j < MPGM_DIM; j++) {
            double gj = a[0] * iF[j];
            for (int i = 1; i < MPGM_DIM; i++) gj += a[i] * iF[MPGM_DIM * i + j];
            C->g[MPGM_DIM * k + j] = gj;
          }
        }
      }
      err = m->type->update(m, MPGM_KIN_FINITE, F, dF, st_n, st_t, P->sigma_t + MPGM_NSTRESS * p,
                            D_t ? D_t + MPGM_NTANGENT * p : NULL);
    }
    if (!err && p == 0 && mpgm_fault_due(pb->ctx, MPGM_ERR_RETURN_MAP, pb->step + 1))
      err = MPGM_ERR_RETURN_MAP; /* tests: as the material would report it */
    if (err) {
      *fail = p;
      *fail_J = 1.0; /* not a det(dF) failure */
      return err;
    }
    if (pb->fx.prestress) { /* sigma += J^-1 F S0 F^T (small: S0) */
      const double *S = P->S0 + MPGM_NSTRESS * p;
      double *sg = P->sigma_t + MPGM_NSTRESS * p;
      if (small) {
        for (int c = 0; c < MPGM_NSTRESS; c++) sg[c] += S[c];
      } else {
        push_prestress(F, S, sg);
      }
    }
    if (each) each(job, p, dF);
  }
  return 0;
}

/* Point loops run as up to EVAL_TASKS contiguous ranges of at least
 * EVAL_CHUNK points; each range keeps its own first failure. */
#define EVAL_TASKS 64
#define EVAL_CHUNK 512

typedef struct {
  mpgm_problem *pb;
  int want_D;
  int ntask;
  int err[EVAL_TASKS], fail[EVAL_TASKS];
  double fail_J[EVAL_TASKS];
} eval_job;

static void eval_task(void *arg, int t, int tid) {
  (void)tid;
  eval_job *j = arg;
  const int np = j->pb->pts.n;
  const int p0 = (int)((long)np * t / j->ntask), p1 = (int)((long)np * (t + 1) / j->ntask);
  j->err[t] = eval_range(j->pb, j->want_D, p0, p1, &j->fail[t], &j->fail_J[t], NULL, NULL);
}

/* The error of a failed evaluation at point p (code err, det J). */
static int eval_error(const mpgm_problem *pb, int err, int p, double J) {
  const mpgm_points *P = &pb->pts;
  char at[MPGM_POINT_STR];
  mpgm_point_str(P->x + MPGM_DIM * p, at);
  if (err == MPGM_ERR_JACOBIAN && !(J > 0.0))
    MPGM_ERROR(pb->ctx, MPGM_ERR_JACOBIAN, "point %d at %s: det(dF) = %g <= 0", P->id[p], at, J);
  MPGM_ERROR(pb->ctx, err, "point %d at %s, material \"%s\": %s", P->id[p], at,
             pb->scene->mats[P->mat[p]].name, mpgm_code_str(err));
}

int mpgm_eval_points(mpgm_problem *pb, int want_D) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_points *P = &pb->pts;
  mpgm_timer_start(ctx, MPGM_T_MATERIAL);
  eval_job j;
  j.pb = pb;
  j.want_D = want_D;
  j.ntask = P->n / EVAL_CHUNK;
  if (j.ntask > EVAL_TASKS) j.ntask = EVAL_TASKS;
  if (j.ntask < 1) j.ntask = 1;
  mpgm_pool_run(pb->pool, j.ntask, eval_task, &j);
  mpgm_count(ctx, MPGM_C_MATERIAL_CALLS, P->n);
  mpgm_timer_stop(ctx, MPGM_T_MATERIAL);
  /* the failure of the lowest point: the one a serial loop stops at */
  for (int t = 0; t < j.ntask; t++)
    if (j.err[t]) return eval_error(pb, j.err[t], j.fail[t], j.fail_J[t]);
  return 0;
}

int mpgm_eval_points_each(mpgm_problem *pb, void (*each)(void *job, int p, const double *dF),
                          void *job) {
  mpgm_ctx *ctx = pb->ctx;
  mpgm_timer_start(ctx, MPGM_T_MATERIAL);
  int fail = 0;
  double fail_J = 1.0;
  const int err = eval_range(pb, 0, 0, pb->pts.n, &fail, &fail_J, each, job);
  mpgm_count(ctx, MPGM_C_MATERIAL_CALLS, pb->pts.n);
  mpgm_timer_stop(ctx, MPGM_T_MATERIAL);
  return err ? eval_error(pb, err, fail, fail_J) : 0;
}

/* ---- external force --------------------------------------------------- */

int mpgm_body_force(mpgm_problem *pb, double t) {
  mpgm_linsys *ls = pb->ls;
  mpgm_ctx *ctx = pb->ctx;
  const int n = pb->nodes.ndof;
  memset(ls->fext, 0, sizeof(double) * (size_t)n);
  if (!pb->fx.gravity && !pb->fx.manufactured) return 0;
  mpgm_timer_start(ctx, MPGM_T_BODYFORCE);
  const double *b = MPGM_MMS_FORCES(pb, t);
  /* static: gravity grows with the load factor; dynamic: it acts in full
   * from the start unless the scene ramps it (gravity_ramp); prescribed
   * displacements ramp over the run */
  const double f = mpgm_gravity_factor(pb, t);
  double g[MPGM_DIM];
  for (int d = 0; d < MPGM_DIM; d++) g[d] = f * pb->scene->gravity[d];
  const mpgm_conn *C = &pb->conn;
  const int *dof = pb->nodes.dof;
  for (int p = 0; p < pb->pts.n; p++) {
    const double m = pb->pts.mass[p];
    double bf[MPGM_DIM];
    for (int d = 0; d < MPGM_DIM; d++) bf[d] = g[d] + (b ? b[MPGM_DIM * p + d] : 0.0);
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      const double w = m * C->N[k];
      for (int d = 0; d < MPGM_DIM; d++)
        if (dof[MPGM_DIM * I + d] >= 0) ls->fext[dof[MPGM_DIM * I + d]] += w * bf[d];
    }
  }
  mpgm_count(ctx, MPGM_C_BODY_FORCE, 1);
  mpgm_timer_stop(ctx, MPGM_T_BODYFORCE);
  return 0;
}
