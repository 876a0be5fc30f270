// syrof-firmware-swarm with --live, as a user starts it, for the live page's
// tests: the program started on the mps2-an386 robot image (a few qemu
// robots for a few seconds), the page's address read from what it prints,
// and its exit status.
//
// The image comes from the Cortex-M4 build (`make test-firmware-swarm`
// builds it): $SYROF_MPS2_ROBOT_IMAGE, else the source tree's
// build-m4/bin/syrof-robot-mps2.elf. Without it the tests skip, unless
// SYROF_REQUIRE_MPS2_IMAGE is set (the Makefile's test-firmware-swarm sets
// both), as tests/firmware/boards/teensy32's image test does.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include "syrof/process/fd.h"
#include "syrof/process/spawn.h"

namespace syrof::firmware::swarm::testing {

inline std::string RobotImage() {
  const char* image = std::getenv("SYROF_MPS2_ROBOT_IMAGE");
  return image != nullptr && *image != 0 ? image : SYROF_SOURCE_DIR "/build-m4/bin/syrof-robot-mps2.elf";
}

/// Whether a missing image fails the test instead of skipping it.
inline bool ImageRequired() { return std::getenv("SYROF_REQUIRE_MPS2_IMAGE") != nullptr; }

inline bool HaveImage() { return access(RobotImage().c_str(), R_OK) == 0; }

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// One syrof-firmware-swarm run with `--live 0 --live-linger 0`: the live
/// page on a free port of 127.0.0.1, the program gone when the run ends.
/// Its output (standard output and error) goes to `out`/output.txt, its
/// files to `out`. The program, and the qemu instances it starts, are killed
/// if still running when this goes.
class LiveSwarm {
 public:
  LiveSwarm(const std::filesystem::path& out, int robots, int seconds) : out_(out) {
    std::filesystem::remove_all(out);
    std::filesystem::create_directories(out);
    process::Fd output(open((out / "output.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
    process::Command command;
    command.argv = {SYROF_FIRMWARE_SWARM, "--image", RobotImage(), "--robots", std::to_string(robots),
                    "--seconds", std::to_string(seconds), "--out", (out / "run").string(), "--live", "0",
                    "--live-linger", "0"};
    command.inherit_environment = true;
    command.descriptors = {{1, output.get()}, {2, output.get()}};
    command.own_process_group = true;
    command.die_with_parent = true;
    child_ = process::Spawn(command);
  }
  ~LiveSwarm() {
    if (child_.started() && !child_.reaped()) child_.KillGroup();
  }

  bool started() const { return child_.started(); }
  std::string output() const { return ReadText(out_ / "output.txt"); }

  /// The live page's port, once the program printed `live page:
  /// http://127.0.0.1:PORT/` (within `timeout`); nullopt if it did not.
  std::optional<int> WaitForPage(std::chrono::milliseconds timeout) {
    static const std::regex kPage("  live page: http://127\\.0\\.0\\.1:([0-9]+)/\n");
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      std::smatch match;
      const std::string text = output();
      if (std::regex_search(text, match, kPage)) return std::stoi(match[1]);
      if (child_.Wait(std::chrono::milliseconds(0))) return std::nullopt;  // it ended without a page
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return std::nullopt;
  }

  /// The program's exit code once it ended (within `timeout`, else its
  /// group is killed and -1 returned).
  int Wait(std::chrono::seconds timeout) {
    const std::optional<process::ExitStatus> status = child_.Wait(timeout);
    if (!status) {
      child_.KillGroup();
      child_.Reap();
      return -1;
    }
    return status->exited() ? status->code : -1;
  }

 private:
  std::filesystem::path out_;
  process::Child child_;
};

}  // namespace syrof::firmware::swarm::testing
