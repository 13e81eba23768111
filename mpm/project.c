/* project.c -- the MPM front end's projection of the points' mass,
 * momentum and acceleration to the nodes of the step (mpm_private.h). */
#include <stdlib.h>
#include <string.h>

#include "mpm_private.h"

typedef struct {
  const mpgm_fe_view *v;
  mpm_data *d;
  int ntask;
} project_job;

#if MPGM_DIM == 3
/* 3-D: the values entry k (point p) brings to its node, by run sums
 * (mpgm_run_scatter): w m_p, w m_p v_p and w m_p a_p, w = N_Ip. */
static void project_entry(const void *job, int p, int k, double *val) {
  const mpgm_fe_view *v = job;
  const mpgm_points *P = v->pts;
  const double wm = v->conn->N[k] * P->mass[p];
  val[0] = wm;
  for (int c = 0; c < MPGM_DIM; c++) {
    val[1 + c] = wm * P->v[MPGM_DIM * p + c];
    val[1 + MPGM_DIM + c] = wm * P->a[MPGM_DIM * p + c];
  }
}

/* Node I's mass, velocity and acceleration from its sums s (project_entry). */
static void project_at(mpgm_nodes *nd, int I, const double *s, int inertia) {
  nd->mass[I] = s[0];
  for (int c = 0; c < MPGM_DIM; c++) {
    nd->v[MPGM_DIM * I + c] = inertia ? s[1 + c] / s[0] : 0.0;
    nd->a[MPGM_DIM * I + c] = inertia ? s[1 + MPGM_DIM + c] / s[0] : 0.0;
  }
}
#endif

/* The projection at the nodes of task t's range, gathered through the
 * transpose (the same sums as a loop over the points). */
static void project_task(void *arg, int t, int tid) {
  (void)tid;
  const project_job *j = arg;
  const mpgm_points *P = j->v->pts;
  mpgm_nodes *nd = j->v->nodes;
  const mpgm_conn *C = j->v->conn;
  const int n = nd->n, inertia = j->v->fx->inertia;
  const int i0 = mpgm_task_begin(n, j->ntask, t), i1 = mpgm_task_begin(n, j->ntask, t + 1);
  for (int I = i0; I < i1; I++) {
#if MPGM_DIM == 3
    double sum[1 + 2 * MPGM_DIM];
    mpgm_run_gather(C, I, 1 + 2 * MPGM_DIM, project_entry, j->v, sum);
    project_at(nd, I, sum, inertia);
    continue;
#endif
    double m = 0.0, q[MPGM_DIM] = {0}, f[MPGM_DIM] = {0};
    for (int e = C->tptr[I]; e < C->tptr[I + 1]; e++) {
      const int p = C->tp[e];
      const double wm = C->N[C->tk[e]] * P->mass[p];
      m += wm;
      if (inertia) /* momentum and inertia force */
        for (int c = 0; c < MPGM_DIM; c++) {
          q[c] += wm * P->v[MPGM_DIM * p + c];
          f[c] += wm * P->a[MPGM_DIM * p + c];
        }
    }
    nd->mass[I] = m;
    for (int c = 0; c < MPGM_DIM; c++) {
      nd->v[MPGM_DIM * I + c] = inertia ? q[c] / m : 0.0;
      nd->a[MPGM_DIM * I + c] = inertia ? f[c] / m : 0.0;
    }
  }
}

