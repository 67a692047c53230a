#pragma once
// `clipray check`: what a GL app's matrix is, and what is wrong with how the app uses it.
// Everything is derived from the matrix itself (and the projection/view when given separately):
// the eye is the null vector of rows 0, 1, 3; a w row without xyz is a parallel projection; where
// the clip planes land along the view direction gives near, far and the convention built for.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "clipray/math/Conventions.hpp"

namespace clipray {

enum class WindowOrigin { LowerLeft, UpperLeft };

struct CheckInput {
  glm::dmat4 clipFromWorld{1.0};         // as the app uploads it, after applying the listing layout
  std::optional<glm::dmat4> projection;  // clipFromView, when given separately
  std::optional<glm::dmat4> view;        // viewFromWorld, when given separately
  std::optional<DepthConvention> declaredDepth;  // what the app draws under (glClipControl)
  bool declaredReversed = false;                 // depth test GREATER, clear 0
  glm::dvec2 depthRange{0.0, 1.0};               // glDepthRange
  std::optional<WindowOrigin> origin;            // where the app's window y counts from
  Viewport viewport{1920, 1080};
  DepthFormat depthFormat = DepthFormat::Unorm24;
  std::optional<std::pair<glm::dvec3, glm::dvec3>> sceneExtent;  // world-space box (min, max)
};

struct MatrixProperties {
  bool perspective = true;  // false: orthographic (parallel)
  bool oblique = false;     // the near plane is not perpendicular to the view direction
  bool offAxis = false;     // the centre of the image is not on the view direction
  bool leftHanded = false;  // (right, up, forward) is left-handed: a mirrored image in a RH world
  std::optional<glm::dvec3> eye;  // perspective only
  glm::dvec3 viewDirection{0.0};
  // Distances along the view direction from the eye (perspective) or from the view origin
  // (orthographic with --view); nullopt far = infinite far plane.
  std::optional<double> nearDistance;
  std::optional<double> farDistance;
  bool infiniteFar = false;
  double depthExtent = 0.0;  // orthographic: distance between the near and far planes
  double fovYDegrees = 0.0, fovXDegrees = 0.0;  // perspective
  double extentX = 0.0, extentY = 0.0;          // orthographic: view-volume width and height
  bool reversed = false;                        // depth decreases with distance
  // The convention whose near plane the matrix was built for: NO and ZO builds of a perspective
  // matrix are the same family (a NO matrix with near n is a ZO matrix with near 2fn/(f+n)), so
  // the build is recognised by which reading gives the rounder near value.
  std::string builtFor;  // "no", "zo", "zo-reversed", or "ambiguous"
  std::optional<double> nearIfBuiltForNo, nearIfBuiltForZo;
  bool yFlipped = false;          // screen up points along world -Y, or the projection has m11 < 0
  bool likelyTransposed = false;  // the transpose looks like a projection, the matrix does not
};

// What each ray method errs by at this camera in float, against the exact ray of the float matrix
// (the ray library's __float128 reference), sampled over five rows of the viewport.
struct MethodPrediction {
  std::string method;       // "two_point", ...
  std::string unavailable;  // why the method cannot run on these inputs (then no figures)
  double angleErrorPx = 0.0;
  double originLateralErrorPx = 0.0;
  double angleErrorPxDouble = 0.0;  // the same method in double: large here means the method
                                    // itself fails on this camera, not float precision
  std::uint64_t nonfinite = 0;
  std::uint64_t backward = 0;
};

struct Finding {
  std::string severity;  // "error", "warning", "info"
  std::string code;
  std::string message;
  std::string fix;
};

struct CheckReport {
  MatrixProperties properties;
  std::vector<MethodPrediction> methods;
  std::vector<Finding> findings;
  bool hasErrors() const;
};

// Throws InputError for unusable input (singular, non-projective, non-finite, contradictory).
CheckReport checkConventions(const CheckInput& input);

nlohmann::json checkReportJson(const CheckReport& report, const CheckInput& input);
std::string checkReportText(const CheckReport& report, const CheckInput& input);

// Parses 16 numbers listed column-major (GL, glm::value_ptr) or row-major (D3D, a C array
// m[row][col]); `what` names the option or field in messages.
glm::dmat4 parseMatrix16(const std::vector<double>& numbers, bool rowMajor,
                         const std::string& what);

}  // namespace clipray
