// Just enough of a little-endian ELF32 file (the robot images) for
// syrof-firmware-config: its sections by name, each allocated section's
// bytes at its load address (as the flash programmer writes them, and as
// `objcopy -O ihex` takes them), and writing bytes of a section in place.
// The file is untrusted: every offset and size is checked, and a failure is
// a lab::Error naming the file and what is wrong.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "syrof/lab/base/error.h"

namespace syrof::firmware::config {

struct ElfSection {
  std::string name;
  uint32_t type = 0;   ///< SHT_PROGBITS 1, SHT_NOBITS 8, ...
  uint32_t flags = 0;  ///< SHF_ALLOC 2, ...
  uint32_t address = 0;      ///< where it runs (VMA)
  uint32_t load_address = 0; ///< where it is flashed (LMA): its segment's physical address
  uint32_t file_offset = 0;
  uint32_t size = 0;
};

/// Bytes to write at `address` (one allocated section with contents).
struct LoadChunk {
  uint32_t address = 0;
  std::vector<uint8_t> bytes;
};

struct ElfFile {
  std::vector<uint8_t> bytes;  ///< the whole file
  uint16_t machine = 0;        ///< EM_ARM is 40
  uint32_t entry = 0;
  std::vector<ElfSection> sections;

  /// The section named `name`, or nullptr.
  const ElfSection* Find(std::string_view name) const;
  /// Every allocated section with contents (not NOBITS, not empty), at its
  /// load address, in address order.
  std::vector<LoadChunk> LoadChunks() const;
};

struct ElfOrError {
  std::optional<ElfFile> elf;
  std::optional<lab::Error> error;
  bool ok() const { return elf.has_value(); }
};

/// Reads `bytes` as an ELF32 little-endian file; `where` names it in errors.
ElfOrError ParseElf(std::vector<uint8_t> bytes, const std::string& where);
/// Reads and parses the file at `path`.
ElfOrError ReadElfFile(const std::string& path);

/// Writes the whole file to `path`; an error names it.
std::optional<lab::Error> WriteFile(const std::string& path, std::span<const uint8_t> bytes);

}  // namespace syrof::firmware::config
