#include "clipray/engine/MultisampleRun.hpp"

#include <stdexcept>
#include <utility>

namespace clipray::engine {

glm::dmat4 clipFromWorldAtSample(const glm::dmat4& clipFromWorld, ClipOrigin origin,
                                 Viewport viewport, glm::dvec2 samplePosition) {
  const double dx = 2.0 * (0.5 - samplePosition.x) / viewport.width;
  const double dyWindow = 2.0 * (0.5 - samplePosition.y) / viewport.height;
  const double dy = origin == ClipOrigin::UpperLeft ? -dyWindow : dyWindow;
  // x_clip += dx w_clip, y_clip += dy w_clip: NDC moves by (dx, dy) wherever w > 0. Glm is
  // column-major: element [column][row].
  glm::dmat4 sheared = clipFromWorld;
  for (int column = 0; column < 4; ++column) {
    sheared[column][0] += dx * clipFromWorld[column][3];
    sheared[column][1] += dy * clipFromWorld[column][3];
  }
  return sheared;
}

MultisampleCamera::MultisampleCamera(const Scene& scene, const Camera& camera, DepthMode mode,
                                     Viewport viewport, unsigned threadCount,
                                     PickRayFunction rayFunction, PickHitFunction hitFunction)
    : scene_(&scene),
      camera_(&camera),
      mode_(mode),
      viewport_(viewport),
      threadCount_(threadCount),
      rayFunction_(std::move(rayFunction)),
      hitFunction_(std::move(hitFunction)),
      drawnClipFromWorld_(camera.clipFromWorld(mode, viewport)) {}

const std::vector<AnalyticPass>& MultisampleCamera::passesAt(
    const std::vector<glm::dvec2>& positions) {
  if (positions == positions_ && !passes_.empty()) return passes_;
  passes_.clear();
  positions_ = positions;
  for (const glm::dvec2 position : positions) {
    Camera atSample = *camera_;
    atSample.rawClipFromWorld =
        clipFromWorldAtSample(drawnClipFromWorld_, mode_.origin, viewport_, position);
    // The app's function is told which sample it is asked for (PickingCamera::samplePosition).
    const auto asked = [position, drawn = drawnClipFromWorld_](const PickingCamera& camera) {
      PickingCamera atPosition = camera;
      atPosition.samplePosition = position;
      atPosition.drawnClipFromWorld = drawn;
      return atPosition;
    };
    // The pass keeps its camera's name only: the sheared copy may go.
    if (hitFunction_) {
      const PickHitFunction atSampleHits = [hits = hitFunction_, asked](
                                               int x, int y, const PickingCamera& camera) {
        return hits(x, y, asked(camera));
      };
      passes_.push_back(
          runAnalyticPass(*scene_, atSample, mode_, viewport_, atSampleHits, threadCount_));
    } else if (rayFunction_) {
      const PickRayFunction atSampleRays = [rays = rayFunction_, asked](
                                               int x, int y, const PickingCamera& camera) {
        return rays(x, y, asked(camera));
      };
      passes_.push_back(
          runAnalyticPass(*scene_, atSample, mode_, viewport_, atSampleRays, threadCount_));
    } else {
      passes_.push_back(runAnalyticPass(*scene_, atSample, mode_, viewport_, threadCount_));
    }
  }
  return passes_;
}

SampleComparison MultisampleCamera::rasterAndCompare(gl::Renderer& renderer,
                                                     DepthFormat depthFormat, VertexMode vertexMode,
                                                     int samples) {
  SampleComparison result;
  result.positions = renderer.samplePositions(depthFormat, samples, viewport_);
  const std::vector<AnalyticPass>& passes = passesAt(result.positions);
  // Drawn with the camera's own matrix, measured from sample 0's reference point (any point
  // serves the raster; the passes' references differ by less than a pixel's footprint).
  gl::RenderRequest request = renderRequest(passes.front(), depthFormat, vertexMode);
  request.clipFromWorld = drawnClipFromWorld_;
  request.samples = samples;
  gl::RenderTimings timings;
  gl::MultisampleFrame frame = renderer.renderSamples(request, &timings);
  if (frame.positions != result.positions) {
    throw gl::GlError("GL: the sample positions changed between the query and the draw");
  }
  return compareSamples(std::move(frame.samples), result.positions, depthFormat, vertexMode,
                        renderer.info().subpixelBits, timings);
}

SampleComparison MultisampleCamera::compareSamples(std::vector<RasterFrame> rasters,
                                                   const std::vector<glm::dvec2>& positions,
                                                   DepthFormat depthFormat, VertexMode vertexMode,
                                                   int subpixelBits,
                                                   const gl::RenderTimings& timings) {
  SampleComparison result;
  result.positions = positions;
  const std::vector<AnalyticPass>& passes = passesAt(positions);
  const int samples = static_cast<int>(positions.size());
  for (std::size_t s = 0; s < rasters.size(); ++s) {
    result.samples.push_back(compareRasterFrame(passes[s], rasters[s], depthFormat, vertexMode,
                                                subpixelBits, timings, threadCount_));
  }

  const std::size_t count = static_cast<std::size_t>(viewport_.width) * viewport_.height;
  MultisamplePixels& pixels = result.pixels;
  pixels.pixels = static_cast<std::int64_t>(count);
  for (std::size_t i = 0; i < count; ++i) {
    bool anyCovered = false, anyBackground = false, unexplained = false, mixed = false;
    std::uint32_t firstId = 0;
    for (std::size_t s = 0; s < rasters.size(); ++s) {
      const std::uint32_t id = rasters[s].ids[i];
      if (id == 0) {
        anyBackground = true;
      } else {
        if (anyCovered && id != firstId) mixed = true;
        if (!anyCovered) firstId = id;
        anyCovered = true;
      }
      const PixelClass c = result.samples[s].pixels.classes[i];
      unexplained = unexplained || c == PixelClass::CoverageUnexplained ||
                    c == PixelClass::IdUnexplained || c == PixelClass::DepthBeyondTolerance;
    }
    pixels.covered += anyCovered ? 1 : 0;
    pixels.partlyCovered += anyCovered && anyBackground ? 1 : 0;
    pixels.mixedPrimitives += mixed ? 1 : 0;
    pixels.unexplained += unexplained ? 1 : 0;
  }
  for (std::size_t s = 0; s < result.samples.size(); ++s) {
    result.samples[s].run.sample =
        SampleRecord{static_cast<int>(s), samples, result.positions[s], pixels};
  }
  result.rasters = std::move(rasters);
  return result;
}

}  // namespace clipray::engine
