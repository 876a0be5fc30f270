// The activation model's and the private inputs' boot words (firmware/robot
// boot_words.h): what the swarm host writes on a robot's -append reads back
// on the image into the same schedule and the same inputs, and what the
// image cannot hold, or a line meant for another robot, is refused.
#include "syrof/firmware/robot/boot_words.h"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace syrof::firmware::robot {
namespace {

// Splits `text` at spaces into (key, value) pairs and reads them as the image
// does (into a BootActivation or a BootInputs).
template <typename Boot>
BootWordRead ReadAll(const std::string& text, Boot& boot) {
  std::vector<std::string> words;
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = text.find(' ', start);
    const std::string word = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!word.empty()) words.push_back(word);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  EXPECT_EQ(words.size() % 2, 0u) << text;
  for (size_t i = 0; i + 1 < words.size(); i += 2) {
    const BootWordRead read = boot.Read(words[i].c_str(), words[i + 1].c_str());
    if (read != BootWordRead::kOk) return read;
  }
  return BootWordRead::kOk;
}

std::string Format(const sync::ActivationConfig& config) {
  std::array<char, 4096> out{};
  size_t length = 0;
  EXPECT_EQ(FormatActivationWords(config, out, length), BootWordsError::kOk);
  return std::string(out.data(), length);
}

// Every epoch and member set of a small swarm gets the same answer from both.
void ExpectSameSchedule(const sync::ActivationConfig& a, const sync::ActivationConfig& b) {
  ASSERT_TRUE(sync::IsValid(b));
  EXPECT_EQ(a.model, b.model);
  EXPECT_EQ(a.schedule, b.schedule);
  EXPECT_EQ(a.seed, b.seed);
  for (uint16_t epoch = 0; epoch < 40; ++epoch) {
    for (uint32_t bits = 1; bits < 16; ++bits) {
      wire::MemberSet members;
      for (uint16_t id = 0; id < 4; ++id) {
        if ((bits & (1u << id)) != 0) members.set(id);
      }
      for (uint16_t id = 0; id < 4; ++id) {
        ASSERT_EQ(sync::IsActive(a, epoch, members, id), sync::IsActive(b, epoch, members, id))
            << "epoch " << epoch << " members " << bits << " robot " << id;
      }
    }
    for (uint16_t id = 0; id < 4; ++id) {
      const sync::AsyncCycle ca = sync::CycleFor(a, epoch, id);
      const sync::AsyncCycle cb = sync::CycleFor(b, epoch, id);
      ASSERT_EQ(ca.start_delay, cb.start_delay);
      ASSERT_EQ(ca.move_epochs, cb.move_epochs);
      ASSERT_EQ(ca.cut, cb.cut);
    }
  }
}

TEST(BootWordsTest, FsyncWritesNoWordSoTheBootLineIsUnchanged) {
  EXPECT_EQ(Format(sync::ActivationConfig{}), "");
}

TEST(BootWordsTest, SsyncRandomReadsBackWithItsSeedAndBound) {
  sync::ActivationConfig config;
  config.model = sync::ActivationModel::kSsync;
  config.schedule = sync::ActivationSchedule::kRandom;
  config.seed = 18'446'744'073'709'551'557ull;  // above 2^63: the whole 64 bits
  config.fair_within = 3;
  const std::string words = Format(config);
  EXPECT_EQ(words, " activation ssync schedule random seed 18446744073709551557 fair_within 3");
  BootActivation boot;
  ASSERT_EQ(ReadAll(words, boot), BootWordRead::kOk);
  EXPECT_EQ(boot.config().fair_within, 3);
  ExpectSameSchedule(config, boot.config());
}

TEST(BootWordsTest, SsyncRoundRobinReadsBack) {
  sync::ActivationConfig config;
  config.model = sync::ActivationModel::kSsync;
  config.schedule = sync::ActivationSchedule::kRoundRobin;
  config.seed = 5;
  BootActivation boot;
  ASSERT_EQ(ReadAll(Format(config), boot), BootWordRead::kOk);
  ExpectSameSchedule(config, boot.config());
}

