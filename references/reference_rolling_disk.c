/* reference_rolling_disk.c -- reference kind "rolling_disk": a solid disk
 * released at rest on an incline rolls without slip (Iaconeta et al. 2017,
 * section 5.2). In a frame aligned with the incline (x down the slope) the
 * distance travelled by the centre is
 *   s_ref(t) = (1/3) g sin(alpha) t^2,
 * (acceleration g sin(alpha) / (1 + I/(m r^2)) with I = m r^2 / 2). The
 * error of eq (67) of the paper compares horizontal projections
 * u = s cos(alpha) over the time steps. */
#include <math.h>

#include "mpgm_reference.h"

static const double deg = 3.14159265358979323846 / 180.0; /* [rad] */

static const mpgm_param_spec params[] = {
    {"incline_deg", "deg", 60.0, 0.0, 90.0, 1, 1, "inclination alpha of the plane"},
    {"g", "m/s^2", 9.81, 0.0, INFINITY, 1, 0, "gravitational acceleration (magnitude)"},
};

/* metrics: s_final (last ux of the probe), s_ref_final, s_error =
 * |s_final - s_ref_final| / s_ref_final (when s_ref_final > 0), and over
 * rows 1..nrow-1 with u = s cos(alpha): error = sqrt(sum (u_ref - u)^2),
 * error_rms = sqrt(mean (u_ref - u)^2), error_max = max |u_ref - u|
 * (when there is such a row). */
static int rolling_disk_metrics(const mpgm_reference *r, int nrow, int ncol, const double *hist,
                                const double *acc, mpgm_metric *out) {
  (void)acc;
  const double alpha = r->param[0] * deg, g = r->param[1];
  const double k2 = g * sin(alpha) / 3.0, ca = cos(alpha); /* s_ref = k2 t^2 */
  const int col = mpgm_ref_column(r->probe, 0);
  const double *last = hist + (size_t)ncol * (nrow - 1);
  const double s_final = last[col], s_ref_final = k2 * last[1] * last[1];
  int n = 0;
  out[n++] = (mpgm_metric){"s_final", s_final};
  out[n++] = (mpgm_metric){"s_ref_final", s_ref_final};
  if (s_ref_final > 0.0) out[n++] = (mpgm_metric){"s_error", fabs(s_final - s_ref_final) / s_ref_final};
  if (nrow >= 2) {
    double sum = 0.0, emax = 0.0;
    for (int k = 1; k < nrow; k++) {
      const double *row = hist + (size_t)ncol * k;
      const double e = fabs(k2 * row[1] * row[1] * ca - row[col] * ca);
      sum += e * e;
      emax = fmax(emax, e);
    }
    out[n++] = (mpgm_metric){"error", sqrt(sum)};
    out[n++] = (mpgm_metric){"error_rms", sqrt(sum / (nrow - 1))};
    out[n++] = (mpgm_metric){"error_max", emax};
  }
  return n;
}

const mpgm_reference_type mpgm_reference_rolling_disk = {
    .name = "rolling_disk",
    .doc = "solid disk rolling without slip down an incline from rest: s(t) = g sin(alpha) t^2 / 3",
    .needs_component = 0,
    .needs_dynamic = 1,
    .nparam = (int)(sizeof params / sizeof params[0]),
    .params = params,
    .metrics = rolling_disk_metrics,
};
