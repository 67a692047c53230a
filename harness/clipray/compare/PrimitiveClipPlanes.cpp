#include "clipray/compare/PrimitiveClipPlanes.hpp"

#include "clipray/scene/Scene.hpp"

namespace clipray {

PrimitiveClipPlanes::PrimitiveClipPlanes(const Scene& scene) {
  const PrimitiveIdTable ids(scene);
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const MeshObject& object = scene.objects[k];
    if (object.clipPlanes.empty() || object.triangles.empty()) continue;
    const std::uint32_t first = ids.firstIdOfObject[k];
    runs_.push_back(
        {first, first + static_cast<std::uint32_t>(object.triangles.size()), object.clipPlanes});
  }
}

}  // namespace clipray
