// Building a submission: copy, generate a CMakeLists.txt for sources-only
// folders, run CMake in a sandboxed child, find the app library.
#include "syrof/grader/build.h"

#include <fcntl.h>
#include <linux/filter.h>
#include <poll.h>
#include <seccomp.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <variant>

#include "syrof/app_host/hosted_app.h"
#include "syrof/lab/base/error.h"
#include "syrof/process/confine.h"
#include "syrof/process/fd.h"
#include "syrof/process/landlock.h"
#include "syrof/process/spawn.h"
#include "syrof/process/tmpfs_holder.h"
#include "shared_text.h"

namespace syrof::grader {
namespace {

namespace fs = std::filesystem;
using assignment::BuildResult;
using assignment::BuildVerdict;
using Clock = std::chrono::steady_clock;
using process::FileRuleset;

using process::SandboxFailure;

// A step's failure: the words go whole into the build's detail and log.
lab::Error Failure(std::string message) { return lab::Error{.where = "", .message = std::move(message)}; }

// The uid and gid a build started by root runs as (nobody, nogroup).
constexpr uid_t kBuildUid = process::kNobodyUid;
constexpr gid_t kBuildGid = process::kNobodyGid;

bool IsSource(const fs::path& path) {
  const std::string extension = path.extension().string();
  return extension == ".c" || extension == ".cc" || extension == ".cpp" || extension == ".cxx";
}

// Folders a copy and the source scan leave out: hidden ones (.git) and a
// student's own build folders.
bool SkippedFolder(const fs::path& name) {
  const std::string text = name.string();
  return text.empty() || text[0] == '.' || text == "build" || text.starts_with("cmake-build");
}

// Opens `path` for reading when it is a regular file with one link (not a
// symbolic link, not a hard link to a file elsewhere), checked on the open
// file so that what is read is what was checked. -1 otherwise.
int OpenPlainFile(const fs::path& path, struct stat& status) {
  // O_NONBLOCK: a FIFO in its place cannot hold the open up.
  const int fd = open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return -1;
  if (fstat(fd, &status) != 0 || !S_ISREG(status.st_mode) || status.st_nlink != 1) {
    close(fd);
    return -1;
  }
  return fd;
}

// Copies what `fd` holds into the new file `to` (0644), then closes `fd`.
bool CopyOpenFile(int fd, const fs::path& to) {
  const int copy = open(to.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
  bool ok = copy >= 0;
  char buffer[65536];
  for (ssize_t got; ok && (got = read(fd, buffer, sizeof buffer)) != 0;) {
    if (got < 0) {
      ok = errno == EINTR;
      continue;
    }
    ok = write(copy, buffer, static_cast<size_t>(got)) == got;
  }
  close(fd);
  if (copy >= 0) close(copy);
  return ok;
}

// Copies regular files only, at most `max_bytes` in all. Symbolic links,
// files with more than one hard link (a link to a file elsewhere on the
// machine, which this process, often root, could read), devices and FIFOs
// are left out, each named in `skipped`. Returns what went wrong, if anything.
std::optional<lab::Error> CopySubmission(const fs::path& from, const fs::path& to, uint64_t max_bytes,
                                         std::vector<std::string>& skipped) {
  std::error_code error;
  fs::remove_all(to, error);
  fs::create_directories(to, error);
  if (error) return Failure("cannot create " + to.string() + ": " + error.message());
  uint64_t total = 0;
  fs::recursive_directory_iterator it(from, fs::directory_options::none, error);
  if (error) return Failure("cannot read " + from.string() + ": " + error.message());
  for (; it != fs::recursive_directory_iterator(); it.increment(error)) {
    if (error) return Failure("cannot read " + from.string() + ": " + error.message());
    const fs::directory_entry& entry = *it;
    const fs::path relative = entry.path().lexically_relative(from);
    if (entry.is_symlink(error)) {
      skipped.push_back(relative.generic_string() + " (a symbolic link)");
      continue;
    }
    if (entry.is_directory(error)) {
      if (SkippedFolder(entry.path().filename())) {
        it.disable_recursion_pending();
        continue;
      }
      fs::create_directories(to / relative, error);
      continue;
    }
    if (!entry.is_regular_file(error)) {
      skipped.push_back(relative.generic_string() + " (not a regular file)");
      continue;
    }
    struct stat status {};
    const int fd = OpenPlainFile(entry.path(), status);
    if (fd < 0) {
      skipped.push_back(relative.generic_string() + " (a hard link to another file)");
      continue;
    }
    total += static_cast<uint64_t>(status.st_size);
    if (total > max_bytes) {
      close(fd);
      return Failure("the submission holds more than " + std::to_string(max_bytes >> 20) + " MB of files");
    }
    if (!CopyOpenFile(fd, to / relative)) {
      return Failure("cannot copy " + relative.string() + ": " + std::strerror(errno));
    }
  }
  return std::nullopt;
}

std::string GeneratedCMakeLists(const std::vector<std::string>& sources) {
  const bool cxx = std::any_of(sources.begin(), sources.end(), [](const std::string& s) {
    return !s.ends_with(".c");
  });
  std::ostringstream text;
  text << "# Written by syrof grade: the submission has no CMakeLists.txt, so every\n"
          "# C/C++ source becomes one app library linked to SyROF::app.\n"
          "cmake_minimum_required(VERSION 3.16)\n"
          "project(submission LANGUAGES C"
       << (cxx ? " CXX" : "")
       << ")\n"
          "find_package(SyROF REQUIRED)\n"
          "add_library(submission MODULE\n";
  for (const std::string& source : sources) text << "  \"" << source << "\"\n";
  text << ")\n"
          "target_include_directories(submission PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})\n"
          "target_link_libraries(submission PRIVATE SyROF::app m)\n"
          "set_target_properties(submission PROPERTIES C_STANDARD 11 CXX_STANDARD 20)\n";
  return text.str();
}

// The build's output: the first `keep` bytes go to the log, the rest are
// counted.
struct OutputLog {
  std::ofstream file;
  uint64_t keep = 0;
  uint64_t total = 0;
  uint64_t kept = 0;
  void Add(const char* data, size_t size) {
    total += size;
    if (kept < keep) {
      const size_t take = static_cast<size_t>(std::min<uint64_t>(size, keep - kept));
      file.write(data, static_cast<std::streamsize>(take));
      kept += take;
    }
  }
};

// The build's system call filter, as a BPF program made with libseccomp in
// the parent (the child only installs it): everything is allowed but
// socket(2), refused with EACCES, and io_uring_setup(2), refused with
// ENOSYS (its requests could open sockets past the filter). The network
// namespace already leaves no interface; this closes UNIX sockets named in
// the file system (an X server's, a container runtime's), which neither
// the namespace nor Landlock's file rights cover. Compilers and CMake open
// no socket. Empty when libseccomp fails.
std::vector<sock_filter> BuildSyscallFilter() {
  std::vector<sock_filter> program;
  scmp_filter_ctx filter = seccomp_init(SCMP_ACT_ALLOW);
  if (filter == nullptr) return program;
  const int memory = memfd_create("syrof-build-filter", MFD_CLOEXEC);
  if (memory >= 0 && seccomp_attr_set(filter, SCMP_FLTATR_CTL_NNP, 0) == 0 &&
      seccomp_rule_add(filter, SCMP_ACT_ERRNO(EACCES), SCMP_SYS(socket), 0) == 0 &&
      seccomp_rule_add(filter, SCMP_ACT_ERRNO(ENOSYS), SCMP_SYS(io_uring_setup), 0) == 0 &&
      seccomp_export_bpf(filter, memory) == 0) {
    const off_t bytes = lseek(memory, 0, SEEK_END);
    if (bytes > 0 && bytes % static_cast<off_t>(sizeof(sock_filter)) == 0) {
      program.resize(static_cast<size_t>(bytes) / sizeof(sock_filter));
      if (pread(memory, program.data(), static_cast<size_t>(bytes), 0) != bytes) program.clear();
    }
  }
  if (memory >= 0) close(memory);
  seccomp_release(filter);
  return program;
}

// The build's sandbox as far as the options say: uid 65534 when root, the
// limits, the system call filter, and `files` (made and filled later; not
// created: no Landlock). The size-limited folder's namespaces come later.
process::Sandbox BuildSandbox(const BuildOptions& options, const FileRuleset& files) {
  process::Sandbox sandbox;
  sandbox.drop_to_nobody = geteuid() == 0;
  sandbox.limits = {{RLIMIT_FSIZE, options.file_size_limit_bytes},
                    {RLIMIT_CPU, options.cpu_limit_s},
                    {RLIMIT_CORE, 0},
                    {RLIMIT_NPROC, options.max_processes}};
  sandbox.files = &files;
  sandbox.syscalls = BuildSyscallFilter();
  return sandbox;
}

// How one step of the build ended.
struct StepOutcome {
  bool started = false;
  bool timed_out = false;
  bool output_limit = false;
  process::ExitStatus status;        // when it ended on its own (not timed out, not over the output limit)
  process::SandboxReport sandbox;    // what the child could set up, as it reported before exec
};

// Runs `command` confined by `sandbox` (process::Spawn: its own process
// group, namespaces, uid 65534 when root, limits, no_new_privs, Landlock,
// the system call filter; in a PID namespace under a small init, so no
// process of the build outlives it) until it ends or `deadline`, its output
// and errors to `log`. Stopped once it writes over `output_limit_bytes`.
// Whatever it leaves in its process group is killed when it ends.
StepOutcome RunStep(process::Command command, const process::Sandbox& sandbox, uint64_t output_limit_bytes,
                    Clock::time_point deadline, OutputLog& log) {
  StepOutcome outcome;
  int ends[2];
  if (pipe2(ends, O_CLOEXEC) != 0) return outcome;
  const process::Fd output(ends[0]);
  process::Fd output_write(ends[1]);
  command.descriptors = {{1, output_write.get()}, {2, output_write.get()}};
  process::Child child = process::Spawn(command, sandbox);
  output_write.Reset();
  if (!child.started()) return outcome;
  outcome.started = true;
  outcome.sandbox = child.sandbox();
  bool exited = false;
  bool output_open = true;
  char buffer[65536];
  while (output_open || !exited) {
    const auto now = Clock::now();
    if (now >= deadline) {
      outcome.timed_out = true;
      break;
    }
    const int wait_ms = static_cast<int>(
        std::min<int64_t>(1000, std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now).count() + 1));
    pollfd fds[2];
    nfds_t count = 0;
    if (output_open) fds[count++] = {output.get(), POLLIN, 0};
    const int pidfd = exited ? -1 : child.pidfd();
    if (pidfd >= 0) fds[count++] = {pidfd, POLLIN, 0};
    if (count == 0) break;
    const int ready = poll(fds, count, wait_ms);
    if (ready < 0 && errno != EINTR) break;
    // (Without a pidfd the child is looked at after each poll.)
    if (!exited && (pidfd < 0 || (count > 0 && fds[count - 1].fd == pidfd && fds[count - 1].revents != 0)) &&
        child.Wait(std::chrono::milliseconds(0)).has_value()) {
      exited = true;
      // Whatever the build left behind in its group goes too; output
      // still in the pipe is read until every writer is gone.
      child.KillGroup();
    }
    if (output_open && (fds[0].revents != 0)) {
      const ssize_t got = read(output.get(), buffer, sizeof buffer);
      if (got > 0) {
        log.Add(buffer, static_cast<size_t>(got));
        if (log.total > output_limit_bytes) {
          outcome.output_limit = true;
          output_open = false;
        }
      } else if (got == 0 || (errno != EINTR && errno != EAGAIN)) {
        output_open = false;
      }
    }
    if (outcome.output_limit) break;
  }
  child.KillGroup();
  // The program's own status (from the namespace's init when there is one):
  // a signal that ended the compiler is named as such.
  const process::ExitStatus status = child.Reap();
  if (!outcome.timed_out && !outcome.output_limit) outcome.status = status;
  return outcome;
}

// The layer of the build's sandbox that did not hold, in words.
std::string FailedLayer(SandboxFailure failure) {
  switch (failure) {
    case SandboxFailure::kUid:
      return "cannot drop to uid " + std::to_string(kBuildUid);
    case SandboxFailure::kLandlock:
      return "Landlock refused the build's file rules";
    case SandboxFailure::kEnterNamespace:
      return "cannot enter its size-limited folder";
    case SandboxFailure::kFilter:
    case SandboxFailure::kNone:
      break;
  }
  return "the system call filter was refused";
}

// The first line of the kept log a student should read: a compiler's
// "error:", else CMake's "CMake Error" with its message, else the last
// non-empty line. The build's temporary stage is cut from paths: its
// work/source/ to the file's own name, work/build/ to build/..., the
// package to package/....
std::string FirstErrorLine(const std::string& log_path, const std::string& stage_root) {
  std::ifstream in(log_path);
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line) && lines.size() < 100000) lines.push_back(line);
  auto clean = [&](std::string text) {
    for (const std::string& cut : {stage_root + "/work/source/", stage_root + "/work/", stage_root + "/"}) {
      for (size_t at = text.find(cut); at != std::string::npos; at = text.find(cut)) text.erase(at, cut.size());
    }
    while (!text.empty() && (text.back() == ' ' || text.back() == '\r')) text.pop_back();
    const size_t first = text.find_first_not_of(' ');
    text = first == std::string::npos ? std::string() : text.substr(first);
    if (text.size() > 300) text = text.substr(0, 297) + "...";
    return text;
  };
  for (const std::string& candidate : lines) {
    if (candidate.find(" error:") != std::string::npos || candidate.find(": fatal error:") != std::string::npos) {
      return clean(candidate);
    }
  }
  for (size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].starts_with("CMake Error")) {
      std::string text = clean(lines[i]);
      for (size_t j = i + 1; j < lines.size() && j < i + 6; ++j) {
        const std::string next = clean(lines[j]);
        if (!next.empty()) return text + " " + next;
      }
      return text;
    }
  }
  for (auto it = lines.rbegin(); it != lines.rend(); ++it) {
    const std::string text = clean(*it);
    if (!text.empty() && !text.starts_with("$ ")) return text;
  }
  return "the build failed without a message";
}

