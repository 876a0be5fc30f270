#include "syrof/firmware/swarm/stress_player.h"

#include <algorithm>

namespace syrof::firmware::swarm {

StressPlayer::StressPlayer(const lab::sim::StressOptions& options, int64_t duration_ns, uint16_t robots)
    : plan_(lab::sim::PlanStalls(options, duration_ns, robots)), stopped_until_(robots, -1) {}

int64_t StressPlayer::Play(int64_t world_ns, const Running& running, const Signal& signal) {
  for (uint16_t robot = 0; robot < stopped_until_.size(); ++robot) {
    if (stopped_until_[robot] < 0 || stopped_until_[robot] > world_ns) continue;
    stopped_until_[robot] = -1;
    if (running(robot)) signal(robot, false);
  }
  int64_t world_stall_ns = 0;
  while (next_ < plan_.size() && plan_[next_].at_ns <= world_ns) {
    const lab::sim::Stall& stall = plan_[next_++];
    if (stall.target == lab::sim::kStallWorld) {
      world_stall_ns = std::max(world_stall_ns, stall.duration_ns);
      ++world_stalls_;
      continue;
    }
    if (stall.target >= stopped_until_.size() || !running(stall.target)) continue;
    int64_t& until = stopped_until_[stall.target];
    if (until < 0) {
      signal(stall.target, true);
      ++robot_stalls_;
    }
    // Overlapping stalls of one robot make one longer stop.
    until = std::max(until, stall.at_ns + stall.duration_ns);
  }
  return world_stall_ns;
}

void StressPlayer::EndAll(const Running& running, const Signal& signal) {
  next_ = plan_.size();
  for (uint16_t robot = 0; robot < stopped_until_.size(); ++robot) {
    if (stopped_until_[robot] < 0) continue;
    stopped_until_[robot] = -1;
    if (running(robot)) signal(robot, false);
  }
}

}  // namespace syrof::firmware::swarm
