#include "measured_port.h"

#include "syrof/board/cycles.h"

namespace syrof::bench {

base::Result<os::TaskId, os::PortError> MeasuredPort::AddTask(os::Task& task, const os::TaskConfig& config) {
  uint16_t slot = 0;
  while (slot < kMaxProbes && probes_[slot].task != nullptr) ++slot;
  if (slot == kMaxProbes) return os::PortError::kTooManyTasks;
  probes_[slot].port = this;
  probes_[slot].task = &task;
  probes_[slot].config = config;
  const auto id = inner_.AddTask(probes_[slot], config);
  if (!id.ok()) {
    probes_[slot] = Probe{};
    return id;
  }
  probes_[slot].id = id.value();
  return id;
}

void MeasuredPort::Probe::Step(int64_t now_ns) {
  const uint64_t begin = board::cycle_counter_read();
  task->Step(now_ns);
  const uint64_t instructions = board::cycle_counter_read() - begin;
  port->observer_(port->context_, id, config, instructions, now_ns);
}

}  // namespace syrof::bench
