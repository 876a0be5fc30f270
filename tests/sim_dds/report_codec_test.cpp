#include "syrof/sim_dds/report_codec.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace syrof::sim_dds {
namespace {

sync::LDMap SampleMap() {
  sync::LDMap map;
  map.epoch = 41;
  map.mode = wire::Mode::kCooperative;
  for (const uint16_t id : {0, 3, 7}) {
    map.members.set(id);
    map.phases[id] = wire::Phase::kVote;
    map.snapshots[id].x_mm = static_cast<int16_t>(100 * id - 5);
    map.snapshots[id].y_mm = static_cast<int16_t>(-7 * id);
    map.snapshots[id].heading_mrad = 3141;
    map.snapshots[id].vx_mm_s = -3;
    const uint8_t payload[] = {1, 2, static_cast<uint8_t>(id)};
    EXPECT_EQ(map.snapshots[id].SetPayload(payload), wire::WireError::kOk);
  }
  return map;
}

TEST(ReportCodecTest, EpochStartRoundTripsTheMapThatP3Compares) {
  const sync::LDMap map = SampleMap();
  const std::vector<uint8_t> bytes = EncodeEpochStart(map);
  const DecodedReport decoded = DecodeReport(static_cast<uint8_t>(ReportKind::kEpochStart), bytes, 8);
  ASSERT_TRUE(decoded.body) << decoded.error;
  EXPECT_TRUE(decoded.body->ldmap.SameKnowledge(map));
  EXPECT_EQ(decoded.body->ldmap.phases[3], wire::Phase::kVote);
}

TEST(ReportCodecTest, EveryOtherKindRoundTrips) {
  wire::MemberSet removed, joined;
  removed.set(2);
  joined.set(5);
  joined.set(6);
  DecodedReport d = DecodeReport(static_cast<uint8_t>(ReportKind::kMembership), EncodeMembership(removed, joined), 8);
  ASSERT_TRUE(d.body) << d.error;
  EXPECT_TRUE(d.body->removed.test(2));
  EXPECT_EQ(d.body->joined.count(), 2);

  d = DecodeReport(static_cast<uint8_t>(ReportKind::kAppFault), EncodeAppFault(1, 9, 3, "SIGSEGV"), 8);
  ASSERT_TRUE(d.body) << d.error;
  EXPECT_EQ(d.body->epoch, 9);
  EXPECT_EQ(d.body->verdict, 3);
  EXPECT_EQ(d.body->text, "SIGSEGV");

  d = DecodeReport(static_cast<uint8_t>(ReportKind::kSafety), EncodeSafety(-12345678901, 4), 8);
  ASSERT_TRUE(d.body) << d.error;
  EXPECT_EQ(d.body->time_ns, -12345678901);
  EXPECT_EQ(d.body->other, 4);

  RoundReport round;
  round.round = 77;
  round.activation_ns = 5'000'000'123;
  round.status = 0;
  round.phase = 2;
  round.epoch_mode = 0;
  round.estimate_valid = 1;
  round.epoch = 12;
  round.est_x_m = 1.25f;
  round.beacons_heard = 99;
  round.heard_in_round.set(3);
  round.heard_in_round.set(6);
  d = DecodeReport(static_cast<uint8_t>(ReportKind::kRound), EncodeRound(round), 8);
  ASSERT_TRUE(d.body) << d.error;
  EXPECT_EQ(d.body->round.round, 77u);
  EXPECT_EQ(d.body->round.activation_ns, 5'000'000'123);
  EXPECT_EQ(d.body->round.epoch, 12);
  EXPECT_EQ(d.body->round.est_x_m, 1.25f);
  EXPECT_EQ(d.body->round.beacons_heard, 99u);
  EXPECT_EQ(d.body->round.heard_in_round, round.heard_in_round);

  AppStateReport app_state;
  app_state.new_round = false;
  app_state.epoch = 513;
  app_state.cooperative = true;
  app_state.map_fingerprint = 0x0123456789abcdefULL;
  app_state.state = 200;
  d = DecodeReport(static_cast<uint8_t>(ReportKind::kAppState), EncodeAppState(app_state), 8);
  ASSERT_TRUE(d.body) << d.error;
  EXPECT_FALSE(d.body->app_state.new_round);
  EXPECT_EQ(d.body->app_state.epoch, 513);
  EXPECT_TRUE(d.body->app_state.cooperative);
  EXPECT_EQ(d.body->app_state.map_fingerprint, 0x0123456789abcdefULL);
  EXPECT_EQ(d.body->app_state.state, 200);
}

TEST(ReportCodecTest, MalformedBodiesAreRefusedWithAReasonNeverRead) {
  const std::vector<uint8_t> good = EncodeEpochStart(SampleMap());
  // Every truncation of a valid body is refused.
  for (size_t length = 0; length < good.size(); ++length) {
    const std::vector<uint8_t> cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(length));
    EXPECT_FALSE(DecodeReport(0, cut, 8).body) << "length " << length;
  }
  std::vector<uint8_t> longer = good;
  longer.push_back(0);
  EXPECT_NE(DecodeReport(0, longer, 8).error.find("more than its layout"), std::string::npos);
  // A member id at or above the swarm size.
  EXPECT_NE(DecodeReport(0, good, 7).error.find("swarm size 7"), std::string::npos);
  EXPECT_NE(DecodeReport(200, {}, 8).error.find("unknown"), std::string::npos);
  RoundReport round;
  round.phase = 9;
  EXPECT_NE(DecodeReport(static_cast<uint8_t>(ReportKind::kRound), EncodeRound(round), 8).error.find("out of range"),
            std::string::npos);
  // A heard robot outside the swarm; an app state with a flag that is not 0 or 1.
  round.phase = 0;
  round.heard_in_round.set(9);
  EXPECT_NE(DecodeReport(static_cast<uint8_t>(ReportKind::kRound), EncodeRound(round), 8).error.find("heard_in_round"),
            std::string::npos);
  std::vector<uint8_t> app_state = EncodeAppState(AppStateReport{});
  app_state[0] = 2;
  EXPECT_NE(DecodeReport(static_cast<uint8_t>(ReportKind::kAppState), app_state, 8).error.find("out of range"),
            std::string::npos);
}

}  // namespace
}  // namespace syrof::sim_dds
