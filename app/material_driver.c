/* material_driver.c -- `mpgm material FILE.json`: one material driven
 * through a prescribed deformation path, without a mesh
 * (docs/material-driver.md).
 *
 * Input: {"material": {...a scene's materials entry...},
 *         "kinematics": "finite" | "small",
 *         "initial_stress": [sxx, syy, sxy, szz],            (optional)
 *         "path": [{"F": [[F11, F12], [F21, F22]], "steps": N}, ...]
 *      or "triaxial": {"confining": p, "axial_strain": e, "steps": N}}
 * Output: one CSV row per increment (step 0 = the initial state): F, the
 * Cauchy stress, its principal values, eps_p, the yield function and the
 * largest relative difference between the material's tangent D and a
 * central-difference tangent of its stress.
 */
#include "material_driver.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mpgm_file.h"
#include "mpgm_json_reader.h"
#include "mpgm_scene_io.h"
#include "mpgm_scene.h"

#define MAX_SEGMENTS 256
#define TRIAX_MAXIT 50

typedef struct segment {
  double F[4]; /* end of the segment, row major */
  int steps;
} segment;

typedef struct driver {
  mpgm_material mat;
  int kin;
  int has_s0;
  double s0[4];
  int triaxial;
  double confining, axial_strain; /* compression-positive magnitudes */
  int nseg;
  segment seg[MAX_SEGMENTS];
} driver;

/* An array of n finite numbers at key (a JSON array). */
static int read_numbers(jr_node *o, const char *key, const cJSON *v, int n, double *out) {
  if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != n)
    return jr_fail(o, key, "expected an array of %d numbers, found %s", n, jr_type(v));
  for (int i = 0; i < n; i++) {
    const cJSON *c = cJSON_GetArrayItem(v, i);
    if (!cJSON_IsNumber(c) || !isfinite(c->valuedouble))
      return jr_fail(o, key, "expected a finite number at index %d, found %s", i, jr_type(c));
    out[i] = c->valuedouble;
  }
  return 0;
}

/* "F": [[F11, F12], [F21, F22]] with det F > 0. */
static int read_F(jr_node *e, double F[4]) {
  const cJSON *v = jr_raw(e, "F");
  if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2)
    return jr_fail(e, "F", "expected [[F11, F12], [F21, F22]], found %s", jr_type(v));
  for (int r = 0; r < 2; r++) {
    char key[8];
    snprintf(key, sizeof key, "F.%d", r);
    MPGM_CALL(read_numbers(e, key, cJSON_GetArrayItem(v, r), 2, F + 2 * r));
  }
  if (!(F[0] * F[3] - F[1] * F[2] > 0.0))
    return jr_fail(e, "F", "expected det F > 0, found %g", F[0] * F[3] - F[1] * F[2]);
  return 0;
}

