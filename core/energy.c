/* energy.c -- the energy and momentum balance of dynamic runs (explicit
 * and implicit; docs/theory.md section 19, "Energy and momentum"): the
 * work of the stresses and of gravity accumulated step by step, the
 * kinetic energy and the momentum of the points and of the nodes; the
 * guard that stops an explicit run whose energy grows without work to
 * account for it. */
#include <math.h>
#include <string.h>

#include "mpgm_core_impl.h"
#include "mpgm_tensor.h"

/* Work of the stresses over the step about to be committed (the trial
 * arrays against the committed ones), by the midpoint rule: the rate of
 * deformation of F(s) = (I + s (dF - I)) F_n at s = 1/2 is
 * sym((dF - I) ((I + dF) / 2)^-1) per unit time, and the work is
 * (V_n sigma_n + V sigma) / 2 : that (plane strain: zz does no work).
 * Kinematics "small": the increment sym(dF - I) itself. */
double mpgm_point_work(const mpgm_points *P, int p, const double *dF, int small) {
  double H[MPGM_TENSOR], h[MPGM_TENSOR];
  for (int c = 0; c < MPGM_TENSOR; c++) H[c] = dF[c] - (MPGM_DIAG(c) ? 1.0 : 0.0);
  if (small) {
    memcpy(h, H, sizeof h);
  } else { /* H M^-1, M = (I + dF) / 2 */
    double M[MPGM_TENSOR], iM[MPGM_TENSOR];
    for (int c = 0; c < MPGM_TENSOR; c++) M[c] = 0.5 * ((MPGM_DIAG(c) ? 1.0 : 0.0) + dF[c]);
    mpgm_inv(M, mpgm_det(M), iM);
    mpgm_mul(H, iM, h);
  }
  const double *s0 = P->sigma + MPGM_NSTRESS * p, *s1 = P->sigma_t + MPGM_NSTRESS * p;
  const double v0 = P->vol[p], v1 = P->vol_t[p];
  double s[MPGM_NVOIGT];
  for (int c = 0; c < MPGM_NVOIGT; c++) s[c] = 0.5 * (v0 * s0[c] + v1 * s1[c]);
  return mpgm_stress_work(s, h);
}

void mpgm_work_internal(mpgm_problem *pb) {
  const mpgm_points *P = &pb->pts;
  const int small = !pb->fx.geometric;
  double w = 0.0;
  for (int p = 0; p < P->n; p++) w += mpgm_point_work(P, p, P->dF_t + MPGM_TENSOR * p, small);
  pb->work_int += w;
}

double mpgm_kinetic_energy(const mpgm_points *P) {
  double k = 0.0;
  for (int p = 0; p < P->n; p++) {
    const double *v = P->v + MPGM_DIM * p;
    double v2 = v[0] * v[0];
    for (int d = 1; d < MPGM_DIM; d++) v2 += v[d] * v[d];
    k += 0.5 * P->mass[p] * v2;
  }
  return k;
}

