#include "syrof/sim_dds/participant.h"

#include <gtest/gtest.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>

#include <set>
#include <string>
#include <thread>
#include <vector>

#include "syrof/sim_dds/topics.h"
#include "test_domain.h"

namespace syrof::sim_dds {
namespace {

TEST(CycloneConfig, LoopbackByDefault) {
  const std::string xml = CycloneConfig(CycloneOptions{});
  EXPECT_NE(xml.find("<NetworkInterface name=\"lo\" multicast=\"true\"/>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<AllowMulticast>spdp</AllowMulticast>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<ParticipantIndex>auto</ParticipantIndex>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<Peer address=\"127.0.0.1\"/>"), std::string::npos) << xml;
}

TEST(CycloneConfig, ParticipantIndexAboveTheProcessCount) {
  CycloneOptions options;
  options.max_processes = 40;
  const std::string xml = CycloneConfig(options);
  EXPECT_NE(xml.find("<MaxAutoParticipantIndex>48</MaxAutoParticipantIndex>"), std::string::npos) << xml;
}

TEST(CycloneConfig, NamedInterfaceWithoutMulticast) {
  CycloneOptions options;
  options.interface = "veth-a";
  options.multicast = false;
  options.peers = {"10.0.0.2"};
  const std::string xml = CycloneConfig(options);
  EXPECT_NE(xml.find("<NetworkInterface name=\"veth-a\"/>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<AllowMulticast>false</AllowMulticast>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<Peer address=\"10.0.0.2\"/>"), std::string::npos) << xml;
  EXPECT_EQ(xml.find("127.0.0.1"), std::string::npos) << xml;
}

TEST(CycloneConfig, RefusesXmlInNamesAndTooManyProcesses) {
  CycloneOptions options;
  options.interface = "lo\"/><x";
  ASSERT_TRUE(CheckCycloneOptions(options).has_value());
  EXPECT_EQ(CheckCycloneOptions(options)->where, "interface");
  options = CycloneOptions{};
  options.peers = {"1.2.3.4<"};
  EXPECT_EQ(CheckCycloneOptions(options)->where, "peer");
  options = CycloneOptions{};
  options.max_processes = kMaxProcesses + 1;
  EXPECT_EQ(CheckCycloneOptions(options)->where, "max_processes");
  EXPECT_FALSE(CheckCycloneOptions(CycloneOptions{}).has_value());
}

TEST(DdsDomainId, FromTheRunIdInRangeAndNeverZero) {
  std::set<uint32_t> seen;
  for (uint64_t run = 0; run < 5000; ++run) {
    const uint32_t id = DomainIdForRun(run);
    ASSERT_GE(id, 1u);
    ASSERT_LT(id, kMaxDomainId);
    seen.insert(id);
  }
  EXPECT_EQ(seen.size(), kMaxDomainId - 1);  // every id 1 .. 231 is used
  EXPECT_EQ(DomainIdForRun(42), DomainIdForRun(42));
}

TEST(DdsDomainId, EnvironmentOverride) {
  EXPECT_EQ(DomainIdFromText(nullptr, 7).domain_id, DomainIdForRun(7));
  EXPECT_EQ(DomainIdFromText("0", 7).domain_id, 0u);
  EXPECT_EQ(DomainIdFromText("232", 7).domain_id, 232u);
  for (const char* bad : {"233", "-1", "", "12a", "1000", " 3"}) {
    const DomainIdOrError got = DomainIdFromText(bad, 7);
    ASSERT_FALSE(got.ok()) << bad;
    EXPECT_EQ(got.error->where, "SYROF_DDS_DOMAIN");
    EXPECT_NE(got.error->message.find(std::string("'") + bad + "'"), std::string::npos) << got.error->message;
  }
}

TEST(DdsParticipant, TwoInOneProcessShareTheDomain) {
  const uint32_t domain = testing::FreshDomainId();
  ParticipantOrError first = Participant::Create(domain, CycloneOptions{});
  ASSERT_TRUE(first.ok()) << first.error->ToString();
  ParticipantOrError second = Participant::Create(domain, CycloneOptions{});
  ASSERT_TRUE(second.ok()) << second.error->ToString();
  EXPECT_EQ(first.participant->domain_id(), domain);
  first.participant.reset();
  // The domain lives on with the second participant.
  EXPECT_TRUE(CreateWriter(*second.participant, TopicKind::kBeacon).ok());
  second.participant.reset();
  ParticipantOrError again = Participant::Create(domain, CycloneOptions{});
  EXPECT_TRUE(again.ok());
}

TEST(CycloneConfig, NetworkThreadsAtFifoOnlyWhenAsked) {
  EXPECT_EQ(CycloneConfig(CycloneOptions{}).find("<Threads>"), std::string::npos);
  CycloneOptions options;
  options.network_fifo_priority = 8;
  const std::string xml = CycloneConfig(options);
  EXPECT_NE(xml.find("<MultipleReceiveThreads>false</MultipleReceiveThreads>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<Thread name=\"recv\"><Scheduling><Class>realtime</Class><Priority>8</Priority>"),
            std::string::npos)
      << xml;
}

// The scheduling policy of each of this process's threads, by name (the
// last thread of a name wins).
std::map<std::string, int> PoliciesByThreadName() {
  std::map<std::string, int> policies;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    std::getline(comm, name);
    policies[name] = sched_getscheduler(std::stoi(task.path().filename().string()));
  }
  return policies;
}

// --realtime: a beacon is taken off the network by a thread at SCHED_FIFO.
// Cyclone's default second and third receive threads (recvUC, recvMC) take
// no scheduling from the configuration and stayed at normal priority, so
// on a loaded machine beacons waited behind a build (CrossRuntimeTest).
TEST(DdsParticipant, WithAFifoPriorityEveryNetworkThreadRunsAtIt) {
  if (!CanUseFifoScheduling()) GTEST_SKIP() << "SCHED_FIFO needs root or CAP_SYS_NICE";
  CycloneOptions options;
  options.network_fifo_priority = sched_get_priority_min(SCHED_FIFO) + 7;
  ParticipantOrError made = Participant::Create(testing::FreshDomainId(), options);
  ASSERT_TRUE(made.ok()) << made.error->ToString();
  // A thread names itself once it runs: wait for the receive thread's name.
  std::map<std::string, int> policies = PoliciesByThreadName();
  for (int tries = 0; tries < 200 && !(policies.contains("recv") && policies.contains("tev") &&
                                       policies.contains("dq.user"));
       ++tries) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    policies = PoliciesByThreadName();
  }
  ASSERT_TRUE(policies.contains("recv"));
  for (const char* name : {"recv", "tev", "dq.user"}) {
    ASSERT_TRUE(policies.contains(name)) << name;
    EXPECT_EQ(policies.at(name), SCHED_FIFO) << name;
  }
  EXPECT_FALSE(policies.contains("recvUC"));
  EXPECT_FALSE(policies.contains("recvMC"));
}

