// Building a submission: copy, generate a CMakeLists.txt for sources-only
// folders, run CMake in a sandboxed child, find the app library.
#include "syrof/grader/build.h"

#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "syrof/app_host/hosted_app.h"

namespace syrof::grader {
namespace {

namespace fs = std::filesystem;
using assignment::BuildResult;
using Clock = std::chrono::steady_clock;

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

// Copies regular files only (no symlinks, devices or FIFOs), at most
// `max_bytes` in all. Returns "" or what went wrong.
std::string CopySubmission(const fs::path& from, const fs::path& to, uint64_t max_bytes) {
  std::error_code error;
  fs::remove_all(to, error);
  fs::create_directories(to, error);
  if (error) return "cannot create " + to.string() + ": " + error.message();
  uint64_t total = 0;
  fs::recursive_directory_iterator it(from, fs::directory_options::none, error);
  if (error) return "cannot read " + from.string() + ": " + error.message();
  for (; it != fs::recursive_directory_iterator(); it.increment(error)) {
    if (error) return "cannot read " + from.string() + ": " + error.message();
    const fs::directory_entry& entry = *it;
    const fs::path relative = entry.path().lexically_relative(from);
    if (entry.is_symlink(error)) continue;
    if (entry.is_directory(error)) {
      if (SkippedFolder(entry.path().filename())) {
        it.disable_recursion_pending();
        continue;
      }
      fs::create_directories(to / relative, error);
      continue;
    }
    if (!entry.is_regular_file(error)) continue;
    total += entry.file_size(error);
    if (total > max_bytes) {
      return "the submission holds more than " + std::to_string(max_bytes >> 20) + " MB of files";
    }
    fs::copy_file(entry.path(), to / relative, fs::copy_options::overwrite_existing, error);
    if (error) return "cannot copy " + relative.string() + ": " + error.message();
  }
  return {};
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

struct ChildOutcome {
  bool started = false;
  bool timed_out = false;
  bool output_limit = false;
  int exit_code = -1;   // when it exited
  int signal = 0;       // when a signal ended it
  int isolation = 0;    // 0 network isolated by a user+net namespace, 1 by a net namespace, 2 not isolated
  int isolation_errno = 0;
};

// Runs `argv` in its own process group with rlimits and no network, output
// to `log`, until it exits or `deadline`. Everything the child does between
// fork and exec is async-signal-safe (the parent may have threads).
ChildOutcome RunSandboxed(const std::vector<std::string>& argv, const std::string& working_dir,
                          const std::vector<std::string>& environment, const BuildOptions& options,
                          Clock::time_point deadline, OutputLog& log) {
  ChildOutcome outcome;
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  std::vector<char*> env;
  for (const std::string& entry : environment) env.push_back(const_cast<char*>(entry.c_str()));
  env.push_back(nullptr);
  int output[2];
  int status_pipe[2];
  if (pipe2(output, O_CLOEXEC) != 0) return outcome;
  if (pipe2(status_pipe, O_CLOEXEC) != 0) {
    close(output[0]);
    close(output[1]);
    return outcome;
  }
  const int null_fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
  const rlimit file_size{options.file_size_limit_bytes, options.file_size_limit_bytes};
  const rlimit cpu{options.cpu_limit_s, options.cpu_limit_s};
  const rlimit no_core{0, 0};
  // The user namespace maps the caller's own ids (the one mapping an
  // unprivileged process may write), so files the build creates are owned
  // as usual; without a mapping creating files fails (EINVAL/EOVERFLOW).
  const std::string uid_map = std::to_string(geteuid()) + " " + std::to_string(geteuid()) + " 1\n";
  const std::string gid_map = std::to_string(getegid()) + " " + std::to_string(getegid()) + " 1\n";
  auto write_file = [](const char* path, const std::string& text) {
    const int fd = open(path, O_WRONLY | O_CLOEXEC);
    if (fd < 0) return false;
    const bool ok = write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
    close(fd);
    return ok;
  };
  const std::string deny = "deny";
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    int report[2] = {0, 0};
    if (unshare(CLONE_NEWUSER | CLONE_NEWNET) == 0) {
      report[0] = 0;
      write_file("/proc/self/setgroups", deny);
      if (!write_file("/proc/self/uid_map", uid_map) || !write_file("/proc/self/gid_map", gid_map)) {
        report[1] = errno;
      }
    } else {
      report[1] = errno;
      report[0] = unshare(CLONE_NEWNET) == 0 ? 1 : 2;
    }
    (void)!write(status_pipe[1], report, sizeof report);
    setrlimit(RLIMIT_FSIZE, &file_size);
    setrlimit(RLIMIT_CPU, &cpu);
    setrlimit(RLIMIT_CORE, &no_core);
    if (null_fd >= 0) dup2(null_fd, 0);
    dup2(output[1], 1);
    dup2(output[1], 2);
    if (chdir(working_dir.c_str()) != 0) _exit(126);
    execve(args[0], args.data(), env.data());
    static const char kFailed[] = "syrof grade: cannot start the build tool\n";
    (void)!write(2, kFailed, sizeof kFailed - 1);
    _exit(127);
  }
  close(output[1]);
  close(status_pipe[1]);
  if (null_fd >= 0) close(null_fd);
  if (pid < 0) {
    close(output[0]);
    close(status_pipe[0]);
    return outcome;
  }
  outcome.started = true;
  setpgid(pid, pid);  // also from the parent: no window where a kill(-pid) misses
  int report[2] = {2, 0};
  if (read(status_pipe[0], report, sizeof report) == static_cast<ssize_t>(sizeof report)) {
    outcome.isolation = report[0];
    outcome.isolation_errno = report[1];
  }
  close(status_pipe[0]);
  const int pidfd = static_cast<int>(syscall(SYS_pidfd_open, pid, 0));
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
    if (output_open) fds[count++] = {output[0], POLLIN, 0};
    if (pidfd >= 0 && !exited) fds[count++] = {pidfd, POLLIN, 0};
    if (count == 0) break;
    const int ready = poll(fds, count, wait_ms);
    if (ready < 0 && errno != EINTR) break;
    if (pidfd < 0 && !exited) {
      int status = 0;
      if (waitpid(pid, &status, WNOHANG) == pid) {
        exited = true;
        if (WIFEXITED(status)) outcome.exit_code = WEXITSTATUS(status);
        if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
      }
    }
    for (nfds_t i = 0; i < count; ++i) {
      if (fds[i].revents == 0) continue;
      if (fds[i].fd == output[0]) {
        const ssize_t got = read(output[0], buffer, sizeof buffer);
        if (got > 0) {
          log.Add(buffer, static_cast<size_t>(got));
          if (log.total > options.output_limit_bytes) {
            outcome.output_limit = true;
            output_open = false;
          }
        } else if (got == 0 || (errno != EINTR && errno != EAGAIN)) {
          output_open = false;
        }
      } else {
        int status = 0;
        if (waitpid(pid, &status, 0) == pid) {
          exited = true;
          if (WIFEXITED(status)) outcome.exit_code = WEXITSTATUS(status);
          if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
          // Whatever the build left behind in its group goes too; output
          // still in the pipe is read until every writer is gone.
          kill(-pid, SIGKILL);
        }
      }
    }
    if (outcome.output_limit) break;
  }
  kill(-pid, SIGKILL);
  if (!exited) {
    int status = 0;
    waitpid(pid, &status, 0);
    if (!outcome.timed_out && !outcome.output_limit) {
      if (WIFEXITED(status)) outcome.exit_code = WEXITSTATUS(status);
      if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
    }
  }
  if (pidfd >= 0) close(pidfd);
  close(output[0]);
  return outcome;
}

// The first line of the kept log a student should read: a compiler's
// "error:", else CMake's "CMake Error" with its message, else the last
// non-empty line. The copy's absolute path is cut to the file's own name.
std::string FirstErrorLine(const std::string& log_path, const std::string& source_dir) {
  std::ifstream in(log_path);
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line) && lines.size() < 100000) lines.push_back(line);
  auto clean = [&](std::string text) {
    for (size_t at = text.find(source_dir + "/"); at != std::string::npos; at = text.find(source_dir + "/")) {
      text.erase(at, source_dir.size() + 1);
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

std::string ExecutableDir() {
  char buffer[4096];
  const ssize_t length = readlink("/proc/self/exe", buffer, sizeof(buffer) - 1);
  if (length <= 0) return {};
  return fs::path(std::string(buffer, static_cast<size_t>(length))).parent_path().string();
}

std::string FindOnPath(const std::string& name) {
  for (const char* dir : {"/usr/local/bin", "/usr/bin", "/bin"}) {
    const std::string candidate = std::string(dir) + "/" + name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
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
  const auto started = Clock::now();
  BuildResult result;
  result.log_path = "build.log";
  auto finish = [&](const char* verdict, std::string detail) {
    result.verdict = verdict;
    result.detail = std::move(detail);
    result.wall_seconds = std::chrono::duration<double>(Clock::now() - started).count();
    return result;
  };
  const fs::path out = fs::absolute(out_dir);
  const fs::path source = out / "source";
  const fs::path build = out / "build";
  std::error_code error;
  fs::create_directories(out, error);
  fs::remove_all(build, error);
  fs::create_directories(build, error);
  if (error) return finish("build_failed", "cannot create " + build.string() + ": " + error.message());
  OutputLog log;
  log.keep = options.log_keep_bytes;
  log.file.open(out / "build.log", std::ios::binary | std::ios::trunc);

  if (std::string problem = CopySubmission(submission_dir, source, options.max_submission_bytes); !problem.empty()) {
    log.file << "syrof grade: " << problem << "\n";
    return finish("build_failed", problem);
  }
  if (!fs::exists(source / "CMakeLists.txt", error)) {
    const std::vector<std::string> sources = FindSources(source.string());
    if (sources.empty()) {
      log.file << "syrof grade: no CMakeLists.txt and no C/C++ source (*.c, *.cc, *.cpp, *.cxx)\n";
      return finish("no_sources", "no CMakeLists.txt and no C/C++ source (*.c, *.cc, *.cpp, *.cxx) in the submission");
    }
    std::ofstream(source / "CMakeLists.txt") << GeneratedCMakeLists(sources);
    log.file << "syrof grade: no CMakeLists.txt; one app library from " << sources.size() << " source file"
             << (sources.size() == 1 ? "" : "s") << "\n";
  }
  const std::string syrof_dir = options.syrof_dir.empty() ? FindSyrofPackage() : options.syrof_dir;
  if (syrof_dir.empty()) {
    return finish("build_failed", "SyROF's CMake package (SyROFConfig.cmake) was not found beside this syrof");
  }
  const std::string cmake = FindOnPath("cmake");
  if (cmake.empty()) return finish("build_failed", "cmake is not installed on the grading machine");

  const std::vector<std::string> environment = {"PATH=/usr/local/bin:/usr/bin:/bin", "LC_ALL=C", "LANG=C",
                                                "HOME=" + build.string(), "TMPDIR=" + build.string()};
  const std::vector<std::vector<std::string>> steps = {
      {cmake, "-S", source.string(), "-B", build.string(), "-DSyROF_DIR=" + syrof_dir,
       "-DCMAKE_BUILD_TYPE=Release"},
      {cmake, "--build", build.string()}};
  const auto deadline = started + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.timeout_s));
  bool noted = false;
  for (const std::vector<std::string>& step : steps) {
    std::string shown = "$";
    for (const std::string& arg : step) shown += " " + arg;
    shown += "\n";
    log.file << shown;
    log.file.flush();
    const ChildOutcome outcome = RunSandboxed(step, build.string(), environment, options, deadline, log);
    if (!noted) {
      noted = true;
      if (outcome.isolation == 1) {
        notes.push_back("build: no user namespace (" + std::string(std::strerror(outcome.isolation_errno)) +
                        "); network cut with a network namespace alone");
      } else if (outcome.isolation == 2) {
        notes.push_back("build: network not isolated (namespaces refused: " +
                        std::string(std::strerror(outcome.isolation_errno)) + ")");
      }
    }
    if (!outcome.started) return finish("build_failed", "cannot start " + cmake);
    if (outcome.timed_out) {
      log.file << "\nsyrof grade: stopped at the build's time limit of " << options.timeout_s << " s\n";
      return finish("timeout", "the build took longer than its limit of " + std::to_string(static_cast<int>(options.timeout_s)) + " s");
    }
    if (outcome.output_limit) {
      log.file << "\nsyrof grade: stopped: the build wrote over " << (options.output_limit_bytes >> 20) << " MB\n";
      return finish("output_limit", "the build wrote over " + std::to_string(options.output_limit_bytes >> 20) + " MB of output");
    }
    if (outcome.exit_code != 0) {
      if (log.total > log.kept) log.file << "\n[syrof grade: " << (log.total - log.kept) << " more bytes not kept]\n";
      log.file.flush();
      std::string detail = FirstErrorLine((out / "build.log").string(), source.string());
      if (outcome.signal != 0) detail = "the build was killed by signal " + std::to_string(outcome.signal) + ": " + detail;
      return finish("build_failed", detail);
    }
  }
  if (log.total > log.kept) log.file << "\n[syrof grade: " << (log.total - log.kept) << " more bytes not kept]\n";
  log.file.close();

  // The app library: lib*.so files the build made (not CMake's own), each
  // checked by the app host as a run would.
  std::vector<std::string> candidates;
  for (fs::recursive_directory_iterator it(build, error); !error && it != fs::recursive_directory_iterator();
       it.increment(error)) {
    if (it->is_directory(error) && it->path().filename() == "CMakeFiles") {
      it.disable_recursion_pending();
      continue;
    }
    const std::string name = it->path().filename().string();
    if (!it->is_symlink(error) && it->is_regular_file(error) && name.starts_with("lib") && name.ends_with(".so")) {
      candidates.push_back(it->path().string());
    }
  }
  std::sort(candidates.begin(), candidates.end());
  if (candidates.empty()) {
    return finish("no_library",
                  "the build made no lib*.so; syrof_add_app(NAME app.c) in CMakeLists.txt makes libNAME.so");
  }
  std::vector<std::string> apps;
  std::string first_error;
  for (const std::string& candidate : candidates) {
    app_host::HostOptions host;
    host.library_path = candidate;
    const app_host::LibraryCheck check = app_host::CheckLibrary(host);
    if (check.ok) {
      apps.push_back(candidate);
    } else if (first_error.empty()) {
      first_error = check.error;
    }
  }
  if (apps.empty()) {
    std::string detail = first_error;
    const std::string prefix = build.string() + "/";
    if (detail.starts_with(prefix)) detail.erase(0, prefix.size());
    return finish("bad_library", detail);
  }
  if (apps.size() > 1) {
    std::string names;
    for (const std::string& app : apps) names += (names.empty() ? "" : ", ") + fs::path(app).filename().string();
    return finish("no_library", std::to_string(apps.size()) + " app libraries were built (" + names +
                                    "); a submission builds exactly one");
  }
  result.library_path = apps.front();
  return finish("ok", "built " + fs::path(apps.front()).filename().string());
}

}  // namespace syrof::grader
