/* reference_rigid_block.c -- reference kind "rigid_block": a block of
 * height H0 and density rho0 on a fixed base between rollers, under gravity
 * (Molinos et al. 2021, section 3.2). With rollers at its sides and nu = 0
 * every horizontal layer carries the weight of what lies above it, however
 * much the block has settled: at equilibrium a point that started at
 * height Y has sigma_yy = -rho0 g (H0 - Y), per unit width in the current
 * configuration as in the initial one (the width does not change), for any
 * material. The block oscillates about that state after gravity is ramped
 * in (gravity_ramp); the kind averages, over the bottom row of points (the
 * points that started lowest) and over time from `from` to the end of the
 * run, the ratio of their sigma_yy to -rho0 g (H0 - Y).
 *
 * Linear elasticity in rate form (sigma' = E d, the explicit schemes' form
 * under kinematics small) is E ln(stretch) in 1-D; the layer at Y then
 * has the stretch exp(-rho0 g (H0 - Y) / E), and the top settles at rest by
 * H0 - (E / (rho0 g)) (1 - exp(-rho0 g H0 / E)). The probe (at the top)
 * oscillates about it: the middle of its extremes over the window is
 * compared. */
#include <math.h>

#include "mpgm_reference.h"

static const mpgm_param_spec params[] = {
    {"height", "m", NAN, 0.0, INFINITY, 1, 0, "height H0 of the block (its base at y = 0)"},
    {"density", "kg/m^3", NAN, 0.0, INFINITY, 1, 0, "density rho0"},
    {"g", "m/s^2", 9.81, 0.0, INFINITY, 1, 0, "gravitational acceleration (magnitude)"},
    {"from", "s", NAN, 0.0, INFINITY, 0, 0, "start of the time window of the average"},
    {"modulus", "Pa", 0.0, 0.0, INFINITY, 0, 0,
     "Young's modulus E of a linear elastic block in rate form: the settlement at rest "
     "(0: not computed)"},
};

enum { SUM, TIME, MIN, MAX, SEEN, BAD, ROW, YMIN };

/* acc: [SUM] the time integral of the row's mean ratio over the window,
 * [TIME] the window's length so far, [MIN]/[MAX] the row's mean ratio's
 * extremes there, [SEEN] 1 once a sample was taken, [BAD] 1 when a stress
 * was not finite, [ROW] the number of points in the bottom row (0 before
 * the first call), [YMIN] the lowest initial height (found at that call:
 * the points' initial positions do not change). */
static void rigid_block_observe(const mpgm_reference *r, double t, double dt,
                                const mpgm_ref_points *pts, double *acc) {
  const double H = r->param[0], rho = r->param[1], g = r->param[2];
  if (acc[ROW] == 0.0) {
    acc[YMIN] = INFINITY;
    for (int p = 0; p < pts->n; p++) acc[YMIN] = fmin(acc[YMIN], pts->x0[MPGM_DIM * p + MPGM_DIM - 1]);
  }
  const double ymin = acc[YMIN];
  double sum = 0.0;
  int n = 0;
  for (int p = 0; p < pts->n; p++) {
    const double Y = pts->x0[MPGM_DIM * p + MPGM_DIM - 1]; /* the vertical: y (3-D z) */
    if (Y > ymin + 1e-9 * H) continue;
    const double s = pts->sigma[MPGM_NSTRESS * p + MPGM_DIM - 1]; /* yy (3-D zz) */
    if (!isfinite(s)) acc[BAD] = 1.0;
    sum += s / (-rho * g * (H - Y));
    n++;
  }
  acc[ROW] = n;
  if (!(t >= r->param[3]) || !(dt > 0.0) || n == 0) return;
  const double mean = sum / n;
  acc[SUM] += dt * mean;
  acc[TIME] += dt;
  acc[MIN] = acc[SEEN] > 0.0 ? fmin(acc[MIN], mean) : mean;
  acc[MAX] = acc[SEEN] > 0.0 ? fmax(acc[MAX], mean) : mean;
  acc[SEEN] = 1.0;
}

/* metrics: bottom_points (the bottom row's size), and over the window:
 * bottom_stress_ratio (the time average of the row's mean ratio
 * sigma_yy / (-rho0 g (H0 - Y))), its _min and _max, bottom_stress_error =
 * |ratio - 1|; stress_not_finite = 1 when a stress was NaN or infinite;
 * with modulus: settlement_ref (above), top_settlement_mid (minus the
 * middle of the probe's y displacement extremes over the window) and
 * settlement_error = |mid - ref| / ref. */
static int rigid_block_metrics(const mpgm_reference *r, int nrow, int ncol, const double *hist,
                               const double *acc, mpgm_metric *out) {
  const double H = r->param[0], rho = r->param[1], g = r->param[2], E = r->param[4];
  int n = 0;
  if (E > 0.0) {
    const double ref = H - E / (rho * g) * (1.0 - exp(-rho * g * H / E));
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < nrow; k++) {
      const double *row = hist + (size_t)ncol * k;
      if (row[1] < r->param[3]) continue;
      const double u = row[mpgm_ref_column(r->probe, MPGM_DIM - 1)]; /* the vertical */
      lo = fmin(lo, u);
      hi = fmax(hi, u);
    }
    out[n++] = (mpgm_metric){"settlement_ref", ref};
    if (hi >= lo) {
      out[n++] = (mpgm_metric){"top_settlement_mid", -0.5 * (lo + hi)};
      out[n++] = (mpgm_metric){"settlement_error", fabs(-0.5 * (lo + hi) - ref) / ref};
    }
  }
  if (!acc) return n;
  out[n++] = (mpgm_metric){"bottom_points", acc[ROW]};
  if (acc[BAD] > 0.0) out[n++] = (mpgm_metric){"stress_not_finite", 1.0};
  if (acc[SEEN] > 0.0 && acc[TIME] > 0.0) {
    const double ratio = acc[SUM] / acc[TIME];
    out[n++] = (mpgm_metric){"bottom_stress_ratio", ratio};
    out[n++] = (mpgm_metric){"bottom_stress_ratio_min", acc[MIN]};
    out[n++] = (mpgm_metric){"bottom_stress_ratio_max", acc[MAX]};
    out[n++] = (mpgm_metric){"bottom_stress_error", fabs(ratio - 1.0)};
  }
  return n;
}

const mpgm_reference_type mpgm_reference_rigid_block = {
    .name = "rigid_block",
    .doc = "block between rollers on a fixed base under gravity: the bottom row's sigma_yy "
           "against -rho0 g (H0 - Y), averaged over a time window",
    .needs_component = 0,
    .needs_dynamic = 1,
    .nparam = (int)(sizeof params / sizeof params[0]),
    .params = params,
    .metrics = rigid_block_metrics,
    .observe = rigid_block_observe,
};
