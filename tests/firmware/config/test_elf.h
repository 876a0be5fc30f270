// A small ELF32 little-endian file made in memory, shaped like a robot
// image: a vector table at 0, the configuration block's section right after
// it, `.data` that runs in RAM and is flashed after the code (its load
// address differs from its address), `.bss` without contents, and the
// section name table. Options leave the block out or give it no contents.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace syrof::firmware::config::testing {

struct TestElfOptions {
  bool config_section = true;
  bool config_contents = true;  ///< false: NOBITS, as a `(NOLOAD)` section would be
  uint32_t config_size = 1024;
  uint32_t entry = 0x411;
};

inline void Put32(std::vector<uint8_t>& out, size_t at, uint32_t value) {
  for (int i = 0; i < 4; ++i) out[at + static_cast<size_t>(i)] = static_cast<uint8_t>(value >> (8 * i));
}
inline void Put16(std::vector<uint8_t>& out, size_t at, uint16_t value) {
  out[at] = static_cast<uint8_t>(value);
  out[at + 1] = static_cast<uint8_t>(value >> 8);
}

inline std::vector<uint8_t> MakeTestElf(const TestElfOptions& options = {}) {
  struct Section {
    std::string name;
    uint32_t type, flags, address, size;
    std::vector<uint8_t> contents;
    uint32_t offset = 0;
    uint32_t name_offset = 0;
  };
  std::vector<Section> sections;
  sections.push_back({"", 0, 0, 0, 0, {}});
  std::vector<uint8_t> vectors(16);
  for (size_t i = 0; i < vectors.size(); ++i) vectors[i] = static_cast<uint8_t>(0xa0 + i);
  sections.push_back({".vectors", 1, 6, 0x0, 16, vectors});
  const uint32_t config_address = 0x10;
  if (options.config_section) {
    sections.push_back({".syrof_config", options.config_contents ? 1u : 8u, 2, config_address, options.config_size,
                        options.config_contents ? std::vector<uint8_t>(options.config_size, 0) : std::vector<uint8_t>{}});
  }
  const uint32_t text_address = config_address + (options.config_section ? options.config_size : 0);
  std::vector<uint8_t> text(40);
  for (size_t i = 0; i < text.size(); ++i) text[i] = static_cast<uint8_t>(i * 7);
  sections.push_back({".text", 1, 6, text_address, static_cast<uint32_t>(text.size()), text});
  const std::vector<uint8_t> data = {1, 2, 3, 4, 5, 6, 7, 8};
  sections.push_back({".data", 1, 3, 0x20000000, 8, data});
  sections.push_back({".bss", 8, 3, 0x20000008, 64, {}});
  sections.push_back({".shstrtab", 3, 0, 0, 0, {}});

  // The name table.
  std::vector<uint8_t> names(1, 0);
  for (Section& section : sections) {
    if (section.name.empty()) continue;
    section.name_offset = static_cast<uint32_t>(names.size());
    names.insert(names.end(), section.name.begin(), section.name.end());
    names.push_back(0);
  }
  sections.back().contents = names;
  sections.back().size = static_cast<uint32_t>(names.size());

  // Layout: header (52), two program headers (32 each), contents, section headers.
  std::vector<uint8_t> file(52 + 2 * 32);
  for (Section& section : sections) {
    if (section.type == 8 || section.type == 0) {
      section.offset = static_cast<uint32_t>(file.size());
      continue;
    }
    while (file.size() % 4 != 0) file.push_back(0);
    section.offset = static_cast<uint32_t>(file.size());
    file.insert(file.end(), section.contents.begin(), section.contents.end());
  }
  while (file.size() % 4 != 0) file.push_back(0);
  const auto section_table = static_cast<uint32_t>(file.size());
  file.resize(file.size() + sections.size() * 40);
  for (size_t i = 0; i < sections.size(); ++i) {
    const size_t at = section_table + i * 40;
    Put32(file, at, sections[i].name_offset);
    Put32(file, at + 4, sections[i].type);
    Put32(file, at + 8, sections[i].flags);
    Put32(file, at + 12, sections[i].address);
    Put32(file, at + 16, sections[i].offset);
    Put32(file, at + 20, sections[i].size);
  }
  // ELF header.
  const uint8_t ident[16] = {0x7f, 'E', 'L', 'F', 1, 1, 1, 0};
  std::memcpy(file.data(), ident, sizeof ident);
  Put16(file, 16, 2);   // ET_EXEC
  Put16(file, 18, 40);  // EM_ARM
  Put32(file, 20, 1);
  Put32(file, 24, options.entry);
  Put32(file, 28, 52);
  Put32(file, 32, section_table);
  Put16(file, 40, 52);
  Put16(file, 42, 32);
  Put16(file, 44, 2);
  Put16(file, 46, 40);
  Put16(file, 48, static_cast<uint16_t>(sections.size()));
  Put16(file, 50, static_cast<uint16_t>(sections.size() - 1));
  // Program headers: the code (vectors to text's end) at 0, and .data
  // flashed right after the code but run at 0x20000000.
  const Section& first = sections[1];
  const Section* text_section = nullptr;
  const Section* data_section = nullptr;
  for (const Section& section : sections) {
    if (section.name == ".text") text_section = &section;
    if (section.name == ".data") data_section = &section;
  }
  const uint32_t code_end = text_section->offset + text_section->size;
  Put32(file, 52, 1);
  Put32(file, 56, first.offset);
  Put32(file, 60, 0);
  Put32(file, 64, 0);
  Put32(file, 68, code_end - first.offset);
  Put32(file, 72, code_end - first.offset);
  Put32(file, 84, 1);
  Put32(file, 88, data_section->offset);
  Put32(file, 92, 0x20000000);
  Put32(file, 96, text_address + text_section->size);
  Put32(file, 100, 8);
  Put32(file, 104, 8);
  return file;
}

}  // namespace syrof::firmware::config::testing