TEST(BootWordsTest, SsyncScriptReadsBackAsOneMaskAnEpoch) {
  const std::vector<sync::ScriptedActivation> script = {{2, 0}, {2, 3}, {3, 1}, {7, 0}, {7, 1}, {7, 2}, {31, 31}};
  sync::ActivationConfig config;
  config.model = sync::ActivationModel::kSsync;
  config.schedule = sync::ActivationSchedule::kScripted;
  config.seed = 1;
  config.script = script;
  const std::string words = Format(config);
  EXPECT_EQ(words, " activation ssync schedule scripted seed 1 active 2:9,3:2,7:7,31:80000000");
  BootActivation boot;
  ASSERT_EQ(ReadAll(words, boot), BootWordRead::kOk);
  const sync::ActivationConfig read = boot.config();
  ASSERT_EQ(read.script.size(), script.size());
  for (size_t i = 0; i < script.size(); ++i) {
    EXPECT_EQ(read.script[i].epoch, script[i].epoch);
    EXPECT_EQ(read.script[i].robot, script[i].robot);
  }
  ExpectSameSchedule(config, read);
}

TEST(BootWordsTest, AsyncRandomAndScriptedReadBack) {
  sync::ActivationConfig config;
  config.model = sync::ActivationModel::kAsync;
  config.schedule = sync::ActivationSchedule::kRandom;
  config.seed = 42;
  config.max_delay_epochs = 2;
  config.min_move_mm = 50;
  BootActivation random;
  ASSERT_EQ(ReadAll(Format(config), random), BootWordRead::kOk);
  EXPECT_EQ(random.config().max_delay_epochs, 2);
  EXPECT_EQ(random.config().min_move_mm, 50u);
  ExpectSameSchedule(config, random.config());

  const std::vector<sync::ScriptedCycle> cycles = {{1, 0, 2, 1, false}, {1, 3, 0, 3, true}, {4, 2, 1, 2, false}};
  config.schedule = sync::ActivationSchedule::kScripted;
  config.cycles = cycles;
  const std::string words = Format(config);
  EXPECT_NE(words.find(" cycles 1:0:2:1:0,1:3:0:3:1,4:2:1:2:0"), std::string::npos) << words;
  BootActivation scripted;
  ASSERT_EQ(ReadAll(words, scripted), BootWordRead::kOk);
  ASSERT_EQ(scripted.config().cycles.size(), cycles.size());
  EXPECT_TRUE(scripted.config().cycles[1].cut);
  ExpectSameSchedule(config, scripted.config());
}

TEST(BootWordsTest, TheImageRefusesMalformedValues) {
  const std::vector<std::pair<const char*, const char*>> bad = {
      {"activation", "lsync"},   {"schedule", "roundrobin"}, {"seed", "-1"},
      {"seed", "18446744073709551616"},                      {"fair_within", "0"},
      {"fair_within", "65536"},  {"max_delay", "9"},         {"min_move_mm", "30001"},
      {"active", "3:0"},         {"active", "3:1,3:2"},      {"active", "4:1,3:2"},
      {"active", "3:1,"},        {"active", "3"},            {"active", "3:1x"},
      {"active", "70000:1"},     {"cycles", "1:0:9:1:0"},    {"cycles", "1:32:0:1:0"},
      {"cycles", "1:0:0:1:2"},   {"cycles", "1:0:0:1"},
  };
  for (const auto& [key, value] : bad) {
    BootActivation boot;
    EXPECT_EQ(boot.Read(key, value), BootWordRead::kBadValue) << key << " " << value;
  }
  BootActivation boot;
  EXPECT_EQ(boot.Read("swarm", "4"), BootWordRead::kNotMine);
}

