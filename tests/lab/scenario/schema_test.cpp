// One test per validation rule: each checks the place of the error and the
// key path its message names.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scenario_test_util.h"

namespace syrof::lab::scenario {
namespace {

using testing::FailsAt;
using testing::kMinimal;
using testing::Load;

// kMinimal followed by `more` (which starts on line 3).
LoadResult LoadWith(const std::string& more, const Overrides& overrides = {}) {
  return Load(std::string(kMinimal) + more, overrides);
}

// --- keys -------------------------------------------------------------------

TEST(Schema, UnknownTopLevelKeySuggestsTheNearest) {
  EXPECT_TRUE(FailsAt(Load("robtos: { count: 4 }\napp: builtin:idle\n"), 1, 1,
                      {"unknown key 'robtos'", "did you mean 'robots'?"}));
}

TEST(Schema, UnknownNestedKeyNamesItsPathAndSuggests) {
  EXPECT_TRUE(FailsAt(Load("robots: { cuont: 4 }\napp: builtin:idle\n"), 1, 11,
                      {"robots: unknown key 'cuont'", "did you mean 'count'?"}));
}

TEST(Schema, UnknownKeyFarFromAnyListsTheValidKeys) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { velocity: 3 }\n"), 3, 11,
                      {"timing: unknown key 'velocity'", "valid keys: radio_round_s"}));
}

TEST(Schema, MissingRobotsIsReportedAtTheTopLevelMap) {
  EXPECT_TRUE(FailsAt(Load("app: builtin:idle\n"), 1, 1, {"missing required key 'robots'"}));
}

TEST(Schema, MissingAppIsReportedAtTheTopLevelMap) {
  EXPECT_TRUE(FailsAt(Load("seed: 3\nrobots: { count: 2 }\n"), 1, 1, {"missing required key 'app'"}));
}

TEST(Schema, MissingCountIsReportedAtTheRobotsMap) {
  EXPECT_TRUE(FailsAt(Load("robots:\n  placement: grid\napp: builtin:idle\n"), 2, 3,
                      {"robots: missing required key 'robots.count'"}));
}

TEST(Schema, TopLevelMustBeAMap) {
  EXPECT_TRUE(FailsAt(Load("- a\n- b\n"), 1, 1, {"top level must be a map", "a list"}));
}

// --- types ------------------------------------------------------------------

TEST(Schema, WrongTypeNumber) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { duration_s: soon }\n"), 3, 23,
                      {"timing.duration_s: expected a number, got 'soon'"}));
}

TEST(Schema, QuotedNumberIsAString) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { duration_s: \"20\" }\n"), 3, 23,
                      {"timing.duration_s: expected a number", "quoted string"}));
}

TEST(Schema, WrongTypeInteger) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { vote_rounds: 2.5 }\n"), 3, 24,
                      {"timing.vote_rounds: expected an integer, got '2.5'"}));
}

TEST(Schema, WrongTypeList) {
  EXPECT_TRUE(FailsAt(LoadWith("faults: { crash: 1 }\n"), 3, 9, {"faults: expected a list, got a map"}));
}

TEST(Schema, WrongTypeMap) {
  EXPECT_TRUE(FailsAt(LoadWith("arena: 4\n"), 3, 8, {"arena: expected a map, got '4'"}));
}

TEST(Schema, WrongTypeString) {
  EXPECT_TRUE(FailsAt(LoadWith("name: [a, b]\n"), 3, 7, {"name: expected a string, got a list"}));
}

TEST(Schema, WrongTypeChoiceSuggestsTheNearest) {
  EXPECT_TRUE(FailsAt(Load("robots: { count: 3, placement: cirle }\napp: builtin:idle\n"), 1, 32,
                      {"robots.placement: unknown value 'cirle'", "did you mean 'circle'?", "grid"}));
}

TEST(Schema, NotANumberIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { duration_s: .nan }\n"), 3, 23, {"timing.duration_s: expected a number"}));
}

TEST(Schema, InfinityIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { duration_s: inf }\n"), 3, 23,
                      {"timing.duration_s: expected a finite number"}));
}

TEST(Schema, OverflowingNumberIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { duration_s: 1e999 }\n"), 3, 23,
                      {"timing.duration_s: expected a finite number"}));
}

TEST(Schema, SeedAcceptsTheWholeUnsigned64Range) {
  const LoadResult result = LoadWith("seed: 18446744073709551615\n");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.scenario->seed, 18446744073709551615ull);
}

TEST(Schema, SeedBeyondUnsigned64IsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("seed: 18446744073709551616\n"), 3, 7, {"seed: must be at most 18446744073709551615"}));
}

