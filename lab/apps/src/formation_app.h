// The common part of the moving built-in apps (gather, circle,
// leader_follow): in a COOPERATIVE epoch every robot plans a target for
// every member from the map, turns the targets into straight segments,
// shortens them with the collision-avoidance rule (collision_avoidance.h) and drives its own segment;
// in an AUTONOMOUS epoch it holds still. Internal to lab/apps.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "syrof/app/app.h"
#include "syrof/lab/apps/formation.h"
#include "syrof/lab/apps/collision_avoidance.h"

namespace syrof::lab::apps {

/// Shorter moves than this are not worth a maneuver: the robot stops.
inline constexpr double kSmallestMoveM = 0.005;

/// A MOVE_TO must reach its end within this fraction of the maneuver, so the
/// robot arrives (and stops) before the maneuver ends.
inline constexpr double kArrivalFraction = 0.8;

/// Robots closer than the safety clearance plus this slide around each
/// other when their straight paths collide (SlideAroundNeighbours).
inline constexpr double kSlideZoneM = 0.05;

class FormationApp : public app::App {
 public:
  app::CallStatus Init(const syrof_app_info& info, app::Platform& platform, uint8_t& global_state) override;
  app::CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t& global_state,
                           uint32_t clock_ms) override;
  app::CallStatus EndOfRound(const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t clock_ms) override;

 protected:
  explicit FormationApp(double margin_m) : margin_m_(margin_m) {}

  /// Sets targets[i] (metres) for every member i of `members` (the map's
  /// members in increasing id order; `targets` arrives holding each
  /// member's own position, i.e. "stay"). Returns false to hold every robot
  /// still this epoch (a query refused the input). Runs on every robot with
  /// the same map, so it must be a deterministic function of the map and
  /// of what every robot knows alike (parameters, arena).
  virtual bool PlanTargets(const syrof_ldmap& ldmap, std::span<const syrof_queries_member> members,
                           std::span<Position> targets) = 0;

  /// Called in AUTONOMOUS epochs, before the robot holds still.
  virtual void HoldStill(const syrof_ldmap& ldmap) { (void)ldmap; }

  app::Platform& platform() { return *platform_; }
  const syrof_app_info& info() const { return info_; }
  ArenaSize arena() const { return {info_.arena_width_m, info_.arena_height_m}; }
  double body_radius_m() const { return info_.body_radius_m; }
  double maneuver_s() const;

 private:
  // Sets `command` for this robot's move in the epoch `ldmap` starts.
  void PlanCommand(syrof_car_command& command, const syrof_ldmap& ldmap);

  double margin_m_;
  syrof_app_info info_{};
  app::Platform* platform_ = nullptr;
  // Per-epoch scratch, kept to avoid allocating once the swarm's size is seen.
  std::vector<syrof_queries_member> members_;
  std::vector<Position> targets_;
  std::vector<Segment> segments_;
};

}  // namespace syrof::lab::apps
