// The cameras of a scene file: a raw clipFromWorld, or a projection with a view ("view": look-at,
// or "viewFromWorld"), each checked to stay finite under every convention it may be drawn under.

#include <algorithm>
#include <cmath>
#include <string_view>
#include <tuple>
#include <utility>

#include "clipray/math/Projections.hpp"
#include "clipray/scene/ExpectedFindings.hpp"
#include "clipray/scene/SceneReader.hpp"

namespace clipray::detail {

Camera SceneReader::camera(const json& value, const Pointer& at,
                           std::map<std::string, Pointer>& names) const {
  expectObject(value, at);
  expectKnownKeys(value, at,
                  {"name", "viewport", "clipFromWorld", "view", "viewFromWorld", "projection",
                   "builtFor", "clipPlanes", "expectedFindings", "logarithmicDepth"});
  Camera camera;
  camera.name = name(value, at, "camera", names);
  camera.viewport = viewport(required(value, at, "viewport"), at / "viewport");
  if (const json* planes = optional(value, "clipPlanes")) {
    camera.clipPlanes = clipPlanes(*planes, at / "clipPlanes");
  }
  if (const json* expected = optional(value, "expectedFindings")) {
    camera.expectedFindings = expectedFindings(*expected, at / "expectedFindings");
  }
  if (const json* logDepth = optional(value, "logarithmicDepth")) {
    camera.logarithmicDepth = logarithmicDepth(*logDepth, at / "logarithmicDepth");
  }

  const json* raw = optional(value, "clipFromWorld");
  const json* view = optional(value, "view");
  const json* viewFromWorld = optional(value, "viewFromWorld");
  const json* projectionValue = optional(value, "projection");
  const json* builtFor = optional(value, "builtFor");

  if (raw) {
    for (std::string_view other : {"view", "viewFromWorld", "projection", "builtFor"}) {
      if (optional(value, other)) {
        fail(at, "expected either \"clipFromWorld\" or " + jsonString(other) + ", got both");
      }
    }
    camera.rawClipFromWorld = clipMatrix(*raw, at / "clipFromWorld");
    camera.projection = std::monostate{};
    return camera;
  }

  if (!view && !viewFromWorld && !projectionValue) {
    fail(at,
         "missing required field \"clipFromWorld\", or \"projection\" with \"view\" or "
         "\"viewFromWorld\"");
  }
  if (view && viewFromWorld) fail(at, "expected either \"view\" or \"viewFromWorld\", got both");
  if (!view && !viewFromWorld) fail(at, "missing required field \"view\" or \"viewFromWorld\"");
  camera.viewFromWorld =
      view ? lookAt(*view, at / "view") : affineMatrix(*viewFromWorld, at / "viewFromWorld");
  if (!projectionValue) fail(at, "missing required field \"projection\"");
  camera.projection = projection(*projectionValue, at / "projection");
  if (builtFor) camera.builtFor = depthMode(*builtFor, at / "builtFor");

  // Extreme but individually valid numbers can still overflow the product.
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    if (!allFinite(camera.clipFromWorld(mode, camera.viewport))) {
      fail(at, "the camera's clipFromWorld overflows double when drawn under " +
                   jsonString(mode.name()));
    }
  }
  return camera;
}

glm::dmat4 SceneReader::lookAt(const json& value, const Pointer& at) const {
  expectObject(value, at);
  expectKnownKeys(value, at, {"eye", "target", "up"});
  const glm::dvec3 eye = vector3(required(value, at, "eye"), at / "eye");
  const glm::dvec3 target = vector3(required(value, at, "target"), at / "target");
  const glm::dvec3 up = vector3(required(value, at, "up"), at / "up");
  if (target == eye) {
    fail(at / "target", "expected a point different from \"eye\" (" + describe(value["eye"]) +
                            "), got " + describe(value["target"]));
  }
  if (up == glm::dvec3(0.0))
    fail(at / "up", "expected a non-zero direction, got " + describe(value["up"]));
  const glm::dvec3 forward = target - eye;
  if (std::isfinite(forward.x) && std::isfinite(forward.y) && std::isfinite(forward.z) &&
      glm::length(glm::cross(safeNormalize(forward), safeNormalize(up))) < kParallelThreshold) {
    fail(at / "up", "expected a direction not parallel to the view direction (target - eye), got " +
                        describe(value["up"]));
  }
  return viewFromWorldLookAt(eye, target, up);
}

