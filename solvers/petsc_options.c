/* petsc_options.c -- solver.petsc split as PETSc 3.18 splits an options
 * string, and held to mpgm's policy (mpgm_petsc_options.h says what is
 * refused and why).
 *
 * The split follows PetscOptionsInsertString (src/sys/objects/options.c)
 * and PetscTokenFind (src/sys/utils/str.c): tokens are separated by spaces
 * (only: a tab is part of a token); a token that starts with '"' runs to
 * the next '"', which ends it, and the spaces after it are skipped; a
 * token is a name when PetscOptionsValidKey says so ('-', an optional
 * second '-', a letter, and not a number such as -inf); a name is followed
 * by its value unless the next token is a name. Only the tokenizer matters
 * here, not PETSc's handling of -options_file and -prefix_push, which are
 * refused: the module then sets each option itself, and PETSc never sees
 * the string.
 *
 * Names are matched without regard to case, as PETSc looks them up. */
#include "mpgm_petsc_options.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h> /* strcasecmp */

/* ---- the reasons ---------------------------------------------------------- */

#define R_OPTFILE                                                                        \
  "reads options from a file or from a YAML text that mpgm has not checked; write the " \
  "options themselves"
#define R_OPTIONS "an option of PETSc's options database, not of a solver"
#define R_PREFIX "would move the options after it out of the solver's own prefix"
#define R_OUT                                                                            \
  "views, monitors, draws, prints, logs, debugs or names a file or folder, and a scene " \
  "writes only to its results folder (-ksp_monitor and -ksp_monitor_true_residual "     \
  "without a value print to the terminal)"
#define R_VIEWER "a viewer: it prints when a solve ends, or writes to the file its value names"
#define R_MONITOR "a monitor prints to the terminal only: give it no value"
#define R_STREAM                                                                        \
  "a MUMPS output stream: 0 (none) or 6 (the terminal) only; another unit is a file " \
  "fort.N in the current folder"
#define R_LEVEL "MUMPS's print level: an integer from 0 to 4"
#define R_OOC "MUMPS's out-of-core factorisation writes the factors to files: 0 only"
#define R_VALUE                                                                        \
  "a value holds letters, digits and _ . , + - only (a '/' only in hypre's relaxation " \
  "types ...SOR/Jacobi): this one could name a file, a folder or a viewer"
#define R_PYTHON "loads and runs Python code"
#define R_NOKEY "a value with no option before it (PETSc would skip it); an option starts with '-'"
#define R_DASH "write an option with one '-'"
#define R_NAME "an option's name holds letters, digits and '_' only"
#define R_QUOTE "a quote without its end"
#define R_QCLOSE "a closing quote must be followed by a space"
#define R_EMPTY "an empty quoted value"
#define R_CONTROL "a tab, newline or other control character (PETSc separates options by spaces only)"

/* ---- refusals ------------------------------------------------------------- */

/* why = 'refused "TOKEN": REASON', or 'refused the value "VALUE" of
 * "TOKEN": REASON' (the token as written, its leading '-' included); -1. */
static int refuse(char *why, size_t len, const char *name, const char *value, const char *reason) {
  if (!why || !len) return -1;
  char shown[2][72];
  const char *in[2] = {name, value};
  for (int k = 0; k < 2; k++) {
    size_t j = 0;
    for (const char *c = in[k]; c && *c && j < 64; c++)
      shown[k][j++] = *c >= 0x20 && *c < 0x7f ? *c : '?';
    if (in[k] && strlen(in[k]) > 64) shown[k][j++] = '.', shown[k][j++] = '.', shown[k][j++] = '.';
    shown[k][j] = '\0';
  }
  if (value)
    snprintf(why, len, "refused the value \"%s\" of \"%s\": %s", shown[1], shown[0], reason);
  else
    snprintf(why, len, "refused \"%s\": %s", shown[0], reason);
  return -1;
}

/* ---- the split ------------------------------------------------------------ */

/* PetscOptionsValidKey: "-" or "--", then a letter, and not a number
 * (strtod reads "-inf" and "-nan": values). */
