// The screen polygon of a triangle for the tolerance model: the triangle clipped to the view
// volume in double, its window-space vertices, depth plane, vertex-transform error bound and
// coverage epsilon, and the distance and inside queries on it.

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "clipray/compare/ToleranceModel.hpp"
#include "clipray/compare/ToleranceTerms.hpp"
#include "clipray/math/Projections.hpp"

namespace clipray {

namespace {

using detail::kDoubleUnitRoundoff;
using detail::kFloatUnitRoundoff;
using detail::kInf;

// Sutherland-Hodgman against one homogeneous clip plane: inside where dot(plane, c) >= 0.
int clipPolygon(const glm::dvec4* in, int count, const glm::dvec4& plane, glm::dvec4* out) {
  int written = 0;
  for (int k = 0; k < count; ++k) {
    const glm::dvec4& a = in[k];
    const glm::dvec4& b = in[k + 1 == count ? 0 : k + 1];
    const double da = glm::dot(plane, a);
    const double db = glm::dot(plane, b);
    if (da >= 0.0) out[written++] = a;
    if ((da >= 0.0) != (db >= 0.0)) out[written++] = a + (b - a) * (da / (da - db));
  }
  return written;
}

double pointSegmentDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 ab = b - a;
  const double lengthSquared = glm::dot(ab, ab);
  const double s =
      lengthSquared > 0.0 ? std::clamp(glm::dot(p - a, ab) / lengthSquared, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + s * ab));
}

}  // namespace

