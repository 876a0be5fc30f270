// Headless Chromium on a live page, for the live page's browser tests
// (tests/lab/live, and tests/firmware/swarm's page of an emulated swarm):
// Chromium runs on a thread of its own, so the test can feed or start the
// run while it loads; what it printed (a DOM dump, or nothing for a
// screenshot), when its output was complete, and the page's own report.
//
// Chromium's virtual time waits while the page's stream is open: give the
// page's fragment `live-until=` (viewer.js) to close it at the moment under
// test, and Chromium then dumps the page or takes its screenshot.
#pragma once

#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <utility>

namespace syrof::lab::live::testing {

/// The host's clock, µs since the epoch (the page's rounds carry the same, `w`).
inline int64_t WallMicroseconds() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

class Browser {
 public:
  /// Starts `chromium` on `url` with `what` ("--dump-dom",
  /// "--screenshot=FILE"), its profile in the folder `profile` (a fresh one
  /// per browser).
  Browser(const std::string& chromium, const std::filesystem::path& profile, const std::string& what,
          const std::string& url) {
    command_ = chromium +
               " --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run --disable-extensions"
               " --disable-dev-shm-usage --user-data-dir=" + profile.string() +
               " --window-size=1280,1000 --virtual-time-budget=30000 " + what + " '" + url + "' 2>/dev/null";
    thread_ = std::thread([this] {
      std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command_.c_str(), "r"), pclose);
      if (!pipe) return;
      std::array<char, 65536> buffer;
      size_t got = 0;
      while ((got = fread(buffer.data(), 1, buffer.size(), pipe.get())) > 0) {
        output_.append(buffer.data(), got);
        if (output_.find("</html>") != std::string::npos && done_us_ == 0) done_us_ = WallMicroseconds();
      }
      if (done_us_ == 0) done_us_ = WallMicroseconds();
    });
  }
  ~Browser() { Join(); }
  Browser(const Browser&) = delete;
  Browser& operator=(const Browser&) = delete;

  /// Waits for Chromium to exit.
  void Join() {
    if (thread_.joinable()) thread_.join();
  }
  /// After Join: what Chromium printed, and when (WallMicroseconds) it was whole.
  const std::string& output() const { return output_; }
  int64_t done_us() const { return done_us_; }

  /// The page's #report (viewer.js's JSON summary), from a DOM dump; null
  /// when the dump has none.
  nlohmann::json Report() const {
    const size_t at = output_.find("<pre id=\"report\"");
    if (at == std::string::npos) return nullptr;
    const size_t start = output_.find('>', at) + 1;
    std::string text = output_.substr(start, output_.find("</pre>", start) - start);
    for (const auto& [from, to] : std::array<std::pair<std::string, std::string>, 4>{
             {{"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&amp;", "&"}}}) {
      for (size_t i = text.find(from); i != std::string::npos; i = text.find(from, i + to.size())) {
        text.replace(i, from.size(), to);
      }
    }
    return nlohmann::json::parse(text, nullptr, false);
  }

 private:
  std::string command_;
  std::string output_;
  int64_t done_us_ = 0;
  std::thread thread_;
};

}  // namespace syrof::lab::live::testing
