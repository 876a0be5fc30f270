#include "robot_chunks.h"

#include <algorithm>

#include "syrof/base/check.h"
#include "syrof/lab/sim/simulation.h"

namespace syrof::lab::sim {
namespace {

// A worker's robots are cut into this many chunks, which the workers take
// as they go (a worker first its own chunks, then what is left of the
// others'), so a core that runs slower, or is shared, takes fewer: a fixed
// half per worker left the faster one waiting for the other (docs/lab.md,
// "Threads"). A chunk has at least kMinChunkRobots robots.
constexpr size_t kChunksPerWorker = 4;
constexpr size_t kMinChunkRobots = 8;

}  // namespace

ChunkPlan::ChunkPlan(size_t robot_count, int threads, bool clocks) : robot_count_(robot_count) {
  SYROF_CHECK(threads >= 1 && threads <= kMaxThreads);
  workers_ = clocks || robot_count < 2 ? 1 : static_cast<int>(std::min(static_cast<size_t>(threads), robot_count));
  const auto workers = static_cast<size_t>(workers_);
  chunks_ = workers == 1 ? 1 : std::max(workers, std::min(workers * kChunksPerWorker, robot_count / kMinChunkRobots));
  for (size_t robot = 0; robot < robot_count; ++robot) {
    if (robot == 0 || ChunkOf(robot) != ChunkOf(robot - 1)) starts_.push_back(robot);
  }
  if (robot_count == 0) starts_.push_back(0);
  SYROF_CHECK(starts_.size() == chunks_);  // no chunk is empty: chunks_ <= robot_count
  starts_.push_back(robot_count);
}

std::vector<uint16_t> ChunkPlan::FirstRobots() const {
  std::vector<uint16_t> first;
  for (size_t chunk = 0; chunk < chunks_; ++chunk) first.push_back(static_cast<uint16_t>(starts_[chunk]));
  return first;
}

RobotChunks::RobotChunks(const ChunkPlan& plan, std::vector<os::SimPort*> robot_ports, ObserverCallHandler& handler)
    : plan_(plan),
      robot_ports_(std::move(robot_ports)),
      handler_(handler),
      queues_(std::make_unique<ChunkQueue[]>(static_cast<size_t>(plan.workers()))),
      chunk_steps_(robot_ports_.size()),
      chunk_step_begin_(plan.chunks() + 1),
      kept_(robot_ports_.size()),
      pool_(plan.workers()) {
  SYROF_CHECK(plan_.workers() > 1);
  uint32_t ports = 0;
  for (const os::SimPort* port : robot_ports_) ports = std::max(ports, port->index() + 1);
  chunk_of_port_.assign(ports, kNoChunk);
  robot_of_port_.assign(ports, 0);
  for (size_t robot = 0; robot < robot_ports_.size(); ++robot) {
    chunk_of_port_[robot_ports_[robot]->index()] = static_cast<int>(plan_.ChunkOf(robot));
    robot_of_port_[robot_ports_[robot]->index()] = static_cast<uint16_t>(robot);
  }
  const auto workers = static_cast<size_t>(plan_.workers());
  for (size_t worker = 0; worker < workers; ++worker) {
    queues_[worker].begin = static_cast<uint32_t>(plan_.chunks() * worker / workers);
    queues_[worker].end = static_cast<uint32_t>(plan_.chunks() * (worker + 1) / workers);
  }
}

// A batch holds one task per port, due at one instant with one priority
// (os::SimScheduler). The world's tasks have priorities of their own
// (registry/tasks.h), so they never share a batch with a robot's; a batch
// that holds one anyway runs serially.
void RobotChunks::RunBatch(std::span<const os::SimStep> steps) {
  bool robots_only = steps.size() >= kMinParallelSteps;
  for (size_t i = 0; robots_only && i < steps.size(); ++i) robots_only = ChunkOfPort(steps[i].port_index) != kNoChunk;
  if (!robots_only) {
    for (const os::SimStep& step : steps) step.task->Step(step.now_ns);
    return;
  }
  // The steps by chunk (a counting sort that keeps the batch's order).
  const size_t chunks = plan_.chunks();
  std::fill(chunk_step_begin_.begin(), chunk_step_begin_.end(), 0u);
  for (const os::SimStep& step : steps) ++chunk_step_begin_[static_cast<size_t>(chunk_of_port_[step.port_index]) + 1];
  for (size_t chunk = 0; chunk < chunks; ++chunk) chunk_step_begin_[chunk + 1] += chunk_step_begin_[chunk];
  for (uint32_t i = 0; i < steps.size(); ++i) {
    uint32_t& end = chunk_step_begin_[static_cast<size_t>(chunk_of_port_[steps[i].port_index])];
    chunk_steps_[end++] = i;
  }
  for (size_t chunk = chunks; chunk > 0; --chunk) chunk_step_begin_[chunk] = chunk_step_begin_[chunk - 1];
  chunk_step_begin_[0] = 0;
  in_batch_ = true;
  batch_ = steps;
  ForEachChunk([this](size_t chunk) {
    for (uint32_t i = chunk_step_begin_[chunk]; i < chunk_step_begin_[chunk + 1]; ++i) {
      const os::SimStep& step = batch_[chunk_steps_[i]];
      step.task->Step(step.now_ns);
    }
  });
  in_batch_ = false;
  for (const os::SimStep& step : steps) {
    std::vector<ObserverCall>& calls = kept_[robot_of_port_[step.port_index]];
    for (const ObserverCall& call : calls) handler_.Handle(call);
    calls.clear();
  }
}

}  // namespace syrof::lab::sim
