#include "loaded_library.h"

#include <sys/types.h>
#include <sys/wait.h>
#include <signal.h>

#include <cerrno>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "host_process.h"
#include "protocol.h"

namespace syrof::app_host {
namespace {

namespace p = protocol;

// What a held host's hello notes say of its copies.
std::string NotCleanReason(uint32_t notes) {
  std::string reason = "the library's constructors left";
  if ((notes & p::kHoldOpenDescriptor) != 0) reason += " an open descriptor";
  if ((notes & p::kHoldSharedMapping) != 0) reason += " a shared memory mapping";
  if ((notes & p::kHoldPendingSignal) != 0) reason += " a pending signal";
  if ((notes & p::kHoldStandardDescriptors) != 0) reason += " descriptors 0-3 changed";
  if ((notes & p::kHoldUnchecked) != 0) reason = "the held host could not read its memory map";
  if ((notes & p::kHoldNoSignalScope) != 0) reason = "no Landlock signal scope (ABI 6) on this kernel";
  return reason + ": each run starts a fresh host";
}

// Whether a process other than `leader` is in its process group (zombies
// included): read from /proc.
bool OthersInGroup(pid_t leader) {
  bool found = false;
  std::error_code error;
  for (const std::filesystem::directory_entry& entry : std::filesystem::directory_iterator("/proc", error)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(name));
    if (pid == leader) continue;
    std::ifstream stat(entry.path() / "stat");
    std::string line;
    std::getline(stat, line);
    const size_t close = line.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream rest(line.substr(close + 1));
    char state = 0;
    pid_t parent = 0;
    pid_t group = 0;
    rest >> state >> parent >> group;
    if (group == leader) found = true;
  }
  return found;
}

}  // namespace

LoadedLibrary::LoadedLibrary(const HostOptions& options) : options_(options) {
  const std::lock_guard<std::mutex> lock(mutex_);
  (void)StartHolder();
}

LoadedLibrary::~LoadedLibrary() {
  // Every copy has ended (each app holds this object): what is left in the
  // held host's group goes with it.
  if (holder_ != nullptr && holder_->pid() > 0) kill(-holder_->pid(), SIGKILL);
}

bool LoadedLibrary::StartHolder() {
  ++starts_;
  HostOptions quiet = options_;
  quiet.log_directory.clear();
  auto holder = std::make_unique<HostProcess>();
  const app::CallStatus status = holder->Start(quiet, 0, HostProcess::Mode::kHold);
  if (!status.ok()) {
    // A fresh host per robot gives the very verdict (and log) of a run.
    fresh_reason_ = "the library does not load in a held host (" + holder->full_detail() + "): each run starts a fresh host";
    return false;
  }
  const uint32_t notes = holder->notes();
  if ((notes & p::kHoldNotClean) != 0) {
    fresh_reason_ = NotCleanReason(notes);
    return false;
  }
  if (first_) {
    first_ = false;
    app_name_ = holder->app_name();
    notes_ = notes;
    load_output_ = holder->load_output();
    load_output_bytes_ = holder->output_bytes();
  } else if (holder->app_name() != app_name_ || notes != notes_ || holder->load_output() != load_output_ ||
             holder->output_bytes() != load_output_bytes_) {
    fresh_reason_ = "the held host loaded differently when started again: each run starts a fresh host";
    return false;
  }
  // A constructor may have made the one clone the held host's filter lets
  // through: the process would be in the held host's group (nothing there
  // may leave it: setpgid and setsid are refused). Found, the group is
  // killed and each run starts a fresh host, whose filter refuses the clone
  // (the verdict a run gives). After the hello no code of the library runs
  // in the held host, so nothing starts later.
  if (OthersInGroup(holder->pid())) {
    fresh_reason_ = "the library's constructors started a process: each run starts a fresh host";
    // The group killed with the held host, then what it left reaped: each
    // is a child of this process (CLONE_PARENT), and no copy exists yet.
    const pid_t group = holder->pid();
    kill(-group, SIGKILL);
    holder.reset();
    while (waitpid(-group, nullptr, 0) > 0 || errno == EINTR) {
    }
    return false;
  }
  holder_ = std::move(holder);
  return true;
}

LoadedLibrary::CopyStart LoadedLibrary::StartCopy(int child_channel, int child_output) {
  const std::lock_guard<std::mutex> lock(mutex_);
  CopyStart copy;
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (!fresh_reason_.empty()) return copy;
    if (holder_ == nullptr && !StartHolder()) {
      holder_.reset();
      return copy;
    }
    int error = 0;
    switch (holder_->MakeCopy(child_channel, child_output, copy.pid, error)) {
      case HostProcess::Copy::kMade:
        copy.made = true;
        copy.load_output = load_output_;
        copy.load_output_bytes = load_output_bytes_;
        return copy;
      case HostProcess::Copy::kRefused:
        return copy;  // this one fresh (no process could be made now)
      case HostProcess::Copy::kGone:
        holder_.reset();  // killed and reaped; started again below
        break;
    }
  }
  return copy;
}

bool LoadedLibrary::holding() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return fresh_reason_.empty();
}

std::string LoadedLibrary::fresh_reason() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return fresh_reason_;
}

int LoadedLibrary::starts() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return starts_;
}

LoadedLibraryState StateOf(const LoadedLibrary& loaded) {
  LoadedLibraryState state;
  state.fresh_reason = loaded.fresh_reason();
  state.holding = state.fresh_reason.empty();
  state.starts = loaded.starts();
  return state;
}

std::shared_ptr<LoadedLibrary> LoadOnce(const HostOptions& options) {
  return std::make_shared<LoadedLibrary>(options);
}

}  // namespace syrof::app_host
