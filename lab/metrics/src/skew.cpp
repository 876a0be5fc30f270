#include <algorithm>
#include <cmath>

#include "syrof/lab/metrics/metrics.h"

namespace syrof::lab::metrics {

namespace {

// The nearest rank of `fraction` (0, 1] in `sorted` (not empty).
int64_t NearestRank(const std::vector<int64_t>& sorted, double fraction) {
  const auto rank = static_cast<size_t>(std::ceil(fraction * static_cast<double>(sorted.size())));
  return sorted[std::min(sorted.size(), std::max<size_t>(rank, 1)) - 1];
}

double Microseconds(int64_t ns) { return static_cast<double>(ns) * 1e-3; }

}  // namespace

SkewStats SkewOf(std::vector<int64_t> skews_ns) {
  SkewStats stats;
  if (skews_ns.empty()) return stats;
  std::sort(skews_ns.begin(), skews_ns.end());
  stats.samples = static_cast<int64_t>(skews_ns.size());
  stats.p50_us = Microseconds(NearestRank(skews_ns, 0.50));
  stats.p99_us = Microseconds(NearestRank(skews_ns, 0.99));
  stats.max_us = Microseconds(skews_ns.back());
  return stats;
}

}  // namespace syrof::lab::metrics
