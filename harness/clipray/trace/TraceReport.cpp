// `clipray check --trace` reports: the text summary and the JSON (stable field names).

#include <algorithm>
#include <sstream>
#include <vector>

#include "clipray/check/CheckText.hpp"
#include "clipray/trace/TraceCheck.hpp"

namespace clipray::trace {

namespace {

std::string number(double value) {
  return detail::checkNumber(value);
}

// The i of each GL_CLIP_DISTANCEi enabled.
std::vector<int> enabledClipDistances(const TraceDepthState& d) {
  std::vector<int> enabled;
  for (int i = 0; i < kGlClipDistances; ++i) {
    if ((d.clipDistances >> i) & 1u) enabled.push_back(i);
  }
  return enabled;
}

std::string depthStateText(const TraceDepthState& d) {
  std::ostringstream out;
  out << "clip control " << (d.clipUpperLeft ? "upper-left" : "lower-left") << ", "
      << (d.clipZeroToOne ? "zero-to-one" : "negative-one-to-one") << "; depth test "
      << (d.depthTest ? glEnumName(d.depthFunc) : std::string("off")) << "; depth range "
      << number(d.depthRange.x) << ", " << number(d.depthRange.y) << "; cleared to "
      << (d.clearedDepth ? number(*d.clearedDepth) : std::string("-")) << "; viewport "
      << d.viewport.width << "x" << d.viewport.height << "; depth buffer " << d.depthFormatName;
  if (d.cullFace) {
    out << "; culls " << glEnumName(d.cullFaceMode) << ", front face " << glEnumName(d.frontFace);
  }
  if (d.depthClamp) out << "; depth clamp on";
  const std::vector<int> clipDistances = enabledClipDistances(d);
  if (!clipDistances.empty()) {
    out << "; clip distance" << (clipDistances.size() == 1 ? " " : "s ");
    for (std::size_t k = 0; k < clipDistances.size(); ++k) {
      out << (k == 0 ? "" : ", ") << clipDistances[k];
    }
    out << " enabled" << (d.writesClipDistance ? " (the program writes gl_ClipDistance)" : "");
  } else if (d.writesClipDistance) {
    out << "; the program writes gl_ClipDistance, but no GL_CLIP_DISTANCEi is enabled";
  }
  return out.str();
}

nlohmann::json depthStateJson(const TraceDepthState& d) {
  return {{"clip_origin", d.clipUpperLeft ? "upper-left" : "lower-left"},
          {"clip_depth", d.clipZeroToOne ? "zero-to-one" : "negative-one-to-one"},
          {"depth_test", d.depthTest},
          {"depth_func", glEnumName(d.depthFunc)},
          {"depth_range", {d.depthRange.x, d.depthRange.y}},
          {"cleared_depth", d.clearedDepth ? nlohmann::json(*d.clearedDepth) : nullptr},
          {"viewport", {d.viewport.width, d.viewport.height}},
          {"depth_format", d.depthFormatName},
          {"cull_face", d.cullFace ? nlohmann::json(glEnumName(d.cullFaceMode)) : nullptr},
          {"front_face", glEnumName(d.frontFace)},
          {"depth_clamp", d.depthClamp},
          {"clip_distances", enabledClipDistances(d)},
          {"writes_clip_distance", d.writesClipDistance},
          {"calls",
           {{"clip_control", d.clipControlCall},
            {"depth_func", d.depthFuncCall},
            {"depth_range", d.depthRangeCall},
            {"clear", d.clearCall},
            {"cull_face", std::max(d.cullFaceCall, d.cullFaceModeCall)},
            {"front_face", d.frontFaceCall},
            {"depth_clamp", d.depthClampCall},
            {"clip_distances", d.clipDistancesCall}}}};
}

nlohmann::json rangeJson(const std::optional<ValueRange>& range) {
  return range ? nlohmann::json{{"min", range->min}, {"max", range->max}} : nlohmann::json(nullptr);
}

nlohmann::json rangesJson(const GroupRanges& ranges) {
  nlohmann::json eye = nullptr;
  if (ranges.eyeX && ranges.eyeY && ranges.eyeZ) {
    eye = {{"min", {ranges.eyeX->min, ranges.eyeY->min, ranges.eyeZ->min}},
           {"max", {ranges.eyeX->max, ranges.eyeY->max, ranges.eyeZ->max}}};
  }
  return {{"near", rangeJson(ranges.near)},
          {"far", rangeJson(ranges.far)},
          {"fov_y_degrees", rangeJson(ranges.fovYDegrees)},
          {"eye", eye}};
}

nlohmann::json occurrenceJson(const Occurrence& occurrence) {
  return {{"frame", occurrence.frame}, {"call", occurrence.call}};
}

std::string rangeText(const ValueRange& range) {
  return range.min == range.max ? number(range.min)
                                : number(range.min) + " to " + number(range.max);
}

// "near 0.1 to 0.5, far 100, fov 60 deg vertical, eye x -1 to 1, y 2, z 5 to 7": each property
// over a group's matrices, a single value where it did not move.
std::string rangesText(const GroupRanges& ranges) {
  std::vector<std::string> parts;
  if (ranges.near) parts.push_back("near " + rangeText(*ranges.near));
  if (ranges.far) parts.push_back("far " + rangeText(*ranges.far));
  if (ranges.fovYDegrees)
    parts.push_back("fov " + rangeText(*ranges.fovYDegrees) + " deg vertical");
  if (ranges.eyeX && ranges.eyeY && ranges.eyeZ) {
    parts.push_back("eye x " + rangeText(*ranges.eyeX) + ", y " + rangeText(*ranges.eyeY) + ", z " +
                    rangeText(*ranges.eyeZ));
  }
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : ", ") + part;
  return text;
}

std::string framesText(const TraceCheckResult& r) {
  if (r.frames.first == 0 && r.frames.last == UINT64_MAX) {
    return std::to_string(r.framesSeen) + " frames";
  }
  return "frames " + std::to_string(r.frames.first) + "-" +
         (r.frames.last == UINT64_MAX ? std::string("end") : std::to_string(r.frames.last));
}

std::size_t countSeverity(const TraceCheckResult& r, const std::string& severity) {
  std::size_t count = 0;
  for (const TracePairGroup& g : r.groups) {
    count += static_cast<std::size_t>(
        std::count_if(g.report.findings.begin(), g.report.findings.end(),
                      [&](const Finding& f) { return f.severity == severity; }));
  }
  return count + static_cast<std::size_t>(
                     std::count_if(r.findings.begin(), r.findings.end(),
                                   [&](const Finding& f) { return f.severity == severity; }));
}

}  // namespace

