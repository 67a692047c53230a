// The SIMD kernels change nothing: random scenes seen by the hard-case cameras, reconciled with the
// kernels and with the portable one-ray, one-pixel double code on either analytic path (the ray
// path's t at every hit, the screen path's planes where it decided), give the same hits bit for
// bit, the same report entry and the same images byte for byte (the shipped scenes are checked the
// same way through the CLI: tests/cli/KernelSamenessCliTest.cpp).

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/rays/HardCases.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/util/KernelChoice.hpp"
#include "support/AnalyticPathFor.hpp"
#include "support/EveryDepthFormat.hpp"
#include "support/GlFixture.hpp"
#include "support/RandomScenes.hpp"
#include "support/Sanitizers.hpp"

namespace clipray {
namespace {

using testing::GlTest;
using testing::randomScene;

// Chooses the kernels for a scope; the SIMD kernels again after it, whatever happens inside.
class KernelsFor {
 public:
  explicit KernelsFor(KernelChoice choice) { chooseKernels(choice); }
  ~KernelsFor() { chooseKernels(KernelChoice::Simd); }
  KernelsFor(const KernelsFor&) = delete;
  KernelsFor& operator=(const KernelsFor&) = delete;
};

// report.json's entry for the run, without what is measured rather than computed.
nlohmann::json runEntry(const RunRecord& run) {
  nlohmann::json entry = reportJson({run}, GlInfo{})["runs"].at(0);
  for (const char* timing : {"timings_ms", "cpu_ms", "analytic_over_raster",
                             "timings_first_round_ms", "cpu_first_round_ms"}) {
    entry.erase(timing);
  }
  return entry;
}

class KernelSameness : public GlTest {};

TEST_F(KernelSameness, RandomScenesThroughTheHardCaseCamerasGiveTheSameHitsReportsAndImages) {
  if (!SceneIntersector::packetKernelsAvailable()) {
    GTEST_SKIP() << "this CPU runs the portable code only";
  }
  int runs = 0, hitPixels = 0, scenesWithPrimitives = 0, scenesWithMeshes = 0;
  // Under AddressSanitizer (ten times slower) the odd size alone: its tails take every path.
  const std::vector<Viewport> sizes = testing::kUnderAddressSanitizer
                                          ? std::vector<Viewport>{{101, 61}}
                                          : std::vector<Viewport>{{96, 64}, {101, 61}};
  for (const AnalyticPath path : {AnalyticPath::Rays, AnalyticPath::Screen}) {
    const testing::AnalyticPathFor chosen(path);
    std::uint64_t seed = 1;
    for (const Viewport size : sizes) {
      for (const HardCase& hardCase : hardCases(size)) {
        const Scene scene = randomScene(hardCase, hardCase.viewport, seed++);
        if (scene.objects.empty() && scene.primitives.empty()) continue;
        scenesWithPrimitives += scene.primitives.empty() ? 0 : 1;
        scenesWithMeshes += scene.objects.empty() ? 0 : 1;
        const Camera camera = testing::hardCaseCamera(hardCase);
        const DepthMode mode = hardCase.inputs.mode;
        const engine::AnalyticPass simd =
            engine::runAnalyticPass(scene, camera, mode, camera.viewport, 2);
        const engine::AnalyticPass portable = [&] {
          const KernelsFor kernels(KernelChoice::Portable);
          return engine::runAnalyticPass(scene, camera, mode, camera.viewport, 2);
        }();
        const std::string what = scene.name + " " + hardCase.convention() + " " +
                                 std::to_string(size.width) + "x" + std::to_string(size.height);
        ASSERT_EQ(simd.frame.hits.size(), portable.frame.hits.size()) << what;
        for (std::size_t i = 0; i < simd.frame.hits.size(); ++i) {
          const Hit& a = simd.frame.hits[i];
          const Hit& b = portable.frame.hits[i];
          ASSERT_EQ(a.primitiveId, b.primitiveId) << what << ", pixel " << i;
          ASSERT_EQ(std::bit_cast<std::uint64_t>(a.t), std::bit_cast<std::uint64_t>(b.t))
              << what << ", pixel " << i;
          hitPixels += a.hit() ? 1 : 0;
        }
        testing::drawInEveryDepthFormat(
            renderer(), simd, runs, [&](DepthFormat format, const auto& compare) {
              engine::ComparedRun withSimd = compare(simd);
              engine::ComparedRun withPortable = [&] {
                const KernelsFor kernels(KernelChoice::Portable);
                return compare(portable);
              }();
              const std::string run = what + " " + depthFormatName(format);
              const nlohmann::json patch =
                  nlohmann::json::diff(runEntry(withSimd.run), runEntry(withPortable.run));
              EXPECT_TRUE(patch.empty())
                  << run << ": the portable code's entry differs by " << patch;
              encodeRunImages(withSimd.run, withSimd.pixels);
              encodeRunImages(withPortable.run, withPortable.pixels);
              ASSERT_EQ(withSimd.run.images.size(), 4u) << run;
              ASSERT_EQ(withPortable.run.images.size(), 4u) << run;
              for (std::size_t k = 0; k < 4; ++k) {
                EXPECT_EQ(withSimd.run.images[k].relativePath,
                          withPortable.run.images[k].relativePath);
                EXPECT_TRUE(withSimd.run.images[k].pngBytes == withPortable.run.images[k].pngBytes)
                    << run << ", " << withSimd.run.images[k].relativePath;
              }
            });
      }
    }
  }
  // The sample is what it claims: every camera, both kinds of geometry, pixels that hit.
  std::size_t cameras = 0;
  for (const Viewport size : sizes) cameras += hardCases(size).size();
  EXPECT_EQ(runs, 2 * 3 * static_cast<int>(cameras));  // both paths, three formats
  EXPECT_GT(scenesWithPrimitives, runs / 6 / 2);
  EXPECT_GT(scenesWithMeshes, runs / 6 / 2);
  EXPECT_GT(hitPixels, 2 * 5 * 96 * 64 * static_cast<int>(sizes.size()));
}

}  // namespace
}  // namespace clipray
