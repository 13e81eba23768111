// nanoflann_bench.cpp -- the nanoflann side of bench_kdtree (C interface in
// nanoflann_bench.h). A nanoflann KDTreeSingleIndexAdaptor over the same
// borrowed interleaved array (stride 2), L2_Simple metric, DIM = 2, uint32
// indices: the configuration nanoflann's README recommends for 2-D points.
// Radius searches ask for sorted results (as ours returns) and reuse one
// result vector; kNN uses knnSearch into caller buffers.
#include <nanoflann.hpp>

#include <cstdint>
#include <vector>

#include "nanoflann_bench.h"

namespace {

struct Cloud {
  const double *xy;
  size_t n;
  size_t kdtree_get_point_count() const { return n; }
  double kdtree_get_pt(size_t i, size_t d) const { return xy[2 * i + d]; }
  template <class BBOX> bool kdtree_get_bbox(BBOX &) const { return false; }
};

typedef nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 2,
                                            uint32_t>
    Tree;

#if NANOFLANN_VERSION >= 0x150
typedef nanoflann::ResultItem<uint32_t, double> Match;
typedef nanoflann::SearchParameters Params;
#else
typedef std::pair<uint32_t, double> Match;
typedef nanoflann::SearchParams Params;
#endif

struct Bench {
  Cloud cloud;
  Tree *tree;
  std::vector<Match> matches;
};

} // namespace

extern "C" {

int nf_version(void) {
  return NANOFLANN_VERSION;
}

void *nf_create(const double *xy, int n, int leaf) {
  Bench *b = new Bench;
  b->cloud.xy = xy;
  b->cloud.n = (size_t)n;
  b->tree = new Tree(2, b->cloud, nanoflann::KDTreeSingleIndexAdaptorParams((size_t)leaf));
  b->matches.reserve(256);
  return b;
}

void nf_destroy(void *p) {
  Bench *b = static_cast<Bench *>(p);
  if (!b) return;
  delete b->tree;
  delete b;
}

long nf_radius_all(void *p, const double *q, int nq, double radius, double *sum_d2) {
  Bench *b = static_cast<Bench *>(p);
  Params params;
  params.sorted = true;
  const double r2 = radius * radius; // nanoflann takes the squared radius (L2)
  long total = 0;
  double s = 0;
  for (int k = 0; k < nq; k++) {
    const size_t m = b->tree->radiusSearch(q + 2 * (size_t)k, r2, b->matches, params);
    total += (long)m;
    if (m) s += b->matches[m - 1].second;
  }
  *sum_d2 = s;
  return total;
}

double nf_knn_all(void *p, const double *q, int nq, int k, uint32_t *idx, double *d2) {
  Bench *b = static_cast<Bench *>(p);
  double s = 0;
  for (int j = 0; j < nq; j++) {
    const size_t m = b->tree->knnSearch(q + 2 * (size_t)j, (size_t)k, idx, d2);
    if (m) s += d2[m - 1];
  }
  return s;
}

} // extern "C"
