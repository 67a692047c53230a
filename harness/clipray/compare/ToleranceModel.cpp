// The tolerance model's construction (screen polygons built up front across threads, or on demand
// into a per-thread cache), the triangle depth tolerance, and the queries that pick the triangle
// or the analytic model by the primitive's kind.

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <memory>

#include "clipray/compare/ToleranceModel.hpp"
#include "clipray/compare/ToleranceTerms.hpp"
#include "clipray/math/Projections.hpp"

namespace clipray {

using detail::kFloatUnitRoundoff;
using detail::kNaN;
using detail::quantumAt;
using detail::triangleDepthTolerance;

std::atomic<std::uint64_t> ToleranceModel::nextSerial{1};

ToleranceModel::ToleranceModel(const SceneIntersector& intersector, const RasterSetup& setup,
                               Viewport viewport)
    : ToleranceModel(intersector, setup, viewport, std::span<const std::uint32_t>()) {
  std::vector<std::uint32_t> everyTriangle;
  everyTriangle.reserve(intersector.triangleCount());
  for (std::uint32_t id = 1; id <= intersector.primitiveIdCount(); ++id) {
    if (!intersector.isAnalytic(id)) everyTriangle.push_back(id);
  }
  buildPolygons(everyTriangle, 0);
}

ToleranceModel::ToleranceModel(const SceneIntersector& intersector, const RasterSetup& setup,
                               Viewport viewport, std::span<const std::uint32_t> primitiveIds,
                               unsigned threadCount)
    : setup_(setup),
      viewport_(viewport),
      intersector_(intersector),
      rays_(setup.clipFromWorld, setup.mode, setup.clipPlanes, setup.depthClamp),
      cameraRelativeMatrix_(setup.clipFromWorld *
                            glm::dmat4(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 1, 0, 0),
                                       glm::dvec4(0, 0, 1, 0),
                                       glm::dvec4(setup.vertexReference, 1.0))),
      slotOfId_(std::size_t{intersector.primitiveIdCount()} + 1, kNoSlot),
      serial_(nextSerial.fetch_add(1, std::memory_order_relaxed)),
      windowFromNdcScale_(setup.windowFromNdcScale()),
      subpixelStep_(std::ldexp(1.0, -setup.subpixelBits)) {
  // A robust ray starts on the near plane (RobustRays.hpp), or with depth clamp at the eye, which
  // the same bound covers (|o_i| + t |d_i| <= 2 |eye_i| + |p_i|). Perspective: the origin o lies
  // between the eye and the hit p on the line of sight, so |o_i| <= |eye_i| + |p_i - eye_i| and t
  // |d_i| = |p_i - o_i| <= |p_i - eye_i|: |o_i| + t |d_i| <= 3 |eye_i| + 2 |p_i|. Parallel: o lies
  // in the near plane's quad (pixel centres within [-1, 1]), whose corners bound |o_i|, and t |d_i|
  // <= |p_i| + |o_i|: |o_i| + t |d_i| <= 2 max |corner_i| + |p_i|.
  const glm::dmat4& worldFromClip = rays_.worldFromClip();
  if (rays_.isParallel()) {
    for (const double x : {-1.0, 1.0}) {
      for (const double y : {-1.0, 1.0}) {
        const glm::dvec4 corner =
            worldFromClip * glm::dvec4(x, y, setup.mode.clipVolumeMinZ(), 1.0);
        rayOriginScale_ = glm::max(rayOriginScale_, 2.0 * glm::abs(glm::dvec3(corner) / corner.w));
      }
    }
    // Depth clamp moves the origin parallelReach further back along the unit direction.
    if (setup.depthClamp.enabled) rayOriginScale_ += 2.0 * setup.depthClamp.parallelReach;
  } else {
    const glm::dvec4 eye = worldFromClip * glm::dvec4(0.0, 0.0, 1.0, 0.0);
    rayOriginScale_ = 3.0 * glm::abs(glm::dvec3(eye) / eye.w);
  }
  const std::uint32_t firstAnalytic = static_cast<std::uint32_t>(intersector.triangleCount()) + 1;
  for (std::size_t p = 0; p < intersector.analyticCount(); ++p) {
    const AnalyticPrimitive& primitive =
        intersector.analyticPrimitive(firstAnalytic + static_cast<std::uint32_t>(p));
    const glm::dmat4 clipFromLocal = setup.clipFromWorld * primitive.worldFromLocal;
    analyticTransforms_.push_back({clipFromLocal, glm::abs(matrixRow(clipFromLocal, 2)),
                                   glm::abs(matrixRow(clipFromLocal, 3))});
  }
  buildPolygons(primitiveIds, threadCount);
}

