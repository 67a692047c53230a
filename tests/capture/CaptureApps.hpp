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

// Runs a shell command in FOLDER; "" on success, else what it printed.
inline std::string runIn(const TempFolder& folder, const std::string& command,
                         const std::string& what) {
  const std::filesystem::path log = folder.path() / ".log";
  const std::string line =
      "cd '" + folder.path().string() + "' && " + command + " >'" + log.string() + "' 2>&1";
  const int raw = std::system(line.c_str());
  const int status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  const std::string output = readText(log);
  std::filesystem::remove(log);
  if (status == 0) return "";
  return what + " failed (status " + std::to_string(status) + "): " + output;
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
