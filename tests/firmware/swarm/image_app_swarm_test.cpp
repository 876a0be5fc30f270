// syrof-firmware-swarm runs the app compiled into its robot image, whatever
// the scenario's `app:` says; the run must say which (image_app.h). Here the
// starter image (its app: circle) on lab/scenarios/gather.yaml, as a user
// would start it: one warning line naming both apps on standard error, and
// the replay's header and metrics.json naming circle (both said
// builtin:gather before). Needs the Cortex-M4 build's robot image
// (live_swarm.h says where it comes from; without it the test skips).
#include <fcntl.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "live_swarm.h"
#include "syrof/lab/replay/reader.h"
#include "syrof/lab/replay/replay.h"
#include "syrof/process/fd.h"
#include "syrof/process/spawn.h"

namespace syrof::firmware::swarm {
namespace {

TEST(FirmwareSwarmImageApp, RunNamesTheImagesAppAndWarnsOfTheScenarios) {
  if (!testing::HaveImage()) {
    if (testing::ImageRequired()) FAIL() << "no robot image " << testing::RobotImage();
    GTEST_SKIP() << "no robot image " << testing::RobotImage() << " (make test-firmware-swarm builds it)";
  }
  const std::filesystem::path out = SYROF_TEST_OUT;
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  process::Child child;
  {
    const process::Fd output(open((out / "output.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
    process::Command command;
    command.argv = {SYROF_FIRMWARE_SWARM, "--image", testing::RobotImage(), "--scenario",
                    SYROF_SOURCE_DIR "/lab/scenarios/gather.yaml", "--robots", "3", "--seconds", "2",
                    "--out", (out / "run").string()};
    command.inherit_environment = true;
    command.descriptors = {{1, output.get()}, {2, output.get()}};
    command.own_process_group = true;
    command.die_with_parent = true;
    child = process::Spawn(command);
  }
  ASSERT_TRUE(child.started());
  const std::optional<process::ExitStatus> status = child.Wait(std::chrono::seconds(120));
  if (!status) child.KillGroup();
  ASSERT_TRUE(status.has_value()) << testing::ReadText(out / "output.txt");
  const std::string output = testing::ReadText(out / "output.txt");
  // It ran (1 would be a check of the run's own failing: not this test's).
  ASSERT_TRUE(status->exited() && (status->code == 0 || status->code == 1)) << output;

  EXPECT_NE(output.find("syrof-firmware-swarm: warning: the scenario names app 'builtin:gather', but the robot image " +
                        testing::RobotImage() + " runs its compiled-in app 'circle'"),
            std::string::npos)
      << output;

  std::ifstream in(out / "run" / "replay", std::ios::binary);
  lab::replay::Reader reader(in);
  lab::replay::Header header;
  ASSERT_TRUE(reader.ReadHeader(header)) << output;
  EXPECT_EQ(header.app_name, "circle");
  EXPECT_EQ(header.scenario_name, "gather");

  const nlohmann::json metrics = nlohmann::json::parse(testing::ReadText(out / "run" / "metrics.json"));
  EXPECT_EQ(metrics["app"]["name"], "circle") << metrics["app"].dump();
  EXPECT_EQ(metrics["app"]["source"], testing::RobotImage()) << metrics["app"].dump();
  EXPECT_EQ(metrics["goal"]["app"], "circle") << metrics["goal"].dump();
  EXPECT_EQ(metrics["runtime"], "firmware");
  EXPECT_NE(output.find("  scenario gather, app circle (the image's); "), std::string::npos) << output;
}

}  // namespace
}  // namespace syrof::firmware::swarm
