#pragma once
// index.html, the report a person reads: one self-contained page (no network, inline CSS, images
// by paths relative to the output folder it sits in): the summary and where it came from, one row
// per run (the worst first, as in the text summary) with its figures and thumbnails, the legend of
// every colour of the images, and for each inconsistent run its largest unexplained clusters with
// their coordinates and enlarged crops. docs/reconcile.md describes the page.

#include <string>
#include <vector>

#include "clipray/report/Report.hpp"

namespace clipray {

// The style sheet index.html carries inline (reconcile --page's index.html uses it too).
const char* reportStyle();

std::string reportHtml(const std::vector<RunRecord>& runs, const GlInfo& gl,
                       const ReportProvenance& provenance = {});

}  // namespace clipray
