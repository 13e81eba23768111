/* bench_timers.c -- cost of mpgm's timers: N timer start/stop pairs (two
 * clock reads each, as every timed region of a run) on one context, best of
 * 5 rounds; prints the nanoseconds per clock read. */
#include <stdio.h>
#include <stdlib.h>

#include "mpgm_base.h"

int main(int argc, char **argv) {
  const long n = argc > 1 ? atol(argv[1]) : 2000000;
  if (n <= 0) {
    fprintf(stderr, "usage: bench_timers [PAIRS > 0]\n");
    return 2;
  }
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  double best = 1e300;
  for (int round = 0; round < 5; round++) {
    const double t0 = mpgm_wtime();
    for (long i = 0; i < n; i++) {
      mpgm_timer_start(&ctx, MPGM_T_ASSEMBLY);
      mpgm_timer_stop(&ctx, MPGM_T_ASSEMBLY);
    }
    const double el = mpgm_wtime() - t0;
    if (el < best) best = el;
  }
  /* the accumulated time keeps the loop from being optimised away */
  printf("%.3f ns per clock read (%ld timer pairs, best of 5; accumulated %.3g s)\n",
         1e9 * best / (2.0 * (double)n), n, ctx.t[MPGM_T_ASSEMBLY]);
  return 0;
}
