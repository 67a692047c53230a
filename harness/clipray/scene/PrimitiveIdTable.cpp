// Primitive ids: the numbering both passes write and read back (Scene.hpp, PrimitiveIdTable).

#include <algorithm>
#include <cstdint>
#include <iterator>

#include "clipray/scene/Scene.hpp"
#include "clipray/util/Check.hpp"

namespace clipray {

PrimitiveIdTable::PrimitiveIdTable(const Scene& scene) {
  std::uint64_t next = 1;  // 0 is background
  firstIdOfObject.reserve(scene.objects.size());
  for (const MeshObject& object : scene.objects) {
    firstIdOfObject.push_back(static_cast<std::uint32_t>(next));
    next += object.triangles.size();
  }
  // The scene reader refuses such a scene (InputError naming /objects) before any table is made.
  CLIPRAY_CHECK(next - 1 + scene.primitives.size() <= PrimitiveIdTable::kMaxPrimitives,
                "scene has too many primitives for 32-bit primitive ids");
  firstAnalyticId = static_cast<std::uint32_t>(next);
  analyticCount = static_cast<std::uint32_t>(scene.primitives.size());
}

PrimitiveIdTable::Decoded PrimitiveIdTable::decode(std::uint32_t id) const {
  if (id == 0) return {};
  if (id >= firstAnalyticId) {
    if (id - firstAnalyticId >= analyticCount) return {};
    return {-1, 0, static_cast<int>(id - firstAnalyticId)};
  }
  // The last object whose first id is <= id (objects without triangles share the next one's id).
  const auto after = std::upper_bound(firstIdOfObject.begin(), firstIdOfObject.end(), id);
  if (after == firstIdOfObject.begin()) return {};
  const auto object = std::prev(after);
  return {static_cast<int>(object - firstIdOfObject.begin()), id - *object, -1};
}

}  // namespace clipray
