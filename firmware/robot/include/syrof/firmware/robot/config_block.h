// The robot image's configuration block: what a robot is told at flash time
// (docs/firmware.md, "The configuration block"; docs/demo-day.md). A
// fixed-size region in its own linker section (`.syrof_config`, right after
// the vector table in both images' linker scripts), all zeros as built; the
// host tool syrof-firmware-config (firmware/config) fills one robot's copy of
// a built image from a scenario: its id, the swarm's size, its kind, its
// swarm's kinds and every robot's, and its own private inputs, as the same words the
// mps2-an386 image reads on its boot line (boot_words.h), with a magic, a
// format version, the scenario's identifier and a checksum:
//
//   offset  bytes  field
//   0       4      magic 0x46435953 (the bytes "SYCF")
//   4       2      format version, 1
//   6       2      the words' length N (bytes, without the zero after them)
//   8       8      scenario id (syrof-firmware-config's hash of the scenario's
//                  name, robot count and every robot's inputs)
//   16      4      CRC-32 (IEEE 802.3) of bytes 0-15 and the N words' bytes
//   20      1004   the words, a zero, zeros to the end
//
// Every field is little-endian. The words: `id N swarm N`, then the kind's
// words as the emulated swarm's host writes them (FormatKindWords: `kind K`
// and, in a mixed swarm, `swarm_kinds K,K,... member_kinds LLL...`; none for
// an omni robot among omni robots), then
// the inputs' words (`inputs ID:N`, N times `input NAME=VALUE`; none without
// inputs).
// At boot the image reads the block (BootConfigBlock::Read): all zeros is
// "empty" (no flash-time configuration: the image's own id, no inputs); a
// filled block is checked (magic, version, length, checksum, every word) and
// one that fails is refused with a line naming why, never a silent default.
// No allocation either way; encoding runs on the host and in tests.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/app/app.h"
#include "syrof/firmware/robot/boot_words.h"

namespace syrof::firmware::robot {

/// The block's size in bytes, and its layout (the table above).
inline constexpr size_t kConfigBlockBytes = 1024;
inline constexpr uint32_t kConfigBlockMagic = 0x46435953;  // "SYCF" in memory order
inline constexpr uint16_t kConfigBlockVersion = 1;
inline constexpr size_t kConfigBlockHeaderBytes = 20;
/// The most bytes of words a block holds (a zero follows them).
inline constexpr size_t kConfigBlockMaxWordsBytes = kConfigBlockBytes - kConfigBlockHeaderBytes - 1;
/// The largest swarm a block says: the robot images' SYROF_MAX_SWARM_SIZE
/// (the Teensy's 32), whatever the host's.
inline constexpr uint16_t kConfigBlockMaxSwarmSize = 32;
/// The linker section the images keep the block in.
inline constexpr const char* kConfigBlockSection = ".syrof_config";

/// What one robot is told at flash time.
struct ConfigBlockContent {
  uint16_t robot_id = 0;
  uint16_t swarm_size = 0;
  uint64_t scenario_id = 0;
  std::span<const app::Parameter> inputs{};  ///< this robot's own values only
  motion::RobotKind kind = motion::RobotKind::kOmni;
  KindSet swarm_kinds = 0;  ///< the swarm's kinds (KindBit); 0: `kind` alone
  /// Every robot's kind by id (swarm_size of them): written as member_kinds
  /// when the swarm has more than one kind, and then needed.
  std::span<const motion::RobotKind> member_kinds{};
};

/// Why EncodeConfigBlock wrote no block.
enum class [[nodiscard]] ConfigBlockError : uint8_t {
  kOk = 0,
  kRobotOutOfRange,  ///< swarm size not 1..kConfigBlockMaxSwarmSize, or the id not below it
  kTooManyInputs,    ///< more than kMaxBootInputs
  kInvalidInput,     ///< a name the image does not take, a name twice, or a value that is not finite
  kDoesNotFit,       ///< the words are longer than kConfigBlockMaxWordsBytes
  kNoSuchKind,       ///< a kind the image does not know, `kind` not among `swarm_kinds`, or a mixed swarm's
                     ///< member_kinds missing, of another length than the swarm or naming another kind for the robot
};

const char* ToString(ConfigBlockError error);

/// Writes `content` as a whole block into `out` (every byte of it) and sets
/// `words_length`; on an error `out` is all zeros.
ConfigBlockError EncodeConfigBlock(const ConfigBlockContent& content, std::span<uint8_t, kConfigBlockBytes> out,
                                   size_t& words_length);

/// The CRC-32 the block's checksum field holds: of bytes 0-15 and the
/// `words_length` bytes of words (words_length at most kConfigBlockMaxWordsBytes).
uint32_t ConfigBlockChecksum(std::span<const uint8_t, kConfigBlockBytes> block, size_t words_length);

/// `id` as 16 lower-case hex digits and a zero: how the tool and the
/// robot's console show a scenario id (without printf's 64-bit formats,
/// which newlib-nano lacks).
void FormatScenarioId(uint64_t id, std::span<char, 17> out);

/// What BootConfigBlock::Read found.
enum class ConfigBlockState : uint8_t {
  kEmpty = 0,  ///< all zeros: no flash-time configuration
  kFilled,     ///< read and checked: robot_id(), swarm_size(), inputs()
  kRefused,    ///< damaged or not a block this image reads: error() says why
};

/// The configuration block as the image reads it at boot, into fixed storage.
class BootConfigBlock {
 public:
  BootConfigBlock() = default;
  // inputs() points into this object: not copied or moved.
  BootConfigBlock(const BootConfigBlock&) = delete;
  BootConfigBlock& operator=(const BootConfigBlock&) = delete;

  /// Reads `block` once (a second call is a caller's bug and is refused).
  ConfigBlockState Read(std::span<const uint8_t, kConfigBlockBytes> block);
  /// After kRefused: why, as a line for the robot's report (no newline).
  const char* error() const { return message_.data(); }
  uint16_t robot_id() const { return robot_id_; }
  uint16_t swarm_size() const { return swarm_size_; }
  uint64_t scenario_id() const { return scenario_id_; }
  std::span<const app::Parameter> inputs() const { return inputs_.inputs(); }
  /// The robot's kind (omni when the block names none) and its swarm's
  /// kinds (its own alone when the block names none).
  motion::RobotKind kind() const { return kind_.self(); }
  KindSet swarm_kinds() const { return kind_.swarm(); }
  /// Every robot's kind by id (the block's member_kinds; empty in a swarm
  /// of one kind, which writes none).
  std::span<const motion::RobotKind> member_kinds() const { return kind_.members(); }

 private:
  ConfigBlockState Refuse(const char* format, ...) __attribute__((format(printf, 2, 3)));
  ConfigBlockState ReadWord(const char* key, const char* value, unsigned index);

  bool read_ = false;
  bool has_id_ = false;
  bool has_swarm_ = false;
  uint16_t robot_id_ = 0;
  uint16_t swarm_size_ = 0;
  uint64_t scenario_id_ = 0;
  BootInputs inputs_;
  BootKind kind_;
  bool has_kind_ = false;
  bool has_swarm_kinds_ = false;
  bool has_member_kinds_ = false;
  std::array<char, 320> message_{};  // the longest refusal quotes a 127-byte word
};

}  // namespace syrof::firmware::robot
