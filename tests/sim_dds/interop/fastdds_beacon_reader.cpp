// An independent reader of a SyROF swarm's beacons, built with eProsima
// Fast DDS 2.9 (Debian's libfastrtps-dev) from types that fastddsgen
// generates from sim_dds/idl/syrof_msgs.idl at build time. It links nothing
// of SyROF: the beacon bytes are decoded here from docs/beacon.md alone, so
// this program checks both the DDS interoperability (another vendor's RTPS
// stack on the same topic and type) and that the documented layout is the
// one on the air.
//
// Usage: fastdds_beacon_reader --domain D --swarm N [--expect K]
//        [--min-per-sender M] [--seconds S] [--run-id R] [--min-foreign F]
// Subscribes to rt/syrof/beacon on loopback (UDPv4 on 127.0.0.1 only, with
// 127.0.0.1 as initial peer), prints one line per sender (samples, valid,
// invalid with the first reason, last round, last epoch and position) and
// exits 0 once senders 0 .. K-1 have each sent M valid beacons and no
// invalid one was seen; 1 when S seconds pass first or a beacon is invalid;
// 2 on bad usage or a DDS error. Only the beacons of run R (default 0) are
// judged: another run that lands on the same domain (a test running beside
// this one, docs/dds.md "Domain ids") is counted as foreign and left alone,
// as a robot refuses other runs' beacons; --min-foreign F also waits for F
// foreign samples (the test that shows they are ignored).
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "syrof_msgsPubSubTypes.h"

namespace {

using namespace eprosima::fastdds::dds;

// docs/beacon.md, "Layout" and "What the decoder rejects", for a swarm of
// `swarm` robots: returns "" for a valid beacon, else the reason.
struct Decoded {
  unsigned robot_id = 0;
  unsigned epoch = 0;
  int x_mm = 0;
  int y_mm = 0;
};

std::string DecodeBeacon(const std::vector<uint8_t>& bytes, unsigned swarm, Decoded& out) {
  const size_t id_bytes = swarm <= 256 ? 1 : 2;
  const size_t waiting_bytes = (swarm + 7) / 8;
  const size_t relay_bytes = swarm <= 255 ? 1 : 2;
  const size_t size = 1 + id_bytes + 2 + 1 + 1 + waiting_bytes + 5 * 2 + 9 + relay_bytes + 3;
  if (bytes.empty() || bytes[0] != 4) return "wrong version";  // docs/beacon.md, "Version"
  if (bytes.size() < size) return "truncated";
  if (bytes.size() > size) return "trailing bytes";
  size_t at = 1;
  auto u16 = [&bytes](size_t offset) { return unsigned(bytes[offset]) | (unsigned(bytes[offset + 1]) << 8); };
  auto s16 = [&u16](size_t offset) {
    const unsigned value = u16(offset);
    return value >= 0x8000 ? int(value) - 0x10000 : int(value);
  };
  out.robot_id = id_bytes == 1 ? bytes[at] : u16(at);
  at += id_bytes;
  if (out.robot_id >= swarm) return "robot id out of range";
  out.epoch = u16(at);
  at += 2;
  const unsigned flags = bytes[at++];
  if ((flags & 0x3) == 3) return "phase out of range";
  const unsigned payload_length = flags >> 4;
  if (payload_length > 9) return "payload too long";
  at += 1;  // vote counter: any value
  for (unsigned id = swarm; id < waiting_bytes * 8; ++id) {
    if (bytes[at + id / 8] & (1u << (id % 8))) return "waiting set names a robot beyond the swarm";
  }
  at += waiting_bytes;
  out.x_mm = s16(at);
  out.y_mm = s16(at + 2);
  const int heading = s16(at + 4);
  if (heading < -3142 || heading > 3142) return "heading out of range";
  at += 10;
  for (size_t i = payload_length; i < 9; ++i) {
    if (bytes[at + i] != 0) return "payload padding not zero";
  }
  at += 9;
  // docs/beacon.md, "Relays": 0 or 1 + a robot id, then two 12-bit
  // coordinates in three bytes, zero when nothing is relayed.
  const unsigned relay = relay_bytes == 1 ? bytes[at] : u16(at);
  at += relay_bytes;
  if (relay > swarm) return "relay out of range";
  const bool coordinates = bytes[at] != 0 || bytes[at + 1] != 0 || bytes[at + 2] != 0;
  if (relay == 0 && coordinates) return "relay out of range";
  return "";
}

struct SenderCount {
  double first_ms = 0;  // since the reader started
  uint64_t samples = 0;
  uint64_t valid = 0;
  uint64_t invalid = 0;
  std::string first_problem;
  uint32_t last_round = 0;
  Decoded last;
};

class BeaconListener : public DataReaderListener {
 public:
  BeaconListener(unsigned swarm, uint64_t run_id)
      : swarm_(swarm), run_id_(run_id), start_(std::chrono::steady_clock::now()) {}

