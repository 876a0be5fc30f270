// Hostile submissions against the build sandbox (grader/src/build.cpp;
// docs/grading.md, "Threat model"). Each submission attacks from its
// CMakeLists.txt (reads, writes, a daemon, links placed in the folder) and
// then builds the gather reference as usual: it must be graded as usual
// while its attack fails. The canary and the victims are readable and
// writable by every uid, so the file permissions alone would not stop the
// attacks: what stops them is Landlock (and, as root, uid 65534).
#include <gtest/gtest.h>
#include <arpa/inet.h>
#include <dirent.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "syrof/process/landlock.h"
#include "syrof/assignment/assignment.h"
#include "syrof/grader/build.h"
#include "syrof/grader/class_grading.h"
#include "syrof/grader/grade.h"
#include "syrof/grader/grade_json.h"
#include "syrof/grader/outputs.h"

namespace syrof::grader {
namespace {

namespace fs = std::filesystem;
using assignment::Assignment;
using assignment::SubmissionResult;

const fs::path kTiny = fs::path(SYROF_TEST_DATA_DIR) / "tiny";
const fs::path kAssignments = fs::path(SYROF_ASSIGNMENTS_DIR);
const fs::path kReference = kAssignments / "gather" / "reference";
// What no output of the grader may ever hold.
const std::string kCanaryText = "CANARY-8c1f2e-the-hidden-answer";
const std::string kSecretEnv = "SECRET-ENV-71d0b4";
// A line of assignments/gather/hidden/gather_10_join.yaml.
const std::string kGatherHiddenLine = "robot 9 is switched on at 8 s";

fs::path Fresh(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("hostile_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::permissions(dir, fs::perms::all);  // 0777: the file permissions stop nothing
  return dir;
}

void Write(const fs::path& path, const std::string& text, fs::perms perms = fs::perms::all) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
  fs::permissions(path, perms);
}

std::string Read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

Assignment LoadTiny() {
  const assignment::LoadResult loaded = assignment::LoadAssignmentFile((kTiny / "assignment.yaml").string());
  EXPECT_TRUE(loaded.ok()) << (loaded.error ? loaded.error->ToString() : "");
  return loaded.ok() ? *loaded.assignment : Assignment{};
}

// The files under `dir` (recursively) that hold `text`.
std::vector<std::string> FilesHolding(const fs::path& dir, const std::string& text) {
  std::vector<std::string> found;
  std::error_code error;
  for (fs::recursive_directory_iterator it(dir, error); !error && it != fs::recursive_directory_iterator();
       it.increment(error)) {
    if (it->is_regular_file(error) && Read(it->path()).find(text) != std::string::npos) {
      found.push_back(it->path().string());
    }
  }
  return found;
}

// Processes whose command line holds `marker`.
int ProcessesWith(const std::string& marker) {
  int count = 0;
  if (DIR* proc = opendir("/proc")) {
    while (const dirent* entry = readdir(proc)) {
      if (entry->d_name[0] < '0' || entry->d_name[0] > '9') continue;
      std::string command = Read(fs::path("/proc") / entry->d_name / "cmdline");
      for (char& c : command) c = c == '\0' ? ' ' : c;
      if (command.find(marker) != std::string::npos) ++count;
    }
    closedir(proc);
  }
  return count;
}

// This process's children that still hold a build's tmpfs (in their mount
// namespace: no mount of this process shows it).
int ChildrenHoldingABuildFolder() {
  int count = 0;
  if (DIR* proc = opendir("/proc")) {
    while (const dirent* entry = readdir(proc)) {
      if (entry->d_name[0] < '0' || entry->d_name[0] > '9') continue;
      const std::string stat = Read(fs::path("/proc") / entry->d_name / "stat");
      const size_t close_paren = stat.rfind(')');
      if (close_paren == std::string::npos) continue;
      std::istringstream rest(stat.substr(close_paren + 2));
      char state = 0;
      pid_t parent = 0;
      rest >> state >> parent;
      if (parent != getpid()) continue;
      if (Read(fs::path("/proc") / entry->d_name / "mountinfo").find("syrof-build") != std::string::npos) ++count;
    }
    closedir(proc);
  }
  return count;
}

// A submission: the gather reference's source, and a CMakeLists.txt that
// runs `attack` (CMake commands) before building it as syrof new does.
void AttackingSubmission(const fs::path& folder, const std::string& attack) {
  fs::create_directories(folder);
  fs::copy_file(kReference / "gather.c", folder / "gather.c");
  Write(folder / "CMakeLists.txt",
        "cmake_minimum_required(VERSION 3.16)\n"
        "project(gather LANGUAGES C)\n"
        "find_package(SyROF REQUIRED)\n"
        "function(attempt what)\n"
        "  execute_process(COMMAND sh -c \"${what}\" OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)\n"
        "  message(STATUS \"attempt [${what}] -> ${rc}: ${out} ${err}\")\n"
        "endfunction()\n" +
            attack + "\nsyrof_add_app(gather gather.c)\n");
}

class HostileBuildTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (process::LandlockAbi() == 0) GTEST_SKIP() << "no Landlock on this kernel: syrof grade refuses to build";
    outside_ = Fresh("outside");
    canary_ = outside_ / "canary.txt";
    Write(canary_, kCanaryText + "\n");
  }