nlohmann::json traceCheckJson(const TraceCheckResult& r) {
  nlohmann::json groups = nlohmann::json::array();
  for (const TracePairGroup& g : r.groups) {
    nlohmann::json matrix = nlohmann::json::array();
    for (int column = 0; column < 4; ++column) {
      for (int row = 0; row < 4; ++row) matrix.push_back(g.matrix[column][row]);
    }
    nlohmann::json group = {{"source", g.source},
                            {"distinct_matrices", g.distinctMatrices},
                            {"draws", g.draws},
                            {"first", occurrenceJson(g.first)},
                            {"last", occurrenceJson(g.last)},
                            {"depth_state", depthStateJson(g.depth)},
                            {"matrix_column_major", matrix}};
    group["left_out"] = nullptr;
    if (g.leftOut) {
      group["left_out"] = {{"draws", g.leftOut->draws},
                           {"distinct_matrices", g.leftOut->distinctMatrices},
                           {"distinct_matrices_at_least", g.leftOut->distinctCapped},
                           {"first", occurrenceJson(g.leftOut->first)},
                           {"last", occurrenceJson(g.leftOut->last)}};
    }
    if (!g.verify.is_null()) group["verify"] = g.verify;
    if (!g.unusable.empty()) {
      group["unusable"] = g.unusable;
    } else {
      const nlohmann::json check = checkReportJson(g.report, g.input);
      group["properties"] = check["properties"];
      group["findings"] = check["findings"];
      group["verdict"] = check["verdict"];
      group["ranges"] = rangesJson(g.ranges);
    }
    groups.push_back(std::move(group));
  }
  nlohmann::json findings = nlohmann::json::array();
  for (const Finding& f : r.findings) {
    findings.push_back(
        {{"severity", f.severity}, {"code", f.code}, {"message", f.message}, {"fix", f.fix}});
  }
  return {{"tool", "clipray check --trace"},
          {"trace", r.traceName},
          {"frames",
           {{"first", r.frames.first},
            {"last",
             r.frames.last == UINT64_MAX ? nlohmann::json(nullptr) : nlohmann::json(r.frames.last)},
            {"read", r.framesSeen}}},
          {"draws", r.draws},
          {"draws_with_projection", r.drawsWithProjection},
          {"draws_not_kept", r.drawsNotKept},
          {"distinct_pairs", r.distinctPairs},
          {"groups", groups},
          {"findings", findings},
          {"verdict", r.hasErrors() ? "errors" : "ok"}};
}

