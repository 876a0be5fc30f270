#include "round_grid.h"

#include <algorithm>
#include <cstddef>

namespace syrof::sim_dds {

int64_t RoundGrid::RoundAt(int64_t monotonic_ns) const {
  const int64_t since = monotonic_ns - origin_ns_;
  return since >= 0 ? since / round_ns_ : -((-since + round_ns_ - 1) / round_ns_);
}

void RoundGrid::FollowRobots(const std::function<bool(uint16_t)>& running) {
  std::vector<int64_t> origins;
  for (uint16_t id = 0; id < robot_origins_.size(); ++id) {
    if (running(id) && robot_origins_[id]) origins.push_back(*robot_origins_[id]);
  }
  if (origins.empty()) return;
  std::nth_element(origins.begin(), origins.begin() + static_cast<std::ptrdiff_t>(origins.size() / 2), origins.end());
  origin_ns_ = origins[origins.size() / 2];
}

}  // namespace syrof::sim_dds