/* The projection by one loop over the points (the sums of project_task). */
static int project_scatter(const mpgm_fe_view *v, mpm_data *d) {
  const mpgm_points *P = v->pts;
  mpgm_nodes *nd = v->nodes;
  const mpgm_conn *C = v->conn;
  const int n = nd->n, inertia = v->fx->inertia;
#if MPGM_DIM == 3
  /* the sums, 1 + 2 MPGM_DIM per node, in the front end's scratch */
  const int w = 1 + 2 * MPGM_DIM;
  if (d->nsum < n) {
    free(d->sum);
    d->nsum = 0;
    MPGM_ALLOC(v->ctx, d->sum, (size_t)w * n);
    d->nsum = n;
  }
  memset(d->sum, 0, sizeof(double) * (size_t)w * n);
  MPGM_CALL(mpgm_conn_runs(v->ctx, v->conn, P->n)); /* anew if nodes were dropped */
  mpgm_run_scatter(C, P->n, w, project_entry, v, d->sum);
  for (int I = 0; I < n; I++) project_at(nd, I, d->sum + w * I, inertia);
  return 0;
#else
  (void)d;
#endif
  memset(nd->mass, 0, sizeof(double) * (size_t)n);
  memset(nd->v, 0, sizeof(double) * MPGM_DIM * (size_t)n);
  memset(nd->a, 0, sizeof(double) * MPGM_DIM * (size_t)n);
  for (int p = 0; p < P->n; p++)
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const int I = C->node[k];
      const double wm = C->N[k] * P->mass[p];
      nd->mass[I] += wm;
      if (inertia) /* momentum and inertia force */
        for (int c = 0; c < MPGM_DIM; c++) {
          nd->v[MPGM_DIM * I + c] += wm * P->v[MPGM_DIM * p + c];
          nd->a[MPGM_DIM * I + c] += wm * P->a[MPGM_DIM * p + c];
        }
    }
  for (int i = 0; i < MPGM_DIM * n && inertia; i++) {
    nd->v[i] /= nd->mass[i / MPGM_DIM];
    nd->a[i] /= nd->mass[i / MPGM_DIM];
  }
  return 0;
}

/* On many processes: the projection's sums at the nodes shared with
 * other processes completed (mass, momentum m v and inertia force m a,
 * each process's part from its own points), and the velocity and
 * acceleration at them anew. */
static int project_shared(const mpgm_fe_view *v, mpm_data *d) {
  mpgm_nodes *nd = v->nodes;
  const int n = nd->n;
  double *s = mpgm_mpm_scratch(v->ctx, d, MPM_XW * (size_t)n);
  if (!s) return MPGM_ERR_NOMEM;
  for (int I = 0; I < n; I++) {
    const double m = nd->mass[I];
    s[MPM_XW * I] = m;
    for (int c = 0; c < MPGM_DIM; c++) {
      s[MPM_XW * I + 1 + c] = m * nd->v[MPGM_DIM * I + c];
      s[MPM_XW * I + 1 + MPGM_DIM + c] = m * nd->a[MPGM_DIM * I + c];
    }
  }
  const int err = mpgm_mpm_node_sums(d, v->ctx, MPM_XW, s);
  for (int I = 0; I < n && !err; I++) {
    const double m = s[MPM_XW * I];
    nd->mass[I] = m;
    for (int c = 0; c < MPGM_DIM && v->fx->inertia; c++) {
      nd->v[MPGM_DIM * I + c] = s[MPM_XW * I + 1 + c] / m;
      nd->a[MPGM_DIM * I + c] = s[MPM_XW * I + 1 + MPGM_DIM + c] / m;
    }
  }
  return err;
}

/* Projection (38)-(41) with the final shape functions: mass, momentum and
 * inertia force of the particles onto the nodes (to round-off), the nodal
 * velocity and acceleration (node by node on the pool's threads, or one
 * loop over the points: mpgm_conn_gathers); CPLS replaces the velocity by
 * its least-squares reconstruction (cpls.c). */
int mpgm_mpm_project(const mpgm_fe_view *v, mpm_data *d) {
  const mpgm_points *P = v->pts;
  mpgm_nodes *nd = v->nodes;
  const int n = nd->n;
  if (mpgm_conn_gathers(v->pool, v->conn, P->n)) {
    MPGM_CALL(mpgm_conn_transpose(v->ctx, v->conn, P->n, n));
    project_job j = {v, d, mpgm_ntask(n, 256)};
    mpgm_pool_run(v->pool, j.ntask, project_task, &j);
  } else {
    MPGM_CALL(project_scatter(v, d));
  }
  if (d->pg) MPGM_CALL(project_shared(v, d));
  if (!v->fx->inertia || !v->scene->shape->velocity_ls) return 0;
#if MPM_PLANE_ONLY
  /* CPLS: the velocities by least squares from centres and corners */
  long lower = 0, kept = 0;
  MPGM_CALL(mpgm_cpls_velocities(v->ctx, &d->cpls, &d->g, P, v->scene->shape_par.order, n,
                                 d->lglob, nd->v, &lower, &kept));
  mpgm_count(v->ctx, MPGM_C_CPLS_LINEAR, lower);
  mpgm_count(v->ctx, MPGM_C_CPLS_PROJECTED, kept);
  return 0;
#else
  (void)d;
  MPGM_ERROR(v->ctx, MPGM_ERR_INTERNAL, "CPLS in a 3-D build");
#endif
}
