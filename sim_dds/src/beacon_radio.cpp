#include "syrof/sim_dds/beacon_radio.h"

#include <chrono>
#include <string>
#include <utility>

#include "syrof/runtime/robot.h"
#include "syrof/sim_dds/topics.h"
#include "syrof/wire/beacon_codec.h"

namespace syrof::sim_dds {
namespace {

static_assert(wire::EncodedSize(kMaxDdsSwarm) <= syrof_msg_dds__BEACON_MAX_BYTES,
              "every beacon of a DDS swarm must fit Beacon_'s wire sequence");

// Samples taken per dds_take call (loaned, so no copies).
constexpr int32_t kTakeBatch = 16;

int64_t SteadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

BeaconRadio::BeaconRadio(const Participant& participant, BeaconRadioOptions options)
    : participant_(&participant),
      options_(std::move(options)),
      send_bytes_(wire::EncodedSize(options_.swarm_size)),
      filter_(options_.self, options_.swarm_size, options_.run_id),
      channel_(options_.channel, options_.swarm_size, options_.seed),
      offsets_(options_.swarm_size) {}

BeaconRadioOrError BeaconRadio::Create(const Participant& participant, BeaconRadioOptions options) {
  if (options.swarm_size < 1 || options.swarm_size > kMaxDdsSwarm) {
    return BeaconRadioOrError::Failed(Error{.where = "swarm_size", .message = "must be in 1 .. " +
                                                                              std::to_string(kMaxDdsSwarm) + ", not " +
                                                                              std::to_string(options.swarm_size)});
  }
  if (options.self >= options.swarm_size) {
    return BeaconRadioOrError::Failed(Error{.where = "self", .message = "robot " + std::to_string(options.self) +
                                                                        " is not in a swarm of " +
                                                                        std::to_string(options.swarm_size)});
  }
  if (options.radio_round_ns <= 0) {
    return BeaconRadioOrError::Failed(Error{.where = "radio_round_ns", .message = "must be positive, not " +
                                                                                  std::to_string(options.radio_round_ns)});
  }
  if (!options.current_round) {
    return BeaconRadioOrError::Failed(Error{.where = "current_round", .message = "is not set"});
  }
  if (std::optional<Error> problem = lab::world::CheckChannelSpec(options.channel, options.swarm_size)) {
    problem->where = problem->where.empty() ? "channel" : "channel " + problem->where;
    return BeaconRadioOrError::Failed(*problem);
  }
  std::unique_ptr<BeaconRadio> radio(new BeaconRadio(participant, std::move(options)));
  const EntityOrError writer = CreateWriter(participant, TopicKind::kBeacon);
  if (!writer.ok()) return BeaconRadioOrError::Failed(*writer.error);
  radio->writer_ = writer.entity;
  return BeaconRadioOrError{std::move(radio), std::nullopt};
}

BeaconRadioOrError BeaconRadio::Create(const Participant& participant, BeaconRadioOptions options, BeaconSink sink) {
  BeaconRadioOrError made = Create(participant, std::move(options));
  if (!made.ok()) return made;
  if (std::optional<Error> problem = made.radio->StartReceiving(std::move(sink))) {
    return BeaconRadioOrError::Failed(*problem);
  }
  return made;
}

std::optional<Error> BeaconRadio::StartReceiving(BeaconSink sink) {
  const std::string name = TopicName(TopicKind::kBeacon);
  if (reader_ != 0) return Error{.where = name, .message = "this radio already receives"};
  if (!sink) return Error{.where = "sink", .message = "is not set"};
  sink_ = std::move(sink);
  const EntityOrError topic = CreateTopic(*participant_, TopicKind::kBeacon);
  if (!topic.ok()) return topic.error;
  Qos qos(TopicKind::kBeacon);
  // Its own participant's beacon would only be counted as kFromSelf.
  dds_qset_ignorelocal(qos.mutable_get(), DDS_IGNORELOCAL_PARTICIPANT);
  dds_listener_t* listener = dds_create_listener(this);
  dds_lset_data_available(listener, &BeaconRadio::OnDataAvailable);
  if (options_.hold_ns) holder_ = std::thread([this] { ReleaseHeld(); });
  const dds_entity_t reader = dds_create_reader(participant_->handle(), topic.entity, qos.get(), listener);
  dds_delete_listener(listener);
  if (reader < 0) return DdsError(name, "dds_create_reader", reader);
  reader_ = reader;
  return std::nullopt;
}

std::optional<Error> BeaconRadio::StartReceiving(runtime::Robot& robot) {
  runtime::Robot* target = &robot;
  return StartReceiving([target](std::span<const uint8_t> frame, uint16_t, uint32_t) { target->ReceiveBytes(frame); });
}

BeaconRadio::~BeaconRadio() {
  // dds_delete waits for a listener call in progress before it returns;
  // then nothing more is held, and what is held never arrives.
  if (reader_ > 0) dds_delete(reader_);
  if (holder_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(held_mutex_);
      stop_holding_ = true;
    }
    held_changed_.notify_all();
    holder_.join();
  }
  if (writer_ > 0) dds_delete(writer_);
}

void BeaconRadio::Broadcast(const wire::Beacon& beacon) {
  const int64_t round = options_.current_round();
  const auto encoded = wire::Encode(beacon, options_.swarm_size, send_bytes_);
  if (!encoded.ok() || round < 0 || round > int64_t{UINT32_MAX}) {
    send_failed_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  syrof_msg_dds__Beacon_ sample{};
  sample.sender = options_.self;
  sample.round = static_cast<uint32_t>(round);
  sample.run_id = options_.run_id;
  sample.wire._maximum = static_cast<uint32_t>(encoded.value());
  sample.wire._length = static_cast<uint32_t>(encoded.value());
  sample.wire._buffer = send_bytes_.data();
  sample.wire._release = false;
  const dds_return_t written = dds_write(writer_, &sample);
  (written < 0 ? send_failed_ : sent_).fetch_add(1, std::memory_order_relaxed);
}

void BeaconRadio::OnDataAvailable(dds_entity_t reader, void* self) { static_cast<BeaconRadio*>(self)->TakeAll(reader); }

void BeaconRadio::TakeAll(dds_entity_t reader) {
  std::lock_guard<std::mutex> lock(receive_mutex_);
  void* samples[kTakeBatch] = {};
  dds_sample_info_t infos[kTakeBatch];
  for (;;) {
    samples[0] = nullptr;  // loan
    const dds_return_t taken = dds_take(reader, samples, infos, kTakeBatch, kTakeBatch);
    if (taken <= 0) return;
    for (int32_t i = 0; i < taken; ++i) {
      if (!infos[i].valid_data) continue;
      received_.fetch_add(1, std::memory_order_relaxed);
      const auto* sample = static_cast<const syrof_msg_dds__Beacon_*>(samples[i]);
      // Another run's robot on this domain: not of this swarm at all.
      if (filter_.CheckRun(sample->run_id) != SampleVerdict::kAccepted) continue;
      const std::span<const uint8_t> bytes(sample->wire._buffer, sample->wire._length);
      const int64_t hold_ns = options_.hold_ns ? options_.hold_ns(sample->sender, sample->round) : 0;
      if (hold_ns > 0) {
        held_count_.fetch_add(1, std::memory_order_relaxed);
        {
          std::lock_guard<std::mutex> held_lock(held_mutex_);
          held_.emplace(SteadyNowNs() + hold_ns,
                        HeldSample{sample->sender, sample->round, std::vector<uint8_t>(bytes.begin(), bytes.end())});
        }
        held_changed_.notify_one();
        continue;
      }
      Arrive(sample->sender, sample->round, bytes);
    }
    dds_return_loan(reader, samples, taken);
    if (taken < kTakeBatch) return;
  }
}

void BeaconRadio::Arrive(uint16_t sender, uint32_t round, std::span<const uint8_t> bytes) {
  const int64_t current_round = options_.current_round();
  const int64_t expected_round = ExpectedRound();
  wire::Beacon beacon;
  const SampleVerdict verdict = filter_.Check(sender, round, bytes, current_round, beacon);
  // A well-formed sample from another robot, in or out of the window:
  // its sender's count against this robot's.
  if ((verdict == SampleVerdict::kAccepted || verdict == SampleVerdict::kRoundOutOfWindow) && expected_round >= 0) {
    offsets_[sender] = SenderRoundOffset{expected_round, static_cast<int64_t>(round) - expected_round};
  }
  if (verdict != SampleVerdict::kAccepted) return;
  if (static_cast<int64_t>(round) == expected_round) {
    HeardRound& heard = heard_[static_cast<size_t>(expected_round) % kHeardRounds];
    if (heard.round != expected_round) heard = HeardRound{expected_round, {}};
    heard.senders.set(sender);
  }
  const double sent_at_s = static_cast<double>(static_cast<int64_t>(round) * options_.radio_round_ns) * 1e-9;
  if (!channel_.Delivers(sender, options_.self, round, sent_at_s)) {
    lost_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  sink_(bytes, sender, round);
  delivered_.fetch_add(1, std::memory_order_release);  // after the sink: a reader of the count sees its effects
}

void BeaconRadio::ReleaseHeld() {
  std::unique_lock<std::mutex> held_lock(held_mutex_);
  for (;;) {
    if (stop_holding_) return;
    if (held_.empty()) {
      held_changed_.wait(held_lock);
      continue;
    }
    const int64_t due_ns = held_.begin()->first;
    if (SteadyNowNs() < due_ns) {
      held_changed_.wait_until(held_lock, std::chrono::steady_clock::time_point(std::chrono::nanoseconds(due_ns)));
      continue;
    }
    HeldSample sample = std::move(held_.begin()->second);
    held_.erase(held_.begin());
    held_lock.unlock();
    {
      std::lock_guard<std::mutex> lock(receive_mutex_);
      Arrive(sample.sender, sample.round, sample.bytes);
    }
    held_lock.lock();
  }
}

wire::MemberSet BeaconRadio::HeardInRound(int64_t round) const {
  if (round < 0) return {};
  std::lock_guard<std::mutex> lock(receive_mutex_);
  const HeardRound& heard = heard_[static_cast<size_t>(round) % kHeardRounds];
  return heard.round == round ? heard.senders : wire::MemberSet{};
}

int64_t BeaconRadio::ExpectedRound() const {
  return options_.expected_round ? options_.expected_round() : options_.current_round();
}

int64_t BeaconRadio::AgreedRoundOffset(int64_t since_round) const {
  std::lock_guard<std::mutex> lock(receive_mutex_);
  return sim_dds::AgreedRoundOffset(offsets_, since_round);
}

void BeaconRadio::ForgetRoundOffsets() {
  std::lock_guard<std::mutex> lock(receive_mutex_);
  for (SenderRoundOffset& offset : offsets_) offset = SenderRoundOffset{};
}

uint32_t BeaconRadio::matched_readers() const {
  dds_publication_matched_status_t status{};
  if (dds_get_publication_matched_status(writer_, &status) < 0) return 0;
  return status.current_count;
}

BeaconRadioCounters BeaconRadio::counters() const {
  return BeaconRadioCounters{.sent = sent_.load(std::memory_order_relaxed),
                             .send_failed = send_failed_.load(std::memory_order_relaxed),
                             .received = received_.load(std::memory_order_relaxed),
                             .held = held_count_.load(std::memory_order_relaxed),
                             .rejected = filter_.counters().rejected(),
                             .lost = lost_.load(std::memory_order_relaxed),
                             .delivered = delivered_.load(std::memory_order_acquire)};
}

}  // namespace syrof::sim_dds