  SubmissionResult Grade(const fs::path& submission, const fs::path& out) {
    std::vector<std::string> notes;
    GradeOptions options;
    options.jobs = 2;
    SubmissionResult result = GradeSubmission(LoadTiny(), submission.string(), out.string(), options, notes);
    const std::string hash = InputsHash(submission.string(), kTiny.string(), result.public_only);
    EXPECT_EQ(WriteSubmissionOutputs(result, hash, notes, out.string()), std::nullopt);
    return result;
  }

  void ExpectGradedAsUsual(const SubmissionResult& result, const fs::path& out) {
    EXPECT_EQ(result.build.verdict, assignment::BuildVerdict::kOk) << result.build.detail << "\n" << Read(out / "build.log");
    EXPECT_EQ(result.points, 60) << "the attack costs nothing and earns nothing";
  }

  fs::path outside_;
  fs::path canary_;
};

TEST_F(HostileBuildTest, ReadsOutsideItsCopyFindNothingAndTheGradeIsAsUsual) {
  setenv("SYROF_TEST_SECRET", kSecretEnv.c_str(), 1);
  const fs::path submission = Fresh("nosy_in");
  // Links placed in the submission itself: copied as neither.
  fs::create_symlink(canary_, submission / "symlink.txt");
  std::error_code linked;
  fs::create_hard_link(canary_, submission / "hardlink.txt", linked);
  const fs::path tree = fs::path(SYROF_SOURCE_DIR);
  AttackingSubmission(
      submission,
      "attempt(\"cat " + canary_.string() + "\")\n" +
          "attempt(\"cat symlink.txt hardlink.txt; cat ${CMAKE_SOURCE_DIR}/symlink.txt ${CMAKE_SOURCE_DIR}/hardlink.txt\")\n" +
          "attempt(\"cat " + (kTiny / "hidden" / "tiny_hidden.yaml").string() + " " +
          (kTiny / "assignment.yaml").string() + "\")\n" +
          "attempt(\"cat " + (kAssignments / "gather" / "hidden" / "gather_10_join.yaml").string() + "\")\n" +
          "attempt(\"ls " + (kAssignments / "gather").string() + " " + tree.string() + "\")\n" +
          "attempt(\"cat /proc/1/environ /proc/" + std::to_string(getpid()) + "/environ /proc/" +
          std::to_string(getppid()) + "/environ\")\n" +
          "attempt(\"env; id\")\n" +
          "attempt(\"ls /root /home /tmp; cat /etc/shadow\")\n" +
          "if(EXISTS " + canary_.string() + ")\n  file(READ " + canary_.string() +
          " stolen)\n  message(STATUS \"stolen: ${stolen}\")\nendif()\n");
  fs::permissions(submission / "CMakeLists.txt", fs::perms::all);
  const fs::path out = Fresh("nosy_out");
  const SubmissionResult result = Grade(submission, out);
  unsetenv("SYROF_TEST_SECRET");

  // file(READ) of the canary is a CMake error: the build fails on it, with
  // the denial (not the text) in its detail. Everything else was tried first.
  const std::string log = Read(out / "build.log");
  EXPECT_EQ(result.build.verdict, assignment::BuildVerdict::kBuildFailed) << result.build.detail << "\n" << log;
  EXPECT_NE(result.build.detail.find("Permission denied"), std::string::npos) << result.build.detail;
  EXPECT_NE(log.find("attempt [env; id] -> 0"), std::string::npos) << "the attempts ran: " << log;
  EXPECT_EQ(FilesHolding(out, kCanaryText), std::vector<std::string>{}) << log;
  EXPECT_EQ(FilesHolding(out, kSecretEnv), std::vector<std::string>{}) << log;
  EXPECT_EQ(FilesHolding(out, "Hidden: the same with three robots"), std::vector<std::string>{})
      << "the hidden scenario's text leaked";
  EXPECT_EQ(FilesHolding(out, kGatherHiddenLine), std::vector<std::string>{}) << "the source tree's assignments leaked";
  EXPECT_EQ(log.find("SYROF_TEST_SECRET"), std::string::npos);
  EXPECT_NE(log.find("left out symlink.txt (a symbolic link)"), std::string::npos) << log;
  if (!linked) {
    EXPECT_NE(log.find("left out hardlink.txt (a hard link to another file)"), std::string::npos) << log;
  }
  if (geteuid() == 0) {
    EXPECT_NE(log.find("uid=65534"), std::string::npos) << "the build runs as nobody: " << log;
  }
  EXPECT_EQ(log.find("uid=0("), std::string::npos) << log;
}

