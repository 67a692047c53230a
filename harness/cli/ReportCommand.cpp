// `clipray report merge DIR... --out OUT [--junit FILE]`: the reports of a sharded reconcile (one
// CI job per shard) as one report, as if one run had made them all.

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "Commands.hpp"
#include "clipray/InputError.hpp"
#include "clipray/io/OutputFolder.hpp"
#include "clipray/report/JUnit.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/report/ReportReading.hpp"

namespace clipray::cli {
namespace {

struct MergeOptions {
  std::vector<std::string> folders;
  std::string out = "report";
  std::string junit;
};

int runMerge(const MergeOptions& options) {
  std::vector<ReadReport> reports;
  for (const std::string& folder : options.folders) {
    std::error_code error;
    if (!std::filesystem::is_directory(folder, error)) {
      throw InputError(folder + ": not a report folder (no such folder)");
    }
    if (std::filesystem::equivalent(folder, options.out, error)) {
      throw InputError("--out " + options.out + ": is one of the reports merged (" + folder +
                       "); merge into another folder");
    }
    reports.push_back(readReport(folder));
  }
  const std::vector<RunRecord> runs = mergeReports(reports);
  OutputFolder out(options.out);
  ReportProvenance provenance{commandLine(), utcNow()};
  writeReport(options.out, runs, reports.front().gl, provenance);
  out.commit();
  if (!options.junit.empty()) writeFileAtomically(options.junit, junitXml(runs, options.out));
  std::cout << textSummary(runs);
  std::cout << "report: " << (std::filesystem::path(options.out) / "index.html").string()
            << " (report.json beside it; merged from " << reports.size() << " reports)\n";
  for (const RunRecord& run : runs) {
    if (!runPasses(run)) return 1;
  }
  return 0;
}

CommandRunner addReportOptions(CLI::App& app) {
  auto options = std::make_shared<MergeOptions>();
  app.require_subcommand(1);
  CLI::App* merge = app.add_subcommand(
      "merge", "Merge the reports of the shards of a reconcile (--shard I/N) into one");
  merge->add_option("folders", options->folders, "Report folders (each with its report.json)")
      ->required();
  merge->add_option("--out", options->out, "Output folder for the merged report")
      ->capture_default_str();
  merge->add_option("--junit", options->junit, "Also write the merged runs as JUnit XML");
  return [options] { return runMerge(*options); };
}

const bool registered =
    registerCommand({"report", "Work with reports: merge the reports of a sharded reconcile", 30,
                     addReportOptions});

}  // namespace
}  // namespace clipray::cli
