#pragma once
// Primitive ids for a raster that knows only which draw call (scene mesh) covers each pixel: an
// app whose shaders write no ids, reconciled with one id per draw call (Reconcile.hpp, AppIds).
// The comparison needs the triangle: where the ray side hit a triangle of the same mesh, that one
// (the depth comparison then decides); elsewhere the triangle of that mesh the pixel centre's line
// of sight meets first, else the one whose projection lies nearest the pixel centre (a silhouette
// pixel the raster covered and the line of sight grazes past). clipFromWorld is column-major,
// p_clip = clipFromWorld * p_world, for `camera.mode`.

#include <cstdint>
#include <vector>

#include "clipray/Picking.hpp"
#include "clipray/compare/Frames.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray {

// meshOfPixel: 0 for background, else 1 + the index of the scene mesh drawn there, for every
// pixel of the viewport (row 0 at the bottom). Returns one primitive id per pixel.
std::vector<std::uint32_t> idsFromDrawCalls(const Scene& scene, const PickingCamera& camera,
                                            const std::vector<std::uint8_t>& meshOfPixel,
                                            const AnalyticFrame& analytic);

}  // namespace clipray
