// The robot image's boot words for the activation model: how
// syrof-firmware-swarm tells each mps2-an386 image a scenario's
// `activation:` (sync/activation.h, docs/activation.md) on qemu's -append
// (mps2_an386_main.cpp), beside `id`, `swarm` and the start pose. The host
// formats them (FormatActivationWords); the image reads them back one key
// and value at a time (BootActivation::Read) into fixed storage, and hands
// config() to the robot. No allocation either way.
//
//   activation ssync|async          absent: fsync, every member every epoch
//   schedule random|round_robin|scripted
//   seed N                          decimal, 0 .. 2^64 - 1 (the scenario's seed)
//   fair_within N                   ssync random: 1 .. 65535
//   active E:MASK,E:MASK,...        ssync scripted: an epoch (decimal) and the
//                                   robots active in it (hex bit mask, bit i
//                                   robot i), epochs increasing
//   max_delay N                     async: 1 .. sync::kMaxAsyncDelayEpochs
//   min_move_mm N                   async: 0 (rigid) .. 30000
//   cycles E:R:D:M:C,...            async scripted: epoch, robot, start delay,
//                                   move epochs, cut 0|1; sorted by epoch, robot
//
// A FSYNC config gives no words, so a FSYNC image boots with the line it
// always had.
//
// The robot's private inputs (the scenario's `inputs:`, its own value of
// each; syrofAppInput) are words of the same line (FormatInputWords,
// BootInputs), only the robot's own:
//
//   inputs ID:N                     written for robot ID, N inputs follow
//   input NAME=VALUE                N times: a name as the scenario's (a
//                                   letter or _, then letters, digits, _;
//                                   at most 63 bytes), a finite decimal
//                                   number that reads back to the same double
//
// No `inputs` word: the robot has no inputs (syrofAppInput answers
// SYROF_APP_NO_SUCH_INPUT, as in the lab for a scenario without them).
//
// The robot's kind and the kinds of its swarm (a scenario's robots' `kind:`;
// FormatKindWords, BootKind), which pick its motion layer
// (runtime::ConfigureKinds: the kind's controller, the safety filter's view
// of the swarm's kinds, a drone's estimator at its flight height), with the
// kinds' default limits compiled in (motion::DefaultKindLimits):
//
//   kind omni|rover|drone           absent: omni
//   swarm_kinds K,K,...             the kinds in the swarm, each once, the
//                                   robot's own among them; absent: the
//                                   robot's own kind alone
//   member_kinds LLL...             every robot's kind by id, a letter each
//                                   (o omni, r rover, d drone; at most
//                                   kMaxBootMemberKinds): what the app reads
//                                   as its members' kinds (syrof_member_state's
//                                   kind). Needed when swarm_kinds names more
//                                   than one kind (a robot is refused without
//                                   it); absent in a swarm of one kind, every
//                                   robot is of that kind. Its letters are
//                                   swarm_kinds' kinds, and the robot's own
//                                   letter its kind word's
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/app.h"
#include "syrof/app/app.h"
#include "syrof/motion/robot_kind.h"
#include "syrof/runtime/robot.h"
#include "syrof/sync/activation.h"

namespace syrof::firmware::robot {

/// The most robots a member_kinds word names (the images' swarm size).
inline constexpr size_t kMaxBootMemberKinds = 32;
/// The most (epoch, robot) pairs of an SSYNC script the image holds.
inline constexpr size_t kMaxBootScriptedActivations = 256;
/// The most ASYNC scripted cycles the image holds.
inline constexpr size_t kMaxBootScriptedCycles = 64;
/// The mps2-an386 image reads at most this many bytes of qemu's command
/// line (the image's path, a space, then -append's text; the board's
/// semihosting buffer holds one more for the terminating zero) ...
inline constexpr size_t kMaxBootLineBytes = 1023;
/// ... split into at most this many words (the path is the first).
inline constexpr size_t kMaxBootLineWords = 64;

/// Why FormatActivationWords could not write the words.
enum class [[nodiscard]] BootWordsError : uint8_t {
  kOk = 0,
  kTooManyScripted,  ///< more than kMaxBootScriptedActivations pairs
  kTooManyCycles,    ///< more than kMaxBootScriptedCycles cycles
  kRobotOutOfRange,  ///< a scripted robot id at or above 32 (a mask's width)
  kInvalid,          ///< sync::IsValid refused the config
  kBufferTooSmall,   ///< `out` is too short
  kTooManyInputs,    ///< more than kMaxBootInputs private inputs
  kNoSuchKind,       ///< a robot kind the image does not know, or the robot's own kind not among its swarm's
};

const char* ToString(BootWordsError error);

/// Writes `config`'s words into `out`, each word preceded by a space (so
/// they append to a line), and sets `length`; FSYNC writes nothing. The
/// words read back (BootActivation) into the same config.
BootWordsError FormatActivationWords(const sync::ActivationConfig& config, std::span<char> out, size_t& length);

/// What BootActivation::Read made of one key and its value.
enum class BootWordRead : uint8_t {
  kNotMine = 0,  ///< not an activation key: the caller's
  kOk,           ///< read
  kBadValue,     ///< an activation key with a value out of range or malformed
  kFull,         ///< a script longer than the image holds
};

/// The activation the image boots with: the config and its scripts' storage.
class BootActivation {
 public:
  BootActivation() = default;
  // config() points into this object: not copied or moved.
  BootActivation(const BootActivation&) = delete;
  BootActivation& operator=(const BootActivation&) = delete;

  /// Reads one boot word pair (`key`, `value`, zero-terminated).
  BootWordRead Read(const char* key, const char* value);
  /// The config read so far (its scripts point into this object). Check it
  /// with sync::IsValid once every word is read.
  sync::ActivationConfig config() const;