void mpgm_problem_energy(const mpgm_problem *pb, mpgm_energy *e) {
  const mpgm_points *P = &pb->pts;
  const mpgm_nodes *nd = &pb->nodes;
  const mpgm_conn *C = &pb->conn;
  memset(e, 0, sizeof *e);
  e->work_int = pb->work_int;
  e->work_ext = pb->work_ext;
  e->kinetic = mpgm_kinetic_energy(P);
  double mom[MPGM_DIM] = {0}, nmom[MPGM_DIM] = {0}; /* in registers, not through e */
  int nodes = pb->step > 0 && C->np == P->n + P->nprobe + P->nsurf;
#if MPGM_DIM == 3
  /* a grid reset (MPM): the step projected m_I = sum_p N_Ip m_p over the
   * same lists, so the nodes' momentum is a loop over the nodes */
  if (nodes && !pb->fe->persistent_nodes && (mpgm_ctx_size(pb->ctx) == 1 || nd->owned)) {
    nodes = 0; /* (many processes: each node on the process that owns it; its mass and
                * velocity are whole there) */
    for (int I = 0; I < nd->n; I++)
      for (int d = 0; d < MPGM_DIM && (!nd->owned || nd->owned[I]); d++)
        nmom[d] += nd->mass[I] * nd->v_new[MPGM_DIM * I + d];
  }
#endif
  for (int p = 0; p < P->n; p++) {
    const double m = P->mass[p];
    for (int d = 0; d < MPGM_DIM; d++) mom[d] += m * P->v[MPGM_DIM * p + d];
    /* the nodes' momentum sum_I m_I v_I with the lumped masses m_I =
     * sum_p N_Ip m_p: summed over the points */
    if (!nodes) continue;
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      for (int d = 0; d < MPGM_DIM; d++) nmom[d] += m * C->N[k] * nd->v_new[MPGM_DIM * I + d];
    }
  }
  for (int d = 0; d < MPGM_DIM; d++) {
    e->momentum[d] += mom[d];
    e->node_momentum[d] += nmom[d];
  }
  if (mpgm_ctx_size(pb->ctx) > 1) { /* the run's sums (each shared node counted once) */
    double v[3 + 2 * MPGM_DIM] = {e->kinetic, e->work_int, e->work_ext};
    memcpy(v + 3, e->momentum, sizeof e->momentum);
    memcpy(v + 3 + MPGM_DIM, e->node_momentum, sizeof e->node_momentum);
    if (mpgm_allreduce(pb->ctx, MPGM_REDUCE_SUM, v, 3 + 2 * MPGM_DIM) == 0) {
      e->kinetic = v[0], e->work_int = v[1], e->work_ext = v[2];
      memcpy(e->momentum, v + 3, sizeof e->momentum);
      memcpy(e->node_momentum, v + 3 + MPGM_DIM, sizeof e->node_momentum);
    }
  }
  if (pb->step == 0) memcpy(e->node_momentum, e->momentum, sizeof e->momentum);
  e->total = e->kinetic + e->work_int - e->work_ext;
}

/* Explicit runs only (core/run.c): every force the explicit schemes apply
 * is counted (the stresses in work_int, gravity and a manufactured body
 * force in work_ext; fixed components, damping and the transfers between
 * points and grid only take energy out; the schemes take no contact and no
 * moving supports), so the total can only grow by what time stepping
 * adds: slowly on a stable step, by a factor every step above the
 * stability limit. The guard's factor MPGM_ENERGY_FACTOR leaves the first
 * far behind (docs/scene-format.md, "Runs are sized and bounded"). */
int mpgm_energy_guard(mpgm_problem *pb) {
  /* on many processes each holds its points' part: the run's sums */
  double e[3] = {mpgm_kinetic_energy(&pb->pts), pb->work_int, pb->work_ext};
  MPGM_CALL(mpgm_allreduce(pb->ctx, MPGM_REDUCE_SUM, e, 3));
  const double kin = e[0], work_int = e[1], work_ext = e[2];
  pb->work_ext_max = fmax(pb->work_ext_max, fabs(work_ext));
  const double total = kin + work_int - work_ext;
  const double scale = fmax(fmax(pb->energy0, pb->work_ext_max), pb->energy_floor);
  if (!(total - pb->energy0 > MPGM_ENERGY_FACTOR * scale)) return 0;
  MPGM_ERROR(pb->ctx, MPGM_ERR_DIVERGED, "diverged: the energy grew from %.6g J to %.6g J "
             "(kinetic %.6g J, work of the stresses %.6g J, of gravity and body forces %.6g J), "
             "more than %g times the largest of the start energy, the work done and the floor "
             "(%.6g J), with no work to account for it: an unstable step (a smaller time.dt, "
             "or none: steps from time.cfl)", pb->energy0, total, kin, work_int,
             work_ext, MPGM_ENERGY_FACTOR, scale);
}
