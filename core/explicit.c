/* explicit.c -- the explicit schemes of the time-integrator family
 * (time.analysis "explicit", time.scheme; docs/theory.md, "Explicit
 * schemes"): on the nodes a front end projected for the step (lumped mass
 * m_I, velocity v_I and acceleration a_I of the points, mpm.c), a step is
 * one stress update, one nodal force and one update of the points. No
 * matrix is assembled or factorised and no Newton iteration runs.
 *
 *   fe   update stress first, momentum form (Molinos et al. 2021, eqs 22-23)
 *   usl  update stress last, symplectic Euler (Tran et al. 2019, eqs 27-40)
 *   npc  Newmark predictor-corrector (Molinos et al. 2021, Algorithm 1,
 *        eqs 30-33; the points' positions as Newmark's beta = 0, or by
 *        their eq 34: time.npc_position)
 *
 * Every scheme ends with the same update of the points (move_points):
 * a_p = sum_I N_Ip A_I, v_p += dt a_p, x_p += sum_I N_Ip (dt V_I +
 * c dt^2 A_I), with A_I = f_I / m_I and V_I, c the scheme's. Fixed
 * components have V = A = 0; a node without mass gets no update. With
 * time.kinetic_damping the points then stop whenever their kinetic energy
 * has passed a peak (kinetic_damping). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core_impl.h"


typedef struct explicit_data {
  double *f;   /**< MPGM_DIM per node: f_ext - f_int [N]               */
  double *mod; /**< per material: P-wave modulus lambda + 2 mu [Pa]    */
  int warned;  /**< a fixed time.dt above the CFL limit was allowed and
                    reported (time.allow_unstable_dt)                   */
  double *wp;  /**< 2 per point: the work of gravity, of a body force    */
  int nwp;     /**< points wp has room for                               */
  int work_done; /**< the step's stress work was summed in the fused pass */
  double work;   /**< that sum, added to pb->work_int at the commit        */
} explicit_data;

static void explicit_destroy(void *self) {
  explicit_data *d = self;
  if (!d) return;
  free(d->f);
  free(d->mod);
  free(d->wp);
  free(d);
}

static int explicit_create(mpgm_problem *pb, void **self) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *s = pb->scene;
  explicit_data *d;
  MPGM_ALLOC(ctx, d, 1);
  *self = d;
  MPGM_ALLOC(ctx, d->f, MPGM_DIM * (size_t)pb->nodes.cap + 1);
  MPGM_ALLOC(ctx, d->mod, s->nmat + 1);
  for (int i = 0; i < s->nmat; i++) {
    const mpgm_material *m = &s->mats[i];
    const double E = mpgm_material_param(m, "E"), nu = mpgm_material_param(m, "nu");
    MPGM_CHECK(ctx, isfinite(E) && isfinite(nu), MPGM_ERR_INPUT,
               "%s: materials.%s: type \"%s\" has no E and nu, from which an explicit run takes "
               "the wave speed of its CFL condition", s->file, m->name, m->type->name);
    double lam, mu;
    mpgm_lame(E, nu, &lam, &mu);
    d->mod[i] = lam + 2.0 * mu;
  }
  /* the energy balance's start and floor (energy.c, mpgm_energy_guard):
   * the most gravity can do on the whole mass within the domain, M sum_d
   * |g_d| (max_d - min_d), which also covers the step by which the
   * schemes' work lags the kinetic energy; and 1e-12 M c^2 */
  const mpgm_points *P = &pb->pts;
  double mass = 0.0, c2max = 0.0, reach = 0.0;
  for (int p = 0; p < P->n; p++) {
    mass += P->mass[p];
    c2max = fmax(c2max, d->mod[P->mat[p]] * P->vol[p] / P->mass[p]);
  }
  double sums[2] = {mass, mpgm_kinetic_energy(P)}; /* over every process of the run */
  MPGM_CALL(mpgm_allreduce(ctx, MPGM_REDUCE_SUM, sums, 2));
  MPGM_CALL(mpgm_allreduce(ctx, MPGM_REDUCE_MAX, &c2max, 1));
  mass = sums[0];
  for (int k = 0; k < MPGM_DIM; k++) reach += fabs(s->gravity[k]) * (s->dom_max[k] - s->dom_min[k]);
  pb->energy0 = sums[1];
  pb->energy_floor = fmax(mass * reach, 1e-12 * mass * c2max);
  return 0;
}

/* The fastest wave or point of pb's present state, max(max_p |v_p|,
 * max_p c_p), c_p = sqrt((lambda + 2 mu) / rho_p) with the point's current
 * density [m/s]. */
