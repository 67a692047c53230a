#pragma once
// The raster pass: draws a scene into an FBO (selected depth format + R32UI primitive ids) under
// a depth convention and vertex mode, and reads depth (GL_FLOAT) and ids back.
// RenderRequest::clipFromWorld: column-major, p_clip = clipFromWorld * p_world, built for its mode.

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/compare/Frames.hpp"
#include "clipray/compare/LogarithmicDepth.hpp"
#include "clipray/gl/GlContext.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::gl {

// A GL call failed or a shader did not compile/link; the message carries the info log.
class GlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A shader info log with its source-string numbers ("2:14(3): error ...") replaced by the file
// names of those strings (files[n - 1]): how a compile error names the GLSL file it is in.
std::string nameShaderSources(const std::string& log, const std::vector<std::string>& files);

struct RenderRequest {
  const Scene* scene = nullptr;
  glm::dmat4 clipFromWorld{1.0};
  DepthMode mode;
  DepthFormat depthFormat = DepthFormat::Float32;
  VertexMode vertexMode = VertexMode::World;
  glm::dvec3 vertexReference{0.0};  // removed on the CPU in camera-relative mode
  Viewport viewport;
  glm::dvec2 depthRange{0.0, 1.0};  // glDepthRange(n, f) (Scene::depthRange)
  // The camera's user clip planes, world space (Camera::clipPlanes): gl_ClipDistance for meshes.
  std::vector<glm::dvec4> clipPlanes{};
  bool depthClamp = false;  // GL_DEPTH_CLAMP (Scene::depthClamp)
  // Samples per pixel: 1 draws single-sampled (render); more draws into multisample attachments
  // with GL_MULTISAMPLE enabled (renderSamples), triangle meshes only.
  int samples = 1;
  // The meshes' fragment shader writes this logarithmic depth (shaders/log_depth.frag) in place
  // of the projective one; nullopt: it writes none.
  std::optional<LogDepthMapping> logDepth{};
};

// A multisampled frame read one sample at a time: samples[s] holds sample s of every pixel, laid
// out as a single-sample frame; positions[s] is where it lies in its pixel (glGetMultisamplefv:
// window coordinates from the pixel's lower-left corner, in pixels).
struct MultisampleFrame {
  std::vector<glm::dvec2> positions;
  std::vector<RasterFrame> samples;
};

struct RenderTimings {  // milliseconds
  double raster = 0.0;
  double readback = 0.0;
  // The process's CPU time in each (all threads: the driver's too; see PhaseClock).
  double rasterCpu = 0.0;
  double readbackCpu = 0.0;
};

class Renderer {
 public:
  // Takes the current context, loads GL through its loader, checks GL >= 4.5 (glClipControl),
  // compiles the shaders.
  explicit Renderer(GlContext& context);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  const GlInfo& info() const { return info_; }
  // min(GL_MAX_VIEWPORT_DIMS, GL_MAX_RENDERBUFFER_SIZE) per axis.
  Viewport maxViewport() const { return maxViewport_; }

  // Single-sampled (request.samples == 1).
  RasterFrame render(const RenderRequest& request, RenderTimings* timings = nullptr);
  // Multisampled (request.samples one of sampleCounts(request.depthFormat)): every sample read.
  // Analytic primitives write one depth per fragment (gl_FragDepth at the pixel centre) and are
  // refused.
  MultisampleFrame renderSamples(const RenderRequest& request, RenderTimings* timings = nullptr);
  // The sample counts above 1 this implementation offers for the depth format beside R32UI ids,
  // ascending; empty where it offers none.
  std::vector<int> sampleCounts(DepthFormat depthFormat);
  // Where each of `samples` samples lies in a pixel of a multisample frame of this depth format
  // and size (as MultisampleFrame::positions), before anything is drawn: the analytic side builds
  // its rays through them. BackendError for a count sampleCounts does not list.
  std::vector<glm::dvec2> samplePositions(DepthFormat depthFormat, int samples, Viewport viewport);

 private:
  struct State;
  std::unique_ptr<State> state_;
  GlInfo info_;
  Viewport maxViewport_;
};

// Whether the current context lists the extension (glGetStringi, GL 3.0 core; the entry points
// loaded by a Renderer).
bool hasGlExtension(std::string_view name);

}  // namespace clipray::gl