// A script longer than the image holds: the host refuses to write it, and
// an image given one anyway says it is full rather than keep a part.
TEST(BootWordsTest, AScriptLongerThanTheImageHoldsIsRefusedOnBothSides) {
  std::vector<sync::ScriptedActivation> script;
  for (uint16_t epoch = 1; script.size() <= kMaxBootScriptedActivations; ++epoch) {
    for (uint16_t robot = 0; robot < 4; ++robot) script.push_back({epoch, robot});
  }
  sync::ActivationConfig config;
  config.model = sync::ActivationModel::kSsync;
  config.schedule = sync::ActivationSchedule::kScripted;
  config.script = script;
  std::array<char, 8192> out{};
  size_t length = 0;
  EXPECT_EQ(FormatActivationWords(config, out, length), BootWordsError::kTooManyScripted);
  EXPECT_EQ(length, 0u);

  std::string active;
  for (size_t epoch = 1; epoch <= kMaxBootScriptedActivations / 4 + 1; ++epoch) {
    active += (active.empty() ? "" : ",") + std::to_string(epoch) + ":f";
  }
  BootActivation boot;
  EXPECT_EQ(boot.Read("active", active.c_str()), BootWordRead::kFull);
  EXPECT_TRUE(boot.config().script.empty());

  // A buffer too short for the words writes none.
  config.script = std::span<const sync::ScriptedActivation>(script.data(), 8);
  std::array<char, 40> small{};
  EXPECT_EQ(FormatActivationWords(config, small, length), BootWordsError::kBufferTooSmall);
  EXPECT_EQ(length, 0u);
}

std::string FormatInputs(uint16_t id, const std::vector<app::Parameter>& inputs) {
  std::array<char, 4096> out{};
  size_t length = 0;
  EXPECT_EQ(FormatInputWords(id, inputs, out, length), BootWordsError::kOk);
  return std::string(out.data(), length);
}

TEST(BootWordsTest, NoInputsWriteNoWordAndReadBackAsNone) {
  EXPECT_EQ(FormatInputs(3, {}), "");
  BootInputs boot;
  EXPECT_EQ(boot.Check(3), nullptr);
  EXPECT_TRUE(boot.inputs().empty());
}

TEST(BootWordsTest, InputsReadBackToTheSameDoublesForTheirRobot) {
  // A whole charge as strongest's, 0.3 (written in its short form), and
  // doubles that need 17 digits: a third, the largest, the smallest normal.
  const std::vector<app::Parameter> inputs = {{"charge", 734},
                                              {"key", 0.3},
                                              {"third", 1.0 / 3.0},
                                              {"_big", 1.7976931348623157e308},
                                              {"tiny9", -2.2250738585072014e-308}};
  const std::string words = FormatInputs(2, inputs);
  EXPECT_EQ(words.substr(0, 38), " inputs 2:5 input charge=734 input key") << words;
  EXPECT_NE(words.find(" input key=0.3 "), std::string::npos) << words;
  BootInputs boot;
  ASSERT_EQ(ReadAll(words, boot), BootWordRead::kOk) << words;
  EXPECT_EQ(boot.Check(2), nullptr);
  ASSERT_EQ(boot.inputs().size(), inputs.size());
  for (size_t i = 0; i < inputs.size(); ++i) {
    EXPECT_EQ(boot.inputs()[i].name, inputs[i].name);
    EXPECT_EQ(boot.inputs()[i].value, inputs[i].value) << inputs[i].name;  // bit for bit
    double value = 0;
    EXPECT_EQ(app::FindParameter(boot.inputs(), inputs[i].name, value, SYROF_APP_NO_SUCH_INPUT), SYROF_APP_OK);
    EXPECT_EQ(value, inputs[i].value);
  }
  double value = 7;
  EXPECT_EQ(app::FindParameter(boot.inputs(), "charg", value, SYROF_APP_NO_SUCH_INPUT), SYROF_APP_NO_SUCH_INPUT);
  EXPECT_EQ(value, 7);
}

