#include "syrof/firmware/robot/boot_words.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "syrof/runtime/robot_kinds.h"

namespace syrof::firmware::robot {

namespace {

constexpr uint32_t kMaxMinMoveMm = 30000;
constexpr uint16_t kMaskWidth = 32;

// Writes into `out` after `used`; false once it no longer fits.
class Writer {
 public:
  explicit Writer(std::span<char> out) : out_(out) {}
  template <typename... Args>
  bool Print(const char* format, Args... args) {
    if (used_ >= out_.size()) return false;
    const int written = std::snprintf(out_.data() + used_, out_.size() - used_, format, args...);
    if (written < 0 || used_ + static_cast<size_t>(written) >= out_.size()) return false;
    used_ += static_cast<size_t>(written);
    return true;
  }
  size_t used() const { return used_; }

 private:
  std::span<char> out_;
  size_t used_ = 0;
};

// Reads a whole number in `base` (10 or 16) from `text`, up to a character
// that is no digit; advances `text` past it. False for no digit, or above `most`.
bool Number(const char*& text, unsigned base, uint64_t most, uint64_t& value) {
  value = 0;
  const char* start = text;
  for (;; ++text) {
    unsigned digit = 0;
    const char c = *text;
    if (c >= '0' && c <= '9') {
      digit = static_cast<unsigned>(c - '0');
    } else if (base == 16 && c >= 'a' && c <= 'f') {
      digit = static_cast<unsigned>(c - 'a' + 10);
    } else {
      break;
    }
    if (digit > most || value > (most - digit) / base) return false;
    value = value * base + digit;
  }
  return text != start;
}

// The whole of `text` as one number.
bool WholeNumber(const char* text, unsigned base, uint64_t most, uint64_t& value) {
  return Number(text, base, most, value) && *text == '\0';
}

// A number followed by `separator`, which it skips.
bool Field(const char*& text, unsigned base, uint64_t most, uint64_t& value, char separator) {
  if (!Number(text, base, most, value)) return false;
  if (*text != separator) return false;
  ++text;
  return true;
}

// A private input's name as the scenario's loader takes it: a letter or
// `_`, then letters, digits and `_`, 1 to kMaxBootInputNameBytes bytes.
bool IsInputName(const char* name, size_t length) {
  if (length == 0 || length > kMaxBootInputNameBytes) return false;
  for (size_t i = 0; i < length; ++i) {
    const char c = name[i];
    const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
    if (!letter && (i == 0 || c < '0' || c > '9')) return false;
  }
  return true;
}

// The whole of `text` as a finite number (strtod: decimal or hex).
bool FiniteNumber(const char* text, double& value) {
  if (*text == '\0') return false;
  char* end = nullptr;
  value = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(value);
}

}  // namespace

const char* ToString(BootWordsError error) {
  switch (error) {
    case BootWordsError::kOk: return "Ok";
    case BootWordsError::kTooManyScripted: return "TooManyScripted";
    case BootWordsError::kTooManyCycles: return "TooManyCycles";
    case BootWordsError::kRobotOutOfRange: return "RobotOutOfRange";
    case BootWordsError::kInvalid: return "Invalid";
    case BootWordsError::kBufferTooSmall: return "BufferTooSmall";
    case BootWordsError::kTooManyInputs: return "TooManyInputs";
    case BootWordsError::kNoSuchKind: return "NoSuchKind";
  }
  return "?";
}

BootWordsError FormatActivationWords(const sync::ActivationConfig& config, std::span<char> out, size_t& length) {
  length = 0;
  if (!sync::IsValid(config)) return BootWordsError::kInvalid;
  if (config.model == sync::ActivationModel::kFsync) {
    if (!out.empty()) out[0] = '\0';
    return out.empty() ? BootWordsError::kBufferTooSmall : BootWordsError::kOk;
  }
  if (config.script.size() > kMaxBootScriptedActivations) return BootWordsError::kTooManyScripted;
  if (config.cycles.size() > kMaxBootScriptedCycles) return BootWordsError::kTooManyCycles;
  Writer writer(out);
  bool fits = writer.Print(" activation %s schedule %s seed %" PRIu64, sync::ToString(config.model),
                           sync::ToString(config.schedule), config.seed);
  if (config.model == sync::ActivationModel::kSsync) {
    if (config.schedule == sync::ActivationSchedule::kRandom) {
      fits = fits && writer.Print(" fair_within %u", static_cast<unsigned>(config.fair_within));
    }
    if (config.schedule == sync::ActivationSchedule::kScripted && !config.script.empty()) {
      fits = fits && writer.Print(" active ");
      // One E:MASK item per epoch (the script is sorted by epoch).
      for (size_t i = 0; i < config.script.size() && fits;) {
        const uint16_t epoch = config.script[i].epoch;
        uint32_t mask = 0;
        for (; i < config.script.size() && config.script[i].epoch == epoch; ++i) {
          if (config.script[i].robot >= kMaskWidth) return BootWordsError::kRobotOutOfRange;
          mask |= uint32_t{1} << config.script[i].robot;
        }
        fits = writer.Print("%u:%" PRIx32, static_cast<unsigned>(epoch), mask) &&
               (i == config.script.size() || writer.Print(","));
      }
    }
  } else {
    if (config.min_move_mm > kMaxMinMoveMm) return BootWordsError::kInvalid;
    fits = fits && writer.Print(" max_delay %u min_move_mm %" PRIu32, static_cast<unsigned>(config.max_delay_epochs),
                                config.min_move_mm);
    if (config.schedule == sync::ActivationSchedule::kScripted && !config.cycles.empty()) {
      fits = fits && writer.Print(" cycles ");
      for (size_t i = 0; i < config.cycles.size() && fits; ++i) {
        const sync::ScriptedCycle& cycle = config.cycles[i];
        if (cycle.robot >= kMaskWidth) return BootWordsError::kRobotOutOfRange;
        fits = writer.Print("%s%u:%u:%u:%u:%u", i == 0 ? "" : ",", static_cast<unsigned>(cycle.epoch),
                            static_cast<unsigned>(cycle.robot), static_cast<unsigned>(cycle.start_delay),
                            static_cast<unsigned>(cycle.move_epochs), cycle.cut ? 1u : 0u);
      }
    }
  }
  if (!fits) return BootWordsError::kBufferTooSmall;
  length = writer.used();
  return BootWordsError::kOk;
}

BootWordRead BootActivation::Read(const char* key, const char* value) {
  uint64_t number = 0;
  if (std::strcmp(key, "activation") == 0) {
    if (std::strcmp(value, "ssync") == 0) {
      config_.model = sync::ActivationModel::kSsync;
    } else if (std::strcmp(value, "async") == 0) {
      config_.model = sync::ActivationModel::kAsync;
    } else if (std::strcmp(value, "fsync") == 0) {
      config_.model = sync::ActivationModel::kFsync;
    } else {
      return BootWordRead::kBadValue;
    }
  } else if (std::strcmp(key, "schedule") == 0) {
    if (std::strcmp(value, "random") == 0) {
      config_.schedule = sync::ActivationSchedule::kRandom;
    } else if (std::strcmp(value, "round_robin") == 0) {
      config_.schedule = sync::ActivationSchedule::kRoundRobin;
    } else if (std::strcmp(value, "scripted") == 0) {
      config_.schedule = sync::ActivationSchedule::kScripted;
    } else {
      return BootWordRead::kBadValue;
    }
  } else if (std::strcmp(key, "seed") == 0) {
    if (!WholeNumber(value, 10, UINT64_MAX, number)) return BootWordRead::kBadValue;
    config_.seed = number;
  } else if (std::strcmp(key, "fair_within") == 0) {
    if (!WholeNumber(value, 10, sync::kMaxFairWithinEpochs, number) || number < 1) return BootWordRead::kBadValue;
    config_.fair_within = static_cast<uint16_t>(number);
  } else if (std::strcmp(key, "max_delay") == 0) {
    if (!WholeNumber(value, 10, sync::kMaxAsyncDelayEpochs, number) || number < 1) return BootWordRead::kBadValue;
    config_.max_delay_epochs = static_cast<uint8_t>(number);
  } else if (std::strcmp(key, "min_move_mm") == 0) {
    if (!WholeNumber(value, 10, kMaxMinMoveMm, number)) return BootWordRead::kBadValue;
    config_.min_move_mm = static_cast<uint32_t>(number);
  } else if (std::strcmp(key, "active") == 0) {
    script_size_ = 0;
    uint64_t previous_epoch = 0;
    for (const char* text = value; *text != '\0';) {
      uint64_t epoch = 0, mask = 0;
      if (!Field(text, 10, UINT16_MAX, epoch, ':') || !Number(text, 16, UINT32_MAX, mask) || mask == 0 ||
          (script_size_ > 0 && epoch <= previous_epoch) || (*text != ',' && *text != '\0')) {
        script_size_ = 0;
        return BootWordRead::kBadValue;
      }
      if (*text == ',') {
        ++text;
        if (*text == '\0') return BootWordRead::kBadValue;
      }
      previous_epoch = epoch;
      for (uint16_t robot = 0; robot < kMaskWidth; ++robot) {
        if ((mask & (uint64_t{1} << robot)) == 0) continue;
        if (script_size_ == script_.size()) {
          script_size_ = 0;
          return BootWordRead::kFull;
        }
        script_[script_size_++] = sync::ScriptedActivation{static_cast<uint16_t>(epoch), robot};
      }
    }
  } else if (std::strcmp(key, "cycles") == 0) {
    cycles_size_ = 0;
    for (const char* text = value; *text != '\0';) {
      uint64_t epoch = 0, robot = 0, delay = 0, move = 0, cut = 0;
      if (!Field(text, 10, UINT16_MAX, epoch, ':') || !Field(text, 10, kMaskWidth - 1, robot, ':') ||
          !Field(text, 10, sync::kMaxAsyncDelayEpochs, delay, ':') ||
          !Field(text, 10, sync::kMaxAsyncDelayEpochs + 1, move, ':') || !Number(text, 10, 1, cut) ||
          (*text != ',' && *text != '\0')) {
        cycles_size_ = 0;
        return BootWordRead::kBadValue;
      }
      if (*text == ',') {
        ++text;
        if (*text == '\0') return BootWordRead::kBadValue;
      }
      if (cycles_size_ == cycles_.size()) {
        cycles_size_ = 0;
        return BootWordRead::kFull;
      }
      cycles_[cycles_size_++] = sync::ScriptedCycle{static_cast<uint16_t>(epoch), static_cast<uint16_t>(robot),
                                                    static_cast<uint8_t>(delay), static_cast<uint8_t>(move), cut == 1};
    }
  } else {
    return BootWordRead::kNotMine;
  }
  return BootWordRead::kOk;
}

sync::ActivationConfig BootActivation::config() const {
  sync::ActivationConfig config = config_;
  config.script = std::span<const sync::ScriptedActivation>(script_.data(), script_size_);
  config.cycles = std::span<const sync::ScriptedCycle>(cycles_.data(), cycles_size_);
  return config;
}

BootWordsError FormatInputWords(uint16_t id, std::span<const app::Parameter> inputs, std::span<char> out,
                                size_t& length) {
  length = 0;
  if (inputs.size() > kMaxBootInputs) return BootWordsError::kTooManyInputs;
  if (out.empty()) return BootWordsError::kBufferTooSmall;
  out[0] = '\0';
  if (inputs.empty()) return BootWordsError::kOk;
  for (size_t i = 0; i < inputs.size(); ++i) {
    if (!IsInputName(inputs[i].name.data(), inputs[i].name.size()) || !std::isfinite(inputs[i].value)) {
      return BootWordsError::kInvalid;
    }
    for (size_t j = 0; j < i; ++j) {
      if (inputs[j].name == inputs[i].name) return BootWordsError::kInvalid;
    }
  }
  Writer writer(out);
  bool fits = writer.Print(" inputs %u:%u", static_cast<unsigned>(id), static_cast<unsigned>(inputs.size()));
  for (const app::Parameter& input : inputs) {
    if (!fits) break;
    // The fewest significant digits (of 15 to 17) that read back to the
    // same double: 0.3 stays "0.3", and every double survives the trip.
    char value[40];
    for (int digits = 15; digits <= 17; ++digits) {
      std::snprintf(value, sizeof value, "%.*g", digits, input.value);
      if (std::strtod(value, nullptr) == input.value) break;
    }
    fits = writer.Print(" input %.*s=%s", static_cast<int>(input.name.size()), input.name.data(), value);
  }
  if (!fits) return BootWordsError::kBufferTooSmall;
  length = writer.used();
  return BootWordsError::kOk;
}

BootWordRead BootInputs::Read(const char* key, const char* value) {
  if (std::strcmp(key, "inputs") == 0) {
    uint64_t id = 0, count = 0;
    const char* text = value;
    if (announced_ || !Field(text, 10, UINT16_MAX, id, ':') || !WholeNumber(text, 10, kMaxBootInputs, count)) {
      return BootWordRead::kBadValue;
    }
    announced_ = true;
    for_id_ = static_cast<uint16_t>(id);
    expected_ = static_cast<size_t>(count);
    return BootWordRead::kOk;
  }
  if (std::strcmp(key, "input") != 0) return BootWordRead::kNotMine;
  const char* equals = std::strchr(value, '=');
  if (!announced_ || equals == nullptr) return BootWordRead::kBadValue;
  const auto name_length = static_cast<size_t>(equals - value);
  double number = 0;
  if (!IsInputName(value, name_length) || !FiniteNumber(equals + 1, number)) return BootWordRead::kBadValue;
  const std::string_view name(value, name_length);
  for (size_t i = 0; i < size_; ++i) {
    if (table_[i].name == name) return BootWordRead::kBadValue;
  }
  if (size_ == expected_) return BootWordRead::kFull;
  std::memcpy(names_[size_].data(), value, name_length);
  names_[size_][name_length] = '\0';
  table_[size_] = app::Parameter{std::string_view(names_[size_].data(), name_length), number};
  ++size_;
  return BootWordRead::kOk;
}

const char* BootInputs::Check(uint16_t self_id) {
  if (!announced_) return nullptr;
  if (for_id_ != self_id) {
    std::snprintf(message_.data(), message_.size(), "the inputs were written for robot %u; this is robot %u",
                  static_cast<unsigned>(for_id_), static_cast<unsigned>(self_id));
    return message_.data();
  }
  if (size_ != expected_) {
    std::snprintf(message_.data(), message_.size(), "inputs %u:%u announced %u inputs; %u came (an input is missing)",
                  static_cast<unsigned>(for_id_), static_cast<unsigned>(expected_), static_cast<unsigned>(expected_),
                  static_cast<unsigned>(size_));
    return message_.data();
  }
  return nullptr;
}

namespace {

constexpr KindSet kAllKinds = static_cast<KindSet>((1u << motion::kRobotKindCount) - 1);

bool IsKind(motion::RobotKind kind) { return static_cast<size_t>(kind) < motion::kRobotKindCount; }

// member_kinds' letter of each kind, in RobotKind's order.
constexpr char kKindLetters[motion::kRobotKindCount + 1] = "ord";

bool KindOfLetter(char letter, motion::RobotKind& kind) {
  for (size_t i = 0; i < motion::kRobotKindCount; ++i) {
    if (kKindLetters[i] == letter) {
      kind = static_cast<motion::RobotKind>(i);
      return true;
    }
  }
  return false;
}

bool SingleKind(KindSet kinds) { return kinds != 0 && (kinds & (kinds - 1)) == 0; }

KindSet KindsOf(std::span<const motion::RobotKind> members) {
  KindSet kinds = 0;
  for (const motion::RobotKind kind : members) kinds = static_cast<KindSet>(kinds | KindBit(kind));
  return kinds;
}

}  // namespace

BootWordsError FormatKindWords(motion::RobotKind self, KindSet swarm, std::span<const motion::RobotKind> member_kinds,
                               std::span<char> out, size_t& length) {
  length = 0;
  if (!IsKind(self) || (swarm & ~kAllKinds) != 0 || (swarm & KindBit(self)) == 0) return BootWordsError::kNoSuchKind;
  const bool mixed = !SingleKind(swarm);
  if (mixed) {
    if (member_kinds.empty() || member_kinds.size() > kMaxBootMemberKinds) return BootWordsError::kNoSuchKind;
    for (const motion::RobotKind kind : member_kinds) {
      if (!IsKind(kind) || (swarm & KindBit(kind)) == 0) return BootWordsError::kNoSuchKind;
    }
  }
  if (out.empty()) return BootWordsError::kBufferTooSmall;
  out[0] = '\0';
  if (self == motion::RobotKind::kOmni && swarm == KindBit(self)) return BootWordsError::kOk;
  Writer writer(out);
  bool fits = writer.Print(" kind %s", motion::ToString(self));
  if (swarm != KindBit(self)) {
    fits = fits && writer.Print(" swarm_kinds ");
    bool first = true;
    for (size_t i = 0; i < motion::kRobotKindCount && fits; ++i) {
      const auto kind = static_cast<motion::RobotKind>(i);
      if ((swarm & KindBit(kind)) == 0) continue;
      fits = writer.Print("%s%s", first ? "" : ",", motion::ToString(kind));
      first = false;
    }
  }
  if (mixed) {
    fits = fits && writer.Print(" member_kinds ");
    for (size_t i = 0; i < member_kinds.size() && fits; ++i) {
      fits = writer.Print("%c", kKindLetters[static_cast<size_t>(member_kinds[i])]);
    }
  }
  if (!fits) return BootWordsError::kBufferTooSmall;
  length = writer.used();
  return BootWordsError::kOk;
}

BootWordRead BootKind::Read(const char* key, const char* value) {
  if (std::strcmp(key, "kind") == 0) {
    return motion::ParseRobotKind(value, self_) ? BootWordRead::kOk : BootWordRead::kBadValue;
  }
  if (std::strcmp(key, "member_kinds") == 0) {
    const size_t count = std::strlen(value);
    if (count == 0 || count > kMaxBootMemberKinds) return BootWordRead::kBadValue;
    for (size_t i = 0; i < count; ++i) {
      if (!KindOfLetter(value[i], members_[i])) return BootWordRead::kBadValue;
    }
    member_count_ = count;
    return BootWordRead::kOk;
  }
  if (std::strcmp(key, "swarm_kinds") != 0) return BootWordRead::kNotMine;
  KindSet kinds = 0;
  for (const char* text = value;;) {
    const char* comma = std::strchr(text, ',');
    const size_t length = comma == nullptr ? std::strlen(text) : static_cast<size_t>(comma - text);
    char name[8];
    motion::RobotKind kind{};
    if (length == 0 || length >= sizeof name) return BootWordRead::kBadValue;
    std::memcpy(name, text, length);
    name[length] = '\0';
    if (!motion::ParseRobotKind(name, kind) || (kinds & KindBit(kind)) != 0) return BootWordRead::kBadValue;
    kinds = static_cast<KindSet>(kinds | KindBit(kind));
    if (comma == nullptr) break;
    text = comma + 1;
  }
  swarm_ = kinds;
  return BootWordRead::kOk;
}

KindSet BootKind::swarm() const {
  if (swarm_ != 0) return swarm_;
  return member_count_ != 0 ? KindsOf(members()) : KindBit(self_);
}

const char* BootKind::Check() {
  if ((swarm() & KindBit(self_)) == 0) {
    std::snprintf(message_.data(), message_.size(), "kind %s is not among its swarm_kinds (a robot is of its swarm)",
                  motion::ToString(self_));
    return message_.data();
  }
  if (swarm_ != 0 && member_count_ != 0 && KindsOf(members()) != swarm_) {
    std::snprintf(message_.data(), message_.size(),
                  "member_kinds names other kinds than swarm_kinds (each of swarm_kinds' kinds, and no other, is "
                  "some robot's)");
    return message_.data();
  }
  return nullptr;
}

const char* ConfigureImageKinds(runtime::RobotConfig& config, motion::RobotKind self, KindSet swarm,
                                std::span<const motion::RobotKind> members, std::span<motion::RobotKind> storage) {
  // Start-up only, one robot an image: the refusal's words are kept here.
  static char message[128];
  const KindSet present = swarm == 0 ? KindBit(self) : swarm;
  if (!IsKind(self) || (present & ~kAllKinds) != 0 || (present & KindBit(self)) == 0) {
    return "the robot's kind is not among its swarm's kinds";
  }
  const size_t swarm_size = config.sync.swarm_size;
  if (swarm_size > storage.size()) return "the swarm is larger than the image's table of its kinds";
  if (members.empty()) {
    if (!SingleKind(present)) {
      return "a swarm of more than one kind needs member_kinds, every robot's kind by id (what its app reads of "
             "its members); syrof-firmware-config and syrof-firmware-swarm write it";
    }
    for (size_t id = 0; id < swarm_size; ++id) storage[id] = self;
  } else {
    if (members.size() != swarm_size) {
      std::snprintf(message, sizeof message, "member_kinds names %u robots; the swarm has %u",
                    static_cast<unsigned>(members.size()), static_cast<unsigned>(swarm_size));
      return message;
    }
    for (size_t id = 0; id < swarm_size; ++id) {
      if (!IsKind(members[id]) || (present & KindBit(members[id])) == 0) {
        std::snprintf(message, sizeof message, "member_kinds gives robot %u a kind not among the swarm's kinds",
                      static_cast<unsigned>(id));
        return message;
      }
      storage[id] = members[id];
    }
    if (members[config.sync.self_id] != self) {
      std::snprintf(message, sizeof message, "member_kinds gives this robot (%u) the kind %s; its kind is %s",
                    static_cast<unsigned>(config.sync.self_id), motion::ToString(members[config.sync.self_id]),
                    motion::ToString(self));
      return message;
    }
  }
  config.member_kinds = std::span<const motion::RobotKind>(storage.data(), swarm_size);
  std::array<motion::SwarmKind, motion::kRobotKindCount> kinds{};
  size_t count = 0;
  for (size_t i = 0; i < motion::kRobotKindCount; ++i) {
    const auto kind = static_cast<motion::RobotKind>(i);
    if ((present & KindBit(kind)) != 0) kinds[count++] = motion::SwarmKind{kind, motion::DefaultKindLimits(kind)};
  }
  config.safety.arena_width_m = config.estimator.arena.width_m;
  config.safety.arena_height_m = config.estimator.arena.depth_m;
  runtime::ConfigureKinds(config, motion::SwarmKind{self, motion::DefaultKindLimits(self)},
                          std::span<const motion::SwarmKind>(kinds.data(), count));
  return nullptr;
}

}  // namespace syrof::firmware::robot
