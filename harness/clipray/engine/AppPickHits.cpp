#include "clipray/engine/AppPickHits.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "clipray/engine/ReconcileRun.hpp"

namespace clipray::engine {

namespace {

std::string pixelText(std::size_t i, int width) {
  // Appended piece by piece: GCC 12's -Wrestrict misfires on "(" + std::to_string(...).
  std::string text = "(";
  text += std::to_string(i % static_cast<std::size_t>(width));
  text += ", ";
  text += std::to_string(i / static_cast<std::size_t>(width));
  text += ")";
  return text;
}

// The primitive id of the app's hit at pixel i (0: it hit nothing).
std::uint32_t primitiveIdOf(const PickHit& pick, const Scene& scene, const PrimitiveIdTable& table,
                            const SceneIntersector& intersector, const Ray& ray, std::size_t i,
                            int width) {
  if (!pick.mesh) return 0;
  const std::string at = "PickHit at pixel " + pixelText(i, width);
  if (*pick.mesh >= scene.objects.size()) {
    throw InputError(at + ": mesh " + std::to_string(*pick.mesh) + ", but the scene has " +
                     std::to_string(scene.objects.size()) + " meshes");
  }
  if (!(std::isfinite(pick.t) && pick.t > 0.0)) {
    throw InputError(at + ": t " + std::to_string(pick.t) +
                     ", expected a finite distance along the ray, above 0");
  }
  const MeshObject& object = scene.objects[*pick.mesh];
  const std::uint32_t firstId = table.firstIdOfObject[*pick.mesh];
  if (pick.triangle) {
    if (*pick.triangle >= object.triangles.size()) {
      throw InputError(at + ": triangle " + std::to_string(*pick.triangle) + " of mesh \"" +
                       object.name + "\", which has " + std::to_string(object.triangles.size()));
    }
    return firstId + *pick.triangle;
  }
  // The mesh's triangle met nearest to t (culled ones too: the app may hit what the picture
  // culls), by the intersector's own test; a ray that meets none keeps triangle 0, and the
  // compare shows the miss.
  std::uint32_t best = firstId;
  double bestGap = std::numeric_limits<double>::infinity();
  for (std::uint32_t k = 0; k < object.triangles.size(); ++k) {
    const std::array<glm::dvec3, 3> v = intersector.worldTriangle(firstId + k);
    // intersectOne skips culled triangles: Moller-Trumbore here, t along the unbounded ray.
    const glm::dvec3 e1 = v[1] - v[0], e2 = v[2] - v[0];
    const glm::dvec3 p = glm::cross(ray.direction, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0) continue;
    const glm::dvec3 s = ray.origin - v[0];
    const double u = glm::dot(s, p) / det;
    const glm::dvec3 q = glm::cross(s, e1);
    const double w = glm::dot(ray.direction, q) / det;
    if (u < 0.0 || w < 0.0 || u + w > 1.0) continue;
    const double gap = std::abs(glm::dot(e2, q) / det - pick.t);
    if (gap < bestGap) bestGap = gap, best = firstId + k;
  }
  return best;
}

}  // namespace

void takeAppPickHits(AnalyticPass& pass, const PickHitFunction& pick, unsigned threadCount) {
  const Viewport viewport = pass.drawnCamera.viewport;
  const std::size_t count = static_cast<std::size_t>(viewport.width) * viewport.height;
  std::vector<std::optional<PickHit>> picked(count);
  // generateRays asks each pixel once on the worker threads (and pixel (0, 0) once more first, to
  // warm the app's per-camera state): each call writes its own pixel's slot.
  const PickRayFunction rays = [&](int x, int y,
                                   const PickingCamera& camera) -> std::optional<Ray> {
    std::optional<PickHit> hit = pick(x, y, camera);
    std::optional<Ray> ray;
    if (hit) ray = hit->ray;
    picked[static_cast<std::size_t>(y) * viewport.width + x] = std::move(hit);
    return ray;
  };
  pass.frame = generateRays(pass.drawnCamera, rays, threadCount);
  pass.frame.hits.resize(count);

  const Scene& scene = *pass.scene;
  const PrimitiveIdTable table(scene);
  const SceneIntersector& intersector = *pass.intersector;
  std::size_t culledHits = 0, firstCulled = 0;
  for (std::size_t i = 0; i < count; ++i) {
    Hit& hit = pass.frame.hits[i];
    hit = Hit{};
    if (!picked[i]) continue;
    const std::uint32_t id =
        primitiveIdOf(*picked[i], scene, table, intersector, pass.frame.rays[i], i, viewport.width);
    if (id == 0) continue;
    hit = {picked[i]->t, id};
    if (intersector.culled(id) && culledHits++ == 0) firstCulled = i;
  }
  if (culledHits > 0) {
    const PrimitiveIdTable::Decoded first = table.decode(pass.frame.hits[firstCulled].primitiveId);
    pass.pickNotes.push_back(
        "the app's picking hit faces the picture culls at " + std::to_string(culledHits) +
        " px (first at pixel " + pixelText(firstCulled, viewport.width) + ": \"" +
        scene.objects[static_cast<std::size_t>(first.object)].name + "\" triangle " +
        std::to_string(first.triangle) +
        "): face culling leaves them out of the picture, so a click there picks what is not "
        "shown; the picking must cull the faces the draw culls");
  }
}

}  // namespace clipray::engine