TEST(BootWordsTest, InputsWrittenForAnotherRobotOrWithOneMissingAreRefusedByTheImage) {
  const std::string words = FormatInputs(2, {{"charge", 5}, {"rank", 1}});
  BootInputs other;
  ASSERT_EQ(ReadAll(words, other), BootWordRead::kOk);
  ASSERT_NE(other.Check(1), nullptr);
  EXPECT_STREQ(other.Check(1), "the inputs were written for robot 2; this is robot 1");

  BootInputs missing;
  ASSERT_EQ(ReadAll(" inputs 2:2 input charge=5", missing), BootWordRead::kOk);
  ASSERT_NE(missing.Check(2), nullptr);
  EXPECT_STREQ(missing.Check(2), "inputs 2:2 announced 2 inputs; 1 came (an input is missing)");

  BootInputs extra;
  EXPECT_EQ(ReadAll(" inputs 2:1 input charge=5 input rank=1", extra), BootWordRead::kFull);
}

TEST(BootWordsTest, MalformedInputWordsAreRefused) {
  for (const char* bad : {"charge", "=5", "charge=", "charge=5x", "charge=nan", "charge=inf", "charge=1e999",
                          "9lives=1", "a-b=1", "charge=5 "}) {
    BootInputs boot;
    ASSERT_EQ(boot.Read("inputs", "0:1"), BootWordRead::kOk);
    EXPECT_EQ(boot.Read("input", bad), BootWordRead::kBadValue) << bad;
  }
  const std::string long_name(kMaxBootInputNameBytes + 1, 'n');
  BootInputs boot;
  ASSERT_EQ(boot.Read("inputs", "0:2"), BootWordRead::kOk);
  EXPECT_EQ(boot.Read("input", (long_name + "=1").c_str()), BootWordRead::kBadValue);
  EXPECT_EQ(boot.Read("input", (long_name.substr(1) + "=1").c_str()), BootWordRead::kOk);  // 63 bytes fit
  EXPECT_EQ(boot.Read("input", (long_name.substr(1) + "=2").c_str()), BootWordRead::kBadValue);  // twice
  EXPECT_EQ(boot.Read("inputs", "0:2"), BootWordRead::kBadValue);  // announced twice

  BootInputs unannounced;
  EXPECT_EQ(unannounced.Read("input", "charge=1"), BootWordRead::kBadValue);
  for (const char* bad : {"1", "1:", ":1", "1:17", "65536:1", "1:1:1"}) {
    BootInputs count;
    EXPECT_EQ(count.Read("inputs", bad), BootWordRead::kBadValue) << bad;
  }
  EXPECT_EQ(unannounced.Read("activation", "ssync"), BootWordRead::kNotMine);
}

TEST(BootWordsTest, InputsTheImageCannotHoldAreRefusedByTheHost) {
  std::vector<std::string> names;
  for (size_t i = 0; i <= kMaxBootInputs; ++i) names.push_back("in" + std::to_string(i));
  std::vector<app::Parameter> inputs;
  for (const std::string& name : names) inputs.push_back({name, 1});
  std::array<char, 4096> out{};
  size_t length = 0;
  EXPECT_EQ(FormatInputWords(0, inputs, out, length), BootWordsError::kTooManyInputs);
  EXPECT_EQ(length, 0u);
  inputs.pop_back();
  EXPECT_EQ(FormatInputWords(0, inputs, out, length), BootWordsError::kOk);
  const std::vector<app::Parameter> not_finite = {{"charge", std::numeric_limits<double>::infinity()}};
  EXPECT_EQ(FormatInputWords(0, not_finite, out, length), BootWordsError::kInvalid);
  const std::vector<app::Parameter> bad_name = {{"a b", 1}};
  EXPECT_EQ(FormatInputWords(0, bad_name, out, length), BootWordsError::kInvalid);
  const std::vector<app::Parameter> twice = {{"a", 1}, {"a", 2}};
  EXPECT_EQ(FormatInputWords(0, twice, out, length), BootWordsError::kInvalid);
  std::array<char, 20> small{};
  EXPECT_EQ(FormatInputWords(0, {{{"charge", 1}}}, small, length), BootWordsError::kBufferTooSmall);
  EXPECT_EQ(length, 0u);
}

