// `--threads` (docs/lab.md, "Threads"): the robots cut into chunks, and the
// chunks stepped side by side on a WorkerPool. Internal to lab/sim; the
// engine (simulation.cpp) decides what runs side by side, this file how.
//
// ChunkPlan: how the robots are cut, fixed for the run: contiguous chunks
// by id, a few per worker, so that a worker that runs slower (a shared
// core) takes fewer. RobotChunks: the pool, each worker's queue of chunks,
// and the batches of robot steps (os::SimBatchRunner): it runs a batch's
// steps chunk by chunk on the workers, keeps what the steps tell the lab
// (ObserverCall) per robot, and hands the kept calls to the engine after
// the batch, robot by robot in the batch's order, which is the order of a
// one-thread run.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "observer_call.h"
#include "syrof/os/sim_port.h"
#include "worker_pool.h"

namespace syrof::lab::sim {

// Below this many steps a batch runs on the calling thread, and below this
// many robots so do the world's per-robot loops: 16 robot steps are a few
// microseconds, about what waking a sleeping worker takes. A reasoned
// guess, not tuned: on the shared machine of docs/lab.md ("Threads") no
// batch size gave a reliable gain to tune against.
inline constexpr size_t kMinParallelSteps = 16;

class ChunkPlan {
 public:
  /// `threads` (1 .. kMaxThreads, SYROF_CHECK) capped at the robot count.
  /// One worker and one chunk with one thread, fewer than two robots, or
  /// clocks: with clocks the radio hands a beacon to its receivers inside
  /// the sender's round step (radio_network.h), so robots' steps are not
  /// independent, and drifting clocks rarely release two robots at one
  /// instant anyway.
  ChunkPlan(size_t robot_count, int threads, bool clocks);

  int workers() const { return workers_; }
  size_t chunks() const { return chunks_; }
  /// Chunk c holds robots begin(c) .. end(c) - 1; none is empty.
  size_t begin(size_t chunk) const { return starts_[chunk]; }
  size_t end(size_t chunk) const { return starts_[chunk + 1]; }
  size_t ChunkOf(size_t robot) const { return robot * chunks_ / robot_count_; }
  /// Each chunk's first robot (RadioNetwork::SplitReceivers' blocks).
  std::vector<uint16_t> FirstRobots() const;

 private:
  size_t robot_count_;
  int workers_;
  size_t chunks_;
  std::vector<size_t> starts_;  // chunk c: starts_[c] .. starts_[c + 1]
};

class RobotChunks final : public os::SimBatchRunner {
 public:
  /// `plan` has more than one worker; `robot_ports` holds every robot's
  /// port, in id order (ports of other ids are the world's); `handler`
  /// takes the kept calls after each batch. The ports and the handler
  /// outlive this; so must whatever the steps and jobs touch, since the
  /// workers stop when this is destroyed.
  RobotChunks(const ChunkPlan& plan, std::vector<os::SimPort*> robot_ports, ObserverCallHandler& handler);
  RobotChunks(const RobotChunks&) = delete;
  RobotChunks& operator=(const RobotChunks&) = delete;
  ~RobotChunks() = default;

  const ChunkPlan& plan() const { return plan_; }
  /// Every robot's port, in id order (os::SimScheduler::BeginSideBySide's).
  std::span<os::SimPort* const> robot_ports() const { return robot_ports_; }

  /// Calls run(chunk) once for every chunk and returns when all calls have;
  /// each worker takes its own chunks first, then what is left of the
  /// others'. Calls run at the same time on different chunks: run(chunk)
  /// may touch only what belongs to chunk's robots.
  template <typename Run>
  void ForEachChunk(Run run);

  /// os::SimBatchRunner. A batch of at least kMinParallelSteps steps, all on
  /// robots' ports, runs chunk by chunk on the workers (each robot's step
  /// touches its own robot, port, broker and radio slot; what it tells the
  /// lab it tells through Keep); any other batch runs here, in order.
  void RunBatch(std::span<const os::SimStep> steps) override;

  /// Whether a batch's steps are running on the workers now: then what a
  /// robot's step tells the lab must be kept (Keep), not handled.
  bool in_batch() const { return in_batch_; }
  /// Keeps `call` for the handler, after the batch; from call.robot's step,
  /// on the worker running its chunk (the robot's own list).
  void Keep(ObserverCall call) { kept_[call.robot].push_back(std::move(call)); }

 private:
  static constexpr int kNoChunk = -1;
  // Which chunks are left in the job running now: worker w's own chunks are
  // queues_[w].next .. queues_[w].end, taken from the front by it and then
  // by the others once theirs are done.
  struct alignas(64) ChunkQueue {
    std::atomic<uint32_t> next{0};
    uint32_t begin = 0;
    uint32_t end = 0;
  };

  int ChunkOfPort(uint32_t port_index) const {
    return port_index < chunk_of_port_.size() ? chunk_of_port_[port_index] : kNoChunk;
  }

  ChunkPlan plan_;
  std::vector<os::SimPort*> robot_ports_;
  ObserverCallHandler& handler_;
  std::vector<int> chunk_of_port_;       // by port index; kNoChunk for the world's ports
  std::vector<uint16_t> robot_of_port_;  // by port index
  std::unique_ptr<ChunkQueue[]> queues_;  // one per worker
  // RunBatch: the batch's steps of chunk c are batch_[chunk_steps_[i]] for
  // i in chunk_step_begin_[c] .. chunk_step_begin_[c + 1], in batch order.
  std::vector<uint32_t> chunk_steps_;
  std::vector<uint32_t> chunk_step_begin_;
  std::span<const os::SimStep> batch_;
  bool in_batch_ = false;
  std::vector<std::vector<ObserverCall>> kept_;  // per robot
  WorkerPool pool_;  // last: its workers stop first
};

template <typename Run>
void RobotChunks::ForEachChunk(Run run) {
  const int workers = plan_.workers();
  for (int worker = 0; worker < workers; ++worker) {
    queues_[worker].next.store(queues_[worker].begin, std::memory_order_relaxed);
  }
  auto job = [this, workers, &run](int worker) {
    for (int k = 0; k < workers; ++k) {
      ChunkQueue& queue = queues_[(worker + k) % workers];
      for (uint32_t chunk; (chunk = queue.next.fetch_add(1, std::memory_order_relaxed)) < queue.end;) run(chunk);
    }
  };
  pool_.Run(job);
}

}  // namespace syrof::lab::sim
