#pragma once
// The predicted per-pixel depth tolerance of a reconcile, and when a pixel's coverage is
// ambiguous: what the raster may legitimately differ from the exact ray by, given the depth
// format, the convention, the matrix and the vertex mode (derivation: docs/reconcile.md).
// RasterSetup::clipFromWorld: column-major, p_clip = clipFromWorld * p_world, built for
// RasterSetup::mode.

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/compare/DepthMapping.hpp"
#include "clipray/compare/Frames.hpp"
#include "clipray/compare/LogarithmicDepth.hpp"
#include "clipray/compare/PolygonOffset.hpp"
#include "clipray/compare/PrimitiveClipPlanes.hpp"
#include "clipray/rays/RobustRays.hpp"

namespace clipray {

namespace detail {
class FrameClassifier;
}  // namespace detail

// What the raster side was: needed to predict what it may legitimately differ by.
struct RasterSetup {
  glm::dmat4 clipFromWorld{1.0};  // the exact (double) matrix of the camera
  DepthMode mode;
  DepthFormat depthFormat = DepthFormat::Float32;
  VertexMode vertexMode = VertexMode::World;
  glm::dvec3 vertexReference{0.0};  // the point removed on the CPU in CameraRelative mode
  int subpixelBits = 4;             // GL_SUBPIXEL_BITS of the rasterizer
  // glDepthRange(n, f) (Scene::depthRange): window depth n + (f - n) d, d what (0, 1) gives.
  glm::dvec2 depthRange{0.0, 1.0};

  // Objects drawn with their own glDepthRange (MeshObject::depthRange), by primitive id.
  PrimitiveDepthRanges objectDepthRanges{};
  // Objects drawn with a polygon offset (MeshObject::polygonOffset), by primitive id.
  PrimitiveOffsets objectOffsets{};
  // The camera's user clip planes (world space, Camera::clipPlanes): the screen polygons are cut by
  // them as the rasterizer cuts the triangles, the rays as the rays are cut.
  std::vector<glm::dvec4> clipPlanes{};
  // The planes of the objects drawn with planes of their own (MeshObject::clipPlanes), beside the
  // camera's, by primitive id.
  PrimitiveClipPlanes objectClipPlanes{};
  // GL_DEPTH_CLAMP (Scene::depthClamp): no near and far clipping, window depth clamped to the depth
  // range; the rays reach in front of the near plane (DepthClampRays).
  DepthClampRays depthClamp{};
  // The meshes' fragment shader writes a logarithmic depth of clip w (Camera::logarithmicDepth);
  // nullopt: the rasterizer's projective depth. Only with triangle meshes, the default depth
  // range, no depth clamp and no polygon offset (the scene loader refuses the rest).
  std::optional<LogDepthMapping> logDepth{};