// The robot's kind (boot_words.h, "kind" and "swarm_kinds").
constexpr KindSet kOmni = KindBit(motion::RobotKind::kOmni);
constexpr KindSet kRover = KindBit(motion::RobotKind::kRover);
constexpr KindSet kDrone = KindBit(motion::RobotKind::kDrone);

// A swarm of `swarm`'s kinds, one robot each: `self` first (robot 0), then
// the others in RobotKind's order.
std::vector<motion::RobotKind> OneOfEach(motion::RobotKind self, KindSet swarm) {
  std::vector<motion::RobotKind> members = {self};
  for (size_t i = 0; i < motion::kRobotKindCount; ++i) {
    const auto kind = static_cast<motion::RobotKind>(i);
    if (kind != self && (swarm & KindBit(kind)) != 0) members.push_back(kind);
  }
  return members;
}

std::string FormatKinds(motion::RobotKind self, KindSet swarm) {
  std::array<char, 96> out{};
  size_t length = 0;
  EXPECT_EQ(FormatKindWords(self, swarm, OneOfEach(self, swarm), out, length), BootWordsError::kOk);
  return std::string(out.data(), length);
}

TEST(BootWordsTest, AnOmniRobotAmongOmniRobotsWritesNoWordAndReadsBackAsOmni) {
  EXPECT_EQ(FormatKinds(motion::RobotKind::kOmni, kOmni), "");
  BootKind kind;
  ASSERT_EQ(ReadAll("", kind), BootWordRead::kOk);
  EXPECT_EQ(kind.Check(), nullptr);
  EXPECT_EQ(kind.self(), motion::RobotKind::kOmni);
  EXPECT_EQ(kind.swarm(), kOmni);
}

TEST(BootWordsTest, EveryKindInEverySwarmOfItReadsBack) {
  for (size_t i = 0; i < motion::kRobotKindCount; ++i) {
    const auto self = static_cast<motion::RobotKind>(i);
    for (KindSet swarm = 1; swarm < 8; ++swarm) {
      if ((swarm & KindBit(self)) == 0) continue;
      const std::string words = FormatKinds(self, swarm);
      BootKind kind;
      ASSERT_EQ(ReadAll(words, kind), BootWordRead::kOk) << words;
      EXPECT_EQ(kind.Check(), nullptr) << words;
      EXPECT_EQ(kind.self(), self) << words;
      EXPECT_EQ(kind.swarm(), swarm) << words;
      // A mixed swarm's words name every robot's kind; one kind's, none.
      const std::vector<motion::RobotKind> members = OneOfEach(self, swarm);
      if (members.size() > 1) {
        EXPECT_EQ(std::vector<motion::RobotKind>(kind.members().begin(), kind.members().end()), members) << words;
      } else {
        EXPECT_TRUE(kind.members().empty()) << words;
      }
    }
  }
  EXPECT_EQ(FormatKinds(motion::RobotKind::kDrone, kDrone), " kind drone");
  EXPECT_EQ(FormatKinds(motion::RobotKind::kDrone, kOmni | kRover | kDrone),
            " kind drone swarm_kinds omni,rover,drone member_kinds dor");
  EXPECT_EQ(FormatKinds(motion::RobotKind::kOmni, kOmni | kDrone), " kind omni swarm_kinds omni,drone member_kinds od");
}

