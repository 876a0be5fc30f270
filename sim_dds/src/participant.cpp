#include "syrof/sim_dds/participant.h"

#include <sched.h>

#include <cerrno>
#include <cstdlib>
#include <map>
#include <mutex>

#include "syrof/base/split_mix64.h"

namespace syrof::sim_dds {
namespace {

// Participant indices above the expected process count: a process that
// restarts (a join) may find its old index not yet free.
constexpr uint32_t kSpareParticipantIndices = 8;

bool SafeInXml(const std::string& text) {
  if (text.empty() || text.size() > 64) return false;
  for (const char c : text) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                       c == '-' || c == '_' || c == ':' || c == '@';
    if (!plain) return false;
  }
  return true;
}

// The domains this process created, with how many Participants use each:
// dds_create_domain refuses an id that exists, and deleting a domain
// deletes every participant on it.
struct DomainTable {
  std::mutex mutex;
  std::map<uint32_t, std::pair<dds_entity_t, int>> domains;  // id -> (domain, users)
};

DomainTable& Domains() {
  static DomainTable* table = new DomainTable;  // never destroyed: outlives static Participants
  return *table;
}

}  // namespace

std::optional<Error> CheckCycloneOptions(const CycloneOptions& options) {
  if (!SafeInXml(options.interface)) {
    return Error{.where = "interface", .message = "'" + options.interface +
                                                      "' is not an interface name (letters, digits, . - _ : @; 1 to 64)"};
  }
  for (const std::string& peer : options.peers) {
    if (!SafeInXml(peer)) {
      return Error{.where = "peer", .message = "'" + peer + "' is not an address (letters, digits, . - _ : @; 1 to 64)"};
    }
  }
  if (options.max_processes == 0 || options.max_processes > kMaxProcesses) {
    return Error{.where = "max_processes",
                 .message = "must be in 1 .. " + std::to_string(kMaxProcesses) + ", not " +
                            std::to_string(options.max_processes)};
  }
  return std::nullopt;
}

bool CanUseFifoScheduling() {
  // The kernel's calls on this thread (0), not pthread's: glibc keeps the
  // policy pthread_setschedparam last set and reports that, whatever
  // sched_setscheduler or the spawn that started the process set since.
  const int policy = sched_getscheduler(0);
  sched_param before{};
  if (policy < 0 || sched_getparam(0, &before) != 0) return false;
  sched_param low{};
  low.sched_priority = sched_get_priority_min(SCHED_FIFO);
  if (sched_setscheduler(0, SCHED_FIFO, &low) != 0) return false;
  // Back to what it was (a robot process may start at SCHED_FIFO).
  (void)sched_setscheduler(0, policy, &before);
  return true;
}

std::string CycloneConfig(const CycloneOptions& options) {
  const bool loopback = options.interface == "lo";
  std::string xml;
  xml += "<CycloneDDS><Domain id=\"any\">";
  xml += "<General><Interfaces><NetworkInterface name=\"" + options.interface + "\"";
  // lo carries no MULTICAST flag, so Cyclone must be told it works there.
  if (loopback && options.multicast) xml += " multicast=\"true\"";
  xml += "/></Interfaces>";
  xml += std::string("<AllowMulticast>") + (options.multicast ? "spdp" : "false") + "</AllowMulticast>";
  xml += "</General>";
  xml += "<Discovery><ParticipantIndex>auto</ParticipantIndex>";
  xml += "<MaxAutoParticipantIndex>" + std::to_string(options.max_processes + kSpareParticipantIndices) +
         "</MaxAutoParticipantIndex>";
  std::vector<std::string> peers = options.peers;
  if (loopback) peers.insert(peers.begin(), "127.0.0.1");
  if (!peers.empty()) {
    xml += "<Peers>";
    for (const std::string& peer : peers) xml += "<Peer address=\"" + peer + "\"/>";
    xml += "</Peers>";
  }
  xml += "</Discovery>";
  if (options.network_fifo_priority > 0) {
    // One receive thread: the extra ones Cyclone starts by default (recvUC,
    // recvMC) take no scheduling from the configuration (it refuses their
    // names) and would stay at normal priority.
    xml += "<Internal><MultipleReceiveThreads>false</MultipleReceiveThreads></Internal>";
    xml += "<Threads>";
    for (const char* name : {"recv", "tev", "dq.user", "dq.builtins"}) {
      xml += std::string("<Thread name=\"") + name + "\"><Scheduling><Class>realtime</Class><Priority>" +
             std::to_string(options.network_fifo_priority) + "</Priority></Scheduling></Thread>";
    }
    xml += "</Threads>";
  }
  xml += "</Domain></CycloneDDS>";
  return xml;
}

