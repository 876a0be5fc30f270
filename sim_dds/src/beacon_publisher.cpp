#include "syrof/sim_dds/beacon_publisher.h"

#include "syrof/sim_dds/topics.h"

namespace syrof::sim_dds {

BeaconPublisherOrError BeaconPublisher::Create(const Participant& participant) {
  const EntityOrError writer = CreateWriter(participant, TopicKind::kBeacon);
  if (!writer.ok()) return BeaconPublisherOrError::Failed(*writer.error);
  return BeaconPublisherOrError{std::unique_ptr<BeaconPublisher>(new BeaconPublisher(writer.entity)), std::nullopt};
}

BeaconPublisher::~BeaconPublisher() {
  // After the participant went, the writer went with it: dds_delete then
  // returns an error, which changes nothing.
  if (writer_ > 0) dds_delete(writer_);
}

bool BeaconPublisher::Publish(uint16_t sender, uint32_t round, std::span<const uint8_t> wire) {
  if (wire.size() > syrof_msg_dds__BEACON_MAX_BYTES) {
    failed_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  syrof_msg_dds__Beacon_ sample{};
  sample.sender = sender;
  sample.round = round;
  sample.wire._maximum = static_cast<uint32_t>(wire.size());
  sample.wire._length = static_cast<uint32_t>(wire.size());
  // dds_write only reads the buffer; the sample does not own it.
  sample.wire._buffer = const_cast<uint8_t*>(wire.data());
  sample.wire._release = false;
  const bool written = dds_write(writer_, &sample) >= 0;
  (written ? published_ : failed_).fetch_add(1, std::memory_order_relaxed);
  return written;
}

uint32_t BeaconPublisher::matched_readers() const {
  dds_publication_matched_status_t status{};
  if (dds_get_publication_matched_status(writer_, &status) < 0) return 0;
  return status.current_count;
}

}  // namespace syrof::sim_dds
