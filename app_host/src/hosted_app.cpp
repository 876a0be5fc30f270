// HostedApp: an app::App whose callbacks run in a syrof-app-host process.
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <span>
#include <utility>
#include <vector>

#include "host_process.h"
#include "loaded_library.h"
#include "protocol.h"
#include "syrof/app_host/hosted_app.h"

namespace syrof::app_host {
namespace {

namespace p = protocol;
using app::CallStatus;

// A refused payload's bytes are never read (Platform's contract: a payload
// over SYROF_APP_MAX_PAYLOAD_BYTES changes nothing); the robot only counts
// and reports its length, so the host sends the length alone.
const uint8_t kNoBytes[SYROF_APP_MAX_PAYLOAD_BYTES] = {};

class HostedApp final : public app::App {
 public:
  HostedApp(const HostOptions& options, uint16_t robot_id, std::shared_ptr<LoadedLibrary> loaded = nullptr)
      : loaded_(std::move(loaded)), request_(p::kMaxRequestBytes) {
    start_status_ = loaded_ != nullptr ? process_.SpawnCopy(options, robot_id, *loaded_)
                                       : process_.Spawn(options, robot_id, HostProcess::Mode::kRun);
    if (start_status_.ok()) {
      start_status_ =
          EncodeEntries(options.params, p::kMaxParameters, kParameterFaults, parameters_);
    }
    const auto own_inputs = options.inputs.find(robot_id);
    if (start_status_.ok() && own_inputs != options.inputs.end()) {
      start_status_ =
          EncodeEntries(own_inputs->second, p::kMaxInputs, kInputFaults, inputs_);
    }
  }

  // The name comes with the host's hello: asking for it waits for the load
  // (a later call returns a load fault, if there was one).
  const char* name() const override {
    process_.EnsureStarted();
    return process_.app_name().empty() ? "library" : process_.app_name().c_str();
  }

  CallStatus Init(const syrof_app_info& info, app::Platform& platform, uint8_t& global_state) override {
    platform_ = &platform;
    if (!start_status_.ok()) return start_status_;
    p::RequestHeader header;
    header.kind = static_cast<uint8_t>(p::RequestKind::kInit);
    header.info = info;
    header.parameter_count = static_cast<uint16_t>(parameters_.size());
    header.input_count = static_cast<uint16_t>(inputs_.size());
    p::Reply reply;
    const CallStatus status = Send(header, nullptr, reply);
    if (status.ok()) global_state = reply.global_state;
    return status;
  }

  CallStatus NewRound(syrof_car_command& command, const syrof_ldmap& ldmap, uint8_t& global_state,
                      uint32_t clock_ms) override {
    p::RequestHeader header = MapHeader(p::RequestKind::kNewRound, ldmap, global_state, clock_ms);
    p::Reply reply;
    const CallStatus status = Send(header, &ldmap, reply);
    if (status.ok()) {
      command = reply.command;
      global_state = reply.global_state;
    }
    return status;
  }

  CallStatus EndOfRound(const syrof_ldmap& ldmap, uint8_t& global_state, uint32_t clock_ms) override {
    p::RequestHeader header = MapHeader(p::RequestKind::kEndOfRound, ldmap, global_state, clock_ms);
    p::Reply reply;
    const CallStatus status = Send(header, &ldmap, reply);
    if (status.ok()) global_state = reply.global_state;
    return status;
  }

 private:
  static p::RequestHeader MapHeader(p::RequestKind kind, const syrof_ldmap& ldmap, uint8_t global_state,
                                    uint32_t clock_ms) {
    p::RequestHeader header;
    header.kind = static_cast<uint8_t>(kind);
    header.global_state = global_state;
    header.mode = ldmap.mode;
    header.clock_ms = clock_ms;
    header.epoch = ldmap.epoch;
    header.self_id = ldmap.self_id;
    header.member_count = ldmap.member_count;
    return header;
  }

