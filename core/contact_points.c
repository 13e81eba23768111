/* contact_points.c -- unilateral contact without slip at points on the
 * bodies' surfaces, held by penalty springs (docs/theory.md, "Contact at
 * surface points").
 *
 * Contact at the grid nodes on the plane (enforce "nodes") holds every node
 * of the plane under the body, over the whole cell row the body dips into:
 * a rolling body is held ahead of its true contact point and has to climb
 * over it, which costs it O(h) of its travel. Here the plane acts on the
 * material's boundary itself: the front end carries tracers on the bodies'
 * boundaries (moved with the body like material points); a tracer that
 * reaches a plane is tied to the place where it crossed it by a spring of
 * stiffness k in both components (no slip), and let go when the spring
 * would pull it back onto the plane (the body lifts off). The springs add
 * k N N^T to the tangent and -k N (x - anchor) to the residual; the active
 * set is updated like the nodes' (mpgm_step solves the step again when it
 * changes), each tracer changing at most once per step.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_core_impl.h"

#if MPGM_DIM != 2
#error "core/contact_points.c is written for plane strain only (MPGM_DIM = 2)"
#endif


/* Axis of the plane's normal and the side the body is on (2-D only: the
 * planes x = value and y = value). */
static void plane_of(const mpgm_scene_boundary *bc, int *axis, int *side) {
  *axis = bc->select == MPGM_SELECT_X ? 0 : 1;
  *side = bc->side;
}

void mpgm_cpoints_free(mpgm_cpoints *cp) {
  free(cp->plane);
  free(cp->flip);
  free(cp->off);
  free(cp->anchor);
  memset(cp, 0, sizeof *cp);
}

int mpgm_cpoints_setup(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *s = pb->scene;
  const mpgm_points *P = &pb->pts;
  mpgm_cpoints *cp = &pb->cp;
  cp->first = P->n + P->nprobe;
  cp->n = P->nsurf;
  MPGM_CHECK(ctx, cp->n > 0, MPGM_ERR_INTERNAL, "contact at points: the front end made no surface tracers");
  MPGM_ALLOC(ctx, cp->plane, cp->n);
  MPGM_ALLOC(ctx, cp->flip, cp->n);
  MPGM_ALLOC(ctx, cp->off, cp->n);
  MPGM_ALLOC(ctx, cp->anchor, MPGM_DIM * (size_t)cp->n);
  for (int t = 0; t < cp->n; t++) {
    const double *x = P->x + MPGM_DIM * (cp->first + t);
    cp->plane[t] = -1;
    for (int i = 0; i < s->nbc && cp->plane[t] < 0; i++) {
      const mpgm_scene_boundary *bc = &s->bcs[i];
      if (!mpgm_bc_at_points(bc)) continue;
      int axis, side;
      plane_of(bc, &axis, &side);
      if (side * (x[axis] - bc->value) > 1e-6 * s->h) continue;
      cp->plane[t] = (signed char)i;
      cp->anchor[MPGM_DIM * t] = x[0]; /* 2-D only: x and y written out */
      cp->anchor[MPGM_DIM * t + 1] = x[1];
      cp->anchor[MPGM_DIM * t + axis] = bc->value;
      cp->held++;
    }
  }
  return 0;
}

/* Position of tracer p at the start of the step: under small kinematics
 * the points stay where they started, and the position is that plus the
 * displacement so far (2-D only: x and y written out). */
static void start_position(const mpgm_problem *pb, int p, double xs[MPGM_DIM]) {
  const int moved = pb->fx.geometric;
  xs[0] = pb->pts.x[MPGM_DIM * p] + (moved ? 0.0 : pb->pts.u[MPGM_DIM * p]);
  xs[1] = pb->pts.x[MPGM_DIM * p + 1] + (moved ? 0.0 : pb->pts.u[MPGM_DIM * p + 1]);
}

/* Position of tracer p at the current increments (2-D only: x and y
 * written out). */
static void iterate_position(const mpgm_problem *pb, int p, double xe[MPGM_DIM]) {
  const mpgm_conn *C = &pb->conn;
  const double *du = pb->nodes.du;
  start_position(pb, p, xe);
  for (int k = C->ptr[p]; k < C->ptr[p + 1]; k++) {
    xe[0] += C->N[k] * du[MPGM_DIM * C->node[k]];
    xe[1] += C->N[k] * du[MPGM_DIM * C->node[k] + 1];
  }
}

