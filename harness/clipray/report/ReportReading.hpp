#pragma once
// report.json read back into the records it was written from (reportJson, Report.hpp), with the
// images it names: what `clipray report merge` puts together from the shards of a run. Figures
// JSON cannot spell (NaN, infinities, written as null) read back as NaN.

#include <filesystem>
#include <string>
#include <vector>

#include "clipray/report/Report.hpp"

namespace clipray {

struct ReadReport {
  std::filesystem::path folder;
  std::string version, gitCommit;
  GlInfo gl;
  ReportProvenance provenance;  // the shard (index, count); command line and start time
  std::vector<RunRecord> runs;  // with every image the report names, read from the folder
};

// Reads <folder>/report.json and the images it names. Throws InputError naming the file, the
// JSON pointer and the value for anything that is not a report of this format, and naming the
// image for one that is missing.
ReadReport readReport(const std::filesystem::path& folder);
// The same for report.json's text already read (`file` names it in messages).
ReadReport parseReport(const std::string& text, const std::filesystem::path& folder,
                       const std::string& file);

// The runs of reports of one clipray build and one GL driver as one report: shards of a
// `clipray reconcile --shard I/N` (all N of them, each once), or reports of disjoint runs. Throws
// InputError naming both reports where they differ in version, commit or GL, overlap in a run or
// a shard, or where a shard is missing. The runs keep the reports' order.
std::vector<RunRecord> mergeReports(const std::vector<ReadReport>& reports);

}  // namespace clipray