TEST(Schema, SeedMustBeDecimal) {
  EXPECT_TRUE(FailsAt(LoadWith("seed: 0x10\n"), 3, 7, {"seed: expected an unsigned integer in decimal digits"}));
}

TEST(Schema, NegativeSeedIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("seed: -1\n"), 3, 7, {"seed: expected an unsigned integer"}));
}

TEST(Schema, NameMustBeSafeForFiles) {
  EXPECT_TRUE(FailsAt(LoadWith("name: ../etc/passwd\n"), 3, 7, {"name: must be 1 to 64 letters"}));
}

// --- ranges -----------------------------------------------------------------

TEST(Schema, NegativeArenaSizeIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("arena: { width_m: -4 }\n"), 3, 19, {"arena.width_m: must be in (0, 1000], got -4"}));
}

TEST(Schema, ProbabilityAboveOneIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("channel: { loss: 1.5 }\n"), 3, 18, {"channel.loss: must be in [0, 1], got 1.5"}));
}

TEST(Schema, NegativeProbabilityIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("sensors: { uwb: { dropout_probability: -0.1 } }\n"), 3, 40,
                      {"sensors.uwb.dropout_probability: must be in [0, 1]"}));
}

TEST(Schema, OutlierRangeMustNotBeReversed) {
  EXPECT_TRUE(FailsAt(LoadWith("sensors: { uwb: { outlier_min_m: 2, outlier_max_m: 1 } }\n"), 3, 52,
                      {"sensors.uwb.outlier_max_m: must be at least outlier_min_m"}));
}

TEST(Schema, VoteRoundsBelowOneIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { vote_rounds: 0 }\n"), 3, 24, {"timing.vote_rounds: must be in [1, 200]"}));
}

TEST(Schema, VoteRoundsAbove200IsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { vote_rounds: 201, silence_rounds: 400, app_round_s: 20 }\n"), 3, 24,
                      {"timing.vote_rounds: must be in [1, 200], got 201"}));
}

TEST(Schema, SilenceRoundsMustExceedVoteRounds) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { vote_rounds: 4, silence_rounds: 4 }\n"), 3, 43,
                      {"timing.silence_rounds", "must be greater than K"}));
}

TEST(Schema, AppRoundMustBeWholeRadioRounds) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { app_round_s: 1.03 }\n"), 3, 24,
                      {"timing.app_round_s", "whole number of radio rounds"}));
}

TEST(Schema, AppRoundMustLastAtLeastKRounds) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { app_round_s: 0.1 }\n"), 3, 24,
                      {"timing.app_round_s", "at least K = 3 radio rounds"}));
}

TEST(Schema, AppRoundTooShortForALargerKBlamesK) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { vote_rounds: 30, silence_rounds: 60 }\n"), 3, 24,
                      {"timing.vote_rounds", "at least K = 30 radio rounds"}));
}

TEST(Schema, PhysicsStepMustDivideTheRadioRound) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { physics_step_s: 0.03 }\n"), 3, 27,
                      {"timing.physics_step_s", "must divide radio_round_s"}));
}

TEST(Schema, KindRadiusMustBePositive) {
  EXPECT_TRUE(FailsAt(LoadWith("kinds: { omni: { body_radius_m: 0 } }\n"), 3, 33,
                      {"kinds.omni.body_radius_m: must be in (0, 1]"}));
}

TEST(Schema, KindKeysDependOnTheKind) {
  EXPECT_TRUE(FailsAt(LoadWith("kinds: { rover: { max_turn_rate_radps: 2 } }\n"), 3, 19,
                      {"kinds.rover: unknown key 'max_turn_rate_radps'"}));
}

TEST(Schema, DroneIsAKindWhereverRoverIs) {
  const LoadResult loaded = Load(
      "arena: { width_m: 4, height_m: 4 }\n"
      "kinds: { drone: { max_speed_mps: 0.7, tilt_time_constant_s: 0.3, flight_height_m: 0.4 } }\n"
      "robots: { kind: drone, poses: [ {x_m: 1, y_m: 1}, {x_m: 3, y_m: 3, kind: omni}, {x_m: 2, y_m: 1, kind: rover} ] }\n"
      "app: builtin:idle\n");
  ASSERT_TRUE(loaded.ok()) << loaded.error->ToString();
  const Scenario& scenario = *loaded.scenario;
  EXPECT_EQ(scenario.robots[0].kind, world::RobotKind::kDrone);
  EXPECT_EQ(scenario.robots[1].kind, world::RobotKind::kOmni);
  EXPECT_EQ(scenario.robots[2].kind, world::RobotKind::kRover);
  EXPECT_DOUBLE_EQ(scenario.kind_spec(world::RobotKind::kDrone).max_speed_mps, 0.7);
  EXPECT_DOUBLE_EQ(scenario.drone.tilt_time_constant_s, 0.3);
  EXPECT_DOUBLE_EQ(scenario.drone.flight_height_m, 0.4);
  EXPECT_DOUBLE_EQ(scenario.drone.max_accel_mps2, 0.5);  // the default
}

