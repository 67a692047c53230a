#pragma once
// `clipray reconcile --page --out DIR`: index.html beside page-report.json, as a scene's reconcile
// writes one (HtmlReport.hpp, with its style sheet): the page, its three.js revision, canvas size
// and devicePixelRatio; one row per run (the page as it is, and toggled: PageToggle.hpp) with its
// depth state, the counts per class, the state check's counts and its picks image; the colours;
// per run the worst picks (the mismatches, largest error over tolerance first: pixel, object, ray
// depth, buffer depth, tolerance) and the state check's findings. Elements a test may look for
// carry ids: #verdict, #summary, #runs (tr.run, data-run = "page" or "toggled"), #legend-picks,
// section.run (data-run) with table.worst and ul.findings.
//
// picks.png (and picks-toggled.png): the C x R grid of picks, one cell of kPickCell x kPickCell
// pixels a pick (fewer for large grids: the image at most 512 pixels a side, at least one pixel a
// pick), coloured by class as pagePickColour says.

#include <string>

#include "clipray/page/PageReconcile.hpp"
#include "clipray/report/RunImages.hpp"

namespace clipray::page {

inline constexpr int kPickCell = 8;

// A pick's colour in picks.png (the legend of index.html lists them): agree on a surface grey,
// agree on the background black, any edge-ambiguous mismatch yellow, depth beyond tolerance
// orange, ray-only red, raster-only magenta (mismatch.png's colours of the like classes).
Rgb pagePickColour(const PagePick& pick);

// picks.png of one run; "" where the picks do not fill the grid.
std::string pagePicksPng(const PageReconcileResult& run);

// index.html; the picks images by the names picks.png and picks-toggled.png where `images`.
std::string pageReconcileHtml(const PageReconcileResult& result, bool images);

}  // namespace clipray::page
