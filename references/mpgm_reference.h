/* mpgm_reference.h -- the reference-solution plug-in family.
 *
 * A scene may name one reference solution ("reference": {"kind": ...}); it
 * is resolved when the scene loads, and at the end of a run it turns the
 * probe history into accuracy metrics of summary.json ("metrics").
 *
 * Every kind reads "probe" (the name of a scene probe) and, when it says so,
 * "component" ("x" | "y", or "z" in 3-D), plus its own numeric parameter
 * table. Each kind is one .c exporting a `const mpgm_reference_type`; the
 * list of all of them is MPGM_REFERENCE_LIST in reference_list.c. Kinds
 * that need "the vertical" take the last axis (y, or z in 3-D).
 *
 * Probe history layout (as core/output.c records it): row-major, nrow rows
 * of ncol doubles; column 0 the step, column 1 the time [s] (dynamic) or
 * the load factor (static), then the MPGM_DIM displacement components [m]
 * of each probe in scene order (component c of probe k at column
 * mpgm_ref_column(k, c)). Row 0 is the initial state.
 */
#ifndef MPGM_REFERENCE_H
#define MPGM_REFERENCE_H

#include "mpgm_base.h" /* mpgm_param_spec */

#ifdef __cplusplus
extern "C" {
#endif

#define MPGM_REF_MAXPARAM 6   /**< numeric parameters of a kind      */
#define MPGM_REF_MAXMETRIC 10 /**< metrics a kind may produce        */
#define MPGM_REF_MAXACC 8     /**< doubles a kind may accumulate over
                                   the run (observe)                  */

typedef struct mpgm_reference_type mpgm_reference_type;

/** A resolved reference block. */
typedef struct mpgm_reference {
  const mpgm_reference_type *type; /**< kind; NULL: the scene has none   */
  int probe;      /**< index of the probe in the scene's probes          */
  int component;  /**< 0: x, 1: y, 2: z (kinds with needs_component;
                       else 0)                                          */
  double param[MPGM_REF_MAXPARAM]; /**< in type->params order            */
  double x0[MPGM_DIM]; /**< the probe's initial position [m] (its
                       material coordinate)                             */
} mpgm_reference;

/** The material points as a kind's observe sees them after a step
 *  (MPGM_DIM doubles per vector, MPGM_NSTRESS per stress: 2-D {xx, yy,
 *  xy, zz}). */
typedef struct mpgm_ref_points {
  int n;                /**< material points                             */
  const double *x0;     /**< initial positions (material coordinates) [m] */
  const double *x;      /**< positions [m]                               */
  const double *v;      /**< velocities [m/s]                            */
  const double *sigma;  /**< Cauchy stresses [Pa]                        */
} mpgm_ref_points;

/** One metric: name (static string) and value. */
typedef struct mpgm_metric {
  const char *name;
  double value;
} mpgm_metric;

struct mpgm_reference_type {
  const char *name;     /**< scene name, e.g. "rolling_disk"              */
  const char *doc;      /**< one line for docs                            */
  int needs_component;  /**< 1: reads "component": "x" | "y" (required)   */
  int needs_dynamic;    /**< 1: not with time.analysis "static"           */
  int nparam;           /**< entries of params                            */
  const mpgm_param_spec *params; /**< numeric parameters (not probe, component) */
  /** Metrics from a probe history (layout above; nrow >= 1 and the probe's
   *  columns exist, the caller checks). Writes at most MPGM_REF_MAXMETRIC
   *  entries of out and returns how many. No allocation. */
  int (*metrics)(const mpgm_reference *r, int nrow, int ncol, const double *hist,
                 const double *acc, mpgm_metric *out);
  /** Optional: the material points at time t, after a step of dt (and at
   *  t = 0 with dt = 0), for metrics of whole fields; what it keeps goes
   *  into acc (MPGM_REF_MAXACC doubles, 0 at the start, carried across a
   *  restart), which metrics then gets (else acc is NULL or zeros). */
  void (*observe)(const mpgm_reference *r, double t, double dt, const mpgm_ref_points *pts,
                  double *acc);
};

/** The column of component c of probe k in a probe history. */
static inline int mpgm_ref_column(int k, int c) { return 2 + MPGM_DIM * k + c; }

/** All kinds, NULL-terminated (for docs and error messages). */
const mpgm_reference_type *const *mpgm_reference_types(void);
/** The kind with scene name `name`; NULL if none (or name NULL). */
const mpgm_reference_type *mpgm_reference_type_find(const char *name);

#ifdef __cplusplus
}
#endif
#endif
