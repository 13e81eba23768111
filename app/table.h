/* table.h -- a table of text cells with named columns, read from and
 * written to CSV (RFC 4180: a cell holding a comma, a quote or a line
 * break is quoted, quotes doubled). study.csv is one. Private to app/.
 */
#ifndef MPGM_TABLE_H
#define MPGM_TABLE_H

#include "mpgm_base.h"

typedef struct mpgm_table {
  int ncol, nrow;
  int capcol, caprow;
  char **head;  /**< ncol column names (owned)                        */
  char ***row;  /**< nrow rows of capcol cells (owned; NULL = empty)   */
} mpgm_table;

/** Index of column name; when absent and create is set it is appended
 *  (empty in every row). -1 when absent (or out of memory). */
int mpgm_table_col(mpgm_table *t, const char *name, int create);
/** Append an empty row; its index, or -1 when out of memory. */
int mpgm_table_add_row(mpgm_table *t);
/** Set a cell (value copied; NULL or "" empties it). 0 or MPGM_ERR_NOMEM. */
int mpgm_table_set(mpgm_table *t, int row, int col, const char *value);
/** Set the cell of column name (created if absent). */
int mpgm_table_set_named(mpgm_table *t, int row, const char *name, const char *value);
/** Cell text ("" when empty or col < 0). */
const char *mpgm_table_get(const mpgm_table *t, int row, int col);
/** Cell as a number: 1 and *v when it is one (finite), else 0. */
int mpgm_table_num(const mpgm_table *t, int row, int col, double *v);
/** Write the table as CSV to path atomically (path.tmp, then rename).
 *  Errors: MPGM_ERR_IO. */
int mpgm_table_write(mpgm_ctx *ctx, const mpgm_table *t, const char *path);
/** Read a CSV file whose first line is the header; rows shorter than the
 *  header are padded with empty cells, longer ones are an error.
 *  Errors: MPGM_ERR_IO (cannot read), MPGM_ERR_INPUT ("FILE: line L: ..."). */
int mpgm_table_read(mpgm_ctx *ctx, const char *path, mpgm_table *t);
/** Free everything (accepts a zeroed table); the table is zeroed. */
void mpgm_table_free(mpgm_table *t);

/** Shortest "%.Ng" text of v that reads back as exactly v (N <= 17), so
 *  0.1 is "0.1", not "0.10000000000000001". buf: at least 32 chars. */
void mpgm_format_double(double v, char *buf, size_t cap);

#endif
