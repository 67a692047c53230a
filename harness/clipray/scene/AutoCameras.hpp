#pragma once
// Cameras framed on a scene's bounds, for assets that ship without one (`clipray reconcile
// model.glb`, and a scene file with "cameras": "auto"). Each looks at the geometry a different
// way a reconcile should see it (docs/scene-format.md, "Automatic cameras"):
//   auto_three_quarter    perspective, 45 deg, from above front-right, the bounding sphere in view
//   auto_grazing          perspective, 45 deg, the eye just above the lowest large upward surface
//                         (a floor, a terrain), looking across it: depth at shallow angles
//   auto_orthographic_X   orthographic along the bounding box's thinnest axis (x, y or z), which
//                         shows the model's largest side
//   auto_near_cut         perspective, 60 deg, the near plane through the bounding box's centre:
//                         the clipped-open model (the rasterizer's near clipping against the rays'
//                         near-plane origins)
// World y is up (glTF's convention, and the usual one for OBJ and PLY). Each camera's
// projection is built for whatever convention a run draws under.

#include <vector>

#include "clipray/scene/Scene.hpp"

namespace clipray {

// The four cameras for the scene's meshes and bounded analytic primitives (an unbounded plane
// has no bounds to frame), at the given viewport. Throws InputError naming scene.path when
// there is nothing finite to frame.
std::vector<Camera> autoCameras(const Scene& scene, Viewport viewport = {640, 480});

}  // namespace clipray
