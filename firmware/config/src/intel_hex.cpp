#include "syrof/firmware/config/intel_hex.h"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace syrof::firmware::config {

namespace {

// One record: ":" length, address, type, data, checksum, in upper-case hex.
void Record(std::string& out, uint8_t type, uint16_t address, std::span<const uint8_t> data) {
  std::vector<uint8_t> bytes = {static_cast<uint8_t>(data.size()), static_cast<uint8_t>(address >> 8),
                                static_cast<uint8_t>(address & 0xff), type};
  bytes.insert(bytes.end(), data.begin(), data.end());
  uint8_t sum = 0;
  for (const uint8_t byte : bytes) sum = static_cast<uint8_t>(sum + byte);
  bytes.push_back(static_cast<uint8_t>(0x100 - sum));
  out += ':';
  for (const uint8_t byte : bytes) {
    char hex[3];
    std::snprintf(hex, sizeof hex, "%02X", byte);
    out += hex;
  }
  out += "\r\n";
}

}  // namespace

std::string WriteIntelHex(std::span<const LoadChunk> chunks, std::optional<uint32_t> start_address) {
  std::string out;
  bool have_upper = false;
  uint32_t upper = 0;
  for (const LoadChunk& chunk : chunks) {
    for (size_t at = 0; at < chunk.bytes.size();) {
      const uint32_t address = chunk.address + static_cast<uint32_t>(at);
      if (!have_upper || address >> 16 != upper) {
        upper = address >> 16;
        have_upper = true;
        const uint8_t high[2] = {static_cast<uint8_t>(upper >> 8), static_cast<uint8_t>(upper & 0xff)};
        Record(out, 0x04, 0, high);
      }
      // Up to 16 bytes, and never across a 64 KiB boundary.
      size_t count = std::min<size_t>(16, chunk.bytes.size() - at);
      count = std::min<size_t>(count, 0x10000 - (address & 0xffff));
      Record(out, 0x00, static_cast<uint16_t>(address & 0xffff),
             std::span<const uint8_t>(chunk.bytes.data() + at, count));
      at += count;
    }
  }
  if (start_address) {
    // As objcopy writes it: a start segment address (03, CS:IP) when the
    // address fits in 20 bits (every Teensy 3.2 flash address does), else
    // a start linear address (05).
    const uint32_t start = *start_address;
    if (start <= 0xfffff) {
      const uint8_t bytes[4] = {static_cast<uint8_t>((start & 0xf0000) >> 12), 0, static_cast<uint8_t>(start >> 8),
                                static_cast<uint8_t>(start)};
      Record(out, 0x03, 0, bytes);
    } else {
      const uint8_t bytes[4] = {static_cast<uint8_t>(start >> 24), static_cast<uint8_t>(start >> 16),
                                static_cast<uint8_t>(start >> 8), static_cast<uint8_t>(start)};
      Record(out, 0x05, 0, bytes);
    }
  }
  Record(out, 0x01, 0, {});
  return out;
}

}  // namespace syrof::firmware::config
