#pragma once
// Face culling seen through the matrix an app draws with: which winding, seen from the eye, GL
// calls front (math/Facing.hpp), and the classic mistake of a projection or view that reverses the
// winding on screen (a y-flipped Direct3D/Vulkan-style projection under GL_UPPER_LEFT, a mirrored
// reflection view) while glFrontFace stays GL_CCW: culling then keeps the insides of meshes wound
// counter-clockwise seen from outside (glTF's, OBJ's and GL's own convention).

#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/check/ConventionCheck.hpp"

namespace clipray {

// +1 when the triangles that wind counter-clockwise in clip space (det[x; y; w] > 0, GL's front
// faces with glFrontFace(GL_CCW) under either clip origin) are the ones that wind
// counter-clockwise seen from the eye in world space; -1 when the matrix reverses the winding; 0
// for a matrix it cannot tell (singular). clipFromWorld: column-major, p_clip = M * p_world.
// reversedDepth: the depth test keeps the greater depth (reversed-Z), so NDC z shrinks away from
// the viewer; only a parallel projection needs telling (a perspective one has its eye).
int windingSign(const glm::dmat4& clipFromWorld, bool reversedDepth = false);

// The culling state at a draw, as the app set it (where each part was set, for the message).
struct CullingState {
  CullFace cull = CullFace::None;  // None: GL_CULL_FACE disabled
  FrontFace frontFace = FrontFace::Ccw;
  ClipOrigin origin = ClipOrigin::LowerLeft;
  bool reversedDepth = false;              // nearer is greater depth (windingSign)
  std::string cullSetAt = "GL's default";  // "call 1234"
  std::string frontFaceSetAt = "GL's default";
};

// A warning "face-culling-keeps-insides" when the matrix reverses the winding and culling
// therefore keeps the triangles that wind clockwise seen from the eye; nullopt otherwise (culling
// off, a matrix that keeps the winding, or a front face that accounts for the reversal).
std::optional<Finding> faceCullingFinding(const glm::dmat4& clipFromWorld,
                                          const CullingState& state);

}  // namespace clipray
