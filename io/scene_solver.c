/* scene_solver.c -- the "solver" block: the linear solver backend (a
 * member of the solver family, solvers/) with its options, and Newton's
 * settings; and the check of the backend's options before a run
 * (mpgm_scene_check_solver). */
#include <string.h>

#include "mpgm_json_reader.h"
#include "mpgm_scene_io.h"
#include "mpgm_solver.h"
#include "scene_impl.h"

/* "solver": the linear solver backend and Newton's settings (read after
 * the boundaries, on which contact_check's default depends). */
/* solver.linear_fallback: "none" or a direct backend, which factorises the
 * matrices an iterative solver.linear cannot solve or precondition
 * (solvers/fallback.c). A direct linear ignores it, as it ignores
 * linear_tol: a case that names a fallback for its PETSc solves can then
 * be run with --set solver.linear=umfpack as it is. */
static int read_fallback(jr_node *so, mpgm_scene *s) {
  const mpgm_solver_type *const *svt = mpgm_solver_types();
  const char *names[16] = {"none"};
  int n = 1;
  for (int i = 0; svt[i] && n < 15; i++)
    if (!svt[i]->iterative) names[n++] = svt[i]->name;
  names[n] = NULL;
  int k;
  MPGM_CALL(jr_enum(so, "linear_fallback", names, 0, &k));
  s->solver_opts.fallback = k && s->solver->iterative ? mpgm_solver_type_find(names[k]) : NULL;
  return 0;
}

/* After the readers of "solver": a key of another backend refused. */
static int backend_keys_end(jr_node *so, const mpgm_scene *s) {
  mpgm_key_owner others[16];
  int n = 0;
  for (const mpgm_solver_type *const *t = mpgm_solver_types(); *t && n < 16; t++)
    if (*t != s->solver) others[n++] = (mpgm_key_owner){"solver.linear", (*t)->name, (*t)->keys, (*t)->nkeys};
  return mpgm_scene_member_keys_end(so, s, "solver.linear", s->solver->name, others, n);
}

