#include "syrof/sim_dds/stress.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "syrof/base/split_mix64.h"

namespace syrof::sim_dds {

std::string CheckStressOptions(const StressOptions& options) {
  if (options.min_stall_ms < 1 || options.max_stall_ms > 10'000 || options.min_stall_ms > options.max_stall_ms) {
    return "stall lengths must be 1 .. 10000 ms with min <= max (got " + std::to_string(options.min_stall_ms) +
           " .. " + std::to_string(options.max_stall_ms) + ")";
  }
  if (!(options.stalls_per_second >= 0) || options.stalls_per_second > 100) {
    return "stalls per second must be 0 .. 100";
  }
  if (options.cpu_quota_permille > 1000) return "the CPU quota is at most 1000 per mille of one core";
  return {};
}

std::vector<Stall> PlanStalls(const StressOptions& options, int64_t duration_ns, uint16_t robots) {
  std::vector<Stall> stalls;
  if (!options.on() || duration_ns <= 0 || robots == 0 || !CheckStressOptions(options).empty()) return stalls;
  base::SplitMix64 random(base::SplitMix64Hash(options.seed));
  const double seconds = static_cast<double>(duration_ns) * 1e-9;
  const auto count = static_cast<size_t>(std::llround(options.stalls_per_second * seconds));
  const uint32_t targets = robots + (options.stall_world ? 1U : 0U);
  const auto window = static_cast<uint64_t>(static_cast<double>(duration_ns) * 0.95);
  for (size_t i = 0; i < count; ++i) {
    Stall stall;
    stall.at_ns = window == 0 ? 0 : static_cast<int64_t>(random.Next() % window);
    stall.duration_ns =
        int64_t{1'000'000} * random.Between(static_cast<int32_t>(options.min_stall_ms), static_cast<int32_t>(options.max_stall_ms));
    const uint32_t target = random.Below(targets);
    stall.target = target == robots ? kStallWorld : static_cast<uint16_t>(target);
    stalls.push_back(stall);
  }
  std::stable_sort(stalls.begin(), stalls.end(), [](const Stall& a, const Stall& b) { return a.at_ns < b.at_ns; });
  return stalls;
}

namespace {

bool WriteFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  if (!out) return false;
  out << text;
  out.flush();
  return static_cast<bool>(out);
}

bool Writable(const std::string& path) { return access(path.c_str(), W_OK) == 0; }

}  // namespace

CpuQuotaGroup::CpuQuotaGroup(uint32_t permille) {
  const std::string name = "syrof-stress-" + std::to_string(getpid());
  constexpr int64_t kPeriodUs = 100'000;
  const int64_t quota_us = std::max<int64_t>(1000, kPeriodUs * permille / 1000);
  // cgroup v1: the cpu controller's own hierarchy.
  for (const char* v1 : {"/sys/fs/cgroup/cpu", "/sys/fs/cgroup/cpu,cpuacct"}) {
    const std::string root = v1;
    if (!Writable(root + "/cgroup.procs")) continue;
    const std::string path = root + "/" + name;
    if (mkdir(path.c_str(), 0755) != 0 && errno != EEXIST) continue;
    if (WriteFile(path + "/cpu.cfs_period_us", std::to_string(kPeriodUs)) &&
        WriteFile(path + "/cpu.cfs_quota_us", std::to_string(quota_us))) {
      path_ = path;
      root_ = root;
      return;
    }
    rmdir(path.c_str());
  }
  // cgroup v2: cpu.max, where the cpu controller is enabled for children.
  for (const char* v2 : {"/sys/fs/cgroup/unified", "/sys/fs/cgroup"}) {
    const std::string root = v2;
    std::ifstream controllers(root + "/cgroup.subtree_control");
    std::string enabled((std::istreambuf_iterator<char>(controllers)), std::istreambuf_iterator<char>());
    if (enabled.find("cpu") == std::string::npos || !Writable(root + "/cgroup.procs")) continue;
    const std::string path = root + "/" + name;
    if (mkdir(path.c_str(), 0755) != 0 && errno != EEXIST) continue;
    if (WriteFile(path + "/cpu.max", std::to_string(quota_us) + " " + std::to_string(kPeriodUs))) {
      path_ = path;
      root_ = root;
      return;
    }
    rmdir(path.c_str());
  }
  error_ = "no writable cgroup cpu controller (v1 /sys/fs/cgroup/cpu, or v2 cpu.max; needs root)";
}

bool CpuQuotaGroup::Add(int pid) { return ok() && WriteFile(path_ + "/cgroup.procs", std::to_string(pid)); }

CpuQuotaGroup::~CpuQuotaGroup() {
  if (!ok()) return;
  // Processes still inside (robots not yet reaped) go back to the root, so
  // the group can be removed.
  std::ifstream procs(path_ + "/cgroup.procs");
  std::string pid;
  while (procs >> pid) (void)WriteFile(root_ + "/cgroup.procs", pid);
  rmdir(path_.c_str());
}

}  // namespace syrof::sim_dds
