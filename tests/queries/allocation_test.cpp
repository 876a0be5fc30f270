// The queries never allocate: this executable replaces the global operator
// new and counts every call made while a query runs. (CGAL's own algorithms,
// which allocate, are not used; see docs/queries.md.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <new>
#include <vector>

#include "query_test_support.h"
#include "syrof/queries/queries.h"
#include "syrof/queries/swarm_queries.h"

namespace {

bool counting = false;
int allocations = 0;

void* Allocate(std::size_t size) {
  if (counting) ++allocations;
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  std::abort();  // no exceptions on the Cortex-M4 build
}

}  // namespace

void* operator new(std::size_t size) { return Allocate(size); }
void* operator new[](std::size_t size) { return Allocate(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return Allocate(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return Allocate(size); }
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete[](void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
void operator delete[](void* memory, std::size_t) noexcept { std::free(memory); }

namespace syrof::queries {
namespace {

TEST(AllocationTest, CounterSeesAllocations) {
  allocations = 0;
  counting = true;
  auto* vector = new std::vector<int>(3);
  counting = false;
  delete vector;
  EXPECT_EQ(allocations, 2);  // the vector and its elements
}

TEST(AllocationTest, NoQueryAllocates) {
  static Workspace workspace;
  testing::Rng rng(61);
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<Member> members = testing::RandomMembers(rng, 1 + rng.Below(kMaxMembers), 2000);
    const std::vector<Point> targets =
        testing::RandomPoints(rng, 1 + rng.Below(std::min<uint32_t>(64, kMaxTargets)), 2000);
    std::vector<uint16_t> hull(members.size());
    std::vector<Assignment> by_robot(members.size());
    std::vector<uint16_t> robot_of_target(targets.size());
    std::vector<syrof_queries_member> c_members;
    for (const Member& member : members) c_members.push_back({member.id, member.position.x_mm, member.position.y_mm});
    uint16_t leader = 0;

    allocations = 0;
    counting = true;
    const bool ok = NumberOfMembers(members).ok() && Leader(members).ok() &&
                    ConvexHull(members, workspace, hull).ok() && ShortestEnclosingCircle(members, workspace).ok() &&
                    MinWeightedMatching(members, targets, workspace, by_robot, robot_of_target).ok() &&
                    PointFromMetres(1.0f, 2.0f).ok() &&
                    syrof_queries_leader(c_members.data(), c_members.size(), &leader) == SYROF_QUERIES_OK;
    counting = false;
    ASSERT_TRUE(ok);
    ASSERT_EQ(allocations, 0) << "trial " << trial;
  }
}

}  // namespace
}  // namespace syrof::queries