static double max_speed(const explicit_data *d, const mpgm_problem *pb) {
  const mpgm_points *P = &pb->pts;
  /* maxima by comparisons, which pass over a NaN as fmax does (and are
   * not library calls); in 3-D the largest |v|^2, whose root is the
   * largest |v| (sqrt is monotone and correctly rounded) */
  double vmax = 0.0, c2max = 0.0;
  for (int p = 0; p < P->n; p++) {
    const double *v = P->v + MPGM_DIM * p;
#if MPGM_DIM == 2
    const double s = hypot(v[0], v[1]);
#else
    const double s = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
#endif
    const double c2 = d->mod[P->mat[p]] * P->vol[p] / P->mass[p];
    if (s > vmax) vmax = s;
    if (c2 > c2max) c2max = c2;
  }
  double both[2] = {vmax, c2max}; /* the fastest of every process's points */
  if (mpgm_allreduce(pb->ctx, MPGM_REDUCE_MAX, both, 2)) return NAN;
  vmax = both[0];
  c2max = both[1];
#if MPGM_DIM == 3
  vmax = sqrt(vmax);
#endif
  return fmax(vmax, sqrt(c2max));
}

/* CFL condition (Molinos et al. 2021, eq 43): dt = cfl h / max speed
 * (max_speed). A fixed time.dt when the scene gives one, checked before
 * every step against h / max speed, above which no explicit scheme is
 * stable: the run fails there (NAN, the reason in the context), or with
 * time.allow_unstable_dt a warning, once, and the step is taken. */
static double explicit_dt_limit(void *self, const mpgm_problem *pb) {
  explicit_data *d = self;
  const mpgm_scene *s = pb->scene;
  if (s->dt > 0.0 && d->warned) return INFINITY; /* allowed, and said so */
  const double speed = max_speed(d, pb);
  if (isnan(speed) && pb->ctx->code) return NAN; /* the reduction failed: said in the context */
  if (s->dt > 0.0) {
    if (!(speed > 0.0) || !(s->dt > s->h / speed)) return INFINITY;
    if (!s->allow_unstable_dt) {
      mpgm_err_set(pb->ctx, MPGM_ERR_DIVERGED, __FILE__, __LINE__, "time.dt = %g s is %.4g times "
                   "the stability limit h / c = %g s (c = %g m/s, the fastest wave or point "
                   "after step %ld), above which explicit schemes are unstable: a time.dt below "
                   "%g s, or none (steps from time.cfl); time.allow_unstable_dt true takes it "
                   "anyway", s->dt, s->dt * speed / s->h, s->h / speed, speed, pb->step,
                   s->h / speed);
      return NAN;
    }
    d->warned = 1;
    mpgm_log(pb->ctx, MPGM_LOG_WARNING, "time.dt = %g s is %.4g times h / c = %g s (c = %g m/s, "
             "the fastest wave or point at step %ld): above it explicit schemes are unstable; "
             "taken, as time.allow_unstable_dt asks", s->dt, s->dt * speed / s->h, s->h / speed,
             speed, pb->step + 1);
    return INFINITY;
  }
  return speed > 0.0 ? s->cfl * s->h / speed : INFINITY;
}

/* Zero the fixed components of a nodal vector (MPGM_DIM per node). */
static void zero_fixed(const mpgm_nodes *nd, double *w) {
  for (int i = 0; i < MPGM_DIM * nd->n; i++)
    if (nd->fix[i]) w[i] = 0.0;
}

/* Kinematics "small": point p's trial volume V (1 + tr(dF - I)), dF its
 * increment. */
static inline void small_volume(mpgm_points *P, int p, const double *dF) {
  double tr = dF[0];
  for (int d = 1; d < MPGM_DIM; d++) tr += dF[(MPGM_DIM + 1) * d];
  P->vol_t[p] = P->vol[p] * (tr - (MPGM_DIM - 1.0));
}

/* The stress of the points after the nodes moved by dt vel: F = (I + dt
 * grad v) F_n (kinematics "small": the strain increment dt sym grad v
 * added to the point's strain, the volume scaled by 1 + tr), the
 * constitutive update (trial arrays of the points). */
static int stress(mpgm_problem *pb, const double *vel) {
  mpgm_nodes *nd = &pb->nodes;
  mpgm_points *P = &pb->pts;
  for (int i = 0; i < MPGM_DIM * nd->n; i++) nd->du[i] = pb->dt * vel[i];
  MPGM_CALL(mpgm_eval_points(pb, 0)); /* no tangent: nothing is assembled */
  if (!pb->fx.geometric)
    for (int p = 0; p < P->n; p++) small_volume(P, p, P->dF_t + MPGM_TENSOR * p);
  return 0;
}

