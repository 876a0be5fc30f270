// The robots' rounds on the DDS world's clock (CLOCK_MONOTONIC, one host).
// On one grid (no alignment) round r starts at start + r * alpha. Aligning
// robots move their boundaries together and number their own rounds, so the
// world follows them: the origin is the median over running robots of (when
// a robot's round report went out) - round * alpha, from each robot's newest
// report. Pure; internal to sim_dds.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace syrof::sim_dds {

class RoundGrid {
 public:
  /// A grid of `radio_round_ns` (> 0) rounds for `robots` robots, its origin at 0.
  RoundGrid(int64_t radio_round_ns, uint16_t robots) : round_ns_(radio_round_ns), robot_origins_(robots) {}

  /// Sets the origin: round 0 starts at `origin_ns`.
  void Start(int64_t origin_ns) { origin_ns_ = origin_ns; }
  int64_t origin_ns() const { return origin_ns_; }
  int64_t round_ns() const { return round_ns_; }

  /// The round `monotonic_ns` falls in (floor: negative before the origin).
  int64_t RoundAt(int64_t monotonic_ns) const;
  /// When round `round` starts.
  int64_t StartOf(int64_t round) const { return origin_ns_ + round * round_ns_; }

  /// Robot `robot` reported its round `round`, activated at `activation_ns`.
  void NoteRound(uint16_t robot, int64_t round, int64_t activation_ns) {
    robot_origins_[robot] = activation_ns - round * round_ns_;
  }
  /// Moves the origin to the median of the origins of the robots that
  /// reported a round and that `running` says run now (the upper one of an
  /// even count); unchanged when there is none.
  void FollowRobots(const std::function<bool(uint16_t)>& running);

 private:
  const int64_t round_ns_;
  int64_t origin_ns_ = 0;
  std::vector<std::optional<int64_t>> robot_origins_;
};

}  // namespace syrof::sim_dds
