// The SIMD kernels change nothing: random scenes seen by the hard-case cameras, reconciled with the
// kernels and with the portable one-ray, one-pixel double code, give the same hits bit for bit,
// the same report entry and the same images byte for byte (the shipped scenes are checked the same
// way through the CLI: tests/cli/KernelSamenessCliTest.cpp).

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/engine/ReconcileRun.hpp"
#include "clipray/rays/HardCases.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/report/Report.hpp"
#include "clipray/util/KernelChoice.hpp"
#include "support/GlFixture.hpp"
#include "support/Sanitizers.hpp"
#include "support/TestScenes.hpp"

namespace clipray {
namespace {

using testing::GlTest;

// Chooses the kernels for a scope; the SIMD kernels again after it, whatever happens inside.
class KernelsFor {
 public:
  explicit KernelsFor(KernelChoice choice) { chooseKernels(choice); }
  ~KernelsFor() { chooseKernels(KernelChoice::Simd); }
  KernelsFor(const KernelsFor&) = delete;
  KernelsFor& operator=(const KernelsFor&) = delete;
};

// A point the camera sees and a size that covers part of the screen there: along the ray of a
// random pixel, at a random fraction of the way to the far plane (log-uniform, so near, middle
// and far all come up), or a random multiple of the near distance when the far plane is at
// infinity; a sixth of them on the near plane itself. The size is the distance to the ray of a
// pixel a tenth of the screen away, at the same ray parameter: right for telephoto, orthographic
// and far-from-origin cameras alike.
struct Placement {
  glm::dvec3 centre;
  double size = 0.0;
};

std::optional<Placement> randomPlacement(const glm::dmat4& clipFromWorld,
                                         const RobustRayGenerator& generator, Viewport viewport,
                                         std::mt19937_64& rng) {
  std::uniform_int_distribution<int> column(0, viewport.width - 1), row(0, viewport.height - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int x = column(rng), y = row(rng);
  const int step = std::max(1, viewport.width / 10);
  const Ray ray = generator.generateForPixel(x, y, viewport);
  const Ray aside =
      generator.generateForPixel(x + step < viewport.width ? x + step : x - step, y, viewport);
  if (!(ray.tMax > 0.0) || !(aside.tMax > 0.0)) return std::nullopt;  // no ray at this pixel
  double t = 0.0;
  if (unit(rng) < 1.0 / 6.0) {
    // On the near plane, cut by it: rays that start inside a shape or on its surface.
  } else if (std::isfinite(ray.tMax)) {
    t = ray.tMax * std::pow(10.0, -2.5 * unit(rng));
  } else {
    // An infinite far plane (a perspective camera): 2 to 300 times the distance from the eye,
    // clip (0, 0, 1, 0) mapped back to the world, to the near plane.
    const glm::dvec4 eye = glm::inverse(clipFromWorld) * glm::dvec4(0.0, 0.0, 1.0, 0.0);
    const double nearDistance = glm::length(ray.origin - glm::dvec3(eye) / eye.w);
    t = std::pow(10.0, 0.3 + 2.2 * unit(rng)) * nearDistance / glm::length(ray.direction);
  }
  const glm::dvec3 centre = ray.origin + t * ray.direction;
  const glm::dvec3 besides = aside.origin + t * aside.direction;
  const double size = glm::length(besides - centre) * (0.3 + 1.2 * unit(rng));
  if (!std::isfinite(centre.x + centre.y + centre.z) || !(size > 0.0) || !std::isfinite(size)) {
    return std::nullopt;
  }
  return Placement{centre, size};
}

glm::dmat4 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
  glm::dvec3 axis(normal(rng), normal(rng), normal(rng));
  if (glm::length(axis) < 1e-6) axis = {0.0, 1.0, 0.0};
  return glm::rotate(glm::dmat4(1.0), angle(rng), glm::normalize(axis));
}

AnalyticPrimitive primitive(std::string name, PrimitiveKind kind,
                            const glm::dmat4& worldFromLocal) {
  AnalyticPrimitive p;
  p.name = std::move(name);
  p.kind = kind;
  p.worldFromLocal = worldFromLocal;
  p.localFromWorld = glm::inverse(worldFromLocal);
  return p;
}

// A heightfield patch of cells x cells quads with shared vertices, tilted at random.
MeshObject patch(const std::string& name, const Placement& at, int cells, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> height(-0.15, 0.15);
  const glm::dmat4 rotation = randomRotation(rng);
  MeshObject mesh;
  mesh.name = name;
  const int n = cells + 1;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const glm::dvec3 local(-1.0 + 2.0 * i / cells, height(rng), -1.0 + 2.0 * j / cells);
      mesh.worldPositions.push_back(at.centre +
                                    at.size * glm::dvec3(rotation * glm::dvec4(local, 0.0)));
    }
  }
  mesh.triangles = testing::gridTriangles(cells);
  return mesh;
}

