#include "clipray/check/ConventionCheck.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "clipray/math/Projections.hpp"
#include "clipray/rays/QuadReference.hpp"
#include "clipray/rays/RayErrors.hpp"
#include "clipray/rays/RayMethods.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/scene/InputError.hpp"

namespace clipray {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value + 0.0);  // + 0.0: no "-0"
  return buffer;
}

std::string vec(const glm::dvec3& v) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.6g, %.6g, %.6g)", v.x + 0.0, v.y + 0.0, v.z + 0.0);
  return buffer;
}

// Significant decimal digits needed to write v to within the precision it was recovered with: the
// build whose near plane is the "rounder" number is the one the app wrote.
int decimalDigits(double v, double relativeTolerance) {
  for (int digits = 1; digits <= 17; ++digits) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.*e", digits - 1, v);
    if (std::abs(std::strtod(buffer, nullptr) - v) <= relativeTolerance * std::abs(v))
      return digits;
  }
  return 18;
}

// Relative precision the matrix entries carry: float values (2^-24), decimals printed with d
// significant digits (half a unit in the d-th digit), or full doubles (2^-53).
double entryPrecision(const glm::dmat4& m) {
  bool allFloat = true;
  int mostDigits = 0;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      const double v = m[c][r];
      allFloat = allFloat && static_cast<double>(static_cast<float>(v)) == v;
      if (v != 0.0) mostDigits = std::max(mostDigits, decimalDigits(v, 0.0));
    }
  }
  if (allFloat) return std::ldexp(1.0, -24);
  if (mostDigits >= 16) return std::ldexp(1.0, -53);
  return 0.5 * std::pow(10.0, 1 - mostDigits);
}

void requireFinite(const glm::dmat4& m, const std::string& what) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) {
        throw InputError(what + ": element (row " + std::to_string(r) + ", column " +
                         std::to_string(c) + ") is " + number(m[c][r]) +
                         "; expected finite numbers");
      }
    }
  }
}

void requireProjection(const glm::dmat4& m, const std::string& what) {
  requireFinite(m, what);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (std::abs(m[c][r]) > static_cast<double>(std::numeric_limits<float>::max())) {
        throw InputError(what + ": element (row " + std::to_string(r) + ", column " +
                         std::to_string(c) + ") is " + number(m[c][r]) +
                         ", beyond float range: a GL uniform cannot hold it");
      }
    }
  }
  bool allZero = true;
  for (int c = 0; c < 4; ++c) allZero = allZero && m[c] == glm::dvec4(0.0);
  if (allZero) throw InputError(what + ": the matrix is all zero");
  const glm::dvec4 w = matrixRow(m, 3);
  if (w == glm::dvec4(0.0)) {
    throw InputError(what +
                     ": row 3 (w) is all zero: not a projection (every point would have w = 0)");
  }
  if (glm::dvec3(w) == glm::dvec3(0.0) && w.w <= 0.0) {
    throw InputError(what + ": row 3 (w) is (0, 0, 0, " + number(w.w) +
                     "): w <= 0 everywhere, so GL clips every point");
  }
  if (scaledDeterminant(m) < 1e-12) {
    throw InputError(what + ": the matrix is singular (scaled determinant " +
                     number(scaledDeterminant(m)) + "); a projection must be invertible");
  }
}

// How much a matrix looks like clipFromView * viewFromWorld: (a) rows 2 and 3 share their xyz
// direction (near plane perpendicular to the view), (b, c) screen x and y are perpendicular to the
// view direction (on-axis), (d) screen x is perpendicular to screen y, (e) w > 0 somewhere.
// An oblique matrix loses (a), an off-axis one (b) and/or (c); a transposed matrix with a camera
// translation keeps at most three points while its transpose scores all five.
int projectionStructureScore(const glm::dmat4& m) {
  const glm::dvec3 x(matrixRow(m, 0)), y(matrixRow(m, 1)), z(matrixRow(m, 2));
  const glm::dvec4 w = matrixRow(m, 3);
  const glm::dvec3 w3(w);
  auto parallel = [](const glm::dvec3& a, const glm::dvec3& b) {
    return glm::length(glm::cross(a, b)) <= 1e-6 * glm::length(a) * glm::length(b);
  };
  auto perpendicular = [](const glm::dvec3& a, const glm::dvec3& b) {
    return std::abs(glm::dot(a, b)) <= 1e-6 * glm::length(a) * glm::length(b);
  };
  const bool orthographic = glm::length(w3) <= 1e-12 * (glm::length(x) + glm::length(y));
  int score = 0;
  score += orthographic ? 1 : parallel(z, w3);
  score += orthographic ? 1 : perpendicular(x, w3);
  score += orthographic ? 1 : perpendicular(y, w3);
  score += perpendicular(x, y);
  score += orthographic ? w.w > 0.0 : 1;
  return score;
}

