// The report of `clipray check` as JSON (stable field names) and as the text a person reads.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "clipray/check/CheckText.hpp"
#include "clipray/check/ConventionCheck.hpp"

namespace clipray {

namespace {

std::string number(double value) {
  return detail::checkNumber(value);
}

std::string vec(const glm::dvec3& v) {
  return detail::checkVector(v);
}

}  // namespace

nlohmann::json checkReportJson(const CheckReport& report, const CheckInput& input) {
  const MatrixProperties& p = report.properties;
  const auto reading = [](const std::optional<Uncertain>& v) {
    return v ? nlohmann::json(v->value) : nlohmann::json(nullptr);
  };
  const auto error = [](const std::optional<Uncertain>& v) {
    return v ? nlohmann::json(v->error) : nlohmann::json(nullptr);
  };
  nlohmann::json properties = {
      {"precision", p.precision},
      {"projection", p.perspective ? "perspective" : "orthographic"},
      {"oblique", p.oblique},
      {"off_axis", p.offAxis},
      {"handedness", p.leftHanded ? "left-handed" : "right-handed"},
      {"mirrored", p.leftHanded},
      {"view_direction", {p.viewDirection.x, p.viewDirection.y, p.viewDirection.z}},
      {"view_direction_error_degrees", p.viewDirectionErrorDegrees},
      {"near", reading(p.near)},
      {"near_error", error(p.near)},
      {"far", p.infiniteFar ? nlohmann::json(nullptr) : reading(p.far)},
      {"far_error", p.infiniteFar ? nlohmann::json(nullptr) : error(p.far)},
      {"infinite_far", p.infiniteFar},
      {"built_for", p.builtFor},
      {"built_for_reason", p.builtForReason},
      {"near_if_built_for_no", reading(p.nearIfBuiltForNo)},
      {"near_if_built_for_zo", reading(p.nearIfBuiltForZo)},
      {"reversed", p.reversedDecided ? nlohmann::json(p.reversed) : nlohmann::json("undecided")},
      {"y_flipped", p.yFlipped},
      {"likely_transposed", p.likelyTransposed},
  };
  if (p.eyeAtInfinityAlong) {
    properties["eye"] = nullptr;
    properties["eye_at_infinity_along"] = {p.eyeAtInfinityAlong->x, p.eyeAtInfinityAlong->y,
                                           p.eyeAtInfinityAlong->z};
  } else if (p.eye) {
    properties["eye"] = {p.eye->x, p.eye->y, p.eye->z};
    properties["eye_error"] = {p.eyeError.x, p.eyeError.y, p.eyeError.z};
  }
  if (p.perspective && p.eyeAtInfinityAlong) {
    // No eye to measure an angle from (the text says "fov -"): no number, not a zero.
    properties["fov_y_degrees"] = nullptr;
    properties["fov_x_degrees"] = nullptr;
    properties["fov_error_degrees"] = nullptr;
  } else if (p.perspective) {
    properties["fov_y_degrees"] = p.fovYDegrees.value;
    properties["fov_x_degrees"] = p.fovXDegrees.value;
    properties["fov_error_degrees"] = std::max(p.fovYDegrees.error, p.fovXDegrees.error);
  } else {
    properties["extent_x"] = p.extentX.value;
    properties["extent_y"] = p.extentY.value;
    properties["depth_extent"] = p.depthExtent ? nlohmann::json(*p.depthExtent) : nullptr;
    properties["measured_from"] = p.orthographicAnchor;
  }
  nlohmann::json methods = nlohmann::json::array();
  for (const MethodPrediction& m : report.methods) {
    if (!m.unavailable.empty()) {
      methods.push_back({{"method", m.method}, {"unavailable", m.unavailable}});
      continue;
    }
    methods.push_back({{"method", m.method},
                       {"angle_err_px", m.angleErrorPx},
                       {"origin_lateral_err_px", m.originLateralErrorPx},
                       {"nonfinite", m.nonfinite},
                       {"backward", m.backward}});
  }
  nlohmann::json findings = nlohmann::json::array();
  for (const Finding& f : report.findings) {
    findings.push_back(
        {{"severity", f.severity}, {"code", f.code}, {"message", f.message}, {"fix", f.fix}});
  }
  return {{"tool", "clipray check"},
          {"declared",
           {{"depth",
             input.declaredDepth
                 ? nlohmann::json(input.declaredDepth == DepthConvention::ZeroToOne ? "zo" : "no")
                 : nlohmann::json(nullptr)},
            {"reversed", input.declaredReversed},
            {"depth_range", {input.depthRange.x, input.depthRange.y}},
            {"viewport", {input.viewport.width, input.viewport.height}},
            {"depth_bits", depthFormatName(input.depthFormat)},
            {"depth_clamp", input.depthClampEnabledAt.has_value()}}},
          {"properties", properties},
          {"ray_methods_float", methods},
          {"findings", findings},
          {"verdict", report.hasErrors() ? "errors" : "ok"}};
}

std::string checkReportText(const CheckReport& report, const CheckInput& input) {
  (void)input;
  const MatrixProperties& p = report.properties;
  std::ostringstream out;
  const auto count = [&](const char* severity) {
    return std::count_if(report.findings.begin(), report.findings.end(),
                         [&](const Finding& f) { return f.severity == severity; });
  };
  const auto findingLines = [&] {
    if (report.findings.empty()) out << "findings: none\n";
    for (const Finding& f : report.findings) {
      out << f.severity << " [" << f.code << "] " << f.message << "\n  fix: " << f.fix << "\n";
    }
    out << count("error") << " errors, " << count("warning") << " warnings, " << count("info")
        << " notes\n";
  };
  if (p.likelyTransposed) {
    // What the scrambled matrix would read as is no property of the camera: say only that.
    out << "matrix: no projection as given (its transpose is one); the camera is not read\n"
        << "  entries read as " << p.precision << "\n";
    findingLines();
    return out.str();
  }
  out << "matrix: " << (p.perspective ? "perspective" : "orthographic")
      << (p.offAxis ? ", off-axis" : "") << (p.oblique ? ", oblique near plane" : "") << ", "
      << (p.leftHanded ? "left-handed (mirrored)" : "right-handed")
      << (p.reversed ? ", reversed-Z" : "") << (p.yFlipped ? ", y flipped" : "") << "\n";
  if (p.eyeAtInfinityAlong) {
    // No point to print: the rows x = y = w = 0 meet only at infinity.
    out << "  no eye point: the centre of projection is at infinity along "
        << vec(*p.eyeAtInfinityAlong)
        << " (rows x, y and w share no point; a light-space perspective warp such as LiSPSM's), "
           "looking along "
        << vec(p.viewDirection) << "\n";
  } else if (p.eye) {
    out << "  eye " << vec(*p.eye) << ", looking along " << vec(p.viewDirection) << "\n";
  } else {
    out << "  looking along " << vec(p.viewDirection) << "\n";
  }
  const auto withError = [](const Uncertain& u) { return detail::checkReading(u); };
  out << "  " << (p.perspective ? "near " : "near plane at ")
      << (p.near ? withError(*p.near) : std::string("-")) << ", far "
      << (p.infiniteFar ? std::string("infinite")
          : p.far       ? withError(*p.far)
                        : std::string("-"));
  if (p.eyeAtInfinityAlong) {
    out << ", fov - (no eye to measure it from)\n";
  } else if (p.perspective) {
    out << ", fov " << withError(p.fovYDegrees) << " deg vertical x " << withError(p.fovXDegrees)
        << " deg horizontal\n";
  } else {
    out << (p.orthographicAnchor == "view" ? " from the camera" : " from the world origin")
        << ", view volume " << number(p.extentX.value) << " x " << number(p.extentY.value) << " x "
        << (p.depthExtent ? number(*p.depthExtent) : std::string("-")) << "\n";
  }
  out << "  built for: " << p.builtFor;
  if (p.nearIfBuiltForNo && p.nearIfBuiltForZo && p.builtFor != "zo-reversed") {
    out << " (near " << shownReading(*p.nearIfBuiltForNo) << " if NO, "
        << shownReading(*p.nearIfBuiltForZo) << " if ZO)";
  }
  out << "\n";
  if (!p.builtForReason.empty() && p.builtFor != "zo-reversed") {
    out << "    because " << p.builtForReason << "\n";
  }
  out << "  entries read as " << p.precision << "\n";
  const bool anyMeasured =
      std::any_of(report.methods.begin(), report.methods.end(),
                  [](const MethodPrediction& m) { return m.unavailable.empty(); });
  if (!report.methods.empty() && !anyMeasured) {
    out << "float picking rays at this camera: not measured (" << report.methods.back().unavailable
        << ")\n";
  }
  if (anyMeasured) {
    out << "float picking rays at this camera, max error in pixels (direction / origin):\n";
    for (const MethodPrediction& m : report.methods) {
      if (!m.unavailable.empty()) continue;
      out << "  " << m.method << " "
          << (m.nonfinite ? std::string("non-finite")
                          : number(m.angleErrorPx) + " / " + number(m.originLateralErrorPx))
          << (m.backward ? " (backward)" : "") << "\n";
    }
  }
  findingLines();
  return out.str();
}

}  // namespace clipray