/* Node-range tasks of the explicit loops: MPGM_DIM per node, gathered
 * through the transpose of the lists (the same sums as a loop over the
 * points, any number of threads). */
typedef struct {
  mpgm_problem *pb;
  int ntask;
  const double *sigma, *vol, *b; /* forces: stress, volumes, body force  */
  double grav[MPGM_DIM];         /* forces: gravity at the step's time   */
  double g;                      /* predictor: npc's gamma               */
  double *out;                   /* MPGM_DIM per node                    */
} node_job;

/* The force of entry k (point p) on its node: m_p N g - vol_p sigma_p
 * grad N. */
static inline void force_of(const node_job *j, const mpgm_points *P, const mpgm_conn *C, int p,
                            int k, double f[MPGM_DIM]) {
  const double *sg = j->sigma + MPGM_NSTRESS * p, m = P->mass[p], v = j->vol[p];
  const double N = C->N[k], *a = C->dN + MPGM_DIM * k;
  for (int i = 0; i < MPGM_DIM; i++) {
    const double g = j->grav[i] + (j->b ? j->b[MPGM_DIM * p + i] : 0.0);
    double sa = sg[mpgm_voigt_of[i][0]] * a[0]; /* (sigma grad N)_i */
    for (int l = 1; l < MPGM_DIM; l++) sa += sg[mpgm_voigt_of[i][l]] * a[l];
    f[i] = m * N * g - v * sa;
  }
}

#if MPGM_DIM == 3
/* force_of as an entry function of the run sums (mpgm_run_scatter) */
static void force_entry(const void *job, int p, int k, double *f) {
  const node_job *j = job;
  force_of(j, &j->pb->pts, &j->pb->conn, p, k, f);
}
#endif

/* f_I = sum_p (m_p N_Ip g - vol_p sigma_p grad N_Ip) at task t's nodes. */
static void force_task(void *arg, int t, int tid) {
  (void)tid;
  const node_job *j = arg;
  const mpgm_conn *C = &j->pb->conn;
  const int n = j->pb->nodes.n;
  const int i0 = mpgm_task_begin(n, j->ntask, t), i1 = mpgm_task_begin(n, j->ntask, t + 1);
#if MPGM_DIM == 3
  for (int I = i0; I < i1; I++) mpgm_run_gather(C, I, MPGM_DIM, force_entry, j, j->out + MPGM_DIM * I);
#else
  const mpgm_points *P = &j->pb->pts;
  for (int I = i0; I < i1; I++) {
    double sum[MPGM_DIM] = {0}, f[MPGM_DIM];
    for (int e = C->tptr[I]; e < C->tptr[I + 1]; e++) {
      force_of(j, P, C, C->tp[e], C->tk[e], f);
      for (int c = 0; c < MPGM_DIM; c++) sum[c] += f[c];
    }
    for (int c = 0; c < MPGM_DIM; c++) j->out[MPGM_DIM * I + c] = sum[c];
  }
#endif
}

/* The same sums by one loop over the points (mpgm_conn_gathers). */
static void force_scatter(const node_job *j) {
  const mpgm_points *P = &j->pb->pts;
  const mpgm_conn *C = &j->pb->conn;
  memset(j->out, 0, sizeof(double) * MPGM_DIM * (size_t)j->pb->nodes.n);
#if MPGM_DIM == 3
  mpgm_run_scatter(C, P->n, MPGM_DIM, force_entry, j, j->out);
  return;
#endif
  for (int p = 0; p < P->n; p++)
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      double f[MPGM_DIM];
      force_of(j, P, C, p, k, f);
      for (int c = 0; c < MPGM_DIM; c++) j->out[MPGM_DIM * C->node[k] + c] += f[c];
    }
}

/* Whether the nodal sums are gathered (mpgm_conn_gathers); then the
 * transpose of the step's lists (built by the front end, or here). */
static int gathers(mpgm_problem *pb, int *yes) {
#if MPGM_DIM == 3 /* the runs of the run sums (known after the projection) */
  MPGM_CALL(mpgm_conn_runs(pb->ctx, &pb->conn, pb->pts.n));
#endif
  *yes = mpgm_conn_gathers(pb->pool, &pb->conn, pb->pts.n);
  if (!*yes || (pb->conn.tn == pb->nodes.n && pb->conn.tn > 0)) return 0;
  return mpgm_conn_transpose(pb->ctx, &pb->conn, pb->pts.n, pb->nodes.n);
}

