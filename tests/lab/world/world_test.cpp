// The lab's bodies: kinematic limits, rover kinematics, and contacts on
// constructed encounters whose contact time follows from the limits.
#include "syrof/lab/world/world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "syrof/base/split_mix64.h"

namespace syrof::lab::world {
namespace {

constexpr int64_t kStepNs = 10'000'000;
constexpr double kDt = 0.01;

// The lab's default kinds (DefaultKindSpec, spelled out: the
// scenario loader is not linked here).
KindSpec OmniSpec() { return KindSpec{0.10, 0.5, 1.0, 3.0, 0.16}; }
KindSpec RoverSpec() { return KindSpec{0.12, 0.4, 0.8, 3.0, 0.16}; }

ArenaSpec Arena(double width_m, double height_m) {
  ArenaSpec arena;
  arena.width_m = width_m;
  arena.height_m = height_m;
  return arena;
}

BodySpec Omni(uint16_t id, double x_m, double y_m, BodyPresence presence = BodyPresence::kActive) {
  return BodySpec{id, RobotKind::kOmni, OmniSpec(), x_m, y_m, 0.0, presence};
}

BodySpec RoverAt(uint16_t id, double x_m, double y_m, double heading_rad) {
  return BodySpec{id, RobotKind::kRover, RoverSpec(), x_m, y_m, heading_rad, BodyPresence::kActive};
}

motion::DriveCommand OmniDrive(double vx_mps, double vy_mps, double yaw_rate_radps = 0) {
  motion::DriveCommand drive;
  drive.kind = motion::DriveKind::kOmni;
  drive.vx_mps = static_cast<float>(vx_mps);
  drive.vy_mps = static_cast<float>(vy_mps);
  drive.yaw_rate_radps = static_cast<float>(yaw_rate_radps);
  return drive;
}

motion::DriveCommand Wheels(double left_mps, double right_mps) {
  motion::DriveCommand drive;
  drive.kind = motion::DriveKind::kWheels;
  drive.left_mps = static_cast<float>(left_mps);
  drive.right_mps = static_cast<float>(right_mps);
  return drive;
}

// Drive setpoints are floats: the value a double setpoint arrives as.
double AsFloat(double value) { return static_cast<float>(value); }

double Gap(const World& world, uint16_t a, uint16_t b) {
  const BodyState& first = world.state(a);
  const BodyState& second = world.state(b);
  return std::hypot(second.x_m - first.x_m, second.y_m - first.y_m) - world.body_radius_m(a) -
         world.body_radius_m(b);
}

// Steps `steps` times from step `first` on, collecting every contact.
struct Events {
  std::vector<Contact> contacts;
  std::vector<WallContact> wall_contacts;
};

void StepMany(World& world, int first, int steps, Events& run) {
  for (int step = first; step < first + steps; ++step) {
    world.Step(step * kStepNs, kDt);
    run.contacts.insert(run.contacts.end(), world.new_contacts().begin(), world.new_contacts().end());
    run.wall_contacts.insert(run.wall_contacts.end(), world.new_wall_contacts().begin(),
                             world.new_wall_contacts().end());
  }
}

TEST(WorldTest, HeadOnOmniPairRecordsExactlyOneContactAndDoesNotPassThrough) {
  // Each accelerates at 1 m/s^2 for 0.5 s (0.125 m), then cruises at 0.5 m/s;
  // the 0.803 m gap closes when each has gone 0.4015 m, at t = 1.053 s: the
  // step ending at 1.06 s.
  const std::vector<BodySpec> bodies{Omni(0, 1.0, 2.0), Omni(1, 2.003, 2.0)};
  World world(Arena(4, 4), bodies);
  world.SetDrive(0, OmniDrive(0.5, 0));
  world.SetDrive(1, OmniDrive(-0.5, 0));
  Events run;
  double worst_gap = std::numeric_limits<double>::infinity();

  for (int step = 1; step <= 300; ++step) {
    StepMany(world, step, 1, run);
    worst_gap = std::min(worst_gap, Gap(world, 0, 1));
  }

  ASSERT_EQ(run.contacts.size(), 1u);
  EXPECT_EQ(run.contacts[0].a, 0);
  EXPECT_EQ(run.contacts[0].b, 1);
  EXPECT_EQ(run.contacts[0].time_ns, 106 * kStepNs);
  EXPECT_EQ(world.contacts(), 1u);
  EXPECT_GE(worst_gap, -1e-9);
  EXPECT_LT(world.state(0).x_m, world.state(1).x_m);
  EXPECT_NEAR(world.state(0).vx_mps, 0.0, 1e-9);  // pushing, but not moving
  EXPECT_NEAR(world.min_separation_m(), 0.0, 1e-12);
  EXPECT_TRUE(run.wall_contacts.empty());
}

TEST(WorldTest, GlancingPassThatMissesRecordsNoContact) {
  // Centre lines 0.21 m apart: the discs (0.1 m each) pass 1 cm apart.
  const std::vector<BodySpec> bodies{Omni(0, 1.0, 2.0), Omni(1, 3.0, 2.21)};
  World world(Arena(4, 4), bodies);
  world.SetDrive(0, OmniDrive(0.5, 0));
  world.SetDrive(1, OmniDrive(-0.5, 0));
  Events run;

  StepMany(world, 1, 500, run);

  EXPECT_TRUE(run.contacts.empty());
  EXPECT_EQ(world.contacts(), 0u);
  EXPECT_NEAR(world.min_separation_m(), 0.01, 1e-9);
  EXPECT_GT(world.state(0).x_m, 3.0);  // they did pass each other
}

TEST(WorldTest, RobotDrivenIntoAWallRecordsOneWallContactAndStaysInside) {
  // The wall is 0.403 m ahead of the disc: reached at t = 1.056 s.
  const std::vector<BodySpec> bodies{Omni(0, 3.497, 2.0)};
  World world(Arena(4, 4), bodies);
  world.SetDrive(0, OmniDrive(0.5, 0));
  Events run;
  double largest_x = 0;

  for (int step = 1; step <= 300; ++step) {
    StepMany(world, step, 1, run);
    largest_x = std::max(largest_x, world.state(0).x_m);
  }

  ASSERT_EQ(run.wall_contacts.size(), 1u);
  EXPECT_EQ(run.wall_contacts[0].robot, 0);
  EXPECT_EQ(run.wall_contacts[0].time_ns, 106 * kStepNs);
  EXPECT_EQ(world.wall_contacts(), 1u);
  EXPECT_LE(largest_x, 3.9 + 1e-12);
  EXPECT_EQ(world.state(0).vx_mps, 0.0);
  EXPECT_TRUE(run.contacts.empty());
}

TEST(WorldTest, LeavingAWallAndComingBackIsASecondWallContact) {
  const std::vector<BodySpec> bodies{Omni(0, 3.8, 2.0)};
  World world(Arena(4, 4), bodies);
  Events run;
  world.SetDrive(0, OmniDrive(0.5, 0));
  StepMany(world, 1, 100, run);
  world.SetDrive(0, OmniDrive(-0.5, 0));
  StepMany(world, 101, 100, run);

  world.SetDrive(0, OmniDrive(0.5, 0));
  StepMany(world, 201, 200, run);

  EXPECT_EQ(world.wall_contacts(), 2u);
  EXPECT_EQ(run.wall_contacts.size(), 2u);
}

TEST(WorldTest, ThreeRobotsMeetingInAPileSeparateAndTouchOnce) {
  std::vector<BodySpec> bodies;
  for (uint16_t id = 0; id < 3; ++id) {
    const double angle = 2 * std::numbers::pi * id / 3;
    bodies.push_back(Omni(id, 2 + 0.5 * std::cos(angle), 2 + 0.5 * std::sin(angle)));
  }
  World world(Arena(4, 4), bodies);
  for (uint16_t id = 0; id < 3; ++id) {
    const double angle = 2 * std::numbers::pi * id / 3;
    world.SetDrive(id, OmniDrive(-0.5 * std::cos(angle), -0.5 * std::sin(angle)));
  }
  Events run;
  double worst_gap = std::numeric_limits<double>::infinity();

  for (int step = 1; step <= 300; ++step) {
    StepMany(world, step, 1, run);
    worst_gap = std::min({worst_gap, Gap(world, 0, 1), Gap(world, 0, 2), Gap(world, 1, 2)});
  }

  EXPECT_GE(worst_gap, -1e-3);
  EXPECT_LE(world.max_overlap_m(), 1e-9);  // separated at the end of every step
  ASSERT_EQ(run.contacts.size(), 3u);
  EXPECT_EQ(run.contacts[0].a, 0);
  EXPECT_EQ(run.contacts[0].b, 1);
  EXPECT_EQ(run.contacts[1].a, 0);
  EXPECT_EQ(run.contacts[1].b, 2);
  EXPECT_EQ(run.contacts[2].a, 1);
  EXPECT_EQ(run.contacts[2].b, 2);
  EXPECT_EQ(run.contacts[0].time_ns, run.contacts[2].time_ns);  // symmetric: all at once
}

TEST(WorldTest, StoppedBodyIsAnObstacleThatDoesNotMove) {
  const std::vector<BodySpec> bodies{Omni(0, 1.0, 2.0), Omni(1, 2.0, 2.0, BodyPresence::kStopped)};
  World world(Arena(4, 4), bodies);
  world.SetDrive(0, OmniDrive(0.5, 0));
  world.SetDrive(1, OmniDrive(-0.5, 0));  // ignored: stopped
  Events run;

  StepMany(world, 1, 400, run);

  EXPECT_EQ(world.state(1).x_m, 2.0);
  EXPECT_EQ(world.state(1).y_m, 2.0);
  EXPECT_EQ(world.state(1).vx_mps, 0.0);
  EXPECT_NEAR(world.state(0).x_m, 1.8, 1e-9);
  EXPECT_EQ(world.contacts(), 1u);
}

TEST(WorldTest, CrashedBodyStopsAtTheNextStepAndTheImuFeelsIt) {
  const std::vector<BodySpec> bodies{Omni(0, 1.0, 2.0)};
  World world(Arena(4, 4), bodies);
  world.SetDrive(0, OmniDrive(0.5, 0));
  Events run;
  StepMany(world, 1, 100, run);
  const double x_at_crash = world.state(0).x_m;

  world.SetPresence(0, BodyPresence::kStopped);
  StepMany(world, 101, 1, run);

  EXPECT_EQ(world.presence(0), BodyPresence::kStopped);
  EXPECT_EQ(world.state(0).x_m, x_at_crash);
  EXPECT_EQ(world.state(0).vx_mps, 0.0);
  EXPECT_NEAR(world.state(0).ax_mps2, -0.5 / kDt, 1e-9);
}

TEST(WorldTest, AbsentBodiesAreIgnored) {
  const std::vector<BodySpec> bodies{Omni(0, 1.0, 2.0), Omni(1, 2.0, 2.0, BodyPresence::kAbsent)};
  World world(Arena(4, 4), bodies);
  world.SetDrive(0, OmniDrive(0.5, 0));
  world.SetDrive(1, OmniDrive(0.5, 0));
  Events run;

  StepMany(world, 1, 400, run);

  EXPECT_GT(world.state(0).x_m, 2.5);  // straight through
  EXPECT_EQ(world.state(1).x_m, 2.0);
  EXPECT_EQ(world.contacts(), 0u);
  EXPECT_EQ(world.min_separation_m(), std::numeric_limits<double>::infinity());
}

TEST(WorldTest, JoiningOnTopOfAnotherBodyIsAContactAndIsSeparated) {
  const std::vector<BodySpec> bodies{Omni(0, 2.0, 2.0), Omni(1, 2.1, 2.0, BodyPresence::kAbsent)};
  World world(Arena(4, 4), bodies);
  Events run;
  StepMany(world, 1, 10, run);
  EXPECT_EQ(world.contacts(), 0u);

  world.SetPresence(1, BodyPresence::kActive);
  StepMany(world, 11, 1, run);

  ASSERT_EQ(run.contacts.size(), 1u);
  EXPECT_EQ(run.contacts[0].time_ns, 11 * kStepNs);
  EXPECT_NEAR(Gap(world, 0, 1), 0.0, 1e-9);
}

TEST(WorldTest, OverlapAtPlacementIsSeparatedButNotCounted) {
  const std::vector<BodySpec> bodies{Omni(0, 2.0, 2.0), Omni(1, 2.15, 2.0), Omni(2, 0.05, 2.0)};
  World world(Arena(4, 4), bodies);
  Events run;

  StepMany(world, 1, 1, run);

  EXPECT_EQ(world.contacts(), 0u);
  EXPECT_EQ(world.wall_contacts(), 0u);
  EXPECT_NEAR(Gap(world, 0, 1), 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(world.state(2).x_m, 0.1);
}

TEST(WorldTest, MaxOverlapRecordsTheDeepestOverlapLeftAfterAStep) {
  // Two stopped bodies are never pushed: placed 0.15 m apart (radii 0.1 m),
  // they overlap by 0.05 m after every step, and the world says so.
  const std::vector<BodySpec> bodies{Omni(0, 2.0, 2.0, BodyPresence::kStopped),
                                     Omni(1, 2.15, 2.0, BodyPresence::kStopped)};
  World world(Arena(4, 4), bodies);
  Events run;
  EXPECT_EQ(world.max_overlap_m(), 0.0);

  StepMany(world, 1, 3, run);

  EXPECT_NEAR(world.max_overlap_m(), 0.05, 1e-12);
  EXPECT_EQ(world.min_separation_m(), 0.0);  // clamped: it cannot show the overlap
}

TEST(WorldTest, OmniVelocitySlewsAtMaxAccelAndIsCappedAtMaxSpeed) {
  const std::vector<BodySpec> bodies{Omni(0, 0.5, 0.5)};
  World world(Arena(10, 10), bodies);
  world.SetDrive(0, OmniDrive(3.0, 4.0, -10.0));  // faster than allowed in both
  Events run;

  StepMany(world, 1, 1, run);
  const BodyState first = world.state(0);
  StepMany(world, 2, 99, run);
  const BodyState later = world.state(0);

  EXPECT_NEAR(first.vx_mps, 0.006, 1e-12);  // 0.01 m/s along (0.6, 0.8)
  EXPECT_NEAR(first.vy_mps, 0.008, 1e-12);
  EXPECT_NEAR(first.ax_mps2, 0.6, 1e-9);
  EXPECT_NEAR(first.ay_mps2, 0.8, 1e-9);
  EXPECT_NEAR(first.x_m, 0.5 + 0.5 * 0.006 * kDt, 1e-12);
  EXPECT_DOUBLE_EQ(first.yaw_rate_radps, -3.0);
  EXPECT_NEAR(std::hypot(later.vx_mps, later.vy_mps), 0.5, 1e-12);
  EXPECT_NEAR(later.ax_mps2, 0.0, 1e-9);
}

TEST(WorldTest, RoverWheelsSlewAtMaxAccelAndAreCapped) {
  const std::vector<BodySpec> bodies{RoverAt(0, 2, 2, 0)};
  World world(Arena(4, 4), bodies);
  world.SetDrive(0, Wheels(1.0, -0.2));
  Events run;

  StepMany(world, 1, 1, run);
  const double left_after_one = world.left_wheel_mps(0);
  const double right_after_one = world.right_wheel_mps(0);
  StepMany(world, 2, 99, run);

  EXPECT_NEAR(left_after_one, 0.008, 1e-12);
  EXPECT_NEAR(right_after_one, -0.008, 1e-12);
  EXPECT_NEAR(world.left_wheel_mps(0), 0.4, 1e-12);
  EXPECT_NEAR(world.right_wheel_mps(0), AsFloat(-0.2), 1e-12);
}

TEST(WorldTest, RoverDrivesStraightAlongItsHeading) {
  const double heading = 0.5;
  const std::vector<BodySpec> bodies{RoverAt(0, 1, 1, heading)};
  World world(Arena(4, 4), bodies);
  world.SetDrive(0, Wheels(0.2, 0.2));
  Events run;

  StepMany(world, 1, 100, run);

  // A ramp of v / a (0.25 s) then cruising: v - v^2 / (2 a) in 1 s.
  const double speed = AsFloat(0.2);
  const double distance = speed - speed * speed / (2 * 0.8);
  EXPECT_NEAR(world.state(0).x_m, 1 + distance * std::cos(heading), 1e-9);
  EXPECT_NEAR(world.state(0).y_m, 1 + distance * std::sin(heading), 1e-9);
  EXPECT_DOUBLE_EQ(world.state(0).heading_rad, heading);
  EXPECT_NEAR(world.state(0).vx_mps, speed * std::cos(heading), 1e-12);
  EXPECT_NEAR(world.state(0).yaw_rate_radps, 0.0, 1e-12);
}

TEST(WorldTest, RoverSpinsInPlace) {
  const std::vector<BodySpec> bodies{RoverAt(0, 2, 2, 0)};
  World world(Arena(4, 4), bodies);
  world.SetDrive(0, Wheels(-0.08, 0.08));
  Events run;

  StepMany(world, 1, 100, run);

  EXPECT_NEAR(world.state(0).x_m, 2.0, 1e-12);
  EXPECT_NEAR(world.state(0).y_m, 2.0, 1e-12);
  // Each wheel ramps for v / a (0.1 s), then the rover spins at 2 v / b.
  const double rate = 2 * AsFloat(0.08) / 0.16;
  const double ramp_s = AsFloat(0.08) / 0.8;
  EXPECT_NEAR(world.state(0).yaw_rate_radps, rate, 1e-12);
  EXPECT_NEAR(world.state(0).heading_rad, rate * (1.0 - ramp_s / 2), 1e-8);
}

TEST(WorldTest, RoverArcHasRadiusHalfWheelBaseTimesSumOverDifference) {
  const std::vector<BodySpec> bodies{RoverAt(0, 2, 2, 0)};
  World world(Arena(4, 4), bodies);
  const double left = AsFloat(0.1);
  const double right = AsFloat(0.2);
  world.SetDrive(0, Wheels(left, right));
  Events run;
  StepMany(world, 1, 50, run);  // both wheels at speed after 0.25 s
  const double radius = 0.16 / 2 * (right + left) / (right - left);
  auto centre = [&] {
    const BodyState& state = world.state(0);
    return std::pair{state.x_m - radius * std::sin(state.heading_rad),
                     state.y_m + radius * std::cos(state.heading_rad)};
  };
  const auto first_centre = centre();

  StepMany(world, 51, 300, run);
  const auto later_centre = centre();

  EXPECT_NEAR(radius, 0.24, 1e-6);
  EXPECT_NEAR(later_centre.first, first_centre.first, 1e-9);
  EXPECT_NEAR(later_centre.second, first_centre.second, 1e-9);
  EXPECT_NEAR(world.state(0).yaw_rate_radps, (right - left) / 0.16, 1e-12);
}

TEST(WorldTest, MinSeparationIsTheSmallestGapEverSeen) {
  const std::vector<BodySpec> bodies{Omni(0, 1.0, 1.0), Omni(1, 2.0, 1.0), Omni(2, 1.0, 3.0)};
  World world(Arena(4, 4), bodies);
  EXPECT_EQ(world.min_separation_m(), std::numeric_limits<double>::infinity());
  Events run;

  StepMany(world, 1, 1, run);
  const double at_rest = world.min_separation_m();
  world.SetDrive(0, OmniDrive(0.2, 0));
  StepMany(world, 2, 100, run);
  const double closest = world.min_separation_m();
  world.SetDrive(0, OmniDrive(-0.2, 0));
  StepMany(world, 102, 200, run);

  // Out: a ramp of v / a then cruising, v - v^2 / 2 in 1 s; back: another
  // v^2 / 2 while reversing, then away.
  const double speed = AsFloat(0.2);
  EXPECT_DOUBLE_EQ(at_rest, 0.8);
  EXPECT_NEAR(closest, 0.8 - (speed - speed * speed / 2), 1e-9);
  EXPECT_NEAR(world.min_separation_m(), 0.8 - speed, 1e-9);
  EXPECT_GT(Gap(world, 0, 1), 0.7);  // moving away did not raise it
}

TEST(WorldTest, OneBodyHasNoSeparation) {
  const std::vector<BodySpec> bodies{Omni(0, 1.0, 1.0)};
  World world(Arena(4, 4), bodies);
  Events run;

  StepMany(world, 1, 10, run);

  EXPECT_EQ(world.min_separation_m(), std::numeric_limits<double>::infinity());
}

TEST(WorldTest, DriveOfTheWrongKindIsRejectedAsAStop) {
  const std::vector<BodySpec> bodies{Omni(0, 1.0, 1.0)};
  World world(Arena(4, 4), bodies);
  world.SetDrive(0, OmniDrive(0.5, 0));
  Events run;
  StepMany(world, 1, 10, run);

  world.SetDrive(0, Wheels(0.3, 0.3));
  StepMany(world, 11, 100, run);

  EXPECT_EQ(world.rejected_drives(), 1u);
  EXPECT_EQ(world.state(0).vx_mps, 0.0);
}

TEST(WorldTest, CheckWorldSpecSaysWhatIsWrongAndWhere) {
  const std::vector<BodySpec> good{Omni(0, 1.0, 1.0), Omni(1, 2.0, 2.0)};
  std::vector<BodySpec> misnumbered{Omni(0, 1.0, 1.0), Omni(2, 2.0, 2.0)};
  std::vector<BodySpec> no_radius{Omni(0, 1.0, 1.0)};
  no_radius[0].spec.body_radius_m = 0;
  std::vector<BodySpec> lost{Omni(0, 1.0, 1.0)};
  lost[0].y_m = std::numeric_limits<double>::infinity();

  auto said = [](const std::optional<Error>& error) { return error ? error->ToString() : std::string("ok"); };
  EXPECT_EQ(said(CheckWorldSpec(Arena(4, 4), good)), "ok");
  EXPECT_EQ(said(CheckWorldSpec(Arena(4, 4), misnumbered)), "body 1: id 2 is not its index");
  EXPECT_EQ(said(CheckWorldSpec(Arena(4, 4), no_radius)), "body 0: radius and limits must be > 0");
  EXPECT_EQ(said(CheckWorldSpec(Arena(4, 4), lost)), "body 0: pose must be finite");
  EXPECT_EQ(said(CheckWorldSpec(Arena(0, 4), std::vector<BodySpec>{})), "arena: width and height must be > 0");
}

// Building a World from a spec that fails the check, or naming a robot it
// does not have, is a caller's bug: the program stops with the reason.
TEST(WorldDeathTest, ConstructorStopsOnABadSpecWithTheReason) {
  const std::vector<BodySpec> misnumbered{Omni(1, 1.0, 1.0)};
  EXPECT_DEATH_IF_SUPPORTED(World(Arena(4, 4), misnumbered), "World: body 0: id 1 is not its index");
  EXPECT_DEATH_IF_SUPPORTED(World(Arena(0, 4), std::vector<BodySpec>{}), "World: arena: width and height");
}

TEST(WorldDeathTest, UnknownRobotAndBadStepStop) {
  const std::vector<BodySpec> bodies{Omni(0, 1.0, 1.0)};
  World world(Arena(4, 4), bodies);

  EXPECT_DEATH_IF_SUPPORTED(world.state(1), "SYROF_CHECK");
  EXPECT_DEATH_IF_SUPPORTED(world.SetDrive(1, OmniDrive(0, 0)), "SYROF_CHECK");
  EXPECT_DEATH_IF_SUPPORTED(world.Step(0, 0.0), "SYROF_CHECK");
}

TEST(WorldTest, TrueStateCarriesTheBodyState) {
  const std::vector<BodySpec> bodies{Omni(0, 1.0, 1.0)};
  World world(Arena(4, 4), bodies);
  world.SetDrive(0, OmniDrive(0.1, -0.2, 0.3));
  Events run;
  StepMany(world, 1, 5, run);

  const sensors::TrueState truth = world.true_state(0);
  const BodyState& state = world.state(0);

  EXPECT_EQ(truth.x_m, state.x_m);
  EXPECT_EQ(truth.y_m, state.y_m);
  EXPECT_EQ(truth.vx_mps, state.vx_mps);
  EXPECT_EQ(truth.vy_mps, state.vy_mps);
  EXPECT_EQ(truth.ax_mps2, state.ax_mps2);
  EXPECT_EQ(truth.ay_mps2, state.ay_mps2);
  EXPECT_EQ(truth.heading_rad, state.heading_rad);
  EXPECT_EQ(truth.yaw_rate_radps, AsFloat(0.3));
}

// A crowd of omni and rover bodies driven at random (seeded) in a small
// arena: nothing overlaps more than a millimetre or leaves the arena, and
// min_separation matches a brute-force search over every pair.
struct Crowd {
  std::vector<BodySpec> bodies;
  std::vector<motion::DriveCommand> drives;
};

Crowd MakeCrowd(uint16_t count, uint64_t seed) {
  base::SplitMix64 random(seed);
  Crowd crowd;
  for (uint16_t id = 0; id < count; ++id) {
    const double x = 0.2 + 0.4 * (id % 9);
    const double y = 0.2 + 0.4 * (id / 9);
    if (id % 4 == 3) {
      crowd.bodies.push_back(RoverAt(id, x, y, 0.1 * id));
      crowd.drives.push_back(Wheels(random.Between(-40, 40) / 100.0, random.Between(-40, 40) / 100.0));
    } else {
      crowd.bodies.push_back(Omni(id, x, y));
      crowd.drives.push_back(OmniDrive(random.Between(-50, 50) / 100.0, random.Between(-50, 50) / 100.0));
    }
  }
  return crowd;
}

TEST(WorldTest, CrowdStaysSeparatedAndMinSeparationMatchesBruteForce) {
  const Crowd crowd = MakeCrowd(72, 7);  // 9 x 8 robots in a 3.6 x 3.2 arena
  World world(Arena(3.6, 3.2), crowd.bodies);
  for (uint16_t id = 0; id < world.size(); ++id) {
    world.SetDrive(id, crowd.drives[id]);
  }
  double brute_force_min = std::numeric_limits<double>::infinity();
  double worst_overlap = 0;
  double worst_wall = 0;

  for (int step = 1; step <= 300; ++step) {
    world.Step(step * kStepNs, kDt);
    for (uint16_t a = 0; a < world.size(); ++a) {
      const BodyState& state = world.state(a);
      const double r = world.body_radius_m(a);
      worst_wall = std::max({worst_wall, r - state.x_m, state.x_m + r - 3.6, r - state.y_m, state.y_m + r - 3.2});
      for (uint16_t b = a + 1; b < world.size(); ++b) {
        const double gap = Gap(world, a, b);
        brute_force_min = std::min(brute_force_min, std::max(0.0, gap));
        worst_overlap = std::max(worst_overlap, -gap);
      }
    }
    ASSERT_NEAR(world.min_separation_m(), brute_force_min, 1e-12) << "step " << step;
  }

  EXPECT_LT(worst_overlap, 1e-3);
  EXPECT_LE(worst_wall, 1e-12);
  EXPECT_GT(world.contacts(), 0u);
  EXPECT_GT(world.wall_contacts(), 0u);
}

TEST(WorldTest, SparseSwarmMinSeparationMatchesBruteForce) {
  // Far apart in a large arena: the grid's neighbourhood holds no pair, so
  // the exact outward search answers.
  std::vector<BodySpec> bodies;
  for (uint16_t id = 0; id < 20; ++id) {
    bodies.push_back(Omni(id, 1.0 + 2.3 * (id % 5) + 0.01 * id, 1.0 + 3.1 * (id / 5)));
  }
  World world(Arena(20, 20), bodies);
  world.SetDrive(7, OmniDrive(0.3, 0.1));
  double brute_force_min = std::numeric_limits<double>::infinity();

  for (int step = 1; step <= 100; ++step) {
    world.Step(step * kStepNs, kDt);
    for (uint16_t a = 0; a < world.size(); ++a) {
      for (uint16_t b = a + 1; b < world.size(); ++b) {
        brute_force_min = std::min(brute_force_min, Gap(world, a, b));
      }
    }
    ASSERT_NEAR(world.min_separation_m(), brute_force_min, 1e-12) << "step " << step;
  }
}

// The smallest gap between present bodies now, clamped at 0, computed as the
// World computes a gap (sqrt, not hypot: the same bits), by brute force.
double SmallestPresentGap(const World& world) {
  double smallest = std::numeric_limits<double>::infinity();
  for (uint16_t a = 0; a < world.size(); ++a) {
    for (uint16_t b = a + 1; b < world.size(); ++b) {
      if (world.presence(a) == BodyPresence::kAbsent || world.presence(b) == BodyPresence::kAbsent) {
        continue;
      }
      const double dx = world.state(b).x_m - world.state(a).x_m;
      const double dy = world.state(b).y_m - world.state(a).y_m;
      const double gap = std::sqrt(dx * dx + dy * dy) - world.body_radius_m(a) - world.body_radius_m(b);
      smallest = std::min(smallest, std::max(0.0, gap));
    }
  }
  return smallest;
}

// 20 bodies 1 m apart (gaps 0.8 m) in a 10 x 10 arena, and one more, absent,
// 0.3 m from body 0: far enough apart that the exact search, not the
// candidates, finds the record.
std::vector<BodySpec> StillGrid() {
  std::vector<BodySpec> bodies;
  for (uint16_t id = 0; id < 20; ++id) {
    bodies.push_back(Omni(id, 1.0 + (id % 5), 1.0 + (id / 5)));
  }
  bodies.push_back(Omni(20, 1.0, 1.5, BodyPresence::kAbsent));
  return bodies;
}

TEST(WorldTest, RecordPairThatDrawsApartAndCloseAgainLowersTheRecordExactly) {
  // The record (0.3 m, bodies 0 and 20) stands while body 20 backs away and
  // every gap grows; then it drives past body 0, closer than ever.
  std::vector<BodySpec> bodies = StillGrid();
  bodies[20].presence = BodyPresence::kActive;
  World world(Arena(10, 10), bodies);
  Events run;
  StepMany(world, 1, 50, run);
  ASSERT_DOUBLE_EQ(world.min_separation_m(), 0.3);

  world.SetDrive(20, OmniDrive(-0.2, 0));  // away from body 0
  double expected = world.min_separation_m();
  for (int step = 51; step <= 350; ++step) {
    if (step == 151) {
      world.SetDrive(20, OmniDrive(0, -0.2));  // down, past body 0
    }
    StepMany(world, step, 1, run);
    expected = std::min(expected, SmallestPresentGap(world));
    ASSERT_EQ(world.min_separation_m(), expected) << "step " << step;
  }

  EXPECT_LT(world.min_separation_m(), 0.2);
}

TEST(WorldTest, BodyAppearingNearAnotherInAStillSwarmLowersTheRecordAtTheNextStep) {
  World world(Arena(10, 10), StillGrid());
  Events run;
  StepMany(world, 1, 50, run);
  ASSERT_DOUBLE_EQ(world.min_separation_m(), 0.8);

  world.SetPresence(20, BodyPresence::kActive);
  StepMany(world, 51, 1, run);

  EXPECT_EQ(world.min_separation_m(), SmallestPresentGap(world));
  EXPECT_DOUBLE_EQ(world.min_separation_m(), 0.3);
}

// Seeded random swarms, spells of standing still and of driving, bodies
// switching presence (appearing anywhere, stopping, leaving): after every
// step the record equals the brute-force smallest gap seen so far, bit for bit.
TEST(WorldTest, RandomSwarmRecordEqualsBruteForceAfterEveryStep) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    base::SplitMix64 random(seed);
    std::vector<BodySpec> bodies;
    for (uint16_t id = 0; id < 36; ++id) {
      // A jittered 2 m grid; every fourth body starts absent, anywhere.
      const bool absent = id % 4 == 3;
      const double grid_x = 1.0 + 2.0 * (id % 6);
      const double grid_y = 1.0 + 2.0 * (id / 6);
      const double x = absent ? random.Between(20, 1180) / 100.0 : grid_x + random.Between(-50, 50) / 100.0;
      const double y = absent ? random.Between(20, 1180) / 100.0 : grid_y + random.Between(-50, 50) / 100.0;
      if (id % 5 == 4) {
        bodies.push_back(RoverAt(id, x, y, random.Between(0, 628) / 100.0));
        bodies.back().presence = absent ? BodyPresence::kAbsent : BodyPresence::kActive;
      } else {
        bodies.push_back(Omni(id, x, y, absent ? BodyPresence::kAbsent : BodyPresence::kActive));
      }
    }
    World world(Arena(12, 12), bodies);
    double expected = std::numeric_limits<double>::infinity();

    for (int step = 1; step <= 600; ++step) {
      if (step % 40 == 1) {
        const bool still = (step / 40) % 2 == 0;
        for (uint16_t id = 0; id < world.size(); ++id) {
          const double first = still ? 0.0 : random.Between(-30, 30) / 100.0;
          const double second = still ? 0.0 : random.Between(-30, 30) / 100.0;
          world.SetDrive(id, id % 5 == 4 ? Wheels(first, second) : OmniDrive(first, second));
        }
      }
      if (random.Below(20) == 0) {
        const auto id = static_cast<uint16_t>(random.Below(world.size()));
        world.SetPresence(id, static_cast<BodyPresence>(random.Below(3)));
      }
      world.Step(step * kStepNs, kDt);
      expected = std::min(expected, SmallestPresentGap(world));
      ASSERT_EQ(world.min_separation_m(), expected) << "seed " << seed << ", step " << step;
    }
  }
}

TEST(WorldTest, SameCallsGiveTheSameBits) {
  const Crowd crowd = MakeCrowd(72, 11);
  World first(Arena(3.6, 3.2), crowd.bodies);
  World second(Arena(3.6, 3.2), crowd.bodies);
  for (uint16_t id = 0; id < first.size(); ++id) {
    first.SetDrive(id, crowd.drives[id]);
    second.SetDrive(id, crowd.drives[id]);
  }

  for (int step = 1; step <= 200; ++step) {
    first.Step(step * kStepNs, kDt);
    second.Step(step * kStepNs, kDt);
  }

  for (uint16_t id = 0; id < first.size(); ++id) {
    EXPECT_EQ(first.state(id).x_m, second.state(id).x_m);
    EXPECT_EQ(first.state(id).y_m, second.state(id).y_m);
    EXPECT_EQ(first.state(id).heading_rad, second.state(id).heading_rad);
  }
  EXPECT_EQ(first.contacts(), second.contacts());
  EXPECT_EQ(first.min_separation_m(), second.min_separation_m());
}

TEST(WorldTest, DriveKindFollowsTheRobotKind) {
  EXPECT_EQ(DriveKindFor(RobotKind::kOmni), motion::DriveKind::kOmni);
  EXPECT_EQ(DriveKindFor(RobotKind::kRover), motion::DriveKind::kWheels);
  EXPECT_EQ(DriveKindFor(RobotKind::kDrone), motion::DriveKind::kOmni);
  EXPECT_STREQ(ToString(RobotKind::kDrone), "drone");
}

// The drone's defaults, with the drift switched off where a test needs
// exact kinematics.
KindSpec DroneSpec(double drift_sigma_mps = 0) {
  KindSpec spec = DefaultKindSpec(RobotKind::kDrone);
  spec.drift_sigma_mps = drift_sigma_mps;
  return spec;
}

BodySpec DroneAt(uint16_t id, double x_m, double y_m, const KindSpec& spec) {
  return BodySpec{id, RobotKind::kDrone, spec, x_m, y_m, 0.0, BodyPresence::kActive};
}

TEST(WorldTest, DroneDefaultsAreFasterAndBrakeLaterThanOmni) {
  const KindSpec drone = DefaultKindSpec(RobotKind::kDrone);
  const KindSpec omni = DefaultKindSpec(RobotKind::kOmni);
  EXPECT_GT(drone.max_speed_mps, omni.max_speed_mps);
  EXPECT_LT(drone.max_accel_mps2, omni.max_accel_mps2);
  EXPECT_GT(drone.tilt_time_constant_s, 0);
  EXPECT_GT(drone.drift_sigma_mps, 0);
  EXPECT_GT(drone.flight_height_m, 0);
  // 0.8^2 / (2 * 0.5) + 0.8 * 0.25 = 0.84 m against the omni's 0.125 m.
  EXPECT_NEAR(StoppingDistanceM(drone), 0.84, 1e-12);
  EXPECT_NEAR(StoppingDistanceM(omni), 0.125, 1e-12);
  EXPECT_EQ(omni.tilt_time_constant_s, 0);
  EXPECT_EQ(DefaultKindSpec(RobotKind::kRover).drift_sigma_mps, 0);
}

TEST(WorldTest, DroneVelocityFollowsTheCommandAsAFirstOrderLag) {
  // A tilt limit too high to bind: the lag alone shapes the response, and
  // after one time constant the speed is 1 - 1/e of the setpoint.
  KindSpec spec = DroneSpec();
  spec.max_accel_mps2 = 100;
  const std::vector<BodySpec> bodies{DroneAt(0, 1, 1, spec)};
  World world(Arena(10, 10), bodies, 7);
  world.SetDrive(0, OmniDrive(0.6, 0.0));
  Events run;

  const int steps_per_tau = static_cast<int>(std::lround(spec.tilt_time_constant_s / kDt));
  StepMany(world, 1, steps_per_tau, run);
  EXPECT_NEAR(world.state(0).vx_mps, AsFloat(0.6) * (1 - std::exp(-1.0)), 1e-9);
  EXPECT_EQ(world.state(0).vy_mps, 0.0);
  StepMany(world, 1 + steps_per_tau, 4 * steps_per_tau, run);
  EXPECT_NEAR(world.state(0).vx_mps, AsFloat(0.6) * (1 - std::exp(-5.0)), 1e-9);
}

TEST(WorldTest, DroneAccelerationIsCappedByTheTiltLimitAndSpeedByItsTopSpeed) {
  const KindSpec spec = DroneSpec();
  const std::vector<BodySpec> bodies{DroneAt(0, 1, 1, spec)};
  World world(Arena(10, 10), bodies);
  world.SetDrive(0, OmniDrive(3.0, 4.0));  // beyond the top speed
  Events run;

  StepMany(world, 1, 1, run);
  // The lag asks for 0.8 * (1 - exp(-0.04)) = 0.031 m/s in a step; the tilt
  // allows 0.5 m/s^2 * 0.01 s = 0.005.
  EXPECT_NEAR(std::hypot(world.state(0).vx_mps, world.state(0).vy_mps), 0.005, 1e-12);
  EXPECT_NEAR(world.state(0).ax_mps2, 0.3, 1e-9);
  EXPECT_NEAR(world.state(0).ay_mps2, 0.4, 1e-9);
  StepMany(world, 2, 999, run);
  EXPECT_NEAR(std::hypot(world.state(0).vx_mps, world.state(0).vy_mps), 0.8, 1e-9);
}

// Distance a body at its top speed along x travels once commanded to stop.
double StoppingRun(const BodySpec& body) {
  const std::vector<BodySpec> bodies{body};
  World world(Arena(20, 4), bodies);
  world.SetDrive(0, OmniDrive(10.0, 0.0));
  Events run;
  StepMany(world, 1, 1000, run);
  const double start_x = world.state(0).x_m;
  world.SetDrive(0, OmniDrive(0.0, 0.0));
  StepMany(world, 1001, 1000, run);
  EXPECT_NEAR(world.state(0).vx_mps, 0.0, 1e-6);
  return world.state(0).x_m - start_x;
}

TEST(WorldTest, DroneStopsWithinItsStoppingDistanceAndFurtherThanItsBrakingAlone) {
  const KindSpec spec = DroneSpec();
  const double distance_m = StoppingRun(DroneAt(0, 1, 2, spec));
  const double braking_only_m = spec.max_speed_mps * spec.max_speed_mps / (2 * spec.max_accel_mps2);
  // v >= a tau: v^2 / 2a + a tau^2 / 2 (0.655 m) <= StoppingDistanceM (0.84 m).
  EXPECT_NEAR(distance_m, braking_only_m + 0.5 * spec.max_accel_mps2 * 0.0625, 0.01);
  EXPECT_LE(distance_m, StoppingDistanceM(spec));
  EXPECT_GT(distance_m, braking_only_m);
  EXPECT_GT(distance_m, 4 * StoppingRun(Omni(0, 1, 2)));
}

TEST(WorldTest, HoveringDroneDriftsBySeedAndTheSameSeedGivesTheSameBits) {
  const std::vector<BodySpec> bodies{DroneAt(0, 2, 2, DroneSpec(0.02)), Omni(1, 1, 1)};
  World first(Arena(4, 4), bodies, 3);
  World again(Arena(4, 4), bodies, 3);
  World other(Arena(4, 4), bodies, 4);
  Events run;
  // A hover (zero setpoint) for 20 s; the velocity's spread over it.
  double sum_squares = 0;
  int samples = 0;
  for (int step = 1; step <= 2000; ++step) {
    first.Step(step * kStepNs, kDt);
    again.Step(step * kStepNs, kDt);
    other.Step(step * kStepNs, kDt);
    sum_squares += first.state(0).vx_mps * first.state(0).vx_mps + first.state(0).vy_mps * first.state(0).vy_mps;
    samples += 2;
  }
  EXPECT_EQ(first.state(0).x_m, again.state(0).x_m);
  EXPECT_EQ(first.state(0).y_m, again.state(0).y_m);
  EXPECT_EQ(first.state(0).vx_mps, again.state(0).vx_mps);
  EXPECT_NE(first.state(0).x_m, other.state(0).x_m);
  const double moved_m = std::hypot(first.state(0).x_m - 2, first.state(0).y_m - 2);
  EXPECT_GT(moved_m, 0.001);  // it drifts ...
  EXPECT_LT(moved_m, 0.5);    // ... slowly: 0.02 m/s, correlated over 2 s
  // The drift velocity's standard deviation per axis is about drift_sigma
  // (10 correlation times: a loose bound).
  const double rms = std::sqrt(sum_squares / samples);
  EXPECT_GT(rms, 0.005);
  EXPECT_LT(rms, 0.05);
  // The omni beside it draws nothing and does not move, whatever the seed.
  EXPECT_EQ(first.state(1).x_m, 1.0);
  EXPECT_EQ(other.state(1).y_m, 1.0);
}

TEST(WorldTest, AWorldWithoutDronesIsTheSameWhateverItsSeed) {
  const Crowd crowd = MakeCrowd(24, 5);
  World first(Arena(3.6, 3.2), crowd.bodies, 1);
  World second(Arena(3.6, 3.2), crowd.bodies, 99);
  for (uint16_t id = 0; id < first.size(); ++id) {
    first.SetDrive(id, crowd.drives[id]);
    second.SetDrive(id, crowd.drives[id]);
  }
  for (int step = 1; step <= 200; ++step) {
    first.Step(step * kStepNs, kDt);
    second.Step(step * kStepNs, kDt);
  }
  base::StateDigest a;
  base::StateDigest b;
  first.AddToDigest(a);
  second.AddToDigest(b);
  EXPECT_EQ(a.value(), b.value());
}

TEST(WorldTest, CheckWorldSpecRefusesANegativeTiltOrDrift) {
  KindSpec spec = DroneSpec();
  spec.tilt_time_constant_s = -0.1;
  const std::vector<BodySpec> bodies{DroneAt(0, 1, 1, spec)};
  const std::optional<Error> problem = CheckWorldSpec(Arena(4, 4), bodies);
  ASSERT_TRUE(problem.has_value());
  EXPECT_EQ(problem->where, "body 0");
  EXPECT_NE(problem->message.find("tilt time constant"), std::string::npos);
}

}  // namespace
}  // namespace syrof::lab::world
