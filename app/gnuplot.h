/* gnuplot.h -- drawing through gnuplot (Debian gnuplot-nox), shared by
 * `mpgm plot` and `mpgm render`. Private to app/. */
#ifndef MPGM_GNUPLOT_H
#define MPGM_GNUPLOT_H

#include <signal.h>
#include <stdio.h>

#include "mpgm_base.h"

/** A gnuplot process reading a script from a pipe. */
typedef struct mpgm_gnuplot {
  FILE *in;          /**< write the script here                       */
  int pid;           /**< the gnuplot process                          */
  char errfile[64];  /**< its stderr, shown when it fails             */
  struct sigaction old_pipe; /**< SIGPIPE's disposition before      */
} mpgm_gnuplot;

/** Find an executable "gnuplot" on PATH; 1 and its path in buf, else 0. */
int mpgm_gnuplot_find(char *buf, size_t cap);
/** 0 when gnuplot is on PATH, else MPGM_ERR_IO with the message below
 *  (so a command can say so before it does any work). */
int mpgm_gnuplot_check(mpgm_ctx *ctx);
/** Start gnuplot (no shell involved) in folder cwd (NULL: the current
 *  one), so the script may name its files relative to it. Errors: MPGM_ERR_IO, with the
 *  message "gnuplot not found on PATH (Debian: apt-get install
 *  gnuplot-nox)" when it is missing. */
int mpgm_gnuplot_open(mpgm_ctx *ctx, mpgm_gnuplot *g, const char *cwd);
/** Close the pipe and wait for gnuplot. Errors: MPGM_ERR_IO when it
 *  failed (its first error lines in the message). */
int mpgm_gnuplot_close(mpgm_ctx *ctx, mpgm_gnuplot *g);
/** Write s as a gnuplot string literal (single quotes, '' inside). */
void mpgm_gnuplot_quote(FILE *f, const char *s);
/** 0 when path exists and is a non-empty file, else MPGM_ERR_IO naming it. */
int mpgm_file_nonempty(mpgm_ctx *ctx, const char *path);

#endif
