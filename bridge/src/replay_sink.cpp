#include "syrof/bridge/replay_sink.h"

namespace syrof::bridge {

void ReplaySink::OnHeader(const lab::replay::Header& header) {
  writer_ = std::make_unique<lab::replay::Writer>(out_, header);
}

void ReplaySink::OnRound(uint32_t index, int64_t time_ns, std::span<const lab::replay::RobotFrame> robots,
                         std::span<const lab::replay::Event> events, std::span<const lab::replay::RobotMap> maps) {
  if (writer_ != nullptr) writer_->WriteRound(index, time_ns, robots, events, maps);
}

void ReplaySink::OnFinish(bool) {
  if (writer_ != nullptr) writer_->Finish();
}

lab::Error ReplaySink::error() const {
  if (writer_ == nullptr) return lab::Error{.where = "replay", .message = "no header was written"};
  return writer_->error();
}

}  // namespace syrof::bridge