// Six to twelve objects in front of the camera: icospheres, heightfield patches, a coplanar pair
// of quads (ties), spheres stretched into ellipsoids, disks, quads, oriented boxes, and now and
// then an unbounded plane.
Scene randomScene(const HardCase& hardCase, Viewport viewport, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const RobustRayGenerator generator(hardCase.inputs.clipFromWorld, hardCase.inputs.mode);
  Scene scene;
  scene.name = hardCase.name + "_" + std::to_string(seed);
  std::uniform_int_distribution<int> kindOf(0, 7), count(6, 12);
  std::uniform_real_distribution<double> stretch(0.3, 1.5);
  const int objects = count(rng);
  for (int k = 0; k < objects; ++k) {
    const std::optional<Placement> at =
        randomPlacement(hardCase.inputs.clipFromWorld, generator, viewport, rng);
    if (!at) continue;
    const std::string name = "object" + std::to_string(k);
    const glm::dmat4 place = glm::translate(glm::dmat4(1.0), at->centre) * randomRotation(rng);
    const auto scaled = [&](glm::dvec3 scale) { return glm::scale(place, at->size * scale); };
    switch (kindOf(rng)) {
      case 0:
        scene.objects.push_back(testing::icosphere(name, at->centre, at->size, 2));
        break;
      case 1:
        scene.objects.push_back(patch(name, *at, 6, rng));
        break;
      case 2: {  // two copies of one quad: the same depth at every pixel, the smaller id wins
        const glm::dvec3 a(place * glm::dvec4(-at->size, -at->size, 0.0, 1.0)),
            b(place * glm::dvec4(at->size, -at->size, 0.0, 1.0)),
            c(place * glm::dvec4(at->size, at->size, 0.0, 1.0)),
            d(place * glm::dvec4(-at->size, at->size, 0.0, 1.0));
        scene.objects.push_back(testing::quad(name, a, b, c, d));
        scene.objects.push_back(testing::quad(name + "_twin", a, b, c, d));
        break;
      }
      case 3:
        scene.primitives.push_back(primitive(name, PrimitiveKind::Sphere,
                                             scaled({stretch(rng), stretch(rng), stretch(rng)})));
        break;
      case 4:
        scene.primitives.push_back(primitive(name, PrimitiveKind::Disk, scaled({1.0, 1.0, 1.0})));
        break;
      case 5:
        scene.primitives.push_back(
            primitive(name, PrimitiveKind::Quad, scaled({stretch(rng), stretch(rng), 1.0})));
        break;
      case 6:
        scene.primitives.push_back(primitive(name, PrimitiveKind::Box,
                                             scaled({stretch(rng), stretch(rng), stretch(rng)})));
        break;
      default:
        if (rng() % 3 == 0) {
          scene.primitives.push_back(primitive(name, PrimitiveKind::Plane, place));
        } else {
          scene.primitives.push_back(primitive(name, PrimitiveKind::Sphere,
                                               scaled({stretch(rng), stretch(rng), stretch(rng)})));
        }
        break;
    }
  }
  return scene;
}

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
  std::uint64_t seed = 1;
  for (const Viewport size : sizes) {
    for (const HardCase& hardCase : hardCases(size)) {
      const Scene scene = randomScene(hardCase, hardCase.viewport, seed++);
      if (scene.objects.empty() && scene.primitives.empty()) continue;
      scenesWithPrimitives += scene.primitives.empty() ? 0 : 1;
      scenesWithMeshes += scene.objects.empty() ? 0 : 1;
      Camera camera;
      camera.name = hardCase.name;
      camera.viewport = hardCase.viewport;
      camera.projection = std::monostate{};
      camera.rawClipFromWorld = hardCase.inputs.clipFromWorld;
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
      for (const DepthFormat format :
           {DepthFormat::Unorm16, DepthFormat::Unorm24, DepthFormat::Float32}) {
        const VertexMode vertexMode =
            runs % 2 == 0 ? VertexMode::World : VertexMode::Pretransformed;
        gl::RenderTimings timings;
        const RasterFrame raster =
            renderer().render(engine::renderRequest(simd, format, vertexMode), &timings);
        const int subpixelBits = renderer().info().subpixelBits;
        engine::ComparedRun withSimd =
            engine::compareRasterFrame(simd, raster, format, vertexMode, subpixelBits, timings, 2);
        engine::ComparedRun withPortable = [&] {
          const KernelsFor kernels(KernelChoice::Portable);
          return engine::compareRasterFrame(portable, raster, format, vertexMode, subpixelBits,
                                            timings, 2);
        }();
        const std::string run = what + " " + depthFormatName(format);
        const nlohmann::json patch =
            nlohmann::json::diff(runEntry(withSimd.run), runEntry(withPortable.run));
        EXPECT_TRUE(patch.empty()) << run << ": the portable code's entry differs by " << patch;
        encodeRunImages(withSimd.run, withSimd.pixels);
        encodeRunImages(withPortable.run, withPortable.pixels);
        ASSERT_EQ(withSimd.run.images.size(), 4u) << run;
        ASSERT_EQ(withPortable.run.images.size(), 4u) << run;
        for (std::size_t k = 0; k < 4; ++k) {
          EXPECT_EQ(withSimd.run.images[k].relativePath, withPortable.run.images[k].relativePath);
          EXPECT_TRUE(withSimd.run.images[k].pngBytes == withPortable.run.images[k].pngBytes)
              << run << ", " << withSimd.run.images[k].relativePath;
        }
        ++runs;
      }
    }
  }
  // The sample is what it claims: every camera, both kinds of geometry, pixels that hit.
  std::size_t cameras = 0;
  for (const Viewport size : sizes) cameras += hardCases(size).size();
  EXPECT_EQ(runs, 3 * static_cast<int>(cameras));
  EXPECT_GT(scenesWithPrimitives, runs / 3 / 2);
  EXPECT_GT(scenesWithMeshes, runs / 3 / 2);
  EXPECT_GT(hitPixels, 5 * 96 * 64 * static_cast<int>(sizes.size()));
}

}  // namespace
}  // namespace clipray
