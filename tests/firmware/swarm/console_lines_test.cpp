#include "syrof/firmware/swarm/console_lines.h"

#include <gtest/gtest.h>

#include <string>

namespace syrof::firmware::swarm {
namespace {

TEST(ConsoleLinesTest, RoundLineGivesTheRobotsState) {
  const ConsoleLine line = ParseConsoleLine(
      "R t_ms=1250 robot=2 epoch=7 mode=0 phase=2 member=1 valid=1 x_mm=-1500 y_mm=2250 lost=3", 4);
  const auto* round = std::get_if<RoundLine>(&line);
  ASSERT_NE(round, nullptr);
  EXPECT_EQ(round->t_ms, 1250);
  EXPECT_EQ(round->robot, 2);
  EXPECT_EQ(round->epoch, 7);
  EXPECT_EQ(round->mode, wire::Mode::kCooperative);
  EXPECT_EQ(round->phase, wire::Phase::kVote);
  EXPECT_TRUE(round->member);
  EXPECT_TRUE(round->estimate_valid);
  EXPECT_DOUBLE_EQ(round->x_m, -1.5);
  EXPECT_DOUBLE_EQ(round->y_m, 2.25);
  EXPECT_EQ(round->epoch_lines_lost, 3u);
}

TEST(ConsoleLinesTest, EpochLineRebuildsTheMapSoSameKnowledgeCanCompareIt) {
  const ConsoleLine line =
      ParseConsoleLine("E t_ms=450 robot=1 epoch=3 mode=0 active=0 members=0:100:-200:31:5:-6:;1:7:8:9:10:11:0aff", 4);
  const auto* epoch = std::get_if<EpochLine>(&line);
  ASSERT_NE(epoch, nullptr);
  EXPECT_EQ(epoch->robot, 1);
  EXPECT_FALSE(epoch->active);
  sync::LDMap expected;
  expected.epoch = 3;
  expected.mode = wire::Mode::kCooperative;
  expected.members.set(0);
  expected.members.set(1);
  expected.snapshots[0] = wire::Snapshot{100, -200, 31, 5, -6, 0, {}};
  expected.snapshots[1] = wire::Snapshot{7, 8, 9, 10, 11, 0, {}};
  const uint8_t payload[] = {0x0a, 0xff};
  ASSERT_EQ(expected.snapshots[1].SetPayload(payload), wire::WireError::kOk);
  EXPECT_TRUE(epoch->map.SameKnowledge(expected));
  expected.snapshots[1].x_mm = 6;
  EXPECT_FALSE(epoch->map.SameKnowledge(expected));
}

// The held line names the app compiled into the image: the rest of the
// line, spaces and all (before, the host read only the word `held`).
TEST(ConsoleLinesTest, HeldLineNamesTheImagesApp) {
  ConsoleLine line = ParseConsoleLine("held id=3 t_ms=12 app=strongest", 4);
  const auto* held = std::get_if<HeldLine>(&line);
  ASSERT_NE(held, nullptr);
  EXPECT_EQ(held->robot, 3);
  EXPECT_EQ(held->t_ms, 12);
  EXPECT_EQ(held->app, "strongest");
  line = ParseConsoleLine("held id=0 t_ms=0 app=my app: v2", 4);
  held = std::get_if<HeldLine>(&line);
  ASSERT_NE(held, nullptr);
  EXPECT_EQ(held->app, "my app: v2");
  line = ParseConsoleLine("held id=0 t_ms=0 app=" + std::string(kMaxAppNameBytes, 'a'), 4);
  held = std::get_if<HeldLine>(&line);
  ASSERT_NE(held, nullptr);
  EXPECT_EQ(held->app.size(), kMaxAppNameBytes);
}

// A held line without its app (an older image), with an empty one, one
// longer than a replay holds or with bytes no header can show is refused,
// naming the field and where.
TEST(ConsoleLinesTest, HeldLineWithoutAReadableAppIsRefused) {
  const auto error_of = [](const std::string& text) {
    const ConsoleLine line = ParseConsoleLine(text, 4);
    const auto* error = std::get_if<LineError>(&line);
    return error != nullptr ? *error : LineError{"parsed", 0};
  };
  LineError error = error_of("held id=0 t_ms=5");
  EXPECT_EQ(error.what, "expected ' app='");
  EXPECT_EQ(error.column, 16u);
  error = error_of("held id=0 t_ms=5 app=");
  EXPECT_EQ(error.what, "app: the image names no app");
  EXPECT_EQ(error.column, 21u);
  error = error_of("held id=0 t_ms=5 app=" + std::string(kMaxAppNameBytes + 1, 'a'));
  EXPECT_EQ(error.what, "app: 257 bytes, more than the 256 a replay holds");
  error = error_of("held id=0 t_ms=5 app=ci\trcle");
  EXPECT_EQ(error.what, "app: a byte that is not printable ASCII");
  EXPECT_EQ(error.column, 23u);
  error = error_of("held id=4 t_ms=5 app=circle");
  EXPECT_EQ(error.what, "id: 4 is outside [0, 3]");
}

TEST(ConsoleLinesTest, OtherLinesAreIgnored) {
  EXPECT_TRUE(std::holds_alternative<OtherLine>(ParseConsoleLine("status t_ms=1000 board=mps2-an386", 4)));
  EXPECT_TRUE(std::holds_alternative<OtherLine>(ParseConsoleLine("robot 0 of 4: spreading on a circle", 4)));
  EXPECT_TRUE(std::holds_alternative<OtherLine>(ParseConsoleLine("", 4)));
  EXPECT_TRUE(std::holds_alternative<OtherLine>(ParseConsoleLine("held", 4)));
  // The line a robot booted on its own image's configuration block prints
  // before its held line (the emulated swarm's default, WriteRobotImages).
  EXPECT_TRUE(std::holds_alternative<OtherLine>(ParseConsoleLine(
      "config robot=2/4 kind=omni swarm_kinds=omni scenario=0123456789abcdef inputs=1 bid=812 (the configuration "
      "block)",
      4)));
}

// A garbled line names the field and where it is.
TEST(ConsoleLinesTest, GarbledLinesNameTheFieldAndColumn) {
  const auto error_of = [](std::string_view text) {
    const ConsoleLine line = ParseConsoleLine(text, 4);
    const auto* error = std::get_if<LineError>(&line);
    return error != nullptr ? *error : LineError{"parsed", 0};
  };
  LineError error = error_of("R t_ms=5 robot=9 epoch=1 mode=0 phase=0 member=1 valid=1 x_mm=0 y_mm=0 lost=0");
  EXPECT_EQ(error.what, "robot: 9 is outside [0, 3]");
  EXPECT_EQ(error.column, 15u);
  error = error_of("R t_ms=5 robot=1 epoch=1 mode=0 phase=0 member=1 valid=1 x_mm=0 y_mm=0");
  EXPECT_EQ(error.what, "expected ' lost='");
  error = error_of("R t_ms=5 robot=1 epoch=1 mode=0 phase=0 member=1 valid=1 x_mm=0 y_mm=0 lost=0 extra");
  EXPECT_EQ(error.what, "unexpected text after lost=");
  error = error_of("E t_ms=1 robot=0 epoch=3 mode=0 active=1 members=0:1:2:3:4:5:;0:1:2:3:4:5:");
  EXPECT_EQ(error.what, "member 0 listed twice");
  error = error_of("E t_ms=1 robot=0 epoch=3 mode=0 active=1 members=0:1:2:3:4:5:0g");
  EXPECT_EQ(error.what, "payload: expected pairs of hex digits");
  error = error_of("E t_ms=1 robot=0 epoch=3 mode=0 active=1 members=0:1:2:3:4:5:00112233445566778899");
  EXPECT_EQ(error.what, "payload: more than 9 bytes");
  error = error_of("E t_ms=1 robot=0 epoch=3 mode=0 active=1 members=0:1:40000:3:4:5:");
  EXPECT_EQ(error.what, "y_mm: 40000 is outside [-32768, 32767]");
  // The robot's own activation decision is part of the line.
  error = error_of("E t_ms=1 robot=0 epoch=3 mode=0 members=0:1:2:3:4:5:");
  EXPECT_EQ(error.what, "expected ' active='");
  error = error_of("E t_ms=1 robot=0 epoch=3 mode=0 active=2 members=0:1:2:3:4:5:");
  EXPECT_EQ(error.what, "active: 2 is outside [0, 1]");
}

}  // namespace
}  // namespace syrof::firmware::swarm
