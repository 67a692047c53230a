#include "clipray/compare/PolygonOffset.hpp"

#include "clipray/scene/Scene.hpp"

namespace clipray {

PrimitiveOffsets::PrimitiveOffsets(const Scene& scene) {
  const PrimitiveIdTable ids(scene);
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const MeshObject& object = scene.objects[k];
    if (!object.polygonOffset || object.triangles.empty()) continue;
    const std::uint32_t first = ids.firstIdOfObject[k];
    runs_.push_back({first, first + static_cast<std::uint32_t>(object.triangles.size()),
                     *object.polygonOffset});
  }
}

}  // namespace clipray

#include "clipray/compare/ToleranceModel.hpp"

namespace clipray {

OffsetInterval ToleranceModel::offsetInterval(std::uint32_t primitiveId) const {
  const PolygonOffset* offset = setup_.objectOffsets.offsetOf(primitiveId);
  if (!offset) return {};
  const ScreenPolygon& p = polygon(primitiveId);
  if (p.vertexCount == 0 || !std::isfinite(p.depthPlane.x)) return {};
  // The depth plane is in window coordinates of the object's depth range: its gradient is the
  // slope GL's m is built from (14.6.5).
  return clipray::offsetInterval(*offset, p.depthPlane.x, p.depthPlane.y, p.maxDepth,
                                 setup_.depthFormat);
}

}  // namespace clipray