TEST(Schema, DroneKeysAreTheDronesAlone) {
  EXPECT_TRUE(FailsAt(LoadWith("kinds: { drone: { wheel_base_m: 0.2 } }\n"), 3, 19,
                      {"kinds.drone: unknown key 'wheel_base_m'"}));
  EXPECT_TRUE(FailsAt(LoadWith("kinds: { omni: { tilt_time_constant_s: 0.2 } }\n"), 3, 18,
                      {"kinds.omni: unknown key 'tilt_time_constant_s'"}));
  EXPECT_TRUE(FailsAt(LoadWith("kinds: { drone: { drift_sigma_mps: -1 } }\n"), 3, 36,
                      {"kinds.drone.drift_sigma_mps: must be in [0, 0.5]"}));
}

TEST(Schema, ADroneInAnArenaTooSmallForItsStoppingDistanceIsRefusedByName) {
  // 2 x (0.12 + 0.84) = 1.92 m needed; 1.5 m given.
  const LoadResult loaded = Load(
      "arena: { width_m: 3, height_m: 1.5 }\n"
      "robots: { kind: omni, poses: [ {x_m: 0.5, y_m: 0.5}, {x_m: 2, y_m: 0.75, kind: drone} ] }\n"
      "app: builtin:idle\n");
  EXPECT_TRUE(FailsAt(loaded, 2, 54,
                      {"robot 1 is a drone", "too small for its stopping distance", "0.84 m to stop",
                       "at least 2 x (radius + stopping distance) = 1.92 m"}));
  // A slower drone fits: 0.3^2 / 1 + 0.3 * 0.25 = 0.165 m to stop.
  EXPECT_TRUE(Load("arena: { width_m: 3, height_m: 1.5 }\n"
                   "kinds: { drone: { max_speed_mps: 0.3 } }\n"
                   "robots: { kind: omni, poses: [ {x_m: 0.5, y_m: 0.5}, {x_m: 2, y_m: 0.75, kind: drone} ] }\n"
                   "app: builtin:idle\n")
                  .ok());
}

// --- the arena's anchors ----------------------------------------------------

TEST(Schema, TooFewAnchorsAreRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("arena: { anchors: [ {x_m: 0, y_m: 0}, {x_m: 4, y_m: 4} ] }\n"), 3, 19,
                      {"arena.anchors: needs 3 to 8 anchors, got 2"}));
}

TEST(Schema, AnchorFarOutsideTheArenaIsImplausible) {
  EXPECT_TRUE(FailsAt(LoadWith("arena: { anchors: [ {x_m: 0, y_m: 0}, {x_m: 40, y_m: 4}, {x_m: 0, y_m: 4} ] }\n"), 3,
                      45, {"arena.anchors[1].x_m: must be in [-4, 8], got 40"}));
}

TEST(Schema, AnchorBelowTheFloorIsImplausible) {
  EXPECT_TRUE(FailsAt(
      LoadWith("arena: { anchors: [ {x_m: 0, y_m: 0, z_m: -1}, {x_m: 4, y_m: 4}, {x_m: 0, y_m: 4} ] }\n"), 3, 43,
      {"arena.anchors[0].z_m: must be in [0, 20]"}));
}

TEST(Schema, AnchorsListedTwiceAreRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("arena: { anchors: [ {x_m: 0, y_m: 0}, {x_m: 4, y_m: 4}, {x_m: 0, y_m: 0} ] }\n"), 3,
                      57, {"arena.anchors[2]", "within 0.1 m of anchors[0]"}));
}

TEST(Schema, AnchorsOnOneLineAreRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("arena: { anchors: [ {x_m: 0, y_m: 0}, {x_m: 2, y_m: 2, z_m: 2}, {x_m: 4, y_m: 4} ] }\n"),
                      3, 19, {"arena.anchors", "on one line"}));
}

// --- robots -----------------------------------------------------------------

TEST(Schema, RobotCountBelowOneIsRefused) {
  EXPECT_TRUE(FailsAt(Load("robots: { count: 0 }\napp: builtin:idle\n"), 1, 18, {"robots.count: must be in [1, 1024]"}));
}

