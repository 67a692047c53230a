// clipray::reconcile (Reconcile.hpp): the public entry point for other projects' tests, built on
// the same analytic pass, renderer and comparison as `clipray reconcile`.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "clipray/Reconcile.hpp"
#include "clipray/gl/AppRender.hpp"
#include "clipray/gl/ReconcileRun.hpp"
#include "clipray/report/Report.hpp"

namespace clipray {

namespace {

const Camera* findCamera(const Scene& scene, const std::string& name) {
  for (const Camera& camera : scene.cameras) {
    if (camera.name == name) return &camera;
  }
  return nullptr;
}

std::vector<const Camera*> selectedCameras(const Scene& scene, const ReconcileOptions& options) {
  std::vector<const Camera*> cameras;
  if (options.cameras.empty()) {
    for (const Camera& camera : scene.cameras) cameras.push_back(&camera);
    return cameras;
  }
  for (const std::string& name : options.cameras) {
    const Camera* camera = findCamera(scene, name);
    if (!camera) {
      std::string known;
      for (const Camera& c : scene.cameras)
        known += (known.empty() ? "\"" : ", \"") + c.name + "\"";
      throw InputError("ReconcileOptions: cameras: no camera \"" + name + "\" in scene \"" +
                       scene.name + "\" (it has " + known + ")");
    }
    cameras.push_back(camera);
  }
  return cameras;
}

void validateOptions(const ReconcileOptions& options) {
  if (options.depthFormats.empty()) {
    throw InputError(
        "ReconcileOptions: depthFormats: expected at least one depth format, got none");
  }
  if (options.render && options.vertexMode != VertexMode::World) {
    throw InputError(
        "ReconcileOptions: vertexMode: the app's render function draws its own "
        "vertices; expected world, got " +
        vertexModeName(options.vertexMode));
  }
}

std::string hitName(const Scene& scene, const PrimitiveIdTable& table, std::uint32_t id) {
  if (id == 0) return "nothing";
  const PrimitiveIdTable::Decoded decoded = table.decode(id);
  if (decoded.object >= 0) {
    return "\"" + scene.objects[static_cast<std::size_t>(decoded.object)].name + "\" triangle " +
           std::to_string(decoded.triangle);
  }
  if (decoded.analytic >= 0) {
    const AnalyticPrimitive& primitive =
        scene.primitives[static_cast<std::size_t>(decoded.analytic)];
    return "\"" + primitive.name + "\" (" + primitiveKindName(primitive.kind) + ")";
  }
  return "id " + std::to_string(id);
}

// Unexplained coverage and id mismatches first, then depths beyond tolerance, then the rest; within
// each, the larger error / tolerance first (pixels without one last), then the lower index.
int severity(PixelClass value) {
  switch (value) {
    case PixelClass::CoverageUnexplained:
    case PixelClass::IdUnexplained:
      return 0;
    case PixelClass::DepthBeyondTolerance:
      return 1;
    case PixelClass::Agree:
      return 2;
    default:
      return 3;  // ambiguous by the model, or background on both sides
  }
}

std::vector<PixelReport> worstPixels(const gl::AnalyticPass& pass, const RasterFrame& raster,
                                     const PixelComparison& pixels,
                                     const ReconcileOptions& options) {
  const std::size_t count = pixels.classes.size();
  std::vector<std::size_t> order;
  order.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    if (pixels.classes[i] != PixelClass::Background) order.push_back(i);
  }
  const auto ratio = [&](std::size_t i) {
    const float r = pixels.toleranceRatio[i];
    return std::isnan(r) ? -1.0f : r;
  };
  const auto worse = [&](std::size_t a, std::size_t b) {
    const int sa = severity(pixels.classes[a]), sb = severity(pixels.classes[b]);
    if (sa != sb) return sa < sb;
    if (ratio(a) != ratio(b)) return ratio(a) > ratio(b);
    return a < b;
  };
  const std::size_t keep = std::min(options.worstPixels, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(keep), order.end(),
                    worse);
  order.resize(keep);