// A listening socket on the loopback: the build's network namespace has
// its own (down) loopback, so nothing reaches this one.
class Listener {
 public:
  Listener() {
    fd_ = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (bind(fd_, reinterpret_cast<sockaddr*>(&address), length) == 0 && listen(fd_, 4) == 0 &&
        getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
      port_ = ntohs(address.sin_port);
    }
  }
  ~Listener() { close(fd_); }
  int port() const { return port_; }
  bool Connected() const {
    const int client = accept(fd_, nullptr, nullptr);
    if (client >= 0) close(client);
    return client >= 0;
  }

 private:
  int fd_ = -1;
  int port_ = 0;
};

TEST_F(HostileBuildTest, TheSameReadsWithoutTheFatalOneAreGradedInFull) {
  const Listener listener;
  ASSERT_NE(listener.port(), 0);
  const fs::path submission = Fresh("quiet_nosy_in");
  AttackingSubmission(submission, "attempt(\"cat " + canary_.string() + " " +
                                      (kTiny / "hidden" / "tiny_hidden.yaml").string() + "\")\n"
                                      "attempt(\"id\")\n"
                                      "file(DOWNLOAD http://127.0.0.1:" + std::to_string(listener.port()) +
                                      "/leak ${CMAKE_BINARY_DIR}/leak STATUS status TIMEOUT 3)\n"
                                      "message(STATUS \"download: ${status}\")\n");
  const fs::path out = Fresh("quiet_nosy_out");
  const SubmissionResult result = Grade(submission, out);
  ExpectGradedAsUsual(result, out);
  const std::string log = Read(out / "build.log");
  EXPECT_NE(log.find("Permission denied"), std::string::npos) << log;
  EXPECT_EQ(FilesHolding(out, kCanaryText), std::vector<std::string>{});
  EXPECT_TRUE(fs::exists(out / "source" / "CMakeLists.txt")) << "the grader keeps what it built";
  EXPECT_FALSE(listener.Connected()) << "the build reached the grader's loopback";
  EXPECT_NE(log.find("-- download: 7;"), std::string::npos) << "curl's 'could not connect': " << log;
}

