#include "syrof/firmware/swarm/round_skew.h"

#include <algorithm>
#include <utility>

namespace syrof::firmware::swarm {

lab::metrics::SkewStats RoundStartSkew(std::span<const std::vector<int64_t>> send_ns, int64_t period_ns,
                                       int64_t from_ns) {
  if (send_ns.size() < 2 || send_ns[0].empty() || period_ns <= 0) return {};
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
  return lab::metrics::SkewOf(std::move(skews));
}

}  // namespace syrof::firmware::swarm
