/* linsys.c -- the life of an implicit run's linear system (mpgm_linsys.h):
 * its solver, its vectors sized by the node capacity, Newton's BFGS
 * arrays; released with everything the pattern and assembly built. */
#include <stdlib.h>

#include "mpgm_core_impl.h"

/* The solver of the scene: "auto" takes Cholesky for symmetric tangents
 * (LU when one is not positive definite), LU for unsymmetric ones;
 * Newton-Krylov gets the scene's direct backend inside the composite, an
 * iterative backend with solver.linear_fallback the direct one for the
 * matrices it cannot do. */
static int create_solver(mpgm_problem *pb, mpgm_linsys *ls) {
  const mpgm_scene *scene = pb->scene;
  mpgm_solver_opts so = scene->solver_opts;
  so.symmetric = ls->symmetric;
  so.part = scene->newton_krylov || so.fallback ? scene->solver : NULL;
  const mpgm_solver_type *st = scene->newton_krylov ? &mpgm_solver_reuse
                               : so.fallback        ? &mpgm_solver_fallback
                                                    : scene->solver;
  return mpgm_solver_create(pb->ctx, st, &so, &ls->solver);
}

/* The step's vectors, sized by the node capacity: a front end whose node
 * set changes every step (MPM) never has more than its capacity. */
static int vectors(mpgm_problem *pb, mpgm_linsys *ls) {
  const size_t nd = MPGM_DIM * (size_t)pb->nodes.cap + 1;
  ls->R = calloc(nd, sizeof(double));
  ls->fext = calloc(nd, sizeof(double));
  ls->delta = calloc(nd, sizeof(double));
  ls->dubar = calloc(nd, sizeof(double));
  ls->react = calloc(nd, sizeof(double));
  ls->cflip = calloc(nd, 1);
  ls->fix_factored = calloc(nd, 1);
  if (pb->scene->hht_alpha != 0.0) ls->fint_n = calloc(nd, sizeof(double));
  MPGM_CHECK(pb->ctx, ls->R && ls->fext && ls->delta && ls->dubar && ls->react && ls->cflip &&
                          ls->fix_factored && (ls->fint_n || pb->scene->hht_alpha == 0.0),
             MPGM_ERR_NOMEM, "out of memory");
  return 0;
}

int mpgm_linsys_create(mpgm_problem *pb) {
  mpgm_ctx *ctx = pb->ctx;
  const mpgm_scene *scene = pb->scene;
  mpgm_linsys *ls;
  MPGM_ALLOC(ctx, ls, 1);
  pb->ls = ls;
  ls->pattern_version = -1;
  ls->graph_version = -1;
  ls->symmetric = 1;
  for (int i = 0; i < scene->nmat; i++) ls->symmetric &= scene->mats[i].symmetric;
  MPGM_CALL(create_solver(pb, ls));
  MPGM_CALL(vectors(pb, ls));
  return mpgm_bfgs_setup(pb);
}

void mpgm_linsys_destroy(mpgm_linsys *ls) {
  if (!ls) return;
  void *arr[] = {ls->K.colptr, ls->K.rowind, ls->K.val, ls->scatter, ls->scatter_ptr, ls->order,
                 ls->grp_ptr, ls->nbr, ls->nbr_ptr, ls->nbr_off, ls->node_order, ls->perm,
                 ls->kloc, ls->kbatch, ls->kmask, ls->kslot, ls->task_grp, ls->task_pts, ls->R,
                 ls->fext, ls->delta, ls->dubar, ls->react, ls->cflip, ls->fix_factored,
                 ls->fint_n};
  for (size_t i = 0; i < sizeof arr / sizeof arr[0]; i++) free(arr[i]);
  mpgm_lowrank_free(&ls->lr);
  mpgm_bfgs_free(&ls->bfgs);
  mpgm_solver_destroy(&ls->solver);
  free(ls);
}
