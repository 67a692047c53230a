// `clipray check --trace`: runs `apitrace dump` on the trace and streams its text, line by line
// from a pipe, into the trace checker (harness/clipray/trace/). apitrace's stderr goes into the
// same pipe, so its "warning: unexpected end of file" and "error: ..." lines reach the checker.
// Only the distinct (matrix, depth state) pairs are kept, never the dump.
//
// The dump runs with --blobs, in a private temporary folder (removed afterwards): apitrace writes
// each call's buffer data there as blob_call<N>.bin, the checker reads the uniform buffers'
// bytes from those files, and each file is removed once its line is read, so the folder holds a
// pipe's worth of calls at most.
//
// CLIPRAY_APITRACE overrides the apitrace executable (default: "apitrace" on PATH).

#include "clipray/trace/TraceFileCheck.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "clipray/InputError.hpp"
#include "clipray/io/InputFile.hpp"
#include "clipray/trace/DumpLine.hpp"
#include "clipray/trace/ReplayDepth.hpp"
#include "clipray/trace/TraceCheck.hpp"

namespace clipray::trace {

namespace {

// A line longer than this is no dump line apitrace writes for a GL app (blobs are files, the line
// names them: blob("blob_call45.bin"); a shader source is the longest string): refused rather
// than held.
constexpr std::size_t kMaxDumpLineBytes = 64u << 20;
constexpr int kExecFailed = 127;
constexpr int kChdirFailed = 126;
// --verify replays the trace once per group, up to the group's first draw.
constexpr std::size_t kMaxReplays = 8;
// A state dump holds every bound texture and buffer; beyond this the group is not verified.
constexpr std::size_t kMaxStateBytes = 512u << 20;

// A child process whose stdout (and stderr, or /dev/null) comes back through a pipe.
class DumpProcess {
 public:
  DumpProcess(std::vector<std::string> words, bool mergeStderr, const char* waffle = nullptr,
              const char* workingDirectory = nullptr) {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) {
      throw std::runtime_error("pipe: " + std::string(strerror(errno)));
    }
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("fork: " + std::string(strerror(errno)));
    if (pid_ == 0) {
      dup2(fds[1], STDOUT_FILENO);
      if (mergeStderr) {
        dup2(fds[1], STDERR_FILENO);
      } else {
        const int null = open("/dev/null", O_WRONLY);
        if (null >= 0) dup2(null, STDERR_FILENO);
      }
      if (waffle) setenv("WAFFLE_PLATFORM", waffle, 1);
      if (workingDirectory && chdir(workingDirectory) != 0) _exit(kChdirFailed);
      std::vector<char*> argv;
      for (std::string& word : words) argv.push_back(word.data());
      argv.push_back(nullptr);
      execvp(argv[0], argv.data());
      _exit(kExecFailed);
    }
    close(fds[1]);
    fd_ = fds[0];
  }

  ~DumpProcess() {
    if (fd_ >= 0) close(fd_);
    if (pid_ > 0 && !reaped_) {
      kill(pid_, SIGTERM);
      int status = 0;
      waitpid(pid_, &status, 0);
    }
  }

  // Reads up to `size` bytes; 0 at the end.
  std::size_t read(char* buffer, std::size_t size) {
    while (true) {
      const ssize_t got = ::read(fd_, buffer, size);
      if (got >= 0) return static_cast<std::size_t>(got);
      if (errno != EINTR)
        throw std::runtime_error("reading apitrace's output: " + std::string(strerror(errno)));
    }
  }

