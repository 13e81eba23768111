/* exit_code.h -- the exit codes of the mpgm command (only app/ decides
 * them): 0 success, 1 simulation failed, 2 bad input, 3 I/O error. */
#ifndef MPGM_EXIT_CODE_H
#define MPGM_EXIT_CODE_H

/* EXIT_HANDOFF is no exit code: a command of the plane-strain build met a
 * 3-D scene, and main hands the whole command to mpgm-3d (mpgm_handoff) */
enum { EXIT_OK = 0, EXIT_SIM = 1, EXIT_INPUT = 2, EXIT_IO = 3, EXIT_HANDOFF = -1 };

/** Exit code of an mpgm error code (mpgm_code). */
int mpgm_exit_code(int code);

/** The command argv run again by mpgm-3d, the 3-D build of this program
 *  beside it (execv: returns only when it cannot, with EXIT_INPUT and a
 *  message on stderr naming the scene and the program looked for). */
int mpgm_handoff(char **argv, const char *scene);

#endif
