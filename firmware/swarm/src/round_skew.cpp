#include "syrof/firmware/swarm/round_skew.h"

#include <algorithm>

namespace syrof::firmware::swarm {

SkewStats RoundStartSkew(std::span<const std::vector<int64_t>> send_ns, int64_t period_ns, int64_t from_ns) {
  SkewStats stats;
  if (send_ns.size() < 2 || send_ns[0].empty() || period_ns <= 0) return stats;
  const std::vector<int64_t>& reference = send_ns[0];
  std::vector<int64_t> skews;
  for (size_t robot = 1; robot < send_ns.size(); ++robot) {
    for (const int64_t t : send_ns[robot]) {
      if (t < from_ns) continue;
      // The nearest reference beacon, on either side.
      const auto after = std::lower_bound(reference.begin(), reference.end(), t);
      int64_t nearest = INT64_MAX;
      if (after != reference.end()) nearest = *after - t;
      if (after != reference.begin()) nearest = std::min(nearest, t - *(after - 1));
      int64_t folded = nearest % period_ns;
      if (folded > period_ns / 2) folded = period_ns - folded;
      skews.push_back(folded);
    }
  }
  if (skews.empty()) return stats;
  std::sort(skews.begin(), skews.end());
  stats.samples = static_cast<int64_t>(skews.size());
  stats.median_ns = skews[skews.size() / 2];
  stats.p95_ns = skews[std::min(skews.size() - 1, skews.size() * 95 / 100)];
  stats.max_ns = skews.back();
  return stats;
}

}  // namespace syrof::firmware::swarm