std::string traceCheckText(const TraceCheckResult& r) {
  std::ostringstream out;
  out << "trace " << r.traceName << ": " << framesText(r) << ", " << r.draws << " draws ("
      << r.drawsWithProjection << " with a projection), " << r.distinctPairs
      << " distinct (matrix, depth state) pairs in " << r.groups.size() << " groups\n";
  if (r.drawsNotKept > 0) {
    out << "  " << r.drawsNotKept << " draws with further new pairs not analysed (more than "
        << kMaxPairsPerGroup << " matrices of one source and depth state, or " << kMaxDistinctPairs
        << " pairs in all)\n";
  }
  std::size_t index = 0;
  for (const TracePairGroup& g : r.groups) {
    out << "\n[" << ++index << "] " << g.source << ": " << g.distinctMatrices
        << (g.distinctMatrices == 1 ? " matrix, " : " matrices, ") << g.draws
        << " draws, first frame " << g.first.frame << " call " << g.first.call << ", last frame "
        << g.last.frame << " call " << g.last.call << "\n";
    out << "  depth state: " << depthStateText(g.depth) << "\n";
    if (g.leftOut) {
      const LeftOutDraws& left = *g.leftOut;
      out << "  left out: " << left.draws << " further draws of this source and depth state ("
          << (left.distinctCapped ? "at least " : "") << left.distinctMatrices
          << " more distinct matrices, frame " << left.first.frame << " call " << left.first.call
          << " to frame " << left.last.frame << " call " << left.last.call << "), past the "
          << kMaxPairsPerGroup << " matrices a group keeps\n";
    }
    if (!g.unusable.empty()) {
      out << "  not analysed: " << g.unusable << "\n";
      continue;
    }
    // The matrix check's report, indented, without its own totals line.
    std::istringstream lines(checkReportText(g.report, g.input));
    std::string line;
    while (std::getline(lines, line)) {
      if (line.find(" errors, ") != std::string::npos && line.ends_with(" notes")) continue;
      out << "  " << line << "\n";
      // The matrix report reads the group's first matrix: the range over all of them follows
      // its property lines.
      if (line.starts_with("matrix: ") && g.distinctMatrices > 1) {
        // A matrix with no eye point (LiSPSM's) has no near, far, fov or eye to range.
        const std::string ranges = rangesText(g.ranges);
        out << "  over its " << g.distinctMatrices
            << " matrices: " << (ranges.empty() ? "no near, far, fov or eye to range" : ranges)
            << " (the lines below read the first)\n";
      }
    }
    if (!g.verifyObservations.empty()) out << "  verify (" << r.verifiedBy << "):\n";
    for (const std::string& observation : g.verifyObservations) {
      out << "    " << observation << "\n";
    }
  }
  if (!r.findings.empty()) out << "\n";
  for (const Finding& f : r.findings) {
    out << f.severity << " [" << f.code << "] " << f.message << "\n  fix: " << f.fix << "\n";
  }
  out << "\n"
      << countSeverity(r, "error") << " errors, " << countSeverity(r, "warning") << " warnings, "
      << countSeverity(r, "info") << " notes\n";
  return out.str();
}

}  // namespace clipray::trace
