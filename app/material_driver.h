/* material_driver.h -- `mpgm material`: one material point driven along a
 * prescribed path (docs/material-driver.md). */
#ifndef MPGM_MATERIAL_DRIVER_H
#define MPGM_MATERIAL_DRIVER_H

#include "mpgm_base.h"

/** Read the driver input `file` (JSON), drive its material and write one
 *  CSV row per increment to out_csv. Returns 0, MPGM_ERR_INPUT (bad input,
 *  "FILE: json.path: expected ..., found ..." in ctx), MPGM_ERR_IO, or the
 *  recoverable code of a failed increment (the rows before it are kept). */
int mpgm_material_driver(mpgm_ctx *ctx, const char *file, const char *out_csv);

#endif