  // The init request's entries of one table (the parameters, or this
  // robot's inputs), checked once (they never change); `faults` says what
  // was wrong with them.
  struct TableFaults {
    const char* too_many;
    const char* bad_name;
  };
  static constexpr TableFaults kParameterFaults{"more app parameters than the app API takes",
                                                "an app parameter name the app API cannot carry"};
  static constexpr TableFaults kInputFaults{"more private inputs than the app API takes",
                                            "a private input name the app API cannot carry"};
  static CallStatus EncodeEntries(const std::map<std::string, double>& values, size_t most, TableFaults faults,
                                  std::vector<p::ParameterEntry>& entries) {
    if (values.size() > most) {
      return CallStatus::Fault(app::Verdict::kBadAbi, faults.too_many);
    }
    for (const auto& [name, value] : values) {
      if (name.empty() || name.size() > SYROF_APP_MAX_PARAMETER_NAME_LENGTH || name.find('\0') != std::string::npos) {
        return CallStatus::Fault(app::Verdict::kBadAbi, faults.bad_name);
      }
      p::ParameterEntry entry;
      std::memcpy(entry.name, name.data(), name.size());
      entry.value = value;
      entries.push_back(entry);
    }
    return CallStatus::Ok();
  }

  CallStatus Send(p::RequestHeader& header, const syrof_ldmap* ldmap, p::Reply& reply) {
    if (!start_status_.ok()) return start_status_;
    if (platform_ == nullptr) return CallStatus::Fault(app::Verdict::kBadAbi, "a callback before init");
    header.sequence = ++sequence_;
    size_t size = sizeof(header);
    if (ldmap != nullptr) {
      if (ldmap->member_count > p::kMaxMembers) {
        return CallStatus::Fault(app::Verdict::kBadAbi, "a map larger than the host takes");
      }
      const size_t members = size_t{ldmap->member_count} * sizeof(syrof_member_state);
      if (members > 0) std::memcpy(request_.data() + sizeof(header), ldmap->members, members);
      size += members;
    } else {
      for (const std::vector<p::ParameterEntry>* table : {&parameters_, &inputs_}) {
        const size_t bytes = table->size() * sizeof(p::ParameterEntry);
        if (bytes > 0) std::memcpy(request_.data() + size, table->data(), bytes);
        size += bytes;
      }
    }
    std::memcpy(request_.data(), &header, sizeof(header));
    app::Platform& platform = *platform_;
    // Each sendMessageData call the app made reaches the robot in order,
    // within this callback, as an in-process app's would.
    return process_.Call(
        request_.data(), size, header.sequence,
        [&platform](const p::PayloadCall& call) {
          const uint8_t* bytes = call.length <= SYROF_APP_MAX_PAYLOAD_BYTES ? call.bytes : kNoBytes;
          (void)platform.SendMessageData(std::span<const uint8_t>(bytes, call.length));
        },
        reply);
  }

  // The held host this app's host is a copy of: it lives while the copy
  // does (declared first, so it goes after the process).
  std::shared_ptr<LoadedLibrary> loaded_;
  mutable HostProcess process_;  // name() may have to wait for the hello
  CallStatus start_status_;
  std::vector<unsigned char> request_;
  std::vector<p::ParameterEntry> parameters_;
  std::vector<p::ParameterEntry> inputs_;
  app::Platform* platform_ = nullptr;
  uint32_t sequence_ = 0;
};

}  // namespace

std::unique_ptr<app::App> MakeHostedApp(const HostOptions& options, uint16_t robot_id) {
  return std::make_unique<HostedApp>(options, robot_id);
}

std::unique_ptr<app::App> MakeHostedApp(const HostOptions& options, uint16_t robot_id,
                                        const std::shared_ptr<LoadedLibrary>& loaded) {
  return std::make_unique<HostedApp>(options, robot_id, loaded);
}

}  // namespace syrof::app_host