double angleDegrees(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * 180.0 / kPi;
}

glm::dvec3 unproject(const glm::dmat4& worldFromClip, const glm::dvec3& ndc) {
  const glm::dvec4 p = worldFromClip * glm::dvec4(ndc, 1.0);
  return glm::dvec3(p) / p.w;
}

std::string conventionName(DepthConvention c) {
  return c == DepthConvention::ZeroToOne ? "ZERO_TO_ONE" : "NEGATIVE_ONE_TO_ONE";
}

// Every ray method in float at this camera against the exact rays of the float matrix, over five
// rows of the viewport at full width (enough to find the worst corner and the centre).
std::vector<MethodPrediction> predictMethodErrors(const CheckInput& input, DepthMode mode) {
  CameraInputs inputs;
  inputs.clipFromWorld = input.clipFromWorld;
  inputs.mode = mode;
  if (input.projection && input.view) {
    inputs.clipFromView = *input.projection;
    inputs.viewFromWorld = *input.view;
  }
  const Viewport viewport = input.viewport;
  std::vector<MethodPrediction> predictions;
  if (!describeProjection(input.clipFromWorld, mode).facts) return predictions;
  const QuadReference reference(glm::dmat4(glm::mat4(input.clipFromWorld)), mode, viewport);
  const QuadReference doubleReference(input.clipFromWorld, mode, viewport);
  std::vector<int> rows = {0, viewport.height / 4, viewport.height / 2, 3 * viewport.height / 4,
                           viewport.height - 1};
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  std::vector<std::vector<ReferenceRay>> referenceRows(rows.size()), doubleRows(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    reference.row(rows[k], referenceRows[k]);
    doubleReference.row(rows[k], doubleRows[k]);
  }
  RayBuffer<float> buffer(static_cast<std::size_t>(viewport.width));
  RayBuffer<double> doubleBuffer(static_cast<std::size_t>(viewport.width));
  for (const RayMethod method : kRayMethods) {
    MethodPrediction prediction;
    prediction.method = rayMethodName(method);
    prediction.unavailable = missingInputs(method, inputs);
    const auto generator = prediction.unavailable.empty()
                               ? makeRayGenerator<float>(method, inputs, viewport)
                               : nullptr;
    if (generator) {
      ErrorAccumulator errors(methodProvidesTMax(method));
      for (std::size_t k = 0; k < rows.size(); ++k) {
        generator->generateRow(rows[k], buffer.span(0, viewport.width));
        errors.addRow(referenceRows[k], buffer.span(0, viewport.width));
      }
      const auto doubleGenerator = makeRayGenerator<double>(method, inputs, viewport);
      ErrorAccumulator doubleErrors(false);
      for (std::size_t k = 0; k < rows.size() && doubleGenerator; ++k) {
        doubleGenerator->generateRow(rows[k], doubleBuffer.span(0, viewport.width));
        doubleErrors.addRow(doubleRows[k], doubleBuffer.span(0, viewport.width));
      }
      prediction.angleErrorPxDouble = doubleErrors.result().anglePx.max;
      const MethodErrors result = errors.result();
      prediction.angleErrorPx = result.anglePx.max;
      prediction.originLateralErrorPx = result.originLateralPx.max;
      prediction.nonfinite = result.nonfinite;
      prediction.backward = result.backward;
    } else if (prediction.unavailable.empty()) {
      prediction.unavailable = "cannot run on this matrix";
    }
    predictions.push_back(prediction);
  }
  return predictions;
}

}  // namespace

