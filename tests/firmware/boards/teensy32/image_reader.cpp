#include "image_reader.h"

#include <fstream>
#include <iterator>
#include <sstream>

namespace syrof::board::teensy32::testing {
namespace {

uint32_t Le16(const std::vector<uint8_t>& b, size_t at) { return b[at] | (b[at + 1] << 8); }
uint32_t Le32(const std::vector<uint8_t>& b, size_t at) {
  return b[at] | (b[at + 1] << 8) | (b[at + 2] << 16) | (static_cast<uint32_t>(b[at + 3]) << 24);
}

int HexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

}  // namespace

bool ReadFile(const std::string& path, std::vector<uint8_t>& bytes) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return false;
  bytes.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  return true;
}

bool ParseElf32(const std::vector<uint8_t>& b, ElfImage& image, std::string& error) {
  if (b.size() < 52 || b[0] != 0x7F || b[1] != 'E' || b[2] != 'L' || b[3] != 'F') {
    error = "not an ELF file";
    return false;
  }
  if (b[4] != 1 || b[5] != 1) {
    error = "not a little-endian ELF32 file";
    return false;
  }
  image.machine = static_cast<uint16_t>(Le16(b, 18));
  image.entry = Le32(b, 24);
  const uint32_t phoff = Le32(b, 28), shoff = Le32(b, 32);
  const uint32_t phentsize = Le16(b, 42), phnum = Le16(b, 44), shentsize = Le16(b, 46), shnum = Le16(b, 48);
  if (phentsize != 32 || shentsize != 40 || phoff + uint64_t{phnum} * 32 > b.size() ||
      shoff + uint64_t{shnum} * 40 > b.size()) {
    error = "header tables outside the file";
    return false;
  }
  // What a programmer writes: each allocated section with contents, at its
  // load address (inside its PT_LOAD segment's file range); not the padding
  // a segment may hold between sections.
  struct Segment {
    uint32_t offset, paddr, filesz;
  };
  std::vector<Segment> segments;
  for (uint32_t i = 0; i < phnum; ++i) {
    const size_t at = phoff + 32 * i;
    if (Le32(b, at) != 1) continue;  // PT_LOAD
    segments.push_back({Le32(b, at + 4), Le32(b, at + 12), Le32(b, at + 16)});
    if (uint64_t{segments.back().offset} + segments.back().filesz > b.size()) {
      error = "segment " + std::to_string(i) + " outside the file";
      return false;
    }
  }
  for (uint32_t i = 0; i < shnum; ++i) {
    const size_t at = shoff + 40 * i;
    const uint32_t type = Le32(b, at + 4), flags = Le32(b, at + 8), offset = Le32(b, at + 16),
                   size = Le32(b, at + 20);
    if ((flags & 0x2) == 0 || type == 8 || size == 0) continue;  // not SHF_ALLOC, or SHT_NOBITS
    const Segment* home = nullptr;
    for (const Segment& segment : segments) {
      if (offset >= segment.offset && uint64_t{offset} + size <= uint64_t{segment.offset} + segment.filesz) {
        home = &segment;
      }
    }
    if (home == nullptr) {
      error = "section " + std::to_string(i) + " is in no loadable segment";
      return false;
    }
    const uint32_t load_address = home->paddr + (offset - home->offset);
    for (uint32_t k = 0; k < size; ++k) image.loadable[load_address + k] = b[offset + k];
  }
  for (uint32_t i = 0; i < shnum; ++i) {
    const size_t at = shoff + 40 * i;
    if (Le32(b, at + 4) != 2) continue;  // SHT_SYMTAB
    const uint32_t offset = Le32(b, at + 16), size = Le32(b, at + 20), link = Le32(b, at + 24);
    if (link >= shnum || uint64_t{offset} + size > b.size()) {
      error = "symbol table outside the file";
      return false;
    }
    const size_t strings_at = shoff + 40 * link;
    const uint32_t strings = Le32(b, strings_at + 16), strings_size = Le32(b, strings_at + 20);
    for (uint32_t s = 0; s + 16 <= size; s += 16) {
      const uint32_t name = Le32(b, offset + s);
      if (name == 0 || name >= strings_size) continue;
      std::string text;
      for (size_t c = strings + name; c < b.size() && b[c] != 0; ++c) text.push_back(static_cast<char>(b[c]));
      image.symbols[text] = Le32(b, offset + s + 4);
    }
  }
  return true;
}

bool ParseIntelHex(const std::string& text, HexImage& image, std::string& error) {
  std::istringstream lines(text);
  std::string line;
  uint32_t base = 0;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    const std::string where = "line " + std::to_string(line_number) + ": ";
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    if (image.has_end) {
      error = where + "record after the end-of-file record";
      return false;
    }
    if (line[0] != ':' || line.size() < 11 || line.size() % 2 == 0) {
      error = where + "not a record (':' and an even count of hex digits)";
      return false;
    }
    std::vector<uint8_t> bytes;
    for (size_t i = 1; i < line.size(); i += 2) {
      const int high = HexDigit(line[i]), low = HexDigit(line[i + 1]);
      if (high < 0 || low < 0) {
        error = where + "not a hex digit at column " + std::to_string(i + 1);
        return false;
      }
      bytes.push_back(static_cast<uint8_t>(high * 16 + low));
    }
    const size_t count = bytes[0];
    if (bytes.size() != count + 5) {
      error = where + "length byte says " + std::to_string(count) + " data bytes";
      return false;
    }
    uint8_t sum = 0;
    for (uint8_t byte : bytes) sum = static_cast<uint8_t>(sum + byte);
    if (sum != 0) {
      error = where + "checksum mismatch";
      return false;
    }
    const uint32_t offset = (bytes[1] << 8) | bytes[2];
    const uint8_t type = bytes[3];
    const uint8_t* data = bytes.data() + 4;
    switch (type) {
      case 0:
        for (size_t i = 0; i < count; ++i) {
          const uint32_t address = base + offset + static_cast<uint32_t>(i);
          if (!image.data.emplace(address, data[i]).second) {
            error = where + "address written twice";
            return false;
          }
        }
        break;
      case 1:
        image.has_end = true;
        break;
      case 2:
        if (count != 2) { error = where + "bad extended segment address"; return false; }
        base = ((data[0] << 8) | data[1]) << 4;
        break;
      case 4:
        if (count != 2) { error = where + "bad extended linear address"; return false; }
        base = static_cast<uint32_t>((data[0] << 8) | data[1]) << 16;
        break;
      case 3:
      case 5:
        if (count != 4) { error = where + "bad start address"; return false; }
        image.has_start_address = true;
        image.start_address = (static_cast<uint32_t>(data[0]) << 24) | (data[1] << 16) | (data[2] << 8) | data[3];
        break;
      default:
        error = where + "unknown record type " + std::to_string(type);
        return false;
    }
  }
  if (!image.has_end) {
    error = "no end-of-file record";
    return false;
  }
  return true;
}

}  // namespace syrof::board::teensy32::testing
