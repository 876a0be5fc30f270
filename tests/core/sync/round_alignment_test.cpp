// Round alignment (round_alignment.h): the decision on hand-made offsets,
// then closed loops of drifting clocks built from the decision alone.
#include "syrof/sync/round_alignment.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace syrof::sync {
namespace {

// Samples from senders 1, 2, 3, ... (robot 0 aligns).
std::vector<AlignmentSample> From(const std::vector<int64_t>& offsets) {
  std::vector<AlignmentSample> samples;
  for (size_t i = 0; i < offsets.size(); ++i) samples.push_back({static_cast<uint16_t>(i + 1), offsets[i]});
  return samples;
}

constexpr int64_t kRound = 50'000'000;  // 50 ms

TEST(WrapPhaseTest, WrapsIntoHalfOpenHalfRounds) {
  EXPECT_EQ(WrapPhase(0, kRound), 0);
  EXPECT_EQ(WrapPhase(1, kRound), 1);
  EXPECT_EQ(WrapPhase(kRound - 1, kRound), -1);
  EXPECT_EQ(WrapPhase(kRound / 2, kRound), -kRound / 2);
  EXPECT_EQ(WrapPhase(kRound / 2 - 1, kRound), kRound / 2 - 1);
  EXPECT_EQ(WrapPhase(-3, kRound), -3);
  EXPECT_EQ(WrapPhase(3 * kRound + 7, kRound), 7);
  EXPECT_EQ(WrapPhase(5, 3), -1);  // odd round: [-1, 2)
}

TEST(AlignTest, NoSamplesNoCorrection) {
  AlignmentStats stats;
  const AlignmentStep step = Align(AlignmentConfig::ForRound(kRound), {}, true, stats);
  EXPECT_EQ(step.correction_ns, 0);
  EXPECT_EQ(step.samples, 0);
  EXPECT_EQ(stats.rounds_with_samples, 0u);
}

TEST(AlignTest, MemberMovesAQuarterOfTheMedianErrorCappedBySlew) {
  AlignmentStats stats;
  const AlignmentConfig config = AlignmentConfig::ForRound(kRound);
  const std::vector<int64_t> offsets = {2'000'000, 4'000'000, kRound - 1'000'000};  // errors 2, 4, -1 ms
  const AlignmentStep step = Align(config, From(offsets), true, stats);
  EXPECT_EQ(step.median_error_ns, 2'000'000);
  EXPECT_EQ(step.correction_ns, 500'000);
  AlignmentConfig tight = config;
  tight.max_slew_ns = 500'000;
  const std::vector<int64_t> far = {kRound / 2 - 1};
  EXPECT_EQ(Align(tight, From(far), true, stats).correction_ns, tight.max_slew_ns);
  EXPECT_EQ(Align(config, From(far), true, stats).correction_ns, (kRound / 2 - 1) / 4);
}

TEST(AlignTest, TheRobotsOwnUnseenCorrectionIsTakenOffEveryError) {
  AlignmentStats stats;
  const AlignmentConfig config = AlignmentConfig::ForRound(kRound);
  const std::vector<int64_t> offsets = {9'000'000, 9'000'000, 9'000'000};
  // A joiner that jumped 9 ms at the last boundary hears the same beacons'
  // old offsets once more: no second jump.
  EXPECT_EQ(Align(config, From(offsets), false, stats, 9'000'000).correction_ns, 0);
  // A member that moved 1 ms, still 3 ms behind: a quarter of the 8 ms left.
  EXPECT_EQ(Align(config, From(offsets), true, stats, 1'000'000).correction_ns, 2'000'000);
}

TEST(AlignTest, OutliersDoNotMoveTheMedian) {
  AlignmentStats stats;
  const AlignmentConfig config = AlignmentConfig::ForRound(kRound);
  // Five senders on time, two wildly late.
  const std::vector<int64_t> offsets = {0, 100, kRound - 100, 50, 0, 20'000'000, 24'000'000};
  EXPECT_EQ(Align(config, From(offsets), true, stats).median_error_ns, 50);
}

TEST(AlignTest, ScatteredMemberFollowsTheLowestIdBelowItsOwn) {
  AlignmentStats stats;
  const std::vector<AlignmentSample> samples = {{5, 10'000'000}, {2, 30'000'000}, {7, 40'000'000}, {9, 1'000'000}};
  const AlignmentStep follower = Align(AlignmentConfig::ForRound(kRound, 4), samples, true, stats);
  EXPECT_TRUE(follower.jumped);
  EXPECT_EQ(follower.correction_ns, -20'000'000);  // robot 2 is 20 ms earlier
  const AlignmentStep lowest = Align(AlignmentConfig::ForRound(kRound, 1), samples, true, stats);
  EXPECT_EQ(lowest.correction_ns, 0);  // nobody lower: it stays and the others come
}

TEST(AlignTest, JoinerJumpsOntoTheMedian) {
  AlignmentStats stats;
  const std::vector<int64_t> offsets = {30'000'000, 30'000'100, 29'999'900};
  const AlignmentStep step = Align(AlignmentConfig::ForRound(kRound), From(offsets), false, stats);
  EXPECT_TRUE(step.jumped);
  EXPECT_EQ(step.correction_ns, -20'000'000);  // 30 ms into a 50 ms round: the group is 20 ms earlier
  EXPECT_EQ(stats.jumps, 1u);
}

TEST(AlignTest, DisabledMeasuresButDoesNotCorrect) {
  AlignmentStats stats;
  AlignmentConfig config = AlignmentConfig::ForRound(kRound);
  config.enabled = false;
  const std::vector<int64_t> offsets = {3'000'000};
  const AlignmentStep step = Align(config, From(offsets), false, stats);
  EXPECT_EQ(step.median_error_ns, 3'000'000);
  EXPECT_EQ(step.correction_ns, 0);
}

TEST(AlignTest, UsesAtMostTheSampleCapacity) {
  AlignmentStats stats;
  std::vector<int64_t> offsets(200, 1000);
  EXPECT_EQ(Align(AlignmentConfig::ForRound(kRound), From(offsets), true, stats).samples, kMaxAlignmentSamples);
}

// A closed loop of robots that hear each other every round: robot i's
// boundaries are at b_i + k * round / (1 + drift_i) in true time; each hears
// every other robot's beacon, sent at the sender's boundary, during its next
// round, and at the end of that round corrects its next boundary by Align's
// decision: the error it acts on is a round old, as on a robot
// (core/runtime's AlignRound). Returns the largest pairwise error (ns) of
// the robots in `measured` over the last `tail` rounds.
struct Loop {
  std::vector<double> boundary_ns;  // next boundary, true time
  std::vector<double> drift_ppm;
  std::vector<bool> member;
  std::vector<double> sent_ns;  // the boundary before it: the beacons heard this round left then
  std::vector<int64_t> last_correction_ns;  // moved boundary_ns, unseen by this round's beacons

  double Spread(const std::vector<size_t>& measured) const {
    double worst = 0;
    for (size_t a : measured) {
      for (size_t b : measured) {
        const auto d = static_cast<int64_t>(boundary_ns[a] - boundary_ns[b]);
        worst = std::max(worst, static_cast<double>(std::llabs(WrapPhase(d, kRound))));
      }
    }
    return worst;
  }

  double Run(int rounds, int tail, const std::vector<size_t>& measured) {
    std::vector<AlignmentStats> stats(boundary_ns.size());
    double worst = 0;
    if (sent_ns.empty()) {
      for (size_t i = 0; i < boundary_ns.size(); ++i) sent_ns.push_back(boundary_ns[i] - kRound / (1 + drift_ppm[i] * 1e-6));
      last_correction_ns.assign(boundary_ns.size(), 0);
    }
    for (int round = 0; round < rounds; ++round) {
      std::vector<double> next = boundary_ns;
      std::vector<int64_t> corrections(boundary_ns.size(), 0);
      for (size_t i = 0; i < boundary_ns.size(); ++i) {
        const double length = kRound / (1 + drift_ppm[i] * 1e-6);
        // The round ending at boundary_ns[i] started at sent_ns[i]; the
        // beacons in it left their senders at sent_ns[j].
        const double start = sent_ns[i] - length;
        std::vector<AlignmentSample> samples;
        for (size_t j = 0; j < boundary_ns.size(); ++j) {
          if (j == i || !member[j]) continue;
          const auto offset = static_cast<int64_t>(sent_ns[j] - start);
          samples.push_back({static_cast<uint16_t>(j), ((offset % kRound) + kRound) % kRound});
        }
        const AlignmentConfig config = AlignmentConfig::ForRound(kRound, static_cast<uint16_t>(i));
        const AlignmentStep step = Align(config, samples, member[i], stats[i], last_correction_ns[i]);
        next[i] = boundary_ns[i] + length + static_cast<double>(step.correction_ns);
        corrections[i] = step.correction_ns;
        member[i] = true;  // a joiner that heard the group joins it
      }
      sent_ns = boundary_ns;
      boundary_ns = next;
      last_correction_ns = corrections;
      if (round >= rounds - tail) worst = std::max(worst, Spread(measured));
    }
    return worst;
  }
};

TEST(AlignLoopTest, OffsetsUpToAWholeRoundAndFiftyPpmConvergeBelowAMillisecond) {
  Loop loop;
  for (int i = 0; i < 16; ++i) {
    loop.boundary_ns.push_back(kRound + (i * 7919 % 50) * 1e6);  // spread over the whole round
    loop.drift_ppm.push_back((i % 2 == 0 ? 1 : -1) * 50.0);
    loop.member.push_back(true);
  }
  std::vector<size_t> all(16);
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  EXPECT_LT(loop.Run(200, 100, all), 1e6);
}

TEST(AlignLoopTest, ABadCrystalIsTrackedAndDoesNotDisturbTheRest) {
  Loop loop;
  for (int i = 0; i < 8; ++i) {
    loop.boundary_ns.push_back(kRound + i * 1e5);
    loop.drift_ppm.push_back(i == 7 ? 1000.0 : 0.0);
    loop.member.push_back(true);
  }
  const std::vector<size_t> good = {0, 1, 2, 3, 4, 5, 6};
  std::vector<size_t> all = good;
  all.push_back(7);
  Loop copy = loop;
  EXPECT_LT(loop.Run(300, 100, good), 10'000);   // the rest: within 10 us
  EXPECT_LT(copy.Run(300, 100, all), 300'000);   // the bad one (50 us a round): tracked within 0.3 ms
}

// The firmware swarm's regression: each robot of a pair moving half of a
// round-old error closes their gap as x[n+2] = x[n+1] - x[n], which keeps a
// gap of 10 ms swinging between +-10 ms with a period of six rounds for good.
// (The joiner's test below caught the other half: without its own unseen
// correction taken off, a joiner jumped again a round later.)
TEST(AlignLoopTest, TwoRobotsTenMillisecondsApartSettleThoughTheErrorIsARoundOld) {
  Loop loop;
  loop.boundary_ns = {kRound, kRound + 10e6};
  loop.drift_ppm = {0, 0};
  loop.member = {true, true};
  const std::vector<size_t> both = {0, 1};
  EXPECT_LT(loop.Run(40, 10, both), 50'000);
}

TEST(AlignLoopTest, AJoinerWithAnArbitraryPhaseAlignsInARound) {
  Loop loop;
  for (int i = 0; i < 5; ++i) {
    loop.boundary_ns.push_back(kRound);
    loop.drift_ppm.push_back(0);
    loop.member.push_back(i != 4);
  }
  loop.boundary_ns[4] = kRound + 31'234'567;
  const std::vector<size_t> all = {0, 1, 2, 3, 4};
  EXPECT_LT(loop.Run(2, 1, all), 1);
}

}  // namespace
}  // namespace syrof::sync
