/* reference_dyka_bar.c -- reference kind "dyka_bar": the bar of Dyka and
 * Ingel (1995) as Molinos et al. (2021, section 3.1, Appendix A) use it.
 * A linear elastic bar 0 <= X <= L (1-D waves, modulus E, density rho,
 * c = sqrt(E / rho)), free at X = 0 and held at X = L, at rest and free of
 * stress but for its quarter X < L/4, which starts with velocity v0.
 *
 * d'Alembert: with the initial velocity f(X) extended to the whole line,
 * even about the free end (sigma = 0 there) and odd about the held end
 * (v = 0 there), so of period 4L,
 *   v(X, t) = (f(X - ct) + f(X + ct)) / 2,
 *   sigma(X, t) = rho c (f(X + ct) - f(X - ct)) / 2   (jump |rho c v0| / 2),
 *   u(X, t) = (Fi(X + ct) - Fi(X - ct)) / (2c),  Fi' = f.
 * Over one period f is v0 on [0, L/4], -v0 on [7L/4, 9L/4] and v0 on
 * [15L/4, 4L], 0 elsewhere: its mean is 0, so Fi is periodic too. The free
 * end moves with v0 until ct = L/4, rests, moves with -v0 from
 * ct = 7L/4 to 9L/4, and so on (period 4L/c).
 *
 * The probe's material coordinate is its initial x (the scene puts the
 * free end at x = 0 and the held end at x = L); so is every point's in the
 * velocity RMS of eq 44, sqrt(mean_p |v_p - v(X_p, t)|^2), kept at the
 * first step that ends at or after t1 and at the end. */
#include <math.h>

#include "mpgm_reference.h"

static const mpgm_param_spec params[] = {
    {"length", "m", NAN, 0.0, INFINITY, 1, 0, "length L of the bar (free end x = 0, held end x = L)"},
    {"modulus", "Pa", NAN, 0.0, INFINITY, 1, 0, "Young's modulus E (nu = 0: the 1-D modulus)"},
    {"density", "kg/m^3", NAN, 0.0, INFINITY, 1, 0, "density rho"},
    {"v0", "m/s", NAN, -INFINITY, INFINITY, 0, 0, "initial velocity of the quarter X < L/4"},
    {"t1", "s", 1e-5, 0.0, INFINITY, 1, 0,
     "time of the first velocity RMS (eq 44; the second is at the end of the run)"},
};

/* The extended initial velocity over one period [0, 4L): SIGN[i] v0 on
 * [FROM[i] L, TO[i] L), 0 elsewhere (above). */
static const double FROM[3] = {0.0, 1.75, 3.75}, TO[3] = {0.25, 2.25, 4.0}, SIGN[3] = {1, -1, 1};

/* y reduced to one period, [0, 4L). */
static double period(double L, double y) { return y - 4.0 * L * floor(y / (4.0 * L)); }

/* Fi(y) = integral_0^y f (f has zero mean over a period: Fi is periodic). */
static double fi(double L, double v0, double y) {
  y = period(L, y);
  double sum = 0.0;
  for (int i = 0; i < 3; i++)
    if (y > FROM[i] * L) sum += SIGN[i] * v0 * (fmin(y, TO[i] * L) - FROM[i] * L);
  return sum;
}

/* f, the extended initial velocity, at y. */
static double f_ext(double L, double v0, double y) {
  y = period(L, y);
  for (int i = 0; i < 3; i++)
    if (y >= FROM[i] * L && y < TO[i] * L) return SIGN[i] * v0;
  return 0.0;
}

/* acc: [0] RMS at t1, [1] the time it was taken (0: not yet), [2] RMS at
 * the last step, [3] its time. */
static void dyka_bar_observe(const mpgm_reference *r, double t, double dt,
                             const mpgm_ref_points *pts, double *acc) {
  (void)dt;
  const double L = r->param[0], c = sqrt(r->param[1] / r->param[2]), v0 = r->param[3];
  double sum = 0.0;
  for (int p = 0; p < pts->n; p++) {
    const double X = pts->x0[MPGM_DIM * p], *v = pts->v + MPGM_DIM * p;
    const double ex = 0.5 * (f_ext(L, v0, X - c * t) + f_ext(L, v0, X + c * t));
    const double dx = v[0] - ex;
    double e2 = dx * dx; /* and the velocity across the bar, which is 0 */
    for (int d = 1; d < MPGM_DIM; d++) e2 += v[d] * v[d];
    sum += e2;
  }
  const double rms = pts->n ? sqrt(sum / pts->n) : 0.0;
  if (acc[1] == 0.0 && t >= r->param[4] * (1.0 - 1e-9)) {
    acc[0] = rms;
    acc[1] = t;
  }
  acc[2] = rms;
  acc[3] = t;
}

/* Displacement u(X, t) of the material point X. */
static double displacement(const mpgm_reference *r, double X, double t) {
  const double L = r->param[0], c = sqrt(r->param[1] / r->param[2]), v0 = r->param[3];
  return (fi(L, v0, X + c * t) - fi(L, v0, X - c * t)) / (2.0 * c);
}

/* metrics: velocity_rms_t1 (with the time it was taken) and
 * velocity_rms_end (eq 44, m/s); against u(X_probe, t) over rows
 * 1..nrow-1: error_rms, error_max and both relative to the free end's
 * travel |v0| L / (4c) (relative_error_rms, relative_error_max);
 * wave_speed = c; stress_jump = rho c |v0| / 2. */
static int dyka_bar_metrics(const mpgm_reference *r, int nrow, int ncol, const double *hist,
                            const double *acc, mpgm_metric *out) {
  const double L = r->param[0], c = sqrt(r->param[1] / r->param[2]), v0 = r->param[3];
  const int col = mpgm_ref_column(r->probe, r->component);
  double sum = 0.0, emax = 0.0;
  for (int k = 1; k < nrow; k++) {
    const double *row = hist + (size_t)ncol * k;
    const double e = fabs(row[col] - displacement(r, r->x0[0], row[1]));
    sum += e * e;
    emax = fmax(emax, e);
  }
  const double travel = fabs(v0) * L / (4.0 * c);
  int n = 0;
  if (acc && acc[1] > 0.0) {
    out[n++] = (mpgm_metric){"velocity_rms_t1", acc[0]};
    out[n++] = (mpgm_metric){"velocity_rms_t1_time", acc[1]};
  }
  if (acc && acc[3] > 0.0) out[n++] = (mpgm_metric){"velocity_rms_end", acc[2]};
  out[n++] = (mpgm_metric){"wave_speed", c};
  out[n++] = (mpgm_metric){"stress_jump", 0.5 * r->param[2] * c * fabs(v0)};
  if (nrow >= 2) {
    out[n++] = (mpgm_metric){"error_rms", sqrt(sum / (nrow - 1))};
    out[n++] = (mpgm_metric){"error_max", emax};
    out[n++] = (mpgm_metric){"relative_error_rms", sqrt(sum / (nrow - 1)) / travel};
    out[n++] = (mpgm_metric){"relative_error_max", emax / travel};
  }
  return n;
}

const mpgm_reference_type mpgm_reference_dyka_bar = {
    .name = "dyka_bar",
    .doc = "Dyka's bar: 1-D elastic waves from an initial velocity of its free quarter, "
           "d'Alembert's solution at the probe's material point",
    .needs_component = 1,
    .needs_dynamic = 1,
    .nparam = (int)(sizeof params / sizeof params[0]),
    .params = params,
    .metrics = dyka_bar_metrics,
    .observe = dyka_bar_observe,
};