TEST_F(HostileBuildTest, WritesAndRemovesOutsideItsCopyChangeNothing) {
  const fs::path victim = outside_ / "victim.txt";
  const fs::path doomed = outside_ / "doomed.txt";
  Write(victim, "untouched\n");
  Write(doomed, "still here\n");
  const fs::path out = Fresh("vandal_out");
  const fs::path assignment_copy = Fresh("vandal_assignment");
  Write(assignment_copy / "assignment.yaml", "points: 60\n");
  const fs::path submission = Fresh("vandal_in");
  AttackingSubmission(
      submission,
      "attempt(\"echo pwned > " + victim.string() + "\")\n" +
          "attempt(\"rm -f " + doomed.string() + "\")\n" +
          "attempt(\"echo 'points: 1000' > " + (assignment_copy / "assignment.yaml").string() + "\")\n" +
          "attempt(\"mkdir -p " + (out / "runs").string() + "; echo '{}' > " + (out / "grade.json").string() +
          "\")\n" + "attempt(\"echo x > /tmp/syrof-hostile-" + std::to_string(getpid()) + "\")\n" +
          "attempt(\"ln -s " + victim.string() + " ${CMAKE_BINARY_DIR}/link; echo pwned > ${CMAKE_BINARY_DIR}/link\")\n" +
          "attempt(\"ln " + victim.string() + " ${CMAKE_BINARY_DIR}/hard; echo pwned >> ${CMAKE_BINARY_DIR}/hard\")\n");
  const SubmissionResult result = Grade(submission, out);
  ExpectGradedAsUsual(result, out);
  EXPECT_EQ(Read(victim), "untouched\n");
  EXPECT_TRUE(fs::exists(doomed));
  EXPECT_EQ(Read(assignment_copy / "assignment.yaml"), "points: 60\n");
  EXPECT_FALSE(fs::exists("/tmp/syrof-hostile-" + std::to_string(getpid())));
  EXPECT_NE(Read(out / "grade.json"), "{}\n") << "grade.json is the grader's";
}

TEST_F(HostileBuildTest, ADaemonTheBuildStartsDiesBeforeAnyRun) {
  const std::string marker = "31.4159" + std::to_string(getpid() % 1000);
  const fs::path submission = Fresh("daemon_in");
  // Double fork, a session of its own, output away from the build's pipe.
  AttackingSubmission(submission, "attempt(\"setsid sh -c 'sleep " + marker +
                                      "' </dev/null >/dev/null 2>&1 & (sleep " + marker +
                                      " </dev/null >/dev/null 2>&1 &) ; echo started\")\n");
  const fs::path out = Fresh("daemon_out");
  std::vector<std::string> notes;
  const assignment::BuildResult build = BuildSubmission(submission.string(), out.string(), {}, notes);
  EXPECT_EQ(build.verdict, assignment::BuildVerdict::kOk) << build.detail << "\n" << Read(out / "build.log");
  EXPECT_NE(Read(out / "build.log").find("started"), std::string::npos) << Read(out / "build.log");
  EXPECT_EQ(ProcessesWith("sleep " + marker), 0) << "a process of the build outlived it";
  for (const std::string& note : notes) EXPECT_EQ(note.find("PID namespace"), std::string::npos) << note;
}

