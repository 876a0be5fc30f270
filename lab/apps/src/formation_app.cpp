#include "formation_app.h"

#include <algorithm>

#include "target_matching.h"
#include "syrof/app/commands.h"

namespace syrof::lab::apps {

app::CallStatus FormationApp::Init(const syrof_app_info& info, app::Platform& platform, uint8_t& global_state) {
  info_ = info;
  platform_ = &platform;
  members_.reserve(info.swarm_size);
  targets_.reserve(info.swarm_size);
  segments_.reserve(info.swarm_size);
  global_state = 0;
  return app::CallStatus::Ok();
}

double FormationApp::maneuver_s() const {
  return static_cast<double>(std::max<uint32_t>(info_.maneuver_ms, 1)) / 1000.0;
}

app::CallStatus FormationApp::NewRound(syrof_car_command& command, const syrof_ldmap& ldmap,
                                       uint8_t& /*global_state*/, uint32_t /*clock_ms*/) {
  PlanCommand(command, ldmap);
  return app::CallStatus::Ok();
}

void FormationApp::PlanCommand(syrof_car_command& command, const syrof_ldmap& ldmap) {
  command = syrof_car_command{};
  command.kind = SYROF_COMMAND_STOP;
  if (platform_ == nullptr || ldmap.members == nullptr || ldmap.member_count == 0) return;
  if (ldmap.mode != SYROF_MODE_COOPERATIVE) {
    // Another robot's map may differ from this one, so a plan made here
    // need not match anyone else's: holding still is the safe choice.
    HoldStill(ldmap);
    return;
  }
  const syrof_member_state* self = app::FindMember(ldmap, ldmap.self_id);
  if (self == nullptr) return;
  const size_t self_index = static_cast<size_t>(self - ldmap.members);

  const size_t count = ldmap.member_count;
  members_.resize(count);
  syrofMembersForQueries(&ldmap, members_.data());
  targets_.resize(count);
  for (size_t i = 0; i < count; ++i) targets_[i] = MemberPosition(members_[i]);
  if (!PlanTargets(ldmap, members_, targets_)) return;

  // Every member's move, as every robot computes it from the same map.
  const double longest_move_m = kArrivalFraction * info_.max_speed_mps * maneuver_s();
  segments_.resize(count);
  for (size_t i = 0; i < count; ++i) {
    const Position start = MemberPosition(members_[i]);
    const Position end = ClampIntoArena(targets_[i], arena(), body_radius_m(), margin_m_);
    segments_[i] = Truncate({start, end}, longest_move_m);
  }
  const double clearance_m = 2.0 * body_radius_m() + margin_m_;
  SlideAroundNeighbours(segments_, clearance_m, kSlideZoneM);
  for (Segment& segment : segments_) {
    // Sliding may point a segment at a wall.
    segment.end = ClampIntoArena(segment.end, arena(), body_radius_m(), margin_m_);
    segment = Truncate(segment, longest_move_m);
  }
  LimitSegments(segments_, clearance_m);

  const Segment& own = segments_[self_index];
  const double length_m = SegmentLengthM(own);
  if (length_m < kSmallestMoveM) return;
  const double speed_mps = std::min<double>(info_.max_speed_mps, length_m / (kArrivalFraction * maneuver_s()));
  command = app::MoveToCommand(static_cast<float>(own.end.x_m), static_cast<float>(own.end.y_m),
                               static_cast<float>(speed_mps));
}

app::CallStatus FormationApp::EndOfRound(const syrof_ldmap& /*ldmap*/, uint8_t& /*global_state*/,
                                         uint32_t /*clock_ms*/) {
  return app::CallStatus::Ok();
}

}  // namespace syrof::lab::apps