int mpgm_scene_read_solver(jr_node *root, mpgm_scene *s) {
  jr_node so;
  MPGM_CALL(jr_child(root, "solver", 0, &so));
  const mpgm_solver_type *const *svt = mpgm_solver_types();
  const char *svn[16];
  int nsv = 0;
  for (; svt[nsv] && nsv < 15; nsv++) svn[nsv] = svt[nsv]->name;
  svn[nsv] = NULL;
  int si; /* the first backend of the list, "auto", is the default */
  const cJSON *lin = jr_override_json(&so, "linear");
  if (!lin) lin = jr_raw(&so, "linear");
  char why[512];
  /* an explicit run loads no solver (core/problem.c) */
  if (s->analysis != MPGM_ANALYSIS_EXPLICIT && cJSON_IsString(lin) &&
      strcmp(lin->valuestring, "petsc") == 0 && !mpgm_solver_usable("petsc", why, sizeof why))
    return jr_fail(&so, "linear", "\"petsc\" cannot be used: %s", why);
  /* mpgm's own GMRES + ILU(0), retired in issue 19: PETSc's was faster
   * on every system of bench/solvers that either converged on */
  if (cJSON_IsString(lin) && strcmp(lin->valuestring, "gmres") == 0)
    return jr_fail(&so, "linear", "\"gmres\" (mpgm's own GMRES + ILU(0)) was retired: use \"petsc\", "
                   "whose default for an unsymmetric tangent is GMRES + ILU(0) (solver.petsc "
                   "\"-ksp_type gmres -pc_type ilu\" for any tangent)");
  MPGM_CALL(jr_enum(&so, "linear", svn, 0, &si));
  s->solver = svt[si];
  MPGM_CALL(jr_num(&so, "rtol", 1e-9, 0, 1, 1, 1, &s->rtol));
  MPGM_CALL(jr_num(&so, "atol", 1e-10, 0, INFINITY, 0, 0, &s->atol));
  MPGM_CALL(jr_num(&so, "dtol", 1e-10, 0, 1, 1, 1, &s->dtol));
  MPGM_CALL(jr_int(&so, "max_iterations", 25, 1, 1000, &s->max_iter));
  static const char *const newton_names[] = {"full", "modified", "krylov", "bfgs", NULL};
  int newton;
  MPGM_CALL(jr_enum(&so, "newton", newton_names, 0, &newton));
  s->newton_modified = newton == 1 || newton == 3;
  s->newton_bfgs = newton == 3;
  s->newton_krylov = newton == 2;
  if (s->newton_krylov && s->solver->iterative)
    return jr_fail(&so, "newton", "\"krylov\" preconditions GMRES with the factorisation of a "
                   "direct solver.linear (auto, cholmod, umfpack, klu, ...), found \"%s\"",
                   s->solver->name);
  MPGM_CALL(jr_num(&so, "reuse_ratio", 0.1, 0.0, 1.0, 1, 1, &s->reuse_ratio));
  MPGM_CALL(jr_int(&so, "bfgs_pairs", 16, 1, MPGM_BFGS_PAIRS_MAX, &s->bfgs_pairs));
  MPGM_CALL(jr_num(&so, "relaxation", 1.0, 0.0, 1.0, 1, 0, &s->relaxation));
  MPGM_CALL(jr_int(&so, "stagnation", 5, 0, 1000, &s->stagnation));
  MPGM_CALL(jr_int(&so, "line_search", 0, 0, 30, &s->line_search));
  MPGM_CALL(jr_int(&so, "contact_rank", 32, 0, 1024, &s->contact_rank));
  /* A point of a contact at points caught during a solve is anchored from
   * the iterate at which the set is checked, so that iterate's error stays
   * in the answer: such scenes check at 1e-6 (docs/theory.md section 17).
   * Grid nodes are held on the plane itself, and 1e-3 saves iterations. */
  const double check_def = mpgm_scene_contact_at_points(s) ? 1e-6 : 1e-3;
  MPGM_CALL(jr_num(&so, "contact_check", check_def, 0.0, 1.0, 0, 1, &s->contact_check));
  static const char *const ordering_names[] = {"backend", "geometric", NULL};
  MPGM_CALL(jr_enum(&so, "ordering", ordering_names, 0, &s->ordering_nd));
  MPGM_CALL(jr_int(&so, "threads", 1, 0, 256, &s->threads));
  /* iterative backends (petsc); the direct ones ignore them */
  s->solver_opts = mpgm_solver_opts_default();
  MPGM_CALL(jr_num(&so, "linear_tol", s->solver_opts.tol, 0, 1, 1, 1, &s->solver_opts.tol));
  MPGM_CALL(jr_int(&so, "linear_restart", s->solver_opts.restart, 1, 1000, &s->solver_opts.restart));
  MPGM_CALL(jr_int(&so, "linear_max_iterations", s->solver_opts.max_iter, 1, 10000000,
                   &s->solver_opts.max_iter));
  MPGM_CALL(jr_int(&so, "refactor_iterations", s->solver_opts.refactor_iterations, 1, 100000,
                   &s->solver_opts.refactor_iterations));
  static const char *const forcing_names[] = {"fixed", "eisenstat_walker", NULL};
  MPGM_CALL(jr_enum(&so, "forcing", forcing_names, 0, &s->forcing_ew));
  MPGM_CALL(read_fallback(&so, s));
  /* the backend's own keys (petsc: its options, held to mpgm's policy
   * here, without PETSc; what PETSc makes of them is
   * mpgm_scene_check_solver's); another backend's refused by its name */
  MPGM_CALL(mpgm_scene_read_keys(&so, s->solver->keys, s->solver->nkeys, &s->solver_opts));
  s->solver_opts.file = s->file; /* the backend's messages of bad options name it */
  MPGM_CALL(backend_keys_end(&so, s));
  MPGM_CALL(jr_end(&so));

  return 0;
}

/* PETSc's own judgement of solver.petsc needs PETSc (the module, MPI: 0.4 s
 * to start), which the loader does not start: the scene fuzzer, studies
 * and restarts load scenes without solving anything. `mpgm check` and
 * mpgm_run call this instead, after the load and before any output. */
int mpgm_scene_check_solver(mpgm_ctx *ctx, const mpgm_scene *s) {
  /* an explicit run creates no solver (core/problem.c), so it judges none */
  if (s->analysis == MPGM_ANALYSIS_EXPLICIT || !s->solver->check) return 0;
  /* the options as core/problem.c hands them to the instance it creates,
   * with the tangent's symmetry (every material's), which picks PETSc's
   * defaults (CG + ICC(0) or GMRES + ILU(0)) and so decides which options
   * are read; solver.linear_fallback's composite hands the same options to
   * its iterative part */
  mpgm_solver_opts o = s->solver_opts;
  o.symmetric = 1;
  for (int i = 0; i < s->nmat; i++) o.symmetric &= s->mats[i].symmetric;
  o.part = o.fallback = NULL;
  return mpgm_solver_check(ctx, s->solver, &o);
}