static int read_input(jr_node *root, driver *d) {
  MPGM_CALL(mpgm_material_load(root->r->ctx, root->r->file, "material", jr_raw(root, "material"),
                               &d->mat));
  snprintf(d->mat.name, sizeof d->mat.name, "material");
  static const char *const kin_names[] = {"finite", "small", NULL};
  MPGM_CALL(jr_enum(root, "kinematics", kin_names, MPGM_KIN_FINITE, &d->kin));
  if (d->kin == MPGM_KIN_FINITE && !d->mat.type->finite)
    return jr_fail(root, "kinematics", "\"%s\" is a small-strain law: expected \"small\", found "
                   "\"finite\"", d->mat.type->name);
  const cJSON *s0 = jr_raw(root, "initial_stress");
  if (s0) {
    MPGM_CALL(read_numbers(root, "initial_stress", s0, 4, d->s0));
    d->has_s0 = 1;
  }
  const cJSON *path = jr_raw(root, "path");
  jr_node tx;
  MPGM_CALL(jr_child(root, "triaxial", 0, &tx));
  if (!!path == !!tx.j)
    return jr_fail(root, "path", "expected exactly one of \"path\" and \"triaxial\", found %s",
                   path ? "both" : "neither");
  if (tx.j) {
    d->triaxial = 1;
    MPGM_CALL(jr_num(&tx, "confining", NAN, 0.0, INFINITY, 0, 1, &d->confining));
    MPGM_CALL(jr_num(&tx, "axial_strain", NAN, 0.0, 1.0, 1, 1, &d->axial_strain));
    d->nseg = 1;
    MPGM_CALL(jr_int(&tx, "steps", -1, 1, 10000000, &d->seg[0].steps));
    MPGM_CALL(jr_end(&tx));
    if (d->has_s0)
      return jr_fail(root, "initial_stress", "expected no initial_stress with \"triaxial\" (it "
                     "starts from the isotropic confining stress), found one");
    d->has_s0 = d->confining > 0.0;
    const double p = -d->confining;
    const double iso[4] = {p, p, 0.0, p};
    memcpy(d->s0, iso, sizeof iso);
  } else {
    if (!cJSON_IsArray(path) || cJSON_GetArraySize(path) < 1)
      return jr_fail(root, "path", "expected a non-empty array of {\"F\": ..., \"steps\": N}, "
                     "found %s", jr_type(path));
    d->nseg = cJSON_GetArraySize(path);
    if (d->nseg > MAX_SEGMENTS)
      return jr_fail(root, "path", "expected at most %d segments, found %d", MAX_SEGMENTS, d->nseg);
    cJSON *arr = cJSON_AddArrayToObject(root->out, "path");
    for (int i = 0; i < d->nseg; i++) {
      jr_node e = {.r = root->r, .j = cJSON_GetArrayItem(path, i)};
      snprintf(e.path, sizeof e.path, "path.%d", i);
      if (!cJSON_IsObject(e.j)) return jr_fail(&e, NULL, "expected an object, found %s", jr_type(e.j));
      e.out = cJSON_CreateObject();
      cJSON_AddItemToArray(arr, e.out);
      MPGM_CALL(read_F(&e, d->seg[i].F));
      MPGM_CALL(jr_int(&e, "steps", -1, 1, 10000000, &d->seg[i].steps));
      MPGM_CALL(jr_end(&e));
    }
  }
  if (d->has_s0 && !d->mat.type->init_stress)
    return jr_fail(root, d->triaxial ? "triaxial.confining" : "initial_stress",
                   "material \"%s\" cannot start from an initial stress; expected none (or "
                   "confining 0), found one", d->mat.type->name);
  return jr_end(root);
}

/* ---- one material point ------------------------------------------------- */
typedef struct point {
  const mpgm_material *m;
  int kin, ns;
  double F[4];    /* committed F                      */
  double *st_n;   /* committed state                  */
  double *st, *work;
} point;

static void mul2(const double A[4], const double B[4], double C[4]) {
  const double c0 = A[0] * B[0] + A[1] * B[2], c1 = A[0] * B[1] + A[1] * B[3];
  const double c2 = A[2] * B[0] + A[3] * B[2], c3 = A[2] * B[1] + A[3] * B[3];
  C[0] = c0; C[1] = c1; C[2] = c2; C[3] = c3;
}
static double det2(const double A[4]) { return A[0] * A[3] - A[1] * A[2]; }

/* Stress (and tangent) at total F from the committed state into state. */
static int eval(const point *p, const double F[4], double *state, double sigma[4], double D[9]) {
  double dF[4];
  if (p->kin == MPGM_KIN_FINITE) {
    const double j = det2(p->F);
    const double inv[4] = {p->F[3] / j, -p->F[1] / j, -p->F[2] / j, p->F[0] / j};
    mul2(F, inv, dF);
  } else {
    memcpy(dF, F, sizeof dF);
  }
  return p->m->type->update(p->m, p->kin, F, dF, p->ns ? p->st_n : NULL, p->ns ? state : NULL,
                            sigma, D);
}

/* Largest |D - D_fd| over the largest |D| entry; D_fd by central
 * differences: finite, J D:sym(H) = d/de tau((I + e H) F) - (H tau + tau
 * H^T); small, d sigma / d eps. */
