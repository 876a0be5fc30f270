// The frames between a HostedApp (the parent) and its syrof-app-host (the
// child), docs/app_host.md "The protocol". Both sides are built from this one
// header by the same compiler, so the structs are the wire format; the
// parent still treats every reply as untrusted (size, magic, sequence,
// ranges) because the child runs a student's code.
//
// The channel is one AF_UNIX SOCK_SEQPACKET pair: one frame is one message
// (a short or long message cannot be mistaken for a frame), and the parent
// sends with MSG_NOSIGNAL (a dead child gives EPIPE, not a SIGPIPE in the
// simulator). The child's stdout and stderr share one pipe, so the log keeps
// the order the app wrote in.
//
// Child descriptors: 0 /dev/null, 1 and 2 the output pipe, 3 the channel.
#pragma once

#include <cstddef>
#include <cstdint>

#include "syrof/app.h"

namespace syrof::app_host::protocol {

inline constexpr int kChannelFd = 3;
inline constexpr uint32_t kRequestMagic = 0x53524551;  // "SREQ"
inline constexpr uint32_t kReplyMagic = 0x53524550;    // "SREP"
/// Bumped whenever a frame below changes (host and parent must agree).
inline constexpr uint32_t kProtocolVersion = 3;
inline constexpr size_t kMaxMembers = SYROF_MAX_SWARM_SIZE;

enum class RequestKind : uint8_t { kInit = 1, kNewRound = 2, kEndOfRound = 3 };

/// One scenario parameter or one of the robot's private inputs, sent with
/// Init (syrofAppParameter, syrofAppInput). `name` is
/// NUL-terminated within the field, 1 .. SYROF_APP_MAX_PARAMETER_NAME_LENGTH
/// bytes; the host refuses a frame where it is not.
struct ParameterEntry {
  char name[SYROF_APP_MAX_PARAMETER_NAME_LENGTH + 1] = {};
  double value = 0;
};

/// One callback. Followed in the same message by `member_count`
/// syrof_member_state (NewRound, EndOfRound), or by `parameter_count`
/// ParameterEntry (Init; at most SYROF_APP_MAX_PARAMETERS), then
/// `input_count` more (the robot's private inputs; at most
/// SYROF_APP_MAX_INPUTS). The host keeps them and answers the app's
/// syrofAppParameter and syrofAppInput itself, without a round trip.
struct RequestHeader {
  uint32_t magic = kRequestMagic;
  uint32_t sequence = 0;  ///< the reply echoes it
  uint8_t kind = 0;       ///< RequestKind
  uint8_t global_state = 0;
  uint8_t mode = 0;       ///< ldmap.mode
  uint8_t reserved = 0;
  uint32_t clock_ms = 0;
  uint16_t epoch = 0;     ///< ldmap.epoch
  uint16_t self_id = 0;   ///< ldmap.self_id
  uint16_t member_count = 0;
  uint16_t parameter_count = 0;  ///< Init only
  uint16_t input_count = 0;      ///< Init only
  syrof_app_info info{};  ///< Init only
};

inline constexpr size_t kMaxParameters = SYROF_APP_MAX_PARAMETERS;
inline constexpr size_t kMaxInputs = SYROF_APP_MAX_INPUTS;
inline constexpr size_t kMaxRequestBytes =
    sizeof(RequestHeader) +
    (kMaxMembers * sizeof(syrof_member_state) > (kMaxParameters + kMaxInputs) * sizeof(ParameterEntry)
         ? kMaxMembers * sizeof(syrof_member_state)
         : (kMaxParameters + kMaxInputs) * sizeof(ParameterEntry));

enum class ReplyKind : uint8_t {
  kHello = 1,  ///< the library is loaded and validated (text: the app's name, then notes)
  kBatch = 2,  ///< sendMessageData calls made so far in this call; the call goes on
  kDone = 3,   ///< the call returned: command, global state, the last calls
  kFault = 4,  ///< the host saw a fault (verdict, detail) and exits
};

/// One sendMessageData call the app made, in order. `length` is what the app
/// passed; bytes hold the payload when length <= SYROF_APP_MAX_PAYLOAD_BYTES.
struct PayloadCall {
  uint32_t length = 0;
  uint8_t bytes[SYROF_APP_MAX_PAYLOAD_BYTES] = {};
  uint8_t reserved[3] = {};
};

inline constexpr size_t kCallsPerReply = 16;
inline constexpr size_t kTextBytes = 256;

/// Every reply is exactly this size.
struct Reply {
  uint32_t magic = kReplyMagic;
  uint32_t sequence = 0;  ///< the request's (0 for the hello)
  uint8_t kind = 0;       ///< ReplyKind
  uint8_t global_state = 0;
  uint8_t verdict = 0;    ///< app::Verdict, kFault only
  uint8_t call_count = 0; ///< valid entries of calls
  uint32_t protocol_version = kProtocolVersion;
  uint32_t notes = 0;     ///< kHello: the NoteBits of layers the kernel refused
  uint32_t calls_total = 0;  ///< sendMessageData calls in this callback so far (counter)
  syrof_car_command command{};  ///< kDone of NewRound
  PayloadCall calls[kCallsPerReply];
  char text[kTextBytes] = {};  ///< NUL-terminated: kHello the app's name; kFault the detail
};

/// The hardening layers a host may have to do without (Reply::notes).
enum NoteBits : uint32_t {
  kNoteNotRoot = 1u << 0,          ///< not started as root: kept the caller's uid
  kNoteNoNamespaces = 1u << 1,     ///< unshare(user|net|ipc|uts) refused
  kNoteNoAslrOff = 1u << 2,        ///< could not turn address randomisation off
  kNoteSanitized = 1u << 3,        ///< a sanitizer build: no RLIMIT_AS, no allocation guard
  kNoteNoCloseRange = 1u << 4,     ///< close_range missing: descriptors closed one by one
  kNoteNoLandlock = 1u << 5,       ///< Landlock missing: the loader's opens are not confined to the library's folders
};

/// Exit statuses of the host that mean something (the parent prefers the
/// fault frame the host sends before them).
inline constexpr int kExitUsage = 64;
inline constexpr int kExitFaultReported = 70;
inline constexpr int kExitParentGone = 71;

}  // namespace syrof::app_host::protocol
