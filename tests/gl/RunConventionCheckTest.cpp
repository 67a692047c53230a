// Each run carries its camera's convention check (engine/RunConventionCheck): through the library,
// a NO-built matrix drawn under ZO fails with the verdict convention-error although raster and rays
// agree, passes with the finding noted as expected once the scene declares it, and a matrix built
// for the convention it is drawn under gets no finding.

#include <string>

#include <gtest/gtest.h>

#include "clipray/Reconcile.hpp"
#include "clipray/engine/RunConventionCheck.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/GlFixture.hpp"

namespace clipray {
namespace {

const float kQuadPositions[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
const std::uint32_t kQuadIndices[] = {0, 1, 2, 0, 2, 3};

// glm::perspectiveRH_NO(60 deg, 4/3, 0.1, 100) * lookAt: an app built for classic depth.
glm::dmat4 noClipFromWorld() {
  return perspectiveClipFromView(glm::radians(60.0), 4.0 / 3.0, 0.1, 100.0, kNegativeOneToOne) *
         viewFromWorldLookAt({0.0, 0.0, 3.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0});
}

SceneBuilder noMatrixScene() {
  SceneBuilder builder("no_under_zo");
  builder.mesh("quad", kQuadPositions, kQuadIndices).camera("main", noClipFromWorld(), {64, 48});
  return builder;
}

ReconcileOptions optionsUnder(DepthMode mode) {
  ReconcileOptions options;
  options.backend = testing::glBackendForTests();
  options.conventions = {mode};
  return options;
}

constexpr const char* kMismatchStart =
    "error [depth-convention-mismatch] built for NEGATIVE_ONE_TO_ONE (near 0.1";

TEST(RunConventionCheck, AnUndeclaredNoMatrixUnderZoIsAConventionError) {
  const ReconcileResult result =
      reconcile(noMatrixScene().build(), robustPickRays(), optionsUnder(kZeroToOne));
  ASSERT_EQ(result.runs.size(), 1u);
  const RunResult& run = result.runs[0];
  // Raster and rays agree (both clip at the near plane the rasterizer uses) ...
  EXPECT_EQ(run.coverageUnexplained + run.idUnexplained + run.depthBeyondTolerance, 0);
  // ... and the run fails all the same, for its camera's depth state.
  EXPECT_EQ(run.verdict, "convention-error");
  EXPECT_FALSE(run.consistent);
  EXPECT_FALSE(result.consistent());
  ASSERT_EQ(run.conventionFindings.size(), 1u);
  EXPECT_TRUE(run.conventionFindings[0].starts_with(kMismatchStart)) << run.conventionFindings[0];
  EXPECT_TRUE(run.summaryLine.starts_with("CONVENTION-ERROR no_under_zo/main zo"))
      << run.summaryLine;
  EXPECT_TRUE(run.summaryLine.ends_with(" check error:depth-convention-mismatch"))
      << run.summaryLine;
  EXPECT_TRUE(
      result.text().ends_with("1 runs: 0 consistent, 0 inconsistent, 1 convention errors\n"))
      << result.text();
}

TEST(RunConventionCheck, ADeclaredMistakePassesAndIsShownAsExpected) {
  SceneBuilder builder = noMatrixScene();
  builder.expectedFindings({"depth-convention-mismatch"});
  const ReconcileResult result =
      reconcile(builder.build(), robustPickRays(), optionsUnder(kZeroToOne));
  ASSERT_EQ(result.runs.size(), 1u);
  const RunResult& run = result.runs[0];
  EXPECT_EQ(run.verdict, "consistent");
  EXPECT_TRUE(run.consistent);
  ASSERT_EQ(run.conventionFindings.size(), 1u);
  EXPECT_TRUE(run.conventionFindings[0].starts_with(kMismatchStart)) << run.conventionFindings[0];
  EXPECT_TRUE(run.conventionFindings[0].ends_with(" (expected by the scene)"))
      << run.conventionFindings[0];
  EXPECT_TRUE(run.summaryLine.ends_with(" check error:depth-convention-mismatch (expected)"))
      << run.summaryLine;
}

TEST(RunConventionCheck, TheMatrixUnderTheConventionItIsBuiltForHasNoFinding) {
  const ReconcileResult result =
      reconcile(noMatrixScene().build(), robustPickRays(), optionsUnder(kNegativeOneToOne));
  ASSERT_EQ(result.runs.size(), 1u);
  EXPECT_EQ(result.runs[0].verdict, "consistent");
  EXPECT_TRUE(result.runs[0].conventionFindings.empty()) << result.text();
  EXPECT_EQ(result.runs[0].summaryLine.find(" check "), std::string::npos)
      << result.runs[0].summaryLine;
}

// The state the run is drawn with reaches the check: face culling of an object, under a clip
// origin whose y-flipped projection reverses the winding.
TEST(RunConventionCheck, AnObjectsFaceCullingIsCheckedUnderTheRunsClipOrigin) {
  const glm::dmat4 view = viewFromWorldLookAt({0.0, 0.0, 3.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0});
  SceneBuilder builder("culling");
  builder.mesh("quad", kQuadPositions, kQuadIndices)
      .faceCulling(CullFace::Back)
      .perspectiveCamera("main", view, 60.0, 0.1, 100.0, {64, 48});
  const TestScene scene = builder.build();
  const Scene& model = scene.model();
  const DepthMode upperLeft = *DepthMode::parse("zo-upper-left");
  const Camera& camera = model.cameras[0];
  const std::vector<RunFinding> flipped =
      engine::runConventionFindings(model, camera, camera.clipFromWorld(upperLeft, {64, 48}),
                                    upperLeft, {64, 48}, DepthFormat::Float32);
  ASSERT_EQ(flipped.size(), 1u);
  EXPECT_EQ(flipped[0].code, "face-culling-keeps-insides");
  EXPECT_EQ(flipped[0].severity, "warning");
  EXPECT_NE(flipped[0].message.find("glCullFace(GL_BACK) at scene object \"quad\""),
            std::string::npos)
      << flipped[0].message;
  EXPECT_TRUE(engine::runConventionFindings(model, camera,
                                            camera.clipFromWorld(kZeroToOne, {64, 48}), kZeroToOne,
                                            {64, 48}, DepthFormat::Float32)
                  .empty());
}

}  // namespace
}  // namespace clipray
