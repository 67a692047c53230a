#pragma once
// The ray side of a scene whose objects are drawn with different state: a glDepthRange of their
// own (MeshObject::depthRange) or user clip planes of their own (MeshObject::clipPlanes).
// With ranges, the depth test keeps the smallest window depth (the greatest under GL_GREATER)
// over every object's own mapping, which need not be the nearest surface along the ray: a
// first-person weapon drawn in [0, 0.1] shows in front of a wall in [0.1, 1] that is nearer than
// it. With planes, each object is cut where its own planes cut it. Within one group of objects
// drawn alike the nearest hit has the extreme window depth (the mapping is monotonic along a ray),
// so each group is traced on its own, along its rays cut by its planes, and each pixel keeps the
// group hit the depth test keeps. Objects drawn with a polygon offset (MeshObject::polygonOffset)
// are grouped apart too: their hits compete with their depth moved by the offset (a decal
// coplanar with a wall wins where its offset pushes it toward the camera).
// PickingCamera::clipFromWorld: column-major, p_clip = clipFromWorld * p_world.

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Picking.hpp"
#include "clipray/compare/Frames.hpp"
#include "clipray/compare/ScreenEvaluator.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::engine {

// The objects drawn with one depth range and one set of planes of their own; the scene's group
// (its range, no planes of their own) also holds the analytic primitives.
struct DrawStateGroup {
  glm::dvec2 range{0.0, 1.0};
  std::vector<glm::dvec4> clipPlanes{};   // the objects' own, beside the camera's
  std::optional<PolygonOffset> offset{};  // the objects' polygon offset
  std::vector<std::size_t> objects{};     // indices into Scene::objects
  bool analytic = false;
};

// One group per distinct (range, planes, offset), the scene's first; a single group where every
// object is drawn with the scene's range and the camera's planes only.
std::vector<DrawStateGroup> drawStateGroups(const Scene& scene);

// The closest hits of the frame's rays against wholeScene (scene's intersector), as
// intersectFrame gives them, where the scene has one group; else the hit the depth test keeps per
// pixel (ties to the smaller primitive id: the object drawn first), each group traced by an
// intersector of its own along the frame's rays cut by the group's planes (t given along the
// frame's own ray). drawnClipFromWorld decides face culling as the frame is drawn; camera is the
// lower-left view the rays were made for (its clipFromWorld maps hits to window depth). Where the
// screen path is chosen (AnalyticChoice.hpp) a scene of one group is evaluated in screen space,
// and so is each group of several: a group keeps its decided pixels' planes, whose depths compete
// in the depth test where their bounds decide it (else the triangle's test along the group's ray
// gives the ray path's depth), and a winner from planes keeps t NaN with frame.planesById by the
// whole scene's ids (the compare tests it along its group's ray where it must). The hits are the
// ray path's. What that did is returned (ScreenEvaluation::used false otherwise, with the
// reason).
ScreenEvaluation intersectByDrawState(AnalyticFrame& frame, const SceneIntersector& wholeScene,
                                      const Scene& scene, const glm::dmat4& drawnClipFromWorld,
                                      const PickingCamera& camera, unsigned threadCount);

// The same decision for one ray (a click: the picking demo's ray pick), t along that ray; camera
// as for intersectByDrawState, its viewport the frame's (polygon offsets depend on the pixel size).
// Builds each group's intersector anew: meant for a pick, not a frame.
Hit closestHitByDrawState(const Ray& ray, const SceneIntersector& wholeScene, const Scene& scene,
                          const glm::dmat4& drawnClipFromWorld, const PickingCamera& camera);

}  // namespace clipray::engine
