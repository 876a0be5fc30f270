// An owned file descriptor, and writing a whole buffer to one.
//
//   process::Fd log(open(path, O_WRONLY | O_CREAT | O_CLOEXEC, 0644));
//   if (!log.valid()) ...                      // errno says why
//   process::WriteAll(log.get(), text.data(), text.size());
//   // closed when `log` goes
#pragma once

#include <cstddef>

namespace syrof::process {

/// Owns one descriptor (or none: -1) and closes it when destroyed or reset.
/// Moved, never copied, so exactly one object closes it.
class Fd {
 public:
  Fd() = default;
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() { Reset(); }
  Fd(Fd&& other) noexcept : fd_(other.Release()) {}
  Fd& operator=(Fd&& other) noexcept {
    if (this != &other) Reset(other.Release());
    return *this;
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;

  int get() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  /// Gives the descriptor up without closing it (-1 afterwards).
  int Release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }
  /// Closes the descriptor held (if any) and holds `fd` instead.
  void Reset(int fd = -1);

 private:
  int fd_ = -1;
};

/// Writes all `size` bytes of `data` to `fd`, again after an interruption or
/// a short write. False when a write fails or writes nothing (the reader
/// gone, a full disk): how much went out is then unknown. Async-signal-safe
/// (a signal handler or a child between fork and exec may call it).
bool WriteAll(int fd, const void* data, size_t size);

}  // namespace syrof::process
