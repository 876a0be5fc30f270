// A PNG screenshot read back as RGBA, for the browser tests of the viewer's
// pages (tests/lab/view/browser_test.cpp, tests/lab/live/live_browser_test.cpp).
#pragma once

#include <png.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace syrof::lab::testing {

struct Image {
  unsigned width = 0;
  unsigned height = 0;
  std::vector<uint8_t> rgba;
  /// The pixel nearest (x, y), as red, green, blue.
  std::array<int, 3> At(double x, double y) const {
    const size_t i = (static_cast<size_t>(std::lround(y)) * width + static_cast<size_t>(std::lround(x))) * 4;
    return {rgba[i], rgba[i + 1], rgba[i + 2]};
  }
};

/// The image at `path`; empty (width 0) when it cannot be read.
inline Image ReadPng(const std::filesystem::path& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  Image image;
  if (png_image_begin_read_from_file(&png, path.c_str()) == 0) return image;
  png.format = PNG_FORMAT_RGBA;
  image.rgba.resize(PNG_IMAGE_SIZE(png));
  if (png_image_finish_read(&png, nullptr, image.rgba.data(), 0, nullptr) == 0) return {};
  image.width = png.width;
  image.height = png.height;
  return image;
}

}  // namespace syrof::lab::testing
