#pragma once
// One click picked three ways (no GL, no window: testable on its own):
//   1. the analytic ray through the pixel centre -> object and hit point;
//   2. the raster depth at the pixel, unprojected through worldFromClip -> world point (the classic
//      depth-readback idiom);
//   3. the raster id at the pixel -> object.
// and the gap between 1 and 2, in world units and in pixel footprints at that depth.

#include <optional>
#include <string>
#include <string_view>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "clipray/compare/Frames.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/math/Conventions.hpp"
#include "clipray/rays/Ray.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::demo {

// The ray methods the demo offers: clipray's `robust`, and `two_point` as most apps write it
// (worldFromClip inverted in float, near and far point, normalize(far - near)), which drifts when
// the camera is far from the origin.
enum class RayMethod { Robust, TwoPoint };
std::string rayMethodName(RayMethod method);  // "robust", "two_point"
std::optional<RayMethod> parseRayMethod(std::string_view text);
inline constexpr RayMethod kRayMethods[] = {RayMethod::Robust, RayMethod::TwoPoint};

// The ray through clip-space xy. two_point returns nullopt where it fails outright (an infinite far
// plane puts its far point at infinity). Never throws.
std::optional<Ray> pickRay(RayMethod method, const glm::dmat4& clipFromWorld, DepthMode mode,
                           glm::dvec2 clipXY);

// What the screen showed when the user clicked.
struct PickView {
  const Scene* scene = nullptr;
  glm::dmat4 clipFromWorld{1.0};
  DepthMode mode;
  DepthFormat depthFormat = DepthFormat::Float32;
  const RasterFrame* raster = nullptr;            // depth and ids read back from the same frame
  const SceneIntersector* intersector = nullptr;  // over the same (possibly teleported) scene
};

struct PickResult {
  glm::ivec2 pixel{0};  // lower-left origin, framebuffer pixels
  Viewport framebuffer;
  RayMethod method = RayMethod::Robust;
  DepthMode mode;
  DepthFormat depthFormat = DepthFormat::Float32;
  // 1. analytic ray
  int rayObject = -1;  // object index, -1: background (or no ray)
  std::optional<glm::dvec3> rayPoint;
  // 2. depth readback
  float windowDepth = 0.0f;
  std::optional<glm::dvec3> depthPoint;  // nullopt where the depth is the clear value
  // 3. id buffer
  int idObject = -1;
  std::uint32_t primitiveId = 0;
  // gaps between 1 and 2 (where both exist)
  std::optional<double> gapWorld;
  std::optional<double> gapPixels;  // gapWorld / one pixel's footprint at the depth point
  bool agree() const { return rayObject == idObject; }
};

// pixel must lie inside the raster frame.
PickResult pick(const PickView& view, RayMethod method, glm::ivec2 pixel);

// Projects a world point to continuous framebuffer coordinates (lower-left origin; pixel (i, j)
// covers [i, i+1) x [j, j+1)). nullopt behind the camera.
std::optional<glm::dvec2> framebufferFromWorld(const glm::dmat4& clipFromWorld, Viewport viewport,
                                               const glm::dvec3& world);

// {pixel, framebuffer, method, convention, depth_format, ray:{object, point}, depth:{point,
// window_depth}, id:{object}, gap_world, gap_px, agree}; absent values are null.
nlohmann::json pickJson(const PickResult& result, const Scene& scene, bool teleported);

}  // namespace clipray::demo