  const Scene& scene = *pass.scene;
  const PrimitiveIdTable table(scene);
  const Viewport size = pixels.viewport;
  std::vector<PixelReport> reports;
  for (const std::size_t i : order) {
    PixelReport report;
    report.x = static_cast<int>(i % static_cast<std::size_t>(size.width));
    report.y = static_cast<int>(i / static_cast<std::size_t>(size.width));
    if (options.window) {
      report.window = windowPositionOfPixel(*options.window, report.x, report.y, size);
    }
    report.pixelClass = pixelClassName(pixels.classes[i]);
    report.rasterHit = hitName(scene, table, raster.ids[i]);
    report.rayHit = hitName(scene, table, pass.frame.hits[i].primitiveId);
    report.rasterDepth = pixels.rasterDepth[i];
    report.rayDepth = pixels.analyticDepth[i];
    report.toleranceRatio = pixels.toleranceRatio[i];
    reports.push_back(std::move(report));
  }
  return reports;
}

RunResult runResult(const RunRecord& run, bool appRender) {
  RunResult result;
  result.scene = run.scene;
  result.camera = run.camera;
  result.convention = run.convention.name();
  result.depthFormat = depthFormatName(run.depthFormat);
  result.vertexMode = vertexModeName(run.vertexMode);
  result.appRender = appRender;
  result.size = run.size;
  const RunMetrics& m = run.metrics;
  result.consistent = m.consistent();
  result.pixels = m.pixels;
  result.rasterHits = m.rasterHits;
  result.rayHits = m.rayHits;
  result.coverageMismatches = m.coverageMismatch.total;
  result.coverageUnexplained = m.coverageMismatch.unexplained;
  result.idMismatches = m.idMismatch.total;
  result.idUnexplained = m.idMismatch.unexplained;
  result.depthCompared = m.depthCompared;
  result.depthBeyondTolerance = m.depthBeyondTolerance;
  result.worstToleranceRatio = m.toleranceRatio.max;
  result.maxDepthErrorQuanta = m.depthErrorQuanta.max;
  result.maxDistanceRelError = m.distanceRelError.max;
  result.summaryLine = runSummaryLine(run) + (appRender ? "  (app render)" : "");
  return result;
}

}  // namespace