bool CheckReport::hasErrors() const {
  return std::any_of(findings.begin(), findings.end(),
                     [](const Finding& f) { return f.severity == "error"; });
}

glm::dmat4 parseMatrix16(const std::vector<double>& numbers, bool rowMajor,
                         const std::string& what) {
  if (numbers.size() != 16) {
    throw InputError(what + ": expected 16 numbers, got " + std::to_string(numbers.size()));
  }
  glm::dmat4 m(0.0);
  for (int i = 0; i < 16; ++i) {
    if (!std::isfinite(numbers[i])) {
      throw InputError(what + ": number " + std::to_string(i + 1) + " is " + number(numbers[i]) +
                       "; expected finite numbers");
    }
    // Column-major: element i is (row i % 4, column i / 4); row-major: (row i / 4, column i % 4).
    if (rowMajor) {
      m[i % 4][i / 4] = numbers[i];
    } else {
      m[i / 4][i % 4] = numbers[i];
    }
  }
  return m;
}

CheckReport checkConventions(const CheckInput& input) {
  if (input.projection) requireProjection(*input.projection, "--projection");
  if (input.view) {
    requireFinite(*input.view, "--view");
    if (matrixRow(*input.view, 3) != glm::dvec4(0, 0, 0, 1)) {
      throw InputError("--view: row 3 is " + vec(glm::dvec3(matrixRow(*input.view, 3))) + ", " +
                       number(input.view->operator[](3)[3]) +
                       "; a view matrix is affine: row 3 must be (0, 0, 0, 1)");
    }
  }
  const glm::dmat4& m = input.clipFromWorld;
  requireProjection(m, input.projection ? "--projection * --view" : "--clip-from-world");
  if (input.depthRange.x == input.depthRange.y) {
    throw InputError("--depth-range: near and far are both " + number(input.depthRange.x) +
                     "; every depth would be equal");
  }

  CheckReport report;
  MatrixProperties& p = report.properties;
  std::vector<Finding>& findings = report.findings;
  const DepthConvention declared = input.declaredDepth.value_or(DepthConvention::NegativeOneToOne);
  const glm::dmat4 worldFromClip = glm::inverse(m);
  requireFinite(worldFromClip,
                std::string(input.projection ? "--projection * --view" : "--clip-from-world") +
                    " (its inverse)");
  const glm::dvec4 rowZ = matrixRow(m, 2), rowW = matrixRow(m, 3);

  p.likelyTransposed =
      projectionStructureScore(glm::transpose(m)) == 5 && projectionStructureScore(m) <= 3;
  p.perspective =
      glm::length(glm::dvec3(rowW)) >
      1e-12 * (glm::length(glm::dvec3(matrixRow(m, 0))) + glm::length(glm::dvec3(matrixRow(m, 1))));

  if (p.perspective) {
    // Eye: the null vector of rows 0, 1, 3 (x = y = w = 0): worldFromClip * (0, 0, 1, 0).
    const glm::dvec4 eyeH = worldFromClip * glm::dvec4(0, 0, 1, 0);
    p.eye = glm::dvec3(eyeH) / eyeH.w;
    // w grows into the view: the view direction is row 3's xyz.
    p.viewDirection = glm::normalize(glm::dvec3(rowW));
    // Along the view direction at distance s from the eye: z_ndc(s) = B + A / s.
    const double wLength = glm::length(glm::dvec3(rowW));
    const double a = glm::dot(rowZ, glm::dvec4(*p.eye, 1.0)) / wLength;
    const double b = glm::dot(glm::dvec3(rowZ), p.viewDirection) / wLength;
    p.reversed = a > 0.0;
    auto distanceAt = [&](double zNdc) -> std::optional<double> {
      const double s = a / (zNdc - b);
      return (std::isfinite(s) && s > 0.0) ? std::optional<double>(s) : std::nullopt;
    };
    if (p.reversed) {
      p.builtFor = "zo-reversed";
      p.nearDistance = distanceAt(1.0);
      p.infiniteFar = std::abs(b) <= 1e-9;
      if (!p.infiniteFar) p.farDistance = distanceAt(0.0);
    } else {
      p.nearIfBuiltForNo = distanceAt(-1.0);
      p.nearIfBuiltForZo = distanceAt(0.0);
      p.infiniteFar = std::abs(1.0 - b) <= 1e-9;
      if (!p.infiniteFar) p.farDistance = distanceAt(1.0);
      if (p.nearIfBuiltForNo && !p.nearIfBuiltForZo) {
        p.builtFor = "no";
      } else if (!p.nearIfBuiltForNo && p.nearIfBuiltForZo) {
        p.builtFor = "zo";
      } else {
        // Near is recovered through r2 . (eye, 1), which cancels when the eye is far from the
        // origin: float entries carry u = 2^-24 relative error, amplified by sum |r2_i e_i| / |r2 .
        // e|.
        const glm::dvec4 e(*p.eye, 1.0);
        const double cancellation = (std::abs(rowZ.x * e.x) + std::abs(rowZ.y * e.y) +
                                     std::abs(rowZ.z * e.z) + std::abs(rowZ.w)) /
                                    std::abs(glm::dot(rowZ, e));
        const double tolerance = 4.0 * entryPrecision(m) * cancellation;
        const int digitsNo = decimalDigits(*p.nearIfBuiltForNo, tolerance);
        const int digitsZo = decimalDigits(*p.nearIfBuiltForZo, tolerance);
        p.builtFor = digitsNo < digitsZo ? "no" : digitsZo < digitsNo ? "zo" : "ambiguous";
      }
      const DepthMode drawn{declared, false};
      p.nearDistance = distanceAt(drawn.nearNdcZ());
    }
  }

  // Ray geometry under the conventions the app draws with (reversed as the matrix says, or as
  // declared for orthographic matrices, whose reversal the matrix cannot show).
  const DepthMode mode = p.perspective
                             ? (p.reversed ? kZeroToOneReversed : DepthMode{declared, false})
                             : DepthMode{declared, input.declaredReversed};
  const RobustRayGenerator rays(m, mode);
  const Ray centre = rays.generate({0.0, 0.0});
  if (!p.perspective) {
    p.reversed = input.declaredReversed;
    p.viewDirection = centre.direction;
    const glm::dvec3 nearCentre = unproject(worldFromClip, {0, 0, mode.nearNdcZ()});
    const glm::dvec3 farCentre = unproject(worldFromClip, {0, 0, mode.farNdcZ()});
    p.depthExtent = glm::length(farCentre - nearCentre);
    p.extentX = glm::length(unproject(worldFromClip, {1, 0, mode.nearNdcZ()}) -
                            unproject(worldFromClip, {-1, 0, mode.nearNdcZ()}));
    p.extentY = glm::length(unproject(worldFromClip, {0, 1, mode.nearNdcZ()}) -
                            unproject(worldFromClip, {0, -1, mode.nearNdcZ()}));
    p.builtFor = "ambiguous";
    if (input.view) {
      const glm::dvec3 origin = glm::dvec3(glm::inverse(*input.view)[3]);
      p.nearDistance = glm::dot(nearCentre - origin, p.viewDirection);
      p.farDistance = glm::dot(farCentre - origin, p.viewDirection);
      if (!p.reversed) {
        const double no = glm::dot(unproject(worldFromClip, {0, 0, -1}) - origin, p.viewDirection);
        const double zo = glm::dot(unproject(worldFromClip, {0, 0, 0}) - origin, p.viewDirection);
        p.nearIfBuiltForNo = no;
        p.nearIfBuiltForZo = zo;
        const int digitsNo = decimalDigits(no, 1e-6), digitsZo = decimalDigits(zo, 1e-6);
        p.builtFor = digitsNo < digitsZo ? "no" : digitsZo < digitsNo ? "zo" : "ambiguous";
      } else {
        p.builtFor = "zo-reversed";
      }
    }
  } else {
    const auto dir = [&](double x, double y) { return rays.generate({x, y}).direction; };
    p.fovYDegrees = angleDegrees(dir(0, -1), dir(0, 1));
    p.fovXDegrees = angleDegrees(dir(-1, 0), dir(1, 0));
    p.offAxis = angleDegrees(centre.direction, p.viewDirection) > 1e-7;
  }
  // Handedness of the camera frame (screen right, screen up, forward): GL's right-handed camera
  // has right x up pointing back at the viewer.
  const glm::dvec3 right =
      p.perspective ? rays.generate({0.5, 0}).direction - rays.generate({-0.5, 0}).direction
                    : rays.generate({0.5, 0}).origin - rays.generate({-0.5, 0}).origin;
  const glm::dvec3 up = p.perspective
                            ? rays.generate({0, 0.5}).direction - rays.generate({0, -0.5}).direction
                            : rays.generate({0, 0.5}).origin - rays.generate({0, -0.5}).origin;
  p.leftHanded = glm::dot(glm::cross(right, up), p.viewDirection) > 0.0;
  const glm::dvec3 nearNormal = glm::dvec3(rowZ - mode.nearNdcZ() * rowW);
  p.oblique = angleDegrees(glm::normalize(nearNormal), p.viewDirection) > 1e-7 &&
              angleDegrees(-glm::normalize(nearNormal), p.viewDirection) > 1e-7;
  p.yFlipped = input.projection ? (*input.projection)[1][1] < 0.0 : glm::normalize(up).y < -1e-9;

  // ---- Findings ----
  const std::string declaredName =
      input.declaredDepth ? (declared == DepthConvention::ZeroToOne ? "zo" : "no") : "";
  if (p.likelyTransposed) {
    findings.push_back(
        {"error", "likely-transposed",
         "the matrix does not have a projection's structure but its transpose does: it was "
         "probably "
         "listed row-major (D3D, a C array m[row][col]) and uploaded as column-major",
         "upload with glUniformMatrix4fv(..., GL_TRUE, ...) or transpose it; clipray check "
         "--layout row-major reads such a listing"});
    // Everything else would describe the scrambled matrix: say only what matters.
    return report;
  }
  if (input.declaredDepth && (p.builtFor == "no" || p.builtFor == "zo") &&
      p.builtFor != declaredName) {
    if (p.builtFor == "no") {
      findings.push_back(
          {"error", "depth-convention-mismatch",
           "built for NEGATIVE_ONE_TO_ONE (near " + number(*p.nearIfBuiltForNo) +
               ") but drawn under ZERO_TO_ONE: "
               "the rasterizer clips at z_ndc = 0, so the effective near plane moves to " +
               number(*p.nearIfBuiltForZo) + " (" +
               number(*p.nearIfBuiltForZo / *p.nearIfBuiltForNo) +
               "x) and NDC [-1, 0), half the depth range, is never used",
           "build the projection for ZO (glm::perspectiveRH_ZO) or draw with "
           "glClipControl(GL_LOWER_LEFT, "
           "GL_NEGATIVE_ONE_TO_ONE)"});
    } else {
      findings.push_back({"error", "depth-convention-mismatch",
                          "built for ZERO_TO_ONE (near " + number(*p.nearIfBuiltForZo) +
                              ") but drawn under NEGATIVE_ONE_TO_ONE: "
                              "the rasterizer keeps geometry down to z_ndc = -1, at " +
                              number(*p.nearIfBuiltForNo) +
                              ", nearer than the intended near plane, and spends half the depth "
                              "range on that sliver",
                          "build the projection for NO (glm::perspectiveRH_NO) or draw with "
                          "glClipControl(GL_LOWER_LEFT, "
                          "GL_ZERO_TO_ONE)"});
    }
  } else if (input.declaredDepth && p.builtFor == "ambiguous" && p.nearIfBuiltForNo &&
             p.nearIfBuiltForZo) {
    findings.push_back(
        {"info", "depth-convention-ambiguous",
         "this matrix reads as built for NO with near " + number(*p.nearIfBuiltForNo) +
             " or for ZO with near " + number(*p.nearIfBuiltForZo) + "; under the declared " +
             conventionName(declared) + " the near plane is at " +
             number(declared == DepthConvention::ZeroToOne ? *p.nearIfBuiltForZo
                                                           : *p.nearIfBuiltForNo),
         "if that is not your near plane, the projection was built for the other convention"});
  }
  const bool reversedRange = input.depthRange.x > input.depthRange.y;
  if ((p.reversed || input.declaredReversed || reversedRange) &&
      declared == DepthConvention::NegativeOneToOne) {
    findings.push_back(
        {"warning", "reversed-z-without-zero-to-one",
         "reversed-Z under NEGATIVE_ONE_TO_ONE gains nothing: window depth (z_ndc + 1) / 2 adds "
         "0.5 "
         "to the small far-away values, where float depth would have kept their precision",
         "glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) with a 32F depth buffer, depth test "
         "GL_GREATER, clear depth 0"});
  }
  // glDepthRange(1, 0) reverses once more: what matters is whether near ends up at the larger
  // window depth, and whether the depth test says so.
  const bool nearIsDeeper = p.reversed != reversedRange;
  if (p.perspective && nearIsDeeper != input.declaredReversed) {
    findings.push_back(
        {"error", "reversed-z-mismatch",
         p.reversed ? "the matrix is reversed-Z (near maps to 1, far to 0) but the app declares a "
                      "classic depth test: "
                      "with GL_LESS and clear 1 the farthest surface wins"
                    : "the app declares reversed-Z (GL_GREATER, clear 0) but the matrix maps near "
                      "to the smaller "
                      "depth: the farthest surface wins",
         p.reversed
             ? "draw with glDepthFunc(GL_GREATER) and glClearDepth(0), or pass --reversed if you do"
             : "build the projection reversed (near -> 1, far -> 0) or use GL_LESS and clear 1"});
  }
  if (input.origin && p.yFlipped) {
    if (*input.origin == WindowOrigin::LowerLeft) {
      findings.push_back(
          {"warning", "y-flipped",
           "the projection flips y (Vulkan-style, screen up along world -Y): under GL's lower-left "
           "origin the image is upside down and triangle winding flips",
           "drop the flip for GL, or keep it and use glClipControl(GL_UPPER_LEFT, ...)"});
    } else {
      findings.push_back(
          {"info", "y-flipped",
           "the projection flips y for an upper-left origin; picking must use the window row as is",
           "no change needed if the app draws with glClipControl(GL_UPPER_LEFT, ...)"});
    }
  } else if (input.origin && *input.origin == WindowOrigin::UpperLeft) {
    findings.push_back(
        {"info", "window-origin-upper-left",
         "window y counts from the top but GL's framebuffer from the bottom: flip once, at the "
         "boundary, y_gl = H - 1 - y_window, after scaling window to framebuffer coordinates",
         "pick with pixel centre (x + 0.5, H - 1 - y + 0.5) in framebuffer pixels"});
  }
  if (p.leftHanded) {
    findings.push_back(
        {"info", "mirrored",
         "the camera frame (screen right, screen up, forward) is left-handed: in a right-handed "
         "world the image is mirrored and front faces wind clockwise",
         "intended for a left-handed (D3D-style) world, or a mirror; otherwise negate one axis"});
  }
  if (p.oblique) {
    findings.push_back(
        {"info", "oblique-near-plane",
         "the near plane is not perpendicular to the view direction (an oblique clip plane, as for "
         "mirrors and portals): rays must start on it, not at a fixed distance from the eye",
         "use plane-based ray origins (clipray's robust method unprojects the near plane)"});
  }
  if (p.infiniteFar) {
    findings.push_back(
        {"warning", "infinite-far-plane",
         "the far plane is at infinity: unProject/two-point rays unproject a far point at infinity "
         "(non-finite) and seed 002 listing 4 fixes the direction's sign with the far plane, whose "
         "normal is zero here",
         "build picking rays from the plane cross product with the sign fixed by the near plane "
         "(clipray's robust method); t_max = +inf"});
  }
  // Float precision: what each ray method errs by at this camera, from the ray library.
  report.methods = predictMethodErrors(input, mode);
  {
    double worstClassic = 0.0;
    std::string table;
    for (const MethodPrediction& prediction : report.methods) {
      if (!prediction.unavailable.empty()) continue;
      // Float precision risk: the classic methods err in float where they would not in double
      // (non-finite rays and structural failures belong to other findings).
      if ((prediction.method == "two_point" || prediction.method == "unproject_glm") &&
          prediction.nonfinite == 0 && prediction.angleErrorPxDouble < 0.01) {
        worstClassic = std::max(worstClassic, prediction.angleErrorPx);
      }
      table += (table.empty() ? "" : "; ") + prediction.method + " " +
               (prediction.nonfinite ? std::string("non-finite")
                                     : number(prediction.angleErrorPx) + " / " +
                                           number(prediction.originLateralErrorPx)) +
               (prediction.backward ? " (backward)" : "");
    }
    if (worstClassic > 0.5) {
      const std::string where = p.perspective && p.eye && p.nearDistance
                                    ? "the eye is " + number(glm::length(*p.eye)) +
                                          " units from the origin with near " +
                                          number(*p.nearDistance) + " (ratio " +
                                          number(glm::length(*p.eye) / *p.nearDistance) + ")"
                                    : "at this camera";
      findings.push_back(
          {"warning", "float-precision-risk",
           where +
               "; float picking rays from this matrix err by up to (direction / origin, in "
               "pixels): " +
               table,
           "build rays with plane-cross directions and near-plane origins (clipray's robust "
           "method), "
           "and make the matrix camera-relative (remove the eye's translation in double before "
           "rounding to float)"});
    }
  }

  // Depth precision over the scene: two surfaces 1% apart are separable while the depth they map
  // to differs by more than one stored quantum; dz ~ z^2 (1/n - 1/f) dd for perspective.
  if (input.sceneExtent && p.perspective && p.nearDistance) {
    const auto [lo, hi] = *input.sceneExtent;
    double farthest = 0.0;
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 corner(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
      farthest = std::max(farthest, glm::dot(corner - *p.eye, p.viewDirection));
    }
    const double wLength = glm::length(glm::dvec3(rowW));
    const double a = glm::dot(rowZ, glm::dvec4(*p.eye, 1.0)) / wLength;
    // Window depth under the convention the app actually draws with (not the matrix's own).
    const double zn = DepthMode{declared, false}.clipVolumeMinZ();
    const double windowScale = std::abs(input.depthRange.y - input.depthRange.x) / (1.0 - zn);
    auto separable = [&](double s) {
      const double zNdc = glm::dot(glm::dvec3(rowZ), p.viewDirection) / wLength + a / s;
      const double windowDepth =
          input.depthRange.x +
          (zNdc - zn) * windowScale * (input.depthRange.y > input.depthRange.x ? 1 : -1);
      const double slope = std::abs(a) / (s * s) * windowScale;  // |d window depth / ds|
      return slope * 0.01 * s > depthQuantum(input.depthFormat, windowDepth);
    };
    if (farthest > *p.nearDistance && !separable(farthest)) {
      double low = *p.nearDistance, high = farthest;  // separable at low, not at high
      for (int i = 0; i < 200 && high / low > 1.0 + 1e-9; ++i) {
        const double mid = std::sqrt(low * high);
        (separable(mid) ? low : high) = mid;
      }
      findings.push_back(
          {"warning", "near-plane-precision",
           "with " +
               std::string(input.depthFormat == DepthFormat::Float32
                               ? "32F"
                               : depthFormatName(input.depthFormat) + "-bit") +
               " depth and near " + number(*p.nearDistance) +
               ", surfaces 1% apart stop being separable beyond " + number(low) +
               " units from the eye; the scene reaches " + number(farthest),
           "move the near plane out, or use reversed-Z with a 32F depth buffer under ZERO_TO_ONE "
           "(relative depth precision then stays ~2^-24 at every distance)"});
    }
  }
  return report;
}

