// The fork server's parent side (docs/app_host.md "The fork server"): one
// library loaded once in a held syrof-app-host, and a copy of it for each
// robot of each run. Thread-safe: a search's jobs ask for copies at once.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "syrof/app_host/hosted_app.h"

namespace syrof::app_host {

class HostProcess;

class LoadedLibrary {
 public:
  /// Starts the held host and waits for its load (load wall cap). When the
  /// library does not load, or its constructors left what copies would
  /// share, it holds nothing: every app is then a fresh host, as without
  /// the fork server (`fresh_reason()` says why).
  explicit LoadedLibrary(const HostOptions& options);
  /// Kills and reaps the held host.
  ~LoadedLibrary();
  LoadedLibrary(const LoadedLibrary&) = delete;
  LoadedLibrary& operator=(const LoadedLibrary&) = delete;

  /// A copy, or why there is none (the caller then starts a fresh host).
  struct CopyStart {
    bool made = false;
    pid_t pid = -1;                  ///< the copy: a child of this process
    std::string load_output;         ///< what the library printed while it loaded (kept bytes)
    uint64_t load_output_bytes = 0;  ///< ... and how many bytes that was in all
  };
  /// Asks the held host for a copy with these descriptors (the copy's
  /// channel, its output pipe). A held host that ended is started again
  /// (once a request); if that fails, or the library loads differently
  /// then, it holds nothing from there on.
  CopyStart StartCopy(int child_channel, int child_output);

  bool holding() const;
  std::string fresh_reason() const;
  /// Held hosts started in all (1 unless one ended).
  int starts() const;

 private:
  // Starts a held host; false (fresh_reason_ set) when it cannot hold.
  bool StartHolder();

  const HostOptions options_;
  mutable std::mutex mutex_;
  std::unique_ptr<HostProcess> holder_;
  bool first_ = true;
  std::string app_name_;
  uint32_t notes_ = 0;
  std::string load_output_;
  uint64_t load_output_bytes_ = 0;
  std::string fresh_reason_;
  int starts_ = 0;
};

}  // namespace syrof::app_host
