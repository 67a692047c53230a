#pragma once
// `clipray reconcile --junit FILE`: the runs as a JUnit XML report, the format CI systems read
// (GitLab's junit artifacts, Jenkins, GitHub Actions test reporters): one <testcase> per run
// (class: the scene; name: camera, convention, depth format and vertex mode, as the summary line
// has them), failed when the run is inconsistent, with the run's summary line and its counts as the
// failure text.

#include <filesystem>
#include <string>
#include <vector>

#include "clipray/report/Report.hpp"

namespace clipray {

// outDir: the reconcile's --out, which the images' paths in the failure text start from.
std::string junitXml(const std::vector<RunRecord>& runs, const std::filesystem::path& outDir);

}  // namespace clipray