void ToleranceModel::buildPolygons(std::span<const std::uint32_t> primitiveIds,
                                   unsigned threadCount) {
  std::vector<std::uint32_t> wanted;
  wanted.reserve(primitiveIds.size());
  for (const std::uint32_t id : primitiveIds) {
    if (id < slotOfId_.size() && slotOfId_[id] == kNoSlot && !intersector_.isAnalytic(id) &&
        id != 0) {
      slotOfId_[id] = static_cast<std::uint32_t>(polygons_.size() + wanted.size());
      wanted.push_back(id);
    }
  }
  const std::size_t first = polygons_.size();
  if (first == 0) {
    polygons_.reserve(wanted.size());
    pixelTerms_.reserve(wanted.size());
    if (setup_.logDepth) logDepthTerms_.reserve(wanted.size());
  }
  // Left unwritten: every one is built below.
  polygons_.resize(first + wanted.size());
  pixelTerms_.resize(first + wanted.size());
  if (setup_.logDepth) logDepthTerms_.resize(first + wanted.size());
  constexpr int kIdsPerChunk = 256;
  const int chunks = static_cast<int>((wanted.size() + kIdsPerChunk - 1) / kIdsPerChunk);
  parallelForRows(chunks, threadCount, [&](int chunkBegin, int chunkEnd) {
    const std::size_t end = std::min(wanted.size(), std::size_t(chunkEnd) * kIdsPerChunk);
    for (std::size_t k = std::size_t(chunkBegin) * kIdsPerChunk; k < end; ++k) {
      polygons_[first + k] = buildPolygon(wanted[k]);
      pixelTerms_[first + k] = pixelTermsOf(polygons_[first + k]);
      if (setup_.logDepth) logDepthTerms_[first + k] = logDepthTermsOf(wanted[k]);
    }
  });
}

const ToleranceModel::ScreenPolygon& ToleranceModel::polygon(std::uint32_t primitiveId) const {
  const std::uint32_t slot = primitiveId < slotOfId_.size() ? slotOfId_[primitiveId] : kNoSlot;
  if (slot != kNoSlot) return polygons_[slot];
  // No triangle's (0, analytic, or past the scene): buildPolygon's empty polygon.
  if (primitiveId == 0 || primitiveId >= slotOfId_.size() || intersector_.isAnalytic(primitiveId)) {
    static const ScreenPolygon empty{};
    return empty;
  }
  // A triangle not built up front (one only the rays show, when the model was built from the
  // raster's ids): from this thread's cache of the polygons it built for this model, else built
  // into it. A frame whose rays show many ids the raster does not (a raster that draws nothing)
  // then builds each about once per thread: 1024 entries keep a 1080p row's ids until the next
  // row asks again. The entries are left unwritten until used (a thread is new for each frame's
  // workers: zeroing 300 KB each time would cost more than the polygons it meets). Each query
  // uses one polygon and is done with it before the next.
  struct Cache {
    std::uint64_t model = 0;  // the serial of the model the entries are for
    std::array<std::uint32_t, 1024> ids;
    FrameVector<ScreenPolygon> polygons;
  };
  thread_local std::unique_ptr<Cache> cache;
  if (!cache) {
    cache = std::make_unique<Cache>();
    cache->polygons.resize(cache->ids.size());  // unwritten (FrameBufferAllocator)
  }
  if (cache->model != serial_) {
    cache->model = serial_;
    cache->ids.fill(0);  // no entry: 0 is no triangle's id
  }
  const std::size_t entry = primitiveId % cache->ids.size();
  if (cache->ids[entry] != primitiveId) {
    cache->polygons[entry] = buildPolygon(primitiveId);
    cache->ids[entry] = primitiveId;
  }
  return cache->polygons[entry];
}

