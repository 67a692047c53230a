#pragma once
// The raster side drawn by the app's own render function (ReconcileOptions::render): clipray makes
// the framebuffer (colour 0 RGBA8, colour 1 R32UI ids, depth in the run's format), hands the app
// GL's default state, and reads back what the app drew. Needs the GL entry points loaded (a
// Renderer on the current context).

#include "clipray/Reconcile.hpp"
#include "clipray/compare/Frames.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/gl/Renderer.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::gl {

struct AppRaster {
  RasterFrame frame;  // depth; ids with AppIds::Written
  // With AppIds::PerDrawCall: 0 background, else 1 + the mesh whose draw call shows at the pixel
  // (idsFromDrawCalls turns them into ids).
  std::vector<std::uint8_t> meshOfPixel;
};

// Calls `render` with `frame` (getProcAddress and framebuffer filled in here) and returns the
// depth and ids (or meshes) it drew. Throws GlError when the app leaves a GL error or no usable
// ids: every id 0 where it drew geometry, an id no primitive of `scene` has (a colour clear of
// the integer attachment, or ids the app did not write as firstId + gl_PrimitiveID), or more draw
// calls than the scene has meshes; InputError for one id per draw call without a stencil (16).
AppRaster renderWithApp(GlContext& context, const AppRenderFunction& render, AppFrame frame,
                        AppIds ids, const Scene& scene, RenderTimings* timings = nullptr);

}  // namespace clipray::gl