/* Position of row r in column c of K (-1 if it is not in the pattern). */
static int entry(const mpgm_csc *K, int r, int c) {
  int lo = K->colptr[c], hi = K->colptr[c + 1] - 1;
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    if (K->rowind[mid] < r) lo = mid + 1;
    else hi = mid;
  }
  return lo <= hi && K->rowind[lo] == r ? lo : -1;
}

void mpgm_cpoints_assemble(mpgm_problem *pb, int want_K, int mass_only) {
  mpgm_linsys *ls = pb->ls;
  const mpgm_cpoints *cp = &pb->cp;
  const mpgm_conn *C = &pb->conn;
  const mpgm_nodes *nd = &pb->nodes;
  const mpgm_scene *s = pb->scene;
  if (!cp->held) return;
  for (int t = 0; t < cp->n; t++) {
    if (cp->plane[t] < 0 || cp->off[t]) continue;
    const int p = cp->first + t;
    const double k = s->bcs[cp->plane[t]].penalty;
    if (!mass_only) { /* spring force -k (x - anchor) on the body */
      double xe[MPGM_DIM];
      iterate_position(pb, p, xe);
      /* 2-D only: written out per component */
      const double f[MPGM_DIM] = {-k * (xe[0] - cp->anchor[MPGM_DIM * t]),
                                  -k * (xe[1] - cp->anchor[MPGM_DIM * t + 1])};
      for (int a = C->ptr[p]; a < C->ptr[p + 1]; a++)
        for (int c = 0; c < MPGM_DIM; c++) {
          const int i = MPGM_DIM * C->node[a] + c, e = nd->dof[i];
          if (e >= 0 && !nd->fix[i]) ls->R[e] += C->N[a] * f[c];
        }
    }
    if (!want_K) continue;
    /* acceleration form for M a = R: the spring as Newmark sees it */
    const double w = mass_only ? s->beta * pb->dt * pb->dt * k : k;
    for (int a = C->ptr[p]; a < C->ptr[p + 1]; a++)
      for (int b = C->ptr[p]; b < C->ptr[p + 1]; b++)
        for (int c = 0; c < MPGM_DIM; c++) {
          const int i = MPGM_DIM * C->node[a] + c, j = MPGM_DIM * C->node[b] + c;
          const int ei = nd->dof[i], ej = nd->dof[j];
          if (ei < 0 || ej < 0 || nd->fix[i] || nd->fix[j]) continue;
          /* FE: the point's nodes are those of a cell holding material,
           * all coupled in the pattern; a meshfree cloud may pair nodes
           * the pattern does not: that entry is left out of the tangent
           * (the residual stays exact) */
          const int q = entry(&ls->K, ei, ej);
          if (q >= 0) ls->K.val[q] += w * C->N[a] * C->N[b];
        }
  }
}

int mpgm_cpoints_update(mpgm_problem *pb) {
  mpgm_cpoints *cp = &pb->cp;
  const mpgm_scene *s = pb->scene;
  int changed = 0;
  for (int t = 0; t < cp->n; t++) {
    if (cp->flip[t] || cp->off[t]) continue;
    const int p = cp->first + t;
    double xe[MPGM_DIM];
    iterate_position(pb, p, xe);
    if (cp->plane[t] >= 0) {
      /* held: let go when the spring pulls the body towards the plane
       * (the tracer sits off the plane on the body's side) */
      int axis, side;
      plane_of(&s->bcs[cp->plane[t]], &axis, &side);
      if (side * (xe[axis] - cp->anchor[MPGM_DIM * t + axis]) > 0.0) {
        cp->plane[t] = -1;
        cp->held--;
        cp->releases++;
        cp->flip[t] = 1;
        changed = 1;
      }
      continue;
    }
    double xs[MPGM_DIM];
    start_position(pb, p, xs);
    for (int i = 0; i < s->nbc; i++) {
      const mpgm_scene_boundary *bc = &s->bcs[i];
      if (!mpgm_bc_at_points(bc)) continue;
      int axis, side;
      plane_of(bc, &axis, &side);
      const double ge = side * (xe[axis] - bc->value);
      if (ge >= 0.0) continue;
      /* held where it crossed the plane in this step (linear in the step) */
      const double gs = side * (xs[axis] - bc->value);
      const double f = gs > 0.0 ? gs / (gs - ge) : 0.0;
      for (int c = 0; c < MPGM_DIM; c++) cp->anchor[MPGM_DIM * t + c] = xs[c] + f * (xe[c] - xs[c]);
      cp->anchor[MPGM_DIM * t + axis] = bc->value;
      cp->plane[t] = (signed char)i;
      cp->held++;
      cp->holds++;
      cp->flip[t] = 1;
      changed = 1;
      break;
    }
  }
  return changed;
}