static int valid_key(const char *key) {
  if (key[0] != '-') return 0;
  if (key[1] == '-') key++;
  if (!isalpha((unsigned char)key[1])) return 0;
  char *end;
  (void)strtod(key, &end);
  if (end != key && !(*end == '_' || isalnum((unsigned char)*end))) return 0;
  return 1;
}

/* The tokens of buf (changed in place), as PetscTokenFind finds them:
 * tok[0 .. *n), quotes taken off. Refusals: a quote
 * without its end, a closing quote followed by more than a space. */
static int split(char *buf, char **tok, int *n, char *why, size_t len) {
  *n = 0;
  char *p = buf;
  while (*p == ' ') p++; /* PETSc's first token would be "", no name */
  while (*p) {
    const int q = *p == '"';
    char *t = p + q, *e = strchr(t, q ? '"' : ' ');
    if (q && !e) return refuse(why, len, p, NULL, R_QUOTE);
    if (q && e[1] && e[1] != ' ') return refuse(why, len, p, NULL, R_QCLOSE);
    if (q && e == t) return refuse(why, len, "\"\"", NULL, R_EMPTY);
    if (*n >= MPGM_PETSC_OPTIONS_N) return refuse(why, len, t, NULL, "too many options");
    tok[(*n)++] = t;
    if (!e) break;
    *e = '\0';
    p = e + 1;
    while (*p == ' ') p++;
  }
  return 0;
}

/* ---- the policy ----------------------------------------------------------- */

/* name == s, or name ends with "_" s. */
static int is_or_ends(const char *name, const char *s) {
  const size_t ln = strlen(name), ls = strlen(s);
  return ln == ls ? strcmp(name, s) == 0 : ln > ls && name[ln - ls - 1] == '_' &&
                                               strcmp(name + ln - ls, s) == 0;
}

/* A word of the name (between '_' or its ends) equal to w, or, when
 * prefix, starting with w. */
static int has_word(const char *name, const char *w, int prefix) {
  const size_t lw = strlen(w);
  for (const char *p = name; *p;) {
    const size_t l = strcspn(p, "_");
    if (prefix ? l >= lw && strncmp(p, w, lw) == 0 : l == lw && strncmp(p, w, lw) == 0) return 1;
    p += l;
    if (*p) p++;
  }
  return 0;
}

/* Names (lower case) that write or read outside the solver; the reason. */
static const char *name_refused(const char *name) {
  static const char *const sub[] = {"view",  "monitor", "draw",   "plot",   "print",  "dump",
                                    "debug", "trace",   "history", "malloc", "python", "socket",
                                    "saws",  "matlab",  "emacs",  "display", "sleep"};
  static const char *const word[] = {"file", "filename", "dir", "tmpdir", "path", "lg", "info", "dll"};
  static const char *const viewer[] = {"converged_reason", "converged_rate", "final_residual",
                                       "compute_eigenvalues", "compute_eigenvalues_explicitly",
                                       "compute_singularvalues"};
  if (strncmp(name, "options_file", 12) == 0 || strcmp(name, "options_string_yaml") == 0)
    return R_OPTFILE;
  if (strncmp(name, "options_", 8) == 0) return R_OPTIONS;
  if (strcmp(name, "prefix_push") == 0 || strcmp(name, "prefix_pop") == 0) return R_PREFIX;
  for (size_t i = 0; i < sizeof sub / sizeof *sub; i++)
    if (strstr(name, sub[i])) return strstr(name, "python") ? R_PYTHON : R_OUT;
  for (size_t i = 0; i < sizeof word / sizeof *word; i++)
    if (has_word(name, word[i], 0)) return R_OUT;
  if (has_word(name, "log", 1)) return R_OUT; /* log, logging, log_view */
  for (size_t i = 0; i < sizeof viewer / sizeof *viewer; i++)
    if (is_or_ends(name, viewer[i])) return R_VIEWER;
  return NULL;
}

/* A value that cannot name a file, a folder, a viewer or code; the
 * reason if it could. */
