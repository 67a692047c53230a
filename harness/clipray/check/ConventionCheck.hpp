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

#include "clipray/Conventions.hpp"
#include "clipray/check/MatrixReading.hpp"
#include "clipray/util/OptionValues.hpp"  // parseMatrix16, for the readers of matrices

namespace clipray {

struct CheckInput {
  // As the app uploads it, after applying the listing layout: column-major, p_clip =
  // clipFromWorld * p_world, GL clip space under the convention the app draws with.
  glm::dmat4 clipFromWorld{1.0};
  std::optional<glm::dmat4> projection;          // clipFromView, when given separately
  std::optional<glm::dmat4> view;                // viewFromWorld (affine), when given separately
  std::optional<DepthConvention> declaredDepth;  // what the app draws under (glClipControl)
  bool listedRowMajor = false;                   // the numbers were given row by row (--layout)
  bool declaredReversed = false;                 // depth test GREATER, clear 0
  glm::dvec2 depthRange{0.0, 1.0};               // glDepthRange
  std::optional<WindowOrigin> origin;            // where the app's window y counts from
  Viewport viewport{1920, 1080};
  DepthFormat depthFormat = DepthFormat::Unorm24;
  std::optional<std::pair<glm::dvec3, glm::dvec3>> sceneExtent;  // world-space box (min, max)
  // The arithmetic the app built the matrix in (--precision); detected from the values if unset.
  std::optional<EntryPrecision::Arithmetic> precision;
  // The near and far planes the app meant (--near, --far): settle NO against ZO.
  std::optional<double> statedNear, statedFar;
  // Face culling the app draws with (--cull, --front-face): checked against the winding the
  // matrix puts on screen (FacingCheck.hpp); unset: not checked.
  std::optional<CullFace> cull;
  std::optional<FrontFace> frontFace;  // unset: GL's default, GL_CCW
  // GL_DEPTH_CLAMP enabled, and where ("--depth-clamp", "glEnable(GL_DEPTH_CLAMP) at call 7");
  // unset: disabled, as by default.
  std::optional<std::string> depthClampEnabledAt;
  bool predictMethods = true;  // the ray-method table (the slow part: __float128 references)
};

struct MatrixProperties {
  std::string precision;    // what the entries were read as: "float32", "double", ...
  bool perspective = true;  // false: orthographic (parallel)
  bool oblique = false;     // the near plane is not perpendicular to the view direction
  bool offAxis = false;     // the centre of the image is not on the view direction
  // (right, up, forward) is left-handed once a y flip is undone: a mirrored image in a RH world.
  bool leftHanded = false;
  std::optional<glm::dvec3> eye;  // perspective only (non-finite where eyeAtInfinityAlong is set)
  // Perspective whose rows x, y and w meet in a direction, not a point: the centre of projection
  // is at infinity along it (a light-space perspective warp such as LiSPSM's); unit length.
  std::optional<glm::dvec3> eyeAtInfinityAlong;
  glm::dvec3 eyeError{0.0};
  glm::dvec3 viewDirection{0.0};
  double viewDirectionErrorDegrees = 0.0;
  // Distances along the view direction from the eye (perspective), or offsets from the camera
  // position (orthographic with --view) or the world origin (orthographic alone); the near plane
  // is the one in force under the declared convention. No far with an infinite far plane.
  std::optional<Uncertain> near, far;
  bool infiniteFar = false;
  std::optional<double> depthExtent;   // orthographic: |far - near|
  std::string orthographicAnchor;      // "view" or "world-origin"
  Uncertain fovYDegrees, fovXDegrees;  // perspective
  Uncertain extentX, extentY;          // orthographic: view-volume width and height
  bool reversed = false;               // depth decreases with distance
  bool reversedDecided = true;         // false: the entries' precision cannot tell (never an error)
  // The convention whose near plane the matrix was built for. NO and ZO builds are one family (a
  // NO perspective with near n is a ZO perspective with near 2fn/(f+n)), so both readings are
  // kept and one is taken only for a stated reason.
  std::string builtFor;  // "no", "zo", "zo-reversed", or "ambiguous"
  std::string builtForReason;
  std::optional<Uncertain> nearIfBuiltForNo, nearIfBuiltForZo;
  std::optional<bool> statedNearMatches, statedFarMatches;  // with --near / --far
  bool yFlipped = false;          // Vulkan-style: clip y negated (screen up along world -Y)
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

}  // namespace clipray