/* The job of the nodal force sums (force_task, force_scatter, the fused
 * pass) of the stress sigma on the volumes vol at time t. */
static node_job force_job(mpgm_problem *pb, explicit_data *d, const double *sigma,
                          const double *vol, double t) {
  const double gf = mpgm_gravity_factor(pb, t);
  node_job j = {.pb = pb, .ntask = mpgm_ntask(pb->nodes.n, 256), .sigma = sigma, .vol = vol,
                .b = MPGM_MMS_FORCES(pb, t),
                .out = d->f};
  for (int c = 0; c < MPGM_DIM; c++) j.grav[c] = gf * pb->scene->gravity[c];
  return j;
}

/* Damping and A = f / m of the nodal sums f (f takes the damping). */
static int forces_finish(mpgm_problem *pb, double *f, const double *vel, double *A) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_nodes *nd = &pb->nodes;
  MPGM_CALL(mpgm_node_sums(pb, MPGM_DIM, f)); /* on many processes: the shared nodes' whole sums */
  mpgm_timer_start(ctx, MPGM_T_ASSEMBLY);
  int err = 0;
  const double alpha = pb->scene->local_damping;
  if (alpha > 0.0)
    for (int i = 0; i < MPGM_DIM * nd->n; i++)
      if (vel[i] != 0.0) f[i] -= alpha * fabs(f[i]) * (vel[i] > 0.0 ? 1.0 : -1.0);
  for (int i = 0; i < MPGM_DIM * nd->n; i++) {
    const double m = nd->mass[i / MPGM_DIM];
    A[i] = nd->fix[i] || !(m > 0.0) ? 0.0 : f[i] / m;
    if (!isfinite(A[i]) && !err) {
      char at[MPGM_POINT_STR];
      err = mpgm_err_set(ctx, MPGM_ERR_NAN, __FILE__, __LINE__, "step %ld: the acceleration of node "
                         "%d at %s is not finite (nodal mass %g kg)", pb->step + 1, i / MPGM_DIM,
                         mpgm_point_str(nd->x + MPGM_DIM * (i / MPGM_DIM), at), m);
      break;
    }
  }
  mpgm_timer_stop(ctx, MPGM_T_ASSEMBLY);
  return mpgm_agree(ctx, err); /* on many processes: the step fails on every one */
}

/* Nodal force f = f_ext - f_int of the stress sigma on the volumes vol
 * (either the committed or the trial arrays of the points) with gravity
 * at time t (its ramp): f_I = sum_p (m_p N_Ip g - vol_p sigma_p grad N_Ip);
 * with time.local_damping alpha, Cundall's local damping f -= alpha |f|
 * sign(vel) per component, vel the nodal velocity the scheme has at this
 * point of the step; the nodal acceleration A = f / m (0 at fixed
 * components and massless nodes). */
static int nodal_forces(mpgm_problem *pb, explicit_data *d, const double *sigma, const double *vol,
                        double t, const double *vel, double *A) {
  mpgm_ctx *ctx = pb->ctx;
  int gather;
  MPGM_CALL(gathers(pb, &gather));
  mpgm_timer_start(ctx, MPGM_T_ASSEMBLY);
  node_job j = force_job(pb, d, sigma, vol, t);
  if (gather) mpgm_pool_run(pb->pool, j.ntask, force_task, &j);
  else force_scatter(&j);
  mpgm_timer_stop(ctx, MPGM_T_ASSEMBLY);
  return forces_finish(pb, d->f, vel, A);
}

/* The stress from the nodal velocity vel and its nodal force at time t
 * (stress, then nodal_forces of the trial arrays). 3-D on one thread: in
 * one pass over the points, each point's force added to the nodes' run
 * sums right after its update, while its lists are in cache (the same
 * sums, the same bits; the time of the sums counts as the material's). */
#if MPGM_DIM == 3
typedef struct {
  node_job j;
  mpgm_run_acc r;
  double w; /* the stress work of the points so far (mpgm_work_internal's sum) */
} fused_job;

static void stress_force_point(void *arg, int p, const double *dF) {
  fused_job *fj = arg;
  mpgm_problem *pb = fj->j.pb;
  mpgm_points *P = &pb->pts;
  if (!pb->fx.geometric) small_volume(P, p, dF);
  fj->w += mpgm_point_work(P, p, dF, !pb->fx.geometric);
  mpgm_run_add(&pb->conn, &fj->r, P->n, p, MPGM_DIM, force_entry, &fj->j, fj->j.out);
}
#endif

