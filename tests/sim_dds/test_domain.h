// A fresh domain id per test and per process, so tests running in parallel
// (ctest -j) never meet on one domain.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <functional>
#include <string>

#include "syrof/sim_dds/participant.h"

namespace syrof::sim_dds::testing {

inline uint32_t FreshDomainId() {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string name = std::string(test->test_suite_name()) + "." + test->name();
  return DomainIdForRun(std::hash<std::string>{}(name) ^ (static_cast<uint64_t>(getpid()) << 32));
}

}  // namespace syrof::sim_dds::testing
