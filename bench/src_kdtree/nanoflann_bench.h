/* nanoflann_bench.h -- C interface to the nanoflann side of bench_kdtree
 * (nanoflann_bench.cpp, compiled only when nanoflann.hpp is found). */
#ifndef NANOFLANN_BENCH_H
#define NANOFLANN_BENCH_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** NANOFLANN_VERSION of the header (0x143 = 1.4.3). */
int nf_version(void);
/** Build a nanoflann tree over n borrowed points xy (stride 2). */
void *nf_create(const double *xy, int n, int leaf);
void nf_destroy(void *b);
/** Sorted radius search (d2 < radius^2, nanoflann's open ball) from each of
 *  the nq query points q; returns the total of the counts, *sum_d2 the sum
 *  of the largest d2 of each query (a checksum). */
long nf_radius_all(void *b, const double *q, int nq, double radius, double *sum_d2);
/** k nearest of each query into idx, d2 (k entries, reused); returns the
 *  sum of the k-th d2 (a checksum). */
double nf_knn_all(void *b, const double *q, int nq, int k, uint32_t *idx, double *d2);

#ifdef __cplusplus
}
#endif
#endif