static double tangent_check(const point *p, const double F[4], const double sigma[4],
                            const double D[9]) {
  const double h = 1e-6;
  const double H[3][4] = {{1, 0, 0, 0}, {0, 0, 0, 1}, {0, 0.5, 0.5, 0}};
  const double J = p->kin == MPGM_KIN_FINITE ? det2(F) : 1.0;
  double dmax = 0.0, emax = 0.0;
  for (int j = 0; j < 3; j++) {
    double Fp[4], Fm[4], sp[4], sm[4];
    if (p->kin == MPGM_KIN_FINITE) {
      const double Ip[4] = {1 + h * H[j][0], h * H[j][1], h * H[j][2], 1 + h * H[j][3]};
      const double Im[4] = {1 - h * H[j][0], -h * H[j][1], -h * H[j][2], 1 - h * H[j][3]};
      mul2(Ip, F, Fp);
      mul2(Im, F, Fm);
    } else {
      for (int q = 0; q < 4; q++) {
        Fp[q] = F[q] + h * H[j][q];
        Fm[q] = F[q] - h * H[j][q];
      }
    }
    if (eval(p, Fp, p->work, sp, NULL) || eval(p, Fm, p->work, sm, NULL)) return NAN;
    double col[3];
    if (p->kin == MPGM_KIN_FINITE) {
      const double Jp = det2(Fp), Jm = det2(Fm);
      /* (H tau + tau H^T) for symmetric H: xx 2 H00 t_xx + 2 H01 t_xy, ... */
      const double tx = J * sigma[0], ty = J * sigma[1], txy = J * sigma[2];
      const double a = H[j][0], b = H[j][1], c = H[j][3];
      const double g[3] = {2 * (a * tx + b * txy), 2 * (b * txy + c * ty),
                           a * txy + b * ty + b * tx + c * txy};
      for (int i = 0; i < 3; i++) col[i] = ((Jp * sp[i] - Jm * sm[i]) / (2 * h) - g[i]) / J;
    } else {
      for (int i = 0; i < 3; i++) col[i] = (sp[i] - sm[i]) / (2 * h);
    }
    for (int i = 0; i < 3; i++) {
      dmax = fmax(dmax, fabs(D[3 * i + j]));
      emax = fmax(emax, fabs(D[3 * i + j] - col[i]));
    }
  }
  return dmax > 0.0 ? emax / dmax : emax;
}

static void principal(const double s[4], double out[3]) {
  const double h = 0.5 * (s[0] - s[1]), mid = 0.5 * (s[0] + s[1]), R = hypot(h, s[2]);
  double v[3] = {mid + R, mid - R, s[3]};
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2 - i; j++)
      if (v[j] < v[j + 1]) {
        const double t = v[j];
        v[j] = v[j + 1];
        v[j + 1] = t;
      }
  memcpy(out, v, sizeof v);
}

static void write_row(FILE *f, long step, const point *p, const double F[4], const double s[4],
                      const double *state, double check) {
  double pr[3];
  principal(s, pr);
  const mpgm_material *m = p->m;
  const double J = p->kin == MPGM_KIN_FINITE ? det2(F) : 1.0;
  const double tau[4] = {J * s[0], J * s[1], J * s[2], J * s[3]};
  const double epsp = m->type->plastic_strain && p->ns ? m->type->plastic_strain(m, state) : NAN;
  const double fy = m->type->yield ? m->type->yield(m, tau) : NAN;
  fprintf(f, "%ld", step);
  for (int i = 0; i < 4; i++) fprintf(f, ",%.17g", F[i]);
  for (int i = 0; i < 4; i++) fprintf(f, ",%.17g", s[i]);
  for (int i = 0; i < 3; i++) fprintf(f, ",%.17g", pr[i]);
  fprintf(f, ",%.17g,%.17g,%.6e\n", epsp, fy, check);
}

/* The increment at F22 = f22 with sigma_xx = -confining: Newton on F11
 * with the material tangent (finite: d sigma_xx / d ln F11 = D_00 +
 * sigma_xx; small: D_00). F[0] holds the start value and the result. */
static int triaxial_increment(mpgm_ctx *ctx, const point *p, const driver *d, long step,
                              double F[4], double s[4], double D[9]) {
  const double target = -d->confining;
  for (int it = 0; it < TRIAX_MAXIT; it++) {
    int err = eval(p, F, p->st, s, D);
    if (err) MPGM_ERROR(ctx, err, "step %ld: material update failed: %s", step, mpgm_code_str(err));
    const double r = s[0] - target;
    if (fabs(r) <= 1e-12 * (fabs(s[0]) + fabs(s[1]) + fabs(s[3]) + 1.0)) return 0;
    const double k = p->kin == MPGM_KIN_FINITE ? D[0] + s[0] : D[0];
    if (!(k > 0.0))
      MPGM_ERROR(ctx, MPGM_ERR_NOT_CONVERGED, "step %ld: triaxial: lateral stiffness %g <= 0",
                 step, k);
    if (p->kin == MPGM_KIN_FINITE) F[0] *= exp(-r / k);
    else F[0] -= r / k;
  }
  MPGM_ERROR(ctx, MPGM_ERR_NOT_CONVERGED,
             "step %ld: triaxial: sigma_xx did not reach -confining in %d Newton iterations on F11",
             step, TRIAX_MAXIT);
}

