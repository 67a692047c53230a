// The computations that belong with the scene data: a camera's clipFromWorld for the convention
// and viewport it is drawn under, and the scene's counts and names.

#include <cstddef>
#include <variant>

#include "clipray/math/Projections.hpp"
#include "clipray/scene/Scene.hpp"
#include "clipray/util/Check.hpp"

namespace clipray {

glm::dmat4 Camera::clipFromWorld(DepthMode drawnUnder, Viewport drawnAt) const {
  if (rawClipFromWorld) return *rawClipFromWorld;
  const DepthMode mode = builtFor.value_or(drawnUnder);
  if (const auto* p = std::get_if<PerspectiveProjection>(&projection)) {
    const double aspect = p->aspect.value_or(static_cast<double>(drawnAt.width) /
                                             static_cast<double>(drawnAt.height));
    return perspectiveClipFromView(glm::radians(p->fovYDegrees), aspect, p->nearDistance,
                                   p->farDistance, mode) *
           viewFromWorld;
  }
  const auto* o = std::get_if<OrthographicProjection>(&projection);
  CLIPRAY_CHECK(o != nullptr,
                "camera \"" + name + "\" has neither a projection nor a clipFromWorld");
  return orthographicClipFromView(o->left, o->right, o->bottom, o->top, o->nearDistance,
                                  o->farDistance, mode) *
         viewFromWorld;
}

std::size_t Scene::triangleCount() const {
  std::size_t count = 0;
  for (const MeshObject& object : objects) count += object.triangles.size();
  return count;
}

const char* logDepthFormName(LogDepthForm form) {
  return form == LogDepthForm::ThreeJs ? "threejs" : "outerra";
}

const char* primitiveKindName(PrimitiveKind kind) {
  switch (kind) {
    case PrimitiveKind::Sphere:
      return "sphere";
    case PrimitiveKind::Disk:
      return "disk";
    case PrimitiveKind::Quad:
      return "quad";
    case PrimitiveKind::Box:
      return "box";
    case PrimitiveKind::Plane:
      return "plane";
  }
  return "?";
}

}  // namespace clipray
