// `syrof swarm` as a process: Ctrl-C stops it and its robots cleanly, and
// a world killed outright (SIGKILL) leaves no robot process behind.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace syrof::cli {
namespace {

using namespace std::chrono_literals;

// The children of `parent` named syrof-robot, from /proc.
std::vector<pid_t> RobotsOf(pid_t parent) {
  std::vector<pid_t> robots;
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat(entry.path() / "stat");
    std::string line;
    if (!std::getline(stat, line)) continue;
    const size_t close = line.rfind(')');
    const size_t open = line.find('(');
    if (open == std::string::npos || close == std::string::npos) continue;
    const std::string comm = line.substr(open + 1, close - open - 1);
    char state = 0;
    int ppid = 0;
    if (sscanf(line.c_str() + close + 1, " %c %d", &state, &ppid) != 2) continue;
    if (comm == "syrof-robot" && ppid == parent) robots.push_back(static_cast<pid_t>(std::stoi(name)));
  }
  return robots;
}

// Starts `syrof swarm` on the 4-robot idle scenario for 60 s, on a domain of
// its own; waits until its 4 robot processes run.
pid_t StartSwarm(const std::string& out_dir, const std::string& domain, std::vector<pid_t>& robots) {
  const pid_t world = fork();
  if (world == 0) {
    setenv("SYROF_DDS_DOMAIN", domain.c_str(), 1);
    execl(SYROF_EXECUTABLE, SYROF_EXECUTABLE, "swarm", SYROF_SCENARIOS_DIR "/idle.yaml", "--duration", "60", "--out",
          out_dir.c_str(), "--quiet", static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + 30s;
  while (std::chrono::steady_clock::now() < deadline) {
    robots = RobotsOf(world);
    if (robots.size() == 4) break;
    std::this_thread::sleep_for(50ms);
  }
  return world;
}

std::string Domain() { return std::to_string(100 + getpid() % 100); }

TEST(SwarmCommandTest, NoRobotProcessOutlivesAWorldKilledWithSigkill) {
  // Orphans come to this process, so it can see them die and reap them.
  ASSERT_EQ(prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  const std::string out = (std::filesystem::temp_directory_path() / ("syrof_swarm_kill_" + std::to_string(getpid()))).string();
  std::vector<pid_t> robots;
  const pid_t world = StartSwarm(out, Domain(), robots);
  ASSERT_EQ(robots.size(), 4u) << "the swarm did not start its robots";
  std::this_thread::sleep_for(1s);  // running, past discovery
  ASSERT_EQ(kill(world, SIGKILL), 0);
  ASSERT_EQ(waitpid(world, nullptr, 0), world);
  // Every robot dies with the world (PR_SET_PDEATHSIG): reaped here within
  // a few seconds, each by SIGKILL.
  for (const pid_t robot : robots) {
    int status = 0;
    pid_t done = 0;
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while ((done = waitpid(robot, &status, WNOHANG)) == 0 && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(20ms);
    }
    ASSERT_EQ(done, robot) << "robot " << robot << " outlived the world";
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  }
  ASSERT_EQ(prctl(PR_SET_CHILD_SUBREAPER, 0), 0);
  std::filesystem::remove_all(out);
}

TEST(SwarmCommandTest, CtrlCStopsTheWorldAndItsRobotsCleanlyAndWritesMetrics) {
  const std::string out = (std::filesystem::temp_directory_path() / ("syrof_swarm_int_" + std::to_string(getpid()))).string();
  std::vector<pid_t> robots;
  const pid_t world = StartSwarm(out, std::to_string(100 + (getpid() + 50) % 100), robots);
  ASSERT_EQ(robots.size(), 4u) << "the swarm did not start its robots";
  std::this_thread::sleep_for(2s);
  ASSERT_EQ(kill(world, SIGINT), 0);
  int status = 0;
  pid_t done = 0;
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while ((done = waitpid(world, &status, WNOHANG)) == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(20ms);
  }
  ASSERT_EQ(done, world) << "syrof swarm did not stop on SIGINT";
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(out) / "metrics.json"));
  for (const pid_t robot : robots) EXPECT_EQ(kill(robot, 0), -1) << "robot " << robot << " is still there";
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace syrof::cli
