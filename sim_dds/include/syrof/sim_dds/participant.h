// A Cyclone DDS participant for one SyROF run: its configuration (loopback
// by default), its domain id (one per run, so concurrent runs and CI jobs do
// not meet) and the participant itself, deleted with its children when the
// object goes (docs/dds.md, "Configuration" and "Domain ids").
//
// Usage:
//   const uint32_t domain = DomainIdForRun(run_id);  // or SYROF_DDS_DOMAIN
//   ParticipantOrError made = Participant::Create(domain, CycloneOptions{});
//   if (!made.ok()) { report made.error->ToString(); }
//   Participant& participant = *made.participant;
//   // topics.h: CreateWriter(participant, TopicKind::kBeacon) ...
#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "syrof/lab/base/error.h"

namespace syrof::sim_dds {

using lab::Error;

/// What the generated Cyclone configuration says.
struct CycloneOptions {
  /// The network interface: "lo" keeps everything on this host; a named
  /// interface ("eth0", "veth-a") lets processes on several hosts meet.
  std::string interface = "lo";
  /// Multicast for discovery only (AllowMulticast spdp); data goes unicast.
  /// Off: discovery by unicast to `peers` (and to 127.0.0.1 on "lo").
  bool multicast = true;
  /// Unicast discovery peers (addresses), in addition to multicast.
  std::vector<std::string> peers;
  /// Processes (participants) expected on one host at most; the automatic
  /// participant index goes a little above it. At most kMaxProcesses.
  uint32_t max_processes = 64;
  /// Above 0: Cyclone's own threads that take samples off the network and
  /// send them on (receive, timed events, delivery queues) run at SCHED_FIFO
  /// with this priority, so that on a loaded machine a beacon is not held
  /// by a thread at normal priority while the robot's tasks run at
  /// SCHED_FIFO (`--realtime`). Needs root or CAP_SYS_NICE: callers check.
  int network_fifo_priority = 0;
};

/// Whether this process may use SCHED_FIFO (root or CAP_SYS_NICE): tried on
/// the calling thread, then put back as it was.
bool CanUseFifoScheduling();

/// Most processes per host one domain's port range can hold (participant
/// indices 0 .. 119 keep every unicast port inside the domain's 250 ports).
inline constexpr uint32_t kMaxProcesses = 110;

/// Cyclone's XML for `options` (for CYCLONEDDS_URI or dds_create_domain):
/// the interface (loopback with multicast="true" by default), AllowMulticast
/// spdp (or false), ParticipantIndex auto with MaxAutoParticipantIndex above
/// max_processes, and the unicast peers. Valid for any domain id.
std::string CycloneConfig(const CycloneOptions& options);

/// Where an options value is unusable (an empty or odd interface name, an
/// address with XML characters, max_processes 0 or above kMaxProcesses), or
/// nothing.
std::optional<Error> CheckCycloneOptions(const CycloneOptions& options);

/// Domain ids a run may get: Cyclone's ports for domain d start at
/// 7400 + 250 d, so d <= 232 keeps them below 65536. Domain 0 (the DDS and
/// ROS 2 default) is never chosen automatically, so a SyROF run never meets
/// a ROS 2 graph by accident; give it explicitly to be seen.
inline constexpr uint32_t kMaxDomainId = 232;

/// The environment variable that overrides the run's domain id.
inline constexpr char kDomainEnvironmentVariable[] = "SYROF_DDS_DOMAIN";

/// The run's domain id from its id alone: 1 + hash(run_id) % 231 (1 .. 231:
/// at 232 only participant indices up to 62 have ports), so every process
/// of a run computes the same id and two runs meet with probability 1/231
/// (Control_ carries the run id too: a robot ignores other runs' worlds).
uint32_t DomainIdForRun(uint64_t run_id);

/// A domain id or why there is none.
struct DomainIdOrError {
  uint32_t domain_id = 0;
  std::optional<Error> error;
  bool ok() const { return !error; }
  static DomainIdOrError Of(uint32_t id) { return {id, std::nullopt}; }
  static DomainIdOrError Failed(Error why) { return {0, std::move(why)}; }
};

/// SYROF_DDS_DOMAIN when it is set (a decimal 0 .. 232; anything else is an
/// error naming the variable and the value), DomainIdForRun(run_id)
/// otherwise.
DomainIdOrError DomainIdFromEnvironment(uint64_t run_id);

/// The same rule for a given value of the variable (nullptr: unset).
DomainIdOrError DomainIdFromText(const char* text, uint64_t run_id);

/// "what: dds_strretcode(code)" as an Error, where = `where`.
Error DdsError(const std::string& where, const std::string& what, dds_return_t code);

class Participant;

struct ParticipantOrError {
  std::unique_ptr<Participant> participant;
  std::optional<Error> error;
  bool ok() const { return participant != nullptr; }
  static ParticipantOrError Failed(Error why) { return {nullptr, std::move(why)}; }
};

/// One DDS participant on its own domain with the generated configuration.
/// Several Participants of one process may share a domain id: the domain is
/// created once (with the first one's configuration) and deleted with the
/// last. Deleting a Participant deletes its topics, readers and writers.
/// Thread-safe to create and destroy from several threads.
class Participant {
 public:
  /// Creates the domain (if this process has none with that id yet) and the
  /// participant. Errors: bad options, a domain id above kMaxDomainId, or
  /// Cyclone's refusal (dds_strretcode's words, where = "domain <id>").
  static ParticipantOrError Create(uint32_t domain_id, const CycloneOptions& options);

  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  dds_entity_t handle() const { return participant_; }
  uint32_t domain_id() const { return domain_id_; }

 private:
  Participant(uint32_t domain_id, dds_entity_t participant) : domain_id_(domain_id), participant_(participant) {}

  uint32_t domain_id_;
  dds_entity_t participant_;
};

}  // namespace syrof::sim_dds
