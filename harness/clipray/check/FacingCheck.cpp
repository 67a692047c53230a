#include "clipray/check/FacingCheck.hpp"

#include <cmath>

#include "clipray/math/Facing.hpp"

namespace clipray {

int windingSign(const glm::dmat4& clipFromWorld, bool reversedDepth) {
  const glm::dmat4 worldFromClip = glm::inverse(clipFromWorld);
  // A triangle inside the view volume (w > 0 at every vertex), counter-clockwise in NDC: its
  // clip-space orientation is positive by construction.
  const auto unproject = [&](double x, double y) {
    const glm::dvec4 p = worldFromClip * glm::dvec4(x, y, 0.5, 1.0);
    return glm::dvec3(p) / p.w;
  };
  const glm::dvec3 a = unproject(-0.5, -0.5), b = unproject(0.5, -0.5), c = unproject(0.0, 0.5);
  const auto clip = [&](const glm::dvec3& p) { return clipFromWorld * glm::dvec4(p, 1.0); };
  const double orientation = clipOrientation(clip(a), clip(b), clip(c));
  const glm::dvec3 normal = glm::cross(b - a, c - a);
  // The eye: the point the matrix sends to x = y = w = 0 (for a parallel projection a point at
  // infinity, the direction towards the viewer up to sign).
  const glm::dvec4 eye = worldFromClip * glm::dvec4(0.0, 0.0, 1.0, 0.0);
  double towardsEye = 0.0;
  if (std::abs(eye.w) > 1e-12 * glm::length(glm::dvec3(eye))) {
    towardsEye = glm::dot(normal, glm::dvec3(eye) / eye.w - a);
  } else {
    // Parallel: the viewer lies against the direction in which the triangle's points recede,
    // the direction from the view volume's centre depth to its far depth (NDC z 0.5 -> 1, or
    // -> 0 under reversed-Z, whose far plane is at 0).
    const glm::dvec4 farther = worldFromClip * glm::dvec4(0.0, 0.0, reversedDepth ? 0.0 : 1.0, 1.0);
    const glm::dvec4 centre = worldFromClip * glm::dvec4(0.0, 0.0, 0.5, 1.0);
    const glm::dvec3 recede = glm::dvec3(farther) / farther.w - glm::dvec3(centre) / centre.w;
    towardsEye = -glm::dot(normal, recede);
  }
  if (!(orientation > 0.0) || towardsEye == 0.0 || !std::isfinite(towardsEye)) return 0;
  return towardsEye > 0.0 ? 1 : -1;
}

std::optional<Finding> faceCullingFinding(const glm::dmat4& clipFromWorld,
                                          const CullingState& state) {
  if (state.cull == CullFace::None) return std::nullopt;
  // A matrix that keeps the winding: a front face of GL_CW is the app's choice (meshes wound
  // clockwise, as Direct3D content is), not a mistake this check can see.
  const int sign = windingSign(clipFromWorld, state.reversedDepth);
  if (sign >= 0) return std::nullopt;
  // The winding seen from the eye of the faces GL keeps: its front faces for GL_BACK.
  const bool frontIsCcwFromEye = state.frontFace == FrontFace::Cw;
  const bool keepsCcwFromEye = frontIsCcwFromEye == (state.cull == CullFace::Back);
  if (keepsCcwFromEye) return std::nullopt;
  const std::string cullName = state.cull == CullFace::Back ? "GL_BACK" : "GL_FRONT";
  const std::string frontName = state.frontFace == FrontFace::Ccw ? "GL_CCW" : "GL_CW";
  const std::string otherFront = state.frontFace == FrontFace::Ccw ? "GL_CW" : "GL_CCW";
  const std::string why =
      state.origin == ClipOrigin::UpperLeft
          ? "the matrix flips y, as a projection built for glClipControl(GL_UPPER_LEFT) does; "
            "the origin turns the picture upright but GL keeps clip space's winding"
          : "the matrix reverses the winding on screen (a y-flipped projection, a left-handed "
            "view and projection, or a mirrored view such as a reflection pass)";
  return Finding{
      "warning", "face-culling-keeps-insides",
      "face culling (glCullFace(" + cullName + ") at " + state.cullSetAt + ", glFrontFace(" +
          frontName + ") at " + state.frontFaceSetAt +
          ") keeps the triangles that wind clockwise seen from the eye: " + why +
          ". Meshes wound counter-clockwise seen from outside (glTF, OBJ, GL's default) show "
          "their insides",
      "glFrontFace(" + otherFront +
          ") while this matrix is in force (nothing, if the meshes are wound clockwise seen "
          "from outside)"};
}

}  // namespace clipray
