#include "clipray/io/OutputFolder.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "clipray/InputError.hpp"
#include "clipray/io/StagedWrite.hpp"

namespace clipray {

namespace {

constexpr const char* kLockName = ".clipray.lock";

std::string readHolder(int fd) {
  char text[32] = {};
  const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
  std::string pid(text, n > 0 ? static_cast<std::size_t>(n) : 0);
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid;
}

}  // namespace

OutputFolder::OutputFolder(const std::filesystem::path& folder, const std::string& option)
    : folder_(folder) {
  namespace fs = std::filesystem;
  const std::string name = option + " " + folder.string();
  std::error_code error;
  if (fs::exists(folder, error) && !fs::is_directory(folder, error)) {
    throw InputError(name + ": exists and is not a folder");
  }
  // The folders this run creates, outermost first, so that a failure removes exactly those.
  std::vector<fs::path> missing;
  for (fs::path f = fs::absolute(folder, error); !f.empty() && !fs::exists(f, error);
       f = f.parent_path()) {
    missing.insert(missing.begin(), f);
    if (f == f.parent_path()) break;
  }
  for (const fs::path& f : missing) {
    if (!fs::create_directory(f, error) && !fs::is_directory(f)) {
      for (auto it = created_.rbegin(); it != created_.rend(); ++it) fs::remove(*it, error);
      throw InputError(name + ": cannot create folder " + f.string() + ": " + error.message());
    }
    created_.push_back(f);
  }
  const fs::path lockPath = folder / kLockName;
  createdLockFile_ = !fs::exists(lockPath, error);
  lockFd_ = ::open(lockPath.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lockFd_ < 0) {
    const std::string why = std::strerror(errno);
    createdLockFile_ = false;
    release();
    throw InputError(name + ": cannot write there: " + why);
  }
  if (::flock(lockFd_, LOCK_EX | LOCK_NB) != 0) {
    // The holder writes its pid just after taking the lock: give it a moment to have done so.
    std::string holder = readHolder(lockFd_);
    for (int attempt = 0; attempt < 20 && holder.empty(); ++attempt) {
      ::usleep(10000);
      holder = readHolder(lockFd_);
    }
    ::close(lockFd_);
    lockFd_ = -1;
    createdLockFile_ = false;  // the holder's
    release();
    throw InputError(name + ": another clipray run" +
                     (holder.empty() ? std::string() : " (pid " + holder + ")") +
                     " is writing there; wait for it to finish or choose another " + option);
  }
  // Holding the lock, this run is the only writer: what a killed run left is undone now.
  recovered_ = recoverInterruptedWrite(folder);
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(lockFd_, 0) != 0 ||
      ::pwrite(lockFd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    const std::string why = std::strerror(errno);
    release();
    throw InputError(name + ": cannot write there: " + why);
  }
}

OutputFolder::~OutputFolder() {
  release();
}

void OutputFolder::release() {
  std::error_code ignored;
  if (!committed_ && createdLockFile_) std::filesystem::remove(folder_ / kLockName, ignored);
  if (lockFd_ >= 0) {
    ::close(lockFd_);  // releases the flock
    lockFd_ = -1;
  }
  if (!committed_) {
    // Only empty folders: whatever else is there is not this run's.
    for (auto it = created_.rbegin(); it != created_.rend(); ++it) {
      std::filesystem::remove(*it, ignored);
    }
  }
  created_.clear();
  createdLockFile_ = false;
}

}  // namespace clipray