// A command's argument as build.log shows it: the temporary stage left out
// (source, build, package).
std::string Shown(std::string argument, const fs::path& stage_root) {
  for (const std::string& cut : {stage_root.string() + "/work/", stage_root.string() + "/"}) {
    for (size_t at = argument.find(cut); at != std::string::npos; at = argument.find(cut)) argument.erase(at, cut.size());
  }
  return argument;
}

std::string FindOnPath(const std::string& name) {
  for (const char* dir : {"/usr/local/bin", "/usr/bin", "/bin"}) {
    const std::string candidate = std::string(dir) + "/" + name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

// SyROF's CMake package as a student's build reads it, copied into the
// build's stage (`into`, readable by every uid, writable by none but the
// grader): SyROFConfig.cmake with its library and include folders pointing
// at the copies, its version file, SyROFAddApp.cmake, libsyrof_app.so.1 and
// the include folders SyROFConfig.cmake names. So the build reads exactly
// what the package holds and nothing beside it (a build tree's source tree,
// with its assignments/, stays out of reach), and it can read it wherever
// SyROF lies: a build tree in a 0700 folder (a CI clone, a home folder) is
// no obstacle to uid 65534. About 140 KB. An error when the package cannot
// be read.
std::optional<lab::Error> StagePackage(const std::string& syrof_dir, const fs::path& into) {
  const fs::path config = fs::path(syrof_dir) / "SyROFConfig.cmake";
  std::ifstream in(config);
  std::ostringstream text;
  text << in.rdbuf();
  std::string content = text.str();
  std::error_code failed;
  const std::string prefix = fs::weakly_canonical(fs::path(syrof_dir) / ".." / ".." / "..", failed).string();
  for (size_t at = content.find("${_syrof_prefix}"); at != std::string::npos; at = content.find("${_syrof_prefix}")) {
    content.replace(at, std::strlen("${_syrof_prefix}"), prefix);
  }
  // The quoted value of `name` in the config: its position and length.
  auto property = [&](const std::string& name, size_t& begin, size_t& length) {
    const size_t at = content.find(name + " \"");
    if (at == std::string::npos) return false;
    begin = at + name.size() + 2;
    const size_t end = content.find('"', begin);
    length = end == std::string::npos ? 0 : end - begin;
    return length > 0;
  };
  size_t library_at = 0, library_length = 0, includes_at = 0, includes_length = 0;
  if (!in || !property("IMPORTED_LOCATION", library_at, library_length) ||
      !property("INTERFACE_INCLUDE_DIRECTORIES", includes_at, includes_length)) {
    return Failure(config.string() + " is missing or names no IMPORTED_LOCATION or INTERFACE_INCLUDE_DIRECTORIES");
  }
  const fs::path library = content.substr(library_at, library_length);
  std::stringstream list(content.substr(includes_at, includes_length));
  std::string staged_includes;
  fs::create_directories(into / "lib", failed);
  const auto copied = fs::copy_options::overwrite_existing;
  fs::copy_file(library, into / "lib" / "libsyrof_app.so.1", copied, failed);  // the file a symlink names
  if (failed) {
    return Failure("cannot copy " + library.string() + ": " + failed.message());
  }
  int index = 0;
  for (std::string folder; std::getline(list, folder, ';');) {
    if (folder.empty()) continue;
    const fs::path staged = into / "include" / std::to_string(index++);
    fs::create_directories(staged, failed);
    fs::copy(folder, staged, fs::copy_options::recursive | copied, failed);
    if (failed) {
      return Failure("cannot copy " + folder + ": " + failed.message());
    }
    staged_includes += (staged_includes.empty() ? "" : ";") + staged.string();
  }
  for (const char* file : {"SyROFConfigVersion.cmake", "SyROFAddApp.cmake"}) {
    fs::copy_file(fs::path(syrof_dir) / file, into / file, copied, failed);
    if (failed) {
      return Failure("cannot copy " + (fs::path(syrof_dir) / file).string() + ": " + failed.message());
    }
  }
  content.replace(includes_at, includes_length, staged_includes);
  content.replace(library_at, library_length, (into / "lib" / "libsyrof_app.so.1").string());
  std::ofstream(into / "SyROFConfig.cmake", std::ios::binary | std::ios::trunc) << content;
  // Readable by all whatever the grader's umask, writable by none but it.
  fs::permissions(into, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                            fs::perms::others_read | fs::perms::others_exec, failed);
  for (fs::recursive_directory_iterator it(into, failed); !failed && it != fs::recursive_directory_iterator();
       it.increment(failed)) {
    const bool folder = it->is_directory(failed);
    fs::permissions(it->path(),
                    folder ? fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                 fs::perms::others_read | fs::perms::others_exec
                           : fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read |
                                 fs::perms::others_read,
                    failed);
  }
  if (failed) return Failure("cannot stage SyROF's package: " + failed.message());
  return std::nullopt;
}

// The build's ruleset: read and execute the toolchain, read the few /etc
// files compilers and CMake open and SyROF's package, read and write /dev's
// null device and its own `work_dir`. Nothing else (docs/grading.md).
std::optional<lab::Error> BuildFileRules(FileRuleset& rules, const fs::path& package, const fs::path& work_dir) {
  using Access = FileRuleset::Access;
  bool ok = true;
  for (const char* toolchain : {"/usr", "/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32"}) {
    ok = ok && rules.Allow(toolchain, Access::kReadExecute);
  }
  for (const char* etc : {"/etc/ld.so.cache", "/etc/ld.so.conf", "/etc/ld.so.conf.d", "/etc/alternatives",
                          "/etc/localtime", "/etc/nsswitch.conf", "/etc/passwd", "/etc/group"}) {
    ok = ok && rules.Allow(etc, Access::kRead);
  }
  for (const char* device : {"/dev/zero", "/dev/urandom", "/dev/random"}) ok = ok && rules.Allow(device, Access::kRead);
  ok = ok && rules.Allow("/dev/null", Access::kReadWrite);
  ok = ok && rules.Allow(package.string(), Access::kRead);
  ok = ok && rules.Allow(work_dir.string(), Access::kReadWrite);
  if (!ok) return Failure(rules.error());
  return std::nullopt;
}

// Hands `dir` and everything beneath it to the build's uid.
bool HandOver(const fs::path& dir) {
  if (lchown(dir.c_str(), kBuildUid, kBuildGid) != 0) return false;
  std::error_code error;
  for (fs::recursive_directory_iterator it(dir, error); !error && it != fs::recursive_directory_iterator();
       it.increment(error)) {
    if (lchown(it->path().c_str(), kBuildUid, kBuildGid) != 0) return false;
  }
  return !error;
}

// A private folder for one build, removed with its contents when the
// object goes: STAGE (0711, the grader's) / package (SyROF's package, the
// grader's, readable by all: StagePackage) and / work (the build's own:
// source/, build/, tmp/). It lies in /tmp when the build drops to uid 65534
// (which must reach it), else in the system's temporary folder.
class Stage {
 public:
  explicit Stage(bool for_other_uid) {
    const fs::path base = for_other_uid ? fs::path("/tmp") : fs::temp_directory_path(error_);
    std::string pattern = (base / "syrof-build-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) {
      error_ = std::error_code(errno, std::generic_category());
      return;
    }
    root_ = pattern;
    if (for_other_uid) fs::permissions(root_, fs::perms::owner_all | fs::perms::group_exec | fs::perms::others_exec, error_);
    for (const char* folder : {"work/source", "work/build", "work/tmp"}) fs::create_directories(root_ / folder, error_);
  }
  ~Stage() {
    std::error_code ignored;
    if (!root_.empty()) fs::remove_all(root_, ignored);
  }
  Stage(const Stage&) = delete;
  Stage& operator=(const Stage&) = delete;

  bool ok() const { return !error_ && !root_.empty(); }
  std::string problem() const { return "cannot make a folder for the build: " + error_.message(); }
  fs::path root() const { return root_; }
  fs::path package() const { return root_ / "package"; }
  fs::path work() const { return root_ / "work"; }

 private:
  std::error_code error_;
  fs::path root_;
};

// The bound on what a build writes in all: its work folder (the copy,
// build/, tmp/; Landlock lets it write nowhere else) is a tmpfs of
// `limit_bytes` (process::TmpfsHolder: mounted over the stage's work/ in a
// mount namespace of its own, which the build's processes enter before
// anything else; the grader reaches the folder through the holder's
// /proc/PID/root). When the build is done, the mount and everything in it
// are gone.
class WorkMount {
 public:
  WorkMount(const fs::path& work, uint64_t limit_bytes) : holder_(work, limit_bytes, kWorkInodes) {}

  bool ok() const { return holder_.ok(); }
  const std::string& problem() const { return holder_.problem(); }
  /// The work folder as the grader reaches it.
  const fs::path& view() const { return holder_.view(); }
  int user_ns() const { return holder_.user_ns(); }
  int mount_ns() const { return holder_.mount_ns(); }
  uint64_t limit_bytes() const { return holder_.size_bytes(); }
  /// What the folder holds reached the bound (its bytes or its files).
  bool Full() const { return holder_.Full(kFullMarginBytes); }

 private:
  // Files and folders the work folder may hold (a tmpfs inode takes memory
  // that its size does not count); a build makes a few hundred.
  static constexpr uint64_t kWorkInodes = 32768;
  // Less room than this left: the build reached the bound.
  static constexpr uint64_t kFullMarginBytes = 64 << 10;
  process::TmpfsHolder holder_;
};

// Copies the library `from` that the build made to `to`, as the grader's
// own file; false when it is not a plain file.
bool TakeLibrary(const fs::path& from, const fs::path& to) {
  struct stat status {};
  const int fd = OpenPlainFile(from, status);
  return fd >= 0 && CopyOpenFile(fd, to);
}

// Where a build stopped short: its verdict and the line the report shows.
struct Stop {
  BuildVerdict verdict;
  std::string detail;
};

// The sandbox's file rules as the options allow (docs/grading.md, "Threat
// model"): without Landlock nothing is built unless the caller said so.
// What is missing, and allowed, goes to `notes`.
std::optional<Stop> CheckIsolation(const BuildOptions& options, FileRuleset& files, const process::Sandbox& sandbox,
                                   std::ofstream& log, std::vector<std::string>& notes) {
  if (!files.Create()) {
    if (!options.allow_unconfined) {
      log << "syrof grade: " << files.error() << "; not building untrusted code\n";
      return Stop{BuildVerdict::kRefused,
                  files.error() + ": the build's file isolation is missing (--unsafe-no-file-isolation builds anyway)"};
    }
    notes.push_back("build: NO FILE ISOLATION (" + files.error() +
                    "): the build can read and write whatever its uid can (--unsafe-no-file-isolation)");
  }
  if (sandbox.syscalls.empty()) {
    notes.push_back("build: no system call filter (libseccomp failed): UNIX sockets in the file system stay "
                    "within the build's reach");
  }
  return std::nullopt;
}

// The submission copied into the build's `source` folder, a CMakeLists.txt
// generated when it has none, and the copy kept as the grader's own record
// (the build never sees `record`).
std::optional<Stop> CopyIn(const std::string& submission_dir, const fs::path& source, const fs::path& record,
                           uint64_t max_bytes, std::ofstream& log) {
  std::error_code error;
  std::vector<std::string> skipped;
  const std::optional<lab::Error> copy_failed = CopySubmission(submission_dir, source, max_bytes, skipped);
  for (const std::string& file : skipped) log << "syrof grade: left out " << file << "\n";
  if (copy_failed) {
    log << "syrof grade: " << copy_failed->ToString() << "\n";
    return Stop{BuildVerdict::kBuildFailed, copy_failed->ToString()};
  }
  if (!fs::exists(source / "CMakeLists.txt", error)) {
    const std::vector<std::string> sources = FindSources(source.string());
    if (sources.empty()) {
      log << "syrof grade: no CMakeLists.txt and no C/C++ source (*.c, *.cc, *.cpp, *.cxx)\n";
      return Stop{BuildVerdict::kNoSources,
                  "no CMakeLists.txt and no C/C++ source (*.c, *.cc, *.cpp, *.cxx) in the submission"};
    }
    std::ofstream(source / "CMakeLists.txt") << GeneratedCMakeLists(sources);
    log << "syrof grade: no CMakeLists.txt; one app library from " << sources.size() << " source file"
        << (sources.size() == 1 ? "" : "s") << "\n";
  }
  fs::remove_all(record, error);
  fs::copy(source, record, fs::copy_options::recursive, error);
  return std::nullopt;
}

// The note for how far the build's process isolation went, when not whole.
std::optional<std::string> IsolationNote(const process::SandboxReport& report) {
  const std::string why = std::strerror(report.isolation_errno);
  if (report.isolation == process::Isolation::kNetworkOnly) {
    return "build: no PID namespace (" + why +
           "): the network is cut, but a process the build leaves in a session of its own may outlive it";
  }
  if (report.isolation == process::Isolation::kNone) {
    return "build: network not isolated and no PID namespace (namespaces refused: " + why + ")";
  }
  return std::nullopt;
}

// What one step's end means for the build: nothing when it succeeded.
std::optional<Stop> StepStop(const StepOutcome& outcome, const std::string& cmake, const WorkMount& mount,
                             const BuildOptions& options, const fs::path& log_path, const Stage& stage,
                             OutputLog& log) {
  using enum BuildVerdict;
  if (!outcome.started) return Stop{kBuildFailed, "cannot start " + cmake};
  if (const SandboxFailure failure = outcome.sandbox.failure; failure != SandboxFailure::kNone) {
    const std::string layer = FailedLayer(failure);
    const char* why = std::strerror(outcome.sandbox.failure_errno);
    log.file << "syrof grade: " << layer << ": " << why << "\n";
    return Stop{kBuildFailed, "the build's sandbox failed: " + layer + ": " + why};
  }
  if (mount.ok() && mount.Full()) {
    const std::string bound = std::to_string(mount.limit_bytes() >> 20) + " MB";
    log.file << "\nsyrof grade: stopped: the build filled its folder (" << bound
             << ", the most a build may write in all)\n";
    return Stop{kBuildFailed, "the build wrote more than its folder holds (" + bound +
                                  " in all: its copy, build files and temporary files)"};
  }
  if (outcome.timed_out) {
    log.file << "\nsyrof grade: stopped at the build's time limit of " << options.timeout_s << " s\n";
    return Stop{kTimeout,
                "the build took longer than its limit of " + std::to_string(static_cast<int>(options.timeout_s)) + " s"};
  }
  if (outcome.output_limit) {
    log.file << "\nsyrof grade: stopped: the build wrote over " << (options.output_limit_bytes >> 20) << " MB\n";
    return Stop{kOutputLimit, "the build wrote over " + std::to_string(options.output_limit_bytes >> 20) + " MB of output"};
  }
  if (!outcome.status.exited() || outcome.status.code != 0) {
    if (log.total > log.kept) log.file << "\n[syrof grade: " << (log.total - log.kept) << " more bytes not kept]\n";
    log.file.flush();
    std::string detail = FirstErrorLine(log_path.string(), stage.root().string());
    if (outcome.status.signaled()) {
      detail = "the build was killed by signal " + std::to_string(outcome.status.signal) + ": " + detail;
    }
    return Stop{kBuildFailed, detail};
  }
  return std::nullopt;
}

// The app library the build made: lib*.so files (not CMake's own), taken
// out of `build` into the grader's `library_dir` (the build's processes are
// gone), each checked by the app host as a run would; exactly one must be
// an app.
std::variant<std::string, Stop> TakeAppLibrary(const fs::path& build, const fs::path& library_dir) {
  using enum BuildVerdict;
  std::error_code error;
  std::vector<fs::path> made;
  for (fs::recursive_directory_iterator it(build, error); !error && it != fs::recursive_directory_iterator();
       it.increment(error)) {
    if (it->is_directory(error) && it->path().filename() == "CMakeFiles") {
      it.disable_recursion_pending();
      continue;
    }
    const std::string name = it->path().filename().string();
    if (!it->is_symlink(error) && it->is_regular_file(error) && name.starts_with("lib") && name.ends_with(".so")) {
      made.push_back(it->path());
    }
  }
  std::sort(made.begin(), made.end());
  std::vector<std::string> candidates;
  for (const fs::path& library : made) {
    const fs::path taken = library_dir / library.lexically_relative(build);
    fs::create_directories(taken.parent_path(), error);
    if (TakeLibrary(library, taken)) candidates.push_back(taken.string());
  }
  if (candidates.empty()) {
    return Stop{kNoLibrary, "the build made no lib*.so; syrof_add_app(NAME app.c) in CMakeLists.txt makes libNAME.so"};
  }
  std::vector<std::string> apps;
  std::string first_error;
  for (const std::string& candidate : candidates) {
    app_host::HostOptions host;
    host.library_path = candidate;
    const app_host::LibraryCheck check = app_host::CheckLibrary(host);
    if (check.ok()) {
      apps.push_back(candidate);
    } else if (first_error.empty()) {
      first_error = check.error->ToString();
    }
  }
  if (apps.empty()) {
    std::string detail = first_error;
    const std::string prefix = library_dir.string() + "/";
    if (detail.starts_with(prefix)) detail.erase(0, prefix.size());
    return Stop{kBadLibrary, detail};
  }
  if (apps.size() > 1) {
    std::string names;
    for (const std::string& app : apps) names += (names.empty() ? "" : ", ") + fs::path(app).filename().string();
    return Stop{kNoLibrary,
                std::to_string(apps.size()) + " app libraries were built (" + names + "); a submission builds exactly one"};
  }
  return apps.front();
}

}  // namespace

std::string FindSyrofPackage() {
  const std::string dir = ExecutableDir();
  if (dir.empty()) return {};
  for (const fs::path& candidate : {fs::path(dir) / "..", fs::path(dir) / ".." / "lib" / "cmake" / "SyROF"}) {
    std::error_code error;
    if (fs::exists(candidate / "SyROFConfig.cmake", error)) return fs::weakly_canonical(candidate, error).string();
  }
  return {};
}

std::vector<std::string> FindSources(const std::string& dir) {
  std::vector<std::string> sources;
  std::error_code error;
  fs::recursive_directory_iterator it(dir, fs::directory_options::none, error);
  for (; !error && it != fs::recursive_directory_iterator(); it.increment(error)) {
    if (it->is_directory(error)) {
      if (SkippedFolder(it->path().filename())) it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file(error) && IsSource(it->path())) {
      sources.push_back(it->path().lexically_relative(dir).generic_string());
    }
  }
  std::sort(sources.begin(), sources.end());
  return sources;
}

BuildResult BuildSubmission(const std::string& submission_dir, const std::string& out_dir,
                            const BuildOptions& options, std::vector<std::string>& notes) {
  using enum BuildVerdict;
  const auto started = Clock::now();
  BuildResult result;
  result.log_path = "build.log";
  auto finish = [&](BuildVerdict verdict, std::string detail) {
    result.verdict = verdict;
    result.detail = std::move(detail);
    result.wall_seconds = std::chrono::duration<double>(Clock::now() - started).count();
    return result;
  };
  auto stop = [&](Stop why) { return finish(why.verdict, std::move(why.detail)); };
  const fs::path out = fs::absolute(out_dir);
  const fs::path library_dir = out / "build";
  std::error_code error;
  fs::create_directories(out, error);
  fs::remove_all(library_dir, error);
  fs::create_directories(library_dir, error);
  if (error) return finish(kBuildFailed, "cannot create " + library_dir.string() + ": " + error.message());
  OutputLog log;
  log.keep = options.log_keep_bytes;
  log.file.open(out / "build.log", std::ios::binary | std::ios::trunc);

  // The sandbox first (what a build's processes may reach; the build's
  // child applies it between fork and exec).
  FileRuleset files;  // not created(): no Landlock (only with allow_unconfined)
  process::Sandbox sandbox = BuildSandbox(options, files);
  if (std::optional<Stop> refused = CheckIsolation(options, files, sandbox, log.file, notes)) return stop(*refused);
  const std::string syrof_dir = options.syrof_dir.empty() ? FindSyrofPackage() : options.syrof_dir;
  if (syrof_dir.empty()) {
    return finish(kBuildFailed, "SyROF's CMake package (SyROFConfig.cmake) was not found beside this syrof");
  }
  const std::string cmake = FindOnPath("cmake");
  if (cmake.empty()) return finish(kBuildFailed, "cmake is not installed on the grading machine");

  const Stage stage(sandbox.drop_to_nobody);
  if (!stage.ok()) return finish(kBuildFailed, stage.problem());
  if (const std::optional<lab::Error> problem = StagePackage(syrof_dir, stage.package())) {
    return finish(kBuildFailed, problem->ToString());
  }
  log.file << "syrof grade: SyROF's package from " << syrof_dir << "\n";
  // The build's folder, bounded in size; `work` is where the grader reaches
  // it, stage.work() where the build sees it (the same folder).
  const WorkMount mount(stage.work(), options.work_limit_bytes);
  fs::path work = stage.work();
  if (mount.ok()) {
    sandbox.enter_user_namespace = mount.user_ns();
    sandbox.enter_mount_namespace = mount.mount_ns();
    work = mount.view();
    for (const char* folder : {"source", "build", "tmp"}) fs::create_directories(work / folder, error);
    if (error) return finish(kBuildFailed, "cannot make a folder for the build: " + error.message());
  } else {
    notes.push_back("build: no bound on what the build writes in all (a size-limited folder: " + mount.problem() +
                    "): only RLIMIT_FSIZE per file");
  }
  if (std::optional<Stop> failed =
          CopyIn(submission_dir, work / "source", out / "source", options.max_submission_bytes, log.file)) {
    return stop(*failed);
  }
  fs::permissions(work, fs::perms::owner_all, error);
  if (sandbox.drop_to_nobody && !HandOver(work)) {
    return finish(kBuildFailed, "cannot hand the build's folder to uid " + std::to_string(kBuildUid) + ": " +
                                      std::strerror(errno));
  }
  // (The rule names the folder the grader reaches: with the bound, the
  // tmpfs itself, not the folder it covers.)
  if (files.created()) {
    if (const std::optional<lab::Error> problem = BuildFileRules(files, stage.package(), work)) {
      return finish(kBuildFailed, problem->ToString());
    }
  }

  // Configure, then build, each a sandboxed step under one deadline; the
  // paths as the build sees them.
  const fs::path built_source = stage.work() / "source";
  const fs::path built_build = stage.work() / "build";
  const std::vector<std::string> environment = {"PATH=/usr/local/bin:/usr/bin:/bin", "LC_ALL=C", "LANG=C",
                                                "HOME=" + stage.work().string(),
                                                "TMPDIR=" + (stage.work() / "tmp").string()};
  const std::vector<std::vector<std::string>> steps = {
      {cmake, "-S", built_source.string(), "-B", built_build.string(), "-DSyROF_DIR=" + stage.package().string(),
       "-DCMAKE_BUILD_TYPE=Release"},
      {cmake, "--build", built_build.string()}};
  const auto deadline = started + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.timeout_s));
  for (size_t i = 0; i < steps.size(); ++i) {
    std::string shown = "$";
    for (const std::string& arg : steps[i]) shown += " " + Shown(arg, stage.root());
    log.file << shown << "\n";
    log.file.flush();
    process::Command command;
    command.argv = steps[i];
    command.environment = environment;
    command.working_directory = built_build.string();
    command.exec_failure_text = "syrof grade: cannot start the build tool\n";
    const StepOutcome outcome = RunStep(command, sandbox, options.output_limit_bytes, deadline, log);
    if (i == 0 && outcome.started && outcome.sandbox.failure == SandboxFailure::kNone) {
      if (std::optional<std::string> note = IsolationNote(outcome.sandbox)) notes.push_back(*note);
    }
    if (std::optional<Stop> ended = StepStop(outcome, cmake, mount, options, out / "build.log", stage, log)) {
      return stop(*ended);
    }
  }
  if (log.total > log.kept) log.file << "\n[syrof grade: " << (log.total - log.kept) << " more bytes not kept]\n";
  log.file.close();

  std::variant<std::string, Stop> app = TakeAppLibrary(work / "build", library_dir);
  if (Stop* none = std::get_if<Stop>(&app)) return stop(std::move(*none));
  result.library_path = std::get<std::string>(std::move(app));
  return finish(kOk, "built " + fs::path(result.library_path).filename().string());
}

}  // namespace syrof::grader
