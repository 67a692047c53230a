#pragma once
// The trace-test apps (tests/traceapps/ConventionApp.cpp) captured at test time through RenderDoc's
// in-app API: librenderdoc.so preloaded, CLIPRAY_CAPTURE_RDC naming the file, on Mesa's
// surfaceless EGL platform. Shared by the capture suites.

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "support/RunCommand.hpp"

namespace clipray::testing {

struct FolderRun {
  int status = -1;     // the shell's exit status: 128 + N for a command killed by signal N
  std::string output;  // what it printed
};

// Runs a shell command in FOLDER.
inline FolderRun runInFolder(const TempFolder& folder, const std::string& command) {
  const std::filesystem::path log = folder.path() / ".log";
  const std::string line =
      "cd '" + folder.path().string() + "' && " + command + " >'" + log.string() + "' 2>&1";
  const int raw = std::system(line.c_str());
  FolderRun run;
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  run.output = readText(log);
  std::filesystem::remove(log);
  return run;
}

inline std::string failureOf(const FolderRun& run, const std::string& what) {
  if (run.status == 0) return "";
  return what + " failed (status " + std::to_string(run.status) + "): " + run.output;
}

// Runs a shell command in FOLDER; "" on success, else what it printed.
inline std::string runIn(const TempFolder& folder, const std::string& command,
                         const std::string& what) {
  return failureOf(runInFolder(folder, command), what);
}

// The same for a command that replays a capture in RenderDoc (the capture reader run directly):
// run once more when a signal killed it, as clipray's own reader runs are (CaptureFileCheck.cpp's
// runReader: RenderDoc 1.24's replay now and then dies by SIGSEGV as it starts).
inline std::string runReplayIn(const TempFolder& folder, const std::string& command,
                               const std::string& what) {
  FolderRun run = runInFolder(folder, command);
  if (run.status > 128) run = runInFolder(folder, command);
  return failureOf(run, what);
}

// FOLDER/CASE.rdc: one frame of `clipray_trace_app CASE 1` through RenderDoc's in-app API.
inline std::string captureCase(const std::string& name, const TempFolder& folder) {
  const std::string failure = runIn(
      folder,
      "CLIPRAY_CAPTURE_RDC='" + (folder.path() / (name + ".rdc")).string() + "' LD_PRELOAD='" +
          CLIPRAY_RENDERDOC_LIBRARY + "' '" + CLIPRAY_TRACE_APP + "' " + name + " 1",
      "the RenderDoc capture of " + name + " (is Debian's renderdoc installed?)");
  if (failure.empty() && !std::filesystem::exists(folder.path() / (name + ".rdc"))) {
    return "the RenderDoc capture of " + name + " wrote no file";
  }
  return failure;
}

}  // namespace clipray::testing
