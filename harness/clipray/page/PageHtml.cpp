// index.html and picks.png of `clipray reconcile --page` (PageHtml.hpp).

#include "clipray/page/PageHtml.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "clipray/io/XmlText.hpp"
#include "clipray/report/HtmlReport.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/util/OptionValues.hpp"
#include "clipray/util/Version.hpp"

namespace clipray::page {

namespace {

constexpr int kMaxImageSide = 512;
constexpr std::size_t kWorstShown = 10;

std::string escaped(const std::string& text) {
  return xmlEscaped(text);
}

std::string figure(double value) {
  return sixDigits(value);
}

std::string factRow(const std::string& name, const std::string& value) {
  return "<tr><th>" + escaped(name) + "</th><td>" + escaped(value) + "</td></tr>\n";
}

std::string css(Rgb c) {
  return "rgb(" + std::to_string(c.r) + "," + std::to_string(c.g) + "," + std::to_string(c.b) + ")";
}

std::string swatch(Rgb c) {
  return "<span class=\"swatch\" style=\"background:" + css(c) + "\"></span>";
}

int cellSize(const PageReconcileResult& run) {
  return std::clamp(kMaxImageSide / std::max(run.columns, run.rows), 1, kPickCell);
}

std::string verdictOf(const PageReconcileResult& run) {
  return run.consistent() ? "consistent" : "inconsistent";
}

// A run's row in #runs.
std::string runRow(const PageReconcileResult& run, const std::string& key, const std::string& title,
                   const std::string& image) {
  const PageReconcileResult::Counts c = run.counts();
  const auto pair = [](std::uint64_t edge, std::uint64_t unexplained) {
    return std::to_string(edge) + "/" + std::to_string(unexplained);
  };
  std::string out = "<tr class=\"run " + verdictOf(run) + "\" data-run=\"" + key + "\"><td>" +
                    escaped(title) + "</td><td class=\"verdict\">" + verdictOf(run) + "</td>";
  out += "<td class=\"figures\">" + std::string(run.reversedDepthBuffer ? "on" : "off") + ", " +
         escaped(run.clipDepth) + ", cleared to " + figure(run.clearDepth) + ", depthRange " +
         figure(run.depthRangeNear) + ", " + figure(run.depthRangeFar) + ", " +
         escaped(run.depthFormat) + "</td>";
  out += "<td class=\"figures\">" + std::to_string(c.agreeSurface) + "+" +
         std::to_string(c.agreeBackground) + "</td><td class=\"figures\">" +
         pair(c.depthEdge, c.depthUnexplained) + "</td><td class=\"figures\">" +
         pair(c.rayOnlyEdge, c.rayOnlyUnexplained) + "</td><td class=\"figures\">" +
         pair(c.rasterOnlyEdge, c.rasterOnlyUnexplained) + "</td><td class=\"figures\">" +
         figure(run.maxDepthError()) + " (" + figure(run.maxErrorOverTolerance()) +
         " tol)</td><td>" + escaped(pageStateCheckCounts(run.check)) + "</td><td class=\"thumbs\">";
  if (!image.empty()) {
    out += "<img class=\"thumb\" src=\"" + escaped(image) + "\" alt=\"picks of " + escaped(title) +
           "\" width=\"" + std::to_string(run.columns * cellSize(run)) + "\" height=\"" +
           std::to_string(run.rows * cellSize(run)) + "\">";
  }
  return out + "</td></tr>\n";
}

// The worst picks of a run (largest |dz| over tolerance first; misses and coverage mismatches
// after those with a depth) and its state check's findings.
std::string runSection(const PageReconcileResult& run, const std::string& key,
                       const std::string& title) {
  std::string out = "<section class=\"run\" data-run=\"" + key + "\">\n<h2>" + escaped(title) +
                    ": " + verdictOf(run) + "</h2>\n";
  std::vector<const PagePick*> worst;
  for (const PagePick& pick : run.picks) {
    if (pick.kind != PagePick::Kind::Agree) worst.push_back(&pick);
  }
  const auto ratio = [](const PagePick* pick) {
    if (!pick->hit || !pick->surface || !(pick->tolerance > 0)) return -1.0;
    return std::abs(pick->rayDepth - pick->bufferDepth) / pick->tolerance;
  };
  std::stable_sort(worst.begin(), worst.end(), [&](const PagePick* a, const PagePick* b) {
    if (a->ambiguous != b->ambiguous) return !a->ambiguous;
    return ratio(a) > ratio(b);
  });
  if (worst.empty()) {
    out += "<p class=\"note\">Every pick agrees.</p>\n";
  } else {
    out += "<h3>The worst picks (" + std::to_string(std::min(worst.size(), kWorstShown)) + " of " +
           std::to_string(worst.size()) +
           " mismatches; unexplained first, largest error over tolerance first)</h3>\n";
    out +=
        "<table class=\"worst\">\n<tr><th>pixel</th><th>class</th><th>object</th><th>ray "
        "depth</th><th>buffer depth</th><th>tolerance</th><th>|dz| / tolerance</th></tr>\n";
    for (std::size_t k = 0; k < std::min(worst.size(), kWorstShown); ++k) {
      const PagePick& pick = *worst[k];
      out +=
          "<tr data-x=\"" + std::to_string(pick.x) + "\" data-y=\"" + std::to_string(pick.y) +
          "\"><td class=\"figures\">" + std::to_string(pick.x) + ", " + std::to_string(pick.y) +
          "</td><td>" + pagePickClassName(pick.kind) + (pick.ambiguous ? " (edge-ambiguous)" : "") +
          "</td><td>" + (pick.hit ? escaped(pick.object) : std::string("nothing")) +
          "</td><td class=\"figures\">" + (pick.hit ? figure(pick.rayDepth) : "") +
          "</td><td class=\"figures\">" + figure(pick.bufferDepth) + "</td><td class=\"figures\">" +
          (pick.hit && std::isfinite(pick.tolerance) ? figure(pick.tolerance) : "") +
          "</td><td class=\"figures\">" + (ratio(&pick) >= 0 ? figure(ratio(&pick)) : "") +
          "</td></tr>\n";
    }
    out += "</table>\n";
  }
  out += "<h3>State check (clipray check --page): " + escaped(pageStateCheckCounts(run.check)) +
         "</h3>\n<ul class=\"findings\">\n";
  for (const CanvasCheck& canvas : run.check.canvases) {
    if (!canvas.result) {
      out +=
          "<li>" + escaped(canvas.name) + " not checked: " + escaped(canvas.notChecked) + "</li>\n";
      continue;
    }
    const auto list = [&](const std::vector<Finding>& findings, const std::string& where) {
      for (const Finding& f : findings) {
        out += "<li data-code=\"" + escaped(f.code) + "\"><span class=\"" + escaped(f.severity) +
               "\">" + escaped(f.severity) + " " + escaped(f.code) + "</span> (" + escaped(where) +
               "): " + escaped(f.message) + "</li>\n";
      }
    };
    list(canvas.result->findings, canvas.name);
    for (const trace::TracePairGroup& group : canvas.result->groups) {
      list(group.report.findings, canvas.name + ", " + group.source);
    }
  }
  return out + "</ul>\n</section>\n";
}

std::string legend() {
  const auto row = [](const PagePick& example, const std::string& text) {
    return "<tr><td>" + swatch(pagePickColour(example)) + "</td><td>" + escaped(text) +
           "</td></tr>\n";
  };
  PagePick surface, background, edge, depth, rayOnly, rasterOnly;
  surface.hit = true;
  edge.kind = PagePick::Kind::RayOnly;
  edge.ambiguous = true;
  depth.kind = PagePick::Kind::DepthBeyondTolerance;
  rayOnly.kind = PagePick::Kind::RayOnly;
  rasterOnly.kind = PagePick::Kind::RasterOnly;
  return "<h2>Colours of the picks images</h2>\n<table id=\"legend-picks\">\n" +
         row(surface, "agree: the ray's first hit within the tolerance of the buffer's depth") +
         row(background, "agree: no hit, the pixel kept the clear depth") +
         row(edge,
             "edge-ambiguous mismatch: the rays 2^-SUBPIXEL_BITS pixel around the centre reach "
             "different objects") +
         row(depth, "depth beyond tolerance (unexplained)") +
         row(rayOnly, "ray-only: the ray hits, the pixel kept the clear depth (unexplained)") +
         row(rasterOnly, "raster-only: no hit, the pixel was drawn (unexplained)") + "</table>\n";
}

}  // namespace

Rgb pagePickColour(const PagePick& pick) {
  if (pick.kind == PagePick::Kind::Agree) {
    return pixelClassColour(pick.hit ? PixelClass::Agree : PixelClass::Background);
  }
  if (pick.ambiguous) return pixelClassColour(PixelClass::CoverageEdgeAmbiguous);
  switch (pick.kind) {
    case PagePick::Kind::DepthBeyondTolerance:
      return pixelClassColour(PixelClass::DepthBeyondTolerance);
    case PagePick::Kind::RayOnly:
      return pixelClassColour(PixelClass::CoverageUnexplained);
    case PagePick::Kind::RasterOnly:
      return pixelClassColour(PixelClass::IdUnexplained);
    case PagePick::Kind::Agree:
      break;
  }
  return {255, 255, 255};
}

std::string pagePicksPng(const PageReconcileResult& run) {
  if (run.columns < 1 || run.rows < 1 ||
      run.picks.size() != static_cast<std::size_t>(run.columns) * run.rows) {
    return "";
  }
  const int cell = cellSize(run);
  const int width = run.columns * cell, height = run.rows * cell;
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3);
  for (std::size_t k = 0; k < run.picks.size(); ++k) {
    const Rgb colour = pagePickColour(run.picks[k]);
    const int column = static_cast<int>(k % static_cast<std::size_t>(run.columns));
    const int row = static_cast<int>(k / static_cast<std::size_t>(run.columns));
    for (int y = row * cell; y < (row + 1) * cell; ++y) {
      for (int x = column * cell; x < (column + 1) * cell; ++x) {
        const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
        rgb[i] = colour.r;
        rgb[i + 1] = colour.g;
        rgb[i + 2] = colour.b;
      }
    }
  }
  return encodeRgbPng(width, height, rgb);
}