static int drive(mpgm_ctx *ctx, const char *file, const driver *d, FILE *f) {
  point p = {.m = &d->mat, .kin = d->kin, .ns = d->mat.type->nstate};
  p.F[0] = p.F[3] = 1.0;
  double *buf = calloc(3 * (size_t)(p.ns + 1), sizeof(double));
  if (!buf) MPGM_ERROR(ctx, MPGM_ERR_NOMEM, "out of memory");
  p.st_n = buf;
  p.st = buf + p.ns + 1;
  p.work = buf + 2 * (p.ns + 1);
  int err = 0;
  char msg[256] = "";
  if (d->mat.type->init_state) d->mat.type->init_state(&d->mat, p.st_n);
  if (d->has_s0 && d->mat.type->init_stress(&d->mat, d->kin, d->s0, p.st_n, msg, sizeof msg))
    err = mpgm_err_set(ctx, MPGM_ERR_INPUT, __FILE__, __LINE__, "%s: %s: %s", file,
                       d->triaxial ? "triaxial.confining" : "initial_stress", msg);
  fputs("step,F11,F12,F21,F22,sigma_xx,sigma_yy,sigma_xy,sigma_zz,sigma_1,sigma_2,sigma_3,"
        "eps_p,yield,tangent_check\n", f);
  double s[4], D[9];
  if (!err) {
    /* step 0: the initial state at F = I */
    err = eval(&p, p.F, p.st, s, D);
    if (err) err = mpgm_err_set(ctx, err, __FILE__, __LINE__, "step 0: material update failed: %s",
                                mpgm_code_str(err));
    else write_row(f, 0, &p, p.F, s, p.st_n, tangent_check(&p, p.F, s, D));
  }
  long step = 0;
  double F0[4] = {1, 0, 0, 1};
  for (int g = 0; g < d->nseg && !err; g++) {
    const int n = d->seg[g].steps;
    for (int i = 1; i <= n && !err; i++) {
      const double a = (double)i / n;
      double F[4];
      step++;
      if (d->triaxial) {
        memcpy(F, p.F, sizeof F);
        F[1] = F[2] = 0.0;
        F[3] = 1.0 - a * d->axial_strain;
        err = triaxial_increment(ctx, &p, d, step, F, s, D);
      } else {
        for (int q = 0; q < 4; q++) F[q] = F0[q] + a * (d->seg[g].F[q] - F0[q]);
        err = eval(&p, F, p.st, s, D);
        if (err) err = mpgm_err_set(ctx, err, __FILE__, __LINE__,
                                    "step %ld: material update failed: %s", step, mpgm_code_str(err));
      }
      if (err) break;
      const double check = tangent_check(&p, F, s, D);
      write_row(f, step, &p, F, s, p.st, check);
      memcpy(p.st_n, p.st, sizeof(double) * (size_t)p.ns);
      memcpy(p.F, F, sizeof F);
    }
    if (!d->triaxial) memcpy(F0, d->seg[g].F, sizeof F0);
  }
  free(buf);
  return err;
}

int mpgm_material_driver(mpgm_ctx *ctx, const char *file, const char *out_csv) {
  cJSON *doc = NULL;
  MPGM_CALL(jr_parse_file(ctx, file, &doc));
  driver *d = calloc(1, sizeof *d);
  cJSON *resolved = cJSON_CreateObject();
  jr_reader r = {.ctx = ctx, .file = file};
  jr_node root = {.r = &r, .j = doc, .out = resolved};
  int err = d ? read_input(&root, d) : mpgm_err_set(ctx, MPGM_ERR_NOMEM, __FILE__, __LINE__, "out of memory");
  cJSON_Delete(r.tmp);
  cJSON_Delete(resolved);
  cJSON_Delete(doc);
  FILE *f = NULL;
  if (!err) {
    err = mpgm_fopen_write(ctx, out_csv, &f);
  }
  if (!err) err = drive(ctx, file, d, f);
  if (f && fclose(f) && !err)
    err = mpgm_err_set(ctx, MPGM_ERR_IO, __FILE__, __LINE__, "%s: write error", out_csv);
  free(d);
  return err;
}
