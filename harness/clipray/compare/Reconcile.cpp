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
    : setup_(setup), viewport_(viewport), polygons_(intersector.triangleCount() + 1) {
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
  const std::uint32_t primitiveCount = static_cast<std::uint32_t>(intersector.triangleCount());
  const ToleranceModel model(intersector, setup, viewport);
  const glm::dmat4& m = setup.clipFromWorld;
  const glm::dmat4 worldFromClip = glm::inverse(m);
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
          if (model.edgeDistancePixels(only, centre) <= model.edgeEpsilonPixels(only)) {
            ++local.coverageMismatch.edgeAmbiguous;
            cls = PixelClass::CoverageEdgeAmbiguous;
          } else {
            ++local.coverageMismatch.unexplained;
            cls = PixelClass::CoverageUnexplained;
          }
        } else if (rasterId == rayId) {
          const double rasterDepth = raster.depth[i];
          const double error = std::abs(rasterDepth - rayDepth);
          const double tolerance = model.depthTolerance(rayId, hitPoint);
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
          pixels.toleranceRatio[i] = static_cast<float>(ratio);
          if (!(ratio <= 1.0)) {  // NaN counts as beyond tolerance
            ++local.depthBeyondTolerance;
            cls = PixelClass::DepthBeyondTolerance;
          } else {
            cls = PixelClass::Agree;
          }
        } else {
          ++local.idMismatch.total;
          // Where does the raster's primitive lie along this pixel? Its plane depth at the centre,
          // and the world point of that depth for its tolerance.
          const double rasterPlaneDepth = model.planeDepthAt(rasterId, centre);
          const glm::dvec4 rasterPointClip(2.0 * centre.x / viewport.width - 1.0,
                                           2.0 * centre.y / viewport.height - 1.0,
                                           ndcFromWindowDepth(rasterPlaneDepth, convention), 1.0);
          const glm::dvec4 rasterPointWorld = worldFromClip * rasterPointClip;
          const double tolerance =
              model.depthTolerance(rayId, hitPoint) +
              model.depthTolerance(rasterId, glm::dvec3(rasterPointWorld) / rasterPointWorld.w);
          if (std::abs(rasterPlaneDepth - rayDepth) <= tolerance) {
            ++local.idMismatch.depthAmbiguous;
            cls = PixelClass::IdDepthAmbiguous;
          } else if (model.edgeDistancePixels(rasterId, centre) <=
                         model.edgeEpsilonPixels(rasterId) ||
                     model.edgeDistancePixels(rayId, centre) <= model.edgeEpsilonPixels(rayId)) {
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
  });
  total.depthErrorQuanta = distributionOf(quanta);
  total.distanceRelError = distributionOf(relative);
  total.toleranceRatio = distributionOf(ratios);
  return result;
}

}  // namespace clipray
