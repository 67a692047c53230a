#pragma once
// Runs the clipray binary the way a user's shell would and captures status, stdout and stderr.

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace clipray::testing {

struct CommandResult {
  int status = -1;
  std::string out;
  std::string err;
};

inline std::string readText(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

// `arguments` is appended to the binary path as shell words; `environment` is prefixed
// (e.g. "CLIPRAY_OSMESA_LIBRARY=/nope"). Runs in `workingDirectory`.
inline CommandResult runClipray(const std::string& arguments,
                                const std::filesystem::path& workingDirectory,
                                const std::string& environment = "") {
  const std::filesystem::path outFile = workingDirectory / ".stdout.txt";
  const std::filesystem::path errFile = workingDirectory / ".stderr.txt";
  const std::string command = "cd '" + workingDirectory.string() + "' && " + environment + " '" +
                              std::string(CLIPRAY_BINARY) + "' " + arguments + " >'" +
                              outFile.string() + "' 2>'" + errFile.string() + "'";
  const int raw = std::system(command.c_str());
  CommandResult result;
  result.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  result.out = readText(outFile);
  result.err = readText(errFile);
  std::filesystem::remove(outFile);
  std::filesystem::remove(errFile);
  return result;
}

// A fresh empty folder under the system temp folder, removed when the object dies.
class TempFolder {
 public:
  TempFolder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "clipray-test-XXXXXX").string();
    path_ = mkdtemp(pattern.data());
  }
  ~TempFolder() { std::filesystem::remove_all(path_); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace clipray::testing
