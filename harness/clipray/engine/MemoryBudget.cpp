#include "clipray/engine/MemoryBudget.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "clipray/InputError.hpp"

namespace clipray::engine {

namespace {

// A number from a one-line file (cgroup v2 writes "max" for no limit); NaN when absent.
double numberFromFile(const char* path) {
  std::ifstream file(path);
  std::string text;
  if (!(file >> text)) return std::nan("");
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' ? value : std::nan("");
}

}  // namespace

double availableMemoryBytes() {
  double available = 0.0;
  std::ifstream meminfo("/proc/meminfo");
  std::string key, unit;
  double kilobytes = 0.0;
  while (meminfo >> key >> kilobytes >> unit) {
    if (key == "MemAvailable:") {
      available = kilobytes * 1024.0;
      break;
    }
  }
  const double limit = numberFromFile("/sys/fs/cgroup/memory.max");
  const double used = numberFromFile("/sys/fs/cgroup/memory.current");
  if (std::isfinite(limit) && std::isfinite(used)) {
    const double left = std::max(0.0, limit - used);
    available = available > 0.0 ? std::min(available, left) : left;
  }
  return available;
}

MemoryBudget machineMemoryBudget() {
  const double bytes = availableMemoryBytes();
  return {bytes, memoryText(bytes) + " is available"};
}

double parseMemorySize(const std::string& text, const std::string& option) {
  char* end = nullptr;
  const double number = std::strtod(text.c_str(), &end);
  double scale = 1.0;
  const std::string suffix(end != nullptr ? end : "");
  if (suffix == "K" || suffix == "k") {
    scale = 1024.0;
  } else if (suffix == "M" || suffix == "m") {
    scale = 1024.0 * 1024.0;
  } else if (suffix == "G" || suffix == "g") {
    scale = 1024.0 * 1024.0 * 1024.0;
  } else if (!suffix.empty()) {
    scale = std::nan("");
  }
  const double bytes = number * scale;
  if (end == text.c_str() || !std::isfinite(bytes) || !(bytes >= 1.0)) {
    throw InputError(option + ": expected a size such as 8G, 512M or a number of bytes, got \"" +
                     text + "\"");
  }
  return bytes;
}

std::string memoryText(double bytes) {
  char text[32];
  if (bytes >= 1073741824.0) {
    std::snprintf(text, sizeof text, "%.2f GiB", bytes / 1073741824.0);
  } else {
    std::snprintf(text, sizeof text, "%.1f MiB", bytes / 1048576.0);
  }
  return text;
}

}  // namespace clipray::engine
