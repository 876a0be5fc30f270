// `syrof compare` (cli/compare_command.cpp) as a user meets it: lab runs of
// the same scenario and seed agree, a crash or another seed is reported at
// the right epoch, handcrafted replays that differ in one field are named
// with that field, and files that cannot be read give exit status 2.
#include "compare_command.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include "cli_test_support.h"
#include "epoch_runs_test_support.h"
#include "run_command.h"
#include "syrof/lab/replay/comparison.h"
#include "syrof/lab/replay/reader.h"

namespace syrof::cli {
namespace {

namespace fs = std::filesystem;
namespace replay = lab::replay;
using replay::testing::kAutonomous;
using replay::testing::kCooperative;
using replay::testing::StartRoundOf;
using replay::testing::SteppedRun;
using replay::testing::SyntheticRun;
using testing::FreshDir;
using testing::Outcome;
using testing::ReadFile;

const std::string kCompareScenarios = SYROF_SCENARIOS_DIR;

// A folder of this test's own (parallel test processes never share one).
fs::path TestDir() {
  const fs::path dir = FreshDir("syrof_compare_test_", ::testing::UnitTest::GetInstance()->current_test_info()->name() +
                                                          std::string("_") + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string WriteReplay(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  return path.string();
}

Outcome Compare(const std::string& a, const std::string& b, std::optional<double> pose_tolerance_m = std::nullopt,
                bool payloads = false) {
  std::ostringstream out, err;
  const int status =
      RunCompareCommand({.run_a = a, .run_b = b, .pose_tolerance_m = pose_tolerance_m, .payloads = payloads}, out, err);
  return Outcome{status, out.str(), err.str()};
}

// `syrof run` of `scenario` into `out_dir`.
void RunLab(const std::string& scenario, const fs::path& out_dir, std::optional<uint64_t> seed = std::nullopt) {
  RunOptions options;
  options.scenario_path = scenario;
  options.out_dir = out_dir.string();
  options.seed = seed;
  options.quiet = true;
  std::ostringstream out, err;
  ASSERT_EQ(RunRunCommand(options, out, err, false), 0) << err.str();
}

// The epoch of robot `robot`'s CRASH event in the replay at `path`.
std::optional<uint16_t> CrashEpoch(const fs::path& path, uint16_t robot) {
  std::ifstream in(path, std::ios::binary);
  replay::Reader reader(in);
  replay::Header header;
  if (!reader.ReadHeader(header)) return std::nullopt;
  replay::Round round;
  while (reader.Next(round)) {
    for (const replay::Event& event : round.events) {
      if (event.kind == replay::EventKind::kCrash && event.robot == robot) return event.epoch;
    }
  }
  return std::nullopt;
}

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(CompareCommandTest, TheSameLabRunTwiceAgrees) {
  const fs::path dir = TestDir();
  RunLab(kCompareScenarios + "/crash.yaml", dir / "first");
  RunLab(kCompareScenarios + "/crash.yaml", dir / "second");

  const Outcome outcome = Compare((dir / "first").string(), (dir / "second").string(), 0.0);

  EXPECT_EQ(outcome.status, 0) << outcome.out << outcome.err;
  EXPECT_EQ(outcome.err, "");
  EXPECT_TRUE(Contains(outcome.out, "agree: ")) << outcome.out;
  EXPECT_TRUE(Contains(outcome.out, "of 6 robots, the same starts, modes and members; true positions within 0 m in "))
      << outcome.out;
  EXPECT_EQ(std::count(outcome.out.begin(), outcome.out.end(), '\n'), 1) << outcome.out;  // one line
  fs::remove_all(dir);
}

TEST(CompareCommandTest, ACrashIsReportedAtTheEpochAfterIt) {
  // crash.yaml without its crash, under the same name.
  const fs::path dir = TestDir();
  std::string scenario = ReadFile(kCompareScenarios + "/crash.yaml");
  const size_t faults = scenario.find("faults:");
  ASSERT_NE(faults, std::string::npos);
  scenario.erase(faults, scenario.find("app:") - faults);
  std::ofstream(dir / "no_crash.yaml") << scenario;
  RunLab(kCompareScenarios + "/crash.yaml", dir / "crash");
  RunLab((dir / "no_crash.yaml").string(), dir / "no_crash");
  // Robot 3 crashes during this epoch: it starts none after it.
  const std::optional<uint16_t> crash_epoch = CrashEpoch(dir / "crash" / "replay", 3);
  ASSERT_TRUE(crash_epoch.has_value());

  const Outcome outcome = Compare((dir / "crash").string(), (dir / "no_crash" / "replay").string());

  EXPECT_EQ(outcome.status, 1) << outcome.out << outcome.err;
  EXPECT_TRUE(Contains(outcome.out, fmt::format("differ at epoch {} (epochs 1 to {} agree): started (robot 3)",
                                                *crash_epoch + 1, *crash_epoch)))
      << outcome.out;
  EXPECT_TRUE(Contains(outcome.out, fmt::format("\nepoch {} in both runs", *crash_epoch + 1))) << outcome.out;
  // Robot 3's row: not started in A, started in B.
  EXPECT_TRUE(Contains(outcome.out, "\n*  3      no ")) << outcome.out;
  fs::remove_all(dir);
}

TEST(CompareCommandTest, AnotherSeedIsReportedAtTheFirstEpochThatDiffers) {
  const fs::path dir = TestDir();
  RunLab(kCompareScenarios + "/crash.yaml", dir / "seed1", 1);
  RunLab(kCompareScenarios + "/crash.yaml", dir / "seed2", 2);
  // The first difference as lab/replay finds it (its own tests check how).
  std::ifstream a(dir / "seed1" / "replay", std::ios::binary), b(dir / "seed2" / "replay", std::ios::binary);
  const replay::ReplayComparison direct = replay::CompareReplays(a, b, {});
  ASSERT_TRUE(direct.epochs.first_difference.has_value()) << "seeds 1 and 2 of crash.yaml no longer differ";
  const int64_t expected = direct.epochs.first_difference->number;

  const Outcome outcome = Compare((dir / "seed1").string(), (dir / "seed2").string());

  EXPECT_EQ(outcome.status, 1) << outcome.out << outcome.err;
  EXPECT_TRUE(Contains(outcome.out, fmt::format("differ at epoch {} (", expected))) << outcome.out;
  EXPECT_TRUE(Contains(outcome.out, "note: different seeds: A 1, B 2")) << outcome.out;
  fs::remove_all(dir);
}

TEST(CompareCommandTest, OneRobotsModeAtEpochKIsNamedAtK) {
  const fs::path dir = TestDir();
  const SyntheticRun a = SteppedRun(3, 6);
  SyntheticRun b = a;
  replay::testing::SetStart(b, StartRoundOf(4), 1, kAutonomous, {0, 1, 2});
  const std::string path_a = WriteReplay(dir / "a.replay", a.Bytes());
  const std::string path_b = WriteReplay(dir / "b.replay", b.Bytes());

  const Outcome outcome = Compare(path_a, path_b);

  EXPECT_EQ(outcome.status, 1) << outcome.err;
  EXPECT_EQ(outcome.out,
            fmt::format("syrof compare: A {} and B {} differ at epoch 4 (epochs 1 to 3 agree): mode (robot 1)\n"
                        "\n"
                        "epoch 4 in both runs (started: the round the robot started it in; members: of its map):\n"
                        "          A:                             B:\n"
                        "   robot  started  mode         members  started  mode         members  differs\n"
                        "   0      round 8  COOPERATIVE  0-2      round 8  COOPERATIVE  0-2\n"
                        "*  1      round 8  COOPERATIVE  0-2      round 8  AUTONOMOUS   0-2      mode\n"
                        "   2      round 8  COOPERATIVE  0-2      round 8  COOPERATIVE  0-2\n",
                        path_a, path_b));
  fs::remove_all(dir);
}

TEST(CompareCommandTest, OneRobotsMembersAtEpochKAreNamedAtK) {
  const fs::path dir = TestDir();
  const SyntheticRun a = SteppedRun(5, 6);
  SyntheticRun b = a;
  replay::testing::SetStart(b, StartRoundOf(3), 4, kCooperative, {0, 1, 3, 4});
  const std::string path_a = WriteReplay(dir / "a.replay", a.Bytes());
  const std::string path_b = WriteReplay(dir / "b.replay", b.Bytes());

  const Outcome outcome = Compare(path_a, path_b);

  EXPECT_EQ(outcome.status, 1) << outcome.err;
  EXPECT_TRUE(Contains(outcome.out, "differ at epoch 3 (epochs 1 to 2 agree): members (robot 4)\n")) << outcome.out;
  EXPECT_TRUE(Contains(outcome.out, "*  4      round 6  COOPERATIVE  0-4      round 6  COOPERATIVE  0 1 3 4  members\n"))
      << outcome.out;
}

TEST(CompareCommandTest, WithPayloadsTheAppsStateIsComparedAndItsBytesShown) {
  const fs::path dir = TestDir();
  SyntheticRun a = SteppedRun(3, 5);
  for (uint16_t epoch = 1; epoch <= 5; ++epoch) replay::testing::SetPayload(a, StartRoundOf(epoch), 1, {'C', 0x62, 0x03});
  SyntheticRun b = a;
  replay::testing::SetPayload(b, StartRoundOf(3), 1, {'C', 0x17, 0x03});
  const std::string path_a = WriteReplay(dir / "a.replay", a.Bytes());
  const std::string path_b = WriteReplay(dir / "b.replay", b.Bytes());

  const Outcome without = Compare(path_a, path_b);
  const Outcome with = Compare(path_a, path_b, std::nullopt, true);
  const Outcome same = Compare(path_a, path_a, std::nullopt, true);

  EXPECT_EQ(without.status, 0) << without.out;
  EXPECT_TRUE(Contains(without.out, "the same starts, modes and members\n")) << without.out;
  EXPECT_EQ(same.status, 0) << same.out;
  EXPECT_TRUE(Contains(same.out, "5 epochs (1 to 5) of 3 robots, the same starts, modes, members and payloads\n"))
      << same.out;
  EXPECT_EQ(with.status, 1) << with.err;
  EXPECT_TRUE(Contains(with.out, "differ at epoch 3 (epochs 1 to 2 agree): payloads (robots 0-2)\n")) << with.out;
  EXPECT_TRUE(Contains(with.out, "*  0      round 6  COOPERATIVE  0-2      round 6  COOPERATIVE  0-2      payloads\n"))
      << with.out;
  EXPECT_TRUE(Contains(with.out,
                       "payloads that differ in robot 0's map of epoch 3 (bytes the members' apps sent):\n"
                       "member  A: payload  B: payload\n"
                       "1       43 62 03    43 17 03\n"
                       "robot 1's map: the payloads of member 1 differ\n"
                       "robot 2's map: the payloads of member 1 differ\n"))
      << with.out;
  fs::remove_all(dir);
}

TEST(CompareCommandTest, ALongerRunIsComparedOnWhatBothHoldAndSaysSo) {
  const fs::path dir = TestDir();
  const SyntheticRun longer = SteppedRun(2, 8);
  SyntheticRun shorter = longer;
  replay::testing::CutAfter(shorter, StartRoundOf(5) + 1);
  const std::string path_a = WriteReplay(dir / "a.replay", shorter.Bytes());
  const std::string path_b = WriteReplay(dir / "b.replay", longer.Bytes());

  const Outcome outcome = Compare(path_a, path_b);

  EXPECT_EQ(outcome.status, 0) << outcome.out << outcome.err;
  EXPECT_EQ(outcome.out,
            fmt::format("syrof compare: A {} and B {} agree: 5 epochs (1 to 5) of 2 robots, the same starts, modes and "
                        "members\n"
                        "note: B is longer: it ends at round 17, A at round 11; compared the epochs started up to round "
                        "11; B's later epochs 6 to 8 not compared\n",
                        path_a, path_b));
}

TEST(CompareCommandTest, PositionsBeyondTheToleranceAreReportedAtTheirRound) {
  const fs::path dir = TestDir();
  const SyntheticRun a = SteppedRun(3, 4);
  SyntheticRun b = a;
  replay::testing::RoundAt(b, 5).robots[2].true_x_m += 0.25f;
  const std::string path_a = WriteReplay(dir / "a.replay", a.Bytes());
  const std::string path_b = WriteReplay(dir / "b.replay", b.Bytes());

  const Outcome within = Compare(path_a, path_b, 0.3);
  const Outcome beyond = Compare(path_a, path_b, 0.1);
  const Outcome unasked = Compare(path_a, path_b);

  EXPECT_EQ(within.status, 0) << within.out;
  EXPECT_TRUE(Contains(within.out, "; true positions within 0.3 m in 9 rounds\n")) << within.out;
  EXPECT_EQ(beyond.status, 1) << beyond.out;
  EXPECT_TRUE(Contains(beyond.out, "agree on 4 epochs (1 to 4) of 3 robots, the same starts, modes and members, but not "
                                   "on positions\n"))
      << beyond.out;
  EXPECT_TRUE(Contains(beyond.out, "true positions differ at round 5 (A t=0.250000000s, B t=0.250000000s): 1 of 3 robots "
                                   "more than 0.1 m apart\n"))
      << beyond.out;
  EXPECT_TRUE(Contains(beyond.out, "2      2.0000  0.0500  2.2500  0.0500  0.25\n")) << beyond.out;
  EXPECT_EQ(unasked.status, 0) << unasked.out;
}

// Runs whose robots had other private inputs, or another message format,
// may start the same epochs: they agree, and the notes say the runs differ.
TEST(CompareCommandTest, OtherInputsOrAnotherMessageFormatAreNoted) {
  const fs::path dir = TestDir();
  SyntheticRun a = SteppedRun(3, 2);
  a.header.robots[1].inputs = {{"charge", 866}};
  SyntheticRun b = a;
  b.header.robots[1].inputs = {{"charge", 38}};
  b.header.robots[2].inputs = {{"charge", 1}};
  lab::message::MessageFormat format;
  format.none = false;
  format.fields = {{"charge", lab::message::FieldType::kU16Be, 0}};
  format.length = 2;
  b.header.message = format;
  const std::string path_a = WriteReplay(dir / "a.replay", a.Bytes());
  const std::string path_b = WriteReplay(dir / "b.replay", b.Bytes());

  const Outcome outcome = Compare(path_a, path_b);

  EXPECT_EQ(outcome.status, 0) << outcome.out << outcome.err;
  EXPECT_TRUE(Contains(outcome.out, "note: different message formats: A not recorded, B 2 bytes: charge u16be\n"))
      << outcome.out;
  EXPECT_TRUE(Contains(outcome.out, "note: different private inputs for robots 1 2 (syrof replay FILE --summary shows "
                                    "them)\n"))
      << outcome.out;
  EXPECT_FALSE(Contains(Compare(path_a, path_a).out, "note:"));
}

TEST(CompareCommandTest, DifferentRobotsAreADifferenceNotComparedFurther) {
  const fs::path dir = TestDir();
  const std::string path_a = WriteReplay(dir / "a.replay", SteppedRun(3, 2).Bytes());
  const std::string path_b = WriteReplay(dir / "b.replay", SteppedRun(6, 2).Bytes());

  const Outcome outcome = Compare(path_a, path_b);

  EXPECT_EQ(outcome.status, 1);
  EXPECT_EQ(outcome.out, fmt::format("syrof compare: A {} and B {} are runs of different robots, not compared: only in "
                                     "A: none; only in B: 3-5\n",
                                     path_a, path_b));
}

TEST(CompareCommandTest, AFileThatCannotBeReadIsExitTwoNamingIt) {
  const fs::path dir = TestDir();
  const SyntheticRun run = SteppedRun(3, 3);
  const replay::testing::Written written = replay::testing::Write(run.header, run.rounds);
  std::string damaged = written.bytes;
  damaged[written.round_ends[1] - 6] ^= 0x01;
  const std::string good = WriteReplay(dir / "good.replay", written.bytes);
  const std::string corrupt = WriteReplay(dir / "corrupt.replay", damaged);
  const std::string cut = WriteReplay(dir / "cut.replay", written.bytes.substr(0, written.round_ends[2]));
  const std::string text = WriteReplay(dir / "notes.txt", "hello, world");
  fs::create_directories(dir / "empty_folder");

  const Outcome damaged_b = Compare(good, corrupt);
  const Outcome cut_a = Compare(cut, good);
  const Outcome not_replay = Compare(text, good);
  const Outcome missing = Compare(good, (dir / "nothing").string());
  const Outcome no_replay = Compare((dir / "empty_folder").string(), good);

  EXPECT_EQ(damaged_b.status, 2);
  EXPECT_EQ(damaged_b.out, "");
  EXPECT_TRUE(Contains(damaged_b.err, fmt::format("syrof compare: B: {}: offset ", corrupt))) << damaged_b.err;
  EXPECT_TRUE(Contains(damaged_b.err, "the file is damaged")) << damaged_b.err;
  EXPECT_EQ(cut_a.status, 2);
  EXPECT_TRUE(Contains(cut_a.err, fmt::format("syrof compare: A: {}: offset ", cut))) << cut_a.err;
  EXPECT_TRUE(Contains(cut_a.err, "truncated")) << cut_a.err;
  EXPECT_EQ(not_replay.status, 2);
  EXPECT_TRUE(Contains(not_replay.err, "not a SyROF replay file")) << not_replay.err;
  EXPECT_EQ(missing.status, 2);
  EXPECT_EQ(missing.err, fmt::format("syrof compare: B: '{}': no such file or folder\n", (dir / "nothing").string()));
  EXPECT_EQ(no_replay.status, 2);
  EXPECT_TRUE(Contains(no_replay.err, "is a folder without a replay file")) << no_replay.err;
  fs::remove_all(dir);
}

// Through the built command: main wires it, and 1 means "differ".
TEST(CompareCommandTest, TheExecutableExitsWithTheComparisonsStatus) {
  const fs::path dir = TestDir();
  const SyntheticRun a = SteppedRun(2, 3);
  SyntheticRun b = a;
  replay::testing::DropStart(b, StartRoundOf(2), 0);
  const std::string path_a = WriteReplay(dir / "a.replay", a.Bytes());
  const std::string path_b = WriteReplay(dir / "b.replay", b.Bytes());
  const auto status = [](const std::string& arguments) {
    return WEXITSTATUS(std::system((std::string(SYROF_EXECUTABLE) + " compare " + arguments + " > /dev/null 2>&1").c_str()));
  };

  EXPECT_EQ(status(path_a + " " + path_a), 0);
  EXPECT_EQ(status(path_a + " " + path_b), 1);
  EXPECT_EQ(status(path_a + " " + (dir / "nothing").string()), 2);
  EXPECT_EQ(status(path_a), 2);                                           // RUN_B missing
  EXPECT_EQ(status(path_a + " " + path_a + " --pose-tolerance-m -1"), 2);  // not a distance
  EXPECT_EQ(status("--help"), 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace syrof::cli