  void on_data_available(DataReader* reader) override {
    syrof::msg::dds_::Beacon_ sample;
    SampleInfo info;
    while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      std::lock_guard<std::mutex> lock(mutex_);
      if (sample.run_id() != run_id_) {
        ++foreign_;
        continue;
      }
      SenderCount& count = senders_[sample.sender()];
      if (count.samples++ == 0) {
        count.first_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
      }
      count.last_round = sample.round();
      Decoded decoded;
      std::string problem = DecodeBeacon(sample.wire(), swarm_, decoded);
      if (problem.empty() && decoded.robot_id != sample.sender()) problem = "sample sender is not the beacon's robot id";
      if (problem.empty()) {
        ++count.valid;
        count.last = decoded;
      } else {
        ++count.invalid;
        if (count.first_problem.empty()) count.first_problem = problem;
      }
    }
  }

  std::map<uint16_t, SenderCount> Snapshot() {
    std::lock_guard<std::mutex> lock(mutex_);
    return senders_;
  }

  uint64_t Foreign() {
    std::lock_guard<std::mutex> lock(mutex_);
    return foreign_;
  }

 private:
  unsigned swarm_;
  uint64_t run_id_;
  uint64_t foreign_ = 0;  // samples of other runs
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  std::map<uint16_t, SenderCount> senders_;
};

bool Done(const std::map<uint16_t, SenderCount>& senders, unsigned expect, uint64_t min_per_sender, uint64_t foreign,
          uint64_t min_foreign) {
  if (foreign < min_foreign) return false;
  for (unsigned sender = 0; sender < expect; ++sender) {
    const auto found = senders.find(static_cast<uint16_t>(sender));
    if (found == senders.end() || found->second.valid < min_per_sender) return false;
  }
  return true;
}

