#pragma once
// Polygon offset (glPolygonOffsetClamp(factor, units, clamp) with GL_POLYGON_OFFSET_FILL), GL 4.6
// core 14.6.5: each fragment's window depth gains
//   o = m * factor + r * units, then min(o, clamp) for clamp > 0, max(o, clamp) for clamp < 0,
// m the maximum depth slope of the polygon in window coordinates, sqrt((dz/dx)^2 + (dz/dy)^2),
// which an implementation may approximate by max(|dz/dx|, |dz/dy|); r the minimum resolvable
// difference: for an n-bit fixed-point buffer a constant of at most 2 * 2^-n (and at least 2^-n,
// else two depths r apart would not stay distinct), for a float buffer 2^(e - 23) with e the
// exponent of the primitive's maximum depth. Fixed-point depths are clamped to [0, 1] after the
// offset is added. Both freedoms (which m, which r) make an interval of offsets per primitive;
// the compare accepts a measured depth anywhere in it (VK-GL-CTS glcPolygonOffsetClampTests.cpp
// and dEQP es3fPolygonOffsetTests.cpp likewise bound the offset, not a single value).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray {

// The offsets GL allows an implementation to add to one primitive's depths: [low, high].
struct OffsetInterval {
  double low = 0.0, high = 0.0;
  double middle() const { return 0.5 * (low + high); }
  double halfWidth() const { return 0.5 * (high - low); }
};

// GL 4.6 14.6.5's clamp: toward zero by at most |clamp|, on the side the clamp's sign names.
inline double clampOffset(double o, double clamp) {
  if (clamp > 0.0) return std::min(o, clamp);
  if (clamp < 0.0) return std::max(o, clamp);
  return o;
}

// The range of r for a depth format: [2^-n, 2 * 2^-n] for n-bit fixed point; for 32f, 2^(e - 23)
// with e the exponent of maxDepth (the largest |window depth| of the primitive's vertices; 0 maps
// to the smallest normal exponent).
inline glm::dvec2 resolvableDifferenceRange(DepthFormat format, double maxDepth) {
  switch (format) {
    case DepthFormat::Unorm16:
      return {std::ldexp(1.0, -16), std::ldexp(1.0, -15)};
    case DepthFormat::Unorm24:
      return {std::ldexp(1.0, -24), std::ldexp(1.0, -23)};
    case DepthFormat::Float32:
      break;
  }
  int exponent = 0;
  // frexp gives maxDepth = f 2^k with f in [0.5, 1): the IEEE exponent e is k - 1.
  std::frexp(std::max(maxDepth, 0x1p-126), &exponent);
  const double r = std::ldexp(1.0, exponent - 1 - 23);
  return {r, r};
}

// The offset interval of a primitive whose depth plane has window-space gradient (a, b) (depth
// per pixel) and whose vertices' largest |window depth| is maxDepth. relativeSlack widens the
// slope for the error of the implementation's float slope (the vertices' rounding).
inline OffsetInterval offsetInterval(const PolygonOffset& offset, double a, double b,
                                     double maxDepth, DepthFormat format,
                                     double relativeSlack = 0x1p-10) {
  const double mLow = std::max(std::abs(a), std::abs(b)) * (1.0 - relativeSlack);
  const double mHigh = std::hypot(a, b) * (1.0 + relativeSlack);
  const glm::dvec2 r = resolvableDifferenceRange(format, maxDepth);
  const double slopeLow = std::min(offset.factor * mLow, offset.factor * mHigh);
  const double slopeHigh = std::max(offset.factor * mLow, offset.factor * mHigh);
  const double unitsLow = std::min(offset.units * r.x, offset.units * r.y);
  const double unitsHigh = std::max(offset.units * r.x, offset.units * r.y);
  // The clamp is monotonic in o: it maps the interval's ends.
  return {clampOffset(slopeLow + unitsLow, offset.clamp),
          clampOffset(slopeHigh + unitsHigh, offset.clamp)};
}

// The depths a fragment whose exact window depth is `depth` may store under offsets in `o`: its
// middle and half width. A fixed-point buffer clamps the offset depth to [0, 1] (14.6.5).
struct OffsetBand {
  double middle = 0.0, halfWidth = 0.0;
};
inline OffsetBand offsetBand(OffsetInterval o, double depth, DepthFormat format) {
  double low = depth + o.low, high = depth + o.high;
  if (format != DepthFormat::Float32) {
    low = std::clamp(low, 0.0, 1.0);
    high = std::clamp(high, 0.0, 1.0);
  }
  return {0.5 * (low + high), 0.5 * (high - low)};
}

// The window-space depth gradient (dz_w/dx_w, dz_w/dy_w) of the plane through three clip-space
// vertices, valid whatever their w (a triangle crossing w = 0 has the same plane as its clipped
// polygon): the 4D normal N with N . p = 0 for the three gives z/w = -(N.x x/w + N.y y/w + N.w) /
// N.z. windowFromNdcScale is the depth range's d(z_w)/d(z_ndc); NaN where the plane is edge-on.
inline glm::dvec2 windowDepthGradient(const glm::dvec4& p, const glm::dvec4& q, const glm::dvec4& s,
                                      glm::dvec2 viewportSize, double windowFromNdcScale) {
  const auto det3 = [](glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    return glm::dot(a, glm::cross(b, c));
  };
  const double nx = det3({p.y, p.z, p.w}, {q.y, q.z, q.w}, {s.y, s.z, s.w});
  const double ny = -det3({p.x, p.z, p.w}, {q.x, q.z, q.w}, {s.x, s.z, s.w});
  const double nz = det3({p.x, p.y, p.w}, {q.x, q.y, q.w}, {s.x, s.y, s.w});
  if (nz == 0.0) return glm::dvec2(std::nan(""));
  // x_w = (x_ndc + 1) w_vp / 2: one pixel is 2 / w_vp in NDC.
  return {-nx / nz * windowFromNdcScale * 2.0 / viewportSize.x,
          -ny / nz * windowFromNdcScale * 2.0 / viewportSize.y};
}

// The polygon offsets of the objects drawn with one (MeshObject::polygonOffset), by primitive id:
// each such object's triangles are one run of ids (PrimitiveIdTable).
class PrimitiveOffsets {
 public:
  PrimitiveOffsets() = default;
  explicit PrimitiveOffsets(const Scene& scene);
  bool empty() const { return runs_.empty(); }
  // The offset of the primitive with that id (nullptr: drawn without one).
  const PolygonOffset* offsetOf(std::uint32_t primitiveId) const {
    if (runs_.empty()) return nullptr;
    const auto run =
        std::upper_bound(runs_.begin(), runs_.end(), primitiveId,
                         [](std::uint32_t id, const Run& r) { return id < r.firstId; });
    if (run == runs_.begin()) return nullptr;
    const Run& r = *(run - 1);
    return primitiveId < r.endId ? &r.offset : nullptr;
  }
  bool operator==(const PrimitiveOffsets&) const = default;

 private:
  struct Run {
    std::uint32_t firstId, endId;  // ids [firstId, endId)
    PolygonOffset offset;
    bool operator==(const Run&) const = default;
  };
  std::vector<Run> runs_;  // in id order
};

}  // namespace clipray
