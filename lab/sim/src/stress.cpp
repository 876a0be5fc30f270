#include "syrof/lab/sim/stress.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "syrof/base/split_mix64.h"

namespace syrof::lab::sim {

std::optional<Error> CheckStressOptions(const StressOptions& options) {
  auto refuse = [](std::string message) { return Error{.where = "stress", .message = std::move(message)}; };
  if (options.min_stall_ms < 1 || options.max_stall_ms > 10'000 || options.min_stall_ms > options.max_stall_ms) {
    return refuse("stall lengths must be 1 .. 10000 ms with min <= max (got " + std::to_string(options.min_stall_ms) +
                  " .. " + std::to_string(options.max_stall_ms) + ")");
  }
  if (!(options.stalls_per_second >= 0) || options.stalls_per_second > 100) {
    return refuse("stalls per second must be 0 .. 100");
  }
  if (options.cpu_quota_permille > 1000) return refuse("the CPU quota is at most 1000 per mille of one core");
  if (!(options.delayed_fraction >= 0 && options.delayed_fraction <= 1)) {
    return refuse("the fraction of samples delayed must be 0 .. 1");
  }
  if (options.min_delay_ms < 1 || options.max_delay_ms > 10'000 || options.min_delay_ms > options.max_delay_ms) {
    return refuse("sample delays must be 1 .. 10000 ms with min <= max (got " + std::to_string(options.min_delay_ms) +
                  " .. " + std::to_string(options.max_delay_ms) + ")");
  }
  return std::nullopt;
}

std::vector<Stall> PlanStalls(const StressOptions& options, int64_t duration_ns, uint16_t robots) {
  std::vector<Stall> stalls;
  if (!options.on() || duration_ns <= 0 || robots == 0 || CheckStressOptions(options)) return stalls;
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

int64_t SampleDelayNs(const StressOptions& options, DelayedStream stream, uint16_t sender, uint16_t receiver,
                      int64_t stamp) {
  if (!options.on() || options.delayed_fraction <= 0 || CheckStressOptions(options)) return 0;
  // One hash per sample, its key folded in one field at a time; the seed's
  // own hash keeps the stalls' draws (SplitMix64 from the same seed) apart.
  uint64_t h = base::SplitMix64Hash(base::SplitMix64Hash(options.seed) ^ 0x5D1A7ED5A3D1E5ull);
  h = base::SplitMix64Hash(h ^ static_cast<uint64_t>(stream));
  h = base::SplitMix64Hash(h ^ (uint64_t{sender} << 16 | receiver));
  h = base::SplitMix64Hash(h ^ static_cast<uint64_t>(stamp));
  // The top 53 bits as a fraction in [0, 1): late when below the fraction.
  const double draw = static_cast<double>(h >> 11) * 0x1.0p-53;
  if (draw >= options.delayed_fraction) return 0;
  const auto span = static_cast<uint64_t>(options.max_delay_ms - options.min_delay_ms + 1);
  const uint64_t length_ms = static_cast<uint64_t>(options.min_delay_ms) + base::SplitMix64Hash(h) % span;
  return static_cast<int64_t>(length_ms) * 1'000'000;
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

}  // namespace syrof::lab::sim