// A UNIX socket named in the file system (an X server's, a container
// runtime's) is reachable from any network namespace, and Landlock's file
// rights do not cover connecting to it: the build's system call filter
// refuses socket(2). The probe is compiled and run by the build itself.
TEST_F(HostileBuildTest, AUnixSocketOnTheMachineIsOutOfReach) {
  const fs::path socket_path = outside_ / "service.sock";
  const int listener = socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::snprintf(address.sun_path, sizeof address.sun_path, "%s", socket_path.c_str());
  ASSERT_EQ(bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(listen(listener, 4), 0);
  fs::permissions(socket_path, fs::perms::all);
  const fs::path submission = Fresh("unix_in");
  Write(submission / "probe.c",
        "#include <errno.h>\n#include <stdio.h>\n#include <string.h>\n#include <sys/socket.h>\n"
        "#include <sys/un.h>\nint main(int argc, char** argv) {\n"
        "  int fd = socket(AF_UNIX, SOCK_STREAM, 0);\n"
        "  if (fd < 0) { printf(\"probe: socket: %s\\n\", strerror(errno)); return 0; }\n"
        "  struct sockaddr_un a = {0}; a.sun_family = AF_UNIX; strncpy(a.sun_path, argv[1], sizeof a.sun_path - 1);\n"
        "  int rc = connect(fd, (struct sockaddr*)&a, sizeof a);\n"
        "  printf(\"probe: connect: %s\\n\", rc == 0 ? \"connected\" : strerror(errno));\n  return 0;\n}\n");
  AttackingSubmission(submission, "execute_process(COMMAND ${CMAKE_C_COMPILER} ${CMAKE_SOURCE_DIR}/probe.c -o "
                                  "${CMAKE_BINARY_DIR}/probe)\n"
                                  "attempt(\"${CMAKE_BINARY_DIR}/probe " + socket_path.string() + "\")\n");
  const fs::path out = Fresh("unix_out");
  std::vector<std::string> notes;
  const assignment::BuildResult build = BuildSubmission(submission.string(), out.string(), {}, notes);
  const std::string log = Read(out / "build.log");
  EXPECT_EQ(build.verdict, assignment::BuildVerdict::kOk) << build.detail << "\n" << log;
  EXPECT_NE(log.find("probe: socket: Permission denied"), std::string::npos) << log;
  const int client = accept(listener, nullptr, nullptr);
  EXPECT_LT(client, 0) << "the build connected to " << socket_path;
  if (client >= 0) close(client);
  close(listener);
}

TEST_F(HostileBuildTest, ABuildInAClassCannotReadItsSiblings) {
  const fs::path class_dir = Fresh("class_in");
  const fs::path bob = class_dir / "bob";
  fs::create_directories(bob);
  fs::copy_file(kReference / "gather.c", bob / "gather.c");
  Write(bob / "answer.txt", kCanaryText + "\n");
  AttackingSubmission(class_dir / "alice", "attempt(\"cat " + (bob / "answer.txt").string() + " ../bob/answer.txt; ls " +
                                               class_dir.string() + "\")\n");
  const fs::path out = Fresh("class_out");
  ClassOptions options;
  options.jobs = 2;
  options.assignment_dir = kTiny.string();
  const ClassResult result = GradeClass(LoadTiny(), class_dir.string(), out.string(), options);
  ASSERT_EQ(result.students.size(), 2u);
  for (const SubmissionResult& student : result.students) EXPECT_EQ(student.points, 60) << student.submission;
  EXPECT_EQ(FilesHolding(out / "alice", kCanaryText), std::vector<std::string>{});
  EXPECT_NE(Read(out / "alice" / "build.log").find("Permission denied"), std::string::npos);
}

// A file the grader has open without close-on-exec (a hidden scenario read
// through a stream, another job's file at the moment of a fork) is no
// descriptor of the build's: it starts with 0-2 only.
TEST_F(HostileBuildTest, ADescriptorTheGraderHasOpenIsNotTheBuilds) {
  int inherited = open(canary_.c_str(), O_RDONLY);  // no O_CLOEXEC, on purpose
  ASSERT_GE(inherited, 0);
  // On a number the shell can name (the finding's 7 when it is free).
  int number = 7;
  while (number < 10 && fcntl(number, F_GETFD) != -1) ++number;
  ASSERT_LT(number, 10) << "no free descriptor below 10";
  ASSERT_EQ(dup2(inherited, number), number);
  close(inherited);
  const fs::path submission = Fresh("descriptor_in");
  AttackingSubmission(submission, "attempt(\"cat <&" + std::to_string(number) +
                                      "; for n in 3 4 5 6 7 8 9; do eval \\\"cat <&$n\\\"; done\")\n");
  const fs::path out = Fresh("descriptor_out");
  const SubmissionResult result = Grade(submission, out);
  close(number);
  ExpectGradedAsUsual(result, out);
  const std::string log = Read(out / "build.log");
  EXPECT_NE(log.find("attempt [cat <&" + std::to_string(number)), std::string::npos) << "the attempt ran: " << log;
  EXPECT_NE(log.find("Bad file descriptor"), std::string::npos) << log;
  EXPECT_EQ(FilesHolding(out, kCanaryText), std::vector<std::string>{}) << log;
}

// A build that tries to write 10 GB (twenty 512 MB files, each under the
// per-file limit) stops at its folder's bound, 32 MB here: it fails with a
// reason that says so, and the student graded beside it at the same time
// gets full marks. Nothing of the bound is left mounted afterwards.
TEST_F(HostileBuildTest, ABuildThatWritesTenGigabytesStopsAtItsBoundAndTheClassGradesOn) {
  const fs::path class_dir = Fresh("filler_class_in");
  AttackingSubmission(class_dir / "alice",
                      "attempt(\"for i in $(seq 1 20); do head -c 536870912 /dev/zero > big$i; done; "
                      "du -sk . ${CMAKE_BINARY_DIR}\")\n");
  fs::create_directories(class_dir / "bob");
  fs::copy_file(kReference / "gather.c", class_dir / "bob" / "gather.c");
  const fs::path out = Fresh("filler_class_out");
  ClassOptions options;
  options.jobs = 2;
  options.assignment_dir = kTiny.string();
  options.grade.build.work_limit_bytes = 32ull << 20;
  const ClassResult result = GradeClass(LoadTiny(), class_dir.string(), out.string(), options);

  ASSERT_EQ(result.students.size(), 2u);
  for (const SubmissionResult& student : result.students) {
    const std::string log = Read(out / fs::path(student.submission).filename() / "build.log");
    if (fs::path(student.submission).filename() == "alice") {
      EXPECT_EQ(student.build.verdict, assignment::BuildVerdict::kBuildFailed) << student.build.detail << "\n" << log;
      EXPECT_NE(student.build.detail.find("more than its folder holds (32 MB"), std::string::npos)
          << student.build.detail;
      EXPECT_NE(log.find("the build filled its folder (32 MB"), std::string::npos) << log;
      EXPECT_NE(log.find("No space left on device"), std::string::npos) << log;
      EXPECT_EQ(student.points, 0);
    } else {
      EXPECT_EQ(student.build.verdict, assignment::BuildVerdict::kOk) << student.build.detail << "\n" << log;
      EXPECT_EQ(student.points, 60) << student.submission;
    }
  }
  EXPECT_EQ(ChildrenHoldingABuildFolder(), 0) << "a build's tmpfs outlived it";
}

// SyROF in a folder only root may enter (a CI clone made with mktemp -d, a
// home folder): the build, as uid 65534, still reads the package, since it
// reads the copy in its stage.
TEST(BuildSubmissionPackageTest, SyrofInAFolderOnlyRootEntersStillBuilds) {
  const fs::path hidden_away = fs::path(::testing::TempDir()) / ("private_syrof_" + std::to_string(getpid()));
  fs::remove_all(hidden_away);
  fs::create_directories(hidden_away / "package");
  for (const char* file : {"SyROFConfig.cmake", "SyROFConfigVersion.cmake", "SyROFAddApp.cmake"}) {
    fs::copy_file(fs::path(SYROF_PACKAGE_DIR) / file, hidden_away / "package" / file);
  }
  fs::permissions(hidden_away, fs::perms::owner_all);  // 0700
  const fs::path out = Fresh("private_syrof_out");
  BuildOptions options;
  options.syrof_dir = (hidden_away / "package").string();
  std::vector<std::string> notes;
  const assignment::BuildResult build = BuildSubmission(kReference.string(), out.string(), options, notes);
  EXPECT_EQ(build.verdict, assignment::BuildVerdict::kOk) << build.detail << "\n" << Read(out / "build.log");
  EXPECT_NE(Read(out / "build.log").find("-DSyROF_DIR=package "), std::string::npos) << Read(out / "build.log");
  fs::remove_all(hidden_away);
}

TEST(BuildWithoutLandlockTest, IsRefusedUnlessTheInstructorSaysSo) {
  setenv("SYROF_PRETEND_NO_LANDLOCK", "1", 1);
  const fs::path out = Fresh("refused_out");
  std::vector<std::string> notes;
  const assignment::BuildResult refused = BuildSubmission(kReference.string(), out.string(), {}, notes);
  EXPECT_EQ(refused.verdict, assignment::BuildVerdict::kRefused);
  EXPECT_NE(refused.detail.find("--unsafe-no-file-isolation"), std::string::npos) << refused.detail;
  EXPECT_FALSE(fs::exists(out / "source")) << "nothing of the submission was touched";
  BuildOptions unsafe;
  unsafe.allow_unconfined = true;
  const assignment::BuildResult built = BuildSubmission(kReference.string(), out.string(), unsafe, notes);
  unsetenv("SYROF_PRETEND_NO_LANDLOCK");
  EXPECT_EQ(built.verdict, assignment::BuildVerdict::kOk) << built.detail;
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes[0].find("NO FILE ISOLATION"), std::string::npos) << notes[0];
}

}  // namespace
}  // namespace syrof::grader
