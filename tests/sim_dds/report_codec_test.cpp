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
  ASSERT_TRUE(decoded.ok()) << decoded.error->ToString();
  EXPECT_TRUE(decoded.body->ldmap.SameKnowledge(map));
  EXPECT_EQ(decoded.body->ldmap.phases[3], wire::Phase::kVote);
}

TEST(ReportCodecTest, EveryOtherKindRoundTrips) {
  wire::MemberSet removed, joined;
  removed.set(2);
  joined.set(5);
  joined.set(6);
  DecodedReport d = DecodeReport(static_cast<uint8_t>(ReportKind::kMembership), EncodeMembership(removed, joined), 8);
  ASSERT_TRUE(d.ok()) << d.error->ToString();
  EXPECT_TRUE(d.body->removed.test(2));
  EXPECT_EQ(d.body->joined.count(), 2);

  d = DecodeReport(static_cast<uint8_t>(ReportKind::kAppFault), EncodeAppFault(1, 9, 3, "SIGSEGV"), 8);
  ASSERT_TRUE(d.ok()) << d.error->ToString();
  EXPECT_EQ(d.body->epoch, 9);
  EXPECT_EQ(d.body->verdict, 3);
  EXPECT_EQ(d.body->text, "SIGSEGV");

  d = DecodeReport(static_cast<uint8_t>(ReportKind::kSafety), EncodeSafety(-12345678901, 4), 8);
  ASSERT_TRUE(d.ok()) << d.error->ToString();
  EXPECT_EQ(d.body->time_ns, -12345678901);
  EXPECT_EQ(d.body->other, 4);

  d = DecodeReport(static_cast<uint8_t>(ReportKind::kPrecaution), EncodePrecaution(987654321, 0xFFFF), 8);
  ASSERT_TRUE(d.ok()) << d.error->ToString();
  EXPECT_EQ(d.body->kind, ReportKind::kPrecaution);
  EXPECT_EQ(d.body->time_ns, 987654321);
  EXPECT_EQ(d.body->other, 0xFFFF);

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
  ASSERT_TRUE(d.ok()) << d.error->ToString();
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
  ASSERT_TRUE(d.ok()) << d.error->ToString();
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
  // What is wrong, where in the report: a refused report's reason in the log.
  auto error_of = [](uint8_t kind, const std::vector<uint8_t>& bytes, uint16_t swarm_size) {
    const DecodedReport decoded = DecodeReport(kind, bytes, swarm_size);
    EXPECT_FALSE(decoded.ok());
    return decoded.error ? decoded.error->ToString() : std::string("(no error)");
  };
  std::vector<uint8_t> longer = good;
  longer.push_back(0);
  EXPECT_EQ(error_of(0, longer, 8), "report kind 0: " + std::to_string(longer.size()) + " bytes, more than its layout");
  EXPECT_EQ(error_of(0, {good.begin(), good.begin() + 7}, 8), "report kind 0: body of 7 bytes is truncated");
  // A member id at or above the swarm size.
  EXPECT_EQ(error_of(0, good, 7), "epoch start: member 7 out of order or at or above the swarm size 7");
  EXPECT_EQ(error_of(200, {}, 8), "report kind 200 unknown (0 .. " + std::to_string(kReportKinds - 1) + ")");
  EXPECT_EQ(error_of(0, std::vector<uint8_t>(kMaxReportBytes + 1), 8),
            "report body of " + std::to_string(kMaxReportBytes + 1) + " bytes, above " +
                std::to_string(kMaxReportBytes));
  RoundReport round;
  round.phase = 9;
  EXPECT_EQ(error_of(static_cast<uint8_t>(ReportKind::kRound), EncodeRound(round), 8),
            "round report: status, phase, mode or estimate flag out of range");
  // A heard robot outside the swarm; an app state with a flag that is not 0 or 1.
  round.phase = 0;
  round.heard_in_round.set(9);
  const DecodedReport heard = DecodeReport(static_cast<uint8_t>(ReportKind::kRound), EncodeRound(round), 8);
  ASSERT_FALSE(heard.ok());
  EXPECT_EQ(heard.error->where, "round report heard_in_round");
  EXPECT_EQ(heard.error->ToString(), "round report heard_in_round: id 9 at or above the swarm size 8");
  std::vector<uint8_t> app_state = EncodeAppState(AppStateReport{});
  app_state[0] = 2;
  EXPECT_EQ(error_of(static_cast<uint8_t>(ReportKind::kAppState), app_state, 8),
            "app state report: call or mode flag out of range");
  wire::MemberSet removed;
  removed.set(9);
  EXPECT_EQ(error_of(static_cast<uint8_t>(ReportKind::kMembership), EncodeMembership(removed, {}), 8),
            "membership removed: id 9 at or above the swarm size 8");
}

}  // namespace
}  // namespace syrof::sim_dds
