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

// The state one of the app's draw calls was made with, read with glGet* just before the call:
// what the app's frame was drawn under, to set beside what the run says it is drawn under.
struct AppDrawState {
  ClipOrigin origin = ClipOrigin::LowerLeft;
  DepthConvention convention = DepthConvention::NegativeOneToOne;
  glm::dvec2 depthRange{0.0, 1.0};
  bool depthTest = false;
  std::uint32_t depthFunc = 0x0201;  // GL_LESS
  CullFace cull = CullFace::None;    // None also for GL_FRONT_AND_BACK (see cullsEverything)
  bool cullsEverything = false;      // glCullFace(GL_FRONT_AND_BACK) with culling enabled
  FrontFace frontFace = FrontFace::Ccw;
  bool depthClamp = false;
  // GL_POLYGON_OFFSET_FILL enabled: glPolygonOffsetClamp's factor, units and clamp (clamp 0 where
  // the implementation has no GL_POLYGON_OFFSET_CLAMP to read).
  std::optional<PolygonOffset> polygonOffset{};
  friend bool operator==(const AppDrawState&, const AppDrawState&) = default;
};

struct AppRaster {
  RasterFrame frame;  // depth; ids with AppIds::Written (sample 0 if multisampled)
  // A multisampled frame (AppFrame::samples above 1): sample s of every pixel, and where it lies
  // in its pixel (MultisampleTarget::samplePositions).
  std::vector<RasterFrame> samples;
  std::vector<glm::dvec2> samplePositions;
  std::vector<AppDrawState> draws;  // one per draw call, in order
  // With AppIds::PerDrawCall: 0 background, else 1 + the mesh whose draw call shows at the pixel
  // (idsFromDrawCalls turns them into ids).
  std::vector<std::uint8_t> meshOfPixel;
};

// Calls `render` with `frame` (getProcAddress and framebuffer filled in here) and returns the
// depth and ids (or meshes) it drew, and the state of each of its draw calls (the draw functions
// it loads through getProcAddress are clipray's, which read the state and then draw). Throws
// GlError when the app leaves a GL error or no usable ids: every id 0 where it drew geometry, an id
// no primitive of `scene` has (a colour clear of the integer attachment, or ids the app did not
// write as firstId + gl_PrimitiveID), or more draw calls than the scene has meshes; InputError for
// one id per draw call without a stencil (16) or in a multisampled frame. With frame.samples above
// 1 (a count the implementation offers) the framebuffer's attachments are multisample textures
// with fixed sample locations, and every sample is read.
AppRaster renderWithApp(GlContext& context, const AppRenderFunction& render, AppFrame frame,
                        AppIds ids, const Scene& scene, RenderTimings* timings = nullptr);

}  // namespace clipray::gl
