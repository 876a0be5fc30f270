// Where an emulated robot's rounds lie on the world's radio-round grid
// (docs/firmware.md, "One start for every robot"). The swarm host sends a
// held robot its Start frame at a round boundary of world time, and the
// robot's clock starts there: its boundaries are that instant (plus the few
// milliseconds the frame takes) and every radio round after. The host
// never sees a boundary itself, only when each beacon reaches it, later by
// the guest's and its own scheduling; from that instant it names the round
// the beacon was sent in, as the lab and the DDS world key the channel's
// loss, and the instant the lab's radio would deliver it.
//
// Pure: world times in nanoseconds (double: the host's world clock is
// fractional), no clocks read here.
#pragma once

#include <cstdint>
#include <map>
#include <optional>

namespace syrof::firmware::swarm {

/// Where a robot was switched on.
struct SwitchOn {
  int64_t round = 0;      ///< the world's round whose boundary it was switched on at
  double world_ns = 0;    ///< the world's time its Start frame was sent (a little after that boundary)
};

/// How much earlier than its switch-on grid a robot's boundary may fall (a
/// robot that aligns its rounds moves them) and its beacon still count for
/// that round.
inline constexpr double kEarlyToleranceNs = 5e6;

/// The world round a beacon reaching the host at world time `arrival_ns`
/// was sent in: the switch-on round plus the whole rounds since the Start
/// frame. Right for a beacon up to a round (less the tolerance) late, and
/// after a pause (the guest's clock ran on).
int64_t BeaconRound(const SwitchOn& on, double arrival_ns, int64_t period_ns);

/// The world time of the robot's boundary that began `round` (its beacon of
/// that round is sent then).
double BoundaryOf(const SwitchOn& on, int64_t round, int64_t period_ns);

/// A robot's boundaries not yet recorded: the world round each beacon was
/// sent in (BeaconRound) to the host instant it arrived, the first beacon
/// of a round kept.
using BoundariesByRound = std::map<int64_t, int64_t>;

/// Round `round`'s boundary from `boundaries`, if its beacon arrived; that
/// round's and every earlier round's entries are dropped, a later round's
/// (a beacon of the next round already in) kept.
std::optional<int64_t> TakeBoundary(BoundariesByRound& boundaries, int64_t round);

}  // namespace syrof::firmware::swarm
