// GL_DEPTH_CLAMP (GL 4.6 13.7, 13.8.1): nothing is clipped at the near and far planes, and window
// depth is clamped to the depth range. A card wholly in front of the near plane is drawn at the
// near depth, a wall beyond the far plane at the far depth; the rays (from the eye, or from
// behind the near plane for a parallel camera) reach both, and the card's pixels are a class of
// their own. Under every convention, clip origin, depth range and depth format.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/GlFixture.hpp"
#include "support/RunStates.hpp"

namespace clipray {
namespace {

using testing::GlTest;

// A camera at the origin looking down -z at 64 x 64 (fov 90 degrees, near 1, far 20, or a
// parallel one of half-width 1 with the same planes); a card at z = cardZ covering x, y in
// [-h, h], and a wall at z = -30, beyond the far plane, behind everything.
std::string clampScene(bool clamp, const std::string& projection, double cardZ, double h,
                       const std::string& range = "[0, 1]") {
  const std::string c = std::to_string(cardZ), e = std::to_string(h);
  return R"({"version": 1, "depthClamp": )" + std::string(clamp ? "true" : "false") +
         R"(, "depthRange": )" + range + R"(,
    "cameras": [{"name": "main", "viewport": [64, 64],
      "view": {"eye": [0, 0, 0], "target": [0, 0, -1], "up": [0, 1, 0]},
      "projection": )" +
         projection + R"(}],
    "objects": [
      {"name": "card", "type": "mesh",
       "positions": [-)" +
         e + ", -" + e + ", " + c + ", " + e + ", -" + e + ", " + c + ", " + e + ", " + e + ", " +
         c + ", -" + e + ", " + e + ", " + c + R"(],
       "indices": [0, 1, 2, 0, 2, 3]},
      {"name": "wall", "type": "mesh",
       "positions": [-100, -100, -30, 100, -100, -30, 100, 100, -30, -100, 100, -30],
       "indices": [0, 1, 2, 0, 2, 3]}]})";
}

const std::string kPerspective =
    R"({"type": "perspective", "fovYDegrees": 90, "near": 1, "far": 20})";
const std::string kParallel =
    R"({"type": "orthographic", "left": -1, "right": 1, "bottom": -1, "top": 1,
        "near": 1, "far": 20})";

// The card's pixels: centres with |x'|, |y'| < 0.5 (the card's half-width over its distance, or
// over the parallel camera's half-width of 1): columns and rows 16 .. 47 of 64, no centre on the
// edge ((2i + 1) / 64 - 1 = +-0.5 has no integer i).
constexpr std::int64_t kCardPixels = 32 * 32;

class DepthClamp : public GlTest {};

struct Case {
  std::string name, projection;
  double cardZ, h;
};
// Perspective: the card at z = -0.5, half-width 0.25, in front of the near plane (z = -1).
// Parallel: the card at z = +2, behind the camera's position, half-width 0.5: a parallel camera
// with depth clamp draws everything along its lines of sight.
const std::vector<Case> kCases = {{"perspective", kPerspective, -0.5, 0.25},
                                  {"parallel", kParallel, 2.0, 0.5}};

