#include "clipray/compare/Reconcile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>

#include "clipray/math/Projections.hpp"

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
    const glm::dvec4& b = in[(k + 1) % count];
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

ToleranceModel::ToleranceModel(const SceneIntersector& intersector, const RasterSetup& setup,
                               Viewport viewport)
    : setup_(setup),
      viewport_(viewport),
      intersector_(intersector),
      rays_(setup.clipFromWorld, setup.mode),
      polygons_(intersector.triangleCount() + 1) {
  const glm::dmat4& m = setup.clipFromWorld;
  const double zn = setup.mode.clipVolumeMinZ();
  // The clip volume z_n w <= z <= w, -w <= x, y <= w as six planes (>= 0 inside).
  const glm::dvec4 planes[6] = {{0, 0, 1, -zn}, {0, 0, -1, 1}, {1, 0, 0, 1},
                                {-1, 0, 0, 1},  {0, 1, 0, 1},  {0, -1, 0, 1}};

  // The matrix and positions the GPU actually multiplies, per vertex mode (for the error bound).
  const glm::dmat4 cameraRelativeMatrix =
      m * glm::dmat4(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 1, 0, 0), glm::dvec4(0, 0, 1, 0),
                     glm::dvec4(setup.vertexReference, 1.0));
  const double u = kFloatUnitRoundoff;
  const double subpixel = std::ldexp(1.0, -setup.subpixelBits);

  for (std::uint32_t id = 1; id < polygons_.size(); ++id) {
    if (intersector.isAnalytic(id)) continue;
    ScreenPolygon& polygon = polygons_[id];
    const std::array<glm::dvec3, 3> world = intersector.worldTriangle(id);

    // Float error of the vertex transform, bounded per clip row r by k u max_v sum_i |M_ri p_i|:
    // World/CameraRelative: matrix and position each rounded to float (2u) plus a 4-term float
    // dot product (gamma_4 ~ 4u): k = 6. Pretransformed: clip coordinates rounded once: k = 1.
    glm::dvec4 bound(0.0);
    for (const glm::dvec3& v : world) {
      for (int r = 0; r < 4; ++r) {
        double magnitude = 0.0;
        if (setup.vertexMode == VertexMode::Pretransformed) {
          magnitude = std::abs(glm::dot(matrixRow(m, r), glm::dvec4(v, 1.0)));
        } else {
          const glm::dmat4& gpuMatrix =
              setup.vertexMode == VertexMode::World ? m : cameraRelativeMatrix;
          const glm::dvec3 gpuPosition =
              setup.vertexMode == VertexMode::World ? v : v - setup.vertexReference;
          const glm::dvec4 row = matrixRow(gpuMatrix, r);
          magnitude = std::abs(row.x * gpuPosition.x) + std::abs(row.y * gpuPosition.y) +
                      std::abs(row.z * gpuPosition.z) + std::abs(row.w);
        }
        bound[r] = std::max(bound[r], magnitude);
      }
    }
    polygon.clipErrorBound =
        bound * (setup.vertexMode == VertexMode::Pretransformed ? 1.0 : 6.0) * u;
    const glm::dvec4& error = polygon.clipErrorBound;

    glm::dvec4 bufferA[kMaxPolygonVertices + 3], bufferB[kMaxPolygonVertices + 3];
    int count = 3;
    for (int k = 0; k < 3; ++k) bufferA[k] = m * glm::dvec4(world[k], 1.0);
    glm::dvec4* current = bufferA;
    glm::dvec4* next = bufferB;
    for (const glm::dvec4& plane : planes) {
      count = clipPolygon(current, count, plane, next);
      std::swap(current, next);
      if (count == 0) break;
    }
    polygon.vertexCount = std::min(count, kMaxPolygonVertices);
    double xyError = 0.0;
    for (int k = 0; k < polygon.vertexCount; ++k) {
      const glm::dvec4 c = current[k];
      const double w = c.w;
      polygon.vertices[k] = {(c.x / w + 1.0) * 0.5 * viewport.width,
                             (c.y / w + 1.0) * 0.5 * viewport.height,
                             windowDepthFromNdc(c.z / w, setup.mode.convention)};
      polygon.maxDepth = std::max(polygon.maxDepth, std::abs(polygon.vertices[k].z));
      // Vertex xy error in pixels: (dx + |x_ndc| dw) / w, scaled to the viewport.
      const double ex = (error.x + std::abs(c.x / w) * error.w) / w * 0.5 * viewport.width;
      const double ey = (error.y + std::abs(c.y / w) * error.w) / w * 0.5 * viewport.height;
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
  }
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
  const glm::dmat4 clipFromLocal = m * primitive.worldFromLocal;
  const glm::dvec3 origin(primitive.localFromWorld * glm::dvec4(ray.origin, 1.0));
  const glm::dvec3 direction(glm::dmat3(primitive.localFromWorld) * ray.direction);
  const glm::dvec3 p = origin + t * direction;

  // 1. Storage: one quantum of the depth format.
  const double storage = depthQuantum(setup_.depthFormat, depth);
  // 2. Depth of the hit evaluated in float: z and w are 4-term dot products of float rows with
  //    the float point (6u sum |M_ri p_i|, as for a vertex), then the divide and the mapping (2u).
  double magnitudeZ = 0.0, magnitudeW = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double coordinate = i < 3 ? std::abs(p[i]) : 1.0;
    magnitudeZ += std::abs(matrixRow(clipFromLocal, 2)[i]) * coordinate;
    magnitudeW += std::abs(matrixRow(clipFromLocal, 3)[i]) * coordinate;
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
  const ScreenPolygon& polygon = this->polygon(primitiveId);
  const double u = kFloatUnitRoundoff;
  const glm::dvec4 c = setup_.clipFromWorld * glm::dvec4(hitWorld, 1.0);
  const double zNdc = c.z / c.w;
  const double depth = windowDepthFromNdc(zNdc, setup_.mode.convention);
  const double toWindow = 1.0 / (1.0 - setup_.mode.clipVolumeMinZ());
  const glm::dvec4& bound = polygon.clipErrorBound;

  // 1. Storage: one quantum of the depth format at this depth.
  const double storage = depthQuantum(setup_.depthFormat, depth);
  // 2. Vertex transform in float, interpolated: dz_ndc = (dz + |z_ndc| dw) / w, plus the GPU's
  //    divide and depth-range mapping (2u relative).
  const double vertex =
      (bound.z + std::abs(zNdc) * bound.w) / std::abs(c.w) * toWindow + 2.0 * u * std::abs(depth);
  // 3. Vertex positions snapped to the subpixel grid and moved by the float xy error: the depth
  //    plane shifts by |gradient| times that displacement.
  const double xyShift =
      std::ldexp(1.0, -setup_.subpixelBits) +
      std::max((bound.x + std::abs(c.x / c.w) * bound.w) * 0.5 * viewport_.width,
               (bound.y + std::abs(c.y / c.w) * bound.w) * 0.5 * viewport_.height) /
          std::abs(c.w);
  const double gradient = std::isfinite(polygon.depthPlane.x)
                              ? std::abs(polygon.depthPlane.x) + std::abs(polygon.depthPlane.y)
                              : 0.0;
  const double snap = gradient * xyShift;
  // 4. Plane evaluation in float (setup of dz/dx, dz/dy and the sum): ~8u of the largest depth
  //    the plane takes over the clipped triangle.
  const double interpolation = 8.0 * u * polygon.maxDepth;
  return storage + vertex + snap + interpolation;
}