std::variant<PerspectiveProjection, OrthographicProjection, std::monostate> SceneReader::projection(
    const json& value, const Pointer& at) const {
  expectObject(value, at);
  const json& type = required(value, at, "type");
  const auto bigger = [&](const json& object, std::string_view lowKey, std::string_view highKey,
                          double low) {
    const json& high = required(object, at, highKey);
    const double x = number(high, at / std::string(highKey));
    if (!(x > low)) {
      fail(at / std::string(highKey), "expected a number greater than " + jsonString(lowKey) +
                                          " (" + describe(object[std::string(lowKey)]) + "), got " +
                                          describe(high));
    }
    return x;
  };
  const auto different = [&](const json& object, std::string_view firstKey,
                             std::string_view secondKey) {
    const double first = number(required(object, at, firstKey), at / std::string(firstKey));
    const json& second = required(object, at, secondKey);
    if (number(second, at / std::string(secondKey)) == first) {
      fail(at / std::string(secondKey), "expected a number different from " + jsonString(firstKey) +
                                            " (" + describe(object[std::string(firstKey)]) +
                                            "), got " + describe(second));
    }
    return std::pair{first, second.get<double>()};
  };

  if (type == "perspective") {
    expectKnownKeys(value, at, {"type", "fovYDegrees", "aspect", "near", "far"});
    PerspectiveProjection p;
    const json& fov = required(value, at, "fovYDegrees");
    p.fovYDegrees = number(fov, at / "fovYDegrees");
    if (!(p.fovYDegrees > 0.0 && p.fovYDegrees < 180.0)) {
      fail(at / "fovYDegrees", "expected a number in (0, 180), got " + describe(fov));
    }
    if (const json* aspect = optional(value, "aspect")) {
      p.aspect = positiveNumber(*aspect, at / "aspect");
    }
    p.nearDistance = positiveNumber(required(value, at, "near"), at / "near");
    if (value.contains("far")) p.farDistance = bigger(value, "near", "far", p.nearDistance);
    return p;
  }
  if (type == "orthographic") {
    expectKnownKeys(value, at, {"type", "left", "right", "bottom", "top", "near", "far"});
    OrthographicProjection o;
    std::tie(o.left, o.right) = different(value, "left", "right");
    std::tie(o.bottom, o.top) = different(value, "bottom", "top");
    o.nearDistance = number(required(value, at, "near"), at / "near");
    o.farDistance = bigger(value, "near", "far", o.nearDistance);
    return o;
  }
  fail(at / "type", "expected one of " + quotedList({"perspective", "orthographic"}) + ", got " +
                        describe(type));
}

LogarithmicDepth SceneReader::logarithmicDepth(const json& value, const Pointer& at) const {
  if (!value.is_object()) {
    fail(at, "expected {\"form\", \"far\", \"constant\"} of a logarithmic depth, got " +
                 describe(value));
  }
  expectKnownKeys(value, at, {"form", "far", "constant"});
  LogarithmicDepth logDepth;
  const json& form = required(value, at, "form");
  const std::string formName = form.is_string() ? form.get<std::string>() : std::string();
  if (formName == "threejs") {
    logDepth.form = LogDepthForm::ThreeJs;
  } else if (formName == "outerra") {
    logDepth.form = LogDepthForm::Outerra;
  } else {
    fail(at / "form",
         "expected one of " + quotedList({"threejs", "outerra"}) + ", got " + describe(form));
  }
  logDepth.far = positiveNumber(required(value, at, "far"), at / "far");
  if (logDepth.form == LogDepthForm::Outerra) {
    logDepth.constant = positiveNumber(required(value, at, "constant"), at / "constant");
  } else if (optional(value, "constant")) {
    fail(at / "constant",
         "three.js's logarithmic depth has no constant (log2(1 + w)); use \"form\": \"outerra\" "
         "for log2(1 + C w) / log2(1 + C far)");
  }
  if (!std::isfinite(std::log2(1.0 + logDepth.constant * logDepth.far)) ||
      !(std::log2(1.0 + logDepth.constant * logDepth.far) > 0.0)) {
    fail(at, "log2(1 + constant * far) is not a positive finite number for constant " +
                 describe(value.value("constant", json(1.0))) + " and far " +
                 describe(value["far"]));
  }
  return logDepth;
}

std::vector<glm::dvec4> SceneReader::clipPlanes(const json& value, const Pointer& at) const {
  if (!value.is_array() || value.size() > Camera::kMaxClipPlanes) {
    fail(at, "expected an array of at most " + std::to_string(Camera::kMaxClipPlanes) +
                 " planes [a, b, c, d] (gl_ClipDistance; GL_MAX_CLIP_DISTANCES is at least 8), "
                 "got " +
                 describe(value));
  }
  std::vector<glm::dvec4> planes;
  for (std::size_t i = 0; i < value.size(); ++i) {
    const json& plane = value[i];
    if (!plane.is_array() || plane.size() != 4) {
      fail(at / i, "expected a plane [a, b, c, d] (kept where a x + b y + c z + d >= 0), got " +
                       describe(plane));
    }
    glm::dvec4 p;
    for (std::size_t k = 0; k < 4; ++k) p[static_cast<int>(k)] = number(plane[k], at / i / k);
    if (p.x == 0.0 && p.y == 0.0 && p.z == 0.0) {
      fail(at / i, "expected a plane with a non-zero normal [a, b, c], got " + describe(plane));
    }
    planes.push_back(p);
  }
  return planes;
}

std::vector<std::string> SceneReader::expectedFindings(const json& value, const Pointer& at) const {
  if (!value.is_array()) {
    fail(at,
         "expected an array of clipray check finding codes (e.g. [\"depth-convention-mismatch\"]), "
         "got " +
             describe(value));
  }
  std::vector<std::string> codes;
  for (std::size_t i = 0; i < value.size(); ++i) {
    const std::string code = string(value[i], at / i);
    if (std::find(kDeclarableFindingCodes.begin(), kDeclarableFindingCodes.end(), code) ==
        kDeclarableFindingCodes.end()) {
      fail(at / i,
           "expected the code of a clipray check error or warning (" +
               quotedList({kDeclarableFindingCodes.begin(), kDeclarableFindingCodes.end()}) +
               "), got " + describe(value[i]));
    }
    if (std::find(codes.begin(), codes.end(), code) != codes.end()) {
      fail(at / i, "expected each code once, got " + describe(value[i]) + " again");
    }
    codes.push_back(code);
  }
  return codes;
}

}  // namespace clipray::detail