ToleranceModel::ScreenPolygon ToleranceModel::buildPolygon(std::uint32_t primitiveId) const {
  ScreenPolygon polygon;
  if (primitiveId == 0 || primitiveId > intersector_.primitiveIdCount() ||
      intersector_.isAnalytic(primitiveId)) {
    return polygon;
  }
  const glm::dmat4& m = setup_.clipFromWorld;
  const double zn = setup_.mode.clipVolumeMinZ();
  const DepthMapping mapping = setup_.depthMappingOf(primitiveId);
  // The clip volume z_n w <= z <= w, -w <= x, y <= w as six planes (>= 0 inside).
  // Then the camera's user clip planes in clip space: dot(P, p_world) = dot(W^T P, p_clip) with W
  // = worldFromClip (gl_ClipDistance is interpolated linearly in clip space, so the cut is
  // this plane there).
  std::array<glm::dvec4, 6 + Camera::kMaxClipPlanes> planes = {glm::dvec4{0, 0, 1, -zn},
                                                               {0, 0, -1, 1},
                                                               {1, 0, 0, 1},
                                                               {-1, 0, 0, 1},
                                                               {0, 1, 0, 1},
                                                               {0, -1, 0, 1}};
  std::size_t planeCount = 6;
  // Depth clamp turns the near and far planes off (GL 4.6 13.7); -w <= x, y <= w still clip
  // everything behind the eye. What lies beyond the far plane then still fails the depth test
  // where the far end is the clear value: the far plane stays (z = w, or z = z_n w for
  // reversed-Z, whose far plane has window depth 0), moved first.
  std::size_t firstPlane = 0;
  if (setup_.depthClamp.enabled) {
    firstPlane = 2;
    if (!setup_.depthClamp.beyondFar) {
      firstPlane = 1;
      planes[1] = planes[setup_.mode.reversed ? 0 : 1];
    }
  }
  const glm::dmat4 clipToWorldTransposed = glm::transpose(rays_.worldFromClip());
  for (const std::span<const glm::dvec4> userPlanes :
       {std::span<const glm::dvec4>(setup_.clipPlanes), setup_.objectClipPlanes.of(primitiveId)}) {
    for (const glm::dvec4& plane : userPlanes) {
      if (planeCount < planes.size()) planes[planeCount++] = clipToWorldTransposed * plane;
    }
  }
  const double u = kFloatUnitRoundoff;
  const double subpixel = std::ldexp(1.0, -setup_.subpixelBits);
  const std::array<glm::dvec3, 3> world = intersector_.worldTriangle(primitiveId);

  // Float error of the vertex transform, bounded per clip row r by k u max_v sum_i |M_ri p_i|:
  // World/CameraRelative: matrix and position each rounded to float (2u) plus a 4-term float
  // dot product (gamma_4 ~ 4u): k = 6. Pretransformed: clip coordinates rounded once: k = 1.
  glm::dvec4 bound(0.0);
  glm::dvec3 largestPosition(0.0);  // max over the vertices of |p_i|, per axis
  for (const glm::dvec3& v : world) {
    largestPosition = glm::max(largestPosition, glm::abs(v));
    for (int r = 0; r < 4; ++r) {
      double magnitude = 0.0;
      if (setup_.vertexMode == VertexMode::Pretransformed) {
        magnitude = std::abs(glm::dot(matrixRow(m, r), glm::dvec4(v, 1.0)));
      } else {
        const glm::dmat4& gpuMatrix =
            setup_.vertexMode == VertexMode::World ? m : cameraRelativeMatrix_;
        const glm::dvec3 gpuPosition =
            setup_.vertexMode == VertexMode::World ? v : v - setup_.vertexReference;
        const glm::dvec4 row = matrixRow(gpuMatrix, r);
        magnitude = std::abs(row.x * gpuPosition.x) + std::abs(row.y * gpuPosition.y) +
                    std::abs(row.z * gpuPosition.z) + std::abs(row.w);
      }
      bound[r] = std::max(bound[r], magnitude);
    }
  }
  // The ray side's clip coordinates are those of a double hit point p = o + t d, not exact: the
  // origin unprojected from the near plane (a 4x4 product and a divide), t from the watertight
  // test, o + t d and clipFromWorld * p each round relative to |o_i| + t |d_i|, within 16 u_d of it
  // per axis. Beside the float terms that is nothing, except where a clip row cancels between
  // large coordinates: a surface lying in an oblique near plane (z ~ 0 while |p| is not, and
  // float depths near 0 are finer than the double hit).
  const glm::dvec3 rayScale = rayOriginScale_ + 2.0 * largestPosition;
  glm::dvec4 rayBound;
  for (int r = 0; r < 4; ++r) {
    const glm::dvec4 row = glm::abs(matrixRow(m, r));
    rayBound[r] = glm::dot(glm::dvec3(row), rayScale) + row.w;
  }
  polygon.clipErrorBound =
      bound * (setup_.vertexMode == VertexMode::Pretransformed ? 1.0 : 6.0) * u +
      rayBound * (16.0 * kDoubleUnitRoundoff);
  const glm::dvec4& error = polygon.clipErrorBound;

  // A convex polygon gains at most one vertex per plane: 3 + 6 + 8. A polygon of more than
  // kMaxPolygonVertices (a triangle cut by more than six of the planes) keeps its first ones.
  glm::dvec4 bufferA[3 + planes.size()], bufferB[3 + planes.size()];
  int count = 3;
  for (int k = 0; k < 3; ++k) bufferA[k] = m * glm::dvec4(world[k], 1.0);
  glm::dvec4* current = bufferA;
  glm::dvec4* next = bufferB;
  // Most triangles of a frame lie inside the clip volume, and clipping leaves those as they are
  // (the same test clipPolygon makes): skip the six passes for them.
  bool inside = true;
  for (std::size_t p = firstPlane; p < planeCount; ++p) {
    for (int k = 0; k < 3; ++k) inside &= glm::dot(planes[p], bufferA[k]) >= 0.0;
  }
  for (std::size_t p = firstPlane; p < planeCount; ++p) {
    if (inside) break;
    count = clipPolygon(current, count, planes[p], next);
    std::swap(current, next);
    if (count == 0) break;
  }
  polygon.vertexCount = std::min(count, kMaxPolygonVertices);
  double xyError = 0.0;
  for (int k = 0; k < polygon.vertexCount; ++k) {
    const glm::dvec4 c = current[k];
    const double w = c.w;
    polygon.vertices[k] = {(c.x / w + 1.0) * 0.5 * viewport_.width,
                           (c.y / w + 1.0) * 0.5 * viewport_.height,
                           mapping.mappedWindowDepth(c.z / w)};
    polygon.maxDepth = std::max(polygon.maxDepth, std::abs(polygon.vertices[k].z));
    // Vertex xy error in pixels: (dx + |x_ndc| dw) / w, scaled to the viewport.
    const double ex = (error.x + std::abs(c.x / w) * error.w) / w * 0.5 * viewport_.width;
    const double ey = (error.y + std::abs(c.y / w) * error.w) / w * 0.5 * viewport_.height;
    xyError = std::max({xyError, ex, ey});
  }
  // Snapping to the subpixel grid moves each edge by at most one subpixel step; the float
  // vertex transform moves it by the xy error (either endpoint, any direction).
  polygon.edgeEpsilon = subpixel + std::sqrt(2.0) * xyError;

  // Window depth is affine in window xy over a planar triangle: fit it from the largest-area
  // triple of polygon vertices (before depth clamp's clamp, which planeDepthAt applies).
  double bestArea = 0.0;
  for (int a = 0; a < polygon.vertexCount; ++a) {
    for (int b = a + 1; b < polygon.vertexCount; ++b) {
      for (int c = b + 1; c < polygon.vertexCount; ++c) {
        const glm::dvec3 pa = polygon.vertices[a], pb = polygon.vertices[b],
                         pc = polygon.vertices[c];
        const double area = (pb.x - pa.x) * (pc.y - pa.y) - (pc.x - pa.x) * (pb.y - pa.y);
        if (std::abs(area) <= std::abs(bestArea)) continue;
        bestArea = area;
        const double gx = ((pb.z - pa.z) * (pc.y - pa.y) - (pc.z - pa.z) * (pb.y - pa.y)) / area;
        const double gy = ((pc.z - pa.z) * (pb.x - pa.x) - (pb.z - pa.z) * (pc.x - pa.x)) / area;
        polygon.depthPlane = {gx, gy, pa.z - gx * pa.x - gy * pa.y};
      }
    }
  }
  return polygon;
}

