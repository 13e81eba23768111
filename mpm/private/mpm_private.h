/* mpm_private.h -- the MPM front end's state, shared by its files
 * (mpm.c: the front end; project.c: the projection to the nodes). */
#ifndef MPGM_MPM_PRIVATE_H
#define MPGM_MPM_PRIVATE_H

#include "mpgm_mpm.h"
#include "mpgm_cpls.h"
#include "mpgm_discretisation.h"
#include "mpgm_grid.h"
#include "mpgm_kdtree.h"
#include "mpgm_parallel.h"

/* Written for both dimensions. The meshfree kinds (clouds of grid nodes
 * over a kd-tree), CPLS and the surface points of contact at points are
 * plane strain only (MPM_PLANE_ONLY: their code is compiled out of a 3-D
 * build, whose scenes cannot ask for them). */
#define MPM_PLANE_ONLY (MPGM_DIM == 2)

typedef struct mpm_data {
  mpgm_grid g;
  int *pcell;          /**< cell of every point (material, then probes)    */
  double *pxi;         /**< local coordinates in that cell, MPGM_DIM per point */
  int *gmap;           /**< grid node -> node of the step, or -1           */
  unsigned char *cact; /**< 1 when the cell holds a material point         */
  unsigned char *gfix; /**< MPGM_DIM per grid node: fixed by a boundary    */
  signed char *gcontact; /**< per grid node: contact code (mpgm_nodes.contact) */
  unsigned char *gfree;  /**< per grid node: a contact node the last step
                              ended with released                        */
  int *lglob;            /**< node of the step -> grid node               */
  /* the last step's final node set, fixity and active cells: when a step
   * has the same, the matrix pattern is the same (only the maps change) */
  int pn;
  int *plglob;
  mpgm_conn plists;    /**< clouds: the lists of the last begin_step         */
  mpgm_conn carry;     /**< scratch of mpgm_tracers_carry                    */
  unsigned char *pfix, *pact;
  double *gm;          /**< per grid node: mass (the light-node rule)       */
  unsigned char *light;/**< per grid node: light (no equation this step)    */
  /* meshfree shape functions (shape.kind mls / lme): clouds of grid nodes;
   * grid kinds (ugimp) take the 4 x 4 grid nodes around a point directly */
  int meshfree;
  int gridfn;          /**< a grid kind: no clouds, no kd-tree              */
  mpgm_shape_params gpar; /**< its parameters (h, the particle half-width)  */
  double *gx;          /**< the grid nodes' positions, MPGM_DIM each [m]    */
  mpgm_kdtree *tree;   /**< over gx: the candidates of the clouds           */
  mpgm_clouds *clouds; /**< the clouds and their shape functions            */
  int *perm;           /**< reorder of the particles (mpgm_points_sort)      */
  double *pscr;        /**< scratch, MPGM_DIM per point                     */
  long step;           /**< steps begun (for messages)                     */
  mpgm_cpls *cpls;     /**< CPLS (shape.kind cpls): the nodal velocities by
                            least squares, its workspace                  */
  mpgm_conn_par par_build; /**< staging of the functions built in parallel */
  mpgm_conn_task tail; /**< staging of a tracer's functions                 */
  double *sum;         /**< 3-D: scratch of the projection's run sums        */
  int nsum;            /**< nodes sum has room for                           */
  /* a run on many processes (distributed.c); NULL / 0 on one */
  mpgm_pgrid *pg;      /**< the grid's nodes partitioned over the processes  */
  int pcap;            /**< points (material + tracers) pcell, pxi, perm and
                            pscr have room for                             */
  int *xijk;           /**< scratch of the sums: a node's (i, j, k) each     */
  int nx;              /**< nodes xijk has room for                          */
  int nstep;           /**< nodes of the step (lglob's length)               */
  int *powner;         /**< the process that moves each probe in this step:
                            the owner of its cell at the step's start     */
  unsigned char *pskip;/**< per tracer: another process moves it          */
  unsigned char *xkeep;/**< migration's scratch: a point stays, and else    */
  int *xdest;          /**< the process it goes to; room for xcap points   */
  int xcap;
  double imb_cut;      /**< the points' imbalance the last cut left         */
  double *xbuf;        /**< scratch of the sums' values (mpgm_mpm_scratch)   */
  size_t xbufcap;
  unsigned char *nowned; /**< per node of the step: this process owns it  */
  int nowned_cap;
} mpm_data;

/* Many processes: the slabs are cut again by the points when the most
 * points on a process exceed the mean by a fifth (and a tenth more than
 * the last cut left: a spread the slabs cannot even out is not cut again
 * at every step). */
#define MPM_REBALANCE 1.2

/* The values per node the sums at shared nodes carry at most: mass,
 * momentum and inertia force. */
#define MPM_XW (1 + 2 * MPGM_DIM)

/* A run on many processes (distributed.c): the partition, and the points
 * of this process's cells only (create); points that left them sent to
 * their process (the start of every step); the sums at the nodes shared
 * with other processes (w values per node of the step; per grid node of
 * the light-node rule's masses); the probes (dist_probes: their mover,
 * each the process of its cell at the step's start, found with sync 0 as
 * the step begins; its values given to every process with sync 1 as the
 * step ends); the step's nodes this process owns (dist_owned, the
 * nodes' `owned`); each a no-op on one process. dist_migrate also cuts
 * the partition again when the points have drifted apart
 * (MPM_REBALANCE). */
/* The scenes MPM runs on many processes (mpgm_frontend_type.check). */
int mpgm_mpm_check(mpgm_ctx *ctx, const mpgm_scene *s);
int mpgm_mpm_dist_create(const mpgm_fe_view *v, mpm_data *d);
int mpgm_mpm_dist_migrate(const mpgm_fe_view *v, mpm_data *d);
int mpgm_mpm_node_sums(void *self, mpgm_ctx *ctx, int w, double *val);
int mpgm_mpm_dist_light(const mpgm_fe_view *v, mpm_data *d);
int mpgm_mpm_dist_probes(const mpgm_fe_view *v, mpm_data *d, int sync);
int mpgm_mpm_dist_owned(const mpgm_fe_view *v, mpm_data *d);
/* Scratch of n doubles kept from step to step (NULL, with the error set,
 * when out of memory); valid until the next call. */
double *mpgm_mpm_scratch(mpgm_ctx *ctx, mpm_data *d, size_t n);
void mpgm_mpm_dist_free(mpm_data *d);

/* Projection (38)-(41) with the final shape functions (project.c). */
int mpgm_mpm_project(const mpgm_fe_view *v, mpm_data *d);

#endif
