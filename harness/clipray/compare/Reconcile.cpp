#include "clipray/compare/Reconcile.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#define CLIPRAY_COMPARE_AVX2 1
#include <immintrin.h>
#else
#define CLIPRAY_COMPARE_AVX2 0
#endif

#if defined(__linux__)
#endif

#include "clipray/math/Projections.hpp"
#include "clipray/rays/FourRays.hpp"

namespace clipray {

namespace {

constexpr double kFloatUnitRoundoff = 0x1p-24;  // u for IEEE single precision
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

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

// a / b and c / d. With SSE2 as one two-lane division (the divider's throughput bounds the
// per-pixel loops): each lane is the correctly rounded IEEE quotient, the scalar division's.
inline std::pair<double, double> divideTwo(double a, double b, double c, double d) {
#if defined(__SSE2__)
  const __m128d quotients = _mm_div_pd(_mm_set_pd(c, a), _mm_set_pd(d, b));
  return {_mm_cvtsd_f64(quotients), _mm_cvtsd_f64(_mm_unpackhi_pd(quotients, quotients))};
#else
  return {a / b, c / d};
#endif
}

// depthQuantum (Conventions.cpp), exactly, without a library call per pixel for Float32:
// nextafter(d, +inf) of a finite non-negative float d is the float whose bit pattern is one more
// (across binades too, at 0 the smallest subnormal, at FLT_MAX +inf as nextafter gives). Infinite
// and NaN depths, and the unorm formats (one quantum at every depth), take depthQuantum itself.
inline double quantumAt(DepthFormat format, double windowDepth) {
  const float d = static_cast<float>(std::fabs(windowDepth));
  const auto bits = std::bit_cast<std::uint32_t>(d);
  if (format != DepthFormat::Float32 || bits >= 0x7f800000u) {
    return depthQuantum(format, windowDepth);
  }
  const float next = std::bit_cast<float>(bits + 1u);
  return std::max(static_cast<double>(next - d),
                  static_cast<double>(std::numeric_limits<float>::min()));
}

double pointSegmentDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 ab = b - a;
  const double lengthSquared = glm::dot(ab, ab);
  const double s =
      lengthSquared > 0.0 ? std::clamp(glm::dot(p - a, ab) / lengthSquared, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + s * ab));
}

Distribution distributionOf(std::vector<double>& values) {
  Distribution result;
  if (values.empty()) return result;
  auto at = [&](double fraction) {
    const std::size_t index =
        std::min(values.size() - 1,
                 static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1) + 0.5));
    std::nth_element(values.begin(), values.begin() + index, values.end());
    return values[index];
  };
  result.p50 = at(0.5);
  result.p99 = at(0.99);
  result.max = *std::max_element(values.begin(), values.end());
  return result;
}

}  // namespace