TEST(Schema, RobotCountAboveCapacityIsRefusedBeforeNarrowing) {
  EXPECT_TRUE(FailsAt(Load("robots: { count: 4294967297 }\napp: builtin:idle\n"), 1, 18,
                      {"robots.count: must be in [1, 1024], got 4294967297"}));
}

TEST(Schema, CountMustMatchThePoses) {
  EXPECT_TRUE(FailsAt(Load("robots:\n  count: 3\n  poses: [ {x_m: 1, y_m: 1} ]\napp: builtin:idle\n"), 2, 10,
                      {"robots.count: 3 does not match the 1 poses listed"}));
}

TEST(Schema, PlacementKeyOfAnotherPlacementIsRefused) {
  EXPECT_TRUE(FailsAt(Load("robots: { count: 3, radius_m: 1 }\napp: builtin:idle\n"), 1, 21,
                      {"robots: 'radius_m' applies to placement circle only (placement is grid)"}));
}

TEST(Schema, ExplicitPlacementNeedsPoses) {
  EXPECT_TRUE(FailsAt(Load("robots: { count: 3, placement: explicit }\napp: builtin:idle\n"), 1, 9,
                      {"missing required key 'robots.poses'"}));
}

TEST(Schema, PoseNeedsItsCoordinates) {
  EXPECT_TRUE(FailsAt(Load("robots: { poses: [ {x_m: 1} ] }\napp: builtin:idle\n"), 1, 20,
                      {"robots.poses[0]: missing required key 'robots.poses[0].y_m'"}));
}

TEST(Schema, CentreOutsideTheArenaIsRefused) {
  EXPECT_TRUE(FailsAt(Load("robots: { count: 1, centre: {x_m: 5, y_m: 1} }\napp: builtin:idle\n"), 1, 35,
                      {"robots.centre.x_m: must be in [0, 4]"}));
}

// --- faults -----------------------------------------------------------------

TEST(Schema, FaultRobotIdOutOfRange) {
  EXPECT_TRUE(FailsAt(LoadWith("faults: [ {crash: 4, at_s: 1} ]\n"), 3, 19,
                      {"faults[0].crash: robot id 4 is out of range: the scenario has 4 robots (ids 0..3)"}));
}

TEST(Schema, NegativeFaultRobotIdIsOutOfRange) {
  EXPECT_TRUE(FailsAt(LoadWith("faults: [ {crash: -1, at_s: 1} ]\n"), 3, 19, {"faults[0].crash: robot id -1"}));
}

TEST(Schema, PauseMustEndAfterItStarts) {
  EXPECT_TRUE(FailsAt(LoadWith("faults:\n  - { pause: 1, at_s: 5, until_s: 5 }\n"), 4, 35,
                      {"faults[0].until_s: must be greater than at_s (5)"}));
}

TEST(Schema, PauseNeedsUntil) {
  EXPECT_TRUE(FailsAt(LoadWith("faults:\n  - { pause: 1, at_s: 5 }\n"), 4, 5, {"missing required key 'faults[0].until_s'"}));
}

TEST(Schema, UntilIsForPausesOnly) {
  EXPECT_TRUE(FailsAt(LoadWith("faults:\n  - { crash: 1, at_s: 5, until_s: 6 }\n"), 4, 26,
                      {"faults[0]: 'until_s' applies to pause, deaf and mute faults only"}));
}

TEST(Schema, DeafAndMuteNeedAnIntervalAndMayOverlapAnything) {
  EXPECT_TRUE(FailsAt(LoadWith("faults:\n  - { deaf: 1, at_s: 5 }\n"), 4, 5, {"missing required key 'faults[0].until_s'"}));
  EXPECT_TRUE(FailsAt(LoadWith("faults:\n  - { mute: 1, at_s: 5, until_s: 4 }\n"), 4, 34,
                      {"faults[0].until_s: must be greater than at_s (5)"}));
  const LoadResult result = LoadWith(
      "faults:\n"
      "  - { pause: 1, at_s: 2, until_s: 6 }\n"
      "  - { deaf: 1, at_s: 3, until_s: 99 }\n"
      "  - { mute: 1, at_s: 4, until_s: 5 }\n");
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  ASSERT_EQ(result.scenario->faults.size(), 3u);
  EXPECT_EQ(result.scenario->faults[1].kind, FaultKind::kDeaf);
  EXPECT_EQ(result.scenario->faults[1].until_s, 99);
  EXPECT_EQ(result.scenario->faults[2].kind, FaultKind::kMute);
}