static int stress_forces(mpgm_problem *pb, explicit_data *d, const double *vel, double t,
                         const double *damp_vel, double *A) {
#if MPGM_DIM == 3
  int gather;
  MPGM_CALL(gathers(pb, &gather));
  /* (CPLS keeps the step's dF_t for its velocity gradient: not fused) */
  if (!gather && mpgm_pool_size(pb->pool) == 1 && !pb->scene->shape->velocity_ls) {
    mpgm_nodes *nd = &pb->nodes;
    for (int i = 0; i < MPGM_DIM * nd->n; i++) nd->du[i] = pb->dt * vel[i];
    fused_job fj = {.j = force_job(pb, d, pb->pts.sigma_t, pb->pts.vol_t, t)};
    memset(d->f, 0, sizeof(double) * MPGM_DIM * (size_t)nd->n);
    MPGM_CALL(mpgm_agree(pb->ctx, mpgm_eval_points_each(pb, stress_force_point, &fj)));
    mpgm_run_end(&pb->conn, &fj.r, MPGM_DIM, d->f);
    d->work = fj.w; /* commit_stress need not sum it again */
    d->work_done = 1;
    return forces_finish(pb, d->f, damp_vel, A);
  }
#endif
  MPGM_CALL(mpgm_agree(pb->ctx, stress(pb, vel))); /* a point failed on some process */
  return nodal_forces(pb, d, pb->pts.sigma_t, pb->pts.vol_t, t, damp_vel, A);
}

/* The trial array (w per point) becomes the committed one and the
 * committed the next step's trial: every material point's F, sigma and vol
 * were written by this step's update (mpgm_eval_points, small_volume),
 * and the points past n (probes, surface points), which have no trial,
 * keep theirs. No copy of the n material points. */
static void commit_swap(double **committed, double **trial, int w, size_t n, size_t m) {
  memcpy(*trial + (size_t)w * n, *committed + (size_t)w * n, sizeof(double) * (size_t)w * (m - n));
  double *old = *committed;
  *committed = *trial;
  *trial = old;
}

/* Commit the stress update of the step (trial -> committed arrays); CPLS
 * keeps the step's velocity gradient L = (dF - I) / dt for its corners.
 * The state is copied: a material may leave slots of the trial state
 * untouched. */
static void commit_stress(mpgm_problem *pb, explicit_data *d) {
  mpgm_points *P = &pb->pts;
  if (d->work_done) pb->work_int += d->work;
  else mpgm_work_internal(pb);
  d->work_done = 0;
  if (pb->scene->shape->velocity_ls)
    for (int p = 0; p < P->n; p++)
      for (int i = 0; i < MPGM_TENSOR; i++)
        P->L[MPGM_TENSOR * p + i] = (P->dF_t[MPGM_TENSOR * p + i] - MPGM_DIAG(i)) / pb->dt;
  const size_t n = (size_t)P->n, m = n + (size_t)P->nprobe + (size_t)P->nsurf;
  commit_swap(&P->F, &P->F_t, MPGM_TENSOR, n, m);
  commit_swap(&P->sigma, &P->sigma_t, MPGM_NSTRESS, n, m);
  commit_swap(&P->vol, &P->vol_t, 1, n, m);
  if (P->nstate) memcpy(P->state, P->state_t, sizeof(double) * (size_t)P->nstate * P->n);
}

typedef struct {
  mpgm_problem *pb;
  int ntask, m;
  const double *V, *A, *b;
  double c2, g[MPGM_DIM];
  double *wp; /* per material point: the work of gravity, of b */
} move_job;

/* Task t's points: a_p = sum N A, v_p += dt a_p, x_p += sum N (dt V + c
 * dt^2 A), and the work of the body forces on that move. */
static void move_task(void *arg, int t, int tid) {
  (void)tid;
  const move_job *j = arg;
  mpgm_points *P = &j->pb->pts;
  const mpgm_conn *C = &j->pb->conn;
  const double dt = j->pb->dt, c2 = j->c2, *V = j->V, *A = j->A;
  const int p0 = mpgm_task_begin(j->m, j->ntask, t), p1 = mpgm_task_begin(j->m, j->ntask, t + 1);
  for (int p = p0; p < p1; p++) {
    double a[MPGM_DIM] = {0}, w[MPGM_DIM] = {0};
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      const double N = C->N[k];
      for (int q = 0; q < MPGM_DIM; q++) {
        a[q] += N * A[MPGM_DIM * I + q];
        w[q] += N * (dt * V[MPGM_DIM * I + q] + c2 * A[MPGM_DIM * I + q]);
      }
    }
    for (int q = 0; q < MPGM_DIM; q++) {
      P->a[MPGM_DIM * p + q] = a[q];
      P->v[MPGM_DIM * p + q] += dt * a[q];
      P->x[MPGM_DIM * p + q] += w[q];
      P->u[MPGM_DIM * p + q] += w[q];
    }
    if (p >= P->n) continue;
    double gw = j->g[0] * w[0], bw = j->b ? j->b[MPGM_DIM * p] * w[0] : 0.0;
    for (int q = 1; q < MPGM_DIM; q++) {
      gw += j->g[q] * w[q];
      if (j->b) bw += j->b[MPGM_DIM * p + q] * w[q];
    }
    j->wp[2 * p] = P->mass[p] * gw;
    if (j->b) j->wp[2 * p + 1] = P->mass[p] * bw;
  }
}

