// GL integration for analytic primitives: the proxy + fragment-shader raster (shaders/
// primitive.frag, camera_rays.glsl) against the CPU's double-precision rays and intersections,
// per primitive kind and under every convention.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "clipray/scene/Scene.hpp"
#include "support/GlFixture.hpp"

namespace clipray {
namespace {

using testing::GlTest;

// A scene with one camera (eye, looking at the origin) and the given objects.
Scene sceneWith(const std::string& objects, const std::string& eye = "[2.5, 1.8, 4]",
                const std::string& far = "100") {
  return parseScene(R"({"version": 1, "cameras": [{"name": "main", "viewport": [160, 120],
      "view": {"eye": )" +
                        eye + R"(, "target": [0, 0, 0], "up": [0, 1, 0]},
      "projection": {"type": "perspective", "fovYDegrees": 50, "near": 0.1, "far": )" +
                        far + R"(}}], "objects": [)" + objects + "]}",
                    "primitive-test.json");
}

std::string describe(const RunRecord& run) {
  const RunMetrics& m = run.metrics;
  return run.convention.name() + " " + depthFormatName(run.depthFormat) + ": raster hits " +
         std::to_string(m.rasterHits) + ", ray hits " + std::to_string(m.rayHits) + ", coverage " +
         std::to_string(m.coverageMismatch.total) + " (unexplained " +
         std::to_string(m.coverageMismatch.unexplained) + "), id unexplained " +
         std::to_string(m.idMismatch.unexplained) + ", depth>tol " +
         std::to_string(m.depthBeyondTolerance) + ", tolerance ratio max " +
         std::to_string(m.toleranceRatio.max);
}

struct KindCase {
  const char* name;
  const char* object;
  PrimitiveKind kind;
};

class PrimitiveRaster : public GlTest, public ::testing::WithParamInterface<KindCase> {};

TEST_P(PrimitiveRaster, ShaderRasterMatchesTheCpuRaysUnderEveryConvention) {
  const Scene scene = sceneWith(GetParam().object);
  ASSERT_EQ(scene.primitives.size(), 1u);
  const Camera& camera = scene.cameras[0];
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    const engine::AnalyticPass pass = engine::runAnalyticPass(scene, camera, mode, camera.viewport);
    for (const DepthFormat format : {DepthFormat::Float32, DepthFormat::Unorm24}) {
      const RunRecord run =
          engine::rasterAndCompare(renderer(), pass, format, VertexMode::World, false);
      const RunMetrics& m = run.metrics;
      EXPECT_TRUE(m.consistent()) << describe(run);
      // The shape covers a good part of the 160x120 frame on both sides...
      EXPECT_GT(m.rasterHits, 1500) << describe(run);
      // ...the same pixels, but for the few whose centre lies within 1/64 px of the outline
      // (one primitive: every pixel both hit is depth-compared, the rest are coverage cases).
      EXPECT_EQ(m.idMismatch.total, 0);
      EXPECT_EQ(m.rasterHits + m.rayHits, 2 * m.depthCompared + m.coverageMismatch.total);
      EXPECT_LE(m.coverageMismatch.total, m.rasterHits / 100) << describe(run);
      // The per-kind figures name the kind and hold every compared pixel.
      ASSERT_EQ(m.byKind.size(), 1u);
      EXPECT_EQ(m.byKind[0].kind, primitiveKindName(GetParam().kind));
      EXPECT_EQ(m.byKind[0].depthCompared, m.depthCompared);
      // Float rays in the shader: a few quanta of D32F, never more than the predicted tolerance.
      EXPECT_LE(m.toleranceRatio.max, 1.0) << describe(run);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Kinds, PrimitiveRaster,
    ::testing::Values(
        KindCase{"Sphere", R"({"name": "s", "type": "sphere", "centre": [0, 0, 0], "radius": 1})",
                 PrimitiveKind::Sphere},
        KindCase{"Ellipsoid", R"({"name": "e", "type": "sphere", "centre": [0, 0, 0],
                                  "radius": 1, "transform": {"scale": [1.5, 0.6, 1]}})",
                 PrimitiveKind::Sphere},
        KindCase{"Disk", R"({"name": "d", "type": "disk", "centre": [0, 0, 0],
                             "normal": [0.2, 1, 0.5], "radius": 1.2})",
                 PrimitiveKind::Disk},
        KindCase{"Quad", R"({"name": "q", "type": "quad", "centre": [0, 0, 0],
                             "halfEdges": [[1.2, 0, 0.3], [0, 0.9, -0.2]]})",
                 PrimitiveKind::Quad},
        KindCase{"Box", R"({"name": "b", "type": "box", "min": [-1, -0.5, -0.8],
                            "max": [1, 0.5, 0.8]})",
                 PrimitiveKind::Box},
        KindCase{"OrientedBox", R"({"name": "o", "type": "box", "centre": [0, 0, 0],
                 "halfExtents": [0.8, 0.6, 0.7],
                 "transform": {"rotateDegrees": {"axis": [1, 2, 0], "angle": 33}}})",
                 PrimitiveKind::Box},
        KindCase{"Plane", R"({"name": "p", "type": "plane", "point": [0, -0.5, 0],
                              "normal": [0, 1, 0]})",
                 PrimitiveKind::Plane}),
    [](const ::testing::TestParamInfo<KindCase>& kindCase) {
      return std::string(kindCase.param.name);
    });

class PrimitiveRasterCases : public GlTest {};