// The check leaves the thread as it found it: a robot process started at
// SCHED_FIFO (DdsWorld's Spawn) was put back to SCHED_OTHER by it.
TEST(DdsParticipant, TheFifoCheckLeavesTheThreadsPolicyAsItWas) {
  if (!CanUseFifoScheduling()) GTEST_SKIP() << "SCHED_FIFO needs root or CAP_SYS_NICE";
  EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER);
  sched_param raised{};
  raised.sched_priority = sched_get_priority_min(SCHED_FIFO) + 3;
  ASSERT_EQ(sched_setscheduler(0, SCHED_FIFO, &raised), 0);
  EXPECT_TRUE(CanUseFifoScheduling());
  sched_param now{};
  EXPECT_EQ(sched_getscheduler(0), SCHED_FIFO);
  ASSERT_EQ(sched_getparam(0, &now), 0);
  EXPECT_EQ(now.sched_priority, raised.sched_priority);
  sched_param normal{};
  ASSERT_EQ(sched_setscheduler(0, SCHED_OTHER, &normal), 0);
}

TEST(DdsParticipant, RefusesADomainAboveTheRange) {
  const ParticipantOrError made = Participant::Create(kMaxDomainId + 1, CycloneOptions{});
  ASSERT_FALSE(made.ok());
  EXPECT_EQ(made.error->where, "domain 233");
}

TEST(DdsTopics, NamesTheRos2Way) {
  EXPECT_EQ(TopicName(TopicKind::kBeacon), "rt/syrof/beacon");
  EXPECT_EQ(TopicName(TopicKind::kImu, 3), "rt/robot_3/syrof/imu");
  EXPECT_EQ(TopicName(TopicKind::kFlow, 0), "rt/robot_0/syrof/flow");
  EXPECT_EQ(TopicName(TopicKind::kUwb, 12), "rt/robot_12/syrof/uwb");
  EXPECT_EQ(TopicName(TopicKind::kDrive, 1), "rt/robot_1/syrof/drive");
  EXPECT_EQ(TopicName(TopicKind::kControl), "rt/syrof/control");
  EXPECT_EQ(TopicName(TopicKind::kReport), "rt/syrof/report");
  EXPECT_EQ(TopicName(TopicKind::kStatus), "rt/syrof/status");
  EXPECT_STREQ(TopicDescriptor(TopicKind::kBeacon)->m_typename, "syrof::msg::dds_::Beacon_");
}