ComparisonResult compareFrames(const RasterFrame& raster, const AnalyticFrame& analytic,
                               const SceneIntersector& intersector, const RasterSetup& setup,
                               unsigned threadCount) {
  const Viewport viewport = raster.viewport;
  const std::size_t count = static_cast<std::size_t>(viewport.width) * viewport.height;
  if (analytic.viewport != viewport || raster.depth.size() != count || raster.ids.size() != count ||
      analytic.rays.size() != count || analytic.hits.size() != count) {
    throw std::invalid_argument("compareFrames: raster and analytic frames differ in size");
  }
  const std::uint32_t primitiveCount = intersector.primitiveIdCount();
  const ToleranceModel model(intersector, setup, viewport);
  const glm::dmat4& m = setup.clipFromWorld;
  const glm::dmat4 worldFromClip = glm::inverse(m);
  // Figures per surface kind: 0 triangles, 1 + PrimitiveKind for analytic primitives.
  constexpr std::size_t kKinds = 1 + static_cast<std::size_t>(PrimitiveKind::Plane) + 1;
  const auto kindOf = [&](std::uint32_t id) -> std::size_t {
    return intersector.isAnalytic(id)
               ? 1 + static_cast<std::size_t>(intersector.analyticPrimitive(id).kind)
               : 0;
  };
  struct KindSamples {
    std::vector<double> quanta, relative, ratios;
  };
  std::array<KindSamples, kKinds> kindSamples;
  const glm::dvec4 rowZ = matrixRow(m, 2), rowW = matrixRow(m, 3);
  const bool parallel = glm::dvec3(rowW) == glm::dvec3(0.0);
  const glm::dvec4 eyeHomogeneous = worldFromClip * glm::dvec4(0.0, 0.0, 1.0, 0.0);
  const glm::dvec3 eye = glm::dvec3(eyeHomogeneous) / eyeHomogeneous.w;
  const DepthConvention convention = setup.mode.convention;

  ComparisonResult result;
  PixelComparison& pixels = result.pixels;
  pixels.viewport = viewport;
  pixels.rasterDepth.assign(count, std::numeric_limits<float>::quiet_NaN());
  pixels.analyticDepth.assign(count, kNaN);
  pixels.toleranceRatio.assign(count, std::numeric_limits<float>::quiet_NaN());
  pixels.classes.assign(count, PixelClass::Background);

  std::mutex merge;
  RunMetrics& total = result.metrics;
  std::vector<double> quanta, relative, ratios;

  parallelForRows(viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
    RunMetrics local;
    std::vector<double> localQuanta, localRelative, localRatios;
    std::array<KindSamples, kKinds> localKinds;
    for (int y = rowBegin; y < rowEnd; ++y) {
      for (int x = 0; x < viewport.width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * viewport.width + x;
        const glm::dvec2 centre(x + 0.5, y + 0.5);
        const std::uint32_t rasterId = raster.ids[i];
        const Hit& hit = analytic.hits[i];
        const std::uint32_t rayId = hit.primitiveId;
        const Ray& ray = analytic.rays[i];
        ++local.pixels;
        if (rasterId != 0) {
          ++local.rasterHits;
          pixels.rasterDepth[i] = raster.depth[i];
        }
        glm::dvec3 hitPoint(0.0);
        double rayDepth = kNaN;
        if (rayId != 0) {
          ++local.rayHits;
          hitPoint = ray.origin + hit.t * ray.direction;
          const glm::dvec4 c = m * glm::dvec4(hitPoint, 1.0);
          rayDepth = windowDepthFromNdc(c.z / c.w, convention);
          pixels.analyticDepth[i] = rayDepth;
        }
        PixelClass& cls = pixels.classes[i];
        if (rasterId == 0 && rayId == 0) {
          cls = PixelClass::Background;
        } else if (rasterId > primitiveCount || ray.tMax < 0.0) {
          // An id no primitive has (a renderer bug) or a pixel without a ray: nothing explains it.
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
          const double rasterDepth = raster.depth[i];
          const double error = std::abs(rasterDepth - rayDepth);
          const double tolerance = intersector.isAnalytic(rayId)
                                       ? model.analyticDepthTolerance(rayId, ray, hit.t)
                                       : model.depthTolerance(rayId, hitPoint);
          const double ratio = error / tolerance;
          // Distance along the ray to where the raster depth lies: z(t) = (Z0 + Z1 t)/(W0 + W1 t).
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
          localQuanta.push_back(error / depthQuantum(setup.depthFormat, rayDepth));
          localRelative.push_back(std::abs(tRaster - hit.t) / scale);
          localRatios.push_back(ratio);
          KindSamples& kind = localKinds[kindOf(rayId)];
          kind.quanta.push_back(localQuanta.back());
          kind.relative.push_back(localRelative.back());
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
                                          : model.depthTolerance(rayId, hitPoint);
          const double tolerance = rayTolerance + model.surfaceToleranceAt(rasterId, centre);
          if (std::abs(rasterPlaneDepth - rayDepth) <= tolerance) {
            ++local.idMismatch.depthAmbiguous;
            cls = PixelClass::IdDepthAmbiguous;
          } else if (model.edgeAmbiguous(rasterId, centre) || model.edgeAmbiguous(rayId, centre)) {
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
    quanta.insert(quanta.end(), localQuanta.begin(), localQuanta.end());
    relative.insert(relative.end(), localRelative.begin(), localRelative.end());
    ratios.insert(ratios.end(), localRatios.begin(), localRatios.end());
    for (std::size_t k = 0; k < kKinds; ++k) {
      KindSamples& into = kindSamples[k];
      const KindSamples& from = localKinds[k];
      into.quanta.insert(into.quanta.end(), from.quanta.begin(), from.quanta.end());
      into.relative.insert(into.relative.end(), from.relative.begin(), from.relative.end());
      into.ratios.insert(into.ratios.end(), from.ratios.begin(), from.ratios.end());
    }
  });
  for (std::size_t k = 0; k < kKinds; ++k) {
    KindSamples& samples = kindSamples[k];
    if (samples.quanta.empty()) continue;
    RunMetrics::KindFigures figures;
    figures.kind = k == 0 ? "triangle" : primitiveKindName(static_cast<PrimitiveKind>(k - 1));
    figures.depthCompared = static_cast<std::int64_t>(samples.quanta.size());
    figures.depthErrorQuanta = distributionOf(samples.quanta);
    figures.distanceRelError = distributionOf(samples.relative);
    figures.toleranceRatio = distributionOf(samples.ratios);
    total.byKind.push_back(std::move(figures));
  }
  total.depthErrorQuanta = distributionOf(quanta);
  total.distanceRelError = distributionOf(relative);
  total.toleranceRatio = distributionOf(ratios);
  return result;
}

}  // namespace clipray
