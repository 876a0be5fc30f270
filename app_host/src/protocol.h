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

/// The fork server (docs/app_host.md "The fork server"). A host started in
/// `hold` mode loads the library, checks what its constructors left, and
/// says in its hello's notes whether copies of it would start clean: any
/// of these bits means they would not, and the parent starts a fresh host
/// per robot instead. Without them it holds the loaded library and makes
/// one copy per ForkRequest.
enum HoldBits : uint32_t {
  kHoldOpenDescriptor = 1u << 16,     ///< a descriptor past 3 is open (a file the copies would share, offset and all)
  kHoldSharedMapping = 1u << 17,      ///< a MAP_SHARED mapping (the copies would see each other's writes)
  kHoldPendingSignal = 1u << 18,      ///< a signal is pending (a fork clears it; a fresh host would have it)
  kHoldStandardDescriptors = 1u << 19,  ///< descriptors 0-3 are not the ones the host was given
  kHoldUnchecked = 1u << 20,          ///< the host could not check (no /proc/self/maps)
  kHoldNoSignalScope = 1u << 21,      ///< no Landlock signal scope (ABI 6): the host did not load the library
};
inline constexpr uint32_t kHoldNotClean = kHoldOpenDescriptor | kHoldSharedMapping | kHoldPendingSignal |
                                          kHoldStandardDescriptors | kHoldUnchecked | kHoldNoSignalScope;

/// Parent to held host: make a copy. Sent with two descriptors
/// (SCM_RIGHTS): the copy's channel (its descriptor 3) and its output pipe
/// (1 and 2).
inline constexpr uint32_t kForkMagic = 0x53464f52;  // "SFOR"
struct ForkRequest {
  uint32_t magic = kForkMagic;
};
/// Held host to parent: the copy's pid (a child of the parent: the copy is
/// made with CLONE_PARENT), or the errno of a refused clone.
struct ForkReply {
  uint32_t magic = kForkMagic;
  int32_t pid = 0;
  int32_t error = 0;
};
/// The only clone a held host's loader filter lets through: a copy whose
/// parent is the host's parent. glibc's fork, vfork, posix_spawn and
/// pthread_create never pass exactly this; a constructor that makes it
/// itself leaves a process in the held host's process group, which the
/// parent finds after the load (and then holds nothing).
inline constexpr unsigned long kCopyCloneFlags = 0x00008000;  // CLONE_PARENT

/// Exit statuses of the host that mean something (the parent prefers the
/// fault frame the host sends before them).
inline constexpr int kExitUsage = 64;
inline constexpr int kExitFaultReported = 70;
inline constexpr int kExitParentGone = 71;

}  // namespace syrof::app_host::protocol