ToleranceModel::PixelTerms ToleranceModel::pixelTerms(std::uint32_t primitiveId) const {
  const std::uint32_t slot = primitiveId < slotOfId_.size() ? slotOfId_[primitiveId] : kNoSlot;
  return slot != kNoSlot ? pixelTerms_[slot] : pixelTermsOf(polygon(primitiveId));
}

ToleranceModel::PixelTerms ToleranceModel::pixelTermsOf(const ScreenPolygon& polygon) {
  return {polygon.clipErrorBound,
          // |gradient| of the depth plane (the snap term of triangleDepthTolerance).
          std::isfinite(polygon.depthPlane.x)
              ? std::abs(polygon.depthPlane.x) + std::abs(polygon.depthPlane.y)
              : 0.0,
          // Plane evaluation in float (setup of dz/dx, dz/dy and the sum): ~8u of the largest
          // depth the plane takes over the clipped triangle.
          8.0 * kFloatUnitRoundoff * polygon.maxDepth};
}

double ToleranceModel::surfaceToleranceAt(std::uint32_t primitiveId, glm::dvec2 pixel) const {
  if (intersector_.isAnalytic(primitiveId)) {
    const Ray ray = rays_.generate(
        {2.0 * pixel.x / viewport_.width - 1.0, 2.0 * pixel.y / viewport_.height - 1.0});
    const Hit hit = intersector_.intersectOne(primitiveId, ray);
    return hit.hit() ? analyticDepthTolerance(primitiveId, ray, hit.t) : 0.0;
  }
  const glm::dvec4 pointClip(
      2.0 * pixel.x / viewport_.width - 1.0, 2.0 * pixel.y / viewport_.height - 1.0,
      setup_.depthMappingOf(primitiveId).ndcOfWindowDepth(planeDepthAt(primitiveId, pixel)), 1.0);
  const glm::dvec4 pointWorld = rays_.worldFromClip() * pointClip;
  return depthTolerance(primitiveId, glm::dvec3(pointWorld) / pointWorld.w);
}

bool ToleranceModel::edgeAmbiguous(std::uint32_t primitiveId, glm::dvec2 pixel) const {
  if (intersector_.isAnalytic(primitiveId)) return analyticEdgeAmbiguous(primitiveId, pixel);
  return edgeDistancePixels(primitiveId, pixel) <= edgeEpsilonPixels(primitiveId);
}

double ToleranceModel::surfaceDepthAt(std::uint32_t primitiveId, glm::dvec2 pixel) const {
  if (!intersector_.isAnalytic(primitiveId)) return planeDepthAt(primitiveId, pixel);
  const Ray ray = rays_.generate(
      {2.0 * pixel.x / viewport_.width - 1.0, 2.0 * pixel.y / viewport_.height - 1.0});
  const Hit hit = intersector_.intersectOne(primitiveId, ray);
  if (!hit.hit()) return kNaN;
  const glm::dvec4 c = setup_.clipFromWorld * glm::dvec4(ray.origin + hit.t * ray.direction, 1.0);
  return setup_.depthMappingOf(primitiveId).windowDepth(c.z / c.w);
}

double ToleranceModel::depthTolerance(std::uint32_t primitiveId, const glm::dvec3& hitWorld) const {
  return depthToleranceAtClip(primitiveId, setup_.clipFromWorld * glm::dvec4(hitWorld, 1.0));
}

double ToleranceModel::depthToleranceAtClip(std::uint32_t primitiveId,
                                            const glm::dvec4& hitClip) const {
  const double zNdc = hitClip.z / hitClip.w;
  const DepthMapping mapping = setup_.depthMappingOf(primitiveId);
  const double depth = mapping.windowDepth(zNdc);
  return triangleDepthTolerance(
      pixelTerms(primitiveId), hitClip, zNdc, depth, quantumAt(setup_.depthFormat, depth),
      setup_.oneDepthRange() ? windowFromNdcScale_ : mapping.windowFromNdcScale(), subpixelStep_,
      viewport_);
}

}  // namespace clipray
