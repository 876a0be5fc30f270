// The answers on a fixed input set, bit for bit as the host computed them
// (golden_expected.inc, written by golden_generate). Runs on the host and on
// the emulated Cortex-M4: passing on both shows the soft-float build and the
// host give identical results, float bits included.
#include <gtest/gtest.h>

#include <iterator>
#include <string>
#include <vector>

#include "golden_cases.h"

namespace syrof::queries {
namespace {

const char* const kExpected[] = {
#include "golden_expected.inc"
};

TEST(GoldenTest, AnswersMatchTheHostTableBitForBit) {
  static Workspace workspace;
  const std::vector<golden::Case> cases = golden::Cases();
  ASSERT_EQ(cases.size(), std::size(kExpected))
      << "regenerate golden_expected.inc (see docs/queries.md, Tests and benchmarks)";
  for (size_t index = 0; index < cases.size(); ++index) {
    EXPECT_EQ(golden::Describe(cases[index], workspace), std::string(kExpected[index])) << "case " << index;
  }
}

}  // namespace
}  // namespace syrof::queries