 private:
  sync::ActivationConfig config_{};
  std::array<sync::ScriptedActivation, kMaxBootScriptedActivations> script_{};
  size_t script_size_ = 0;
  std::array<sync::ScriptedCycle, kMaxBootScriptedCycles> cycles_{};
  size_t cycles_size_ = 0;
};

/// The most private inputs the image holds: as many as a scenario gives.
inline constexpr size_t kMaxBootInputs = SYROF_APP_MAX_INPUTS;
/// The longest input name the image holds (bytes, without the zero).
inline constexpr size_t kMaxBootInputNameBytes = SYROF_APP_MAX_PARAMETER_NAME_LENGTH;

/// Writes robot `id`'s `inputs` as words into `out` (each preceded by a
/// space) and sets `length`; no inputs write nothing. kTooManyInputs for
/// more than kMaxBootInputs, kInvalid for a name the image does not take
/// or a value that is not finite, kBufferTooSmall when `out` is too short.
BootWordsError FormatInputWords(uint16_t id, std::span<const app::Parameter> inputs, std::span<char> out,
                                size_t& length);

/// The private inputs the image boots with: their names and values in
/// fixed storage, and the table syrofAppInput reads.
class BootInputs {
 public:
  BootInputs() = default;
  // inputs() points into this object: not copied or moved.
  BootInputs(const BootInputs&) = delete;
  BootInputs& operator=(const BootInputs&) = delete;

  /// Reads one boot word pair (`key`, `value`, zero-terminated): kNotMine
  /// for another key, kBadValue for a malformed value, an `input` before
  /// `inputs`, a name given twice or more inputs than `inputs` announced.
  BootWordRead Read(const char* key, const char* value);
  /// Once every word is read: nullptr when the inputs are whole and were
  /// written for `self_id`, else why not (a line for the robot's report).
  const char* Check(uint16_t self_id);
  /// The inputs read (names point into this object).
  std::span<const app::Parameter> inputs() const { return {table_.data(), size_}; }

 private:
  bool announced_ = false;
  uint16_t for_id_ = 0;
  size_t expected_ = 0;
  size_t size_ = 0;
  std::array<std::array<char, kMaxBootInputNameBytes + 1>, kMaxBootInputs> names_{};
  std::array<app::Parameter, kMaxBootInputs> table_{};
  std::array<char, 112> message_{};
};

/// A set of robot kinds: bit i for motion::RobotKind i.
using KindSet = uint8_t;
inline constexpr KindSet KindBit(motion::RobotKind kind) {
  return static_cast<KindSet>(1u << static_cast<unsigned>(kind));
}

/// Writes the words of robot kind `self` in a swarm of the kinds `swarm` into
/// `out` (each word preceded by a space) and sets `length`: nothing for an
/// omni robot among omni robots (the line every image had before), `kind K`
/// when `swarm` is `self` alone, else `kind K swarm_kinds K,K,...` in
/// RobotKind's order, then `member_kinds` (every robot's kind by id) as a
/// member_kinds word when `swarm` has more than one kind. kNoSuchKind for a
/// kind the image does not know, `self` not in `swarm`, or a mixed swarm's
/// member_kinds empty, longer than kMaxBootMemberKinds or naming a kind not
/// in `swarm`; kBufferTooSmall when `out` is too short.
BootWordsError FormatKindWords(motion::RobotKind self, KindSet swarm, std::span<const motion::RobotKind> member_kinds,
                               std::span<char> out, size_t& length);

/// The kinds the image boots with.
class BootKind {
 public:
  /// Reads one boot word pair (`key`, `value`, zero-terminated): kNotMine
  /// for another key, kBadValue for a kind the image does not know, a
  /// swarm_kinds list with one twice or none, or a member_kinds word with a
  /// letter other than o, r, d, none, or more than kMaxBootMemberKinds.
  BootWordRead Read(const char* key, const char* value);
  /// Once every word is read: nullptr, or why the kinds cannot run (the
  /// robot's kind not among swarm_kinds; member_kinds naming a kind
  /// swarm_kinds does not; a line for the robot's report).
  const char* Check();
  motion::RobotKind self() const { return self_; }
  /// The swarm's kinds (swarm_kinds; without it, member_kinds' kinds, or the
  /// robot's own alone).
  KindSet swarm() const;
  /// member_kinds' kinds by id; empty when the word was not given.
  std::span<const motion::RobotKind> members() const { return {members_.data(), member_count_}; }

 private:
  motion::RobotKind self_ = motion::RobotKind::kOmni;
  KindSet swarm_ = 0;
  std::array<motion::RobotKind, kMaxBootMemberKinds> members_{};
  size_t member_count_ = 0;
  std::array<char, 112> message_{};
};

/// The robot image's motion layer for a robot of kind `self` in a swarm of
/// the kinds `swarm` (0: `self` alone), with the kinds' default limits
/// compiled in (motion::DefaultKindLimits), set in `config` as the lab sets
/// its robot's (runtime::ConfigureKinds), and the safety filter's walls at
/// the estimator's arena (the image's; the lab's are the scenario's).
/// `config.member_kinds` views `storage`, filled from `members` (every
/// robot's kind by id, config.sync.swarm_size of them, the robot's own
/// `self`) or, when `members` is empty and the swarm is of one kind, with
/// that kind. nullptr, or why not (an unknown kind, `self` not in `swarm`,
/// a mixed swarm without `members`, `members` of another length, another
/// kind for the robot itself, or a kind not in `swarm`); `storage` must
/// outlive the robot and hold the swarm.
const char* ConfigureImageKinds(runtime::RobotConfig& config, motion::RobotKind self, KindSet swarm,
                                std::span<const motion::RobotKind> members, std::span<motion::RobotKind> storage);

}  // namespace syrof::firmware::robot