TEST(Schema, SilenceAndAppRoundAreBoundedForTheEpochNumbers) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { silence_rounds: 4097 }\n"), 3, 27, {"timing.silence_rounds"}));
  EXPECT_TRUE(FailsAt(LoadWith("timing: { radio_round_s: 0.01, app_round_s: 41 }\n"), 3, 45,
                      {"must last at most 4096 radio rounds"}));
}

TEST(Schema, FaultAfterTheDurationIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { duration_s: 20 }\nfaults:\n  - { crash: 1, at_s: 25 }\n"), 5, 23,
                      {"faults[0].at_s", "after the end of the run (duration_s = 20)"}));
}

TEST(Schema, FaultNeedsAKind) {
  EXPECT_TRUE(FailsAt(LoadWith("faults:\n  - { at_s: 5 }\n"), 4, 5, {"faults[0]: a fault needs one of crash, pause, join"}));
}

TEST(Schema, FaultWithTwoKindsIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("faults:\n  - { crash: 1, join: 1, at_s: 5 }\n"), 4, 5,
                      {"faults[0]: names two fault kinds"}));
}

TEST(Schema, NothingHappensToACrashedRobot) {
  EXPECT_TRUE(FailsAt(LoadWith("faults:\n  - { pause: 1, at_s: 9, until_s: 10 }\n  - { crash: 1, at_s: 5 }\n"), 4, 5,
                      {"faults[0]: robot 1 already crashed at 5 s (faults[1])"}));
}

TEST(Schema, JoinComesFirst) {
  EXPECT_TRUE(FailsAt(LoadWith("faults:\n  - { pause: 2, at_s: 1, until_s: 2 }\n  - { join: 2, at_s: 3 }\n"), 5, 5,
                      {"faults[1]: robot 2 joins only once, before its other faults"}));
}

TEST(Schema, PausesOfOneRobotMustNotOverlap) {
  EXPECT_TRUE(FailsAt(
      LoadWith("faults:\n  - { pause: 2, at_s: 1, until_s: 5 }\n  - { pause: 2, at_s: 4, until_s: 6 }\n"), 5, 5,
      {"faults[1]: robot 2 is still paused until 5 s (faults[0])"}));
}

TEST(Schema, FaultsAreSortedByTimeThenRobotAndJoinersStartAbsent) {
  const LoadResult result = LoadWith(
      "faults:\n"
      "  - { crash: 3, at_s: 12 }\n"
      "  - { join: 2, at_s: 3 }\n"
      "  - { pause: 0, at_s: 3, until_s: 4 }\n");

  ASSERT_TRUE(result.ok()) << result.error->ToString();
  const std::vector<FaultSpec>& faults = result.scenario->faults;
  ASSERT_EQ(faults.size(), 3u);
  EXPECT_EQ(faults[0].robot, 0);
  EXPECT_EQ(faults[0].kind, FaultKind::kPause);
  EXPECT_EQ(faults[0].until_s, 4);
  EXPECT_EQ(faults[1].robot, 2);
  EXPECT_EQ(faults[1].kind, FaultKind::kJoin);
  EXPECT_EQ(faults[2].robot, 3);
  EXPECT_FALSE(result.scenario->robots[2].present_at_start);
  EXPECT_TRUE(result.scenario->robots[3].present_at_start);
}

// --- the channel ------------------------------------------------------------

TEST(Schema, ModelKeysDependOnTheModel) {
  EXPECT_TRUE(FailsAt(LoadWith("channel: { model: gilbert_elliott, loss: 0.1 }\n"), 3, 36,
                      {"channel: 'loss' applies to model iid only (model is gilbert_elliott)"}));
}

TEST(Schema, AScriptedChannelListsItsLostBeacons) {
  const LoadResult result =
      LoadWith("channel: { model: scripted, lost: [[12, 0, 3], [40, 3, 0]] }\n");
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.scenario->channel.model, world::ChannelModel::kScripted);
  EXPECT_EQ(result.scenario->channel.lost, (std::vector<world::LostBeacon>{{12, 0, 3}, {40, 3, 0}}));
}

