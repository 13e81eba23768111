/* json_reader.h -- private helper of scene loading: typed, validated reads
 * of a cJSON tree with dotted-path error messages and --set overrides.
 *
 * Every read names its key: the key is marked as known (so jr_end can reject
 * unknown keys), an override "path=value" given on the command line takes
 * precedence over the file and is converted to the type the read expects,
 * and the value used (after defaults) is mirrored into a "resolved" tree.
 */
#ifndef MPGM_JSON_READER_H
#define MPGM_JSON_READER_H

#include <cjson/cJSON.h>

#include "mpgm_base.h"

#define JR_MAXKEYS 48
#define JR_PATH 256
#define JR_MAX_DEPTH 64                 /**< arrays and objects within each other */
#define JR_MAX_FILE ((size_t)64 << 20) /**< largest JSON file read [bytes]       */

typedef struct jr_override {
  char path[JR_PATH]; /**< dotted path, e.g. "mesh.h"   */
  const char *value;  /**< text after '='               */
  int used;           /**< consumed by a read           */
} jr_override;

typedef struct jr_reader {
  mpgm_ctx *ctx;
  const char *file;   /**< for messages                 */
  jr_override *ov;
  int nov;
  cJSON *tmp;         /**< values made from overrides (freed at the end) */
  double h;           /**< mesh.h once read: the cell of lengths in cells (0: none yet) */
} jr_reader;

typedef struct jr_node {
  jr_reader *r;
  const cJSON *j;            /**< object read (NULL when absent)   */
  char path[JR_PATH];        /**< dotted path, "" for the root      */
  cJSON *out;                /**< resolved mirror (owned by parent) */
  const char *seen[JR_MAXKEYS];
  int nseen;
} jr_node;

/** Record "FILE: path.key: message" in ctx; returns MPGM_ERR_INPUT. */
int jr_fail(jr_node *o, const char *key, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
/** Name of a JSON value's type for messages ("number", "string", ...). */
const char *jr_type(const cJSON *v);
/** Number with default (NAN: required) and range [lo, hi] (open ends when
 *  lo_open / hi_open). */
int jr_num(jr_node *o, const char *key, double def, double lo, double hi,
           int lo_open, int hi_open, double *out);
/** Integer with default (def < lo: required) and range [lo, hi]. */
int jr_int(jr_node *o, const char *key, int def, int lo, int hi, int *out);
/** true or false, with a default. */
int jr_bool(jr_node *o, const char *key, int def, int *out);
/** One of choices (NULL-terminated); def < 0: required. */
int jr_enum(jr_node *o, const char *key, const char *const *choices, int def,
            int *out);
/** String; def NULL: required. */
int jr_str(jr_node *o, const char *key, const char *def, char *buf,
           size_t len);
/** Array of MPGM_DIM finite numbers ([x, y], or [x, y, z] in 3-D); def
 *  NULL: required. */
int jr_vec(jr_node *o, const char *key, const double *def, double out[MPGM_DIM]);
/** A length: a number (metres), {"cells": k} (k h) or {"at": x, "cells": k}
 *  (x + k h), h = o->r->h (docs/scene-format.md, "Lengths in cells"); def
 *  NAN: required; range [lo, hi] in metres. The resolved tree holds metres. */
int jr_len(jr_node *o, const char *key, double def, double lo, double hi, double *out);
/** [x, y] ([x, y, z] in 3-D) whose components are lengths as jr_len reads
 *  them; def NULL: required. */
int jr_vec_len(jr_node *o, const char *key, const double *def, double out[MPGM_DIM]);
/** Child object (absent allowed when !required: child->j = NULL). */
int jr_child(jr_node *o, const char *key, int required, jr_node *child);
/** Raw item of a key (marks it known; overrides are not applied). */
const cJSON *jr_raw(jr_node *o, const char *key);
/** Reject unknown and duplicate keys of o. */
int jr_end(jr_node *o);
/** Read FILE and parse it as a JSON object into *doc (caller deletes).
 *  Errors: MPGM_ERR_IO (cannot read), MPGM_ERR_NOMEM, MPGM_ERR_INPUT
 *  ("FILE: line L, column C: JSON syntax error near '...'", or
 *  "FILE: (root): expected an object, found ..."). */
int jr_parse_file(mpgm_ctx *ctx, const char *file, cJSON **doc);
/** The same for text[0, len) (need not be NUL-terminated); file names it in
 *  messages. */
int jr_parse_text(mpgm_ctx *ctx, const char *file, const char *text, size_t len, cJSON **doc);
/** Strict RFC 8259 check of text[0, len): one JSON value with whitespace
 *  around it; strings (and keys) UTF-8 without NUL, raw or as \u0000, and
 *  without lone surrogates; numbers in JSON's grammar (no "01", "1.", ".5");
 *  nesting at most JR_MAX_DEPTH. Returns 0, or 1 with *at the byte offset of
 *  the first fault and why (nwhy bytes) saying what it is. */
int jr_strict_check(const char *text, size_t len, size_t *at, char *why, size_t nwhy);
/** Offset of the first byte of s[0, len) that does not start a valid UTF-8
 *  sequence, -1 when all are valid. */
long jr_utf8_invalid(const char *s, size_t len);
/** 1 when the whole of s is a JSON number. */
int jr_is_json_number(const char *s);
/** Refuse an override whose value is not UTF-8, or starts like an array or
 *  object ('[' or '{') and is not strict JSON: "FILE: PATH: ..." */
int jr_check_override(mpgm_ctx *ctx, const char *file, const jr_override *ov);
/** Overrides not consumed by any read: error "unknown path". */
int jr_unused_overrides(jr_reader *r);
/** A JSON value given by an override for path (NULL if none); marks it used
 *  and parses it as JSON (arrays, objects) or a string. */
const cJSON *jr_override_json(jr_node *o, const char *key);

#endif
