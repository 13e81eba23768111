/* units.h -- the units of what `mpgm render` colours by (the fields of
 * the points' VTK files) and of what `mpgm plot` draws (the columns of
 * study.csv): one table, so the two commands and docs/studies.md agree.
 * A name the table does not know has no unit (NULL), never a guessed one.
 * Private to app/. */
#ifndef MPGM_UNITS_H
#define MPGM_UNITS_H

/** Unit of a render field name ("stress_q", "displacement_x", "eps_p"):
 *  the unit of the VTK field it is taken from (docs/scene-format.md,
 *  "Results folder"); "-" for a dimensionless one; NULL if unknown. */
const char *mpgm_field_unit(const char *field);

/** Unit of a study.csv column ("mesh.h", "time_s.total",
 *  "metrics.tip_uy", "metrics.error"); "-" when dimensionless; NULL when
 *  unknown (the metrics of a reference are in docs/scene-format.md,
 *  "reference"). */
const char *mpgm_column_unit(const char *column);

/** A field in Pa drawn in Pa, kPa or MPa as fits amax (the largest
 *  magnitude drawn): the divisor, and the unit's name in *unit. */
double mpgm_stress_scale(double amax, const char **unit);

#endif