/* Kinetic damping (time.kinetic_damping; dynamic relaxation): when the
 * kinetic energy of the material points, sum_p m_p |v_p|^2 / 2, has
 * fallen since the last step, it has just passed a peak, where a body
 * swinging in its slowest mode passes its rest state; every point's (and
 * tracer's) velocity and acceleration are then set to zero, and the next
 * swing starts from there with the energy still out of balance. The
 * energy it takes out shows as a loss of the total. */
static int kinetic_damping(mpgm_problem *pb) {
  mpgm_points *P = &pb->pts;
  double ke = mpgm_kinetic_energy(P);
  MPGM_CALL(mpgm_allreduce(pb->ctx, MPGM_REDUCE_SUM, &ke, 1)); /* every process's points */
  if (ke < pb->ke_last) {
    const size_t m = (size_t)(P->n + P->nprobe + P->nsurf);
    memset(P->v, 0, sizeof(double) * MPGM_DIM * m);
    memset(P->a, 0, sizeof(double) * MPGM_DIM * m);
    mpgm_count(pb->ctx, MPGM_C_KINETIC_RESETS, 1);
    ke = 0.0;
  }
  pb->ke_last = ke;
  return 0;
}

/* The points (material points and tracers) from the nodes, on the pool's
 * threads: a_p = sum N A, v_p += dt a_p, x_p += sum N (dt V + c dt^2 A);
 * the work of gravity and of a manufactured body force at their values in
 * the middle of the step, added up in the order of the points. */
static int move_points(mpgm_problem *pb, explicit_data *d, const double *V, const double *A,
                       double c) {
  mpgm_ctx *ctx = pb->ctx;
  mpgm_points *P = &pb->pts;
  if (P->n > d->nwp) {
    free(d->wp);
    d->nwp = 0;
    MPGM_ALLOC(ctx, d->wp, 2 * (size_t)P->n);
    d->nwp = P->n;
  }
  mpgm_timer_start(ctx, MPGM_T_UPDATE);
  const double dt = pb->dt, gf = mpgm_gravity_factor(pb, pb->t + 0.5 * dt);
  const int m = P->n + P->nprobe + P->nsurf;
  move_job j = {.pb = pb, .ntask = mpgm_ntask(m, 512), .m = m, .V = V, .A = A,
                .b = MPGM_MMS_FORCES(pb, pb->t + 0.5 * dt),
                .c2 = c * dt * dt, .wp = d->wp};
  for (int q = 0; q < MPGM_DIM; q++) j.g[q] = gf * pb->scene->gravity[q];
  mpgm_pool_run(pb->pool, j.ntask, move_task, &j);
  double wext = 0.0;
  for (int p = 0; p < P->n; p++) {
    wext += d->wp[2 * p];
    if (j.b) wext += d->wp[2 * p + 1];
  }
  pb->work_ext += wext;
  const int err = pb->scene->kinetic_damping ? kinetic_damping(pb) : 0;
  mpgm_timer_stop(ctx, MPGM_T_UPDATE);
  return err;
}

/* fe: the stress from the projected velocity v_I (update stress first),
 * the force of that stress, the momentum p_I + dt f_I: V = v + dt A. */
static int fe_step(void *self, mpgm_problem *pb) {
  mpgm_nodes *nd = &pb->nodes;
  double *V = nd->v_new, *A = nd->a_new;
  zero_fixed(nd, nd->v);
  MPGM_CALL(stress_forces(pb, self, nd->v, pb->t + pb->dt, nd->v, A));
  for (int i = 0; i < MPGM_DIM * nd->n; i++) V[i] = nd->v[i] + pb->dt * A[i];
  commit_stress(pb, self);
  MPGM_CALL(move_points(pb, self, V, A, 0.0));
  return 0;
}

/* usl: the force of the stress of the last step, the new nodal velocity
 * V = v + dt A, then the stress from V (update stress last). */
