/* frontend_check.c -- a loaded scene against its front end's traits
 * (mpgm_frontend_type): what a method takes is read from its record, and a
 * refusal names the methods that would take it. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "mpgm_frontends.h"

/* "FILE: path: message" as MPGM_ERR_INPUT. */
static int fail(mpgm_ctx *ctx, const mpgm_scene *s, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int fail(mpgm_ctx *ctx, const mpgm_scene *s, const char *path, const char *fmt, ...) {
  char msg[768];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  return mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: %s: %s", s->file, path, msg);
}

/* The names of the methods whose trait `field` has every bit of `bits`
 * ("fem, mpm"; "none"). */
enum { SHAPES, GEOMETRIES, CONDITIONS, OBSTACLES, EXPLICIT, PROCESSES };
static const char *takers(int field, unsigned bits, char *buf, size_t len) {
  const mpgm_frontend_type *const *t = mpgm_frontend_types();
  buf[0] = '\0';
  for (int i = 0; t[i]; i++) {
    const unsigned have = field == SHAPES       ? t[i]->shapes
                          : field == GEOMETRIES ? t[i]->geometries
                          : field == CONDITIONS ? t[i]->conditions
                          : field == OBSTACLES  ? (unsigned)t[i]->obstacles
                          : field == EXPLICIT   ? (unsigned)t[i]->explicit_schemes
                                                : t[i]->processes;
    if ((have & bits) != bits) continue;
    const size_t n = strlen(buf);
    snprintf(buf + n, len - n, "%s%s", n ? ", " : "", t[i]->name);
  }
  return buf[0] ? buf : "none";
}

/* The shape kinds of one class ("mls", "lme"). */
static const char *kinds(int cell, char *buf, size_t len) {
  const mpgm_shapefn_type *const *t = mpgm_shapefn_types();
  buf[0] = '\0';
  for (int i = 0; t[i]; i++) {
    if (!!t[i]->needs_cell != cell) continue;
    const size_t n = strlen(buf);
    snprintf(buf + n, len - n, "%s\"%s\"", n ? ", " : "", t[i]->name);
  }
  return buf;
}

static int check_shape(mpgm_ctx *ctx, const mpgm_scene *s) {
  const mpgm_frontend_type *fe = s->frontend;
  const int cell = s->shape->needs_cell;
  const unsigned need = cell ? MPGM_FE_SHAPE_CELL : MPGM_FE_SHAPE_CLOUD;
  if (s->shape->grid_only && fe->persistent_nodes)
    return fail(ctx, s, "shape.kind", "\"%s\" needs the regular background grid of method mpm; "
                "method %s's nodes are its own", s->shape->name, fe->name);
  if (fe->shapes & need) return 0;
  char k[128], m[128];
  return fail(ctx, s, "shape.kind",
              "method %s takes %s shape kinds (%s), found \"%s\", a %s kind (methods that take "
              "it: %s)", fe->name, cell ? "meshfree" : "cell-based", kinds(!cell, k, sizeof k),
              s->shape->name, cell ? "cell-based" : "meshfree", takers(SHAPES, need, m, sizeof m));
}

static int check_bodies(mpgm_ctx *ctx, const mpgm_scene *s) {
  static const char *const geo[] = {MPGM_DIM == 2 ? "rectangle" : "box", MPGM_DIM == 2 ? "disk" : "sphere",
                                     "polygon", "ring", "cylinder"};
  for (int b = 0; b < s->nbody; b++) {
    const unsigned g = 1u << s->bodies[b].geometry;
    if (s->frontend->geometries & g) continue;
    char path[32], m[128];
    snprintf(path, sizeof path, "bodies.%d", b);
    return fail(ctx, s, path, "method %s does not take %s bodies (methods that take them: %s)",
                s->frontend->name, geo[s->bodies[b].geometry], takers(GEOMETRIES, g, m, sizeof m));
  }
  for (int b = 0; b < s->nbody; b++) /* surface points are made on circles and polygons */
    for (int i = 0; i < s->nbc && s->bodies[b].geometry == MPGM_GEOM_RING; i++)
      if (mpgm_bc_at_points(&s->bcs[i])) {
        char path[48];
        snprintf(path, sizeof path, "boundaries.%d.enforce", i);
        return fail(ctx, s, path, "contact at points needs surface points, which ring bodies "
                    "(bodies.%d) do not have: expected \"nodes\"", b);
      }
  return 0;
}

/* 1 when boundary bc's selector meets body b (within its tol). */
static int selector_meets(const mpgm_scene_boundary *bc, const mpgm_scene_body *b) {
  const double t = bc->tol;
  if (bc->select != MPGM_SELECT_BOX)
    return bc->value >= b->min[bc->select] - t && bc->value <= b->max[bc->select] + t;
  double lo[MPGM_DIM], hi[MPGM_DIM];
  for (int d = 0; d < MPGM_DIM; d++) lo[d] = bc->min[d] - t, hi[d] = bc->max[d] + t;
  return mpgm_body_meets_box(b, lo, hi);
}

/* Persistent nodes lie on the bodies: a selector that misses every body
 * picks no node (the front end checks the exact node selection when it
 * makes them). A grid covers mesh.domain: the selector must meet it. */
static int check_selector(mpgm_ctx *ctx, const mpgm_scene *s, int i) {
  const mpgm_scene_boundary *bc = &s->bcs[i];
  char path[48];
  snprintf(path, sizeof path, "boundaries.%d.%s", i,
           mpgm_select_key(bc->select));
  if (s->frontend->persistent_nodes) {
    for (int k = 0; k < s->nbody; k++)
      if (selector_meets(bc, &s->bodies[k])) return 0;
    return fail(ctx, s, path, "expected a selector that meets a body (only bodies carry nodes), "
                "found none within tol = %g of it", bc->tol);
  }
  mpgm_scene_body dom = {.geometry = MPGM_GEOM_RECTANGLE};
  memcpy(dom.min, s->dom_min, sizeof dom.min);
  memcpy(dom.max, s->dom_max, sizeof dom.max);
  if (selector_meets(bc, &dom)) return 0;
  return fail(ctx, s, path, "expected a selector that meets mesh.domain (the background grid "
              "covers the domain), found none within tol = %g of it", bc->tol);
}

static int check_boundaries(mpgm_ctx *ctx, const mpgm_scene *s) {
  const mpgm_frontend_type *fe = s->frontend;
  for (int i = 0; i < s->nbc; i++) {
    const mpgm_scene_boundary *bc = &s->bcs[i];
    MPGM_CALL(check_selector(ctx, s, i));
    char path[48], m[128];
    const unsigned cond = bc->condition != MPGM_COND_CONTACT ? MPGM_FE_COND_FIX
                          : mpgm_bc_at_points(bc)            ? MPGM_FE_COND_CONTACT_POINTS
                                                             : MPGM_FE_COND_CONTACT_NODES;
    snprintf(path, sizeof path, "boundaries.%d.condition", i);
    if (!(fe->conditions & cond))
      return fail(ctx, s, path, "\"contact\" enforced at %s is not a condition of method %s "
                  "(methods that take it: %s)", cond == MPGM_FE_COND_CONTACT_POINTS ? "surface "
                  "points" : "grid nodes", fe->name, takers(CONDITIONS, cond, m, sizeof m));
    const int moves = bc->displacement[0] != 0.0 || bc->displacement[1] != 0.0;
    snprintf(path, sizeof path, "boundaries.%d.displacement", i);
    if (moves && !(fe->conditions & MPGM_FE_COND_DISPLACEMENT))
      return fail(ctx, s, path, "expected [0, 0] with method %s (%s; methods that take "
                  "prescribed displacements: %s), found [%g, %g]", fe->name,
                  fe->persistent_nodes ? "its nodes do not carry them"
                                       : "its grid is reset every step",
                  takers(CONDITIONS, MPGM_FE_COND_DISPLACEMENT, m, sizeof m), bc->displacement[0],
                  bc->displacement[1]);
  }
  return 0;
}

/* time.analysis "explicit": a method that projects lumped masses, and what
 * the explicit schemes do not enforce yet (contact; moving supports are
 * refused by the methods that take explicit schemes, MPM). */
static int check_explicit(mpgm_ctx *ctx, const mpgm_scene *s) {
  if (s->analysis != MPGM_ANALYSIS_EXPLICIT) return 0;
  char m[128], path[48];
  if (!s->frontend->explicit_schemes)
    return fail(ctx, s, "time.analysis", "method %s has no explicit schemes (methods that take "
                "\"explicit\": %s)", s->frontend->name, takers(EXPLICIT, 1, m, sizeof m));
  for (int i = 0; i < s->nbc; i++) {
    const mpgm_scene_boundary *bc = &s->bcs[i];
    if (bc->condition == MPGM_COND_CONTACT) {
      snprintf(path, sizeof path, "boundaries.%d.condition", i);
      return fail(ctx, s, path, "\"contact\" is not enforced by the explicit schemes: use "
                  "time.analysis \"dynamic\" (implicit), or fixed or slip supports");
    }
  }
  return 0;
}

/* A run on many processes (mpiexec -n P): only the analyses the front
 * end runs so (mpgm_frontend_type.processes), never a wrong run. */
static int check_processes(mpgm_ctx *ctx, const mpgm_scene *s) {
  const int np = mpgm_ctx_size(ctx);
  if (np == 1) return 0;
  const int expl = s->analysis == MPGM_ANALYSIS_EXPLICIT;
  const unsigned need = expl ? MPGM_FE_MANY_EXPLICIT : MPGM_FE_MANY_IMPLICIT;
  char m[128];
  if (!(s->frontend->processes & need))
    return fail(ctx, s, "method", "method %s runs its %s analyses on one process only so far, and "
                "this run was started on %d (methods that run them on many: %s); run it without "
                "mpiexec, or with -n 1", s->frontend->name, expl ? "explicit" : "implicit", np,
                takers(PROCESSES, need, m, sizeof m));
  /* what a run writes and observes on many processes so far: the points'
   * .vtu pieces of a .pvtu frame, the probes, the histories, summary.json */
  const char *key = NULL;
  char what[160];
  if (s->vtk != MPGM_VTK_NONE && (s->formats & (MPGM_FORMAT_VTK | MPGM_FORMAT_XDMF)))
    key = "output.format", snprintf(what, sizeof what, "a run on many processes writes only \"vtu\" "
                                    "so far (each process its points' piece of a .pvtu frame)");
  else if (s->grid)
    key = "output.grid", snprintf(what, sizeof what, "a run on many processes writes no "
                                  "background grid series so far");
  else if (s->checkpoint_every > 0)
    key = "output.checkpoint_every", snprintf(what, sizeof what, "a run on many processes writes "
                                              "no checkpoints so far");
  else if (s->manufactured)
    key = "manufactured", snprintf(what, sizeof what, "a run on many processes measures no "
                                   "manufactured solution's errors so far");
  else if (s->reference.type && s->reference.type->observe)
    key = "reference", snprintf(what, sizeof what, "reference \"%s\" observes every material "
                                "point, which a run on many processes does not do so far",
                                s->reference.type->name);
  if (!key) return 0;
  return fail(ctx, s, key, "%s, and this run was started on %d; run it without mpiexec, or with "
              "-n 1", what, np);
}

int mpgm_frontend_check(mpgm_ctx *ctx, const mpgm_scene *s) {
  const mpgm_frontend_type *fe = s->frontend;
  MPGM_CALL(check_shape(ctx, s));
  MPGM_CALL(check_bodies(ctx, s));
  MPGM_CALL(check_boundaries(ctx, s));
  char m[128];
  if (s->nobstacle > 0 && !fe->obstacles)
    return fail(ctx, s, "obstacles", "method %s takes no obstacles (methods that take them: %s)",
                fe->name, takers(OBSTACLES, 1, m, sizeof m));
  if (s->grid && !fe->background)
    return fail(ctx, s, "output.grid", "expected false, found true: method %s has no "
                "background grid (its nodes and cells are its own, written as mesh.pvd; method "
                "mpm has one)", fe->name);
  MPGM_CALL(check_explicit(ctx, s));
  MPGM_CALL(check_processes(ctx, s));
  return fe->check ? fe->check(ctx, s) : 0;
}
