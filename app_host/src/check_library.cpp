// FindHostBinary, CheckLibrary and SandboxNotes.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include "host_process.h"
#include "protocol.h"
#include "syrof/app_host/hosted_app.h"

namespace syrof::app_host {
namespace {

namespace p = protocol;

std::mutex notes_mutex;
std::vector<std::string> sandbox_notes;

bool Executable(const std::string& path) {
  struct stat info {};
  return stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode) && access(path.c_str(), X_OK) == 0;
}

std::vector<std::string> NoteLines(uint32_t notes) {
  std::vector<std::string> lines;
  if ((notes & p::kNoteNotRoot) != 0) {
    lines.push_back("not started as root: the app hosts keep the caller's uid (no drop to uid 65534)");
  }
  if ((notes & p::kNoteNoNamespaces) != 0) {
    lines.push_back("user/net/ipc/uts namespaces unavailable: the app hosts share the system's "
                    "(the system call filter still refuses sockets)");
  }
  if ((notes & p::kNoteNoAslrOff) != 0) {
    lines.push_back("address randomisation could not be turned off: an app that prints or hashes "
                    "pointers may differ between runs");
  }
  if ((notes & p::kNoteSanitized) != 0) {
    lines.push_back("sanitizer build: no address-space limit and no allocation guard in the app hosts");
  }
  if ((notes & p::kNoteNoCloseRange) != 0) {
    lines.push_back("close_range unavailable: the app hosts close their descriptors one by one");
  }
  if ((notes & p::kNoteNoLandlock) != 0) {
    lines.push_back("Landlock unavailable (kernel older than 5.13, or not enabled): a library's constructors "
                    "may read any file uid 65534 may read, not only the library's and the system's libraries");
  }
  return lines;
}

}  // namespace

std::string FindHostBinary() {
  if (const char* forced = std::getenv("SYROF_APP_HOST"); forced != nullptr && forced[0] != '\0') {
    return Executable(forced) ? std::string(forced) : std::string();
  }
  char buffer[4096];
  const ssize_t length = readlink("/proc/self/exe", buffer, sizeof(buffer) - 1);
  if (length <= 0) return {};
  const std::string exe(buffer, static_cast<size_t>(length));
  const std::string dir = exe.substr(0, exe.rfind('/'));
  for (const std::string& candidate : {dir + "/syrof-app-host", dir + "/../libexec/syrof/syrof-app-host"}) {
    if (Executable(candidate)) return candidate;
  }
  return {};
}

LibraryCheck CheckLibrary(const HostOptions& options) {
  LibraryCheck check;
  const std::string& path = options.library_path;
  auto refuse = [&](std::string message) {
    check.error = lab::Error{.where = path.empty() ? std::string("(no library)") : path, .message = std::move(message)};
    return check;
  };
  struct stat info {};
  if (path.empty() || stat(path.c_str(), &info) != 0) return refuse("not found");
  if (!S_ISREG(info.st_mode)) return refuse("not a file");
  HostOptions quiet = options;
  quiet.log_directory.clear();
  HostProcess process;
  const app::CallStatus status = process.Start(quiet, 0, HostProcess::Mode::kCheck);
  if (!status.ok()) {
    std::string detail = process.full_detail();
    if (status.verdict() == app::Verdict::kCrashed) {
      detail = "crashed while loading (" + detail.substr(0, detail.find(" during load")) + ")";
    } else if (status.verdict() != app::Verdict::kLoadFailed && status.verdict() != app::Verdict::kBadAbi) {
      detail = std::string(app::ToString(status.verdict())) + ": " + detail;
    }
    return refuse(std::move(detail));
  }
  check.app_name = process.app_name();
  const std::lock_guard<std::mutex> lock(notes_mutex);
  sandbox_notes = NoteLines(process.notes());
  return check;
}

std::vector<std::string> SandboxNotes() {
  const std::lock_guard<std::mutex> lock(notes_mutex);
  return sandbox_notes;
}

}  // namespace syrof::app_host