static int usl_step(void *self, mpgm_problem *pb) {
  mpgm_nodes *nd = &pb->nodes;
  double *V = nd->v_new, *A = nd->a_new;
  MPGM_CALL(nodal_forces(pb, self, pb->pts.sigma, pb->pts.vol, pb->t, nd->v, A));
  zero_fixed(nd, nd->v);
  for (int i = 0; i < MPGM_DIM * nd->n; i++) V[i] = nd->v[i] + pb->dt * A[i];
  MPGM_CALL(mpgm_agree(pb->ctx, stress(pb, V)));
  commit_stress(pb, self);
  MPGM_CALL(move_points(pb, self, V, A, 0.0));
  return 0;
}

/* The momentum of npc's predictor that entry k (point p) brings to its
 * node: N m_p (v_p + (1 - gamma) dt a_p). */
static inline void predictor_of(const node_job *j, const mpgm_points *P, const mpgm_conn *C, int p,
                                int k, double q[MPGM_DIM]) {
  const double w = C->N[k] * P->mass[p], dt = j->pb->dt;
  for (int c = 0; c < MPGM_DIM; c++)
    q[c] = w * (P->v[MPGM_DIM * p + c] + (1.0 - j->g) * dt * P->a[MPGM_DIM * p + c]);
}

/* v_pred = sum (predictor_of) / m_I at node I (0 at fixed components and
 * massless nodes). */
static inline void predictor_at(const node_job *j, int I) {
  const mpgm_nodes *nd = &j->pb->nodes;
  const double m = nd->mass[I];
  for (int c = 0; c < MPGM_DIM; c++) {
    double *V = j->out + MPGM_DIM * I + c;
    *V = nd->fix[MPGM_DIM * I + c] || !(m > 0.0) ? 0.0 : *V / m;
  }
}

#if MPGM_DIM == 3
/* predictor_of as an entry function of the run sums */
static void predictor_entry(const void *job, int p, int k, double *q) {
  const node_job *j = job;
  predictor_of(j, &j->pb->pts, &j->pb->conn, p, k, q);
}
#endif

/* npc's predictor at task t's nodes, gathered through the transpose. */
static void predictor_task(void *arg, int t, int tid) {
  (void)tid;
  const node_job *j = arg;
  const mpgm_points *P = &j->pb->pts;
  const mpgm_conn *C = &j->pb->conn;
  const int n = j->pb->nodes.n;
  const int i0 = mpgm_task_begin(n, j->ntask, t), i1 = mpgm_task_begin(n, j->ntask, t + 1);
  for (int I = i0; I < i1; I++) {
#if MPGM_DIM == 3
    (void)P;
    mpgm_run_gather(C, I, MPGM_DIM, predictor_entry, j, j->out + MPGM_DIM * I);
    predictor_at(j, I);
    continue;
#endif
    double sum[MPGM_DIM] = {0}, q[MPGM_DIM];
    for (int e = C->tptr[I]; e < C->tptr[I + 1]; e++) {
      predictor_of(j, P, C, C->tp[e], C->tk[e], q);
      for (int c = 0; c < MPGM_DIM; c++) sum[c] += q[c];
    }
    for (int c = 0; c < MPGM_DIM; c++) j->out[MPGM_DIM * I + c] = sum[c];
    predictor_at(j, I);
  }
}

/* The same by one loop over the points (mpgm_conn_gathers). */
static void predictor_scatter(const node_job *j) {
  const mpgm_points *P = &j->pb->pts;
  const mpgm_conn *C = &j->pb->conn;
  const int n = j->pb->nodes.n;
  memset(j->out, 0, sizeof(double) * MPGM_DIM * (size_t)n);
#if MPGM_DIM == 3
  mpgm_run_scatter(C, P->n, MPGM_DIM, predictor_entry, j, j->out);
  for (int I = 0; I < n; I++) predictor_at(j, I);
  return;
#endif
  for (int p = 0; p < P->n; p++)
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      double q[MPGM_DIM];
      predictor_of(j, P, C, p, k, q);
      for (int c = 0; c < MPGM_DIM; c++) j->out[MPGM_DIM * C->node[k] + c] += q[c];
    }
  for (int I = 0; I < n; I++) predictor_at(j, I);
}

/* 3-D, and on many processes: the predictor from the step's projection (only the MPM front end
 * takes explicit schemes; its begin_step projected m_I, v_I = q_I / m_I
 * and a_I = f_I / m_I over the same lists): v_pred = v_I + (1 - gamma)
 * dt a_I is the sum of predictor_of over m_I, without a pass over the
 * points. CPLS (its own velocities) keeps the sums. */
