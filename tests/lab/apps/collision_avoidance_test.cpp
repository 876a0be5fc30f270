#include "syrof/lab/apps/collision_avoidance.h"

#include <gtest/gtest.h>

#include <vector>

#include "syrof/base/split_mix64.h"

namespace syrof::lab::apps {
namespace {

constexpr double kClearanceM = 0.28;

Segment Move(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y1}}; }

TEST(SegmentDistanceTest, ParallelCrossingAndPointCases) {
  EXPECT_NEAR(SegmentDistanceM(Move(0, 0, 1, 0), Move(0, 1, 1, 1)), 1.0, 1e-12);
  EXPECT_NEAR(SegmentDistanceM(Move(0, 0, 1, 1), Move(0, 1, 1, 0)), 0.0, 1e-12);
  EXPECT_NEAR(SegmentDistanceM(Move(0, 0, 0, 0), Move(-1, 2, 1, 2)), 2.0, 1e-12);
  EXPECT_NEAR(SegmentDistanceM(Move(0, 0, 1, 0), Move(2, 0, 3, 0)), 1.0, 1e-12);
}

TEST(SegmentsSeparateTest, MovingApartSeparatesMovingTogetherDoesNot) {
  EXPECT_TRUE(SegmentsSeparate(Move(0, 0, -1, 0), Move(0.3, 0, 1.3, 0)));
  EXPECT_TRUE(SegmentsSeparate(Move(0, 0, 0, 1), Move(0.3, 0, 0.3, -1)));
  EXPECT_FALSE(SegmentsSeparate(Move(0, 0, 0.1, 0), Move(0.3, 0, 1.3, 0)));
}

TEST(TruncateTest, KeepsStartAndDirection) {
  // Act
  const Segment cut = Truncate(Move(1, 1, 4, 5), 2.5);

  // Assert
  EXPECT_NEAR(SegmentLengthM(cut), 2.5, 1e-12);
  EXPECT_NEAR(cut.end.x_m, 1 + 1.5, 1e-12);
  EXPECT_NEAR(cut.end.y_m, 1 + 2.0, 1e-12);
  EXPECT_NEAR(SegmentLengthM(Truncate(Move(0, 0, 1, 0), 3)), 1.0, 1e-12);
}

TEST(LimitSegmentsTest, HeadOnPairSharesTheRoom) {
  // Arrange: 1 m apart, each wants to drive 0.4 m towards the other.
  std::vector<Segment> segments{Move(0, 0, 0.4, 0), Move(1, 0, 0.6, 0)};

  // Act
  LimitSegments(segments, kClearanceM);

  // Assert: (1 - 0.28) / 2 each.
  EXPECT_NEAR(SegmentLengthM(segments[0]), 0.36, 1e-9);
  EXPECT_NEAR(SegmentLengthM(segments[1]), 0.36, 1e-9);
  EXPECT_GE(SegmentDistanceM(segments[0], segments[1]), kClearanceM - 1e-9);
}

TEST(LimitSegmentsTest, ChainLetsTheFrontRobotGoFirst) {
  // Arrange: robot 1 leaves the place robot 0 wants.
  std::vector<Segment> segments{Move(0, 0, 0.3, 0), Move(0.3, 0, 0.6, 0)};

  // Act
  LimitSegments(segments, kClearanceM);

  // Assert
  EXPECT_NEAR(SegmentLengthM(segments[0]), 0.0, 1e-12);
  EXPECT_NEAR(SegmentLengthM(segments[1]), 0.3, 1e-12);
}

TEST(LimitSegmentsTest, ClearPairsAreLeftAlone) {
  // Arrange
  std::vector<Segment> segments{Move(0, 0, 0.4, 0), Move(0, 1, 0.4, 1)};

  // Act
  LimitSegments(segments, kClearanceM);

  // Assert
  EXPECT_NEAR(SegmentLengthM(segments[0]), 0.4, 1e-12);
  EXPECT_NEAR(SegmentLengthM(segments[1]), 0.4, 1e-12);
}

TEST(LimitSegmentsTest, RandomSwarmsEndWithEveryPairSafe) {
  base::SplitMix64 random(42);
  for (int trial = 0; trial < 200; ++trial) {
    // Arrange: starts at least the clearance apart, moves up to 0.4 m.
    std::vector<Segment> segments;
    while (segments.size() < 8) {
      const Position start{random.Between(0, 2000) / 1000.0, random.Between(0, 2000) / 1000.0};
      bool clear = true;
      for (const Segment& other : segments) {
        clear = clear && SegmentDistanceM({start, start}, {other.start, other.start}) >= kClearanceM;
      }
      if (!clear) continue;
      const Position end{start.x_m + random.Between(-400, 400) / 1000.0, start.y_m + random.Between(-400, 400) / 1000.0};
      segments.push_back({start, end});
    }

    // Act
    SlideAroundNeighbours(segments, kClearanceM, 0.05);
    LimitSegments(segments, kClearanceM);

    // Assert
    for (size_t i = 0; i < segments.size(); ++i) {
      for (size_t j = i + 1; j < segments.size(); ++j) {
        EXPECT_GE(SegmentDistanceM(segments[i], segments[j]), kClearanceM - 1e-9) << "trial " << trial;
      }
    }
  }
}

TEST(SlideAroundNeighboursTest, HeadOnRobotsBothTurnLeftAndSeparate) {
  // Arrange: touching the clearance, each aimed at the other.
  std::vector<Segment> segments{Move(0, 0, 0.4, 0), Move(0.29, 0, -0.11, 0)};

  // Act
  SlideAroundNeighbours(segments, kClearanceM, 0.05);

  // Assert: robot 0 faces +x and turns to +y; robot 1 faces -x and turns to -y.
  EXPECT_GT(segments[0].end.y_m, 0.1);
  EXPECT_LT(segments[1].end.y_m, -0.1);
  EXPECT_TRUE(SegmentsSeparate(segments[0], segments[1]));
}

TEST(SlideAroundNeighboursTest, FarRobotsKeepTheirSegments) {
  // Arrange
  std::vector<Segment> segments{Move(0, 0, 0.4, 0), Move(1.5, 0, 1.1, 0)};

  // Act
  SlideAroundNeighbours(segments, kClearanceM, 0.05);

  // Assert
  EXPECT_DOUBLE_EQ(segments[0].end.x_m, 0.4);
  EXPECT_DOUBLE_EQ(segments[1].end.x_m, 1.1);
}

}  // namespace
}  // namespace syrof::lab::apps
