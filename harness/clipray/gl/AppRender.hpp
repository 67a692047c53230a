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

// Calls `render` with `frame` (getProcAddress and framebuffer filled in here) and returns the
// depth and ids it drew. Throws GlError when the app leaves a GL error or no usable ids: every id
// 0 where it drew geometry, or an id no primitive of `scene` has (a colour clear of the integer
// attachment, or ids the app did not write as firstId + gl_PrimitiveID).
RasterFrame renderWithApp(GlContext& context, const AppRenderFunction& render, AppFrame frame,
                          const Scene& scene, RenderTimings* timings = nullptr);

}  // namespace clipray::gl
