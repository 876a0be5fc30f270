#include "syrof/bridge/dds_output.h"

#include "syrof/sim_dds/beacon_publisher.h"
#include "syrof/sim_dds/participant.h"

namespace syrof::bridge {

DdsOutputOrError DdsBeaconOutput::Create(uint32_t domain_id, const std::string& interface) {
  sim_dds::CycloneOptions options;
  options.interface = interface;
  sim_dds::ParticipantOrError participant = sim_dds::Participant::Create(domain_id, options);
  if (!participant.ok()) return DdsOutputOrError{nullptr, participant.error};
  sim_dds::BeaconPublisherOrError publisher = sim_dds::BeaconPublisher::Create(*participant.participant);
  if (!publisher.ok()) return DdsOutputOrError{nullptr, publisher.error};
  std::unique_ptr<DdsBeaconOutput> output(new DdsBeaconOutput());
  output->participant_ = std::move(participant.participant);
  output->publisher_ = std::move(publisher.publisher);
  return DdsOutputOrError{std::move(output), std::nullopt};
}

DdsBeaconOutput::~DdsBeaconOutput() {
  publisher_.reset();  // the writer before its participant
  participant_.reset();
}

void DdsBeaconOutput::OnBeacon(const wire::Beacon& beacon, std::span<const uint8_t> wire_bytes, int8_t,
                               uint32_t round) {
  (void)publisher_->Publish(beacon.robot_id, round, wire_bytes);
}

uint64_t DdsBeaconOutput::published() const { return publisher_->published(); }
uint64_t DdsBeaconOutput::failed() const { return publisher_->failed(); }
uint32_t DdsBeaconOutput::matched_readers() const { return publisher_->matched_readers(); }

}  // namespace syrof::bridge