int Usage() {
  std::fprintf(stderr,
               "usage: fastdds_beacon_reader --domain D --swarm N [--expect K] [--min-per-sender M] [--seconds S] [--run-id R] [--min-foreign F]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  long domain = -1, swarm = 0, expect = -1, min_per_sender = 5, seconds = 30, min_foreign = 0;
  unsigned long long run_id = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    char* end = nullptr;
    if (flag == "--run-id") {
      run_id = std::strtoull(argv[i + 1], &end, 10);
      if (*end != '\0' || argv[i + 1][0] < '0' || argv[i + 1][0] > '9') return Usage();
      continue;
    }
    const long value = std::strtol(argv[i + 1], &end, 10);
    if (*end != '\0' || value < 0) return Usage();
    if (flag == "--domain") domain = value;
    else if (flag == "--swarm") swarm = value;
    else if (flag == "--expect") expect = value;
    else if (flag == "--min-per-sender") min_per_sender = value;
    else if (flag == "--seconds") seconds = value;
    else if (flag == "--min-foreign") min_foreign = value;
    else return Usage();
  }
  if (argc % 2 == 0 || domain < 0 || domain > 232 || swarm < 1 || swarm > 65535) return Usage();
  if (expect < 0) expect = swarm;

  // Only loopback: with Fast DDS's defaults it would advertise eth0's
  // address alone, which a Cyclone on lo never reaches.
  DomainParticipantQos participant_qos;
  participant_qos.name("syrof_fastdds_beacon_reader");
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.push_back("127.0.0.1");
  participant_qos.transport().user_transports.push_back(udp);
  participant_qos.transport().use_builtin_transports = false;
  eprosima::fastrtps::rtps::Locator_t peer;
  eprosima::fastrtps::rtps::IPLocator::setIPv4(peer, 127, 0, 0, 1);
  participant_qos.wire_protocol().builtin.initialPeersList.push_back(peer);

  DomainParticipant* participant =
      DomainParticipantFactory::get_instance()->create_participant(static_cast<DomainId_t>(domain), participant_qos);
  if (participant == nullptr) {
    std::fprintf(stderr, "fastdds_beacon_reader: cannot create a participant on domain %ld\n", domain);
    return 2;
  }
  TypeSupport type(new syrof::msg::dds_::Beacon_PubSubType());
  type.register_type(participant);
  Topic* topic = participant->create_topic("rt/syrof/beacon", type.get_type_name(), TOPIC_QOS_DEFAULT);
  Subscriber* subscriber = participant->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
  DataReaderQos reader_qos = DATAREADER_QOS_DEFAULT;
  reader_qos.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
  reader_qos.durability().kind = VOLATILE_DURABILITY_QOS;
  reader_qos.history().kind = KEEP_LAST_HISTORY_QOS;
  reader_qos.history().depth = 1;
  // One instance per sender: Fast DDS's default of 10 instances would drop
  // every robot past the tenth (seen with 16 and 32 processes).
  // The key is (sender, run): room for the robots of another run on the
  // domain too (up to kMaxDdsSwarm = 1024), whose instances would otherwise
  // take the slots of this run's robots and silence them.
  constexpr long kForeignInstances = 1024;
  reader_qos.resource_limits().max_instances = static_cast<int32_t>(swarm + kForeignInstances);
  reader_qos.resource_limits().max_samples_per_instance = 1;
  reader_qos.resource_limits().max_samples = static_cast<int32_t>(swarm + kForeignInstances);
  BeaconListener listener(static_cast<unsigned>(swarm), static_cast<uint64_t>(run_id));
  DataReader* reader = topic == nullptr || subscriber == nullptr
                           ? nullptr
                           : subscriber->create_datareader(topic, reader_qos, &listener);
  if (reader == nullptr) {
    std::fprintf(stderr, "fastdds_beacon_reader: cannot create the reader of rt/syrof/beacon\n");
    return 2;
  }
  std::printf("fastdds_beacon_reader: domain %ld, type %s, run %llu, waiting for senders 0..%ld\n", domain,
              type.get_type_name().c_str(), run_id, expect - 1);
  std::fflush(stdout);

  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  std::map<uint16_t, SenderCount> senders;
  bool invalid = false;
  uint64_t foreign = 0;
  for (;;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    senders = listener.Snapshot();
    foreign = listener.Foreign();
    for (const auto& [sender, count] : senders) invalid = invalid || count.invalid > 0;
    if (invalid ||
        Done(senders, static_cast<unsigned>(expect), static_cast<uint64_t>(min_per_sender), foreign,
             static_cast<uint64_t>(min_foreign)) ||
        std::chrono::steady_clock::now() > deadline) {
      break;
    }
  }
  SubscriptionMatchedStatus matched;
  reader->get_subscription_matched_status(matched);
  double first_ms = 0, last_ms = 0;
  for (const auto& [sender, count] : senders) {
    first_ms = first_ms == 0 ? count.first_ms : std::min(first_ms, count.first_ms);
    last_ms = std::max(last_ms, count.first_ms);
  }
  std::printf("fastdds_beacon_reader: %d beacon writers matched; first beacon after %.0f ms, every sender's after %.0f ms\n",
              matched.current_count, first_ms, last_ms);
  participant->delete_contained_entities();
  DomainParticipantFactory::get_instance()->delete_participant(participant);

  for (const auto& [sender, count] : senders) {
    std::printf("sender %u: samples %llu valid %llu invalid %llu last_round %u epoch %u x_mm %d y_mm %d%s%s\n", sender,
                static_cast<unsigned long long>(count.samples), static_cast<unsigned long long>(count.valid),
                static_cast<unsigned long long>(count.invalid), count.last_round, count.last.epoch, count.last.x_mm,
                count.last.y_mm, count.first_problem.empty() ? "" : " first problem: ", count.first_problem.c_str());
  }
  std::printf("fastdds_beacon_reader: %llu samples of other runs ignored\n", static_cast<unsigned long long>(foreign));
  const bool done = Done(senders, static_cast<unsigned>(expect), static_cast<uint64_t>(min_per_sender), foreign,
                         static_cast<uint64_t>(min_foreign));
  std::printf("fastdds_beacon_reader: %s (%zu senders heard, %ld expected, %ld valid beacons each)\n",
              invalid ? "INVALID beacons" : done ? "OK" : "TIMEOUT", senders.size(), expect, min_per_sender);
  return !invalid && done ? 0 : 1;
}
