/* units.c -- the one table of units of render fields and study columns
 * (units.h). */
#include "units.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

typedef struct unit_row {
  const char *name, *unit;
} unit_row;

/* The point fields of the VTK output (docs/scene-format.md, "Results
 * folder"); volume and mass are per metre of thickness. */
static const unit_row fields[] = {
    {"displacement", "m"}, {"velocity", "m/s"}, {"acceleration", "m/s^2"}, {"stress", "Pa"},
    {"mass", "kg/m"},      {"volume", "m^3/m"}, {"J", "-"},               {"material", "-"},
    {"eps_p", "-"},        {"id", "-"},         {"body", "-"},
};

/* Run keys and results of study.csv, by their whole name. */
static const unit_row columns[] = {
    {"mesh.h", "m"},      {"time.dt", "s"},      {"time.end", "s"},       {"mesh.ppc", "-"},
    {"reference.relative_error", "-"},
};

/* Metrics (after "metrics." or "metrics_at_stop."): the run's own and
 * those of the references (the files of references/). The errors of probe_value,
 * rolling_disk, column_wave and dyka_bar are displacements [m]; the
 * relative ones and ratios are dimensionless. */
static const unit_row metrics[] = {
    {"error", "m"},
    {"error_rms", "m"},
    {"error_max", "m"},
    {"relative_error", "-"},
    {"relative_error_rms", "-"},
    {"relative_error_max", "-"},
    {"s_error", "-"},
    {"s_final", "m"},
    {"s_ref_final", "m"},
    {"reference_value", NULL}, /* the probe_value's component: m; but kept apart from the study's */
    {"top_amplitude", "m"},
    {"top_amplitude_ref", "m"},
    {"period_ref", "s"},
    {"wave_speed", "m/s"},
    {"stress_jump", "Pa"},
    {"velocity_rms_t1", "m/s"},
    {"velocity_rms_t1_time", "s"},
    {"velocity_rms_end", "m/s"},
    {"bottom_points", "-"},
    {"bottom_stress_ratio", "-"},
    {"bottom_stress_ratio_min", "-"},
    {"bottom_stress_ratio_max", "-"},
    {"bottom_stress_error", "-"},
    {"settlement_error", "-"},
    {"settlement_ref", "m"},
    {"top_settlement_mid", "m"},
    {"mass_total", "kg/m"},
    {"volume_total", "m^3/m"},
    {"runout", "m"},
    {"height", "m"},
    {"eps_p_max", "-"},
};

static const char *lookup(const unit_row *t, size_t n, const char *name, int *found) {
  for (size_t i = 0; i < n; i++)
    if (!strcmp(t[i].name, name)) {
      if (found) *found = 1;
      return t[i].unit;
    }
  if (found) *found = 0;
  return NULL;
}

const char *mpgm_field_unit(const char *field) {
  const size_t nf = sizeof fields / sizeof *fields;
  const char *u = lookup(fields, nf, field, NULL);
  if (u) return u;
  /* NAME_x of a vector, NAME_xx .. NAME_q of a tensor: NAME's unit */
  const char *us = strrchr(field, '_');
  if (!us) return NULL;
  static const char *const comp[] = {"x", "y", "xx", "yy", "xy", "zz", "p", "q"};
  for (size_t k = 0; k < sizeof comp / sizeof *comp; k++)
    if (!strcmp(us + 1, comp[k])) {
      char base[128];
      snprintf(base, sizeof base, "%.*s", (int)(us - field), field);
      return lookup(fields, nf, base, NULL);
    }
  return NULL;
}

const char *mpgm_column_unit(const char *column) {
  int found;
  const char *u = lookup(columns, sizeof columns / sizeof *columns, column, &found);
  if (found) return u;
  if (!strncmp(column, "time_s.", 7)) return "s"; /* the wall-time split of summary.json */
  const char *m = !strncmp(column, "metrics.", 8) ? column + 8
                  : !strncmp(column, "metrics_at_stop.", 16) ? column + 16 : NULL;
  if (!m) m = column; /* `--y error` names the metric itself */
  u = lookup(metrics, sizeof metrics / sizeof *metrics, m, &found);
  if (found) return u;
  /* a probe's final displacement: NAME_ux, NAME_uy */
  const size_t n = strlen(m);
  if (n > 3 && (!strcmp(m + n - 3, "_ux") || !strcmp(m + n - 3, "_uy"))) return "m";
  return NULL;
}

double mpgm_stress_scale(double amax, const char **unit) {
  if (amax >= 1e6) {
    *unit = "MPa";
    return 1e6;
  }
  if (amax >= 1e3) {
    *unit = "kPa";
    return 1e3;
  }
  *unit = "Pa";
  return 1.0;
}
