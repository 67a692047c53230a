#include "clipray/check/ConventionCheck.hpp"

#include "clipray/check/CheckText.hpp"
#include "clipray/check/DepthClampCheck.hpp"
#include "clipray/check/FacingCheck.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "clipray/InputError.hpp"
#include "clipray/check/BuiltFor.hpp"
#include "clipray/check/MatrixReading.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/rays/QuadReference.hpp"
#include "clipray/rays/RayErrors.hpp"
#include "clipray/rays/RayMethods.hpp"
#include "clipray/rays/RobustRays.hpp"

namespace clipray {

using detail::BuildReading;
using detail::kStatedPlaneTolerance;
using detail::readBuild;
using detail::readOrthographicBuild;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string number(double value) {
  return detail::checkNumber(value);
}

std::string vec(const glm::dvec3& v) {
  return detail::checkVector(v);
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
// The tests are relative to the rows' lengths, at `tolerance` (from the entries' precision).
int projectionStructureScore(const glm::dmat4& m, double tolerance) {
  const glm::dvec3 x(matrixRow(m, 0)), y(matrixRow(m, 1)), z(matrixRow(m, 2));
  const glm::dvec4 w = matrixRow(m, 3);
  const glm::dvec3 w3(w);
  auto parallel = [&](const glm::dvec3& a, const glm::dvec3& b) {
    return glm::length(glm::cross(a, b)) <= tolerance * glm::length(a) * glm::length(b);
  };
  auto perpendicular = [&](const glm::dvec3& a, const glm::dvec3& b) {
    return std::abs(glm::dot(a, b)) <= tolerance * glm::length(a) * glm::length(b);
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
      const MethodErrors result = errors.result();
      if (result.rays == 0) {
        // Every sampled pixel looks beyond the horizon of an oblique near plane (or the matrix,
        // under these conventions, puts the near plane behind the eye): nothing to measure.
        prediction.unavailable = "no sampled pixel has a ray";
        predictions.push_back(prediction);
        continue;
      }
      prediction.angleErrorPxDouble = doubleErrors.result().anglePx.max;
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

// The convention the app draws under: --declared-depth, else GL's default NEGATIVE_ONE_TO_ONE.
DepthConvention declaredConvention(const CheckInput& input) {
  return input.declaredDepth.value_or(DepthConvention::NegativeOneToOne);
}

// Refuses what no reading can come from (InputError naming the option): non-finite or
// non-projective matrices, a view that is not affine, an empty depth range, a matrix whose inverse
// overflows.
void requireUsableInput(const CheckInput& input) {
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
  requireFinite(glm::inverse(m),
                std::string(input.projection ? "--projection * --view" : "--clip-from-world") +
                    " (its inverse)");
}

// The precision the entries carry (p.precision), and whether the matrix reads as listed transposed.
EntryPrecision readPrecision(const CheckInput& input, MatrixProperties& p) {
  const glm::dmat4& m = input.clipFromWorld;
  // The precision the entries carry, and the uncertainty of every figure read from them.
  std::vector<glm::dmat4> listed = {m};
  if (input.projection) listed = {*input.projection, input.view.value_or(glm::dmat4(1.0))};
  EntryPrecision precision = detectEntryPrecision(listed);
  if (input.precision) precision.arithmetic = *input.precision;
  p.precision = precision.description();
  // A row's direction carries about (roundings per entry) u of error; 16x that is still far below
  // what a transposed camera translation does to the structure.
  const double structureTolerance =
      std::max(1e-6, 16.0 * (8.0 * precision.unitRoundoff() + precision.decimalRelative()));
  p.likelyTransposed = projectionStructureScore(glm::transpose(m), structureTolerance) == 5 &&
                       projectionStructureScore(m, structureTolerance) <= 3;
  return precision;
}

// The direction in which rows x, y and w (their xyz parts) meet when they have no common point:
// their null direction, the largest of their pairwise cross products (rank 2), signed so that its
// largest component is positive.
glm::dvec3 centreAtInfinity(const glm::dmat4& m) {
  const glm::dvec3 x(matrixRow(m, 0)), y(matrixRow(m, 1)), w(matrixRow(m, 3));
  glm::dvec3 direction = glm::cross(x, y);
  for (const glm::dvec3& other : {glm::cross(y, w), glm::cross(x, w)}) {
    if (glm::length(other) > glm::length(direction)) direction = other;
  }
  if (!(glm::length(direction) > 0.0)) return glm::dvec3(0.0);
  direction = glm::normalize(direction);
  int largest = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(direction[k]) > std::abs(direction[largest])) largest = k;
  }
  return direction[largest] < 0.0 ? -direction : direction;
}

// A perspective matrix: its eye, whether it is oblique, off-axis or reversed, its near and far
// planes, and which convention it was built for.
void readPerspective(const MatrixReading& reading, const CheckInput& input, MatrixProperties& p) {
  const DepthConvention declared = declaredConvention(input);
  const auto distance = [](const Uncertain& u) -> std::optional<Uncertain> {
    return std::isfinite(u.value) ? std::optional<Uncertain>(u) : std::nullopt;
  };
  p.eye = reading.eye;
  if (!std::isfinite(reading.eye.x) || !std::isfinite(reading.eye.y) ||
      !std::isfinite(reading.eye.z)) {
    p.eyeAtInfinityAlong = centreAtInfinity(input.clipFromWorld);
  }
  p.eyeError = reading.eyeError;
  // The near plane is oblique when the depth row's xyz leaves the w row's line (any convention:
  // every near plane z = z_n w is then tilted with it).
  p.oblique = reading.obliqueAngleZo.clearlyPositive();
  // z_ndc = b + a / s along the view: a > 0 means depth falls with distance. Where the
  // translation cancels a (an eye far from the origin), b still tells for a near plane facing
  // the view: z_ndc tends to b far away, 1 or more for classic depth and 0 or less reversed.
  // An oblique plane's b says nothing: then reversal stays undecided.
  if (!reading.a.withinErrorOfZero()) {
    p.reversed = reading.a.clearlyPositive();
  } else if (!p.oblique &&
             (reading.b.value >= 1.0 - reading.b.error || reading.b.value <= reading.b.error)) {
    p.reversed = reading.b.value < 0.5;
  } else {
    p.reversedDecided = false;
  }
  if (p.reversed) {
    // Reversed: near at z_ndc = 1; far at 0 under ZO, at -1 under NO (Godot's GL renderer).
    p.builtFor = "zo-reversed";
    p.near = distance(reading.nearIfReversed);
    const bool underNo = declared == DepthConvention::NegativeOneToOne && input.declaredDepth;
    const Uncertain farZ{reading.b.value + (underNo ? 1.0 : 0.0), reading.b.error};
    // No distance reaching the far depth (a ZO-reversed matrix under NO) clips nothing either;
    // but where the translation cancels a, no distance is known at all.
    p.far = distance(underNo ? reading.nearIfNo : reading.farIfReversed);
    p.infiniteFar = farZ.withinErrorOfZero() || (!p.far && !reading.a.withinErrorOfZero());
    if (p.infiniteFar) p.far.reset();
  } else {
    p.nearIfBuiltForNo = distance(reading.nearIfNo);
    p.nearIfBuiltForZo = distance(reading.nearIfZo);
    p.infiniteFar = !(std::abs(1.0 - reading.b.value) > reading.b.error);
    if (!p.infiniteFar) p.far = distance(reading.far);
    BuildReading build =
        readBuild(p.nearIfBuiltForNo, p.nearIfBuiltForZo, input.statedNear, "near plane");
    if (p.oblique && !input.statedNear) {
      // A tilted near plane's distance along the view is no value the app typed.
      build = {"ambiguous",
               "the near plane is oblique: its distance along the view is not a typed value",
               {}};
    }
    p.builtFor = build.builtFor;
    p.builtForReason = build.reason;
    p.statedNearMatches = build.statedMatches;
    p.near = declared == DepthConvention::ZeroToOne ? p.nearIfBuiltForZo : p.nearIfBuiltForNo;
  }
  p.offAxis = reading.offAxisAngle.clearlyPositive();
  p.fovYDegrees = reading.fovYDegrees;
  p.fovXDegrees = reading.fovXDegrees;
}

// An orthographic matrix: its extent, its near and far plane offsets and which convention it was
// built for.
void readOrthographic(const MatrixReading& reading, const CheckInput& input,
                      const std::optional<glm::dvec3>& viewOrigin, MatrixProperties& p) {
  const DepthConvention declared = declaredConvention(input);
  // Orthographic: near and far are offsets along the view direction from the camera position
  // (--view), else from the world origin (the camera position when the matrix is a projection
  // alone). Reversal does not show in a parallel projection's matrix: it is what is declared.
  p.reversed = input.declaredReversed;
  p.orthographicAnchor = viewOrigin ? "view" : "world-origin";
  p.extentX = reading.extentX;
  p.extentY = reading.extentY;
  p.oblique = reading.obliqueAngleZo.clearlyPositive();
  if (p.reversed) {
    // Offsets along the view direction, which runs against the growth of reversed depth.
    p.builtFor = "zo-reversed";
    p.near = Uncertain{-reading.nearIfReversed.value, reading.nearIfReversed.error};
    p.far = Uncertain{-reading.farIfReversed.value, reading.farIfReversed.error};
  } else {
    p.nearIfBuiltForNo = reading.nearIfNo;
    p.nearIfBuiltForZo = reading.nearIfZo;
    p.far = reading.far;
    // Offsets from the world origin are no values an app typed: only a camera position (the
    // view, or a projection given alone) makes the readings comparable with typed planes.
    const BuildReading build =
        viewOrigin ? readOrthographicBuild(reading.nearIfNo, reading.nearIfZo, reading.far,
                                           input.statedNear)
                   : BuildReading{"ambiguous",
                                  "an orthographic matrix alone does not fix the camera "
                                  "position its near plane is measured from (give --projection "
                                  "and --view)",
                                  {}};
    p.builtFor = build.builtFor;
    p.builtForReason = build.reason;
    p.statedNearMatches = build.statedMatches;
    p.near = declared == DepthConvention::ZeroToOne ? p.nearIfBuiltForZo : p.nearIfBuiltForNo;
  }
  if (p.near && p.far) p.depthExtent = std::abs(p.far->value - p.near->value);
}

// Whether the stated far plane (--far) is the matrix's.
void readStatedFar(const MatrixReading& reading, const CheckInput& input, MatrixProperties& p) {
  if (input.statedFar && !p.infiniteFar && p.far &&
      std::abs(p.far->value - *input.statedFar) >
          p.far->error + kStatedPlaneTolerance * std::abs(*input.statedFar)) {
    p.statedFarMatches = false;
  } else if (input.statedFar && p.infiniteFar && std::isfinite(*input.statedFar)) {
    // An infinite reading covers any far plane beyond what the precision can tell apart.
    p.statedFarMatches = *input.statedFar * (1.0 - reading.b.value) >= 0.0;
  }
}

// Handedness, and a Vulkan-style y flip: negating the clip y row also flips the frame, so a
// left-handed frame whose screen up points down a Y-up world reads as that flip, not a mirror.
void readHandedness(const MatrixReading& reading, const CheckInput& input, MatrixProperties& p) {
  // A parallel projection's forward is read as where depth grows: the viewer's back under a
  // declared reversed-Z, whose depth shrinks away from the viewer (the frame turns around).
  const bool reversedParallel = !p.perspective && p.reversed;
  const bool frameLeftHanded = (reading.handedness.value > 0.0) != reversedParallel;
  p.yFlipped = input.projection ? (*input.projection)[1][1] < 0.0
                                : frameLeftHanded && reading.screenUpY.clearlyNegative();
  p.leftHanded = frameLeftHanded != p.yFlipped;
}

// What the matrix is, read from the matrix alone (and the stated planes): the properties the
// findings are made from.
MatrixProperties readProperties(const CheckInput& input) {
  MatrixProperties p;
  const glm::dmat4& m = input.clipFromWorld;
  const EntryPrecision precision = readPrecision(input, p);
  const std::optional<glm::dvec3> viewOrigin =
      input.view ? std::optional<glm::dvec3>(glm::dvec3(glm::inverse(*input.view)[3]))
                 : std::nullopt;
  const glm::dvec3 anchor = translationAnchor(m);
  const MatrixReading reading =
      readMatrix(m, entryErrors(m, precision, anchor), viewOrigin.value_or(glm::dvec3(0.0)));
  p.perspective = reading.perspective;
  p.viewDirection = reading.viewDirection;
  p.viewDirectionErrorDegrees = reading.viewDirectionAngle.error * 180.0 / kPi;

  if (p.perspective) {
    readPerspective(reading, input, p);
  } else {
    readOrthographic(reading, input, viewOrigin, p);
    // Read as where depth grows, which a declared reversed-Z turns towards the viewer.
    if (p.reversed) p.viewDirection = -p.viewDirection;
  }
  readStatedFar(reading, input, p);
  readHandedness(reading, input, p);
  return p;
}

// Ray geometry for the method predictions, under the conventions the app draws with (reversed as
// the matrix says, or as declared for orthographic matrices).
DepthMode predictionMode(const CheckInput& input, const MatrixProperties& p) {
  const DepthConvention declared = declaredConvention(input);
  const DepthMode drawn{declared, false};
  return p.perspective ? (p.reversed ? kZeroToOneReversed : drawn)
                       : DepthMode{declared, input.declaredReversed};
}

// The glm function whose structure the matrix has (orthographic or perspective, off-axis,
// infinite far, the camera frame's handedness), built for `convention` ("NO" or "ZO").
std::string glmProjectionFunction(const MatrixProperties& p, const std::string& convention) {
  const std::string base = !p.perspective  ? "ortho"
                           : p.offAxis     ? "frustum"
                           : p.infiniteFar ? "infinitePerspective"
                                           : "perspective";
  return "glm::" + base + (p.leftHanded ? "LH_" : "RH_") + convention;
}

std::string clipOriginName(const CheckInput& input) {
  return input.origin == WindowOrigin::UpperLeft ? "GL_UPPER_LEFT" : "GL_LOWER_LEFT";
}

// The matrix against the declared convention and the stated planes: built for the other
// convention, readable as built for either, a stated near or far plane that is not the matrix's.
void conventionFindings(const CheckInput& input, const MatrixProperties& p,
                        std::vector<Finding>& findings) {
  const DepthConvention declared = declaredConvention(input);
  const std::string declaredName =
      input.declaredDepth ? (declared == DepthConvention::ZeroToOne ? "zo" : "no") : "";
  const std::string nearWord = p.perspective ? "near" : "near plane offset";
  if (input.declaredDepth && (p.builtFor == "no" || p.builtFor == "zo") &&
      p.builtFor != declaredName) {
    const double no = p.nearIfBuiltForNo->value, zo = p.nearIfBuiltForZo->value;
    const std::string why = " (read as built for " + p.builtFor + ": " + p.builtForReason + ")";
    if (p.builtFor == "no") {
      findings.push_back(
          {"error", "depth-convention-mismatch",
           "built for NEGATIVE_ONE_TO_ONE (" + nearWord + " " + shownReading(*p.nearIfBuiltForNo) +
               ") but drawn under ZERO_TO_ONE: the rasterizer clips at z_ndc = 0, so the "
               "effective near plane moves to " +
               shownReading(*p.nearIfBuiltForZo) +
               (p.perspective ? " (" + number(zo / no) + "x)" : std::string()) +
               " and NDC [-1, 0), half the depth range, is never used" + why,
           "build the projection for ZO (" + glmProjectionFunction(p, "ZO") +
               "; in any engine, the depth row z replaced by (z + w) / 2) or draw with "
               "glClipControl(" +
               clipOriginName(input) + ", GL_NEGATIVE_ONE_TO_ONE)"});
    } else {
      findings.push_back(
          {"error", "depth-convention-mismatch",
           "built for ZERO_TO_ONE (" + nearWord + " " + shownReading(*p.nearIfBuiltForZo) +
               ") but drawn under NEGATIVE_ONE_TO_ONE: the rasterizer keeps geometry down to "
               "z_ndc = -1, at " +
               shownReading(*p.nearIfBuiltForNo) +
               ", nearer than the intended near plane, and spends half the depth range on that "
               "sliver" +
               why,
           "build the projection for NO (" + glmProjectionFunction(p, "NO") +
               "; in any engine, the depth row z replaced by 2 z - w) or draw with "
               "glClipControl(" +
               clipOriginName(input) + ", GL_ZERO_TO_ONE)"});
    }
  } else if (input.declaredDepth && p.builtFor == "ambiguous" && p.nearIfBuiltForNo &&
             p.nearIfBuiltForZo) {
    findings.push_back(
        {"info", "depth-convention-ambiguous",
         "this matrix reads as built for NO with " + nearWord + " " +
             shownReading(*p.nearIfBuiltForNo) + " or for ZO with " + nearWord + " " +
             shownReading(*p.nearIfBuiltForZo) + " (" + p.builtForReason +
             "); under the declared " + conventionName(declared) + " the near plane is at " +
             shownReading(*p.near),
         "if that is not your near plane, the projection was built for the other convention; "
         "--near states the plane you meant"});
  }
  if (p.statedNearMatches == false) {
    findings.push_back(
        {"error", "near-plane-mismatch",
         "the stated near plane " + number(*input.statedNear) +
             " is neither reading of the matrix (" +
             (p.nearIfBuiltForNo ? shownReading(*p.nearIfBuiltForNo) : std::string("none")) +
             " if built for NO, " +
             (p.nearIfBuiltForZo ? shownReading(*p.nearIfBuiltForZo) : std::string("none")) +
             " if built for ZO)",
         "check which matrix the app uploads, and the near value it builds it with"});
  }
  if (p.statedFarMatches == false) {
    findings.push_back({"error", "far-plane-mismatch",
                        "the stated far plane " + number(*input.statedFar) +
                            " is not the matrix's (" +
                            (p.infiniteFar ? std::string("infinite") : shownReading(*p.far)) + ")",
                        "check which matrix the app uploads, and the far value it builds it with"});
  }
}

// Reversed-Z: under a convention that wastes it, or against the depth test the app declares.
void depthTestFindings(const CheckInput& input, const MatrixProperties& p,
                       std::vector<Finding>& findings) {
  const DepthConvention declared = declaredConvention(input);
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
  if (p.perspective && p.reversedDecided && nearIsDeeper != input.declaredReversed) {
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
}

// The camera frame: a y flip, the window origin, a mirror, an oblique near plane, a far plane at
// infinity.
void frameFindings(const CheckInput& input, const MatrixProperties& p,
                   std::vector<Finding>& findings) {
  if (p.yFlipped) {
    if (input.origin != WindowOrigin::UpperLeft) {
      findings.push_back(
          {"warning", "y-flipped",
           "the projection flips y (Vulkan-style, screen up along world -Y): under GL's " +
               std::string(input.origin ? "" : "default ") +
               "lower-left origin the image is upside down and triangle winding flips",
           "drop the flip for GL, or keep it and use glClipControl(GL_UPPER_LEFT, ...) (then "
           "--origin upper-left)"});
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
}

// A far plane at infinity, and what the ray methods measured at this camera make of it.
void infiniteFarFinding(const MatrixProperties& p, const std::vector<MethodPrediction>& methods,
                        std::vector<Finding>& findings) {
  if (!p.infiniteFar) return;
  const auto measured = [&](const char* name) -> const MethodPrediction* {
    for (const MethodPrediction& m : methods) {
      if (m.method == name && m.unavailable.empty()) return &m;
    }
    return nullptr;
  };
  std::string message =
      "the far plane is at infinity: unproject_glm and two_point unproject the far point, whose w "
      "is 0";
  const MethodPrediction* unproject = measured("unproject_glm");
  const MethodPrediction* twoPoint = measured("two_point");
  if (unproject && twoPoint) {
    message += unproject->nonfinite > 0 || twoPoint->nonfinite > 0
                   ? " (non-finite rays at this camera)"
                   : " (finite at this camera only because float rounding leaves that w off 0)";
  }
  const MethodPrediction* full = measured("full");
  if (p.reversed) {
    message +=
        "; seed 002 listing 4 (full) puts the far plane at z_ndc = 1, which reversed-Z "
        "makes the near plane";
  } else {
    message +=
        "; seed 002 listing 4 (full) takes the direction's sign from dot(mw - mz, d), which "
        "is exactly 0 here, so from the sign of a zero";
    if (full) {
      message += full->backward > 0 || full->nonfinite > 0
                     ? ": backward at this camera"
                     : ": right at this camera (see the ray table), but only because of the view "
                       "direction's octant";
    }
  }
  findings.push_back({"warning", "infinite-far-plane", message,
                      "build picking rays from the plane cross product turned to where clip w "
                      "grows, dot(mw, d) > 0, in front of the eye at every pixel (clipray's robust "
                      "method), starting on the near plane; t_max = +inf"});
}

// The finding on the method predictions: float picking rays that err where double ones would not.
void floatPrecisionFinding(const MatrixProperties& p, const std::vector<MethodPrediction>& methods,
                           std::vector<Finding>& findings) {
  double worstClassic = 0.0;
  std::string table;
  for (const MethodPrediction& prediction : methods) {
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
    const std::string where = p.perspective && p.eye && p.near
                                  ? "the eye is " + number(glm::length(*p.eye)) +
                                        " units from the origin with near " +
                                        shownReading(*p.near) + " (ratio " +
                                        number(glm::length(*p.eye) / p.near->value) + ")"
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
void depthPrecisionFinding(const CheckInput& input, const MatrixProperties& p,
                           std::vector<Finding>& findings) {
  const glm::dmat4& m = input.clipFromWorld;
  const DepthConvention declared = declaredConvention(input);
  if (input.sceneExtent && p.perspective && p.near) {
    const auto [lo, hi] = *input.sceneExtent;
    double farthest = 0.0;
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 corner(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
      farthest = std::max(farthest, glm::dot(corner - *p.eye, p.viewDirection));
    }
    const glm::dvec4 rowZ = matrixRow(m, 2), rowW = matrixRow(m, 3);
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
    if (farthest > p.near->value && !separable(farthest)) {
      double low = p.near->value, high = farthest;  // separable at low, not at high
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
               " depth and near " + shownReading(*p.near) +
               ", surfaces 1% apart stop being separable beyond " + number(low) +
               " units from the eye; the scene reaches " + number(farthest),
           "move the near plane out, or use reversed-Z with a 32F depth buffer under ZERO_TO_ONE "
           "(relative depth precision then stays ~2^-24 at every distance)"});
    }
  }
}

}  // namespace

bool CheckReport::hasErrors() const {
  return std::any_of(findings.begin(), findings.end(),
                     [](const Finding& f) { return f.severity == "error"; });
}

CheckReport checkConventions(const CheckInput& input) {
  requireUsableInput(input);
  CheckReport report;
  report.properties = readProperties(input);
  const MatrixProperties& p = report.properties;
  if (p.likelyTransposed) {
    if (input.listedRowMajor) {
      // The user said row by row; the numbers are the other order (GL's or XMMATRIX's memory).
      report.findings.push_back(
          {"error", "likely-transposed",
           "read row by row (--layout row-major), the numbers do not have a projection's "
           "structure but read column by column they do: they are probably in column-major order "
           "(a GL mat4 or a DirectXMath XMMATRIX as it lies in memory)",
           "give the numbers with --layout column-major (the default); an app that uploads this "
           "memory with glUniformMatrix4fv(..., GL_FALSE, ...) uploads it correctly"});
    } else {
      report.findings.push_back(
          {"error", "likely-transposed",
           "the matrix does not have a projection's structure but its transpose does: it was "
           "probably listed row-major (D3D, a C array m[row][col]) and uploaded as column-major",
           "upload with glUniformMatrix4fv(..., GL_TRUE, ...) or transpose it; if the numbers "
           "are written row by row, clipray check --layout row-major reads them so"});
    }
    // Everything else would describe the scrambled matrix: say only what matters.
    return report;
  }
  conventionFindings(input, p, report.findings);
  if (!input.declaredDepth) {
    report.findings.push_back(
        {"info", "depth-convention-unchecked",
         "no depth convention declared: the matrix (" +
             (p.builtFor == "ambiguous" ? std::string("readable as built for NO or ZO")
                                        : "built for " + p.builtFor) +
             ") was not checked against the one the app draws under, and the near plane shown "
             "is the one GL's default NEGATIVE_ONE_TO_ONE gives",
         "give --declared-depth no, zo or zo-reversed (glClipControl's depth mode, and GL_GREATER "
         "with reversed-Z) to check it"});
  }
  depthTestFindings(input, p, report.findings);
  frameFindings(input, p, report.findings);
  // Float precision: what each ray method errs by at this camera, from the ray library.
  if (input.predictMethods) report.methods = predictMethodErrors(input, predictionMode(input, p));
  infiniteFarFinding(p, report.methods, report.findings);
  floatPrecisionFinding(p, report.methods, report.findings);
  depthPrecisionFinding(input, p, report.findings);
  if (input.cull) {
    CullingState culling;
    culling.cull = *input.cull;
    culling.frontFace = input.frontFace.value_or(FrontFace::Ccw);
    culling.reversedDepth = input.declaredReversed;
    culling.cullSetAt = "--cull";
    culling.frontFaceSetAt = input.frontFace ? "--front-face" : "GL's default";
    if (auto finding = faceCullingFinding(input.clipFromWorld, culling)) {
      report.findings.push_back(std::move(*finding));
    }
  }
  if (auto finding = depthClampFinding(input, p)) report.findings.push_back(std::move(*finding));
  return report;
}

}  // namespace clipray
