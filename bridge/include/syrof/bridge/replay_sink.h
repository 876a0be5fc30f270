// The replay file as a RoundSink: what the base station hands its sinks,
// written with lab/replay's Writer (docs/replay.md), so `syrof view` shows a
// base station's recording like any run's.
#pragma once

#include <cstdint>
#include <memory>
#include <ostream>
#include <span>

#include "syrof/lab/base/error.h"
#include "syrof/lab/replay/round_sink.h"
#include "syrof/lab/replay/writer.h"

namespace syrof::bridge {

class ReplaySink final : public lab::replay::RoundSink {
 public:
  /// Writes to `out`, which the caller owns and must outlive the sink.
  explicit ReplaySink(std::ostream& out) : out_(out) {}

  void OnHeader(const lab::replay::Header& header) override;
  void OnRound(uint32_t index, int64_t time_ns, std::span<const lab::replay::RobotFrame> robots,
               std::span<const lab::replay::Event> events, std::span<const lab::replay::RobotMap> maps) override;
  /// Writes the end marker (whether or not the run was complete: what was
  /// recorded is whole) and flushes.
  void OnFinish(bool complete) override;

  /// False once the writer refused something or the stream failed.
  bool ok() const { return writer_ != nullptr && writer_->ok(); }
  /// Why not ok().
  lab::Error error() const;

 private:
  std::ostream& out_;
  std::unique_ptr<lab::replay::Writer> writer_;
};

}  // namespace syrof::bridge
