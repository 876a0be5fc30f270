// Bounded text building for reports: no allocation, no printf.
#pragma once

#include <cstddef>
#include <cstdint>

namespace syrof::app::detail {

// Appends to a NUL-terminated buffer of `size` bytes, truncating.
class TextBuilder {
 public:
  TextBuilder(char* out, size_t size) : out_(out), size_(size) {
    if (size_ > 0) out_[0] = '\0';
  }
  TextBuilder& Append(const char* text) {
    if (text == nullptr) return *this;
    while (*text != '\0' && length_ + 1 < size_) out_[length_++] = *text++;
    if (size_ > 0) out_[length_] = '\0';
    return *this;
  }
  TextBuilder& Append(uint32_t value) {
    char digits[10];
    size_t count = 0;
    do {
      digits[count++] = static_cast<char>('0' + value % 10);
      value /= 10;
    } while (value != 0);
    char text[11];
    for (size_t i = 0; i < count; ++i) text[i] = digits[count - 1 - i];
    text[count] = '\0';
    return Append(text);
  }

 private:
  char* out_;
  size_t size_;
  size_t length_ = 0;
};

}  // namespace syrof::app::detail