std::string pageReconcileHtml(const PageReconcileResult& r, bool images) {
  const bool consistent = r.allConsistent();
  const std::string overall = consistent ? "consistent" : "inconsistent";
  std::string out = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  out += "<title>clipray reconcile --page: " + escaped(r.check.page) + ": " + overall +
         "</title>\n<style>" + std::string(reportStyle()) + "</style>\n</head>\n<body>\n";
  out += "<h1>clipray reconcile --page</h1>\n";
  const std::string toggleName =
      std::string("reversedDepthBuffer toggled ") + (r.reversedDepthBuffer ? "off" : "on");
  std::string verdict = overall + ": the page as it is " + verdictOf(r);
  if (r.toggle.run) {
    verdict += ", " + toggleName + " " + verdictOf(*r.toggle.run);
  } else if (!r.toggle.failed.empty()) {
    verdict += ", " + toggleName + " failed";
  }
  out += "<p id=\"verdict\" class=\"verdict " + overall + "\">" + escaped(verdict) + "</p>\n";
  out += "<table class=\"facts\" id=\"summary\">\n";
  out += factRow("clipray", versionString());
  out += factRow("page", r.check.page);
  out += factRow("URL", r.check.url);
  out += factRow("three.js", "r" + r.revision);
  out += factRow("canvas", r.canvas + ", drawing buffer " + std::to_string(r.width) + "x" +
                               std::to_string(r.height) + ", shown at " + figure(r.cssWidth) + "x" +
                               figure(r.cssHeight) + " CSS px, devicePixelRatio " +
                               figure(r.devicePixelRatio));
  out += factRow("camera", r.camera.value("type", std::string("camera")) + ", near " +
                               figure(r.camera.value("near", 0.0)) + ", far " +
                               figure(r.camera.value("far", 0.0)));
  out += factRow("picks", "the page's Raycaster.setFromCamera at " + std::to_string(r.columns) +
                              "x" + std::to_string(r.rows) +
                              " pixel centres, first hit against the depth buffer");
  std::string toggle;
  if (r.toggle.run) {
    toggle =
        "made: the page loaded again with its renderer's depth buffer flipped before its "
        "first frame";
  } else if (!r.toggle.skipped.empty()) {
    toggle = "not made (" + r.toggle.skipped + ")";
  } else if (!r.toggle.notApplicable.empty()) {
    toggle = "not applicable: " + r.toggle.notApplicable;
  } else {
    toggle = "failed: " + r.toggle.failed;
  }
  out += factRow(toggleName, toggle);
  out += "</table>\n";

  out +=
      "<h2>Runs</h2>\n<table id=\"runs\">\n<tr><th>run</th><th>verdict</th><th>depth "
      "(reversedDepthBuffer, clip, clear, range, format)</th><th>agree</th><th>&gt;tol "
      "e/u</th><th>ray-only e/u</th><th>raster-only e/u</th><th>max |dz|</th><th>state "
      "check</th><th>picks</th></tr>\n";
  out += runRow(r, "page", "the page as it is", images ? "picks.png" : "");
  if (r.toggle.run) {
    out += runRow(*r.toggle.run, "toggled", toggleName, images ? "picks-toggled.png" : "");
  }
  out +=
      "</table>\n<p class=\"note\">e edge-ambiguous, u unexplained; the page is consistent "
      "without unexplained picks.</p>\n";
  out += legend();
  out += runSection(r, "page", "The page as it is");
  if (r.toggle.run) out += runSection(*r.toggle.run, "toggled", toggleName);
  out += "</body>\n</html>\n";
  return out;
}

}  // namespace clipray::page
