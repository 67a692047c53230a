#pragma once
// clipray's version: the CMake project version, and the git commit the build came from (written
// at build time by harness/cmake/WriteVersion.cmake).

#include <string>

namespace clipray {

const char* versionNumber();  // "0.1.0": project(clipray VERSION ...)
const char* gitCommit();      // "d16c754a1b2c", "-dirty" appended for local changes; "" outside git
// "0.1.0 (git d16c754a1b2c)", or "0.1.0" outside a git checkout.
inline std::string versionString() {
  const std::string commit = gitCommit();
  return std::string(versionNumber()) + (commit.empty() ? "" : " (git " + commit + ")");
}

}  // namespace clipray
