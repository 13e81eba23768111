/* reference_column_wave.c -- reference kind "column_wave": a laterally
 * confined elastic column of height H, fixed at its base, under gravity
 * applied suddenly at t = 0 from rest and zero stress (1-D waves, constrained
 * modulus M, density rho, wave speed c = sqrt(M / rho)).
 *
 * The displacement u(z, t) solves rho u_tt = M u_zz - rho g with u(0) = 0,
 * u_z(H) = 0. Around the static solution u_s(z) = -(rho g / M)(H z - z^2/2)
 * it oscillates in the modes sin(k_n z), k_n = (2n - 1) pi / (2H), with
 * amplitudes 2 rho g / (M H k_n^3); at the top their sum is a periodic
 * piecewise parabola of period T = 4H/c. The top falls freely,
 * w = -g t^2 / 2, until the wave from the base arrives (t = H/c,
 * w = -rho g H^2 / (2M)), stops at w = -rho g H^2 / M (t = 2H/c), and comes
 * back the same way to 0 at t = T. */
#include <math.h>

#include "mpgm_reference.h"

static const mpgm_param_spec params[] = {
    {"height", "m", NAN, 0.0, INFINITY, 1, 0, "height H of the column (base to top)"},
    {"modulus", "Pa", NAN, 0.0, INFINITY, 1, 0,
     "constrained modulus M = E (1 - nu) / ((1 + nu)(1 - 2 nu))"},
    {"density", "kg/m^3", NAN, 0.0, INFINITY, 1, 0, "density rho"},
    {"g", "m/s^2", 9.81, 0.0, INFINITY, 1, 0, "gravitational acceleration (magnitude)"},
};

/* Top displacement at time t (along the probe's component: gravity points
 * to its negative side). */
static double top_displacement(const mpgm_reference *r, double t) {
  const double H = r->param[0], M = r->param[1], rho = r->param[2], g = r->param[3];
  const double c = sqrt(M / rho), T = 4.0 * H / c;
  double tau = fmod(t, T); /* one period: [0, T) */
  if (tau < 0.0) tau += T;
  /* the period is symmetric about T/2 and each half about H/c's parabola */
  if (tau > 0.5 * T) tau = T - tau;          /* [0, 2H/c] */
  const double t1 = H / c, wmax = rho * g * H * H / M;
  if (tau <= t1) return -0.5 * g * tau * tau; /* free fall until the wave arrives */
  const double s = 2.0 * t1 - tau;            /* mirror: stopping at 2H/c */
  return -(wmax - 0.5 * g * s * s);
}

/* metrics: top_amplitude (the probe's largest minus smallest displacement
 * in the component), top_amplitude_ref = rho g H^2 / M, period_ref = 4H/c,
 * and over rows 1..nrow-1: error_rms, error_max (against w(t)) and
 * relative_error_max = error_max / top_amplitude_ref. */
static int column_wave_metrics(const mpgm_reference *r, int nrow, int ncol, const double *hist,
                               const double *acc, mpgm_metric *out) {
  (void)acc;
  const double H = r->param[0], M = r->param[1], rho = r->param[2], g = r->param[3];
  const int col = mpgm_ref_column(r->probe, r->component);
  const double amp_ref = rho * g * H * H / M;
  double lo = INFINITY, hi = -INFINITY, sum = 0.0, emax = 0.0;
  for (int k = 0; k < nrow; k++) {
    const double *row = hist + (size_t)ncol * k;
    lo = fmin(lo, row[col]);
    hi = fmax(hi, row[col]);
    if (k == 0) continue;
    const double e = fabs(row[col] - top_displacement(r, row[1]));
    sum += e * e;
    emax = fmax(emax, e);
  }
  int n = 0;
  out[n++] = (mpgm_metric){"top_amplitude", hi - lo};
  out[n++] = (mpgm_metric){"top_amplitude_ref", amp_ref};
  out[n++] = (mpgm_metric){"period_ref", 4.0 * H / sqrt(M / rho)};
  if (nrow >= 2) {
    out[n++] = (mpgm_metric){"error_rms", sqrt(sum / (nrow - 1))};
    out[n++] = (mpgm_metric){"error_max", emax};
    out[n++] = (mpgm_metric){"relative_error_max", emax / amp_ref};
  }
  return n;
}

const mpgm_reference_type mpgm_reference_column_wave = {
    .name = "column_wave",
    .doc = "elastic column fixed at its base under gravity applied suddenly: the top oscillates "
           "between 0 and -rho g H^2 / M with period 4 H / c",
    .needs_component = 1,
    .needs_dynamic = 1,
    .nparam = (int)(sizeof params / sizeof params[0]),
    .params = params,
    .metrics = column_wave_metrics,
};
