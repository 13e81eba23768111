/* exit_code.h -- the exit codes of the mpgm command (only app/ decides
 * them): 0 success, 1 simulation failed, 2 bad input, 3 I/O error. */
#ifndef MPGM_EXIT_CODE_H
#define MPGM_EXIT_CODE_H

enum { EXIT_OK = 0, EXIT_SIM = 1, EXIT_INPUT = 2, EXIT_IO = 3 };

/** Exit code of an mpgm error code (mpgm_code). */
int mpgm_exit_code(int code);

#endif