TEST(Schema, AScriptedChannelsMistakesAreNamed) {
  EXPECT_TRUE(FailsAt(LoadWith("channel: { model: scripted, lost: [[12, 0]] }\n"), 3, 36,
                      {"channel.lost[0]: must be [round, sender, receiver], got 2 numbers"}));
  EXPECT_TRUE(FailsAt(LoadWith("channel: { model: scripted, lost: [[12, 0, 9]] }\n"), 3, 44,
                      {"channel.lost[0][2]", "robot id 9 is out of range"}));
  EXPECT_TRUE(FailsAt(LoadWith("channel: { model: scripted, lost: [[12, 1, 1]] }\n"), 3, 44,
                      {"never hears its own beacon"}));
  EXPECT_TRUE(FailsAt(LoadWith("channel: { model: scripted, lost: [[-3, 0, 1]] }\n"), 3, 37, {"channel.lost[0][0]"}));
  EXPECT_TRUE(FailsAt(LoadWith("channel: { lost: [[12, 0, 1]] }\n"), 3, 12,
                      {"'lost' applies to model scripted only (model is iid)"}));
  EXPECT_TRUE(FailsAt(LoadWith("channel: { model: scripted, loss: 0.1 }\n"), 3, 29,
                      {"'loss' applies to model iid only (model is scripted)"}));
  EXPECT_TRUE(FailsAt(LoadWith("channel: { model: scripted, lost_file: no_such.yaml }\n"), 3, 40,
                      {"no such file 'no_such.yaml'"}));
}

TEST(Schema, AScriptedChannelReadsItsListFromAFile) {
  const std::string folder = ::testing::TempDir() + "scripted_channel_" + std::to_string(getpid());
  std::filesystem::create_directories(folder);
  std::ofstream(folder + "/lost.yaml") << "# losses\n- [3, 1, 0]\n- [4, 2, 0]\n";
  std::ofstream(folder + "/bad.yaml") << "- [3, 1, 0]\n- [4, 2]\n";
  std::ofstream(folder + "/run.yaml") << kMinimal << "channel: { model: scripted, lost_file: lost.yaml }\n";
  std::ofstream(folder + "/bad_run.yaml") << kMinimal << "channel: { model: scripted, lost_file: bad.yaml }\n";
  const LoadResult result = LoadScenarioFile(folder + "/run.yaml");
  const LoadResult bad = LoadScenarioFile(folder + "/bad_run.yaml");
  std::filesystem::remove_all(folder);
  ASSERT_TRUE(result.ok()) << result.error->ToString();
  EXPECT_EQ(result.scenario->channel.lost, (std::vector<world::LostBeacon>{{3, 1, 0}, {4, 2, 0}}));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error->message.find("bad.yaml:2:3: lost[1]: must be [round, sender, receiver]"), std::string::npos)
      << bad.error->ToString();
}

// A lost_file is held to the scenario's own text rules, and a path that is
// not a file says what it is instead of "no such file".
TEST(Schema, AScriptedChannelsFileIsOneYamlDocumentInAFile) {
  const std::string folder = ::testing::TempDir() + "scripted_channel_file_" + std::to_string(getpid());
  std::filesystem::create_directories(folder);
  std::ofstream(folder + "/two.yaml") << "- [3, 1, 0]\n---\n- [4, 2, 0]\n";
  ASSERT_EQ(mkfifo((folder + "/fifo").c_str(), 0600), 0);
  std::filesystem::create_symlink("loop", folder + "/loop");
  const auto load = [&folder](const std::string& lost_file) {
    std::ofstream(folder + "/run.yaml") << kMinimal << "channel: { model: scripted, lost_file: " << lost_file << " }\n";
    return LoadScenarioFile(folder + "/run.yaml");
  };
  const LoadResult two = load("two.yaml");
  const LoadResult directory = load(".");
  const LoadResult device = load("/dev/zero");
  const LoadResult fifo = load("fifo");
  const LoadResult loop = load("loop");
  std::filesystem::remove_all(folder);
  EXPECT_TRUE(FailsAt(two, 3, 29, {"channel.lost_file: ", "two.yaml:2:1: ", "second YAML document"}));
  EXPECT_TRUE(FailsAt(directory, 3, 40, {"channel.lost_file: '.' is a directory"}));
  EXPECT_TRUE(FailsAt(device, 3, 40, {"'/dev/zero' is not a regular file"}));
  EXPECT_TRUE(FailsAt(fifo, 3, 40, {"'fifo' is not a regular file"}));
  EXPECT_TRUE(FailsAt(loop, 3, 40, {"'loop' cannot be read"}));
  EXPECT_TRUE(FailsAt(LoadWith("channel: { model: scripted, lost_file: '' }\n"), 3, 40, {"must name a file"}));
}

TEST(Schema, LinkRobotIdOutOfRange) {
  EXPECT_TRUE(FailsAt(LoadWith("channel:\n  links: [ {from: 0, to: 7, loss: 0.5} ]\n"), 4, 26,
                      {"channel.links[0].to: robot id 7 is out of range"}));
}

TEST(Schema, LinkToItselfIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("channel:\n  links: [ {from: 1, to: 1, loss: 0.5} ]\n"), 4, 12,
                      {"channel.links[0]: a link joins two different robots"}));
}