ReconcileResult reconcile(const TestScene& testScene, const PickRayFunction& pick,
                          const ReconcileOptions& options) {
  validateOptions(options);
  const Scene& scene = testScene.model();
  const std::vector<const Camera*> cameras = selectedCameras(scene, options);
  std::vector<DepthMode> conventions = options.conventions;
  if (conventions.empty()) conventions = scene.conventions;
  if (conventions.empty()) conventions = {kZeroToOne};

  const std::unique_ptr<gl::GlContext> context = gl::createContext(options.backend);
  gl::Renderer renderer(*context);  // loads GL and checks for 4.5 (glClipControl)
  const PrimitiveIdTable table(scene);
  std::vector<std::uint32_t> firstIds = table.firstIdOfObject;

  ReconcileResult result;
  std::vector<RunRecord> records;
  for (const Camera* camera : cameras) {
    for (const DepthMode mode : conventions) {
      const gl::AnalyticPass pass =
          gl::runAnalyticPass(scene, *camera, mode, camera->viewport, pick, options.threads);
      for (const DepthFormat format : options.depthFormats) {
        RasterFrame raster;
        gl::RenderTimings timings;
        if (options.render) {
          AppFrame frame;
          frame.size = camera->viewport;
          frame.viewport = {0, 0, camera->viewport.width, camera->viewport.height};
          if (options.window) {
            const AppWindow& window = *options.window;
            frame.viewport.x = window.viewportX;
            frame.viewport.y = window.viewportY;
            frame.size.width = window.framebufferWidth != 0
                                   ? window.framebufferWidth
                                   : window.viewportX + camera->viewport.width;
            frame.size.height = window.framebufferHeight != 0
                                    ? window.framebufferHeight
                                    : window.viewportY + camera->viewport.height;
            if (frame.size.width < frame.viewport.x + frame.viewport.z ||
                frame.size.height < frame.viewport.y + frame.viewport.w) {
              throw InputError(
                  "ReconcileOptions: window: a " + std::to_string(frame.size.width) + "x" +
                  std::to_string(frame.size.height) + " framebuffer cannot hold camera \"" +
                  camera->name + "\"'s " + std::to_string(frame.viewport.z) + "x" +
                  std::to_string(frame.viewport.w) + " viewport at (" +
                  std::to_string(frame.viewport.x) + ", " + std::to_string(frame.viewport.y) + ")");
            }
          }
          frame.camera = pass.camera;
          frame.depthFormat = format;
          frame.firstIds = firstIds;
          raster = gl::renderWithApp(*context, options.render, std::move(frame), scene, &timings);
        } else {
          gl::RenderRequest request;
          request.scene = &scene;
          request.clipFromWorld = pass.camera.clipFromWorld;
          request.mode = mode;
          request.depthFormat = format;
          request.vertexMode = options.vertexMode;
          request.vertexReference = pass.reference;
          request.viewport = camera->viewport;
          raster = renderer.render(request, &timings);
        }
        gl::ComparedRun compared =
            gl::compareRasterFrame(pass, raster, format, options.vertexMode,
                                   renderer.info().subpixelBits, timings, options.threads);
        RunResult run = runResult(compared.run, static_cast<bool>(options.render));
        run.worstPixels = worstPixels(pass, raster, compared.pixels, options);
        if (!options.reportDirectory.empty() &&
            (options.imagesForEveryRun || !compared.run.metrics.consistent())) {
          encodeRunImages(compared.run, compared.pixels);
          for (const EncodedImage& image : compared.run.images) {
            run.images.push_back(
                (std::filesystem::path(options.reportDirectory) / image.relativePath).string());
          }
        }
        result.runs.push_back(std::move(run));
        records.push_back(std::move(compared.run));
      }
    }
  }
  if (!options.reportDirectory.empty()) {
    writeReport(options.reportDirectory, records, renderer.info());
    result.reportDirectory = options.reportDirectory;
  }
  return result;
}

bool ReconcileResult::consistent() const {
  return std::all_of(runs.begin(), runs.end(), [](const RunResult& run) { return run.consistent; });
}

std::string PixelReport::text() const {
  std::ostringstream out;
  out << "pixel (" << x << ", " << y << ")";
  if (window) out << " window (" << window->x << ", " << window->y << ")";
  out << " " << pixelClass << ": raster " << rasterHit;
  if (!std::isnan(rasterDepth)) out << " at depth " << shortNumber(rasterDepth);
  out << ", ray " << rayHit;
  if (!std::isnan(rayDepth)) out << " at depth " << shortNumber(rayDepth);
  if (!std::isnan(toleranceRatio)) out << ", error/tolerance " << shortNumber(toleranceRatio);
  return out.str();
}

std::string ReconcileResult::text() const {
  std::string out;
  std::size_t inconsistent = 0;
  for (const RunResult& run : runs) {
    out += run.summaryLine + "\n";
    inconsistent += run.consistent ? 0 : 1;
  }
  for (const RunResult& run : runs) {
    if (run.consistent) continue;
    out += run.scene + "/" + run.camera + " " + run.convention + " " + run.depthFormat +
           ": worst pixels\n";
    for (const PixelReport& pixel : run.worstPixels) out += "  " + pixel.text() + "\n";
    for (const std::string& image : run.images) out += "  image " + image + "\n";
  }
  out += std::to_string(runs.size()) + " runs: " + std::to_string(runs.size() - inconsistent) +
         " consistent, " + std::to_string(inconsistent) + " inconsistent";
  if (!reportDirectory.empty()) out += "; report " + reportDirectory + "/index.html";
  return out + "\n";
}

}  // namespace clipray
