#include "syrof/app/command_check.h"
#include "syrof/app/commands.h"

#include <gtest/gtest.h>

#include <array>
#include <limits>
#include <string>

namespace syrof::app {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInfinity = std::numeric_limits<float>::infinity();

constexpr syrof_car_command MoveTo(float x_m, float y_m, float speed_mps) {
  return app::MoveToCommand(x_m, y_m, speed_mps);
}
constexpr syrof_car_command Velocity(float vx_mps, float vy_mps) { return app::VelocityCommand(vx_mps, vy_mps); }
constexpr syrof_car_command TurnTo(float heading_rad) { return app::TurnToCommand(heading_rad); }

std::string Described(const syrof_car_command& command) {
  std::array<char, 64> text{};
  return Describe(CheckCommand(command), text.data(), text.size());
}

void ExpectRefused(const syrof_car_command& command, CommandError error, const char* field) {
  const CommandCheck check = CheckCommand(command);
  EXPECT_EQ(check.error, error) << Described(command);
  EXPECT_STREQ(check.field, field);
  EXPECT_FALSE(check.ok());
}

TEST(CheckCommandTest, AcceptsEveryWellFormedKind) {
  EXPECT_TRUE(CheckCommand(syrof_car_command{}).ok());
  EXPECT_TRUE(CheckCommand(MoveTo(1.5f, -2.0f, 0.1f)).ok());
  EXPECT_TRUE(CheckCommand(MoveTo(kMaxTargetM, -kMaxTargetM, 100.0f)).ok());
  EXPECT_TRUE(CheckCommand(Velocity(-50.0f, 50.0f)).ok());  // capped by the robot, not refused
  EXPECT_TRUE(CheckCommand(TurnTo(100.0f)).ok());          // wrapped, not refused
}

TEST(CheckCommandTest, StopIgnoresItsFields) {
  syrof_car_command command{};
  command.x_m = kNaN;
  command.speed_mps = -1.0f;

  EXPECT_TRUE(CheckCommand(command).ok());
}

TEST(CheckCommandTest, FieldsTheKindDoesNotUseAreNotLookedAt) {
  syrof_car_command velocity = Velocity(0.1f, 0.0f);
  velocity.x_m = kNaN;
  velocity.heading_rad = kInfinity;
  syrof_car_command turn = TurnTo(1.0f);
  turn.speed_mps = -3.0f;

  EXPECT_TRUE(CheckCommand(velocity).ok());
  EXPECT_TRUE(CheckCommand(turn).ok());
}

TEST(CheckCommandTest, RefusesAnUnknownKind) {
  syrof_car_command command{};
  command.kind = 7;

  ExpectRefused(command, CommandError::kUnknownKind, "kind");
  EXPECT_EQ(Described(command), "kind 7 is unknown");
}

TEST(CheckCommandTest, RefusesAMoveToWithANonFiniteField) {
  ExpectRefused(MoveTo(kNaN, 1.0f, 0.1f), CommandError::kNotFinite, "x_m");
  ExpectRefused(MoveTo(1.0f, -kInfinity, 0.1f), CommandError::kNotFinite, "y_m");
  ExpectRefused(MoveTo(1.0f, 1.0f, kNaN), CommandError::kNotFinite, "speed_mps");
  EXPECT_EQ(Described(MoveTo(kNaN, 1.0f, 0.1f)), "MOVE_TO x_m is not finite");
}

TEST(CheckCommandTest, RefusesAMoveToTargetBeyondWhatAMapCarries) {
  ExpectRefused(MoveTo(33.0f, 1.0f, 0.1f), CommandError::kOutOfRange, "x_m");
  ExpectRefused(MoveTo(1.0f, -1e30f, 0.1f), CommandError::kOutOfRange, "y_m");
  EXPECT_EQ(Described(MoveTo(33.0f, 1.0f, 0.1f)), "MOVE_TO x_m is beyond 32.767 m");
}

TEST(CheckCommandTest, RefusesAMoveToSpeedThatIsNotPositive) {
  ExpectRefused(MoveTo(1.0f, 1.0f, 0.0f), CommandError::kSpeedNotPositive, "speed_mps");
  ExpectRefused(MoveTo(1.0f, 1.0f, -0.2f), CommandError::kSpeedNotPositive, "speed_mps");
  EXPECT_EQ(Described(MoveTo(1.0f, 1.0f, -0.2f)), "MOVE_TO speed_mps is not > 0");
}

TEST(CheckCommandTest, RefusesANonFiniteVelocity) {
  ExpectRefused(Velocity(kNaN, 0.0f), CommandError::kNotFinite, "vx_mps");
  ExpectRefused(Velocity(0.0f, kInfinity), CommandError::kNotFinite, "vy_mps");
}

TEST(CheckCommandTest, RefusesANonFiniteHeading) {
  ExpectRefused(TurnTo(kNaN), CommandError::kNotFinite, "heading_rad");
  EXPECT_EQ(Described(TurnTo(kNaN)), "TURN_TO heading_rad is not finite");
}

TEST(CheckCommandTest, DescribeTruncatesToTheBuffer) {
  std::array<char, 8> text{};
  syrof_car_command command{};
  command.kind = 200;

  Describe(CheckCommand(command), text.data(), text.size());

  EXPECT_STREQ(text.data(), "kind 20");
}

TEST(CheckCommandTest, EveryErrorHasItsName) {
  EXPECT_STREQ(ToString(CommandError::kOk), "ok");
  EXPECT_STREQ(ToString(CommandError::kUnknownKind), "unknown_kind");
  EXPECT_STREQ(ToString(CommandError::kNotFinite), "not_finite");
  EXPECT_STREQ(ToString(CommandError::kOutOfRange), "out_of_range");
  EXPECT_STREQ(ToString(CommandError::kSpeedNotPositive), "speed_not_positive");
}

}  // namespace
}  // namespace syrof::app
