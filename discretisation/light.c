/* light.c -- the light-node rule (mesh.min_node_mass; docs/theory.md): a
 * node that carries less than a fraction of the heaviest node's mass is
 * supported by a sliver of material; its stiffness and mass are nearly
 * singular (a cut cell, a node at the edge of a cloud) and Newton stalls.
 * It takes no part in the step: MPM gives it no equation, GMM parks it
 * (fixed, carried along by its neighbours). The points that used it keep
 * a partition of unity by Shepard renormalisation over their other nodes. */
#include <math.h>
#include <string.h>

#include "mpgm_discretisation.h"


#if MPGM_DIM == 3
typedef struct {
  const mpgm_conn *c;
  const double *pmass;
} light_job;

/* the mass N_Ip m_p that entry k (point p) brings to its node */
static void light_entry(const void *job, int p, int k, double *m) {
  const light_job *j = job;
  m[0] = j->c->N[k] * j->pmass[p];
}
#endif

int mpgm_light_nodes(const mpgm_conn *c, int np, const double *pmass, int nnode,
                     const unsigned char *eligible, double min_node_mass, double *mass,
                     unsigned char *light) {
  memset(mass, 0, sizeof(double) * (size_t)nnode);
#if MPGM_DIM == 3 /* by runs of points (mpgm_run_scatter) */
  const light_job j = {c, pmass};
  mpgm_run_scatter(c, np, 1, light_entry, &j, mass);
#else
  for (int p = 0; p < np; p++)
    for (int k = c->ptr[p]; k < c->ptr[p + 1]; k++) mass[c->node[k]] += c->N[k] * pmass[p];
#endif
  double mmax = 0.0;
  for (int i = 0; i < nnode; i++) mmax = fmax(mmax, mass[i]);
  const double cut = min_node_mass * mmax;
  int n = 0;
  for (int i = 0; i < nnode; i++) {
    if (eligible && !eligible[i]) {
      light[i] = 0;
      continue;
    }
    light[i] = light[i] || !(mass[i] > cut);
    n += light[i];
  }
  return n;
}

/* What point p is, for messages. */
static const char *kind_of(const mpgm_points *P, int p) {
  return p < P->n ? "point" : p < P->n + P->nprobe ? "probe" : "surface point";
}

int mpgm_light_drop(mpgm_ctx *ctx, mpgm_conn *c, int m, const unsigned char *light,
                    const mpgm_points *P, mpgm_cpoints *cp, long step, double min_node_mass) {
  const int first_surface = P->n + P->nprobe;
  /* nothing to drop (the common case: only the empty nodes are light,
   * and no list holds one) when no surface point may lose its lists */
  if (m <= first_surface) {
    int any = 0;
    for (int p = 0; p < m && !any; p++) {
      if (p < c->rn && c->rc[p]) continue; /* the list of p - 1 again */
      for (int k = c->ptr[p]; k < c->ptr[p + 1] && !any; k++) any = light[c->node[k]];
    }
    if (!any) return 0;
  }
  c->rn = 0; /* the lists change */
  int w = 0;
  for (int p = 0; p < m; p++) {
    const int k0 = c->ptr[p], k1 = c->ptr[p + 1];
    c->ptr[p] = w;
    const int surface = p >= first_surface;
    /* a surface point not enforced in this step has no functions */
    if (surface && mpgm_cpoints_unenforced(cp, p - first_surface)) continue;
    /* Shepard's sums: of N and of grad N over the nodes kept */
    double S = 0, Sg[MPGM_DIM] = {0};
    int lost = 0;
    for (int k = k0; k < k1; k++) {
      if (light[c->node[k]]) {
        lost = 1;
        continue;
      }
      S += c->N[k];
      for (int d = 0; d < MPGM_DIM; d++) Sg[d] += c->dN[MPGM_DIM * k + d];
    }
    if (lost && !(S > 1e-12)) {
      /* a surface point among light nodes only: not enforced this step;
       * a probe: no functions (both are carried by mpgm_tracers_carry) */
      if (surface) mpgm_cpoints_unenforce(cp, p - first_surface);
      if (p >= P->n) continue;
      char at[MPGM_POINT_STR];
      MPGM_ERROR(ctx, MPGM_ERR_SHAPE, "step %ld: %s %d at %s lost every node to "
                 "mesh.min_node_mass = %g", step + 1, kind_of(P, p), p < P->n ? P->id[p] : p - P->n,
                 mpgm_point_str(P->x + MPGM_DIM * p, at), min_node_mass);
    }
    for (int k = k0; k < k1; k++) {
      if (light[c->node[k]]) continue;
      const double Nk = c->N[k];
      double g[MPGM_DIM];
      memcpy(g, c->dN + MPGM_DIM * k, sizeof g);
      c->node[w] = c->node[k];
      if (lost) { /* Shepard: sum N = 1 and sum grad N = 0 still hold */
        c->N[w] = Nk / S;
        for (int d = 0; d < MPGM_DIM; d++) c->dN[MPGM_DIM * w + d] = g[d] / S - Nk * Sg[d] / (S * S);
      } else {
        c->N[w] = Nk;
        memcpy(c->dN + MPGM_DIM * w, g, sizeof g);
      }
      w++;
    }
  }
  c->ptr[m] = w;
  return 0;
}
