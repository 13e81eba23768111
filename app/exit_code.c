/* exit_code.c -- the one table from error codes to exit codes. */
#include "exit_code.h"

#include "mpgm_base.h"

int mpgm_exit_code(int code) {
  if (code == 0) return EXIT_OK;
  if (code == MPGM_ERR_INPUT) return EXIT_INPUT;
  if (code == MPGM_ERR_IO) return EXIT_IO;
  return EXIT_SIM;
}
