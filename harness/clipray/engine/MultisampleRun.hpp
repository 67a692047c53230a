#pragma once
// A multisampled run: the frame drawn once with N samples per pixel (gl::Renderer::renderSamples)
// and each sample compared with an analytic pass of its own, whose rays go through that sample's
// position instead of the pixel centre. The pass of sample s traces the camera's matrix sheared by
// clipFromWorldAtSample, which moves the image so that the sample position lands on the pixel
// centre the rays are built through: every existing ray method, intersector and tolerance model
// then evaluates coverage and depth at the sample. The shear adds multiples of the w row to the x
// and y rows only, so z, w and the window depth are the matrix's own.
//
//   MultisampleCamera sampled(scene, scene.cameras[0], kZeroToOne, viewport);
//   SampleComparison run = sampled.rasterAndCompare(renderer, DepthFormat::Float32,
//                                                  VertexMode::World, 4);
//   EXPECT_EQ(run.pixels.unexplained, 0);

#include <cstdint>
#include <map>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/engine/ReconcileRun.hpp"

namespace clipray::engine {

// clipFromWorld (as drawn under `origin` at `viewport`) sheared so that what it puts at window
// position (x + p.x, y + p.y) lands at (x + 0.5, y + 0.5): NDC x moves by 2 (0.5 - p.x) / width,
// NDC y by 2 (0.5 - p.y) / height (negated for an upper-left origin, whose window y runs against
// NDC y). Column-major, p_clip = clipFromWorld * p_world.
glm::dmat4 clipFromWorldAtSample(const glm::dmat4& clipFromWorld, ClipOrigin origin,
                                 Viewport viewport, glm::dvec2 samplePosition);

struct SampleComparison {
  std::vector<glm::dvec2> positions;  // as the implementation reports them
  std::vector<ComparedRun> samples;   // sample s's run, compared with its own pass
  std::vector<RasterFrame> rasters;   // sample s of every pixel, as read back
  MultisamplePixels pixels;
  bool consistent() const { return pixels.unexplained == 0; }
};

// One camera under one convention, reconciled at several samples per pixel. The sample passes are
// made for the positions the renderer reports and kept while they stay the same (every depth
// format and vertex mode at one count shares them).
class MultisampleCamera {
 public:
  // With clipray's robust rays, or with the caller's ray function or hit function (the app's
  // picking), asked with each sample's sheared camera, PickingCamera::samplePosition and
  // drawnClipFromWorld set (pickingInWindow asks the app at the sample's window position).
  MultisampleCamera(const Scene& scene, const Camera& camera, DepthMode mode, Viewport viewport,
                    unsigned threadCount = 0, PickRayFunction rayFunction = {},
                    PickHitFunction hitFunction = {});
  // The sample passes for these positions (made on first use).
  const std::vector<AnalyticPass>& passesAt(const std::vector<glm::dvec2>& positions);
  SampleComparison rasterAndCompare(gl::Renderer& renderer, DepthFormat depthFormat,
                                    VertexMode vertexMode, int samples);
  // The same for a frame drawn elsewhere (the app's render function): `rasters` sample s of every
  // pixel, at `positions`.
  SampleComparison compareSamples(std::vector<RasterFrame> rasters,
                                  const std::vector<glm::dvec2>& positions, DepthFormat depthFormat,
                                  VertexMode vertexMode, int subpixelBits,
                                  const gl::RenderTimings& timings);
  const glm::dmat4& drawnClipFromWorld() const { return drawnClipFromWorld_; }

 private:
  const Scene* scene_;
  const Camera* camera_;
  DepthMode mode_;
  Viewport viewport_;
  unsigned threadCount_;
  PickRayFunction rayFunction_;
  PickHitFunction hitFunction_;
  glm::dmat4 drawnClipFromWorld_;
  std::vector<glm::dvec2> positions_;
  std::vector<AnalyticPass> passes_;
};

}  // namespace clipray::engine