  bool defaultDepthRange() const { return depthRange == glm::dvec2(0.0, 1.0); }
  // Every primitive drawn with the scene's depth range (no object has its own).
  bool oneDepthRange() const { return objectDepthRanges.empty(); }
  // The scene's mapping of NDC z to window depth (what the analytic primitives and every object
  // without its own range are drawn with).
  DepthMapping depthMapping() const { return {mode, depthRange, depthClamp.enabled}; }
  // The mapping of the primitive with that id.
  DepthMapping depthMappingOf(std::uint32_t primitiveId) const {
    return {mode, objectDepthRanges.rangeOf(primitiveId, depthRange), depthClamp.enabled};
  }
  // The scene's mapping's (DepthMapping).
  double windowDepth(double zNdc) const { return depthMapping().windowDepth(zNdc); }
  double mappedWindowDepth(double zNdc) const { return depthMapping().mappedWindowDepth(zNdc); }
  double clampToDepthRange(double windowDepth) const {
    return depthMapping().clampToDepthRange(windowDepth);
  }
  bool inFrontOfNear(double unclampedWindowDepth) const {
    return depthMapping().inFrontOfNear(unclampedWindowDepth);
  }
  double nearWindowDepth() const { return depthMapping().nearWindowDepth(); }
  double ndcOfWindowDepth(double windowDepth) const {
    return depthMapping().ndcOfWindowDepth(windowDepth);
  }
  double windowFromNdcScale() const { return depthMapping().windowFromNdcScale(); }
};

// The predicted tolerance model, exposed for tests: window-depth tolerance at a pixel whose
// analytic hit lies on primitive `primitiveId` at window depth `windowDepth`.
class ToleranceModel {
 public:
  // Clips every triangle of the scene to its screen polygon up front.
  ToleranceModel(const SceneIntersector& intersector, const RasterSetup& setup, Viewport viewport);
  // Clips up front only the triangles among primitiveIds (those a frame shows: the rest of a big
  // scene is never asked about), across threadCount threads (0: all cores). Any other primitive
  // may still be asked about: its polygon is then clipped when asked, and kept in a small cache of
  // the asking thread's (same answers).
  ToleranceModel(const SceneIntersector& intersector, const RasterSetup& setup, Viewport viewport,
                 std::span<const std::uint32_t> primitiveIds, unsigned threadCount = 0);
  // The setup the model answers for. Only the tolerances read its depth format (the storage
  // quantum at a depth); the polygons and their terms do not: a model built for one run serves
  // the runs of the same camera, convention and vertex mode in other depth formats, once told
  // which (one run at a time).
  const RasterSetup& setup() const { return setup_; }
  Viewport viewport() const { return viewport_; }
  void useDepthFormat(DepthFormat format) { setup_.depthFormat = format; }
  // Window-depth tolerance for a hit on primitive id at a world hit point.
  double depthTolerance(std::uint32_t primitiveId, const glm::dvec3& hitWorld) const;
  // The same, given the hit's clip coordinates clipFromWorld * (hitWorld, 1) (callers that have
  // them already save the matrix product).
  double depthToleranceAtClip(std::uint32_t primitiveId, const glm::dvec4& hitClip) const;
  // Distance in pixels from a window position to the boundary of the primitive's clipped screen
  // polygon (+inf for a primitive clipped away entirely).
  double edgeDistancePixels(std::uint32_t primitiveId, glm::dvec2 pixel) const;
  bool insidePolygon(std::uint32_t primitiveId, glm::dvec2 pixel) const;
  // How close to an edge a pixel centre must be for coverage to be ambiguous, in pixels.
  double edgeEpsilonPixels(std::uint32_t primitiveId) const;
  // Window depth of the primitive's plane at a window position (NaN if it has no screen polygon).
  double planeDepthAt(std::uint32_t primitiveId, glm::dvec2 pixel) const;
  // The polygon offsets GL allows for the primitive's fragments in the model's depth format
  // (PolygonOffset.hpp: its depth plane's slope, its vertices' largest depth); {0, 0} for a
  // primitive drawn without an offset or without a screen polygon.
  OffsetInterval offsetInterval(std::uint32_t primitiveId) const;
  // Under setup().logDepth: the tolerance of the depth the shader writes for a hit on triangle
  // primitiveId at clip coordinates hitClip, stored with quantum `storage` (LogarithmicDepth.hpp;
  // the w error from the polygon's clipErrorBound.w and the snap times the screen gradient of w).
  double logDepthTolerance(std::uint32_t primitiveId, const glm::dvec4& hitClip,
                           double storage) const;

  // Analytic primitives (drawn by a fragment shader that intersects the surface in float):
  // window-depth tolerance for the hit at parameter t of a (double, robust) ray.
  double analyticDepthTolerance(std::uint32_t primitiveId, const Ray& ray, double t) const;
  // Whether the primitive's coverage (hit or miss, and entering or leaving the surface) changes
  // within kAnalyticEdgeEpsilonPixels of the pixel position: the float ray of the shader may
  // then legitimately land on the other side.
  bool analyticEdgeAmbiguous(std::uint32_t primitiveId, glm::dvec2 pixel) const;
  // Window depth where the primitive (triangle plane or analytic surface) lies along the robust
  // ray of a pixel position (NaN: misses), and the tolerance of that depth.
  double surfaceDepthAt(std::uint32_t primitiveId, glm::dvec2 pixel) const;
  double surfaceToleranceAt(std::uint32_t primitiveId, glm::dvec2 pixel) const;
  // Coverage of the primitive is ambiguous at this pixel position (any primitive kind).
  bool edgeAmbiguous(std::uint32_t primitiveId, glm::dvec2 pixel) const;
  // The triangle lies in one of the camera's clip planes within the rounding of the float clip
  // distance the vertex shader computes (a box resting on the water plane that clips it): GL keeps
  // or clips its fragments as that rounding falls, so its coverage is ambiguous everywhere.
  bool onClipPlane(std::uint32_t primitiveId) const;
  // The float rays of primitive.frag differ from the double robust rays by far less than this
  // (issue #3: robust float rays are within 0.01 px of the exact ray for fov >= 1 deg; the
  // shader's construction is the same, evaluated in the primitive's local frame).
  static constexpr double kAnalyticEdgeEpsilonPixels = 1.0 / 64.0;

