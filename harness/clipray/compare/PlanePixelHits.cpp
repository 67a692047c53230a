#include "clipray/compare/PlanePixelHits.hpp"

#include <span>

namespace clipray {

PlanePixelHits::PlanePixelHits(const PixelCentreRays& frameRays,
                               const PrimitiveClipPlanes& objectPlanes)
    : objectPlanes_(&objectPlanes) {
  const RobustRayGenerator& frame = frameRays.generator();
  for (std::size_t k = 0; k < objectPlanes.objectCount(); ++k) {
    std::vector<glm::dvec4> planes(frame.clipPlanes().begin(), frame.clipPlanes().end());
    const std::span<const glm::dvec4> own = objectPlanes.planesOfObject(k);
    planes.insert(planes.end(), own.begin(), own.end());
    objectRays_.push_back(std::make_unique<const PixelCentreRays>(
        frame.clipFromWorld(), frame.mode(), frameRays.viewport(), planes, frame.depthClamp()));
  }
}

Hit PlanePixelHits::rayPathHit(const SceneIntersector& intersector, std::uint32_t primitiveId,
                               int x, int y, const Ray& frameRay) const {
  const std::size_t object = objectPlanes_->objectOf(primitiveId);
  if (object >= objectRays_.size()) {
    const Hit hit = intersector.intersectOne(primitiveId, frameRay);
    return hit.hit() ? hit : intersector.closestHit(frameRay);
  }
  // The object's ray starts where its planes cut the frame's (DrawStateGroups.cpp's merge,
  // operation for operation).
  Ray cut;
  objectRays_[object]->row(y, x, 1, &cut);
  Hit hit = intersector.intersectOne(primitiveId, cut);
  if (!hit.hit()) return intersector.closestHit(frameRay);
  const glm::dvec3 point = cut.origin + hit.t * cut.direction;
  hit.t = glm::dot(point - frameRay.origin, frameRay.direction) /
          glm::dot(frameRay.direction, frameRay.direction);
  return hit;
}

}  // namespace clipray