nlohmann::json checkReportJson(const CheckReport& report, const CheckInput& input) {
  const MatrixProperties& p = report.properties;
  auto optional = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
  };
  nlohmann::json properties = {
      {"projection", p.perspective ? "perspective" : "orthographic"},
      {"oblique", p.oblique},
      {"off_axis", p.offAxis},
      {"handedness", p.leftHanded ? "left-handed" : "right-handed"},
      {"mirrored", p.leftHanded},
      {"view_direction", {p.viewDirection.x, p.viewDirection.y, p.viewDirection.z}},
      {"near", optional(p.nearDistance)},
      {"far", p.infiniteFar ? nlohmann::json("infinite") : optional(p.farDistance)},
      {"built_for", p.builtFor},
      {"near_if_built_for_no", optional(p.nearIfBuiltForNo)},
      {"near_if_built_for_zo", optional(p.nearIfBuiltForZo)},
      {"reversed", p.reversed},
      {"y_flipped", p.yFlipped},
      {"likely_transposed", p.likelyTransposed},
  };
  if (p.eye) properties["eye"] = {p.eye->x, p.eye->y, p.eye->z};
  if (p.perspective) {
    properties["fov_y_degrees"] = p.fovYDegrees;
    properties["fov_x_degrees"] = p.fovXDegrees;
  } else {
    properties["extent_x"] = p.extentX;
    properties["extent_y"] = p.extentY;
    properties["depth_extent"] = p.depthExtent;
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
            {"depth_bits", depthFormatName(input.depthFormat)}}},
          {"properties", properties},
          {"ray_methods_float", methods},
          {"findings", findings},
          {"verdict", report.hasErrors() ? "errors" : "ok"}};
}

