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
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/sync/activation.h"

namespace syrof::firmware::robot {

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

}  // namespace syrof::firmware::robot