const char* pixelClassName(PixelClass value) {
  switch (value) {
    case PixelClass::Background:
      return "background";
    case PixelClass::Agree:
      return "agree";
    case PixelClass::DepthBeyondTolerance:
      return "depth_beyond_tolerance";
    case PixelClass::CoverageEdgeAmbiguous:
      return "coverage_edge_ambiguous";
    case PixelClass::CoverageUnexplained:
      return "coverage_unexplained";
    case PixelClass::IdDepthAmbiguous:
      return "id_depth_ambiguous";
    case PixelClass::IdEdgeAmbiguous:
      return "id_edge_ambiguous";
    case PixelClass::IdUnexplained:
      return "id_unexplained";
  }
  return "?";
}

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
      rays_(setup.clipFromWorld, setup.mode),
      cameraRelativeMatrix_(setup.clipFromWorld *
                            glm::dmat4(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 1, 0, 0),
                                       glm::dvec4(0, 0, 1, 0),
                                       glm::dvec4(setup.vertexReference, 1.0))),
      slotOfId_(std::size_t{intersector.primitiveIdCount()} + 1, kNoSlot),
      serial_(nextSerial.fetch_add(1, std::memory_order_relaxed)),
      windowFromNdcScale_(1.0 / (1.0 - setup.mode.clipVolumeMinZ())),
      subpixelStep_(std::ldexp(1.0, -setup.subpixelBits)) {
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
  }
  // Left unwritten: every one is built below.
  polygons_.resize(first + wanted.size());
  pixelTerms_.resize(first + wanted.size());
  constexpr int kIdsPerChunk = 256;
  const int chunks = static_cast<int>((wanted.size() + kIdsPerChunk - 1) / kIdsPerChunk);
  parallelForRows(chunks, threadCount, [&](int chunkBegin, int chunkEnd) {
    const std::size_t end = std::min(wanted.size(), std::size_t(chunkEnd) * kIdsPerChunk);
    for (std::size_t k = std::size_t(chunkBegin) * kIdsPerChunk; k < end; ++k) {
      polygons_[first + k] = buildPolygon(wanted[k]);
      pixelTerms_[first + k] = pixelTermsOf(polygons_[first + k]);
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

ToleranceModel::ScreenPolygon ToleranceModel::buildPolygon(std::uint32_t primitiveId) const {
  ScreenPolygon polygon;
  if (primitiveId == 0 || primitiveId > intersector_.primitiveIdCount() ||
      intersector_.isAnalytic(primitiveId)) {
    return polygon;
  }
  const glm::dmat4& m = setup_.clipFromWorld;
  const double zn = setup_.mode.clipVolumeMinZ();
  // The clip volume z_n w <= z <= w, -w <= x, y <= w as six planes (>= 0 inside).
  const glm::dvec4 planes[6] = {{0, 0, 1, -zn}, {0, 0, -1, 1}, {1, 0, 0, 1},
                                {-1, 0, 0, 1},  {0, 1, 0, 1},  {0, -1, 0, 1}};
  const double u = kFloatUnitRoundoff;
  const double subpixel = std::ldexp(1.0, -setup_.subpixelBits);
  const std::array<glm::dvec3, 3> world = intersector_.worldTriangle(primitiveId);

  // Float error of the vertex transform, bounded per clip row r by k u max_v sum_i |M_ri p_i|:
  // World/CameraRelative: matrix and position each rounded to float (2u) plus a 4-term float
  // dot product (gamma_4 ~ 4u): k = 6. Pretransformed: clip coordinates rounded once: k = 1.
  glm::dvec4 bound(0.0);
  for (const glm::dvec3& v : world) {
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
  polygon.clipErrorBound =
      bound * (setup_.vertexMode == VertexMode::Pretransformed ? 1.0 : 6.0) * u;
  const glm::dvec4& error = polygon.clipErrorBound;

  glm::dvec4 bufferA[kMaxPolygonVertices + 3], bufferB[kMaxPolygonVertices + 3];
  int count = 3;
  for (int k = 0; k < 3; ++k) bufferA[k] = m * glm::dvec4(world[k], 1.0);
  glm::dvec4* current = bufferA;
  glm::dvec4* next = bufferB;
  // Most triangles of a frame lie inside the clip volume, and clipping leaves those as they are
  // (the same test clipPolygon makes): skip the six passes for them.
  bool inside = true;
  for (const glm::dvec4& plane : planes) {
    for (int k = 0; k < 3; ++k) inside &= glm::dot(plane, bufferA[k]) >= 0.0;
  }
  for (const glm::dvec4& plane : planes) {
    if (inside) break;
    count = clipPolygon(current, count, plane, next);
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
                           windowDepthFromNdc(c.z / w, setup_.mode.convention)};
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
  // triple of polygon vertices.
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

namespace {

// Outward normal of the canonical shape at a local point on it (unnormalized; see Scene.hpp).
glm::dvec3 localNormal(PrimitiveKind kind, const glm::dvec3& p) {
  if (kind == PrimitiveKind::Sphere) return p;
  if (kind == PrimitiveKind::Box) {
    const glm::dvec3 a = glm::abs(p);
    const int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    glm::dvec3 n(0.0);
    n[axis] = p[axis] >= 0.0 ? 1.0 : -1.0;
    return n;
  }
  return {0.0, 0.0, 1.0};
}

// Hit state of a ray on one primitive: 0 miss, +1 entering the surface, -1 leaving it (the ray
// starts inside a sphere or box, so the far side is what both sides draw).
int analyticHitState(const SceneIntersector& intersector, std::uint32_t id, const Ray& ray) {
  const Hit hit = intersector.intersectOne(id, ray);
  if (!hit.hit()) return 0;
  const AnalyticPrimitive& primitive = intersector.analyticPrimitive(id);
  const glm::dvec3 origin(primitive.localFromWorld * glm::dvec4(ray.origin, 1.0));
  const glm::dvec3 direction(glm::dmat3(primitive.localFromWorld) * ray.direction);
  const glm::dvec3 p = origin + hit.t * direction;
  const double facing = glm::dot(localNormal(primitive.kind, p), direction);
  if (primitive.kind == PrimitiveKind::Sphere || primitive.kind == PrimitiveKind::Box) {
    return facing <= 0.0 ? 1 : -1;
  }
  return 1;  // flat shapes are seen from either side
}

}  // namespace

double ToleranceModel::analyticDepthTolerance(std::uint32_t primitiveId, const Ray& ray,
                                              double t) const {
  const AnalyticPrimitive& primitive = intersector_.analyticPrimitive(primitiveId);
  const double u = kFloatUnitRoundoff;
  const glm::dmat4& m = setup_.clipFromWorld;
  const glm::dvec3 hitWorld = ray.origin + t * ray.direction;
  const glm::dvec4 c = m * glm::dvec4(hitWorld, 1.0);
  const double zNdc = c.z / c.w;
  const double depth = windowDepthFromNdc(zNdc, setup_.mode.convention);
  const double toWindow = 1.0 / (1.0 - setup_.mode.clipVolumeMinZ());

  // The shader works in the local frame with clipFromLocal rounded to float.
  const AnalyticTransform& transform =
      analyticTransforms_[primitiveId - 1 - intersector_.triangleCount()];
  const glm::dvec3 origin(primitive.localFromWorld * glm::dvec4(ray.origin, 1.0));
  const glm::dvec3 direction(glm::dmat3(primitive.localFromWorld) * ray.direction);
  const glm::dvec3 p = origin + t * direction;

  // 1. Storage: one quantum of the depth format.
  const double storage = quantumAt(setup_.depthFormat, depth);
  // 2. Depth of the hit evaluated in float: z and w are 4-term dot products of float rows with
  //    the float point (6u sum |M_ri p_i|, as for a vertex), then the divide and the mapping (2u).
  double magnitudeZ = 0.0, magnitudeW = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double coordinate = i < 3 ? std::abs(p[i]) : 1.0;
    magnitudeZ += transform.magnitudeRowZ[i] * coordinate;
    magnitudeW += transform.magnitudeRowW[i] * coordinate;
  }
  const double evaluation =
      6.0 * u * (magnitudeZ + std::abs(zNdc) * magnitudeW) / std::abs(c.w) * toWindow +
      2.0 * u * std::abs(depth);
  // 3. Where the float ray meets the surface. The ray (plane crosses, a 3-plane solve) and the
  //    intersection are a few dozen float operations on quantities of size |o| + t|d|: the local
  //    hit point moves by delta = 32 u (|o| + t |d|) across the ray, hence by delta / cos(theta)
  //    along it (theta between ray and normal). Near a tangent the error grows like sqrt(delta)
  //    instead (the shapes have unit size locally), so cos is floored at sqrt(delta).
  const double delta = 32.0 * u * (glm::length(origin) + t * glm::length(direction));
  const glm::dvec3 normal = localNormal(primitive.kind, p);
  const double cosine = std::abs(glm::dot(glm::normalize(normal), glm::normalize(direction)));
  const double alongRay = delta / (glm::length(direction) * std::max(cosine, std::sqrt(delta)));
  // d(window depth)/dt along the world ray: (z' w - z w') / w^2.
  const double zRate = glm::dot(glm::dvec3(matrixRow(m, 2)), ray.direction);
  const double wRate = glm::dot(glm::dvec3(matrixRow(m, 3)), ray.direction);
  const double depthRate = std::abs(zRate * c.w - c.z * wRate) / (c.w * c.w) * toWindow;
  return storage + evaluation + depthRate * alongRay;
}

bool ToleranceModel::analyticEdgeAmbiguous(std::uint32_t primitiveId, glm::dvec2 pixel) const {
  const auto rayAt = [&](glm::dvec2 position) {
    return rays_.generate(
        {2.0 * position.x / viewport_.width - 1.0, 2.0 * position.y / viewport_.height - 1.0});
  };
  const int centre = analyticHitState(intersector_, primitiveId, rayAt(pixel));
  const double e = kAnalyticEdgeEpsilonPixels;
  for (const glm::dvec2 offset :
       {glm::dvec2(e, 0), glm::dvec2(-e, 0), glm::dvec2(0, e), glm::dvec2(0, -e)}) {
    if (analyticHitState(intersector_, primitiveId, rayAt(pixel + offset)) != centre) return true;
  }
  return false;
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
      ndcFromWindowDepth(planeDepthAt(primitiveId, pixel), setup_.mode.convention), 1.0);
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
  return windowDepthFromNdc(c.z / c.w, setup_.mode.convention);
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
  return plane.x * pixel.x + plane.y * pixel.y + plane.z;
}

double ToleranceModel::depthTolerance(std::uint32_t primitiveId, const glm::dvec3& hitWorld) const {
  return depthToleranceAtClip(primitiveId, setup_.clipFromWorld * glm::dvec4(hitWorld, 1.0));
}

namespace {

// The tolerance model of a triangle hit (see depthToleranceAtClip) from its screen polygon's
// PixelTerms and the hit's clip coordinates c, with z_ndc = c.z / c.w, its window depth and the
// depth quantum there given (compareFrames has them already). Terms is
// ToleranceModel::PixelTerms.
template <class Terms>
inline double triangleDepthTolerance(const Terms& terms, const glm::dvec4& c, double zNdc,
                                     double depth, double storage, double toWindow,
                                     double subpixelStep, Viewport viewport) {
  const double u = kFloatUnitRoundoff;
  const glm::dvec4& bound = terms.clipErrorBound;
  // 1. Storage: one quantum of the depth format at this depth (given).
  // 2. Vertex transform in float, interpolated: dz_ndc = (dz + |z_ndc| dw) / w, plus the GPU's
  //    divide and depth-range mapping (2u relative).
  // 3. Vertex positions snapped to the subpixel grid and moved by the float xy error
  //    ((dx + |x_ndc| dw) / w in pixels, likewise y): the depth plane shifts by |gradient| times
  //    that displacement.
  // The quotients of 2 and 3 are taken in pairs (see divideTwo).
  const auto [xNdc, yNdc] = divideTwo(c.x, c.w, c.y, c.w);
  const double xyError = std::max((bound.x + std::abs(xNdc) * bound.w) * 0.5 * viewport.width,
                                  (bound.y + std::abs(yNdc) * bound.w) * 0.5 * viewport.height);
  const auto [vertexNdc, xyErrorPixels] =
      divideTwo(bound.z + std::abs(zNdc) * bound.w, std::abs(c.w), xyError, std::abs(c.w));
  const double vertex = vertexNdc * toWindow + 2.0 * u * std::abs(depth);
  const double xyShift = subpixelStep + xyErrorPixels;
  const double snap = terms.gradient * xyShift;
  // 4. Plane evaluation in float: terms.interpolation (see pixelTermsOf).
  return storage + vertex + snap + terms.interpolation;
}

}  // namespace

double ToleranceModel::depthToleranceAtClip(std::uint32_t primitiveId,
                                            const glm::dvec4& hitClip) const {
  const double zNdc = hitClip.z / hitClip.w;
  const double depth = windowDepthFromNdc(zNdc, setup_.mode.convention);
  return triangleDepthTolerance(pixelTerms(primitiveId), hitClip, zNdc, depth,
                                quantumAt(setup_.depthFormat, depth), windowFromNdcScale_,
                                subpixelStep_, viewport_);
}

namespace {

// The triangles and primitives the raster shows (ascending): the ids the tolerance model is
// asked about in every pixel that compares depth (there the rays show the same id). On a big
// scene far fewer than all of them. The few ids only the rays show are asked about at mismatched
// pixels alone, and built there (ToleranceModel::polygon); reading the hits here too read 40 MB
// of a 1080p frame where the raster ids are 8 MB.
std::vector<std::uint32_t> idsInRaster(const RasterFrame& raster, std::uint32_t primitiveCount,
                                       unsigned threadCount) {
  std::vector<std::uint8_t> shown(std::size_t{primitiveCount} + 1, 0);
  const Viewport viewport = raster.viewport;
  parallelForRows(viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
    // Every id marked with a store and no branch (a mesh's small triangles change the id every
    // few pixels: a branch on "same as the last" mispredicted there). Threads may mark the same
    // id: relaxed atomics make that well-defined (plain byte stores on x86). Background and
    // invalid ids mark a byte of this thread's own, not one every thread writes.
    std::uint8_t elsewhere = 0;
    const std::size_t begin = static_cast<std::size_t>(rowBegin) * viewport.width;
    const std::size_t end = static_cast<std::size_t>(rowEnd) * viewport.width;
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint32_t id = raster.ids[i];
      std::uint8_t& flag = id != 0 && id <= primitiveCount ? shown[id] : elsewhere;
      std::atomic_ref<std::uint8_t>(flag).store(1, std::memory_order_relaxed);
    }
  });
  std::vector<std::uint32_t> ids;
  for (std::uint32_t id = 1; id <= primitiveCount; ++id) {
    if (shown[id] != 0) ids.push_back(id);
  }
  return ids;
}

// The same Distribution as distributionOf over the concatenation of parts, without
// concatenating them and without sorting: for non-negative doubles (no NaN, no -0) the order of
// the values is the order of their bit patterns, so a histogram of the top 16 bits narrows each
// requested rank to one bucket, and nth_element runs on that bucket's few values only. The
// values are the ones distributionOf picks (a rank's value does not depend on how ties or the
// order of the input fall). Anything else (NaN, where nth_element's answer depends on the
// input's order) takes distributionOf itself on the concatenation.
Distribution distributionOfParts(const std::vector<const FrameVector<double>*>& parts) {
  std::size_t count = 0;
  for (const FrameVector<double>* part : parts) count += part->size();
  Distribution result;
  if (count == 0) return result;

  constexpr int kBucketShift = 48;
  constexpr std::uint64_t kPositiveInfinityBits = 0x7ff0000000000000ull;
  constexpr std::size_t kBuckets = std::size_t{1} << (64 - kBucketShift);
  // Four interleaved histograms, summed after: neighbouring pixels' values mostly share a bucket,
  // and one histogram made each increment wait for the previous one's store.
  std::vector<std::uint32_t> histograms(4 * kBuckets, 0);
  std::uint64_t maxBits = 0;
  bool ordinary = true;  // every value is +0, positive or +inf
  for (const FrameVector<double>* part : parts) {
    // Four values at a time, one to each table (unrolled: the loop's own count would otherwise
    // pick the table), then the rest into the first.
    const double* values = part->data();
    const std::size_t size = part->size();
    const auto tally = [&](std::size_t table, double value) {
      const auto bits = std::bit_cast<std::uint64_t>(value);
      ordinary &= bits <= kPositiveInfinityBits;
      maxBits = std::max(maxBits, bits);
      ++histograms[table * kBuckets + (bits >> kBucketShift)];
    };
    std::size_t i = 0;
    for (; i + 4 <= size; i += 4) {
      for (std::size_t table = 0; table < 4; ++table) tally(table, values[i + table]);
    }
    for (; i < size; ++i) tally(0, values[i]);
  }
  std::vector<std::uint32_t> histogram(kBuckets);
  for (std::size_t b = 0; b < kBuckets; ++b) {
    histogram[b] = histograms[b] + histograms[kBuckets + b] + histograms[2 * kBuckets + b] +
                   histograms[3 * kBuckets + b];
  }
  if (!ordinary || count > std::numeric_limits<std::uint32_t>::max()) {
    std::vector<double> all;
    all.reserve(count);
    for (const FrameVector<double>* part : parts) all.insert(all.end(), part->begin(), part->end());
    return distributionOf(all);
  }
  // The ranks distributionOf reads, each located in its bucket (the rank within the bucket).
  const auto locate = [&](double fraction) {
    std::size_t rank = std::min(
        count - 1, static_cast<std::size_t>(fraction * static_cast<double>(count - 1) + 0.5));
    std::size_t bucket = 0;
    while (rank >= histogram[bucket]) rank -= histogram[bucket++];
    return std::pair{bucket, rank};
  };
  const auto [bucket50, rank50] = locate(0.5);
  const auto [bucket99, rank99] = locate(0.99);
  // Both buckets' values in one pass over the parts.
  std::vector<std::uint64_t> in50, in99;
  in50.reserve(histogram[bucket50]);
  if (bucket99 != bucket50) in99.reserve(histogram[bucket99]);
  for (const FrameVector<double>* part : parts) {
    for (const double value : *part) {
      const auto bits = std::bit_cast<std::uint64_t>(value);
      const std::uint64_t bucket = bits >> kBucketShift;
      if (bucket == bucket50) {
        in50.push_back(bits);
      } else if (bucket == bucket99) {
        in99.push_back(bits);
      }
    }
  }
  const auto valueOfRank = [](std::vector<std::uint64_t>& inBucket, std::size_t rank) {
    std::nth_element(inBucket.begin(), inBucket.begin() + static_cast<std::ptrdiff_t>(rank),
                     inBucket.end());
    return std::bit_cast<double>(inBucket[rank]);
  };
  result.p50 = valueOfRank(in50, rank50);
  // Within one bucket, nth_element again on the partitioned values finds the same value.
  result.p99 = valueOfRank(bucket99 == bucket50 ? in50 : in99, rank99);
  result.max = std::bit_cast<double>(maxBits);
  return result;
}

#if CLIPRAY_COMPARE_AVX2
// The per-pixel figures of four neighbouring pixels where both sides show the same triangle, four
// lanes per instruction: the scalar loop's operations in its order (glm's mat4 * vec4 is
// (m0 x + m1 y) + (m2 z + m3 w), its dot products (x + y) + z and (x + y) + (z + w); division and
// square root are correctly rounded; std::max(a, b) is maxpd(b, a), NaN included), so the same
// bits. No FMA in this target: each multiply and add rounds as in the scalar code.
struct FourPixelsInput {
  glm::dmat4 clipFromWorld;
  glm::dvec4 rowZ, rowW;
  glm::dvec3 eye;
  bool parallel;
  double zn;             // the convention's near NDC z
  double toWindowDepth;  // 1 / (1 - zn): exact (a power of two), so (z - zn) / (1 - zn) too
  double toWindow;       // the tolerance model's 1 / (1 - clipVolumeMinZ)
  double subpixelStep;
  double width, height;  // the viewport, as doubles
};
struct FourPolygons {  // the lanes' screen polygons' fields
  double boundX[4], boundY[4], boundZ[4], boundW[4], gradient[4], interpolation[4];
};
struct FourPixels {
  double rayDepth[4], ratio[4], quanta[4], relative[4];
};

// Appends four values with one size check (the samples are reserved for the frame up front).
void appendFour(FrameVector<double>& values, const double four[4]) {
  const std::size_t size = values.size();
  values.resize(size + 4);  // left unwritten by the allocator; written here
  std::memcpy(values.data() + size, four, 4 * sizeof(double));
}

// Free functions, not lambdas: GCC 12 does not give a lambda its enclosing function's target.
__attribute__((target("avx2"))) inline __m256d broadcast(double v) {
  return _mm256_set1_pd(v);
}
__attribute__((target("avx2"))) inline __m256d absolute(__m256d v) {
  return _mm256_andnot_pd(_mm256_set1_pd(-0.0), v);
}
// glm::dot(row, (x, y, z, 1)) = (r.x x + r.y y) + (r.z z + r.w 1), and of (x, y, z) alone
// (r.x x + r.y y) + r.z z.
__attribute__((target("avx2"))) inline __m256d dotPoint(const glm::dvec4& row, __m256d x, __m256d y,
                                                        __m256d z) {
  return _mm256_add_pd(
      _mm256_add_pd(_mm256_mul_pd(broadcast(row.x), x), _mm256_mul_pd(broadcast(row.y), y)),
      _mm256_add_pd(_mm256_mul_pd(broadcast(row.z), z),
                    _mm256_mul_pd(broadcast(row.w), broadcast(1.0))));
}
__attribute__((target("avx2"))) inline __m256d dotDirection(const glm::dvec4& row, __m256d x,
                                                            __m256d y, __m256d z) {
  return _mm256_add_pd(
      _mm256_add_pd(_mm256_mul_pd(broadcast(row.x), x), _mm256_mul_pd(broadcast(row.y), y)),
      _mm256_mul_pd(broadcast(row.z), z));
}

// Returns false (and computes nothing useful) when a lane's window depth is not a finite float
// (quantumAt then asks depthQuantum): the caller takes the scalar path for those four.
__attribute__((target("avx2"))) bool fourTrianglePixels(const FourPixelsInput& in, const Ray* rays,
                                                        const Hit* hits,
                                                        const float* rasterDepthFloat,
                                                        const FourPolygons& polygons,
                                                        FourPixels& out) {
  const simd::FourRays four = simd::loadFourRays(rays);
  const __m256d ox = four.originX, oy = four.originY, oz = four.originZ;
  const __m256d dx = four.directionX, dy = four.directionY, dz = four.directionZ;
  const __m256d tMax = four.tMax;
  const __m256d t = _mm256_set_pd(hits[3].t, hits[2].t, hits[1].t, hits[0].t);
  const __m256d rasterDepth = _mm256_cvtps_pd(_mm_loadu_ps(rasterDepthFloat));

  // The hit in clip space: m * (o + t d, 1).
  const __m256d px = _mm256_add_pd(ox, _mm256_mul_pd(t, dx));
  const __m256d py = _mm256_add_pd(oy, _mm256_mul_pd(t, dy));
  const __m256d pz = _mm256_add_pd(oz, _mm256_mul_pd(t, dz));
  const glm::dmat4& m = in.clipFromWorld;
  __m256d c[4];
  for (int row = 0; row < 4; ++row) {
    c[row] =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(broadcast(m[0][row]), px),
                                    _mm256_mul_pd(broadcast(m[1][row]), py)),
                      _mm256_add_pd(_mm256_mul_pd(broadcast(m[2][row]), pz), broadcast(m[3][row])));
  }
  const __m256d zNdc = _mm256_div_pd(c[2], c[3]);
  const __m256d rayDepth =
      _mm256_mul_pd(_mm256_sub_pd(zNdc, broadcast(in.zn)), broadcast(in.toWindowDepth));
  const __m256d error = absolute(_mm256_sub_pd(rasterDepth, rayDepth));

  // quantumAt for Float32: the next float up minus the depth, at least FLT_MIN.
  const __m128 depthFloat = _mm256_cvtpd_ps(absolute(rayDepth));
  const __m128i bits = _mm_castps_si128(depthFloat);
  // Unsigned bits >= 0x7f800000 (inf, NaN; the sign bit is clear): not this path.
  if (_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpgt_epi32(bits, _mm_set1_epi32(0x7f7fffff)))) != 0) {
    return false;
  }
  const __m128 next = _mm_castsi128_ps(_mm_add_epi32(bits, _mm_set1_epi32(1)));
  const __m256d quantum =
      _mm256_max_pd(broadcast(static_cast<double>(std::numeric_limits<float>::min())),
                    _mm256_cvtps_pd(_mm_sub_ps(next, depthFloat)));

  // triangleDepthTolerance.
  const double u = kFloatUnitRoundoff;
  const __m256d boundX = _mm256_loadu_pd(polygons.boundX),
                boundY = _mm256_loadu_pd(polygons.boundY),
                boundZ = _mm256_loadu_pd(polygons.boundZ),
                boundW = _mm256_loadu_pd(polygons.boundW);
  const __m256d xNdc = _mm256_div_pd(c[0], c[3]);
  const __m256d yNdc = _mm256_div_pd(c[1], c[3]);
  const __m256d errorX = _mm256_mul_pd(
      _mm256_mul_pd(_mm256_add_pd(boundX, _mm256_mul_pd(absolute(xNdc), boundW)), broadcast(0.5)),
      broadcast(in.width));
  const __m256d errorY = _mm256_mul_pd(
      _mm256_mul_pd(_mm256_add_pd(boundY, _mm256_mul_pd(absolute(yNdc), boundW)), broadcast(0.5)),
      broadcast(in.height));
  const __m256d xyError = _mm256_max_pd(errorY, errorX);  // std::max(errorX, errorY)
  const __m256d absW = absolute(c[3]);
  const __m256d vertexNdc =
      _mm256_div_pd(_mm256_add_pd(boundZ, _mm256_mul_pd(absolute(zNdc), boundW)), absW);
  const __m256d xyErrorPixels = _mm256_div_pd(xyError, absW);
  const __m256d vertex = _mm256_add_pd(_mm256_mul_pd(vertexNdc, broadcast(in.toWindow)),
                                       _mm256_mul_pd(broadcast(2.0 * u), absolute(rayDepth)));
  const __m256d xyShift = _mm256_add_pd(broadcast(in.subpixelStep), xyErrorPixels);
  const __m256d snap = _mm256_mul_pd(_mm256_loadu_pd(polygons.gradient), xyShift);
  const __m256d tolerance = _mm256_add_pd(_mm256_add_pd(_mm256_add_pd(quantum, vertex), snap),
                                          _mm256_loadu_pd(polygons.interpolation));
  const __m256d ratio = _mm256_div_pd(error, tolerance);
  const __m256d quanta = _mm256_div_pd(error, quantum);

  // Distance along the ray to the raster depth, relative to the distance from the eye (or the view
  // volume's depth).
  const __m256d zRaster =
      _mm256_add_pd(_mm256_mul_pd(rasterDepth, broadcast(1.0 - in.zn)), broadcast(in.zn));
  const __m256d z0 = dotPoint(in.rowZ, ox, oy, oz), z1 = dotDirection(in.rowZ, dx, dy, dz);
  const __m256d w0 = dotPoint(in.rowW, ox, oy, oz), w1 = dotDirection(in.rowW, dx, dy, dz);
  const __m256d tRaster = _mm256_div_pd(_mm256_sub_pd(z0, _mm256_mul_pd(zRaster, w0)),
                                        _mm256_sub_pd(_mm256_mul_pd(zRaster, w1), z1));
  __m256d scale;
  if (in.parallel) {
    const __m256d finite = _mm256_cmp_pd(
        absolute(tMax), broadcast(std::numeric_limits<double>::infinity()), _CMP_LT_OQ);
    scale = _mm256_blendv_pd(t, tMax, finite);
  } else {
    const __m256d ex = _mm256_sub_pd(ox, broadcast(in.eye.x));
    const __m256d ey = _mm256_sub_pd(oy, broadcast(in.eye.y));
    const __m256d ez = _mm256_sub_pd(oz, broadcast(in.eye.z));
    const __m256d length = _mm256_sqrt_pd(_mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(ex, ex), _mm256_mul_pd(ey, ey)), _mm256_mul_pd(ez, ez)));
    scale = _mm256_add_pd(t, length);
  }
  const __m256d relative = _mm256_div_pd(absolute(_mm256_sub_pd(tRaster, t)), scale);
  _mm256_storeu_pd(out.rayDepth, rayDepth);
  _mm256_storeu_pd(out.ratio, ratio);
  _mm256_storeu_pd(out.quanta, quanta);
  _mm256_storeu_pd(out.relative, relative);
  return true;
}