TEST(BootWordsTest, EveryRobotsKindReachesTheAppsMap) {
  // Robot 1, a rover, in a swarm of two omni robots, a rover and a drone.
  BootKind kind;
  ASSERT_EQ(ReadAll(" kind rover swarm_kinds omni,rover,drone member_kinds ordo", kind), BootWordRead::kOk);
  ASSERT_EQ(kind.Check(), nullptr);
  runtime::RobotConfig config;
  config.sync = sync::SyncConfig::ForSwarm(4, 1);
  std::array<motion::RobotKind, 4> storage{};
  ASSERT_EQ(ConfigureImageKinds(config, kind.self(), kind.swarm(), kind.members(), storage), nullptr);
  const std::vector<motion::RobotKind> expected = {motion::RobotKind::kOmni, motion::RobotKind::kRover,
                                                   motion::RobotKind::kDrone, motion::RobotKind::kOmni};
  EXPECT_EQ(std::vector<motion::RobotKind>(config.member_kinds.begin(), config.member_kinds.end()), expected);
  EXPECT_EQ(config.kind, motion::RobotKind::kRover);

  // Without member_kinds the swarm's kinds come from swarm_kinds, or the
  // robot's own: a swarm of one kind needs no list.
  BootKind drones;
  ASSERT_EQ(ReadAll(" kind drone", drones), BootWordRead::kOk);
  runtime::RobotConfig drone;
  drone.sync = sync::SyncConfig::ForSwarm(3, 2);
  ASSERT_EQ(ConfigureImageKinds(drone, drones.self(), drones.swarm(), drones.members(), storage), nullptr);
  EXPECT_EQ(std::vector<motion::RobotKind>(drone.member_kinds.begin(), drone.member_kinds.end()),
            std::vector<motion::RobotKind>(3, motion::RobotKind::kDrone));

  // member_kinds alone gives the swarm's kinds.
  BootKind listed;
  ASSERT_EQ(ReadAll(" kind omni member_kinds oood", listed), BootWordRead::kOk);
  EXPECT_EQ(listed.Check(), nullptr);
  EXPECT_EQ(listed.swarm(), kOmni | kDrone);
}

TEST(BootWordsTest, MemberKindsThatDisagreeAreRefusedByName) {
  BootKind kind;
  EXPECT_EQ(kind.Read("member_kinds", "oox"), BootWordRead::kBadValue);
  EXPECT_EQ(kind.Read("member_kinds", ""), BootWordRead::kBadValue);
  EXPECT_EQ(kind.Read("member_kinds", "O"), BootWordRead::kBadValue);
  EXPECT_EQ(kind.Read("member_kinds", std::string(kMaxBootMemberKinds + 1, 'o').c_str()), BootWordRead::kBadValue);
  EXPECT_EQ(kind.Read("member_kinds", std::string(kMaxBootMemberKinds, 'o').c_str()), BootWordRead::kOk);

  BootKind other;
  ASSERT_EQ(ReadAll(" kind omni swarm_kinds omni,drone member_kinds oor", other), BootWordRead::kOk);
  EXPECT_STREQ(other.Check(),
               "member_kinds names other kinds than swarm_kinds (each of swarm_kinds' kinds, and no other, is some "
               "robot's)");

  std::array<motion::RobotKind, 4> storage{};
  const std::vector<motion::RobotKind> od = {motion::RobotKind::kOmni, motion::RobotKind::kDrone};
  runtime::RobotConfig config;
  config.sync = sync::SyncConfig::ForSwarm(3, 1);
  EXPECT_STREQ(ConfigureImageKinds(config, motion::RobotKind::kDrone, kOmni | kDrone, {}, storage),
               "a swarm of more than one kind needs member_kinds, every robot's kind by id (what its app reads of its "
               "members); syrof-firmware-config and syrof-firmware-swarm write it");
  EXPECT_STREQ(ConfigureImageKinds(config, motion::RobotKind::kDrone, kOmni | kDrone, od, storage),
               "member_kinds names 2 robots; the swarm has 3");
  config.sync = sync::SyncConfig::ForSwarm(2, 0);
  EXPECT_STREQ(ConfigureImageKinds(config, motion::RobotKind::kDrone, kOmni | kDrone, od, storage),
               "member_kinds gives this robot (0) the kind omni; its kind is drone");
  const std::vector<motion::RobotKind> orover = {motion::RobotKind::kOmni, motion::RobotKind::kRover};
  EXPECT_STREQ(ConfigureImageKinds(config, motion::RobotKind::kOmni, kOmni | kDrone, orover, storage),
               "member_kinds gives robot 1 a kind not among the swarm's kinds");
  config.sync = sync::SyncConfig::ForSwarm(5, 0);
  EXPECT_STREQ(ConfigureImageKinds(config, motion::RobotKind::kOmni, kOmni, {}, storage),
               "the swarm is larger than the image's table of its kinds");

  // The host writes no words it could not read back.
  std::array<char, 96> out{};
  size_t length = 0;
  EXPECT_EQ(FormatKindWords(motion::RobotKind::kOmni, kOmni | kDrone, {}, out, length), BootWordsError::kNoSuchKind);
  EXPECT_EQ(FormatKindWords(motion::RobotKind::kOmni, kOmni | kDrone, orover, out, length), BootWordsError::kNoSuchKind);
}