std::string checkReportText(const CheckReport& report, const CheckInput& input) {
  (void)input;
  const MatrixProperties& p = report.properties;
  std::ostringstream out;
  out << "matrix: " << (p.perspective ? "perspective" : "orthographic")
      << (p.offAxis ? ", off-axis" : "") << (p.oblique ? ", oblique near plane" : "") << ", "
      << (p.leftHanded ? "left-handed (mirrored)" : "right-handed")
      << (p.reversed ? ", reversed-Z" : "") << (p.yFlipped ? ", y flipped" : "") << "\n";
  if (p.eye) out << "  eye " << vec(*p.eye) << ", looking along " << vec(p.viewDirection) << "\n";
  if (!p.eye) out << "  looking along " << vec(p.viewDirection) << "\n";
  out << "  near " << (p.nearDistance ? number(*p.nearDistance) : "-") << ", far "
      << (p.infiniteFar   ? "infinite"
          : p.farDistance ? number(*p.farDistance)
                          : "-");
  if (p.perspective) {
    out << ", fov " << number(p.fovYDegrees) << " deg vertical x " << number(p.fovXDegrees)
        << " deg horizontal\n";
  } else {
    out << ", view volume " << number(p.extentX) << " x " << number(p.extentY) << " x "
        << number(p.depthExtent) << "\n";
  }
  out << "  built for: " << p.builtFor;
  if (p.nearIfBuiltForNo && p.nearIfBuiltForZo && p.builtFor != "zo-reversed") {
    out << " (near " << number(*p.nearIfBuiltForNo) << " if NO, " << number(*p.nearIfBuiltForZo)
        << " if ZO)";
  }
  out << "\n";
  if (!report.methods.empty()) {
    out << "float picking rays at this camera, max error in pixels (direction / origin):\n";
    for (const MethodPrediction& m : report.methods) {
      if (!m.unavailable.empty()) continue;
      out << "  " << m.method << " "
          << (m.nonfinite ? std::string("non-finite")
                          : number(m.angleErrorPx) + " / " + number(m.originLateralErrorPx))
          << (m.backward ? " (backward)" : "") << "\n";
    }
  }
  if (report.findings.empty()) out << "findings: none\n";
  for (const Finding& f : report.findings) {
    out << f.severity << " [" << f.code << "] " << f.message << "\n  fix: " << f.fix << "\n";
  }
  const auto count = [&](const char* severity) {
    return std::count_if(report.findings.begin(), report.findings.end(),
                         [&](const Finding& f) { return f.severity == severity; });
  };
  out << count("error") << " errors, " << count("warning") << " warnings, " << count("info")
      << " notes\n";
  return out.str();
}

}  // namespace clipray
