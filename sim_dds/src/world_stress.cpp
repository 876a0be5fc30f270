#include "world_stress.h"

#include <signal.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <new>
#include <utility>

#include "syrof/os/posix_port.h"

namespace syrof::sim_dds {

namespace {

// What the stress could not do, where "stress".
lab::Error StressError(std::string message) {
  return lab::Error{.where = "stress", .line = 0, .column = 0, .message = std::move(message)};
}

}  // namespace

WorldStress::WorldStress(const lab::sim::StressOptions& options, uint16_t robots)
    : options_(options), stalled_until_(robots, -1) {}

WorldStress::~WorldStress() { EndStaller(); }

std::optional<StressFailure> WorldStress::OpenQuota() {
  if (!options_.on() || options_.cpu_quota_permille <= 0) return std::nullopt;
  quota_ = std::make_unique<lab::sim::CpuQuotaGroup>(options_.cpu_quota_permille);
  if (!quota_->ok()) return StressFailure{1, StressError(quota_->error())};
  return std::nullopt;
}

std::optional<StressFailure> WorldStress::Start(int64_t duration_ns, int64_t start_monotonic_ns, std::ostream& log) {
  if (!options_.on()) return std::nullopt;
  if (const std::optional<lab::Error> why = lab::sim::CheckStressOptions(options_)) {
    return StressFailure{2, *why};
  }
  seed_ = options_.seed;
  stalls_plan_ = lab::sim::PlanStalls(options_, duration_ns, static_cast<uint16_t>(stalled_until_.size()));
  std::vector<std::pair<int64_t, int64_t>> world_stalls;  // monotonic start, length
  for (const lab::sim::Stall& stall : stalls_plan_) {
    if (stall.target == lab::sim::kStallWorld) world_stalls.emplace_back(start_monotonic_ns + stall.at_ns, stall.duration_ns);
  }
  log << "syrof swarm: stress seed " << options_.seed << ": " << stalls_plan_.size() << " SIGSTOP bursts of "
      << options_.min_stall_ms << "-" << options_.max_stall_ms << " ms (" << world_stalls.size() << " of the world)";
  if (options_.delayed_fraction > 0) {
    log << ", " << options_.delayed_fraction * 100 << " % of beacons and readings " << options_.min_delay_ms << "-"
        << options_.max_delay_ms << " ms late";
  }
  if (quota_) log << ", robots' CPU quota " << options_.cpu_quota_permille << " per mille of a core";
  log << "\n";
  stalls_ += static_cast<int64_t>(world_stalls.size());
  if (world_stalls.empty()) return std::nullopt;
  void* page = mmap(nullptr, sizeof(std::atomic<int>), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (page == MAP_FAILED) return StressFailure{1, StressError("mmap failed")};
  staller_stop_ = new (page) std::atomic<int>(0);
  const pid_t world = getpid();
  world_staller_ = process::ForkHelper([this, world, &world_stalls] {
    // Sleep, stop the world, sleep, resume it. It checks the stop flag at
    // least every 10 ms, and never leaves the world stopped: each SIGSTOP
    // is followed by its SIGCONT.
    const auto sleep_until = [this](int64_t until_ns) {
      for (;;) {
        if (staller_stop_->load() != 0) return false;
        const int64_t now = os::PosixPort::MonotonicNowNs();
        if (now >= until_ns) return true;
        const int64_t step = std::min<int64_t>(until_ns - now, 10'000'000);
        timespec t{static_cast<time_t>(step / 1'000'000'000), static_cast<long>(step % 1'000'000'000)};
        (void)nanosleep(&t, nullptr);
      }
    };
    for (const auto& [at, length] : world_stalls) {
      if (!sleep_until(at)) break;
      (void)kill(world, SIGSTOP);
      timespec t{static_cast<time_t>(length / 1'000'000'000), static_cast<long>(length % 1'000'000'000)};
      while (nanosleep(&t, &t) != 0 && errno == EINTR) {
      }
      (void)kill(world, SIGCONT);
    }
    return 0;
  });
  if (!world_staller_.started()) {
    return StressFailure{1, StressError(std::string("cannot start the process that stalls the world: ") +
                                        std::strerror(world_staller_.start_error()))};
  }
  return std::nullopt;
}

void WorldStress::Play(int64_t now_ns, const Robot& running, const Signal& signal) {
  for (uint16_t id = 0; id < stalled_until_.size(); ++id) {
    if (stalled_until_[id] < 0 || stalled_until_[id] > now_ns) continue;
    stalled_until_[id] = -1;
    if (running(id)) signal(id, false);
  }
  while (next_stall_ < stalls_plan_.size() && stalls_plan_[next_stall_].at_ns <= now_ns) {
    const lab::sim::Stall& stall = stalls_plan_[next_stall_++];
    if (stall.target == lab::sim::kStallWorld || stall.target >= stalled_until_.size()) continue;
    if (!running(stall.target)) continue;
    int64_t& until = stalled_until_[stall.target];
    if (until < 0) {
      signal(stall.target, true);
      ++stalls_;
    }
    // Overlapping stalls of one robot make one longer stop.
    until = std::max(until, stall.at_ns + stall.duration_ns);
  }
}

void WorldStress::End(const Robot& may_continue, const Signal& signal) {
  next_stall_ = stalls_plan_.size();
  for (uint16_t id = 0; id < stalled_until_.size(); ++id) {
    if (stalled_until_[id] < 0) continue;
    stalled_until_[id] = -1;
    if (may_continue(id)) signal(id, false);
  }
  EndStaller();
}

void WorldStress::EndStaller() {
  if (world_staller_.started() && !world_staller_.reaped()) {
    staller_stop_->store(1);
    (void)world_staller_.Reap();
  }
  if (staller_stop_ != nullptr) {
    (void)munmap(staller_stop_, sizeof(std::atomic<int>));
    staller_stop_ = nullptr;
  }
}

}  // namespace syrof::sim_dds
