#include "syrof/firmware/config/elf_file.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>

namespace syrof::firmware::config {

namespace {

constexpr uint32_t kShtNobits = 8;
constexpr uint32_t kShfAlloc = 2;
constexpr uint32_t kPtLoad = 1;

uint32_t Word(const std::vector<uint8_t>& bytes, size_t offset) {
  return uint32_t{bytes[offset]} | uint32_t{bytes[offset + 1]} << 8 | uint32_t{bytes[offset + 2]} << 16 |
         uint32_t{bytes[offset + 3]} << 24;
}
uint16_t Half(const std::vector<uint8_t>& bytes, size_t offset) {
  return static_cast<uint16_t>(bytes[offset] | bytes[offset + 1] << 8);
}

// Whether [offset, offset + count * size) lies within a file of `length` bytes.
bool Within(uint64_t offset, uint64_t count, uint64_t size, uint64_t length) {
  return offset <= length && count * size <= length - offset;
}

lab::Error At(const std::string& where, std::string message) { return lab::Error{.where = where, .message = std::move(message)}; }

struct Segment {
  uint32_t type, offset, virtual_address, physical_address, file_size;
};

}  // namespace

const ElfSection* ElfFile::Find(std::string_view name) const {
  for (const ElfSection& section : sections) {
    if (section.name == name) return &section;
  }
  return nullptr;
}

std::vector<LoadChunk> ElfFile::LoadChunks() const {
  std::vector<LoadChunk> chunks;
  for (const ElfSection& section : sections) {
    if ((section.flags & kShfAlloc) == 0 || section.type == kShtNobits || section.size == 0) continue;
    chunks.push_back(LoadChunk{section.load_address,
                               std::vector<uint8_t>(bytes.begin() + section.file_offset,
                                                    bytes.begin() + section.file_offset + section.size)});
  }
  std::sort(chunks.begin(), chunks.end(), [](const LoadChunk& a, const LoadChunk& b) { return a.address < b.address; });
  return chunks;
}

ElfOrError ParseElf(std::vector<uint8_t> bytes, const std::string& where) {
  const uint64_t length = bytes.size();
  if (length < 52 || bytes[0] != 0x7f || bytes[1] != 'E' || bytes[2] != 'L' || bytes[3] != 'F') {
    return {std::nullopt, At(where, "not an ELF file (no \\x7fELF at its start)")};
  }
  if (bytes[4] != 1 || bytes[5] != 1) {
    return {std::nullopt, At(where, "not a 32-bit little-endian ELF file (a robot image for the Cortex-M4 is one)")};
  }
  ElfFile elf;
  elf.machine = Half(bytes, 18);
  elf.entry = Word(bytes, 24);
  const uint32_t program_offset = Word(bytes, 28);
  const uint32_t section_offset = Word(bytes, 32);
  const uint16_t program_size = Half(bytes, 42), program_count = Half(bytes, 44);
  const uint16_t section_size = Half(bytes, 46), section_count = Half(bytes, 48), names_index = Half(bytes, 50);
  if (section_count == 0 || section_size < 40 || !Within(section_offset, section_count, section_size, length)) {
    return {std::nullopt, At(where, "its section header table is missing or lies outside the file")};
  }
  if (program_count > 0 && (program_size < 32 || !Within(program_offset, program_count, program_size, length))) {
    return {std::nullopt, At(where, "its program header table lies outside the file")};
  }
  std::vector<Segment> segments;
  for (uint16_t i = 0; i < program_count; ++i) {
    const size_t at = program_offset + size_t{i} * program_size;
    const Segment segment{Word(bytes, at), Word(bytes, at + 4), Word(bytes, at + 8), Word(bytes, at + 12),
                          Word(bytes, at + 16)};
    if (segment.type != kPtLoad) continue;
    if (!Within(segment.offset, 1, segment.file_size, length)) {
      return {std::nullopt, At(where, "program header " + std::to_string(i) + " lies outside the file")};
    }
    segments.push_back(segment);
  }
  if (names_index >= section_count) return {std::nullopt, At(where, "its section name table index is out of range")};
  const size_t names_at = section_offset + size_t{names_index} * section_size;
  const uint32_t names_offset = Word(bytes, names_at + 16), names_size = Word(bytes, names_at + 20);
  if (!Within(names_offset, 1, names_size, length)) {
    return {std::nullopt, At(where, "its section name table lies outside the file")};
  }
  for (uint16_t i = 0; i < section_count; ++i) {
    const size_t at = section_offset + size_t{i} * section_size;
    ElfSection section;
    const uint32_t name = Word(bytes, at);
    section.type = Word(bytes, at + 4);
    section.flags = Word(bytes, at + 8);
    section.address = Word(bytes, at + 12);
    section.file_offset = Word(bytes, at + 16);
    section.size = Word(bytes, at + 20);
    if (name >= names_size) return {std::nullopt, At(where, "section " + std::to_string(i) + "'s name lies outside its table")};
    const auto* text = reinterpret_cast<const char*>(bytes.data() + names_offset + name);
    section.name.assign(text, strnlen(text, names_size - name));
    const bool has_contents = section.type != kShtNobits && section.type != 0;
    if (has_contents && !Within(section.file_offset, 1, section.size, length)) {
      return {std::nullopt, At(where, "section " + section.name + " lies outside the file")};
    }
    // Its load address: where its segment is flashed, as objcopy takes it.
    section.load_address = section.address;
    if (has_contents && (section.flags & kShfAlloc) != 0 && section.size > 0) {
      bool found = false;
      for (const Segment& segment : segments) {
        if (section.file_offset >= segment.offset &&
            uint64_t{section.file_offset} + section.size <= uint64_t{segment.offset} + segment.file_size) {
          section.load_address = segment.physical_address + (section.file_offset - segment.offset);
          found = true;
          break;
        }
      }
      if (!found) return {std::nullopt, At(where, "section " + section.name + " lies in no loadable segment")};
    }
    elf.sections.push_back(std::move(section));
  }
  elf.bytes = std::move(bytes);
  return {std::move(elf), std::nullopt};
}

ElfOrError ReadElfFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {std::nullopt, At(path, "cannot read the file")};
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) return {std::nullopt, At(path, "cannot read the file")};
  return ParseElf(std::move(bytes), path);
}

std::optional<lab::Error> WriteFile(const std::string& path, std::span<const uint8_t> bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (out) out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (out) out.close();
  if (!out) return At(path, "cannot write the file");
  return std::nullopt;
}

}  // namespace syrof::firmware::config