  // Stops the dump early (the frames asked for are read) and returns its exit status.
  int finish(bool early) {
    close(fd_);
    fd_ = -1;
    if (early) kill(pid_, SIGTERM);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    reaped_ = true;
    if (early) return 0;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

 private:
  pid_t pid_ = -1;
  int fd_ = -1;
  bool reaped_ = false;
};

// A folder of its own under the system's temporary folder, removed with what is in it.
class PrivateFolder {
 public:
  PrivateFolder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "clipray-dump-XXXXXX").string();
    if (!mkdtemp(pattern.data())) {
      throw std::runtime_error("cannot create a temporary folder for apitrace's blob files: " +
                               std::string(strerror(errno)));
    }
    path_ = pattern;
  }
  ~PrivateFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  PrivateFolder(const PrivateFolder&) = delete;
  PrivateFolder& operator=(const PrivateFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace

TraceCheckResult checkTrace(const std::string& tracePath, const std::string& frames) {
  requireReadableFile(tracePath);
  const trace::FrameRange range =
      frames.empty() ? trace::FrameRange{} : trace::parseFrameRange(frames);
  const char* overridden = std::getenv("CLIPRAY_APITRACE");
  const std::string apitrace = overridden && *overridden ? overridden : "apitrace";
  trace::TraceCheckCollector collector(tracePath, range);
  const PrivateFolder blobs;
  collector.setBlobDirectory(blobs.path());
  // The dump runs in the blob folder: the trace's path is made absolute first.
  const std::string traceFile = std::filesystem::absolute(tracePath).string();
  DumpProcess dump(
      {apitrace, "dump", "--color=never", "--multiline=false", "--blobs", "--", traceFile}, true,
      nullptr, blobs.path().c_str());
  const auto addLine = [&](std::string_view line) {
    const bool wantsMore = collector.addLine(line);
    if (line.find("blob(\"") != std::string_view::npos) {
      for (const std::string& name : trace::blobFileNames(line)) {
        std::error_code ignored;
        std::filesystem::remove(blobs.path() / name, ignored);
      }
    }
    return wantsMore;
  };
  std::string pending;
  std::vector<char> buffer(1 << 16);
  bool more = true;
  std::uint64_t lines = 0;
  while (more) {
    const std::size_t got = dump.read(buffer.data(), buffer.size());
    if (got == 0) break;
    std::size_t start = 0;
    for (std::size_t k = 0; k < got && more; ++k) {
      if (buffer[k] != '\n') continue;
      if (pending.empty()) {
        more = addLine(std::string_view(buffer.data() + start, k - start));
      } else {
        pending.append(buffer.data() + start, k - start);
        more = addLine(pending);
        pending.clear();
      }
      ++lines;
      start = k + 1;
    }
    if (more) pending.append(buffer.data() + start, got - start);
    if (pending.size() > kMaxDumpLineBytes) {
      throw InputError(tracePath + ": a dump line longer than " +
                       std::to_string(kMaxDumpLineBytes) + " bytes");
    }
  }
  if (more && !pending.empty()) more = addLine(pending);
  const int status = dump.finish(!more);
  if (status == kExecFailed && lines == 0) {
    throw InputError(apitrace +
                     ": cannot run apitrace (not installed?): install Debian's "
                     "apitrace (harness/install-deps.sh), or set CLIPRAY_APITRACE");
  }
  if (status == kChdirFailed && lines == 0) {
    throw InputError(apitrace + ": cannot run apitrace in the temporary folder " +
                     blobs.path().string());
  }
  TraceCheckResult result = collector.finish();
  if (status != 0) {
    throw InputError(tracePath + ": apitrace dump failed (exit status " + std::to_string(status) +
                     ")");
  }
  return result;
}

void verifyTrace(const std::string& tracePath, TraceCheckResult& result) {
  const char* overridden = std::getenv("CLIPRAY_EGLRETRACE");
  const std::string retrace = overridden && *overridden ? overridden : "eglretrace";
  std::size_t replayed = 0;
  for (trace::TracePairGroup& group : result.groups) {
    const bool textureSpace =
        std::any_of(group.report.findings.begin(), group.report.findings.end(),
                    [](const Finding& f) { return f.code == "texture-space-matrix"; });
    if (!group.unusable.empty() || textureSpace) continue;
    if (replayed == kMaxReplays) {
      group.verifyObservations.push_back("not replayed: at most " + std::to_string(kMaxReplays) +
                                         " groups are");
      continue;
    }
    ++replayed;
    // The state after the group's first draw, replayed headlessly on Mesa's surfaceless EGL.
    // (A glBegin's fragments are written by its glEnd: eglretrace cannot dump inside the pair.)
    DumpProcess replay(
        {retrace, "-D", std::to_string(group.first.completedAtCall), "--", tracePath}, false,
        "surfaceless_egl");
    std::string state;
    std::vector<char> buffer(1 << 16);
    bool tooLarge = false;
    while (const std::size_t got = replay.read(buffer.data(), buffer.size())) {
      if (state.size() + got > kMaxStateBytes) {
        tooLarge = true;
        break;
      }
      state.append(buffer.data(), got);
    }
    const int status = replay.finish(tooLarge);
    std::string failure;
    if (tooLarge) failure = "its state dump exceeds " + std::to_string(kMaxStateBytes) + " bytes";
    if (failure.empty() && status == kExecFailed && state.empty()) {
      failure = "cannot run " + retrace + " (Debian's apitrace; or set CLIPRAY_EGLRETRACE)";
    }
    if (failure.empty() && status != 0) {
      failure = retrace + " exited with status " + std::to_string(status);
    }
    std::optional<trace::DepthImage> image;
    if (failure.empty()) {
      try {
        image = trace::depthImageFromState(state);
        if (!image) failure = "the replayed state has no depth buffer";
      } catch (const std::invalid_argument& error) {
        failure = error.what();
      }
    }
    if (!failure.empty()) {
      group.verifyObservations.push_back("not verified: " + failure);
      group.verify = {{"call", group.first.completedAtCall}, {"failure", failure}};
      continue;
    }
    const trace::DepthUse use = trace::analyseDepthUse(*image, group);
    group.verifyObservations = use.observations;
    group.verify = trace::depthUseJson(use);
  }
}

}  // namespace clipray::trace