double ToleranceModel::edgeDistancePixels(std::uint32_t primitiveId, glm::dvec2 pixel) const {
  const ScreenPolygon& polygon = this->polygon(primitiveId);
  if (polygon.vertexCount == 0) return kInf;
  double best = kInf;
  for (int k = 0; k < polygon.vertexCount; ++k) {
    const glm::dvec3& a = polygon.vertices[k];
    const glm::dvec3& b = polygon.vertices[(k + 1) % polygon.vertexCount];
    best = std::min(best, pointSegmentDistance(pixel, {a.x, a.y}, {b.x, b.y}));
  }
  return best;
}

bool ToleranceModel::insidePolygon(std::uint32_t primitiveId, glm::dvec2 pixel) const {
  const ScreenPolygon& polygon = this->polygon(primitiveId);
  if (polygon.vertexCount < 3) return false;
  bool positive = false, negative = false;
  for (int k = 0; k < polygon.vertexCount; ++k) {
    const glm::dvec3& a = polygon.vertices[k];
    const glm::dvec3& b = polygon.vertices[(k + 1) % polygon.vertexCount];
    const double side = (b.x - a.x) * (pixel.y - a.y) - (b.y - a.y) * (pixel.x - a.x);
    positive |= side > 0.0;
    negative |= side < 0.0;
  }
  return !(positive && negative);
}

double ToleranceModel::edgeEpsilonPixels(std::uint32_t primitiveId) const {
  return polygon(primitiveId).edgeEpsilon;
}

double ToleranceModel::planeDepthAt(std::uint32_t primitiveId, glm::dvec2 pixel) const {
  const glm::dvec3& plane = polygon(primitiveId).depthPlane;
  const double depth = plane.x * pixel.x + plane.y * pixel.y + plane.z;
  return setup_.depthClamp.enabled ? setup_.depthMappingOf(primitiveId).clampToDepthRange(depth)
                                   : depth;
}

bool ToleranceModel::onClipPlane(std::uint32_t primitiveId) const {
  if (primitiveId == 0 || primitiveId > intersector_.primitiveIdCount() ||
      intersector_.isAnalytic(primitiveId)) {
    return false;
  }
  const std::span<const glm::dvec4> ownPlanes = setup_.objectClipPlanes.of(primitiveId);
  if (setup_.clipPlanes.empty() && ownPlanes.empty()) return false;
  const std::array<glm::dvec3, 3> world = intersector_.worldTriangle(primitiveId);
  for (const std::span<const glm::dvec4> userPlanes :
       {std::span<const glm::dvec4>(setup_.clipPlanes), ownPlanes}) {
    for (const glm::dvec4& plane : userPlanes) {
      bool inPlane = true;
      for (const glm::dvec3& p : world) {
        // gl_ClipDistance = dot(plane, (p, 1)) in float from float operands: a few roundings of
        // the terms' magnitudes, bounded generously by 16 u times their sum.
        const double magnitude = std::abs(plane.x * p.x) + std::abs(plane.y * p.y) +
                                 std::abs(plane.z * p.z) + std::abs(plane.w);
        inPlane &=
            std::abs(glm::dot(plane, glm::dvec4(p, 1.0))) <= 16.0 * kFloatUnitRoundoff * magnitude;
      }
      if (inPlane) return true;
    }
  }
  return false;
}

}  // namespace clipray
