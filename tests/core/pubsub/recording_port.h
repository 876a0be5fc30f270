// A Port for broker tests: records notifications in order and checks that
// critical sections balance. No tasks ever run.
#pragma once

#include <ostream>
#include <vector>

#include "syrof/os/port.h"
#include "syrof/pubsub/broker.h"

namespace syrof::pubsub::testing {

class RecordingPort final : public os::Port {
 public:
  base::Result<os::TaskId, os::PortError> AddTask(os::Task&, const os::TaskConfig&) override {
    return os::PortError::kTooManyTasks;
  }
  os::PortError Start() override { return os::PortError::kOk; }
  os::PortError Stop() override { return os::PortError::kOk; }
  void Notify(os::TaskId task) override { notified.push_back(task); }
  int64_t now_ns() const override { return 0; }
  void Lock() override { ++depth; }
  void Unlock() override { --depth; }

  std::vector<os::TaskId> notified;
  int depth = 0;
};

}  // namespace syrof::pubsub::testing

namespace syrof::pubsub {
// Lets GoogleTest print broker errors by name.
inline void PrintTo(BrokerError error, std::ostream* out) { *out << ToString(error); }
}  // namespace syrof::pubsub
