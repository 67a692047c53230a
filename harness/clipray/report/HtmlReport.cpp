// reportHtml: index.html (see HtmlReport.hpp). Elements a test or script may look for carry ids
// and data- attributes: #verdict, #summary, #runs (tr.run, data-run = the run's folder), #legend-
// classes (tr data-class = pixelClassName), #legend-heatmap, #legend-depth, #no-images, and per
// inconsistent run section.clusters (p.worst-pixel and tr.cluster with data-gl-x/-y, tr.cluster
// also with data-image-x/-y and td.hit: what the raster and the rays hit), and tr.check under a
// run whose camera's convention check has findings (data-for-run = the run's folder; details
// data-code).

#include "clipray/report/HtmlReport.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <utility>

#include "clipray/io/XmlText.hpp"
#include "clipray/report/RunImages.hpp"
#include "clipray/util/OptionValues.hpp"
#include "clipray/util/Version.hpp"

namespace clipray {
namespace {

constexpr const char* kStyle = R"css(
body { font: 14px/1.4 system-ui, sans-serif; margin: 16px 24px; color: #1a1a1a; background: #fafafa; }
h1 { font-size: 22px; margin: 0 0 8px; }
h2 { font-size: 18px; margin: 28px 0 8px; border-bottom: 1px solid #ccc; }
h3 { font-size: 15px; margin: 18px 0 6px; }
table { border-collapse: collapse; }
td, th { padding: 3px 7px; text-align: left; vertical-align: middle; }
th { background: #e8e8e8; font-weight: 600; }
tr:nth-child(even) td { background: #f0f0f0; }
.facts th { background: none; font-weight: 600; padding-right: 16px; }
.facts td, .facts tr:nth-child(even) td { background: none; }
.mono, .figures { font-family: ui-monospace, monospace; font-size: 13px; }
.figures, .facts th, td.thumbs { white-space: nowrap; }
.verdict { font-weight: 700; }
.consistent .verdict, p.verdict.consistent { color: #1b7d2c; }
.inconsistent .verdict, p.verdict.inconsistent { color: #c01818; }
.convention-error .verdict, p.verdict.convention-error { color: #b04a00; }
tr.check td { font-size: 13px; }
tr.check .error { color: #c01818; font-weight: 600; }
tr.check .warning { color: #8a6d00; font-weight: 600; }
tr.check .expected { color: #555; }
p.verdict { font-size: 18px; margin: 4px 0 12px; }
img.thumb { image-rendering: pixelated; border: 1px solid #888; }
img.crop { image-rendering: pixelated; border: 1px solid #888; }
.swatch { display: inline-block; width: 28px; height: 16px; border: 1px solid #666; vertical-align: middle; }
.bar { width: 480px; height: 20px; border: 1px solid #666; }
.ticks { position: relative; width: 480px; height: 18px; font-size: 12px; }
.ticks span { position: absolute; transform: translateX(-50%); }
.note, td.name span { color: #555; }
td.name span { font-size: 12px; }
a { color: #1a55b0; }
)css";

std::string escaped(const std::string& text) {
  return xmlEscaped(text);
}

std::string css(Rgb c) {
  return "rgb(" + std::to_string(c.r) + "," + std::to_string(c.g) + "," + std::to_string(c.b) + ")";
}

std::string swatch(Rgb c) {
  return "<span class=\"swatch\" style=\"background:" + css(c) + "\"></span>";
}

std::string count(std::int64_t value) {
  return std::to_string(value);
}

std::string figure(double value) {
  return shortNumber(value);
}

// The path of the run's image named `file`, or empty.
std::string imagePath(const RunRecord& run, const std::string& file) {
  const std::string suffix = "/" + file;
  for (const EncodedImage& image : run.images) {
    if (image.relativePath.ends_with(suffix)) return image.relativePath;
  }
  return "";
}

std::string runTitle(const RunRecord& run) {
  return runTitleText(run);
}

// What one side hit, for a table cell: "\"floor\" triangle 12<br>depth 0.499871", "nothing".
std::string hitCell(const SurfaceHit& hit) {
  std::string out = "<td class=\"hit\">" + escaped(hit.name());
  if (hit.hit() && !std::isnan(hit.depth)) out += "<br>depth " + escaped(sixDigits(hit.depth));
  return out + "</td>";
}

std::string factRow(const std::string& name, const std::string& value, bool mono = false) {
  return "<tr><th>" + escaped(name) + "</th><td" + (mono ? " class=\"mono\"" : "") + ">" +
         escaped(value) + "</td></tr>\n";
}

std::string summarySection(const std::vector<RunRecord>& runs, const GlInfo& gl,
                           const ReportProvenance& provenance) {
  std::size_t consistent = 0, conventionErrors = 0;
  for (const RunRecord& run : runs) {
    const RunVerdict verdict = runVerdict(run);
    consistent += verdict == RunVerdict::Consistent ? 1 : 0;
    conventionErrors += verdict == RunVerdict::ConventionError ? 1 : 0;
  }
  const std::size_t inconsistent = runs.size() - consistent - conventionErrors;
  const char* overall = inconsistent > 0       ? "inconsistent"
                        : conventionErrors > 0 ? "convention-error"
                                               : "consistent";
  std::string out;
  out += "<p id=\"verdict\" class=\"verdict " + std::string(overall) + "\">" + overall + ": " +
         std::to_string(runs.size()) + " runs, " + std::to_string(consistent) + " consistent, " +
         std::to_string(inconsistent) + " inconsistent" +
         (conventionErrors > 0 ? ", " + std::to_string(conventionErrors) + " convention error" +
                                     (conventionErrors == 1 ? "" : "s")
                               : std::string()) +
         "</p>\n";
  out += "<table class=\"facts\" id=\"summary\">\n";
  const std::string commit = gitCommit();
  out += factRow("clipray", versionNumber() + (commit.empty() ? "" : " (git " + commit + ")"));
  if (!provenance.commandLine.empty()) out += factRow("command", provenance.commandLine, true);
  if (!provenance.startedAt.empty()) out += factRow("started", provenance.startedAt);
  out += factRow("GL backend", gl.backend);
  out += factRow("GL vendor", gl.vendor);
  out += factRow("GL renderer", gl.renderer);
  out += factRow("GL version", gl.version);
  out += factRow("subpixel bits", std::to_string(gl.subpixelBits));
  out += "</table>\n";
  return out;
}

// An <img> shown size.width x size.height pixels.
std::string image(const std::string& path, const std::string& alt, const char* cls, Viewport size) {
  return "<img class=\"" + std::string(cls) + "\" src=\"" + escaped(path) + "\" alt=\"" +
         escaped(alt) + "\" width=\"" + std::to_string(size.width) + "\" height=\"" +
         std::to_string(size.height) + "\">";
}

// A thumbnail of a small frame, enlarged by a whole factor (its pixels stay square) towards
// kThumbnailSide.
Viewport thumbnailShownSize(Viewport frame) {
  const Viewport thumb = thumbnailSize(frame);
  const int factor = std::max(1, kThumbnailSide / std::max(thumb.width, thumb.height));
  return {thumb.width * factor, thumb.height * factor};
}

Viewport cropShownSize(const CropWindow& window) {
  return {window.width * kCropScale, window.height * kCropScale};
}

// The run's thumbnails, each linking to its full-size image where one was written.
std::string thumbnailsCell(const RunRecord& run) {
  std::string out = "<td class=\"thumbs\">";
  for (const auto& [file, full, what] : std::array<std::array<const char*, 3>, 2>{
           {{"thumb_mismatch.png", "mismatch.png", "mismatch"},
            {"thumb_heatmap.png", "error_heatmap.png", "error / tolerance"}}}) {
    const std::string thumb = imagePath(run, file);
    if (thumb.empty()) continue;
    const std::string fullPath = imagePath(run, full);
    const std::string img =
        image(thumb, runTitle(run) + ": " + what, "thumb", thumbnailShownSize(run.size));
    out += fullPath.empty()
               ? "<span title=\"no full-size image: clipray reconcile --images all writes every "
                 "run's\">" +
                     img + "</span>"
               : "<a href=\"" + escaped(fullPath) + "\">" + img + "</a>";
    out += " ";
  }
  return out + "</td>";
}

// Links to the full-size images and to the run's clusters.
std::string linksCell(const RunRecord& run, std::size_t rank) {
  std::string out = "<td>";
  bool first = true;
  for (const auto& [file, label] :
       std::array<std::array<const char*, 2>, 4>{{{"raster_depth.png", "raster depth"},
                                                  {"ray_depth.png", "ray depth"},
                                                  {"error_heatmap.png", "heat map"},
                                                  {"mismatch.png", "mismatch"}}}) {
    const std::string path = imagePath(run, file);
    if (path.empty()) continue;
    out += (first ? "" : "<br>") + ("<a href=\"" + escaped(path) + "\">" + label + "</a>");
    first = false;
  }
  if (!run.clusters.largest.empty()) {
    out += std::string(first ? "" : "<br>") + "<a href=\"#clusters-" + std::to_string(rank) +
           "\">clusters</a>";
  }
  return out + "</td>";
}

// The row under a run with findings of its camera's convention check: one line per finding (its
// severity, code and whether the scene expects it) that opens to its message and fix. Those that
// make the run's verdict convention-error are open; the others stay one line, so the runs below
// stay in view.
std::string checkRow(const RunRecord& run, std::size_t columns) {
  const bool conventionError = runVerdict(run) == RunVerdict::ConventionError;
  std::string out = "<tr class=\"check\" data-for-run=\"" + escaped(runFolderName(run)) +
                    "\"><td></td><td colspan=\"" + std::to_string(columns - 1) +
                    "\">convention check (clipray check on the camera under the run's state):";
  for (const RunFinding& f : run.conventionFindings) {
    const bool open = conventionError && f.severity == "error" && !f.expected;
    out += "<details data-code=\"" + escaped(f.code) + "\"" + (open ? " open" : "") +
           "><summary><span class=\"" + escaped(f.severity) + "\">" + escaped(f.severity) + " [" +
           escaped(f.code) + "]</span>" +
           (f.expected ? " <span class=\"expected\">(expected by the scene)</span>" : "") +
           "</summary>" + escaped(f.message);
    if (!f.fix.empty()) out += "<br>fix: " + escaped(f.fix);
    out += "</details>";
  }
  return out + "</td></tr>\n";
}

std::string runRow(const RunRecord& run, std::size_t rank, bool anyImages) {
  const RunMetrics& m = run.metrics;
  const RunVerdict verdict = runVerdict(run);
  std::string out = "<tr class=\"run " + std::string(runVerdictName(verdict)) + "\" id=\"run-" +
                    std::to_string(rank) + "\" data-run=\"" + escaped(runFolderName(run)) + "\">";
  out += "<td>" + std::to_string(rank) + "</td>";
  out += "<td class=\"verdict\">" +
         std::string(verdict == RunVerdict::Consistent     ? "consistent"
                     : verdict == RunVerdict::Inconsistent ? "INCONSISTENT"
                                                           : "CONVENTION ERROR") +
         "</td>";
  out += "<td class=\"name\">" + escaped(run.scene + "/" + run.camera) + "<br><span>" +
         escaped(run.convention.name()) + " " + escaped(depthFormatName(run.depthFormat)) + " " +
         escaped(vertexModeName(run.vertexMode) + sampleSuffix(run)) + " " +
         std::to_string(run.size.width) + "x" + std::to_string(run.size.height) + "</span></td>";
  if (anyImages) out += thumbnailsCell(run);
  out += "<td class=\"figures\">cov " + count(m.coverageMismatch.total) + " (e" +
         count(m.coverageMismatch.edgeAmbiguous) + " u" + count(m.coverageMismatch.unexplained) +
         ")<br>id " + count(m.idMismatch.total) + " (z" + count(m.idMismatch.depthAmbiguous) +
         " e" + count(m.idMismatch.edgeAmbiguous) + " u" + count(m.idMismatch.unexplained) +
         ")<br>&gt;tol " + count(m.depthBeyondTolerance) + "</td>";
  if (m.depthCompared == 0) {
    out += "<td class=\"figures\">n/a (0 compared)</td>";
  } else {
    out += "<td class=\"figures\">tol " + figure(m.toleranceRatio.max) + "/" +
           figure(m.toleranceRatio.p99) + "<br>rel " + figure(m.distanceRelError.p99) + "</td>";
  }
  if (anyImages) out += linksCell(run, rank);
  out += "</tr>\n";
  if (!run.conventionFindings.empty()) out += checkRow(run, anyImages ? 7 : 5);
  return out;
}

std::string runsSection(const std::vector<RunRecord>& runs, const std::vector<std::size_t>& order,
                        bool anyImages) {
  std::string out = "<h2>Runs</h2>\n";
  out +=
      "<p>The worst first: inconsistent runs, then by unexplained pixels, then by worst error / "
      "tolerance. cov: coverage mismatches (e edge-ambiguous, u unexplained); id: id mismatches "
      "(z depth-ambiguous, e edge-ambiguous, u unexplained); &gt;tol: depths beyond tolerance; "
      "tol: depth error / predicted tolerance, max/p99 (above 1: beyond it); rel: p99 distance "
      "error / eye distance; n/a (0 compared): no pixel where both sides hit the same "
      "primitive. Under a run, the errors and warnings of clipray check on its camera under the "
      "state it is drawn with; an error the scene does not expect fails the run as CONVENTION "
      "ERROR.";
  if (anyImages) {
    out +=
        " Thumbnails: each pixel the most severe class (or largest error / tolerance) of its "
        "block of the frame; they link to the full-size image where it was written.";
  }
  out +=
      "</p>\n<table id=\"runs\">\n<thead><tr><th>#</th><th>verdict</th>"
      "<th>scene/camera<br>convention, format, vertex mode, size</th>";
  if (anyImages) out += "<th>thumbnails: mismatch, error / tolerance</th>";
  out += "<th>mismatches</th><th>depth error</th>";
  if (anyImages) out += "<th>images</th>";
  out += "</tr></thead>\n<tbody>\n";
  for (std::size_t k = 0; k < order.size(); ++k) out += runRow(runs[order[k]], k + 1, anyImages);
  out += "</tbody>\n</table>\n";
  return out;
}

std::string boundsText(int x0, int y0, int x1, int y1) {
  return "(" + std::to_string(x0) + ", " + std::to_string(y0) + ") - (" + std::to_string(x1) +
         ", " + std::to_string(y1) + ")";
}

std::string clustersSection(const std::vector<RunRecord>& runs,
                            const std::vector<std::size_t>& order) {
  std::string out = "<h2>Unexplained clusters</h2>\n";
  out += "<p>The largest " + std::to_string(kReportedClusters) +
         " connected components (8-connected) of each inconsistent run's unexplained pixels "
         "(coverage unexplained, id unexplained, depth beyond tolerance). Each is named by one of "
         "its pixels, the nearest its centroid, in GL window coordinates (x from the left, y up "
         "from the bottom row: what glReadPixels and a picking function take) and in image "
         "coordinates (y down from the top row: what an image viewer shows); bounds are inclusive. "
         "Crops: " +
         std::to_string(kCropSide) + " x " + std::to_string(kCropSide) +
         " pixels of mismatch.png around that pixel, each drawn " + std::to_string(kCropScale) +
         " x " + std::to_string(kCropScale) + ", the pixel outlined in white.</p>\n";
  bool any = false;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const RunRecord& run = runs[order[k]];
    if (run.metrics.consistent()) continue;
    any = true;
    const std::string rank = std::to_string(k + 1);
    out += "<section class=\"clusters\" id=\"clusters-" + rank + "\" data-run=\"" +
           escaped(runFolderName(run)) + "\">\n<h3>#" + rank + " " + escaped(runTitle(run)) + ": " +
           std::to_string(run.clusters.count) +
           (run.clusters.count == 1 ? " cluster" : " clusters") + "</h3>\n";
    const int height = run.size.height;
    if (run.worstPixel) {
      const PixelHits& p = *run.worstPixel;
      out += "<p class=\"worst-pixel\" data-gl-x=\"" + std::to_string(p.x) + "\" data-gl-y=\"" +
             std::to_string(p.y) + "\">Worst pixel: GL window (" + std::to_string(p.x) + ", " +
             std::to_string(p.y) + ") = image (" + std::to_string(p.x) + ", " +
             std::to_string(imageY(p.y, height)) + "): " + escaped(p.text()) + "</p>\n";
    }
    const bool hits = !run.clusterHits.empty();
    out +=
        "<table>\n<thead><tr><th>#</th><th>pixels</th><th>coverage / id / depth</th>"
        "<th>pixel: GL window<br>image</th>";
    if (hits) out += "<th>class at the pixel</th><th>raster hit</th><th>ray hit</th>";
    out +=
        "<th>bounds: GL window<br>image</th><th>crop</th></tr></thead>\n"
        "<tbody>\n";
    for (std::size_t c = 0; c < run.clusters.largest.size(); ++c) {
      const MismatchCluster& cluster = run.clusters.largest[c];
      const int imageYValue = imageY(cluster.y, height);
      out += "<tr class=\"cluster\" data-pixels=\"" + count(cluster.pixels) + "\" data-gl-x=\"" +
             std::to_string(cluster.x) + "\" data-gl-y=\"" + std::to_string(cluster.y) +
             "\" data-image-x=\"" + std::to_string(cluster.x) + "\" data-image-y=\"" +
             std::to_string(imageYValue) + "\">";
      out += "<td>" + std::to_string(c + 1) + "</td><td>" + count(cluster.pixels) + "</td>";
      out += "<td class=\"figures\">" + count(cluster.coverageUnexplained) + " / " +
             count(cluster.idUnexplained) + " / " + count(cluster.depthBeyondTolerance) + "</td>";
      out += "<td class=\"figures\">(" + std::to_string(cluster.x) + ", " +
             std::to_string(cluster.y) + ")<br>(" + std::to_string(cluster.x) + ", " +
             std::to_string(imageYValue) + ")</td>";
      if (hits) {
        if (c < run.clusterHits.size()) {
          const PixelHits& p = run.clusterHits[c];
          out += "<td class=\"figures\">" + escaped(pixelClassName(p.pixelClass)) + "</td>" +
                 hitCell(p.raster) + hitCell(p.ray);
        } else {
          out += "<td></td><td></td><td></td>";
        }
      }
      out += "<td class=\"figures\">" +
             boundsText(cluster.minX, cluster.minY, cluster.maxX, cluster.maxY) + "<br>" +
             boundsText(cluster.minX, imageY(cluster.maxY, height), cluster.maxX,
                        imageY(cluster.minY, height)) +
             "</td>";
      const std::string crop = imagePath(run, "cluster" + std::to_string(c + 1) + ".png");
      out += "<td>" +
             (crop.empty() ? std::string("no image")
                           : image(crop, runTitle(run) + ": cluster " + std::to_string(c + 1),
                                   "crop", cropShownSize(clusterCropWindow(cluster, run.size)))) +
             "</td></tr>\n";
    }
    out += "</tbody>\n</table>\n</section>\n";
  }
  if (!any) out += "<p class=\"note\">None: every run is consistent.</p>\n";
  return out;
}

struct ClassEntry {
  PixelClass value;
  const char* label;
  const char* meaning;
};
constexpr std::array<ClassEntry, 9> kClasses{{
    {PixelClass::Agree, "agree",
     "same primitive, depth error within the predicted tolerance (mid grey)"},
    {PixelClass::InFrontOfNear, "in front of near",
     "in front of the near plane, drawn by depth clamp at the near depth (where two surfaces lie "
     "there, the first drawn shows): out of reach of a picking ray that starts on the near "
     "plane"},
    {PixelClass::DepthBeyondTolerance, "depth beyond tolerance",
     "same primitive, depth error above the tolerance (unexplained)"},
    {PixelClass::CoverageEdgeAmbiguous, "coverage, edge-ambiguous",
     "one side hits; the pixel centre is within epsilon of the primitive's outline"},
    {PixelClass::CoverageUnexplained, "coverage, unexplained",
     "one side hits, nowhere near an edge (unexplained)"},
    {PixelClass::IdDepthAmbiguous, "id, depth-ambiguous",
     "different primitives at the same depth within tolerance (z-fighting)"},
    {PixelClass::IdEdgeAmbiguous, "id, edge-ambiguous",
     "different primitives, pixel centre within epsilon of an edge of either"},
    {PixelClass::IdUnexplained, "id, unexplained",
     "different primitives, neither explanation holds (unexplained)"},
    {PixelClass::Background, "background", "neither side hits"},
}};

std::string legendSection() {
  std::string out = "<h2>Colours</h2>\n";
  out +=
      "<h3>mismatch.png, its thumbnail and the cluster crops: the class of each pixel (in the "
      "thumbnail, the most severe of its block; an unexplained block also paints the eight around "
      "it)</h3>\n";
  out += "<table class=\"legend\" id=\"legend-classes\">\n";
  for (const ClassEntry& entry : kClasses) {
    out += "<tr data-class=\"" + std::string(pixelClassName(entry.value)) + "\"><td>" +
           swatch(pixelClassColour(entry.value)) + "</td><td>" + entry.label + "</td><td>" +
           escaped(entry.meaning) + "</td></tr>\n";
  }
  out += "<tr data-class=\"outline\"><td>" + swatch({255, 255, 255}) +
         "</td><td>white outline</td><td>the cluster's pixel named by its coordinates (crops "
         "only)</td></tr>\n</table>\n";

  // The bar is exact: the ramp is linear in log10(ratio) between its stops.
  out +=
      "<h3>error_heatmap.png and its thumbnail: depth error / predicted tolerance, "
      "logarithmic</h3>\n<div id=\"legend-heatmap\">\n<div class=\"bar\" style=\"background: "
      "linear-gradient(to right";
  const double kLow = -4.0, kHigh = 1.0;  // log10 of kHeatMapFloor and kHeatMapCeiling
  const auto percent = [&](double decades) {
    char text[16];
    std::snprintf(text, sizeof text, "%.0f%%", (decades - kLow) / (kHigh - kLow) * 100.0);
    return std::string(text);
  };
  for (const double decades : {-4.0, -3.0, -2.0, -1.0, 0.0}) {
    out += ", " + css(heatMapColour(std::pow(10.0, decades))) + " " + percent(decades);
  }
  out += ", " + css(heatMapColour(std::nextafter(1.0, 2.0))) + " " + percent(0.0) + ", " +
         css(heatMapColour(kHeatMapCeiling)) + " 100%)\"></div>\n<div class=\"ticks\">";
  for (const auto& [decades, label] :
       std::array<std::pair<double, const char*>, 6>{{{-4.0, "&le;1e-4"},
                                                      {-3.0, "1e-3"},
                                                      {-2.0, "0.01"},
                                                      {-1.0, "0.1"},
                                                      {0.0, "1 = tolerance"},
                                                      {1.0, "&ge;10"}}}) {
    out += "<span style=\"left:" + percent(decades) + "\">" + label + "</span>";
  }
  out += "</div>\n<p>" + swatch(heatMapColour(std::nan(""))) +
         " not compared (the two sides do not show the same primitive). Within tolerance (up to "
         "1): one decade per step of the ramp, so a consistent run shows where it sits within its "
         "tolerance; beyond it, red turning white at 10 and above.</p>\n</div>\n";

  out += "<h3>raster_depth.png and ray_depth.png: window depth</h3>\n<p id=\"legend-depth\">" +
         swatch({kNearGrey, kNearGrey, kNearGrey}) + " nearest &nbsp; " +
         swatch({kFarGrey, kFarGrey, kFarGrey}) +
         " farthest (one range shared by both images; a flat frame is mid-grey) &nbsp; " +
         swatch(kDepthBackground) + " no hit</p>\n";
  return out;
}

}  // namespace

const char* reportStyle() {
  return kStyle;
}

std::string reportHtml(const std::vector<RunRecord>& runs, const GlInfo& gl,
                       const ReportProvenance& provenance) {
  bool anyImages = false;
  for (const RunRecord& run : runs) anyImages = anyImages || !run.images.empty();
  const std::vector<std::size_t> order = worstFirst(runs);
  std::size_t failing = 0;
  for (const RunRecord& run : runs) failing += runPasses(run) ? 0 : 1;
  std::string out = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  out += "<title>clipray reconcile: " + std::to_string(failing) + " of " +
         std::to_string(runs.size()) + " runs failing</title>\n";
  out += "<style>" + std::string(kStyle) + "</style>\n</head>\n<body>\n";
  out += "<h1>clipray reconcile</h1>\n";
  out += summarySection(runs, gl, provenance);
  if (!anyImages) {
    out +=
        "<p class=\"note\" id=\"no-images\">No images: this report was written without them "
        "(clipray reconcile --images none).</p>\n";
  }
  // The colours first: a person reads the thumbnails below with them.
  out += legendSection();
  out += runsSection(runs, order, anyImages);
  out += clustersSection(runs, order);
  out += "</body>\n</html>\n";
  return out;
}

}  // namespace clipray
