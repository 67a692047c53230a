#pragma once
// The ray path's hit at a pixel the screen path decided from its triangle's planes (t NaN in
// AnalyticFrame::hits): what the compare classifies along the ray where the planes leave the
// pixel's class open. Bit for bit the hit the ray path would have found: the triangle's
// watertight test along the ray its group was traced along (DrawStateGroups.hpp): the frame's,
// or for an object with clip planes of its own the frame's cut by them too (the camera's planes,
// then the object's), its t then given along the frame's ray as the groups' merge gives it.

#include <cstdint>
#include <memory>
#include <vector>

#include "clipray/Picking.hpp"
#include "clipray/compare/PrimitiveClipPlanes.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "clipray/rays/RobustRays.hpp"

namespace clipray {

class PlanePixelHits {
 public:
  // frameRays: the frame's computed rays; objectPlanes: the scene's objects' own planes.
  PlanePixelHits(const PixelCentreRays& frameRays, const PrimitiveClipPlanes& objectPlanes);
  // The hit of the triangle primitiveId at pixel (x, y), whose frame ray is frameRay; the scene's
  // closest hit along frameRay should the triangle's test miss (a bound that failed).
  Hit rayPathHit(const SceneIntersector& intersector, std::uint32_t primitiveId, int x, int y,
                 const Ray& frameRay) const;

 private:
  const PrimitiveClipPlanes* objectPlanes_;
  // Per object with planes of its own (PrimitiveClipPlanes' order), its group's rays.
  std::vector<std::unique_ptr<const PixelCentreRays>> objectRays_;
};

}  // namespace clipray
