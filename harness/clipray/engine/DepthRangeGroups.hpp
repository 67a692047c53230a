#pragma once
// The ray side of a scene whose objects are drawn with different glDepthRange values
// (MeshObject::depthRange): the depth test keeps the smallest window depth (the greatest under
// GL_GREATER) over every object's own mapping, which need not be the nearest surface along the
// ray: a first-person weapon drawn in [0, 0.1] shows in front of a wall in [0.1, 1] that is nearer
// than it. Within one range the nearest hit has the extreme window depth (the mapping is monotonic
// along a ray), so each group of objects sharing a range is traced on its own and each pixel keeps
// the group hit the depth test keeps. Objects drawn with a polygon offset (MeshObject::
// polygonOffset) are grouped apart too: their hits compete with their depth moved by the offset
// (a decal coplanar with a wall wins where its offset pushes it toward the camera).
// PickingCamera::clipFromWorld: column-major, p_clip = clipFromWorld * p_world.

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Picking.hpp"
#include "clipray/compare/Frames.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::engine {

// The objects drawn with one depth range; the scene's group also holds the analytic primitives.
struct DepthRangeGroup {
  glm::dvec2 range{0.0, 1.0};
  std::optional<PolygonOffset> offset{};  // the group's objects' polygon offset
  std::vector<std::size_t> objects;       // indices into Scene::objects
  bool analytic = false;                  // the scene's range: the analytic primitives' too
};

// One group per distinct range and polygon offset, the scene's first; a single group where every
// object is drawn with the scene's range and no offset.
std::vector<DepthRangeGroup> depthRangeGroups(const Scene& scene);

// The closest hits of the frame's rays against wholeScene (scene's intersector), as
// intersectFrame gives them, where the scene has one depth range; else the hit the depth test
// keeps per pixel (ties to the smaller primitive id: the object drawn first), each group traced
// by an intersector of its own. drawnClipFromWorld decides face culling as the frame is drawn;
// camera is the lower-left view the rays were made for (its clipFromWorld maps hits to window
// depth).
void intersectByDepthRange(AnalyticFrame& frame, const SceneIntersector& wholeScene,
                           const Scene& scene, const glm::dmat4& drawnClipFromWorld,
                           const PickingCamera& camera, unsigned threadCount);

}  // namespace clipray::engine
