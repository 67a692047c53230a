#pragma once
// A run record and GL description with every field set, for the tests of report.json, the text
// summary and the run images; a tiny per-pixel comparison with every pixel class; and a run's
// encoded image by file name.

#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>

#include "clipray/report/Report.hpp"

namespace clipray::testing {

inline RunRecord sampleRun() {
  RunRecord run;
  run.scene = "standard";
  run.camera = "main";
  run.convention = kZeroToOne;
  run.depthFormat = DepthFormat::Unorm24;
  run.vertexMode = VertexMode::World;
  run.size = {640, 480};
  RunMetrics& m = run.metrics;
  m.pixels = 307200;
  m.rasterHits = 150000;
  m.rayHits = 150010;
  m.coverageMismatch.total = 12;
  m.coverageMismatch.edgeAmbiguous = 10;
  m.coverageMismatch.unexplained = 2;
  m.idMismatch.total = 3;
  m.idMismatch.depthAmbiguous = 2;
  m.idMismatch.edgeAmbiguous = 1;
  m.idMismatch.unexplained = 0;
  m.depthCompared = 149990;
  m.depthBeyondTolerance = 0;
  m.depthErrorQuanta = {1.0, 0.25, 0.5};
  m.distanceRelError = {4.5e-7, 1.5e-8, 2.125e-7};
  m.toleranceRatio = {0.75, 0.125, 0.5};
  RunMetrics::KindFigures sphere;
  sphere.kind = "sphere";
  sphere.depthCompared = 1000;
  sphere.depthErrorQuanta = {3.0, 1.5, 2.5};
  sphere.distanceRelError = {2e-5, 1e-6, 1.5e-5};
  sphere.toleranceRatio = {0.25, 0.0625, 0.125};
  m.byKind = {sphere};
  run.timings = {1.5, 2.5, 3.25, 40.0, 5.0};
  run.cpu = {2.75, 2.5, 3.0, 78.5, 9.75};
  run.analyticOverRaster = 32.5;
  return run;
}

// What each side hit at pixel (x, y): the raster nothing, the rays triangle 1 of "far_wall" (id 4)
// at window depth 0.75, a coverage mismatch (no error / tolerance).
inline PixelHits sampleHits(int x, int y) {
  PixelHits hits;
  hits.x = x;
  hits.y = y;
  hits.pixelClass = PixelClass::CoverageUnexplained;
  hits.ray = {4, "far_wall", "triangle", 1, 0.75};
  return hits;
}

inline GlInfo sampleGl() {
  return {"osmesa", "Mesa", "llvmpipe (LLVM 15.0.6, 256 bits)", "4.5 (Core)", 8};
}

inline const EncodedImage& imageNamed(const RunRecord& run, const std::string& file) {
  for (const EncodedImage& image : run.images)
    if (std::filesystem::path(image.relativePath).filename() == file) return image;
  throw std::runtime_error("no image " + file);
}

// A 4x3 comparison, row 0 at the bottom. Depths on the shared range [0, 1]: the analytic side
// holds the nearest depth (0), the raster side the farthest (1).
inline PixelComparison tinyComparison() {
  constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  PixelComparison p;
  p.viewport = {4, 3};
  // clang-format off
  p.rasterDepth = {kNaNf, 0.25f, 0.5f,  1.0f,    // row 0 (bottom)
                   0.5f,  0.5f,  0.5f,  0.5f,    // row 1
                   0.75f, 0.5f,  0.5f,  kNaNf};  // row 2 (top)
  p.analyticDepth = {kNaN, 0.0,  0.5,  0.75,
                     0.5,  0.5,  0.5,  0.5,
                     0.75, 0.5,  kInf, kNaN};
  p.toleranceRatio = {kNaNf, 0.0f, 0.5f, 1.0f,
                      1.5f,  2.0f, 5.0f, -1.0f,
                      std::numeric_limits<float>::infinity(), 0.25f, 0.75f, kNaNf};
  p.classes = {PixelClass::Background, PixelClass::Agree, PixelClass::DepthBeyondTolerance,
               PixelClass::CoverageEdgeAmbiguous,
               PixelClass::CoverageUnexplained, PixelClass::IdDepthAmbiguous,
               PixelClass::IdEdgeAmbiguous, PixelClass::IdUnexplained,
               PixelClass::Agree, PixelClass::Agree, PixelClass::Agree, PixelClass::Background};
  // clang-format on
  return p;
}

}  // namespace clipray::testing
