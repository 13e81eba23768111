/* scene_keys.c -- the keys plug-ins declare for their own part of the scene
 * (mpgm_key_spec): read into their parameter structs; a key that another
 * plug-in declares is refused by the name of its owner (in "shape" the
 * kinds and the front ends, in "mesh" the front ends, in "time" the
 * explicit schemes, mpgm_scene_scheme_keys_end); and the "shape" section
 * itself. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "mpgm_frontends.h"
#include "scene_impl.h"

int mpgm_scene_read_keys(jr_node *o, const mpgm_key_spec *keys, int n, void *base) {
  for (int i = 0; i < n; i++) {
    const mpgm_key_spec *k = &keys[i];
    char *f = (char *)base + k->offset;
    int c;
    switch (k->type) {
    case MPGM_KEY_REAL:
      MPGM_CALL(jr_num(o, k->name, k->def, k->lo, k->hi, k->lo_open, k->hi_open, (double *)f));
      break;
    case MPGM_KEY_INT:
      MPGM_CALL(jr_int(o, k->name, (int)k->def, (int)k->lo, (int)k->hi, (int *)f));
      break;
    case MPGM_KEY_CHOICE:
      MPGM_CALL(jr_enum(o, k->name, k->choices, (int)(k->def - k->lo), &c));
      *(int *)f = (int)k->lo + c;
      break;
    case MPGM_KEY_STRING:
      MPGM_CALL(jr_str(o, k->name, "", f, k->size));
      break;
    default:
      return jr_fail(o, k->name, "internal error: key type %d", k->type);
    }
    char why[400];
    if (k->valid && k->valid(f, why, sizeof why)) return jr_fail(o, k->name, "%s", why);
  }
  return 0;
}

static int declares(const mpgm_key_spec *keys, int n, const char *key) {
  for (int i = 0; i < n; i++)
    if (strcmp(keys[i].name, key) == 0) return 1;
  return 0;
}

static void append(char *buf, size_t len, const char *fmt, ...) {
  const size_t at = strlen(buf);
  if (at + 1 >= len) return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf + at, len - at, fmt, ap);
  va_end(ap);
}

/* The owners of others (n) that declare key, grouped by what selects
 * them: "shape.kind \"cpdi\" or \"cpls\" or method \"gmm\"" ("": none). */
static void key_owners(const mpgm_key_owner *others, int n, const char *key, char *who, size_t len) {
  who[0] = '\0';
  const char *last = NULL;
  for (int i = 0; i < n; i++) {
    if (!declares(others[i].keys, others[i].nkeys, key)) continue;
    const int same = last && strcmp(last, others[i].what) == 0;
    append(who, len, "%s%s%s\"%s\"", who[0] ? " or " : "", same ? "" : others[i].what, same ? "" : " ",
           others[i].name);
    last = others[i].what;
  }
}

static int seen(const jr_node *o, const char *key) {
  for (int i = 0; i < o->nseen; i++)
    if (strcmp(o->seen[i], key) == 0) return 1;
  return 0;
}

/* Key, not read from o, of one of others: refused, naming its owners and
 * the keys o's readers took. In a run's own record (a resolved scene an
 * earlier mpgm wrote, which resolved every meshfree key for every
 * meshfree kind) such a key is passed over (known, not resolved): it
 * changed nothing in that run. */
static int foreign_key(jr_node *o, const mpgm_scene *s, const mpgm_key_owner *others, int n,
                       const char *mine, const char *hint, const char *key, int from_override) {
  char who[256];
  key_owners(others, n, key, who, sizeof who);
  if (!who[0]) return 0; /* nobody's: jr_end or the overrides' check says so */
  if (!s->from_file && !from_override) {
    jr_raw(o, key);
    return 0;
  }
  char list[512] = "";
  for (int i = 0; i < o->nseen; i++) append(list, sizeof list, "%s%s", i ? ", " : "", o->seen[i]);
  return jr_fail(o, key, "a key of %s, not of %s (expected one of: %s)%s", who, mine, list,
                 from_override ? "" : hint);
}

int mpgm_scene_foreign_keys(jr_node *o, const mpgm_scene *s, const mpgm_key_owner *others, int n,
                            const char *mine, const char *hint) {
  for (const cJSON *c = o->j ? o->j->child : NULL; c; c = c->next)
    if (!seen(o, c->string)) MPGM_CALL(foreign_key(o, s, others, n, mine, hint, c->string, 0));
  const size_t len = strlen(o->path);
  for (int i = 0; i < o->r->nov; i++) {
    const char *p = o->r->ov[i].path;
    if (!o->r->ov[i].used && strncmp(p, o->path, len) == 0 && p[len] == '.' && !strchr(p + len + 1, '.'))
      MPGM_CALL(foreign_key(o, s, others, n, mine, hint, p + len + 1, 1));
  }
  return 0;
}

int mpgm_scene_read_shape_keys(jr_node *sh, mpgm_scene *s) {
  memset(&s->shape_par, 0, sizeof s->shape_par);
  memset(&s->pattern, 0, sizeof s->pattern);
  MPGM_CALL(mpgm_scene_read_keys(sh, s->shape->keys, s->shape->nkeys, &s->shape_par));
  MPGM_CALL(mpgm_scene_read_keys(sh, s->frontend->shape_keys, s->frontend->nshape_keys, &s->pattern));
  mpgm_key_owner others[32];
  int n = 0;
  for (const mpgm_shapefn_type *const *t = mpgm_shapefn_types(); *t && n < 16; t++)
    if (*t != s->shape) others[n++] = (mpgm_key_owner){"shape.kind", (*t)->name, (*t)->keys, (*t)->nkeys};
  for (const mpgm_frontend_type *const *f = mpgm_frontend_types(); *f && n < 32; f++)
    if (*f != s->frontend)
      others[n++] = (mpgm_key_owner){"method", (*f)->name, (*f)->shape_keys, (*f)->nshape_keys};
  char mine[128];
  snprintf(mine, sizeof mine, "shape.kind \"%s\" with method \"%s\"", s->shape->name, s->frontend->name);
  /* a kind or method changed by --set over a scene written for another
   * (no hint when --set gave the whole section) */
  int whole = 0;
  for (int i = 0; i < sh->r->nov; i++) whole |= strcmp(sh->r->ov[i].path, sh->path) == 0;
  return mpgm_scene_foreign_keys(sh, s, others, n, mine, whole ? "" : "; to change the kind, give "
                                 "the whole section, --set 'shape={\"kind\": ...}'");
}

int mpgm_scene_member_keys_end(jr_node *o, const mpgm_scene *s, const char *what, const char *name,
                               const mpgm_key_owner *others, int n) {
  char mine[160];
  snprintf(mine, sizeof mine, "%s \"%s\"", what, name);
  return mpgm_scene_foreign_keys(o, s, others, n, mine, "");
}

int mpgm_scene_mesh_keys_end(jr_node *mesh, const mpgm_scene *s) {
  mpgm_key_owner others[16];
  int n = 0;
  for (const mpgm_frontend_type *const *f = mpgm_frontend_types(); *f && n < 16; f++)
    if (*f != s->frontend) others[n++] = (mpgm_key_owner){"method", (*f)->name, (*f)->mesh_keys, (*f)->nmesh_keys};
  return mpgm_scene_member_keys_end(mesh, s, "method", s->frontend->name, others, n);
}
