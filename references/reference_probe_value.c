/* reference_probe_value.c -- reference kind "probe_value": one published or
 * converged value of a probe displacement component at the end of the run
 * (e.g. the cantilever's tip deflection). */
#include <math.h>

#include "mpgm_reference.h"

static const mpgm_param_spec params[] = {
    {"value", "m", NAN, -INFINITY, INFINITY, 0, 0,
     "reference displacement of the probe component at the end of the run"},
};

/* metrics: reference_value, error = |u_final - value|, relative_error =
 * error / |value| (left out when value = 0) */
static int probe_value_metrics(const mpgm_reference *r, int nrow, int ncol, const double *hist,
                               const double *acc, mpgm_metric *out) {
  (void)acc;
  const double value = r->param[0];
  const double u = hist[(size_t)ncol * (nrow - 1) + mpgm_ref_column(r->probe, r->component)];
  const double err = fabs(u - value);
  int n = 0;
  out[n++] = (mpgm_metric){"reference_value", value};
  out[n++] = (mpgm_metric){"error", err};
  if (value != 0.0) out[n++] = (mpgm_metric){"relative_error", err / fabs(value)};
  return n;
}

const mpgm_reference_type mpgm_reference_probe_value = {
    .name = "probe_value",
    .doc = "final displacement component of a probe against a reference value",
    .needs_component = 1,
    .needs_dynamic = 0,
    .nparam = (int)(sizeof params / sizeof params[0]),
    .params = params,
    .metrics = probe_value_metrics,
};