RunRecord reconcile(gl::Renderer& renderer, const Scene& scene, DepthMode mode) {
  const Camera& camera = scene.cameras[0];
  return engine::rasterAndCompare(renderer,
                                  engine::runAnalyticPass(scene, camera, mode, camera.viewport),
                                  DepthFormat::Float32, VertexMode::World, false);
}

TEST_F(PrimitiveRasterCases, CameraInsideASphereOrBoxSeesItsFarSideEverywhere) {
  // The proxy box contains the eye: depth clamping keeps its far faces, whose fragments find
  // the exit point of every ray.
  for (const char* object :
       {R"({"name": "s", "type": "sphere", "centre": [0.3, 0, 0], "radius": 10})",
        R"({"name": "b", "type": "box", "min": [-8, -6, -9], "max": [7, 5, 12]})"}) {
    const Scene scene = sceneWith(object);
    for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
      const RunRecord run = reconcile(renderer(), scene, mode);
      EXPECT_TRUE(run.metrics.consistent()) << object << " " << describe(run);
      EXPECT_EQ(run.metrics.rasterHits, 160 * 120) << object << " " << describe(run);
      EXPECT_EQ(run.metrics.rayHits, 160 * 120) << object << " " << describe(run);
    }
  }
}

TEST_F(PrimitiveRasterCases, FarPlaneCutsTheInfinitePlaneOnBothSides) {
  // Eye 1 unit above an unbounded plane, looking level; the far plane (20) meets the plane
  // atan(1/20) below the horizon: NDC y = -(1/20) / tan(25 deg) = -0.10723, window row
  // 60 (1 - 0.10723) = 53.57. Rows 0..53 (54 x 160 pixel centres) see the plane, no others.
  const Scene scene = parseScene(R"({"version": 1, "cameras": [{"name": "main",
      "viewport": [160, 120], "view": {"eye": [0, 1, 5], "target": [0, 1, 0], "up": [0, 1, 0]},
      "projection": {"type": "perspective", "fovYDegrees": 50, "near": 0.1, "far": 20}}],
      "objects": [{"name": "p", "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}]})",
                                 "plane.json");
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    const RunRecord run = reconcile(renderer(), scene, mode);
    EXPECT_TRUE(run.metrics.consistent()) << describe(run);
    EXPECT_EQ(run.metrics.rasterHits, 54 * 160) << describe(run);
    EXPECT_EQ(run.metrics.rayHits, 54 * 160) << describe(run);
  }
}

TEST_F(PrimitiveRasterCases, NestedSphereNeverShows) {
  const Scene scene = sceneWith(R"({"name": "outer", "type": "sphere", "centre": [0, 0, 0],
      "radius": 1}, {"name": "inner", "type": "sphere", "centre": [0.2, 0, 0], "radius": 0.5})");
  const Camera& camera = scene.cameras[0];
  const engine::AnalyticPass pass =
      engine::runAnalyticPass(scene, camera, kZeroToOne, camera.viewport);
  const RasterFrame raster =
      renderer().render({&scene, pass.camera.clipFromWorld, kZeroToOne, DepthFormat::Float32,
                         VertexMode::World, pass.reference, camera.viewport});
  const PrimitiveIdTable ids(scene);
  int outer = 0;
  for (std::size_t i = 0; i < raster.ids.size(); ++i) {
    EXPECT_NE(raster.ids[i], ids.firstAnalyticId + 1) << "inner sphere visible at pixel " << i;
    EXPECT_NE(pass.frame.hits[i].primitiveId, ids.firstAnalyticId + 1);
    outer += raster.ids[i] == ids.firstAnalyticId;
  }
  EXPECT_GT(outer, 1500);
}

TEST_F(PrimitiveRasterCases, AWrongPickingRayIsCaughtOnASphere) {
  // y flipped: the picking rays miss the sphere where the raster draws it (the sphere is off
  // centre), so the comparison must fail.
  const Scene scene = sceneWith(R"({"name": "s", "type": "sphere", "centre": [0, 0.8, 0],
                                     "radius": 0.6})");
  const Camera& camera = scene.cameras[0];
  const PickRayFunction flipped = [](int x, int y, const PickingCamera& pickingCamera) {
    const PickRayFunction robust = robustPickRays();
    return robust(x, pickingCamera.viewport.height - 1 - y, pickingCamera);
  };
  const RunRecord run = engine::rasterAndCompare(
      renderer(), engine::runAnalyticPass(scene, camera, kZeroToOne, camera.viewport, flipped),
      DepthFormat::Float32, VertexMode::World, false);
  EXPECT_FALSE(run.metrics.consistent());
  EXPECT_GT(run.metrics.coverageMismatch.unexplained, 500);
}

TEST(ShaderSources, CompileErrorsNameTheFileTheyAreIn) {
  // Mesa's format; source string 2 is camera_rays.glsl, 1 the main file (see Renderer.cpp).
  EXPECT_EQ(gl::nameShaderSources("2:14(3): error: `q' undeclared\n1:20(9): error: syntax error\n",
                                  {"shaders/primitive.frag", "shaders/camera_rays.glsl"}),
            "shaders/camera_rays.glsl:14(3): error: `q' undeclared\n"
            "shaders/primitive.frag:20(9): error: syntax error\n");
  // The "ERROR: n:line:" format of other drivers, and numbers that name no file stay as they are.
  EXPECT_EQ(gl::nameShaderSources("ERROR: 2:7: 'x' : undeclared identifier\n0:3(1): warning\n",
                                  {"a.frag", "b.glsl"}),
            "ERROR: b.glsl:7: 'x' : undeclared identifier\n0:3(1): warning\n");
}

}  // namespace
}  // namespace clipray
