#pragma once
// What the trace unit tests share: a dump's text checked line by line as `clipray check --trace`
// reads it, and a group's findings as "severity:code".

#include <sstream>
#include <string>
#include <vector>

#include "clipray/trace/TraceCheck.hpp"

namespace clipray::trace::testing {

inline TraceCheckResult checkLines(const std::string& text, FrameRange frames = {}) {
  TraceCheckCollector collector("app.trace", frames);
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (!collector.addLine(line)) break;
  }
  return collector.finish();
}

inline std::vector<std::string> codes(const TracePairGroup& group) {
  std::vector<std::string> result;
  for (const Finding& f : group.report.findings) result.push_back(f.severity + ":" + f.code);
  return result;
}

}  // namespace clipray::trace::testing