uint32_t DomainIdForRun(uint64_t run_id) {
  return 1 + static_cast<uint32_t>(base::SplitMix64Hash(run_id ^ 0x5359524f46444453ull) % (kMaxDomainId - 1));
}

DomainIdOrError DomainIdFromText(const char* text, uint64_t run_id) {
  if (text == nullptr) return DomainIdOrError::Of(DomainIdForRun(run_id));
  const std::string value = text;
  bool digits = !value.empty() && value.size() <= 3;
  for (const char c : value) digits = digits && c >= '0' && c <= '9';
  if (!digits || std::stoul(value) > kMaxDomainId) {
    return DomainIdOrError::Failed(Error{.where = kDomainEnvironmentVariable,
                                         .message = "must be a domain id 0 .. " + std::to_string(kMaxDomainId) +
                                                    ", not '" + value + "'"});
  }
  return DomainIdOrError::Of(static_cast<uint32_t>(std::stoul(value)));
}

DomainIdOrError DomainIdFromEnvironment(uint64_t run_id) {
  return DomainIdFromText(std::getenv(kDomainEnvironmentVariable), run_id);
}

Error DdsError(const std::string& where, const std::string& what, dds_return_t code) {
  return Error{.where = where, .message = what + ": " + dds_strretcode(code)};
}

ParticipantOrError Participant::Create(uint32_t domain_id, const CycloneOptions& options) {
  if (std::optional<Error> problem = CheckCycloneOptions(options)) return ParticipantOrError::Failed(*problem);
  const std::string where = "domain " + std::to_string(domain_id);
  if (domain_id > kMaxDomainId) {
    return ParticipantOrError::Failed(
        Error{.where = where, .message = "above the largest domain id " + std::to_string(kMaxDomainId)});
  }
  DomainTable& table = Domains();
  std::lock_guard<std::mutex> lock(table.mutex);
  auto found = table.domains.find(domain_id);
  if (found == table.domains.end()) {
    const std::string config = CycloneConfig(options);
    const dds_entity_t domain = dds_create_domain(domain_id, config.c_str());
    if (domain < 0) return ParticipantOrError::Failed(DdsError(where, "dds_create_domain", domain));
    found = table.domains.emplace(domain_id, std::pair{domain, 0}).first;
  }
  const dds_entity_t participant = dds_create_participant(domain_id, nullptr, nullptr);
  if (participant < 0) {
    if (found->second.second == 0) {
      dds_delete(found->second.first);
      table.domains.erase(found);
    }
    return ParticipantOrError::Failed(DdsError(where, "dds_create_participant", participant));
  }
  ++found->second.second;
  return ParticipantOrError{std::unique_ptr<Participant>(new Participant(domain_id, participant)), std::nullopt};
}

Participant::~Participant() {
  DomainTable& table = Domains();
  std::lock_guard<std::mutex> lock(table.mutex);
  dds_delete(participant_);
  auto found = table.domains.find(domain_id_);
  if (found != table.domains.end() && --found->second.second == 0) {
    dds_delete(found->second.first);
    table.domains.erase(found);
  }
}

}  // namespace syrof::sim_dds
