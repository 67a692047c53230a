#include "clipray/util/Check.hpp"

#include <string>

namespace clipray::detail {

namespace {

// The source tree's root as this file was compiled (__FILE__ ends in harness/clipray/util/
// Check.cpp), so that a message names "harness/clipray/x/File.cpp" wherever the tree lies. A file
// compiled from elsewhere, or with a relative path, is named as the compiler named it.
std::string_view sourcePath(std::string_view file) {
  constexpr std::string_view self = __FILE__;
  constexpr std::string_view tail = "harness/clipray/util/Check.cpp";
  if (!self.ends_with(tail)) return file;
  const std::string_view root = self.substr(0, self.size() - tail.size());
  if (!root.empty() && file.starts_with(root)) file.remove_prefix(root.size());
  return file;
}

}  // namespace

void checkFailed(const char* file, int line, const char* condition, std::string_view message) {
  std::string what = std::string(sourcePath(file)) + ":" + std::to_string(line) + ": " + condition;
  if (!message.empty()) what += ": " + std::string(message);
  throw InternalError(what);
}

}  // namespace clipray::detail
