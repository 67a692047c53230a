#include "clipray/io/StagedWrite.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace clipray {

namespace {

namespace fs = std::filesystem;

constexpr const char* kStaging = ".clipray-staging";
constexpr const char* kPrevious = ".clipray-previous";

void writeWhole(const fs::path& path, std::string_view bytes, const fs::path& named) {
  const auto fail = [&](int error) {
    throw std::runtime_error("cannot write " + named.string() + ": " + std::strerror(error));
  };
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) fail(errno);
  if (const int error = writeAllBytes(fd, bytes); error != 0) {
    ::close(fd);
    fail(error);
  }
  if (::close(fd) != 0) fail(errno);
}

void makeFolders(const fs::path& folder, const fs::path& named) {
  std::error_code error;
  fs::create_directories(folder, error);
  if (error) throw std::runtime_error("cannot write " + named.string() + ": " + error.message());
}

// Holds back the signals a user sends to stop a program for as long as it lives: each one that
// arrives meanwhile is noted, and sent again once the previous handlers are back, after the
// switch. A handler, not a signal mask: a mask is per thread, and the GL driver's and the image
// encoder's threads would take a process-directed Ctrl-C without one.
volatile std::sig_atomic_t heldSignal = 0;

extern "C" void noteHeldSignal(int signal) {
  heldSignal = signal;
}

class SignalsHeldBack {
 public:
  SignalsHeldBack() {
    heldSignal = 0;
    struct sigaction note = {};
    note.sa_handler = noteHeldSignal;
    sigemptyset(&note.sa_mask);
    for (std::size_t k = 0; k < kSignals.size(); ++k) {
      ::sigaction(kSignals[k], &note, &before_[k]);
    }
  }
  ~SignalsHeldBack() {
    for (std::size_t k = 0; k < kSignals.size(); ++k) {
      ::sigaction(kSignals[k], &before_[k], nullptr);
    }
    if (heldSignal != 0) ::raise(heldSignal);
  }
  SignalsHeldBack(const SignalsHeldBack&) = delete;
  SignalsHeldBack& operator=(const SignalsHeldBack&) = delete;

 private:
  static constexpr std::array<int, 4> kSignals{SIGINT, SIGTERM, SIGHUP, SIGQUIT};
  std::array<struct sigaction, 4> before_{};
};

// For the interrupt tests only: CLIPRAY_TEST_SIGNAL_IN_SWITCH="<signal number>:<renames>" sends
// the process that signal after that many files were switched in, as a user or the kernel could.
struct InjectedSignal {
  int signal = 0;
  std::size_t afterRenames = 0;
};

InjectedSignal injectedSignal() {
  const char* text = std::getenv("CLIPRAY_TEST_SIGNAL_IN_SWITCH");
  InjectedSignal injected;
  if (text == nullptr) return injected;
  char* end = nullptr;
  injected.signal = static_cast<int>(std::strtol(text, &end, 10));
  if (*end == ':') injected.afterRenames = std::strtoul(end + 1, nullptr, 10);
  return injected;
}

}  // namespace

int writeAllBytes(int fd, std::string_view bytes) {
  const char* data = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t written = ::write(fd, data, left);
    if (written < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    data += written;
    left -= static_cast<std::size_t>(written);
  }
  return 0;
}

bool recoverInterruptedWrite(const fs::path& folder) {
  std::error_code error;
  const fs::path previous = folder / kPrevious;
  const fs::path staging = folder / kStaging;
  bool recovered = false;
  if (fs::is_directory(previous, error)) {
    for (auto it = fs::recursive_directory_iterator(previous, error);
         it != fs::recursive_directory_iterator(); it.increment(error)) {
      if (error) break;
      if (!it->is_regular_file()) continue;
      const fs::path target = folder / fs::relative(it->path(), previous);
      fs::create_directories(target.parent_path(), error);
      fs::rename(it->path(), target, error);
    }
    fs::remove_all(previous, error);
    recovered = true;
  }
  if (fs::exists(staging, error)) {
    fs::remove_all(staging, error);
    recovered = true;
  }
  return recovered;
}

namespace {

void writeInto(const fs::path& folder, const std::vector<FileToWrite>& files) {
  recoverInterruptedWrite(folder);
  const fs::path staging = folder / kStaging;
  const fs::path previous = folder / kPrevious;
  std::error_code ignored;

  // 1. Everything into the staging folder; a failure here leaves the folder as it was.
  try {
    for (const FileToWrite& file : files) {
      const fs::path staged = staging / file.relative;
      makeFolders(staged.parent_path(), folder / file.relative);
      writeWhole(staged, file.bytes, folder / file.relative);
    }
  } catch (...) {
    fs::remove_all(staging, ignored);
    throw;
  }

  // 2. The switch. Each step is recorded so that a failing rename can undo the ones before it.
  const SignalsHeldBack held;
  const InjectedSignal injected = injectedSignal();
  struct Step {
    fs::path relative;
    bool replacedOld = false;
  };
  std::vector<Step> done;
  std::vector<fs::path> createdFolders;
  const auto undo = [&] {
    for (auto step = done.rbegin(); step != done.rend(); ++step) {
      const fs::path target = folder / step->relative;
      fs::remove(target, ignored);
      if (step->replacedOld) fs::rename(previous / step->relative, target, ignored);
    }
    for (auto it = createdFolders.rbegin(); it != createdFolders.rend(); ++it) {
      fs::remove(*it, ignored);  // only if empty
    }
    fs::remove_all(previous, ignored);
    fs::remove_all(staging, ignored);
  };
  try {
    for (const FileToWrite& file : files) {
      const fs::path target = folder / file.relative;
      std::error_code error;
      for (fs::path f = target.parent_path(); f != folder && !fs::exists(f, ignored);
           f = f.parent_path()) {
        createdFolders.insert(createdFolders.begin(), f);
      }
      makeFolders(target.parent_path(), target);
      Step step{file.relative, false};
      if (fs::exists(target, ignored)) {
        makeFolders((previous / file.relative).parent_path(), target);
        fs::rename(target, previous / file.relative, error);
        if (error)
          throw std::runtime_error("cannot replace " + target.string() + ": " + error.message());
        step.replacedOld = true;
      }
      fs::rename(staging / file.relative, target, error);
      if (error) {
        if (step.replacedOld) fs::rename(previous / file.relative, target, ignored);
        throw std::runtime_error("cannot write " + target.string() + ": " + error.message());
      }
      done.push_back(step);
      if (injected.signal != 0 && done.size() == injected.afterRenames) ::raise(injected.signal);
    }
  } catch (...) {
    undo();
    throw;
  }
  fs::remove_all(previous, ignored);
  fs::remove_all(staging, ignored);
}

}  // namespace

void writeFilesAsOne(const fs::path& folder, const std::vector<FileToWrite>& files) {
  std::error_code ignored;
  const bool folderWasThere = fs::exists(folder, ignored);
  makeFolders(folder, folder);
  try {
    writeInto(folder, files);
  } catch (...) {
    if (!folderWasThere) fs::remove(folder, ignored);  // only if empty
    throw;
  }
}

}  // namespace clipray
