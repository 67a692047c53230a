#pragma once
// Reconciling a scene from a test: the app's picking rays against a headless raster, pixel for
// pixel (docs/library.md). The raster is clipray's own renderer, or the app's render function
// (ReconcileOptions::render) drawing into clipray's framebuffer with the app's shaders and GL
// state, so that a wrong clip control, depth function or viewport in the app's render code fails
// too. Pixels are GL's: (x, y) integer indices from the viewport's lower-left corner.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "clipray/Conventions.hpp"
#include "clipray/GlFunctions.hpp"
#include "clipray/InputError.hpp"
#include "clipray/Picking.hpp"
#include "clipray/SceneBuilder.hpp"

namespace clipray {

// What the app's render function gets, with clipray's headless GL 4.5 core context current and
// `framebuffer` bound to GL_FRAMEBUFFER: the app's window's framebuffer (ReconcileOptions::window;
// without one, the camera's viewport is the whole framebuffer); clipray reads back the camera's
// viewport at `viewport` from it, so a wrong glViewport shows. Its attachments: colour 0 RGBA8 (the
// app's colour), colour 1 R32UI (primitive ids), both already cleared to 0 and both draw buffers;
// depth in the run's format, filled with 0.5 (not cleared: clearing it is the app's job, with its
// own clear value). The rest of the GL state is GL's default (NEGATIVE_ONE_TO_ONE, GL_LESS, depth
// test off, depth range [0, 1], viewport the whole framebuffer): the app sets what it draws with.
// The function draws the scene's meshes as the test built them and says what it drew at each
// pixel (AppIds): by writing to colour 1 the id firstId(mesh) + gl_PrimitiveID of each fragment,
// or, for shaders that write no ids, with one draw call per mesh in the order the scene added
// them, through functions loaded with getProcAddress. It must clear depth only (glClear of an
// integer attachment with a float colour is undefined) and leave `framebuffer` bound.
struct AppFrame {
  GlGetProcAddress getProcAddress = nullptr;  // load the app's GL functions through this
  unsigned framebuffer = 0;
  Viewport size;           // the framebuffer's
  glm::ivec4 viewport{0};  // x, y, width, height: the region clipray compares
  PickingCamera camera;    // the run's camera and the convention the test expects
  DepthFormat depthFormat = DepthFormat::Float32;
  // Samples per pixel of the attachments (ReconcileOptions::samples): above 1 they are multisample
  // textures with fixed sample locations, GL_MULTISAMPLE is on (GL's default), and clipray reads
  // every sample of depth and ids; the app draws as it draws into its own multisampled window.
  int samples = 1;
  std::vector<std::uint32_t> firstIds;  // id of triangle 0 of each mesh, in the order added
  std::uint32_t firstId(std::size_t mesh) const { return firstIds.at(mesh); }
};
using AppRenderFunction = std::function<void(const AppFrame&)>;

// How the app's render function tells clipray which primitive it drew at each pixel.
enum class AppIds {
  // Its fragment shader writes firstId(mesh) + gl_PrimitiveID to colour attachment 1
  // (layout(location = 1) out uint): the comparison is triangle by triangle.
  Written,
  // It writes no ids: clipray counts the draw calls it makes through getProcAddress's functions
  // (glDraw*, glMultiDraw*: call k draws mesh k) and marks each call's visible fragments in the
  // stencil buffer. Needs depth formats 24 or 32f (with stencil) and an app that does not use the
  // stencil itself; at most 255 draw calls. Where the ray side hit another triangle of the same
  // mesh, that triangle is taken for the raster's; elsewhere the mesh's triangle met first by the
  // pixel centre's line of sight, else the one projecting nearest to it.
  PerDrawCall,
};

struct ReconcileOptions {
  std::vector<DepthMode> conventions;  // empty: the scene's own ("conventions"), else zo
  std::vector<DepthFormat> depthFormats = {DepthFormat::Float32};
  VertexMode vertexMode = VertexMode::World;  // clipray's renderer only
  std::vector<std::string> cameras;           // empty: every camera of the scene
  std::string backend = "osmesa";             // or "egl"
  // Where to write the report of the runs, as `clipray reconcile --out` writes it (report.json,
  // index.html with every run's thumbnails, each inconsistent run's PNGs and cluster crops, or
  // every run's with imagesForEveryRun), claimed and locked before the runs start; empty: nothing
  // is written.
  std::string reportDirectory;
  bool imagesForEveryRun = false;
  std::size_t worstPixels = 5;  // how many pixels each run describes
  // The app's window: reports name pixels in its coordinates too (as pickingInWindow maps them),
  // and the app's render function draws into a framebuffer of its size.
  std::optional<AppWindow> window;
  AppRenderFunction render;  // set: the app draws the raster side
  AppIds appIds = AppIds::Written;
  unsigned threads = 0;  // 0: every core
  // Samples per pixel: above 1 every frame is drawn multisampled (a count the GL implementation
  // offers), by clipray's renderer or the app's render function (AppFrame::samples; its ids
  // written, AppIds::Written), and each sample is a run of its own (RunResult::sample), compared
  // with rays through its position: pickingInWindow asks the app at the sample's window position
  // (a raw PickRayFunction gets the camera sheared to put the sample on the pixel centre,
  // PickingCamera::samplePosition). 0: the scene's own (SceneBuilder::samples), else 1.
  int samples = 0;
  // A folder for RenderDoc captures of the app's frames that fail: while RenderDoc is loaded into
  // the process (LD_PRELOAD=librenderdoc.so, Debian's librenderdoc) and with the "egl" backend
  // (RenderDoc hooks EGL, not OSMesa), each frame the render function draws is captured through
  // RenderDoc's in-app API; a failing run's frame is kept as
  // <scene>-<camera>-<convention>-<depth format>.rdc (RunResult::capture), to open in RenderDoc or
  // give to `clipray reconcile --capture`; a passing run's is removed. Without RenderDoc a failing
  // run notes why it has no capture. Empty: nothing is captured.
  std::string renderDocCaptures;
};

// One pixel of a run, as both sides saw it.
struct PixelReport {
  int x = 0, y = 0;                  // viewport pixel, lower-left origin
  std::optional<glm::dvec2> window;  // its centre in the app's window coordinates
  std::string pixelClass;  // pixel class: "coverage_unexplained", "depth_beyond_tolerance", ...
  std::string rasterHit, rayHit;  // "\"floor\" triangle 12", "\"ball\" (sphere)", "nothing"
  double rasterDepth = 0.0, rayDepth = 0.0;  // window depth; NaN where that side hit nothing
  double toleranceRatio = 0.0;  // |depth error| / predicted tolerance; NaN: not compared
  std::string text() const;     // one line
};

struct RunResult {
  std::string scene, camera, convention, depthFormat, vertexMode;  // "zo", "32f", "world"
  bool appRender = false;  // the raster side is the app's render function
  Viewport size;
  // For a multisampled frame (ReconcileOptions::samples): which sample this run compares, of how
  // many, and where it lies in the pixel (window coordinates from the lower-left corner, pixels);
  // sampleCount 1 otherwise. A pixel of the frame is unexplained where any of its samples is:
  // frameUnexplainedPixels counts them (the same on each of the frame's runs).
  int sample = 0, sampleCount = 1;
  glm::dvec2 samplePosition{0.5, 0.5};
  std::int64_t framePartlyCoveredPixels = 0, frameUnexplainedPixels = 0;
  // The run passes: verdict "consistent". It fails as "inconsistent" where raster and rays
  // disagree beyond what is explained, else as "convention-error" where `clipray check` on the
  // camera under the run's state (clip control, depth range, face culling, depth clamp) finds an
  // error the scene does not declare (SceneBuilder::expectedFindings).
  bool consistent = false;
  std::string verdict;  // "consistent", "inconsistent" or "convention-error"
  // That check's errors and warnings, one line each: "error [depth-convention-mismatch] built for
  // ... (expected by the scene)".
  std::vector<std::string> conventionFindings;
  std::int64_t pixels = 0, rasterHits = 0, rayHits = 0;
  std::int64_t coverageMismatches = 0, coverageUnexplained = 0;
  std::int64_t idMismatches = 0, idUnexplained = 0;
  std::int64_t depthCompared = 0, depthBeyondTolerance = 0;
  double worstToleranceRatio = 0.0;      // max |depth error| / tolerance over compared pixels
  double maxDepthErrorQuanta = 0.0;      // in units of the depth format's quantum
  double maxDistanceRelError = 0.0;      // |t_raster - t_ray| / distance from the eye
  std::vector<PixelReport> worstPixels;  // unexplained first, then by tolerance ratio
  // With the app's render function: where its draws were made with other state than the run says
  // (clip control, depth range, depth test, face culling, depth clamp), one line each, naming the
  // draw calls ("draw 1: glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), but the run is ...").
  std::vector<std::string> notes;
  // The run's full-size PNGs and cluster crops written under ReconcileOptions::reportDirectory.
  std::vector<std::string> images;
  // The RenderDoc capture of the app's frame, kept for a failing run (renderDocCaptures).
  std::string capture;
  std::string summaryLine;  // the line `clipray reconcile` prints for this run
};

struct ReconcileResult {
  std::vector<RunResult> runs;
  std::string reportDirectory;  // where the report went; empty: not written
  bool consistent() const;
  // Every run's summary line, then for each inconsistent run its worst pixels and images.
  std::string text() const;
};

// Reconciles every camera x convention x depth format of the scene, through the same engine as
// `clipray reconcile` (the same options give the same report.json and images). The rays come from
// `pick` (the app's picking, robustPickRays() for clipray's). Throws InputError for options that
// name a camera the scene lacks or ask for nothing, or a reportDirectory that cannot be written (or
// another run is writing); std::runtime_error where no headless GL 4.5
// context can be made or the app's render function leaves a GL error or no usable ids (the
// message says which); and whatever the app's own functions throw. The call makes a headless
// context of its own current on the calling thread and leaves no context current: a test that
// has its own GL context makes it current again afterwards.
ReconcileResult reconcile(const TestScene& scene, const PickRayFunction& pick,
                          const ReconcileOptions& options = {});
// The same with the app's picking and its own hits (PickHit): what its intersection code hits is
// compared with the picture, where `reconcile` with rays intersects them itself. A hit on a face
// the picture culls is an id mismatch, and the run's notes say so. Throws InputError too for a
// hit on a mesh or triangle the scene lacks, or at a t that is not finite and positive.
ReconcileResult reconcile(const TestScene& scene, const PickHitFunction& pick,
                          const ReconcileOptions& options = {});

}  // namespace clipray