TEST(Schema, LinkGivenTwiceIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("channel:\n  links:\n    - {from: 1, to: 2, loss: 0.5}\n    - {from: 1, to: 2, loss: 0.1}\n"),
                      6, 7, {"channel.links[1]: the link 1 -> 2 is already given in links[0]"}));
}

TEST(Schema, CutsAreReadWithTheirWindowAndDirection) {
  const LoadResult loaded = LoadWith(
      "channel:\n  cuts:\n    - { from: 3, to: 1, start_s: 1, end_s: 2 }\n"
      "    - { from: 0, to: 2, start_s: 0.5, end_s: 4, both_ways: true }\n");
  ASSERT_TRUE(loaded.ok()) << loaded.error->ToString();
  ASSERT_EQ(loaded.scenario->channel.cuts.size(), 2u);
  EXPECT_EQ(loaded.scenario->channel.cuts[0].from, 3);
  EXPECT_EQ(loaded.scenario->channel.cuts[0].to, 1);
  EXPECT_FALSE(loaded.scenario->channel.cuts[0].both_ways);
  EXPECT_TRUE(loaded.scenario->channel.cuts[1].both_ways);
  EXPECT_EQ(loaded.scenario->channel.cuts[1].end_s, 4);
}

TEST(Schema, BadCutsAreRefusedWhereTheyAreWrong) {
  EXPECT_TRUE(FailsAt(LoadWith("channel:\n  cuts: [ {from: 1, to: 1, start_s: 1, end_s: 2} ]\n"), 4, 11,
                      {"channel.cuts[0]: a cut joins two different robots"}));
  EXPECT_TRUE(FailsAt(LoadWith("channel:\n  cuts: [ {from: 1, to: 2, start_s: 3, end_s: 2} ]\n"), 4, 47,
                      {"channel.cuts[0].end_s: must be greater than start_s"}));
  EXPECT_TRUE(FailsAt(LoadWith("channel:\n  cuts: [ {from: 1, to: 2, start_s: 1, end_s: 2, both_ways: yes} ]\n"), 4,
                      61, {"channel.cuts[0].both_ways: must be true or false"}));
  EXPECT_TRUE(FailsAt(LoadWith("channel:\n  cuts: [ {from: 1, to: 2, start_s: 1} ]\n"), 4, 11,
                      {"channel.cuts[0]", "end_s"}));
}

TEST(Schema, PartitionRobotListedTwice) {
  EXPECT_TRUE(FailsAt(LoadWith("channel:\n  partitions:\n    - { start_s: 1, end_s: 2, groups: [[0, 1], [2, 1]] }\n"),
                      5, 52, {"channel.partitions[0].groups[1][1]: robot 1 is listed twice (already in groups[0])"}));
}

TEST(Schema, PartitionRobotIdOutOfRange) {
  EXPECT_TRUE(FailsAt(LoadWith("channel:\n  partitions:\n    - { start_s: 1, end_s: 2, groups: [[0, 9]] }\n"), 5, 44,
                      {"channel.partitions[0].groups[0][1]: robot id 9 is out of range"}));
}

TEST(Schema, PartitionMustEndAfterItStarts) {
  EXPECT_TRUE(FailsAt(LoadWith("channel:\n  partitions:\n    - { start_s: 5, end_s: 2, groups: [[0]] }\n"), 5, 28,
                      {"channel.partitions[0].end_s: must be greater than start_s (5)"}));
}

TEST(Schema, PartitionAfterTheDurationIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("timing: { duration_s: 4 }\nchannel:\n  partitions:\n    - { start_s: 5, end_s: 8, groups: [[0]] }\n"),
                      6, 18, {"channel.partitions[0].start_s", "after the end of the run"}));
}

TEST(Schema, PartitionsMustNotOverlap) {
  EXPECT_TRUE(FailsAt(LoadWith("channel:\n  partitions:\n"
                               "    - { start_s: 1, end_s: 5, groups: [[0]] }\n"
                               "    - { start_s: 4, end_s: 6, groups: [[1]] }\n"),
                      6, 7, {"channel.partitions[1]", "overlaps partitions[0]"}));
}

}  // namespace
}  // namespace syrof::lab::scenario

