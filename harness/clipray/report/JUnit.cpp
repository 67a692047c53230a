// junitXml: the JUnit XML of a reconcile (see JUnit.hpp).

#include "clipray/report/JUnit.hpp"

#include <cstdio>
#include <string>

#include "clipray/io/XmlText.hpp"

namespace clipray {

namespace {

std::string seconds(const RunTimings& t) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3f",
                (t.raster + t.readback + t.rays + t.intersect + t.compare) / 1000.0);
  return buffer;
}

// The convention check's findings on the run's camera, for a failure's text or a passing run's
// output; empty without findings.
std::string conventionText(const RunRecord& run) {
  if (run.conventionFindings.empty()) return "";
  return "convention check (clipray check on the camera under the run's state):\n" +
         conventionFindingsText(run, "  ");
}

// A run that fails only for its camera's convention check: the findings first, then its line.
std::string conventionFailureText(const RunRecord& run) {
  return std::to_string(unexpectedConventionErrors(run)) +
         " convention error(s) the scene does not expect (raster and rays agree)\n" +
         runSummaryLine(run) + "\n" + conventionText(run);
}

// What a person reading the CI log needs first: which pixels are wrong, how many, how badly.
std::string failureText(const RunRecord& run, const std::filesystem::path& outDir) {
  const RunMetrics& m = run.metrics;
  char buffer[512];
  char worst[64] = "no depths compared";
  if (m.depthCompared > 0) {
    std::snprintf(worst, sizeof worst, "worst error / tolerance %.3g", m.toleranceRatio.max);
  }
  std::snprintf(buffer, sizeof buffer,
                "%lld unexplained coverage mismatches, %lld unexplained id mismatches, %lld depths "
                "beyond tolerance (%s) of %lld pixels",
                static_cast<long long>(m.coverageMismatch.unexplained),
                static_cast<long long>(m.idMismatch.unexplained),
                static_cast<long long>(m.depthBeyondTolerance), worst,
                static_cast<long long>(m.pixels));
  std::string text = buffer;
  text.append("\n").append(runSummaryLine(run));
  // Where to look: the largest clusters, in both coordinate systems a person may have at hand.
  const MismatchClusters& clusters = run.clusters;
  if (!clusters.largest.empty()) {
    text += "\nlargest unexplained clusters (" + std::to_string(clusters.largest.size()) + " of " +
            std::to_string(clusters.count) + ", 8-connected):";
  }
  for (const MismatchCluster& c : clusters.largest) {
    const int height = run.size.height;
    std::snprintf(buffer, sizeof buffer,
                  "\n  %lld px at GL window (%d, %d) = image (%d, %d), GL bounds (%d, %d) - (%d, "
                  "%d): coverage %lld, id %lld, depth %lld",
                  static_cast<long long>(c.pixels), c.x, c.y, c.x, imageY(c.y, height), c.minX,
                  c.minY, c.maxX, c.maxY, static_cast<long long>(c.coverageUnexplained),
                  static_cast<long long>(c.idUnexplained),
                  static_cast<long long>(c.depthBeyondTolerance));
    text += buffer;
  }
  // Which side hit what: at the worst pixel and at each cluster's pixel.
  const std::string hits = runHitsText(run, "  ");
  if (!hits.empty()) {
    text += "\nwhich side hit what (GL window pixels):\n" + hits;
    text.pop_back();  // the last line's newline
  }
  if (!run.images.empty()) {
    text += "\nimages:";
    for (const EncodedImage& image : run.images) {
      text.append(" ").append((outDir / image.relativePath).string());
    }
  }
  const std::string convention = conventionText(run);
  if (!convention.empty()) {
    text += "\n" + convention;
    text.pop_back();  // the last line's newline
  }
  return text;
}

}  // namespace

std::string junitXml(const std::vector<RunRecord>& runs, const std::filesystem::path& outDir) {
  std::size_t failures = 0;
  RunTimings total;
  for (const RunRecord& run : runs) {
    failures += runPasses(run) ? 0 : 1;
    total.raster += run.timings.raster;
    total.readback += run.timings.readback;
    total.rays += run.timings.rays;
    total.intersect += run.timings.intersect;
    total.compare += run.timings.compare;
  }
  std::string counts = "tests=\"";
  counts.append(std::to_string(runs.size()))
      .append("\" failures=\"")
      .append(std::to_string(failures))
      .append("\" errors=\"0\" time=\"")
      .append(seconds(total))
      .append("\"");
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out.append("<testsuites name=\"clipray reconcile\" ").append(counts).append(">\n");
  out.append("  <testsuite name=\"clipray reconcile\" ").append(counts).append(">\n");
  for (const RunRecord& run : runs) {
    std::string name = run.camera;
    name.append(" ")
        .append(run.convention.name())
        .append(" ")
        .append(depthFormatName(run.depthFormat))
        .append(" ")
        .append(vertexModeName(run.vertexMode))
        .append(sampleSuffix(run));
    out.append("    <testcase classname=\"")
        .append(xmlEscaped(run.scene))
        .append("\" name=\"")
        .append(xmlEscaped(name))
        .append("\" time=\"")
        .append(seconds(run.timings))
        .append("\"");
    const RunVerdict verdict = runVerdict(run);
    if (verdict == RunVerdict::Consistent) {
      // Expected findings and warnings: shown, not failed.
      const std::string convention = conventionText(run);
      if (convention.empty()) {
        out += "/>\n";
        continue;
      }
      out.append(">\n      <system-out>")
          .append(xmlEscaped(convention))
          .append("</system-out>\n    </testcase>\n");
      continue;
    }
    const bool conventionError = verdict == RunVerdict::ConventionError;
    out.append(">\n      <failure message=\"")
        .append(conventionError ? "convention error" : "inconsistent")
        .append("\" type=\"")
        .append(runVerdictName(verdict))
        .append("\">")
        .append(xmlEscaped(conventionError ? conventionFailureText(run) : failureText(run, outDir)))
        .append("</failure>\n    </testcase>\n");
  }
  out += "  </testsuite>\n</testsuites>\n";
  return out;
}

}  // namespace clipray