TEST(DdsTopics, QosAsTheIdlSays) {
  EXPECT_FALSE(QosOf(TopicKind::kBeacon).reliable);
  EXPECT_EQ(QosOf(TopicKind::kBeacon).keep_last, 1);
  EXPECT_EQ(QosOf(TopicKind::kImu).keep_last, 4);
  EXPECT_TRUE(QosOf(TopicKind::kControl).reliable);
  EXPECT_TRUE(QosOf(TopicKind::kControl).transient_local);
  EXPECT_EQ(QosOf(TopicKind::kReport).keep_last, 0);
  EXPECT_FALSE(QosOf(TopicKind::kReport).transient_local);
  EXPECT_TRUE(QosOf(TopicKind::kStatus).transient_local);
}

TEST(DdsTopics, EveryTopicGetsAReaderAndAWriter) {
  ParticipantOrError made = Participant::Create(testing::FreshDomainId(), CycloneOptions{});
  ASSERT_TRUE(made.ok()) << made.error->ToString();
  for (int kind = 0; kind < kTopicKinds; ++kind) {
    const auto topic = static_cast<TopicKind>(kind);
    const EntityOrError writer = CreateWriter(*made.participant, topic, 2);
    ASSERT_TRUE(writer.ok()) << writer.error->ToString();
    const EntityOrError reader = CreateReader(*made.participant, topic, 2);
    ASSERT_TRUE(reader.ok()) << reader.error->ToString();
  }
}

// Two runs on one domain (docs/dds.md, "Domain ids") use the same robot ids.
// Every topic a robot or a world keeps only the newest samples of is keyed
// by the run as well, so one run's samples never push the other's out of a
// reader's history: before, a beacon of robot 3 in one run replaced robot
// 3's beacon of the other in every reader not yet taken (keep last 1 per
// sender), and four readings of the other world pushed out this world's.
template <typename Sample>
std::vector<uint64_t> RunsLeftAfterTwoRunsWrite(TopicKind kind, Sample sample) {
  ParticipantOrError made = Participant::Create(testing::FreshDomainId(), CycloneOptions{});
  EXPECT_TRUE(made.ok()) << made.error->ToString();
  if (!made.ok()) return {};
  const EntityOrError writer = CreateWriter(*made.participant, kind, 3);
  const EntityOrError reader = CreateReader(*made.participant, kind, 3);
  EXPECT_TRUE(writer.ok() && reader.ok());
  // This run's sample, then as many of the other run's as the history keeps.
  sample.run_id = 11;
  EXPECT_EQ(dds_write(writer.entity, &sample), 0);
  sample.run_id = 22;
  for (int i = 0; i < std::max(1, QosOf(kind).keep_last); ++i) EXPECT_EQ(dds_write(writer.entity, &sample), 0);
  std::vector<uint64_t> runs;
  void* samples[16] = {};
  dds_sample_info_t infos[16];
  const dds_return_t taken = dds_take(reader.entity, samples, infos, 16, 16);
  for (dds_return_t i = 0; i < taken; ++i) {
    if (infos[i].valid_data) runs.push_back(static_cast<const Sample*>(samples[i])->run_id);
  }
  if (taken > 0) dds_return_loan(reader.entity, samples, taken);
  return runs;
}

// Both runs' samples of robot 3 are left for `kind` (the robot field named
// `sender` for beacons, `robot` elsewhere).
template <typename Sample>
void ExpectBothRunsLeft(TopicKind kind, uint16_t Sample::*robot_field, const char* what) {
  Sample sample{};
  sample.*robot_field = 3;
  const std::vector<uint64_t> runs = RunsLeftAfterTwoRunsWrite(kind, sample);
  const auto has = [&](uint64_t run) { return std::find(runs.begin(), runs.end(), run) != runs.end(); };
  EXPECT_TRUE(has(11) && has(22)) << what;
}

TEST(DdsTopics, TwoRunsOnOneDomainNeverPushOutEachOthersSamples) {
  ExpectBothRunsLeft(TopicKind::kBeacon, &syrof_msg_dds__Beacon_::sender, "beacons");
  ExpectBothRunsLeft(TopicKind::kStatus, &syrof_msg_dds__Status_::robot, "status");
  ExpectBothRunsLeft(TopicKind::kImu, &syrof_msg_dds__Imu_::robot, "imu");
  ExpectBothRunsLeft(TopicKind::kFlow, &syrof_msg_dds__Flow_::robot, "flow");
  ExpectBothRunsLeft(TopicKind::kUwb, &syrof_msg_dds__Uwb_::robot, "uwb");
  ExpectBothRunsLeft(TopicKind::kDrive, &syrof_msg_dds__Drive_::robot, "drive");
}

}  // namespace
}  // namespace syrof::sim_dds
