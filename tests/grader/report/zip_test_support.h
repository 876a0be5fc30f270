// Reading a zip back in tests (libzip): every entry's name, Unix mode, MS-DOS
// time and bytes, in the order the zip holds them; and extracting it as
// unzip does (folders, files, modes).
#pragma once

#include <sys/stat.h>
#include <zip.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>
#include <string>
#include <vector>

namespace syrof::grader::report::testing {

struct ZipEntry {
  std::string name;
  uint32_t mode = 0;      ///< st_mode bits from the Unix external attributes
  uint8_t opsys = 0;      ///< ZIP_OPSYS_UNIX when they are Unix attributes
  uint16_t dos_time = 0;  ///< as stored in the central directory
  uint16_t dos_date = 0;
  uint16_t method = 0;    ///< ZIP_CM_STORE, ZIP_CM_DEFLATE
  std::string bytes;
};

namespace zip_detail {

inline uint32_t Little(const std::string& bytes, size_t at, int size) {
  uint32_t value = 0;
  for (int i = size - 1; i >= 0; --i) value = (value << 8) | static_cast<uint8_t>(bytes.at(at + i));
  return value;
}

// The MS-DOS time and date of each central directory entry, read from the
// file's bytes (libzip gives them only as a local time_t).
inline std::vector<std::pair<uint16_t, uint16_t>> DosTimes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::pair<uint16_t, uint16_t>> times;
  if (bytes.size() < 22) return times;
  const size_t end = bytes.size() - 22;  // no archive comment
  if (Little(bytes, end, 4) != 0x06054b50) return times;
  const uint32_t count = Little(bytes, end + 10, 2);
  size_t at = Little(bytes, end + 16, 4);
  for (uint32_t i = 0; i < count && at + 46 <= bytes.size(); ++i) {
    if (Little(bytes, at, 4) != 0x02014b50) break;
    times.emplace_back(static_cast<uint16_t>(Little(bytes, at + 12, 2)), static_cast<uint16_t>(Little(bytes, at + 14, 2)));
    at += 46 + Little(bytes, at + 28, 2) + Little(bytes, at + 30, 2) + Little(bytes, at + 32, 2);
  }
  return times;
}

}  // namespace zip_detail

/// The zip's entries, or an empty list (and `error` set) when it cannot be read.
inline std::vector<ZipEntry> ReadZip(const std::string& path, std::string& error) {
  std::vector<ZipEntry> entries;
  int code = 0;
  zip_t* zip = zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &code);
  if (zip == nullptr) {
    error = "cannot open " + path + " (libzip error " + std::to_string(code) + ")";
    return entries;
  }
  const zip_int64_t count = zip_get_num_entries(zip, 0);
  for (zip_int64_t i = 0; i < count; ++i) {
    const auto index = static_cast<zip_uint64_t>(i);
    ZipEntry entry;
    entry.name = zip_get_name(zip, index, ZIP_FL_ENC_RAW);
    zip_uint8_t opsys = 0;
    zip_uint32_t attributes = 0;
    zip_file_get_external_attributes(zip, index, 0, &opsys, &attributes);
    entry.opsys = opsys;
    entry.mode = attributes >> 16;
    zip_stat_t stat;
    zip_stat_index(zip, index, 0, &stat);
    entry.method = stat.comp_method;
    if (zip_file_t* file = zip_fopen_index(zip, index, 0)) {
      entry.bytes.resize(stat.size);
      const zip_int64_t got = zip_fread(file, entry.bytes.data(), stat.size);
      if (got != static_cast<zip_int64_t>(stat.size)) error = "short read of " + entry.name;
      zip_fclose(file);
    }
    entries.push_back(std::move(entry));
  }
  zip_discard(zip);
  const std::vector<std::pair<uint16_t, uint16_t>> times = zip_detail::DosTimes(path);
  if (times.size() != entries.size()) {
    error = "the central directory of " + path + " could not be read";
    return {};
  }
  for (size_t i = 0; i < entries.size(); ++i) {
    entries[i].dos_time = times[i].first;
    entries[i].dos_date = times[i].second;
  }
  return entries;
}

/// Extracts `zip_path` into `dir` as unzip would: folders, files, and each
/// entry's Unix permission bits. Returns "" or what went wrong.
inline std::string ExtractZip(const std::string& zip_path, const std::filesystem::path& dir) {
  std::string error;
  const std::vector<ZipEntry> entries = ReadZip(zip_path, error);
  if (!error.empty()) return error;
  for (const ZipEntry& entry : entries) {
    const std::filesystem::path path = dir / entry.name;
    if (entry.name.ends_with("/")) {
      std::filesystem::create_directories(path);
    } else {
      std::filesystem::create_directories(path.parent_path());
      std::ofstream(path, std::ios::binary) << entry.bytes;
    }
    if (chmod(path.c_str(), entry.mode & 07777) != 0) return "cannot chmod " + path.string();
  }
  return {};
}

}  // namespace syrof::grader::report::testing
