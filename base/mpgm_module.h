/* mpgm_module.h -- parts of mpgm built as modules of their own (a shared
 * object loaded on first use, so that a run that never needs them never
 * loads them nor the libraries under them): the solver backend "petsc"
 * (mpgm_petsc.so, solvers/plugin.c) and the process group of a run on
 * many processes (mpgm_par.so, parallel/loader.c).
 *
 * A module is looked for in $MPGM_PLUGIN_DIR, then beside the running
 * executable, then in the build folder it was built in (so that the unit
 * tests in build/tests find it too). */
#ifndef MPGM_MODULE_H
#define MPGM_MODULE_H

#include <stddef.h>

/** dlopen the first file called `file` (e.g. "mpgm_petsc.so") in the
 *  places above: its handle, or NULL when none loads. */
void *mpgm_module_open(const char *file);

/** Why `file` did not load, into msg (len bytes): the first place whose
 *  file does not load with dlopen's reason, or that there is no such file
 *  (and how to build it: `what` names what it brings, e.g. "PETSc"). */
void mpgm_module_why_not(const char *file, const char *what, char *msg, size_t len);

#endif
