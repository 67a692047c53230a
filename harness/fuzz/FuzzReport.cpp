// libFuzzer target: report.json as `clipray report merge` reads it back (its images looked up in a
// folder that does not exist), merged, and written again. Any input may be rejected with an
// InputError; anything else is a bug, and so is a report that reads back as other runs than the
// ones it was written from.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "clipray/InputError.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/report/ReportReading.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const clipray::ReadReport report =
        clipray::parseReport(text, "/nonexistent-fuzz-report", "fuzz.json");
    const std::vector<clipray::RunRecord> runs = clipray::mergeReports({report});
    (void)clipray::textSummary(runs);
    // Written again and read back, the report is the same report.
    const std::string again = clipray::reportJson(runs, report.gl, report.provenance).dump();
    const clipray::ReadReport reread =
        clipray::parseReport(again, "/nonexistent-fuzz-report", "again.json");
    if (clipray::reportJson(reread.runs, reread.gl, reread.provenance).dump() != again) {
      std::abort();
    }
  } catch (const clipray::InputError&) {
    // Rejecting bad input with a message is the expected outcome.
  }
  return 0;
}
