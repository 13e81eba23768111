/* help.h -- `mpgm help [COMMAND]`, `mpgm COMMAND --help`: the usage text
 * of every command, in one place (help.c). Private to app/. */
#ifndef MPGM_HELP_H
#define MPGM_HELP_H

#include <stdio.h>

/** The overview: every command's usage line and the exit codes. */
void mpgm_help_overview(FILE *f);

/** Print COMMAND's usage and options to f; 0, or -1 when there is no such
 *  command (nothing printed). */
int mpgm_help_command(FILE *f, const char *command);

/** Does argv[2..] ask for help (--help or -h)? */
int mpgm_help_asked(int argc, char **argv);

#endif