namespace syrof::lab::scenario {
namespace {

// --- safety (docs/safety.md) --------------------------------------------------

TEST(SchemaSafety, IsOnUnlessTheScenarioSaysOff) {
  const LoadResult plain = testing::Load(testing::kMinimal);
  const LoadResult off = testing::Load(std::string(testing::kMinimal) + "safety: off\n");
  const LoadResult on = testing::Load(std::string(testing::kMinimal) + "safety: on\n");

  ASSERT_TRUE(plain.ok() && off.ok() && on.ok());
  EXPECT_TRUE(plain.scenario->safety);
  EXPECT_FALSE(off.scenario->safety);
  EXPECT_TRUE(on.scenario->safety);
}

TEST(SchemaSafety, AnUnknownValueNamesThePlaceAndTheNearest) {
  EXPECT_TRUE(testing::FailsAt(testing::Load(std::string(testing::kMinimal) + "safety: offf\n"), 3, 9,
                               {"safety: unknown value 'offf'", "did you mean 'off'?", "on, off"}));
}

TEST(SchemaSafety, AMisspelledKeySuggestsSafety) {
  EXPECT_TRUE(testing::FailsAt(testing::Load(std::string(testing::kMinimal) + "safty: off\n"), 3, 1,
                               {"unknown key 'safty'", "did you mean 'safety'?"}));
}

// Beacons carry positions as int16 millimetres: a 60 m arena was accepted and
// its positions silently clipped at 32.767 m (gather aimed at 18.9 m, not 30).
TEST(SchemaSafety, AnArenaLargerThanTheBeaconCanExpressIsRefused) {
  EXPECT_TRUE(testing::FailsAt(
      testing::Load(std::string(testing::kMinimal) + "arena: { width_m: 60, height_m: 4 }\n"), 3, 19,
      {"arena.width_m", "60 m wide", "int16 millimetres", "at most 32.767 m"}));
  EXPECT_TRUE(testing::FailsAt(
      testing::Load(std::string(testing::kMinimal) + "arena: { width_m: 4, height_m: 32.8 }\n"), 3, 32,
      {"arena.height_m", "32.8 m high"}));
  EXPECT_TRUE(testing::Load(std::string(testing::kMinimal) + "arena: { width_m: 32.767, height_m: 4 }\n").ok());
}

// --- clocks ------------------------------------------------------------------

TEST(Schema, NoClocksSectionKeepsTheSharedClock) {
  const LoadResult result = LoadWith("");
  ASSERT_TRUE(result.ok());
  EXPECT_FALSE(result.scenario->clocks.enabled);
}

TEST(Schema, ClocksFixedAndSeededValuesResolvePerRobot) {
  const LoadResult fixed = LoadWith("clocks: { offset_ms: [0, 10, 20, 49.5], drift_ppm: -30, alignment: off }\n");
  ASSERT_TRUE(fixed.ok()) << fixed.error->ToString();
  const ClockSpec& clocks = fixed.scenario->clocks;
  EXPECT_TRUE(clocks.enabled);
  EXPECT_FALSE(clocks.alignment);
  EXPECT_EQ(clocks.offset_ms, (std::vector<double>{0, 10, 20, 49.5}));
  EXPECT_EQ(clocks.drift_ppm, (std::vector<double>(4, -30.0)));

  const LoadResult seeded = LoadWith("clocks: { offset_max_ms: 50, drift_max_ppm: 100, jitter_ms: 0.5 }\n");
  ASSERT_TRUE(seeded.ok());
  const ClockSpec& drawn = seeded.scenario->clocks;
  ASSERT_EQ(drawn.offset_ms.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_GE(drawn.offset_ms[i], 0);
    EXPECT_LE(drawn.offset_ms[i], 50);
    EXPECT_GE(drawn.drift_ppm[i], -100);
    EXPECT_LE(drawn.drift_ppm[i], 100);
  }
  EXPECT_NE(drawn.offset_ms[0], drawn.offset_ms[1]);
  EXPECT_EQ(LoadWith("clocks: { offset_max_ms: 50, drift_max_ppm: 100, jitter_ms: 0.5 }\n").scenario->clocks.offset_ms,
            drawn.offset_ms);
}

TEST(Schema, ClocksOffsetBeyondARoundIsRefused) {
  EXPECT_TRUE(FailsAt(LoadWith("clocks: {offset_ms: 60}\n"), 3, 21, {"clocks.offset_ms: must be in [0, 50], got 60"}));
}

TEST(Schema, ClocksListNeedsOneValuePerRobot) {
  EXPECT_TRUE(FailsAt(LoadWith("clocks: {offset_ms: [1, 2]}\n"), 3, 21,
                      {"clocks.offset_ms: has 2 values; the scenario has 4 robots"}));
}

TEST(Schema, ClocksFixedAndDrawnExcludeEachOther) {
  EXPECT_TRUE(FailsAt(LoadWith("clocks: {drift_ppm: 5, drift_max_ppm: 3}\n"), 3, 39,
                      {"clocks.drift_max_ppm: give either 'drift_ppm' (fixed) or 'drift_max_ppm'"}));
}

}  // namespace
}  // namespace syrof::lab::scenario