TEST_F(DepthClamp, WhatLiesInFrontOfTheNearPlaneIsDrawnAtTheNearDepthAndTheRaysReachIt) {
  for (const Case& c : kCases) {
    for (const std::string range : {"[0, 1]", "[1, 0]", "[0.2, 0.7]"}) {
      const Scene scene =
          parseScene(clampScene(true, c.projection, c.cardZ, c.h, range), "clamp.json");
      const Camera& camera = scene.cameras.at(0);
      const std::uint32_t cardFirst = 1, cardLast = 2;
      for (const DepthMode lowerMode : testing::kLowerLeftModes) {
        for (const DepthMode mode : {lowerMode, testing::upperLeft(lowerMode)}) {
          const engine::AnalyticPass pass =
              engine::runAnalyticPass(scene, camera, mode, camera.viewport);
          for (const DepthFormat format : testing::kDepthFormats) {
            const std::string name =
                c.name + " " + range + " " + mode.name() + " " + depthFormatName(format);
            const engine::ComparedRun compared =
                engine::rasterAndComparePixels(renderer(), pass, format, VertexMode::World);
            const RunMetrics& m = compared.run.metrics;
            EXPECT_TRUE(m.consistent()) << name;
            EXPECT_TRUE(compared.run.depthClamp) << name;
            EXPECT_EQ(m.inFrontOfNear, kCardPixels) << name;
            EXPECT_EQ(m.coverageMismatch.total, 0) << name;
            EXPECT_EQ(m.idMismatch.total, 0) << name;
            // Every pixel shows the card or the wall; both store an end of the depth range (the
            // near end in front, the far end beyond): nothing is measured along the ray. The
            // wall only where the far end is not the clear value (1 for GL_LESS, 0 for
            // GL_GREATER), which the strict depth test never passes: only (0.2, 0.7).
            const bool wallDrawn = range == "[0.2, 0.7]";
            EXPECT_EQ(m.rasterHits, wallDrawn ? 64 * 64 : kCardPixels) << name;
            EXPECT_EQ(m.depthCompared, 0) << name;
            // The near end: n, or f under reversed-Z (whose near plane has window depth 1).
            glm::dvec2 r = scene.depthRange;
            const double nearDepth = mode.reversed ? r.y : r.x;
            const double farDepth = mode.reversed ? r.x : r.y;
            std::int64_t card = 0;
            for (std::size_t i = 0; i < compared.pixels.classes.size(); ++i) {
              const std::uint32_t id = pass.frame.hits[i].primitiveId;
              const bool onCard = id >= cardFirst && id <= cardLast;
              card += onCard ? 1 : 0;
              EXPECT_EQ(compared.pixels.classes[i], onCard      ? PixelClass::InFrontOfNear
                                                    : wallDrawn ? PixelClass::Agree
                                                                : PixelClass::Background)
                  << name << " pixel " << i;
              if (onCard || wallDrawn) {
                EXPECT_EQ(compared.pixels.analyticDepth[i], onCard ? nearDepth : farDepth)
                    << name << " pixel " << i;
                // The raster stores that end in its format: within one quantum of it.
                const double stored = onCard ? nearDepth : farDepth;
                EXPECT_LE(std::abs(compared.pixels.rasterDepth[i] - stored),
                          depthQuantum(format, stored))
                    << name << " pixel " << i;
              }
              if (::testing::Test::HasFailure()) break;
            }
            EXPECT_EQ(card, kCardPixels) << name;
          }
        }
      }
    }
  }
}

TEST_F(DepthClamp, WithoutItTheCardIsClippedOnBothSides) {
  for (const Case& c : kCases) {
    const Scene scene = parseScene(clampScene(false, c.projection, c.cardZ, c.h), "clamp.json");
    const Camera& camera = scene.cameras.at(0);
    const engine::AnalyticPass pass =
        engine::runAnalyticPass(scene, camera, kZeroToOne, camera.viewport);
    const engine::ComparedRun compared =
        engine::rasterAndComparePixels(renderer(), pass, DepthFormat::Float32, VertexMode::World);
    const RunMetrics& m = compared.run.metrics;
    EXPECT_TRUE(m.consistent()) << c.name;
    EXPECT_EQ(m.inFrontOfNear, 0) << c.name;
    // Neither the card (in front of the near plane) nor the wall (beyond the far plane) is drawn.
    EXPECT_EQ(m.rasterHits, 0) << c.name;
    EXPECT_EQ(m.rayHits, 0) << c.name;
  }
}

// A raster drawn with depth clamp against rays that start on the near plane (the picking most
// apps have): the card's pixels are coverage the rays cannot explain.
TEST_F(DepthClamp, NearPlaneRaysMissWhatTheClampedPictureShows) {
  const Scene clamped = parseScene(clampScene(true, kPerspective, -0.5, 0.25), "clamp.json");
  const Scene open = parseScene(clampScene(false, kPerspective, -0.5, 0.25), "clamp.json");
  const Camera& camera = clamped.cameras.at(0);
  const engine::AnalyticPass clampedPass =
      engine::runAnalyticPass(clamped, camera, kZeroToOne, camera.viewport);
  const engine::AnalyticPass nearPlanePass =
      engine::runAnalyticPass(open, open.cameras.at(0), kZeroToOne, camera.viewport);
  const RasterFrame raster = renderer().render(
      engine::renderRequest(clampedPass, DepthFormat::Float32, VertexMode::World));
  const engine::ComparedRun compared =
      engine::compareRasterFrame(nearPlanePass, raster, DepthFormat::Float32, VertexMode::World,
                                 renderer().info().subpixelBits, {});
  const RunMetrics& m = compared.run.metrics;
  EXPECT_FALSE(m.consistent());
  EXPECT_EQ(m.coverageMismatch.unexplained, kCardPixels);
  EXPECT_EQ(m.rayHits, 0);
}

}  // namespace
}  // namespace clipray
