#include "syrof/firmware/robot/config_block.h"

#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <cstring>

#include "syrof/wire/member_set.h"

namespace syrof::firmware::robot {

static_assert(kConfigBlockMaxSwarmSize <= wire::kMaxSwarmSize, "a block's swarm must fit the image's member sets");

namespace {

constexpr size_t kMagicOffset = 0;
constexpr size_t kVersionOffset = 4;
constexpr size_t kLengthOffset = 6;
constexpr size_t kScenarioOffset = 8;
constexpr size_t kChecksumOffset = 16;
constexpr size_t kCheckedHeaderBytes = kChecksumOffset;  // the checksum covers the fields before it

// A word of the block longer than these is no word the image takes.
constexpr size_t kMaxKeyBytes = 15;
constexpr size_t kMaxValueBytes = 127;

void PutLittleEndian(std::span<uint8_t> out, size_t offset, uint64_t value, size_t bytes) {
  for (size_t i = 0; i < bytes; ++i) out[offset + i] = static_cast<uint8_t>(value >> (8 * i));
}

uint64_t GetLittleEndian(std::span<const uint8_t> in, size_t offset, size_t bytes) {
  uint64_t value = 0;
  for (size_t i = 0; i < bytes; ++i) value |= uint64_t{in[offset + i]} << (8 * i);
  return value;
}

// CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320), bit by bit: 1 KB
// once at boot needs no table.
uint32_t BlockCrc32(uint32_t crc, std::span<const uint8_t> bytes) {
  crc = ~crc;
  for (const uint8_t byte : bytes) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

// The whole of `text` as a decimal number at most `most`.
bool DecimalWord(const char* text, uint32_t most, uint32_t& value) {
  value = 0;
  if (*text == '\0') return false;
  for (; *text != '\0'; ++text) {
    if (*text < '0' || *text > '9') return false;
    const uint64_t next = uint64_t{value} * 10 + static_cast<uint64_t>(*text - '0');
    if (next > most) return false;
    value = static_cast<uint32_t>(next);
  }
  return true;
}

}  // namespace

const char* ToString(ConfigBlockError error) {
  switch (error) {
    case ConfigBlockError::kOk: return "Ok";
    case ConfigBlockError::kRobotOutOfRange: return "RobotOutOfRange";
    case ConfigBlockError::kTooManyInputs: return "TooManyInputs";
    case ConfigBlockError::kInvalidInput: return "InvalidInput";
    case ConfigBlockError::kDoesNotFit: return "DoesNotFit";
    case ConfigBlockError::kNoSuchKind: return "NoSuchKind";
  }
  return "?";
}

void FormatScenarioId(uint64_t id, std::span<char, 17> out) {
  constexpr char kDigits[] = "0123456789abcdef";
  for (int i = 0; i < 16; ++i) out[static_cast<size_t>(i)] = kDigits[(id >> (60 - 4 * i)) & 0xf];
  out[16] = '\0';
}

uint32_t ConfigBlockChecksum(std::span<const uint8_t, kConfigBlockBytes> block, size_t words_length) {
  const uint32_t header = BlockCrc32(0, block.subspan(0, kCheckedHeaderBytes));
  return BlockCrc32(header, block.subspan(kConfigBlockHeaderBytes, words_length));
}

ConfigBlockError EncodeConfigBlock(const ConfigBlockContent& content, std::span<uint8_t, kConfigBlockBytes> out,
                                   size_t& words_length) {
  std::memset(out.data(), 0, out.size());
  words_length = 0;
  if (content.swarm_size < 1 || content.swarm_size > kConfigBlockMaxSwarmSize || content.robot_id >= content.swarm_size) {
    return ConfigBlockError::kRobotOutOfRange;
  }
  // One byte more than the words may take: the zero after them.
  auto* words = reinterpret_cast<char*>(out.data() + kConfigBlockHeaderBytes);
  const size_t room = kConfigBlockMaxWordsBytes + 1;
  const int head = std::snprintf(words, room, "id %u swarm %u", static_cast<unsigned>(content.robot_id),
                                 static_cast<unsigned>(content.swarm_size));
  size_t length = static_cast<size_t>(head);
  const KindSet swarm_kinds = content.swarm_kinds == 0 ? KindBit(content.kind) : content.swarm_kinds;
  size_t kind_length = 0;
  if (!content.member_kinds.empty() &&
      (content.member_kinds.size() != content.swarm_size || content.member_kinds[content.robot_id] != content.kind)) {
    std::memset(out.data(), 0, out.size());
    return ConfigBlockError::kNoSuchKind;
  }
  switch (FormatKindWords(content.kind, swarm_kinds, content.member_kinds,
                          std::span<char>(words + length, room - length), kind_length)) {
    case BootWordsError::kOk: break;
    case BootWordsError::kBufferTooSmall: std::memset(out.data(), 0, out.size()); return ConfigBlockError::kDoesNotFit;
    default: std::memset(out.data(), 0, out.size()); return ConfigBlockError::kNoSuchKind;
  }
  length += kind_length;
  size_t inputs_length = 0;
  switch (FormatInputWords(content.robot_id, content.inputs, std::span<char>(words + length, room - length),
                           inputs_length)) {
    case BootWordsError::kOk: break;
    case BootWordsError::kTooManyInputs: std::memset(out.data(), 0, out.size()); return ConfigBlockError::kTooManyInputs;
    case BootWordsError::kBufferTooSmall: std::memset(out.data(), 0, out.size()); return ConfigBlockError::kDoesNotFit;
    default: std::memset(out.data(), 0, out.size()); return ConfigBlockError::kInvalidInput;
  }
  length += inputs_length;
  PutLittleEndian(out, kMagicOffset, kConfigBlockMagic, 4);
  PutLittleEndian(out, kVersionOffset, kConfigBlockVersion, 2);
  PutLittleEndian(out, kLengthOffset, length, 2);
  PutLittleEndian(out, kScenarioOffset, content.scenario_id, 8);
  PutLittleEndian(out, kChecksumOffset, ConfigBlockChecksum(out, length), 4);
  words_length = length;
  return ConfigBlockError::kOk;
}

ConfigBlockState BootConfigBlock::Refuse(const char* format, ...) {
  va_list arguments;
  va_start(arguments, format);
  std::vsnprintf(message_.data(), message_.size(), format, arguments);
  va_end(arguments);
  return ConfigBlockState::kRefused;
}

ConfigBlockState BootConfigBlock::ReadWord(const char* key, const char* value, unsigned index) {
  uint32_t number = 0;
  if (std::strcmp(key, "id") == 0 || std::strcmp(key, "swarm") == 0) {
    const bool id = key[0] == 'i';
    if ((id ? has_id_ : has_swarm_) ||
        !DecimalWord(value, id ? kConfigBlockMaxSwarmSize - 1u : kConfigBlockMaxSwarmSize, number) ||
        (!id && number == 0)) {
      return Refuse("the configuration block's word %u '%s': '%s' is not a value it takes (id 0..%u, swarm 1..%u, "
                    "each once)",
                    index, key, value, static_cast<unsigned>(kConfigBlockMaxSwarmSize - 1),
                    static_cast<unsigned>(kConfigBlockMaxSwarmSize));
    }
    (id ? has_id_ : has_swarm_) = true;
    (id ? robot_id_ : swarm_size_) = static_cast<uint16_t>(number);
    return ConfigBlockState::kFilled;
  }
  if (std::strcmp(key, "kind") == 0 || std::strcmp(key, "swarm_kinds") == 0 || std::strcmp(key, "member_kinds") == 0) {
    bool& given = key[0] == 'k' ? has_kind_ : key[0] == 's' ? has_swarm_kinds_ : has_member_kinds_;
    if (given || kind_.Read(key, value) != BootWordRead::kOk) {
      return Refuse("the configuration block's word %u '%s': '%s' is not a value it takes (a robot kind this image "
                    "knows: omni, rover or drone; swarm_kinds lists them, each once; member_kinds a letter o, r or "
                    "d for each robot; each word once)",
                    index, key, value);
    }
    given = true;
    return ConfigBlockState::kFilled;
  }
  switch (inputs_.Read(key, value)) {
    case BootWordRead::kOk: return ConfigBlockState::kFilled;
    case BootWordRead::kNotMine:
      return Refuse("the configuration block's word %u: unknown key '%s' (id, swarm, kind, swarm_kinds, member_kinds, "
                    "inputs, input)",
                    index - 1, key);
    case BootWordRead::kBadValue:
    case BootWordRead::kFull: break;
  }
  return Refuse("the configuration block's word %u '%s': '%s' is not a value it takes (inputs ID:N first, then N "
                "input NAME=VALUE, each name once, each value a finite number)",
                index, key, value);
}

ConfigBlockState BootConfigBlock::Read(std::span<const uint8_t, kConfigBlockBytes> block) {
  if (read_) return Refuse("the configuration block was read twice");
  read_ = true;
  bool empty = true;
  for (const uint8_t byte : block) empty = empty && byte == 0;
  if (empty) return ConfigBlockState::kEmpty;

  const auto magic = static_cast<uint32_t>(GetLittleEndian(block, kMagicOffset, 4));
  if (magic != kConfigBlockMagic) {
    return Refuse("the configuration block is not empty and its magic is 0x%08" PRIx32 ", not 0x%08" PRIx32
                  " (damaged, or not written by syrof-firmware-config)",
                  magic, kConfigBlockMagic);
  }
  const auto version = static_cast<unsigned>(GetLittleEndian(block, kVersionOffset, 2));
  if (version != kConfigBlockVersion) {
    return Refuse("the configuration block is format version %u; this image reads version %u (write it again with "
                  "this image's syrof-firmware-config)",
                  version, static_cast<unsigned>(kConfigBlockVersion));
  }
  const auto length = static_cast<size_t>(GetLittleEndian(block, kLengthOffset, 2));
  if (length > kConfigBlockMaxWordsBytes) {
    return Refuse("the configuration block's words take %u bytes; at most %u fit", static_cast<unsigned>(length),
                  static_cast<unsigned>(kConfigBlockMaxWordsBytes));
  }
  const auto stored = static_cast<uint32_t>(GetLittleEndian(block, kChecksumOffset, 4));
  const uint32_t computed = ConfigBlockChecksum(block, length);
  if (stored != computed) {
    return Refuse("the configuration block's checksum is 0x%08" PRIx32 " but its contents give 0x%08" PRIx32
                  " (the block is damaged: write it again)",
                  stored, computed);
  }
  scenario_id_ = GetLittleEndian(block, kScenarioOffset, 8);

  // The words: `key value` pairs, one space between words.
  const auto* words = reinterpret_cast<const char*>(block.data() + kConfigBlockHeaderBytes);
  // The words' zero and every byte after it, to the end, are zeros.
  for (size_t at = kConfigBlockHeaderBytes + length; at < kConfigBlockBytes; ++at) {
    if (block[at] != 0) {
      return Refuse("the configuration block's byte %u, after its words, is 0x%02x, not 0 (the block is damaged: "
                    "write it again)",
                    static_cast<unsigned>(at), static_cast<unsigned>(block[at]));
    }
  }
  std::array<char, kMaxKeyBytes + 1> key{};
  std::array<char, kMaxValueBytes + 1> value{};
  unsigned index = 0;
  for (size_t at = 0; at < length;) {
    // Two words: the key, then its value.
    for (int part = 0; part < 2; ++part) {
      char* const text = part == 0 ? key.data() : value.data();
      const size_t most = part == 0 ? kMaxKeyBytes : kMaxValueBytes;
      ++index;
      size_t used = 0;
      while (at < length && words[at] != ' ') {
        const char c = words[at];
        if (c < '!' || c > '~') {
          return Refuse("the configuration block's word %u holds the byte 0x%02x (printable words only)", index,
                        static_cast<unsigned>(static_cast<uint8_t>(c)));
        }
        if (used == most) return Refuse("the configuration block's word %u is longer than %u bytes", index,
                                        static_cast<unsigned>(most));
        text[used++] = c;
        ++at;
      }
      text[used] = '\0';
      if (used == 0) return Refuse("the configuration block's word %u is empty (two spaces, or a space at an end)", index);
      if (part == 0 && at == length) return Refuse("the configuration block's word %u '%s' has no value", index, text);
      if (at < length) ++at;  // the space
      if (at == length && words[at - 1] == ' ') {
        return Refuse("the configuration block's words end with a space");
      }
    }
    if (ReadWord(key.data(), value.data(), index) == ConfigBlockState::kRefused) return ConfigBlockState::kRefused;
  }
  if (!has_id_ || !has_swarm_) {
    return Refuse("the configuration block gives no %s", has_id_ ? "swarm" : "id");
  }
  if (robot_id_ >= swarm_size_) {
    return Refuse("the configuration block's id %u is not below its swarm %u", static_cast<unsigned>(robot_id_),
                  static_cast<unsigned>(swarm_size_));
  }
  if (const char* error = kind_.Check()) return Refuse("the configuration block: %s", error);
  if (has_member_kinds_ && kind_.members().size() != swarm_size_) {
    return Refuse("the configuration block's member_kinds names %u robots; its swarm has %u",
                  static_cast<unsigned>(kind_.members().size()), static_cast<unsigned>(swarm_size_));
  }
  if (has_member_kinds_ && kind_.members()[robot_id_] != kind_.self()) {
    return Refuse("the configuration block's member_kinds gives robot %u the kind %s; its kind word says %s",
                  static_cast<unsigned>(robot_id_), motion::ToString(kind_.members()[robot_id_]),
                  motion::ToString(kind_.self()));
  }
  if (!has_member_kinds_ && (kind_.swarm() & (kind_.swarm() - 1)) != 0) {
    return Refuse("the configuration block names a swarm of more than one kind and no member_kinds (write it again "
                  "with this image's syrof-firmware-config)");
  }
  if (const char* error = inputs_.Check(robot_id_)) return Refuse("the configuration block: %s", error);
  return ConfigBlockState::kFilled;
}

}  // namespace syrof::firmware::robot
