#include "demo.h"

#include <gtest/gtest.h>

#include <sstream>

namespace syrof::lab::demo {
namespace {

struct DemoRun {
  DemoReport report;
  std::string text;
};

DemoRun RunWith(DemoOptions options) {
  std::ostringstream out;
  DemoRun run;
  run.report = RunDemo(options, out);
  run.text = out.str();
  return run;
}

TEST(DemoTest, SameOptionsGiveTheSameTextAndAnotherSeedDoesNot) {
  const DemoOptions options{.robots = 4, .seconds = 2.0, .loss = 0.3, .seed = 11};
  DemoOptions other_seed = options;
  other_seed.seed = 12;

  const DemoRun first = RunWith(options);
  const DemoRun second = RunWith(options);
  const DemoRun third = RunWith(other_seed);

  EXPECT_EQ(first.text, second.text);
  EXPECT_NE(first.text, third.text);
}

TEST(DemoTest, EveryBeaconIsReceivedOrCountedLost) {
  const DemoOptions options{.robots = 5, .seconds = 3.0, .loss = 0.25, .seed = 3};

  const DemoRun run = RunWith(options);

  ASSERT_EQ(run.report.robots.size(), 5u);
  EXPECT_EQ(run.report.radio_rounds, 61);
  int sent = 0, received = 0, lost = 0;
  for (const RobotReport& robot : run.report.robots) {
    EXPECT_EQ(robot.beacons_sent, run.report.radio_rounds);
    sent += robot.beacons_sent;
    received += robot.beacons_received;
    lost += robot.beacons_lost;
  }
  EXPECT_EQ(received + lost, sent * (5 - 1));
  EXPECT_GT(lost, 0);
  EXPECT_GT(received, lost);
}

TEST(DemoTest, WithoutLossEveryoneHearsEveryoneAndPositionsSurviveTheWire) {
  const DemoOptions options{.robots = 3, .seconds = 1.0, .loss = 0.0, .seed = 1};

  const DemoRun run = RunWith(options);

  for (const RobotReport& robot : run.report.robots) {
    EXPECT_EQ(robot.beacons_lost, 0);
    EXPECT_EQ(robot.beacons_received, run.report.radio_rounds * 2);
    // Millimetre fixed point: at most half a millimetre per axis.
    EXPECT_LE(robot.largest_position_error_m, 0.0005 * 1.4143);
  }
}

TEST(DemoTest, TotalLossDeliversNothing) {
  const DemoRun run = RunWith({.robots = 2, .seconds = 0.5, .loss = 1.0, .seed = 5});

  for (const RobotReport& robot : run.report.robots) EXPECT_EQ(robot.beacons_received, 0);
}

TEST(DemoTest, MalformedForeignFramesAreRejectedWithTheirReasons) {
  const DemoRun run = RunWith({.robots = 3, .seconds = 1.0, .loss = 0.1, .seed = 2});

  for (const RobotReport& robot : run.report.robots) {
    EXPECT_EQ(robot.frames_rejected, 2);
    EXPECT_EQ(robot.rejection_reasons, (std::vector<std::string>{"WrongVersion", "Truncated"}));
  }
}

TEST(DemoTest, BeaconFitsOneBleAdvertisingPayload) {
  const DemoRun run = RunWith({.robots = 2, .seconds = 0.1, .loss = 0.0, .seed = 1});

  EXPECT_EQ(run.report.beacon_bytes, 29);
  EXPECT_NE(run.text.find("29 bytes on the wire"), std::string::npos);
}

TEST(DemoTest, ValidateNamesTheOffendingOption) {
  EXPECT_EQ(Validate({}), "");
  EXPECT_NE(Validate({.robots = 1}).find("--robots"), std::string::npos);
  EXPECT_NE(Validate({.robots = 9}).find("--robots"), std::string::npos);
  EXPECT_NE(Validate({.seconds = 0.0}).find("--seconds"), std::string::npos);
  EXPECT_NE(Validate({.loss = 1.5}).find("--loss"), std::string::npos);
  EXPECT_NE(Validate({.loss = -0.1}).find("--loss"), std::string::npos);
}

}  // namespace
}  // namespace syrof::lab::demo