static const char *value_refused(const char *v) {
  size_t slash = 0;
  for (const char *c = v; *c; c++) {
    if (*c == '/') {
      slash++;
      continue;
    }
    if (!isalnum((unsigned char)*c) && !strchr("_.,+-", *c)) return R_VALUE;
  }
  if (slash) { /* symmetric-SOR/Jacobi, SOR/Jacobi, backward-SOR/Jacobi, ... */
    const size_t l = strlen(v);
    if (slash > 1 || l < 10 || strcasecmp(v + l - 10, "sor/jacobi") != 0) return R_VALUE;
  }
  if (strcasecmp(v, "python") == 0) return R_PYTHON;
  return NULL;
}

/* MUMPS's ICNTL(1..4) and (22): what value each may take; 0 when the
 * option is none of them or its value is allowed, else the reason. */
static const char *mumps_refused(const char *name, const char *value) {
  static const char *const stream[] = {"mat_mumps_icntl_1", "mat_mumps_icntl_2",
                                       "mat_mumps_icntl_3"};
  const char *v = value ? value : "";
  for (int i = 0; i < 3; i++)
    if (is_or_ends(name, stream[i])) return strcmp(v, "0") == 0 || strcmp(v, "6") == 0 ? NULL : R_STREAM;
  if (is_or_ends(name, "mat_mumps_icntl_4"))
    return strlen(v) == 1 && v[0] >= '0' && v[0] <= '4' ? NULL : R_LEVEL;
  if (is_or_ends(name, "mat_mumps_icntl_22")) return strcmp(v, "0") == 0 ? NULL : R_OOC;
  return NULL;
}

/* One option: name (after its '-') and value (NULL: none) to the policy. */
static int check_option(const char *name, const char *value, char *why, size_t len) {
  if (name[0] == '-') return refuse(why, len, name - 1, NULL, R_DASH);
  char low[MPGM_PETSC_OPTIONS_MAX + 1];
  size_t l = 0;
  for (const char *c = name; *c; c++) {
    if (!isalnum((unsigned char)*c) && *c != '_') return refuse(why, len, name - 1, NULL, R_NAME);
    low[l++] = (char)tolower((unsigned char)*c);
  }
  low[l] = '\0';
  if (is_or_ends(low, "ksp_monitor") || is_or_ends(low, "ksp_monitor_true_residual"))
    return value ? refuse(why, len, name - 1, value, R_MONITOR) : 0;
  const char *r = name_refused(low);
  if (r) return refuse(why, len, name - 1, NULL, r);
  if ((r = mumps_refused(low, value))) return refuse(why, len, name - 1, value, r);
  if (value && (r = value_refused(value))) return refuse(why, len, name - 1, value, r);
  return 0;
}

int mpgm_petsc_options_parse(const char *text, mpgm_petsc_options *out, char *why, size_t len) {
  mpgm_petsc_options local, *o = out ? out : &local;
  if (why && len) why[0] = '\0';
  o->n = 0;
  const size_t n = strlen(text);
  if (n > MPGM_PETSC_OPTIONS_MAX) {
    if (why) snprintf(why, len, "refused: longer than %d characters", MPGM_PETSC_OPTIONS_MAX);
    return -1;
  }
  for (size_t i = 0; i < n; i++)
    if ((unsigned char)text[i] < 0x20 || text[i] == 0x7f) {
      if (why) snprintf(why, len, "refused the character at offset %zu: %s", i, R_CONTROL);
      return -1;
    }
  memcpy(o->text, text, n + 1);
  char *tok[MPGM_PETSC_OPTIONS_N];
  int nt;
  if (split(o->text, tok, &nt, why, len)) return -1;
  for (int i = 0; i < nt;) {
    const char *name = tok[i];
    if (!valid_key(name)) return refuse(why, len, name, NULL, R_NOKEY);
    const char *value = i + 1 < nt && !valid_key(tok[i + 1]) ? tok[i + 1] : NULL;
    i += value ? 2 : 1;
    if (check_option(name + 1, value, why, len)) return -1;
    o->name[o->n] = name + 1;
    o->value[o->n++] = value;
  }
  return 0;
}
