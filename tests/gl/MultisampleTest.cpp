// Multisampling (GL 4.6 14.3.1): the standard scene drawn at 4 samples per pixel and at the
// largest count the implementation offers, every sample read back (a multisample depth texture
// fetched by a shader: glReadPixels cannot read it) and compared with rays through that sample's
// own position (MultisampleCamera), under every convention, origin and depth format.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "clipray/engine/MultisampleRun.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/GlFixture.hpp"
#include "support/RunStates.hpp"

namespace clipray {
namespace {

using testing::GlTest;

class Multisample : public GlTest {};

constexpr Viewport kSize{160, 120};

Scene standardScene() {
  return loadScene(testing::sourcePath("scenes/standard.json"));
}

bool unexplained(PixelClass c) {
  return c == PixelClass::CoverageUnexplained || c == PixelClass::IdUnexplained ||
         c == PixelClass::DepthBeyondTolerance;
}

// The counts the test runs at: 4 (GL 4.6's minimum GL_MAX_SAMPLES for a conformant
// implementation) and the largest the implementation offers for every depth format.
std::vector<int> countsToRun(gl::Renderer& renderer) {
  int largest = 1 << 30;
  for (const DepthFormat format : testing::kDepthFormats) {
    const std::vector<int> offered = renderer.sampleCounts(format);
    EXPECT_NE(std::find(offered.begin(), offered.end(), 4), offered.end())
        << depthFormatName(format);
    largest = std::min(largest, offered.empty() ? 4 : offered.back());
  }
  return largest == 4 ? std::vector<int>{4} : std::vector<int>{4, largest};
}

TEST_F(Multisample, TheSamplePositionsAreTheImplementationsAndInsideThePixel) {
  const std::vector<glm::dvec2> positions =
      renderer().samplePositions(DepthFormat::Float32, 4, kSize);
  ASSERT_EQ(positions.size(), 4u);
  for (std::size_t s = 0; s < positions.size(); ++s) {
    EXPECT_GT(positions[s].x, 0.0) << s;
    EXPECT_LT(positions[s].x, 1.0) << s;
    EXPECT_GT(positions[s].y, 0.0) << s;
    EXPECT_LT(positions[s].y, 1.0) << s;
    for (std::size_t t = 0; t < s; ++t) EXPECT_NE(positions[s], positions[t]) << s << " " << t;
  }
  std::printf("4x sample positions:");
  for (const glm::dvec2 p : positions) std::printf(" (%g, %g)", p.x, p.y);
  std::printf("\n");
}

TEST_F(Multisample, EverySampleAgreesWithRaysThroughItsPosition) {
  const Scene scene = standardScene();
  const Camera& camera = scene.cameras.at(0);
  int runs = 0;
  for (const int samples : countsToRun(renderer())) {
    for (const DepthMode lowerLeft : testing::kLowerLeftModes) {
      for (const DepthMode mode : {lowerLeft, testing::upperLeft(lowerLeft)}) {
        engine::MultisampleCamera sampled(scene, camera, mode, kSize);
        for (const DepthFormat format : testing::kDepthFormats) {
          const std::string name =
              mode.name() + " " + depthFormatName(format) + " x" + std::to_string(samples);
          const engine::SampleComparison run =
              sampled.rasterAndCompare(renderer(), format, VertexMode::World, samples);
          ASSERT_EQ(run.samples.size(), static_cast<std::size_t>(samples)) << name;
          for (std::size_t s = 0; s < run.samples.size(); ++s) {
            const RunMetrics& m = run.samples[s].run.metrics;
            EXPECT_TRUE(m.consistent())
                << name << " sample " << s << ": depth beyond " << m.depthBeyondTolerance
                << ", ids unexplained " << m.idMismatch.unexplained << ", coverage unexplained "
                << m.coverageMismatch.unexplained;
            EXPECT_GT(m.depthCompared, kSize.width * kSize.height / 2) << name << " " << s;
          }
          EXPECT_EQ(run.pixels.pixels, kSize.width * kSize.height);
          EXPECT_EQ(run.pixels.unexplained, 0) << name;
          // The scene's silhouettes cross pixels: some are covered by some samples only. The
          // counts are llvmpipe's (Mesa 22.3, Debian 12), the same under every state: the
          // conventions and origins change neither coverage nor which sample sees what.
          if (samples == 4) {
            EXPECT_EQ(run.pixels.covered, 10086) << name;
            EXPECT_EQ(run.pixels.partlyCovered, 151) << name;
          }
          EXPECT_GT(run.pixels.mixedPrimitives, 0) << name;
          std::printf("%s: %lld covered, %lld partly, %lld mixed\n", name.c_str(),
                      static_cast<long long>(run.pixels.covered),
                      static_cast<long long>(run.pixels.partlyCovered),
                      static_cast<long long>(run.pixels.mixedPrimitives));
          ++runs;
        }
      }
    }
  }
  EXPECT_GE(runs, 18);
}

// The samples differ where they should: each sample's coverage is that of a single-sample frame
// drawn with the matrix sheared to its position (the same geometry, rounded once more in float).
TEST_F(Multisample, EachSampleIsTheFrameShearedToItsPosition) {
  const Scene scene = standardScene();
  const Camera& camera = scene.cameras.at(0);
  for (const DepthMode mode : {kZeroToOne, testing::upperLeft(kZeroToOneReversed)}) {
    engine::MultisampleCamera sampled(scene, camera, mode, kSize);
    const engine::SampleComparison run =
        sampled.rasterAndCompare(renderer(), DepthFormat::Float32, VertexMode::World, 4);
    for (std::size_t s = 0; s < run.samples.size(); ++s) {
      const engine::AnalyticPass& pass = sampled.passesAt(run.positions)[s];
      const RasterFrame single =
          renderer().render(engine::renderRequest(pass, DepthFormat::Float32, VertexMode::World));
      const engine::ComparedRun again =
          engine::compareRasterFrame(pass, single, DepthFormat::Float32, VertexMode::World,
                                     renderer().info().subpixelBits, {});
      EXPECT_EQ(again.run.metrics.rasterHits, run.samples[s].run.metrics.rasterHits)
          << mode.name() << " sample " << s;
    }
  }
}

// The classic mistake: a sample compared as if it lay at the pixel centre (a picking function that
// reads one sample of a multisample depth buffer and unprojects it at the centre). The depth at a
// sample a quarter pixel or more from the centre differs from the centre's by the surface's depth
// slope times that distance, far beyond float32's tolerance on every slanted surface: almost
// every covered pixel gives it away, not only the silhouettes.
TEST_F(Multisample, ASampleTakenForThePixelCentreIsCaught) {
  const Scene scene = standardScene();
  const Camera& camera = scene.cameras.at(0);
  engine::MultisampleCamera sampled(scene, camera, kZeroToOne, kSize);
  const engine::SampleComparison run =
      sampled.rasterAndCompare(renderer(), DepthFormat::Float32, VertexMode::World, 4);
  const engine::AnalyticPass centre = engine::runAnalyticPass(scene, camera, kZeroToOne, kSize);
  gl::RenderRequest request =
      engine::renderRequest(centre, DepthFormat::Float32, VertexMode::World);
  request.samples = 4;
  const gl::MultisampleFrame frame = renderer().renderSamples(request);
  const engine::ComparedRun wrong =
      engine::compareRasterFrame(centre, frame.samples[0], DepthFormat::Float32, VertexMode::World,
                                 renderer().info().subpixelBits, {});
  EXPECT_FALSE(wrong.run.metrics.consistent());
  std::int64_t wrongPixels = 0;
  for (const PixelClass c : wrong.pixels.classes) wrongPixels += unexplained(c) ? 1 : 0;
  EXPECT_GT(wrongPixels, run.pixels.covered * 9 / 10);
  EXPECT_GT(wrong.run.metrics.depthBeyondTolerance, run.pixels.covered * 9 / 10);
  EXPECT_TRUE(run.consistent());
  std::printf("sample 0 taken for the centre: %lld of %lld covered pixels unexplained\n",
              static_cast<long long>(wrongPixels), static_cast<long long>(run.pixels.covered));
}

TEST_F(Multisample, ACountTheImplementationDoesNotOfferIsRefusedWithTheCountsItDoes) {
  const std::vector<int> offered = renderer().sampleCounts(DepthFormat::Unorm24);
  std::string counts;
  for (const int n : offered) counts += (counts.empty() ? "" : ", ") + std::to_string(n);
  try {
    renderer().samplePositions(DepthFormat::Unorm24, 3, kSize);
    FAIL() << "3 samples accepted";
  } catch (const gl::BackendError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("offers no 3-sample 24 depth with R32UI ids (it offers " + counts + ")"),
              std::string::npos)
        << message;
  }
}

}  // namespace
}  // namespace clipray