 private:
  // The per-pixel classification reads the polygons' terms directly (the hit's depth and depth
  // quantum, which depthToleranceAtClip would compute again, are shared with the pixel's figures).
  friend class detail::FrameClassifier;
  // A triangle clipped against the six clip planes has at most 3 + 6 vertices.
  static constexpr int kMaxPolygonVertices = 9;
  struct ScreenPolygon {
    std::array<glm::dvec3, kMaxPolygonVertices> vertices;  // window x, y (pixels), window depth
    int vertexCount = 0;
    glm::dvec3 depthPlane{std::nan("")};  // d = a x + b y + c in window coordinates
    double maxDepth = 0.0;
    double edgeEpsilon = 0.0;  // pixels
    // Bounds of the error in clip space, per clip row (x, y, z, w), between the raster's and the
    // ray's clip coordinates of one point: the float vertex transform plus the double hit point.
    glm::dvec4 clipErrorBound{0.0};
  };
  // What the tolerance of each pixel of a triangle reads from its polygon, packed: 48 bytes in
  // place of the polygon's 300, so that the per-pixel loop's reads stay in cache.
  struct PixelTerms {
    glm::dvec4 clipErrorBound;  // the polygon's
    double gradient;            // |a| + |b| of the depth plane, 0 where it has none
    double interpolation;       // 8 u maxDepth: the rounding of evaluating the plane in float
  };
  // What the log depth's tolerance of each pixel of a triangle reads (logDepthTolerance), from its
  // clip vertices: |d(1/w)/dx_ndc| 2 / width + |d(1/w)/dy_ndc| 2 / height (infinite for a
  // triangle seen edge-on, whose pixels are not measurable), and the smallest w of the polygon the
  // near plane leaves (NaN where there is none: the hit's own w is taken).
  struct LogDepthTerms {
    double wGradient;
    double wMin;
  };
  static constexpr std::uint32_t kNoSlot = 0xffffffffu;
  static PixelTerms pixelTermsOf(const ScreenPolygon& polygon);
  LogDepthTerms logDepthTermsOf(std::uint32_t primitiveId) const;
  // The primitive's PixelTerms: built up front, else from its polygon now.
  PixelTerms pixelTerms(std::uint32_t primitiveId) const;
  // The clipped screen polygon of a primitive (an empty one for analytic primitives and ids that
  // name no primitive), as computed by buildPolygon.
  const ScreenPolygon& polygon(std::uint32_t primitiveId) const;
  ScreenPolygon buildPolygon(std::uint32_t primitiveId) const;
  // Builds the polygons of the given ids (each at most once) across threads.
  void buildPolygons(std::span<const std::uint32_t> primitiveIds, unsigned threadCount);
  RasterSetup setup_;
  Viewport viewport_;
  const SceneIntersector& intersector_;
  RobustRayGenerator rays_;
  glm::dmat4 cameraRelativeMatrix_;      // the matrix the GPU multiplies in CameraRelative mode
  std::vector<std::uint32_t> slotOfId_;  // primitive id -> index in polygons_, or kNoSlot
  // Tells this model's entries apart in a thread's cache of polygons not built up front.
  static std::atomic<std::uint64_t> nextSerial;
  std::uint64_t serial_;
  FrameVector<ScreenPolygon> polygons_;       // the polygons built up front (kept from run to run)
  FrameVector<PixelTerms> pixelTerms_;        // the same slots' PixelTerms
  FrameVector<LogDepthTerms> logDepthTerms_;  // the same slots', under setup_.logDepth only
  // Per analytic primitive (in the intersector's order): clipFromWorld * worldFromLocal, the
  // matrix its shader rounds to float, and the magnitudes of its z and w rows (the tolerance of
  // each of its pixels reads them).
  struct AnalyticTransform {
    glm::dmat4 clipFromLocal;
    glm::dvec4 magnitudeRowZ, magnitudeRowW;
  };
  std::vector<AnalyticTransform> analyticTransforms_;
  // Per world axis, what bounds |o_i| + t |d_i| of a robust ray's hit o + t d beyond the part
  // that the hit point's own |p_i| bounds (see buildPolygon): 3 |eye_i| for a perspective camera,
  // twice the largest |o_i| over the near plane's corners for a parallel one.
  glm::dvec3 rayOriginScale_{0.0};
  double windowFromNdcScale_;  // 1 / (1 - z_n): NDC depth to window depth
  double subpixelStep_;        // 2^-subpixelBits pixels
};

}  // namespace clipray