static int predictor_projected(const mpgm_problem *pb, double g, double *V) {
  const mpgm_nodes *nd = &pb->nodes;
  if (pb->scene->shape->velocity_ls) return 0;
  const double c = (1.0 - g) * pb->dt;
  for (int I = 0; I < nd->n; I++)
    for (int d = 0; d < MPGM_DIM; d++) {
      const int i = MPGM_DIM * I + d;
      V[i] = nd->fix[i] || !(nd->mass[I] > 0.0) ? 0.0 : nd->v[i] + c * nd->a[i];
    }
  return 1;
}

/* npc: the predictor of eq 30, projected from the points, v_pred =
 * sum_p N m_p (v_p + (1 - gamma) dt a_p) / m_I; the stress from it; the
 * corrector V = v_pred + gamma dt A (eq 31); the points' velocity and
 * acceleration by eqs 32-33, their positions by time.npc_position. */
static int npc_step(void *self, mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  mpgm_nodes *nd = &pb->nodes;
  const double g = pb->scene->scheme.npc_gamma, dt = pb->dt;
  double *V = nd->v_new, *A = nd->a_new;
  int gather;
  MPGM_CALL(gathers(pb, &gather));
  mpgm_timer_start(ctx, MPGM_T_MASS);
  node_job j = {.pb = pb, .ntask = mpgm_ntask(nd->n, 256), .g = g, .out = V};
  /* (on many processes the sums over the points would be partial at the
   * shared nodes: the projection's are whole) */
  const int projected = (MPGM_DIM == 3 || mpgm_ctx_size(ctx) > 1) && predictor_projected(pb, g, V);
  if (projected) { /* V holds it */
  } else if (gather) {
    mpgm_pool_run(pb->pool, j.ntask, predictor_task, &j);
  } else {
    predictor_scatter(&j);
  }
  mpgm_timer_stop(ctx, MPGM_T_MASS);
  MPGM_CALL(stress_forces(pb, self, V, pb->t + pb->dt, V, A));
  for (int i = 0; i < MPGM_DIM * nd->n; i++) V[i] += g * dt * A[i];
  commit_stress(pb, self);
  /* newmark: the points move by what their strain used, dt v_pred =
   * dt V - gamma dt^2 A; eq34: dt V + dt^2 A / 2 (003's eq 34 and code) */
  MPGM_CALL(move_points(pb, self, V, A, pb->scene->scheme.npc_eq34 ? 0.5 : -g));
  return 0;
}

/* npc's keys of "time" (docs/scene-format.md, "Explicit schemes") */
static const char *const position_names[] = {"newmark", "eq34", NULL};
static const mpgm_key_spec npc_keys[] = {
    {.name = "npc_gamma", .type = MPGM_KEY_REAL, .offset = offsetof(mpgm_scheme_params, npc_gamma),
     .def = 0.5, .lo = 0.0, .hi = 1.0, .unit = "-",
     .doc = "gamma of the predictor v + (1 - gamma) dt a and the corrector + gamma dt f / m"},
    {.name = "npc_position", .type = MPGM_KEY_CHOICE, .offset = offsetof(mpgm_scheme_params, npc_eq34),
     .def = 0, .lo = 0, .hi = 1, .choices = position_names, .unit = "-",
     .doc = "how the points move: by dt v_pred (newmark) or by 003's eq 34 (eq34)"},
};

const mpgm_integrator_type mpgm_integrator_npc = {
    .name = "npc",
    .doc = "explicit Newmark predictor-corrector (Molinos et al. 2021, Algorithm 1; "
           "time.npc_gamma)",
    .implicit = 0,
    .create = explicit_create,
    .destroy = explicit_destroy,
    .step = npc_step,
    .dt_limit = explicit_dt_limit,
    .keys = npc_keys,
    .nkeys = sizeof npc_keys / sizeof *npc_keys,
};

const mpgm_integrator_type mpgm_integrator_fe = {
    .name = "fe",
    .doc = "explicit forward Euler, update stress first, momentum form (Molinos et al. 2021, "
           "eqs 22-23)",
    .implicit = 0,
    .create = explicit_create,
    .destroy = explicit_destroy,
    .step = fe_step,
    .dt_limit = explicit_dt_limit,
};

const mpgm_integrator_type mpgm_integrator_usl = {
    .name = "usl",
    .doc = "explicit update stress last with symplectic Euler (Tran et al. 2019, eqs 27-40)",
    .implicit = 0,
    .create = explicit_create,
    .destroy = explicit_destroy,
    .step = usl_step,
    .dt_limit = explicit_dt_limit,
};
