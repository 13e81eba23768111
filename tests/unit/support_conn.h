/* support_conn.h -- checks of a connectivity's functions shared by the
 * front-end tests in 3-D (test_hexmesh.c, test_mpm3.c): at every point and
 * tracer p < np, the worst |sum N - 1| (partition of unity), |sum N_a X_a -
 * x_p| (linear reproduction) and |sum grad N_a (x) X_a - I| (its gradient),
 * X the nodes' positions (MPGM_DIM each), x the points'. */
#ifndef MPGM_SUPPORT_CONN_H
#define MPGM_SUPPORT_CONN_H

#include <math.h>

#include "mpgm_data.h"

typedef struct conn_errors {
  double unity, linear, gradient;
} conn_errors;

static inline conn_errors conn_check(const mpgm_conn *C, const double *X, const double *x, int np) {
  conn_errors e = {0.0, 0.0, 0.0};
  for (int p = 0; p < np; p++) {
    double s = 0.0, y[MPGM_DIM] = {0}, G[MPGM_TENSOR] = {0};
    for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
      const double *Xa = X + MPGM_DIM * C->node[k];
      s += C->N[k];
      for (int i = 0; i < MPGM_DIM; i++) {
        y[i] += C->N[k] * Xa[i];
        for (int j = 0; j < MPGM_DIM; j++) G[MPGM_DIM * i + j] += C->dN[MPGM_DIM * k + j] * Xa[i];
      }
    }
    e.unity = fmax(e.unity, fabs(s - 1.0));
    for (int i = 0; i < MPGM_DIM; i++) {
      e.linear = fmax(e.linear, fabs(y[i] - x[MPGM_DIM * p + i]));
      for (int j = 0; j < MPGM_DIM; j++) e.gradient = fmax(e.gradient, fabs(G[MPGM_DIM * i + j] - (i == j)));
    }
  }
  return e;
}

/* A neo-Hookean material of density rho (E = 1 MPa, nu = 0.3), set up. */
static inline void neo_hookean_of(mpgm_material *m, double rho) {
  m->type = mpgm_material_type_find("neo_hookean");
  m->density = rho;
  m->param[0] = 1e6, m->param[1] = 0.3;
  char msg[128];
  m->type->setup(m, msg, sizeof msg);
}

#endif