TEST(BootWordsTest, AKindTheImageDoesNotKnowIsRefusedOnBothSides) {
  BootKind kind;
  EXPECT_EQ(kind.Read("kind", "tank"), BootWordRead::kBadValue);
  EXPECT_EQ(kind.Read("kind", "Drone"), BootWordRead::kBadValue);
  EXPECT_EQ(kind.Read("kind", ""), BootWordRead::kBadValue);
  EXPECT_EQ(kind.Read("swarm_kinds", "omni,tank"), BootWordRead::kBadValue);
  EXPECT_EQ(kind.Read("swarm_kinds", "omni,omni"), BootWordRead::kBadValue);  // each once
  EXPECT_EQ(kind.Read("swarm_kinds", "omni,"), BootWordRead::kBadValue);
  EXPECT_EQ(kind.Read("swarm_kinds", ""), BootWordRead::kBadValue);
  EXPECT_EQ(kind.Read("swarm_kinds", "droneomni"), BootWordRead::kBadValue);
  EXPECT_EQ(kind.Read("swarm", "4"), BootWordRead::kNotMine);

  BootKind outside;
  ASSERT_EQ(ReadAll(" kind drone swarm_kinds omni,rover", outside), BootWordRead::kOk);
  ASSERT_NE(outside.Check(), nullptr);
  EXPECT_STREQ(outside.Check(), "kind drone is not among its swarm_kinds (a robot is of its swarm)");

  std::array<char, 64> out{};
  size_t length = 7;
  EXPECT_EQ(FormatKindWords(static_cast<motion::RobotKind>(3), KindSet{8}, {}, out, length), BootWordsError::kNoSuchKind);
  EXPECT_EQ(length, 0u);
  EXPECT_EQ(FormatKindWords(motion::RobotKind::kDrone, kOmni, {}, out, length), BootWordsError::kNoSuchKind);
  std::array<char, 8> short_out{};
  EXPECT_EQ(FormatKindWords(motion::RobotKind::kDrone, kDrone, {}, short_out, length), BootWordsError::kBufferTooSmall);

  runtime::RobotConfig config;
  std::array<motion::RobotKind, 4> storage{};
  EXPECT_STREQ(ConfigureImageKinds(config, motion::RobotKind::kDrone, kOmni, {}, storage),
               "the robot's kind is not among its swarm's kinds");
  EXPECT_NE(ConfigureImageKinds(config, static_cast<motion::RobotKind>(3), 0, {}, storage), nullptr);
}

}  // namespace
}  // namespace syrof::firmware::robot
