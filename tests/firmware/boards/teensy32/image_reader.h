// Just enough of ELF32 and Intel HEX to check a firmware image without the
// cross tools: the loadable bytes by load (physical) address, the entry
// point and the symbols. Errors name the file and what is wrong.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace syrof::board::teensy32::testing {

/// Address -> byte, as the flash programmer writes it.
using MemoryImage = std::map<uint32_t, uint8_t>;

struct ElfImage {
  uint16_t machine = 0;
  uint32_t entry = 0;
  MemoryImage loadable;  ///< allocated sections' bytes at their load addresses (as objcopy writes them)
  std::map<std::string, uint32_t> symbols;
};

/// Reads `bytes` as a little-endian ELF32 file; on failure returns false and
/// sets `error`.
bool ParseElf32(const std::vector<uint8_t>& bytes, ElfImage& image, std::string& error);

struct HexImage {
  MemoryImage data;
  bool has_start_address = false;
  uint32_t start_address = 0;  ///< record type 05
  bool has_end = false;        ///< record type 01 seen (and nothing after it)
};

/// Reads Intel HEX text (record types 00-05), checking every checksum;
/// errors name the line.
bool ParseIntelHex(const std::string& text, HexImage& image, std::string& error);

/// The whole file, or false.
bool ReadFile(const std::string& path, std::vector<uint8_t>& bytes);

}  // namespace syrof::board::teensy32::testing
