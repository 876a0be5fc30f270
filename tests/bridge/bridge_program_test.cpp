// syrof-bridge as a program: a capture with garbage between its frames gives
// the same replay, byte for byte, as the clean capture, and its bridge.json
// differs only in the byte and rejection counts.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "bridge_test_support.h"

namespace syrof::bridge {
namespace {

using namespace testing;

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void WriteFile(const std::filesystem::path& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

int RunBridge(const std::filesystem::path& input, const std::filesystem::path& out, const std::string& more = "") {
  const std::string command = std::string(SYROF_BRIDGE_BINARY) + " --input " + input.string() +
                              " --robots 4 --no-dds --quiet --out " + out.string() + more;
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(BridgeProgramTest, AGarbledCaptureGivesTheCleanCapturesReplayByteForByte) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("syrof-bridge-program-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);

  // Ten rounds of 4 robots, epochs 1 to 3; the garbled copy has seeded
  // random bytes and a cut frame before every frame.
  std::vector<uint8_t> clean, garbled;
  std::mt19937 random(7);
  for (uint16_t round = 0; round < 10; ++round) {
    for (uint16_t robot = 0; robot < kSwarm; ++robot) {
      const auto phase = round % 4 == 3 ? wire::Phase::kVote : wire::Phase::kProgress;
      const std::vector<uint8_t> frame =
          ReceivedFrame(EncodeBeacon(MakeBeacon(robot, static_cast<uint16_t>(1 + round / 4), phase)));
      Append(clean, frame);
      std::vector<uint8_t> noise(1 + random() % 40);
      for (uint8_t& byte : noise) byte = static_cast<uint8_t>(random());
      Append(garbled, noise);
      Append(garbled, std::vector<uint8_t>(frame.begin(), frame.begin() + frame.size() / 2));
      Append(garbled, frame);
    }
  }
  WriteFile(dir / "clean.bin", clean);
  WriteFile(dir / "garbled.bin", garbled);

  ASSERT_EQ(RunBridge(dir / "clean.bin", dir / "clean"), 0);
  ASSERT_EQ(RunBridge(dir / "garbled.bin", dir / "garbled"), 0);

  const std::string clean_replay = ReadFile(dir / "clean" / "replay");
  ASSERT_FALSE(clean_replay.empty());
  EXPECT_EQ(ReadFile(dir / "garbled" / "replay"), clean_replay);

  nlohmann::json clean_json = nlohmann::json::parse(ReadFile(dir / "clean" / "bridge.json"));
  nlohmann::json garbled_json = nlohmann::json::parse(ReadFile(dir / "garbled" / "bridge.json"));
  EXPECT_EQ(clean_json["rejected"]["total"], 0);
  EXPECT_GT(garbled_json["rejected"]["total"].get<uint64_t>(), 40u);
  EXPECT_EQ(clean_json["beacons_accepted"], 40);
  for (const char* key : {"rejected", "bytes", "input", "wall_s", "replay"}) {
    clean_json.erase(key);
    garbled_json.erase(key);
  }
  // Everything else (frames, kinds, beacons, rounds, events, each robot) is the clean capture's.
  EXPECT_EQ(garbled_json, clean_json);

  // With the live page on (a free port, no linger), the same replay; it
  // says where the page was. An address that is not one is bad input.
  ASSERT_EQ(RunBridge(dir / "clean.bin", dir / "live", " --live=127.0.0.1:0 --live-linger 0 2>" +
                                                            (dir / "live.txt").string()),
            0);
  EXPECT_EQ(ReadFile(dir / "live" / "replay"), clean_replay);
  EXPECT_NE(ReadFile(dir / "live.txt").find("live page: http://127.0.0.1:"), std::string::npos)
      << ReadFile(dir / "live.txt");
  EXPECT_EQ(RunBridge(dir / "clean.bin", dir / "bad", " --live=nowhere 2>/dev/null"), 2);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace syrof::bridge
