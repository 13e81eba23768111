/* bench_solvers.h -- `mpgm bench-solvers DIR`: every linear solver backend
 * on the systems a run wrote with output.matrices (docs/scene-format.md,
 * "Command line"). */
#ifndef MPGM_BENCH_SOLVERS_H
#define MPGM_BENCH_SOLVERS_H

#include <stdio.h>

#include "mpgm_base.h"
#include "mpgm_solver.h"

typedef struct mpgm_bench_opts {
  const char *dir;         /**< a matrices folder, or a run folder holding
                                matrices/                                  */
  const char *csv;         /**< CSV file; NULL: DIR/bench_solvers.csv (DIR
                                the matrices folder)                       */
  int repeat;              /**< runs per backend and system; the best time
                                of each phase is reported (>= 1)           */
  const char *only;        /**< comma-separated backend names; NULL: all   */
  mpgm_solver_opts solver; /**< options of the iterative backends          */
} mpgm_bench_opts;

/** Time every backend of mpgm_solver_types() (or o->only) on every system
 *  NAME_K.mtx / NAME_b.mtx of the folder: analyse, factor and solve (the
 *  best of o->repeat fresh instances, through the mpgm_solver_* wrappers),
 *  entries of the factors, peak memory, iterations, the relative residual
 *  |A x - b| / |b| and the relative difference |x - x_ref| / |x_ref| from
 *  UMFPACK's solution. SPD-only backends run on symmetric matrices only
 *  and report "not SPD" when the factorisation fails. Writes one CSV row
 *  per system and backend and prints a Markdown table to `table`. A
 *  backend that fails is reported in its row, not as an error. Returns 0,
 *  MPGM_ERR_INPUT (no such folder, no systems, a malformed file: "FILE:
 *  line L: expected ..., found ...", a right-hand side missing or of
 *  another length, an unknown backend in o->only), MPGM_ERR_IO (a file
 *  that cannot be read, the CSV that cannot be written), MPGM_ERR_NOMEM. */
int mpgm_bench_solvers(mpgm_ctx *ctx, const mpgm_bench_opts *o, FILE *table);

#endif
