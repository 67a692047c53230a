#pragma once
// The user clip planes of the objects drawn with planes of their own (MeshObject::clipPlanes), by
// primitive id: each such object's triangles are one run of ids (PrimitiveIdTable). GL clips a
// draw by every plane enabled for it: the camera's (Camera::clipPlanes) and the object's.
// Planes are world space, [a, b, c, d] keeping a x + b y + c z + d >= 0.

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace clipray {

struct Scene;

class PrimitiveClipPlanes {
 public:
  PrimitiveClipPlanes() = default;
  explicit PrimitiveClipPlanes(const Scene& scene);
  bool empty() const { return runs_.empty(); }
  // The object's own planes of the primitive with that id (none for most).
  std::span<const glm::dvec4> of(std::uint32_t primitiveId) const {
    const std::size_t object = objectOf(primitiveId);
    return object < runs_.size() ? std::span<const glm::dvec4>(runs_[object].planes)
                                 : std::span<const glm::dvec4>();
  }
  // The objects with planes of their own, in id order: how many, each one's planes, and which
  // one the primitive with that id belongs to (objectCount() for none).
  std::size_t objectCount() const { return runs_.size(); }
  std::span<const glm::dvec4> planesOfObject(std::size_t object) const {
    return runs_[object].planes;
  }
  std::size_t objectOf(std::uint32_t primitiveId) const {
    const auto run =
        std::upper_bound(runs_.begin(), runs_.end(), primitiveId,
                         [](std::uint32_t id, const Run& r) { return id < r.firstId; });
    if (run == runs_.begin() || primitiveId >= (run - 1)->endId) return runs_.size();
    return static_cast<std::size_t>(run - 1 - runs_.begin());
  }
  bool operator==(const PrimitiveClipPlanes&) const = default;

 private:
  struct Run {
    std::uint32_t firstId, endId;  // ids [firstId, endId)
    std::vector<glm::dvec4> planes;
    bool operator==(const Run&) const = default;
  };
  std::vector<Run> runs_;  // in id order
};

}  // namespace clipray
