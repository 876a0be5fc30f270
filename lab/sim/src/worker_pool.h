// A fixed pool of threads that runs one job on every worker at once: the
// lab's `--threads` (robot_chunks.h). Internal to lab/sim.
//
// Made once per run; Run() allocates nothing and, between jobs, the workers
// sleep on an atomic (a futex), so an idle pool costs no CPU. The caller's
// thread is worker 0.
#pragma once

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace syrof::lab::sim {

class WorkerPool {
 public:
  /// A pool of `workers` (>= 1) workers: the caller and workers - 1 threads.
  explicit WorkerPool(int workers);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int size() const { return static_cast<int>(threads_.size()) + 1; }

  /// Calls job(worker) for every worker 0 .. size() - 1, worker 0 on the
  /// calling thread, and returns when every call has returned. What the
  /// calls wrote is visible to the caller afterwards, and what the caller
  /// wrote before is visible to them. `job` must not throw.
  template <typename Job>
  void Run(Job& job) {
    RunErased(&job, [](void* context, int worker) { (*static_cast<Job*>(context))(worker); });
  }

 private:
  using Erased = void (*)(void* context, int worker);
  void RunErased(void* context, Erased call);
  void WorkerLoop(int worker);

  std::vector<std::thread> threads_;
  void* context_ = nullptr;
  Erased call_ = nullptr;
  bool stopping_ = false;
  std::atomic<uint32_t> generation_{0};  // bumped to start a job
  std::atomic<int32_t> remaining_{0};    // threads still running the job
};

}  // namespace syrof::lab::sim
