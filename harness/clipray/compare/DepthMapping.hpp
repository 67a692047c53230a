#pragma once
// How a primitive's NDC depth becomes the window depth the depth buffer stores: the convention's
// (0, 1) mapping, then glDepthRange(n, f) (GL 4.6 13.8.1: z_w = n + (f - n) d), then depth clamp's
// clamp to the range. A scene draws every object with its range (Scene::depthRange) unless the
// object has its own (MeshObject::depthRange: a first-person weapon in [0, 0.1] in front of a
// world in [0.1, 1]).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"

namespace clipray {

struct Scene;

// Whether the depth test keeps the greater window depth (GL_GREATER, clear 0): reversed-Z maps the
// near plane to 1, and a reversed depth range (n > f) turns window depth around once more.
inline bool nearerIsGreater(DepthMode mode, glm::dvec2 depthRange) {
  return mode.reversed != (depthRange.x > depthRange.y);
}

// Under depth clamp, whether what lies beyond the far plane is drawn (at the far end of the depth
// range): not where that end is the clear value (1 for GL_LESS, 0 for GL_GREATER), which the
// strict depth test never passes.
inline bool clampedFarIsDrawn(DepthMode mode, glm::dvec2 depthRange) {
  const double farEnd = mode.reversed ? depthRange.x : depthRange.y;
  const double clearValue = nearerIsGreater(mode, depthRange) ? 0.0 : 1.0;
  return farEnd != clearValue;
}

// One depth range's mapping of NDC z to window depth, under a convention and depth clamp.
struct DepthMapping {
  DepthMode mode;
  glm::dvec2 range{0.0, 1.0};  // glDepthRange(n, f)
  bool clamp = false;          // GL_DEPTH_CLAMP

  bool defaultRange() const { return range == glm::dvec2(0.0, 1.0); }
  // The window depth the raster stores for NDC z (windowDepthFromNdc, then the depth range; the
  // default range maps nothing, so its bits are windowDepthFromNdc's), clamped to the range under
  // depth clamp.
  double windowDepth(double zNdc) const {
    const double mapped = mappedWindowDepth(zNdc);
    return clamp ? clampToDepthRange(mapped) : mapped;
  }
  // The depth range's mapping of NDC z before depth clamp's clamp (linear in NDC z).
  double mappedWindowDepth(double zNdc) const {
    const double d = windowDepthFromNdc(zNdc, mode.convention);
    return defaultRange() ? d : range.x + (range.y - range.x) * d;
  }
  // GL 4.6 13.8.1: with depth clamp, z_w is clamped to [min(n, f), max(n, f)].
  double clampToDepthRange(double windowDepth) const {
    return std::clamp(windowDepth, std::min(range.x, range.y), std::max(range.x, range.y));
  }
  // Whether a window depth (as mapped, before the clamp) lies in front of the near plane: on the
  // near end's side of the range (the nearer side is the greater one for a reversed mapping).
  bool inFrontOfNear(double unclampedWindowDepth) const {
    return nearerIsGreater(mode, range) ? unclampedWindowDepth > nearWindowDepth()
                                        : unclampedWindowDepth < nearWindowDepth();
  }
  // The window depth of the near plane: n, or f for reversed-Z (whose near plane has d = 1).
  double nearWindowDepth() const { return mode.reversed ? range.y : range.x; }
  // Its inverse.
  double ndcOfWindowDepth(double windowDepth) const {
    const double d = defaultRange() ? windowDepth : (windowDepth - range.x) / (range.y - range.x);
    return ndcFromWindowDepth(d, mode.convention);
  }
  // d(window depth) / d(NDC z): 1 / (1 - z_n) scaled by |f - n|.
  double windowFromNdcScale() const {
    const double scale = 1.0 / (1.0 - mode.clipVolumeMinZ());
    return defaultRange() ? scale : scale * std::abs(range.y - range.x);
  }
};

// The depth ranges of the objects drawn with their own (MeshObject::depthRange), by primitive id:
// each such object's triangles are one run of ids (PrimitiveIdTable). Every other primitive is
// drawn with the scene's range.
class PrimitiveDepthRanges {
 public:
  PrimitiveDepthRanges() = default;
  // The objects whose range differs from the scene's.
  explicit PrimitiveDepthRanges(const Scene& scene);
  bool empty() const { return runs_.empty(); }
  // The range of the primitive with that id: its object's own, else sceneRange.
  glm::dvec2 rangeOf(std::uint32_t primitiveId, glm::dvec2 sceneRange) const {
    if (runs_.empty()) return sceneRange;
    const auto run =
        std::upper_bound(runs_.begin(), runs_.end(), primitiveId,
                         [](std::uint32_t id, const Run& r) { return id < r.firstId; });
    if (run == runs_.begin()) return sceneRange;
    const Run& r = *(run - 1);
    return primitiveId < r.endId ? r.range : sceneRange;
  }
  bool operator==(const PrimitiveDepthRanges&) const = default;

 private:
  struct Run {
    std::uint32_t firstId, endId;  // ids [firstId, endId)
    glm::dvec2 range;
    bool operator==(const Run&) const = default;
  };
  std::vector<Run> runs_;  // in id order
};

}  // namespace clipray