bool cpuHasAvx2() {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}
#endif

}  // namespace

ComparisonResult compareFrames(const RasterFrame& raster, const AnalyticFrame& analytic,
                               const SceneIntersector& intersector, const RasterSetup& setup,
                               unsigned threadCount) {
  const Viewport viewport = raster.viewport;
  const std::size_t count = static_cast<std::size_t>(viewport.width) * viewport.height;
  if (analytic.viewport != viewport || raster.depth.size() != count || raster.ids.size() != count ||
      analytic.hits.size() != count) {
    throw std::invalid_argument("compareFrames: raster and analytic frames differ in size");
  }
  if (!analytic.hasRays()) {
    throw std::invalid_argument(
        "compareFrames: the analytic frame needs one ray per pixel, stored or computed (not both)");
  }
  const std::uint32_t primitiveCount = intersector.primitiveIdCount();
  // Screen polygons only for the primitives the frames show (a big scene's other triangles are
  // never asked about), clipped across the threads.
  const ToleranceModel model(intersector, setup, viewport,
                             idsInRaster(raster, primitiveCount, threadCount), threadCount);
  const glm::dmat4& m = setup.clipFromWorld;
  const glm::dmat4 worldFromClip = glm::inverse(m);
  // Figures per surface kind: 0 triangles, 1 + PrimitiveKind for analytic primitives.
  constexpr std::size_t kKinds = 1 + static_cast<std::size_t>(PrimitiveKind::Plane) + 1;
  const auto kindOf = [&](std::uint32_t id) -> std::size_t {
    return intersector.isAnalytic(id)
               ? 1 + static_cast<std::size_t>(intersector.analyticPrimitive(id).kind)
               : 0;
  };
  // The three figures of one kind, as gathered by one worker (kept apart until the end: the
  // distributions read the parts where they lie).
  struct KindSamples {
    FrameVector<double> quanta, relative, ratios;
  };
  const unsigned workerCount = parallelWorkerCount(viewport.height, threadCount);
  std::vector<std::array<KindSamples, kKinds>> samplesOfWorker(workerCount);
  const glm::dvec4 rowZ = matrixRow(m, 2), rowW = matrixRow(m, 3);
  const bool parallel = glm::dvec3(rowW) == glm::dvec3(0.0);
  const glm::dvec4 eyeHomogeneous = worldFromClip * glm::dvec4(0.0, 0.0, 1.0, 0.0);
  const glm::dvec3 eye = glm::dvec3(eyeHomogeneous) / eyeHomogeneous.w;
  const DepthConvention convention = setup.mode.convention;

  ComparisonResult result;
  PixelComparison& pixels = result.pixels;
  pixels.viewport = viewport;
  // Frame buffers (a previous run's pages where one of the same size was released), left unwritten
  // here: the per-pixel loop writes all four images at every pixel, so they are written once, on
  // the threads (a fill first wrote 35 MB of 1080p images twice).
  pixels.analyticDepth.resize(count);
  pixels.rasterDepth.resize(count);
  pixels.toleranceRatio.resize(count);
  pixels.classes.resize(count);

  std::mutex merge;
  RunMetrics& total = result.metrics;
#if CLIPRAY_COMPARE_AVX2
  // Four pixels at a time where all four show the same triangle on both sides (most pixels of a
  // mesh), with a float depth buffer (quantumAt's bit trick).
  const bool fourAtOnce = setup.depthFormat == DepthFormat::Float32 && cpuHasAvx2();
  const FourPixelsInput fourInput{m,
                                  rowZ,
                                  rowW,
                                  eye,
                                  parallel,
                                  convention == DepthConvention::ZeroToOne ? 0.0 : -1.0,
                                  convention == DepthConvention::ZeroToOne ? 1.0 : 0.5,
                                  model.windowFromNdcScale_,
                                  model.subpixelStep_,
                                  static_cast<double>(viewport.width),
                                  static_cast<double>(viewport.height)};
#endif

  parallelForRowsByWorker(
      viewport.height, threadCount, [&](unsigned worker, int rowBegin, int rowEnd) {
        RunMetrics local;
        std::array<KindSamples, kKinds>& localKinds = samplesOfWorker[worker];
        const std::size_t width = static_cast<std::size_t>(viewport.width);
        local.pixels = static_cast<std::int64_t>(width) * (rowEnd - rowBegin);
        const auto samplesOf = [&](std::size_t kindIndex) -> KindSamples& {
          KindSamples& kind = localKinds[kindIndex];
          if (kind.quanta.capacity() == 0) {
            // Room for this worker's share of the frame up front: growing would copy and
            // touch fresh pages again (reserving only maps address space).
            const std::size_t share = count / workerCount + count / 8 + 1;
            kind.quanta.reserve(share);
            kind.relative.reserve(share);
            kind.ratios.reserve(share);
          }
          return kind;
        };
#if CLIPRAY_COMPARE_AVX2
        // Pixels first .. first + 3 when each shows the same triangle on both sides (with a ray
        // and a polygon built up front): their figures as the scalar loop below computes them.
        const auto compareFour = [&](std::size_t first, const Ray* rays) {
          FourPolygons polygons;
          for (std::size_t l = 0; l < 4; ++l) {
            const std::uint32_t rasterId = raster.ids[first + l];
            const std::uint32_t rayId = analytic.hits[first + l].primitiveId;
            if (rasterId == 0 || rasterId != rayId || rasterId > primitiveCount ||
                rays[l].tMax < 0.0 || intersector.isAnalytic(rayId)) {
              return false;
            }
            const std::uint32_t slot = model.slotOfId_[rayId];
            if (slot == ToleranceModel::kNoSlot) return false;
            const ToleranceModel::PixelTerms& terms = model.pixelTerms_[slot];
            polygons.boundX[l] = terms.clipErrorBound.x;
            polygons.boundY[l] = terms.clipErrorBound.y;
            polygons.boundZ[l] = terms.clipErrorBound.z;
            polygons.boundW[l] = terms.clipErrorBound.w;
            polygons.gradient[l] = terms.gradient;
            polygons.interpolation[l] = terms.interpolation;
          }
          FourPixels figures;
          if (!fourTrianglePixels(fourInput, rays, &analytic.hits[first], &raster.depth[first],
                                  polygons, figures)) {
            return false;
          }
          // The four pixels' figures and images, as the scalar loop below writes them one by one
          // (the samples in the same order).
          KindSamples& kind = samplesOf(0);
          local.rasterHits += 4;
          local.rayHits += 4;
          local.depthCompared += 4;
          std::memcpy(&pixels.rasterDepth[first], &raster.depth[first], 4 * sizeof(float));
          std::memcpy(&pixels.analyticDepth[first], figures.rayDepth, 4 * sizeof(double));
          appendFour(kind.quanta, figures.quanta);
          appendFour(kind.relative, figures.relative);
          appendFour(kind.ratios, figures.ratio);
          for (std::size_t l = 0; l < 4; ++l) {
            pixels.toleranceRatio[first + l] = static_cast<float>(figures.ratio[l]);
            const bool beyond = !(figures.ratio[l] <= 1.0);  // NaN counts as beyond tolerance
            local.depthBeyondTolerance += beyond ? 1 : 0;
            pixels.classes[first + l] =
                beyond ? PixelClass::DepthBeyondTolerance : PixelClass::Agree;
          }
          return true;
        };
#endif
        // The row goes in runs of 64 pixels. A run that shows nothing on either side (a terrain's
        // sky, most of a small scene's frame) only gets the background's images, written at once.
        // The others get their rays where the frame computes them (robustRayFrame: 107 KB at 1920
        // pixels, read from this core's cache); a background pixel never reads its ray.
        constexpr std::size_t kRun = 64;
        // Runs start at multiples of 4: compareFour's four pixels never straddle two.
        static_assert(kRun % 4 == 0);
        std::vector<Ray> rowScratch(analytic.pixelCentreRays ? width : 0);
        std::vector<std::uint8_t> runShows((width + kRun - 1) / kRun);
        for (int y = rowBegin; y < rowEnd; ++y) {
          const std::size_t rowStart = static_cast<std::size_t>(y) * width;
          const double centreY = y + 0.5;
          const Ray* rowRays =
              analytic.pixelCentreRays ? rowScratch.data() : analytic.rays.data() + rowStart;
          for (std::size_t x0 = 0; x0 < width; x0 += kRun) {
            const std::size_t n = std::min(kRun, width - x0);
            std::uint32_t shown = 0;
            for (std::size_t k = rowStart + x0; k < rowStart + x0 + n; ++k) {
              shown |= raster.ids[k] | analytic.hits[k].primitiveId;
            }
            runShows[x0 / kRun] = shown != 0 ? 1 : 0;
            if (shown != 0 && analytic.pixelCentreRays) {
              analytic.pixelCentreRays->row(y, static_cast<int>(x0), static_cast<int>(n),
                                            rowScratch.data() + x0);
            }
          }
          for (std::size_t x = 0; x < width; ++x) {
            if (x % kRun == 0 && runShows[x / kRun] == 0) {
              // What the loop below writes at a background pixel, for the whole run.
              const std::size_t first = rowStart + x, n = std::min(kRun, width - x);
              std::fill_n(&pixels.analyticDepth[first], n, kNaN);
              std::fill_n(&pixels.rasterDepth[first], n, std::numeric_limits<float>::quiet_NaN());
              std::fill_n(&pixels.toleranceRatio[first], n,
                          std::numeric_limits<float>::quiet_NaN());
              std::fill_n(&pixels.classes[first], n, PixelClass::Background);
              x += n - 1;
              continue;
            }
#if CLIPRAY_COMPARE_AVX2
            if (fourAtOnce && x % 4 == 0 && x + 4 <= width &&
                compareFour(rowStart + x, rowRays + x)) {
              x += 3;
              continue;
            }
#endif
            const std::size_t i = rowStart + x;
            const std::uint32_t rasterId = raster.ids[i];
            const Hit& hit = analytic.hits[i];
            const std::uint32_t rayId = hit.primitiveId;
            // What the images show where nothing below writes: no depth, not compared.
            pixels.analyticDepth[i] = kNaN;
            pixels.rasterDepth[i] = std::numeric_limits<float>::quiet_NaN();
            pixels.toleranceRatio[i] = std::numeric_limits<float>::quiet_NaN();
            pixels.classes[i] = PixelClass::Background;
            if (rasterId == 0 && rayId == 0) continue;  // background
            const glm::dvec2 centre(static_cast<double>(x) + 0.5, centreY);
            const Ray& ray = rowRays[x];
            if (rasterId != 0) {
              ++local.rasterHits;
              pixels.rasterDepth[i] = raster.depth[i];
            }
            glm::dvec4 hitClip(0.0);
            double zNdc = kNaN, rayDepth = kNaN;
            if (rayId != 0) {
              ++local.rayHits;
              const glm::dvec3 hitPoint = ray.origin + hit.t * ray.direction;
              hitClip = m * glm::dvec4(hitPoint, 1.0);
              zNdc = hitClip.z / hitClip.w;
              rayDepth = windowDepthFromNdc(zNdc, convention);
              pixels.analyticDepth[i] = rayDepth;
            }
            PixelClass& cls = pixels.classes[i];
            if (rasterId > primitiveCount || ray.tMax < 0.0) {
              // An id no primitive has (a renderer bug) or a pixel without a ray: nothing explains
              // it.
              ++local.coverageMismatch.total;
              ++local.coverageMismatch.unexplained;
              cls = PixelClass::CoverageUnexplained;
            } else if (rasterId == 0 || rayId == 0) {
              const std::uint32_t only = rasterId != 0 ? rasterId : rayId;
              ++local.coverageMismatch.total;
              if (model.edgeAmbiguous(only, centre)) {
                ++local.coverageMismatch.edgeAmbiguous;
                cls = PixelClass::CoverageEdgeAmbiguous;
              } else {
                ++local.coverageMismatch.unexplained;
                cls = PixelClass::CoverageUnexplained;
              }
            } else if (rasterId == rayId) {
              const bool analyticSurface = intersector.isAnalytic(rayId);
              const double rasterDepth = raster.depth[i];
              const double error = std::abs(rasterDepth - rayDepth);
              const double quantum = quantumAt(setup.depthFormat, rayDepth);
              double tolerance = 0.0;
              if (analyticSurface) {
                tolerance = model.analyticDepthTolerance(rayId, ray, hit.t);
              } else {
                // depthToleranceAtClip, sharing the hit's depth and quantum.
                tolerance = triangleDepthTolerance(model.pixelTerms(rayId), hitClip, zNdc, rayDepth,
                                                   quantum, model.windowFromNdcScale_,
                                                   model.subpixelStep_, viewport);
              }
              if (analyticSurface && !(error <= tolerance) &&
                  model.analyticEdgeAmbiguous(rayId, centre)) {
                // The same sphere or box, but one side entered the surface where the other
                // started inside it (the near plane cuts the shape within float error of this
                // pixel): the front surface's coverage is ambiguous here, not the depth of
                // either surface.
                ++local.coverageMismatch.total;
                ++local.coverageMismatch.edgeAmbiguous;
                cls = PixelClass::CoverageEdgeAmbiguous;
                continue;
              }
              const auto [ratio, quanta] = divideTwo(error, tolerance, error, quantum);
              // Distance along the ray to where the raster depth lies: z(t) = (Z0 + Z1 t)/(W0 + W1
              // t).
              const double zRaster = ndcFromWindowDepth(rasterDepth, convention);
              const double z0 = glm::dot(rowZ, glm::dvec4(ray.origin, 1.0));
              const double z1 = glm::dot(glm::dvec3(rowZ), ray.direction);
              const double w0 = glm::dot(rowW, glm::dvec4(ray.origin, 1.0));
              const double w1 = glm::dot(glm::dvec3(rowW), ray.direction);
              const double tRaster = (z0 - zRaster * w0) / (zRaster * w1 - z1);
              // Relative to the distance from the eye (perspective) or the view volume's depth
              // (orthographic), so the figure reads the same at any scale.
              const double scale = parallel ? (std::isfinite(ray.tMax) ? ray.tMax : hit.t)
                                            : hit.t + glm::length(ray.origin - eye);
              ++local.depthCompared;
              KindSamples& kind = samplesOf(analyticSurface ? kindOf(rayId) : 0);
              kind.quanta.push_back(quanta);
              kind.relative.push_back(std::abs(tRaster - hit.t) / scale);
              kind.ratios.push_back(ratio);
              pixels.toleranceRatio[i] = static_cast<float>(ratio);
              if (!(ratio <= 1.0)) {  // NaN counts as beyond tolerance
                ++local.depthBeyondTolerance;
                cls = PixelClass::DepthBeyondTolerance;
              } else {
                cls = PixelClass::Agree;
              }
            } else {
              ++local.idMismatch.total;
              // Where does the raster's primitive lie along this pixel? Its depth at the centre
              // (plane or analytic surface) and the tolerance there.
              const double rasterPlaneDepth = model.surfaceDepthAt(rasterId, centre);
              const double rayTolerance = intersector.isAnalytic(rayId)
                                              ? model.analyticDepthTolerance(rayId, ray, hit.t)
                                              : model.depthToleranceAtClip(rayId, hitClip);
              const double tolerance = rayTolerance + model.surfaceToleranceAt(rasterId, centre);
              if (std::abs(rasterPlaneDepth - rayDepth) <= tolerance) {
                ++local.idMismatch.depthAmbiguous;
                cls = PixelClass::IdDepthAmbiguous;
              } else if (model.edgeAmbiguous(rasterId, centre) ||
                         model.edgeAmbiguous(rayId, centre)) {
                ++local.idMismatch.edgeAmbiguous;
                cls = PixelClass::IdEdgeAmbiguous;
              } else {
                ++local.idMismatch.unexplained;
                cls = PixelClass::IdUnexplained;
              }
            }
          }
        }
        const std::lock_guard<std::mutex> lock(merge);
        total.pixels += local.pixels;
        total.rasterHits += local.rasterHits;
        total.rayHits += local.rayHits;
        total.coverageMismatch.total += local.coverageMismatch.total;
        total.coverageMismatch.edgeAmbiguous += local.coverageMismatch.edgeAmbiguous;
        total.coverageMismatch.unexplained += local.coverageMismatch.unexplained;
        total.idMismatch.total += local.idMismatch.total;
        total.idMismatch.depthAmbiguous += local.idMismatch.depthAmbiguous;
        total.idMismatch.edgeAmbiguous += local.idMismatch.edgeAmbiguous;
        total.idMismatch.unexplained += local.idMismatch.unexplained;
        total.depthCompared += local.depthCompared;
        total.depthBeyondTolerance += local.depthBeyondTolerance;
      });

  // Every distribution to compute: per kind with samples, then over all kinds. Where one kind
  // holds every sample, the overall figures are that kind's (the same values, so the same
  // quantiles) and are not computed twice.
  using Parts = std::vector<const FrameVector<double>*>;
  struct Job {
    Parts parts;
    Distribution* into;
  };
  std::vector<Job> jobs;
  std::vector<std::size_t> kindsWithSamples;
  for (std::size_t k = 0; k < kKinds; ++k) {
    for (const auto& worker : samplesOfWorker) {
      if (!worker[k].quanta.empty()) {
        kindsWithSamples.push_back(k);
        break;
      }
    }
  }
  total.byKind.resize(kindsWithSamples.size());
  Parts allQuanta, allRelative, allRatios;
  for (std::size_t n = 0; n < kindsWithSamples.size(); ++n) {
    const std::size_t k = kindsWithSamples[n];
    RunMetrics::KindFigures& figures = total.byKind[n];
    figures.kind = k == 0 ? "triangle" : primitiveKindName(static_cast<PrimitiveKind>(k - 1));
    Parts quanta, relative, ratios;
    for (const auto& worker : samplesOfWorker) {
      figures.depthCompared += static_cast<std::int64_t>(worker[k].quanta.size());
      quanta.push_back(&worker[k].quanta);
      relative.push_back(&worker[k].relative);
      ratios.push_back(&worker[k].ratios);
    }
    allQuanta.insert(allQuanta.end(), quanta.begin(), quanta.end());
    allRelative.insert(allRelative.end(), relative.begin(), relative.end());
    allRatios.insert(allRatios.end(), ratios.begin(), ratios.end());
    jobs.push_back({std::move(quanta), &figures.depthErrorQuanta});
    jobs.push_back({std::move(relative), &figures.distanceRelError});
    jobs.push_back({std::move(ratios), &figures.toleranceRatio});
  }
  if (kindsWithSamples.size() > 1) {
    jobs.push_back({std::move(allQuanta), &total.depthErrorQuanta});
    jobs.push_back({std::move(allRelative), &total.distanceRelError});
    jobs.push_back({std::move(allRatios), &total.toleranceRatio});
  }
  parallelForRows(static_cast<int>(jobs.size()), threadCount, [&](int begin, int end) {
    for (int j = begin; j < end; ++j) *jobs[j].into = distributionOfParts(jobs[j].parts);
  });
  if (kindsWithSamples.size() == 1) {
    total.depthErrorQuanta = total.byKind[0].depthErrorQuanta;
    total.distanceRelError = total.byKind[0].distanceRelError;
    total.toleranceRatio = total.byKind[0].toleranceRatio;
  }
  return result;
}

}  // namespace clipray
