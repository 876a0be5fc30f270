// A fixed set of query inputs and a one-line description of every answer
// (ids, exact integers, float bits in hex). golden_generate prints the
// descriptions on the host into golden_expected.inc; golden_test checks them
// on the host and on the emulated Cortex-M4, so the two must agree bit for
// bit. Inputs stay within the Teensy build's limits: 32 members with ids
// below 32, and at most 32 targets.
#pragma once

#include <algorithm>
#include <bit>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "query_test_support.h"
#include "syrof/queries/swarm_queries.h"

namespace syrof::queries::golden {

struct Case {
  std::vector<Member> members;
  std::vector<Point> targets;
};

inline std::vector<Case> Cases() {
  std::vector<Case> cases;
  // Hand-made degenerate cases.
  cases.push_back({{{5, {0, 0}}}, {{1000, 1000}}});
  cases.push_back({{{3, {100, 100}}, {1, {100, 100}}, {2, {100, 100}}}, {{0, 0}, {0, 0}}});
  cases.push_back({{{0, {-1000, -1000}}, {1, {0, 0}}, {2, {1000, 1000}}, {3, {2000, 2000}}}, {{0, 1}, {1, 0}}});
  cases.push_back({{{0, {-32768, -32768}}, {1, {32767, 32767}}, {2, {32767, -32768}}, {3, {-32768, 32767}}},
                   {{32767, 32767}, {-32768, -32768}, {0, 0}, {1, 1}, {-1, -1}}});
  cases.push_back({{{7, {-32768, 0}}, {8, {32767, 1}}, {9, {0, 2}}}, {{0, 0}, {0, 0}, {0, 0}}});
  cases.push_back({{{0, {0, 0}}, {1, {1000, 0}}, {2, {2000, 0}}}, {{1000, 0}, {2000, 0}, {3000, 0}}});
  cases.push_back({{{0, {-1500, -2000}}, {1, {1500, -2000}}, {2, {0, 2500}}, {3, {100, 100}}}, {}});
  // Seeded random cases of every size up to 32, three coordinate extents,
  // with fewer, as many and more targets than members.
  testing::Rng rng(2024);
  const int32_t extents[] = {5, 700, 32767};
  for (uint32_t size = 2; size <= 32; size += 2) {
    const int32_t extent = extents[size % 3];
    const size_t target_count = std::min<size_t>(32, size / 2 + rng.Below(size + 2));
    cases.push_back(
        {testing::RandomMembers(rng, size, extent, /*id_limit=*/32), testing::RandomPoints(rng, target_count, extent)});
  }
  return cases;
}

inline std::string Hex(float value) {
  char text[16];
  std::snprintf(text, sizeof text, "%08" PRIx32, std::bit_cast<uint32_t>(value));
  return text;
}

/// Every query's answer on the case, as one line of text.
inline std::string Describe(const Case& input, Workspace& workspace) {
  std::string text;
  char buffer[96];
  const auto append = [&text, &buffer](const char* format, auto... values) {
    std::snprintf(buffer, sizeof buffer, format, values...);
    text += buffer;
  };
  append("n=%u leader=%u", unsigned{NumberOfMembers(input.members).value()}, unsigned{Leader(input.members).value()});
  std::vector<uint16_t> hull(input.members.size());
  hull.resize(ConvexHull(input.members, workspace, hull).value());
  text += " hull=";
  for (const uint16_t id : hull) append("%u,", unsigned{id});
  const Circle circle = ShortestEnclosingCircle(input.members, workspace).value();
  text += " circle=" + Hex(circle.centre_x_m) + "," + Hex(circle.centre_y_m) + "," + Hex(circle.radius_m);
  append(" support=%u:%u,%u,%u", unsigned{circle.support_count}, unsigned{circle.support_ids[0]},
         unsigned{circle.support_ids[1]}, unsigned{circle.support_ids[2]});
  std::vector<Assignment> by_robot(input.members.size());
  std::vector<uint16_t> robot_of_target(input.targets.size());
  const MatchingSummary summary =
      MinWeightedMatching(input.members, input.targets, workspace, by_robot, robot_of_target).value();
  text += " match=";
  for (const Assignment& assignment : by_robot)
    append("%u>%u,", unsigned{assignment.robot_id}, unsigned{assignment.target_index});
  append(" b2=%" PRIu64 " q15=%" PRIu64, summary.bottleneck_squared_mm2, summary.total_distance_q15_mm);
  text += " bm=" + Hex(summary.bottleneck_m) + " tm=" + Hex(summary.total_m);
  return text;
}

}  // namespace syrof::queries::golden
