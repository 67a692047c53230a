// clipray::checkCurrentState (StateCheck.hpp): engine::checkCurrentState's findings in the public
// types.

#include <algorithm>

#include "clipray/StateCheck.hpp"
#include "clipray/engine/CurrentStateCheck.hpp"

namespace clipray {

bool StateCheckResult::hasErrors() const {
  return std::any_of(findings.begin(), findings.end(),
                     [](const StateFinding& finding) { return finding.severity == "error"; });
}

StateCheckResult checkCurrentState(const glm::dmat4& clipFromWorld,
                                   GlGetProcAddress getProcAddress) {
  const engine::CurrentStateCheck check = engine::checkCurrentState(clipFromWorld, getProcAddress);
  StateCheckResult result;
  for (const Finding& finding : check.report.findings) {
    result.findings.push_back({finding.severity, finding.code, finding.message, finding.fix});
  }
  result.text = checkReportText(check.report, check.input);
  return result;
}

}  // namespace clipray
