#include "Picking.hpp"

#include <cmath>

#include "clipray/rays/RobustRays.hpp"

namespace clipray::demo {

std::string rayMethodName(RayMethod method) {
  return method == RayMethod::Robust ? "robust" : "two_point";
}

std::optional<RayMethod> parseRayMethod(std::string_view text) {
  for (const RayMethod method : kRayMethods) {
    if (rayMethodName(method) == text) return method;
  }
  return std::nullopt;
}

namespace {

// two_point as apps write it (seed 003, GLU): everything in float, the matrix inverted once.
std::optional<Ray> twoPointFloat(const glm::dmat4& clipFromWorld, DepthMode mode,
                                 glm::dvec2 clipXY) {
  const glm::mat4 worldFromClip = glm::inverse(glm::mat4(clipFromWorld));
  const float x = static_cast<float>(clipXY.x), y = static_cast<float>(clipXY.y);
  const glm::vec4 nearH = worldFromClip * glm::vec4(x, y, static_cast<float>(mode.nearNdcZ()), 1);
  const glm::vec4 farH = worldFromClip * glm::vec4(x, y, static_cast<float>(mode.farNdcZ()), 1);
  const glm::vec3 nearPoint = glm::vec3(nearH) / nearH.w;
  const glm::vec3 farPoint = glm::vec3(farH) / farH.w;
  const glm::vec3 span = farPoint - nearPoint;
  const float length = glm::length(span);
  if (!std::isfinite(length) || !(length > 0.0f) || !std::isfinite(nearPoint.x) ||
      !std::isfinite(nearPoint.y) || !std::isfinite(nearPoint.z)) {
    return std::nullopt;
  }
  Ray ray;
  ray.origin = glm::dvec3(nearPoint);
  ray.direction = glm::normalize(glm::dvec3(span / length));
  ray.tMax = static_cast<double>(length);
  return ray;
}

glm::dvec3 unproject(const glm::dmat4& worldFromClip, const glm::dvec3& ndc) {
  const glm::dvec4 p = worldFromClip * glm::dvec4(ndc, 1.0);
  return glm::dvec3(p) / p.w;
}

nlohmann::json pointJson(const std::optional<glm::dvec3>& point) {
  if (!point) return nullptr;
  return nlohmann::json::array({point->x, point->y, point->z});
}

nlohmann::json objectJson(const Scene& scene, int object) {
  if (object < 0) return nullptr;
  return scene.objects[static_cast<std::size_t>(object)].name;
}

nlohmann::json optionalJson(const std::optional<double>& value) {
  if (!value) return nullptr;
  return *value;
}

}  // namespace

std::optional<Ray> pickRay(RayMethod method, const glm::dmat4& clipFromWorld, DepthMode mode,
                           glm::dvec2 clipXY) {
  if (method == RayMethod::TwoPoint) return twoPointFloat(clipFromWorld, mode, clipXY);
  return RobustRayGenerator(clipFromWorld, mode).generate(clipXY);
}

std::optional<glm::dvec2> framebufferFromWorld(const glm::dmat4& clipFromWorld, Viewport viewport,
                                               const glm::dvec3& world) {
  const glm::dvec4 clip = clipFromWorld * glm::dvec4(world, 1.0);
  if (!(clip.w > 0.0)) return std::nullopt;
  const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
  return glm::dvec2((ndc.x + 1.0) * 0.5 * viewport.width, (ndc.y + 1.0) * 0.5 * viewport.height);
}

PickResult pick(const PickView& view, RayMethod method, glm::ivec2 pixel) {
  const Scene& scene = *view.scene;
  const RasterFrame& raster = *view.raster;
  const Viewport viewport = raster.viewport;
  const PrimitiveIdTable ids(scene);
  PickResult result;
  result.pixel = pixel;
  result.framebuffer = viewport;
  result.method = method;
  result.mode = view.mode;
  result.depthFormat = view.depthFormat;
  const glm::dvec2 clipXY = clipXYOfPixelCentre(pixel.x, pixel.y, viewport);

  // 1. The analytic ray through the pixel centre.
  if (const std::optional<Ray> ray = pickRay(method, view.clipFromWorld, view.mode, clipXY)) {
    const Hit hit = view.intersector->closestHit(*ray);
    if (hit.hit()) {
      result.rayObject = ids.decode(hit.primitiveId).object;
      result.rayPoint = ray->origin + hit.t * ray->direction;
    }
  }

  // 2. and 3. What the raster stored at that pixel.
  const std::size_t index = static_cast<std::size_t>(pixel.y) * viewport.width + pixel.x;
  result.windowDepth = raster.depth[index];
  result.primitiveId = raster.ids[index];
  result.idObject = ids.decode(result.primitiveId).object;
  const glm::dmat4 worldFromClip = glm::inverse(view.clipFromWorld);
  const float clearDepth = view.mode.reversed ? 0.0f : 1.0f;
  if (result.windowDepth != clearDepth) {
    const double zNdc = ndcFromWindowDepth(result.windowDepth, view.mode.convention);
    result.depthPoint = unproject(worldFromClip, glm::dvec3(clipXY, zNdc));
  }

  if (result.rayPoint && result.depthPoint) {
    result.gapWorld = glm::distance(*result.rayPoint, *result.depthPoint);
    // One pixel's footprint at the depth point: the next pixel centre at the same NDC depth.
    const double zNdc = ndcFromWindowDepth(result.windowDepth, view.mode.convention);
    const glm::dvec3 neighbour =
        unproject(worldFromClip, glm::dvec3(clipXY.x + 2.0 / viewport.width, clipXY.y, zNdc));
    const double footprint = glm::distance(neighbour, *result.depthPoint);
    if (footprint > 0.0 && std::isfinite(footprint))
      result.gapPixels = *result.gapWorld / footprint;
  }
  return result;
}

nlohmann::json pickJson(const PickResult& result, const Scene& scene, bool teleported) {
  nlohmann::json line;
  line["pixel"] = {result.pixel.x, result.pixel.y};
  line["framebuffer"] = {result.framebuffer.width, result.framebuffer.height};
  line["method"] = rayMethodName(result.method);
  line["convention"] = result.mode.name();
  line["depth_format"] = depthFormatName(result.depthFormat);
  line["teleported"] = teleported;
  line["ray"] = {{"object", objectJson(scene, result.rayObject)},
                 {"point", pointJson(result.rayPoint)}};
  line["depth"] = {{"point", pointJson(result.depthPoint)},
                   {"window_depth", static_cast<double>(result.windowDepth)}};
  line["id"] = {{"object", objectJson(scene, result.idObject)}};
  line["gap_world"] = optionalJson(result.gapWorld);
  line["gap_px"] = optionalJson(result.gapPixels);
  line["agree"] = result.agree();
  return line;
}

}  // namespace clipray::demo
