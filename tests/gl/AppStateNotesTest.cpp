// engine::appStateNotes: the app's draw states set beside the run's, one line per difference with
// the draws it concerns. No GL context: the states are made here as renderWithApp reads them.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "clipray/engine/AppStateNotes.hpp"

namespace clipray {
namespace {

// Two meshes, "floor" and "box", culled as given.
Scene twoMeshes(CullFace floorCull, CullFace boxCull) {
  Scene scene;
  scene.objects.resize(2);
  scene.objects[0].name = "floor";
  scene.objects[0].cull = floorCull;
  scene.objects[1].name = "box";
  scene.objects[1].cull = boxCull;
  return scene;
}

// What an app that gets everything right draws each mesh with under ZO.
gl::AppDrawState rightUnderZeroToOne() {
  gl::AppDrawState state;
  state.convention = DepthConvention::ZeroToOne;
  state.depthTest = true;
  return state;
}

TEST(AppStateNotes, AnAppThatDrawsAsTheRunSaysGetsNone) {
  const Scene scene = twoMeshes(CullFace::None, CullFace::None);
  const std::vector<gl::AppDrawState> draws(2, rightUnderZeroToOne());
  EXPECT_TRUE(engine::appStateNotes(draws, kZeroToOne, scene, AppIds::Written).empty());
  // LEQUAL keeps the nearer surface too; glDepthRange read back in float rounding.
  std::vector<gl::AppDrawState> lequal = draws;
  lequal[1].depthFunc = 0x0203;
  lequal[1].depthRange = {0.0, 1.0 - 1e-8};
  EXPECT_TRUE(engine::appStateNotes(lequal, kZeroToOne, scene, AppIds::Written).empty());
}

TEST(AppStateNotes, EachDifferenceOnceWithItsDraws) {
  const Scene scene = twoMeshes(CullFace::Back, CullFace::Back);
  std::vector<gl::AppDrawState> draws(3, rightUnderZeroToOne());
  for (gl::AppDrawState& d : draws) d.cull = CullFace::Back;
  draws[0].depthClamp = true;
  draws[2].depthClamp = true;
  draws[1].depthRange = {0.0, 0.5};
  draws[2].cull = CullFace::None;
  // Three draws for two meshes: the culling is set beside the one every mesh declares.
  EXPECT_EQ(engine::appStateNotes(draws, kZeroToOne, scene, AppIds::Written),
            (std::vector<std::string>{
                "draws 1, 3: GL_DEPTH_CLAMP is enabled, but the scene does not declare it "
                "(depthClamp, SceneBuilder::depthClamp): what the picture shows in front of the "
                "near plane no ray from the near plane can hit",
                "draw 2: glDepthRange(0, 0.5), but the scene declares (0, 1) (depthRange, "
                "SceneBuilder::depthRange)",
                "draw 3: no face culling, but the scene declares glCullFace(GL_BACK) with "
                "glFrontFace(GL_CCW) for mesh \"floor\" (cull and frontFace, "
                "SceneBuilder::faceCulling)"}));
}

TEST(AppStateNotes, PolygonOffsetIsSetBesideTheMeshOfEachDraw) {
  Scene scene = twoMeshes(CullFace::None, CullFace::None);
  scene.objects[1].polygonOffset = PolygonOffset{-1.0, -2.0, 0.0};
  std::vector<gl::AppDrawState> draws(2, rightUnderZeroToOne());
  draws[1].polygonOffset = PolygonOffset{-1.0, -2.0, 0.0};
  EXPECT_TRUE(engine::appStateNotes(draws, kZeroToOne, scene, AppIds::Written).empty());
  // The box's signs kept from another depth test, and the floor offset though it declares none.
  draws[1].polygonOffset = PolygonOffset{1.0, 2.0, 0.0};
  draws[0].polygonOffset = PolygonOffset{-1.0, -2.0, 0.5};
  EXPECT_EQ(engine::appStateNotes(draws, kZeroToOne, scene, AppIds::Written),
            (std::vector<std::string>{
                "draw 1: glPolygonOffsetClamp(-1, -2, 0.5), but the scene declares no polygon "
                "offset for mesh \"floor\" (polygonOffset, SceneBuilder::objectPolygonOffset)",
                "draw 2: glPolygonOffsetClamp(1, 2, 0), but the scene declares "
                "glPolygonOffsetClamp(-1, -2, 0) for mesh \"box\" (polygonOffset, "
                "SceneBuilder::objectPolygonOffset)"}));
  // The box drawn without its offset.
  draws[0].polygonOffset.reset();
  draws[1].polygonOffset.reset();
  EXPECT_EQ(
      engine::appStateNotes(draws, kZeroToOne, scene, AppIds::Written),
      (std::vector<std::string>{"draw 2: GL_POLYGON_OFFSET_FILL disabled, but the scene declares "
                                "glPolygonOffsetClamp(-1, -2, 0) for mesh \"box\" (polygonOffset, "
                                "SceneBuilder::objectPolygonOffset)"}));
}

TEST(AppStateNotes, DepthClampIsSetBesideTheScenes) {
  Scene scene = twoMeshes(CullFace::None, CullFace::None);
  scene.depthClamp = true;
  std::vector<gl::AppDrawState> draws(2, rightUnderZeroToOne());
  draws[0].depthClamp = true;
  EXPECT_EQ(engine::appStateNotes(draws, kZeroToOne, scene, AppIds::Written),
            (std::vector<std::string>{
                "draw 2: GL_DEPTH_CLAMP is disabled, but the scene declares it (depthClamp, "
                "SceneBuilder::depthClamp): the picture is clipped at the near and far planes"}));
}

TEST(AppStateNotes, CullingIsSetBesideTheMeshOfEachDraw) {
  const Scene scene = twoMeshes(CullFace::None, CullFace::Back);
  std::vector<gl::AppDrawState> draws(2, rightUnderZeroToOne());
  draws[0].cull = CullFace::Back;  // the floor culled, the box not: both wrong
  EXPECT_EQ(
      engine::appStateNotes(draws, kZeroToOne, scene, AppIds::PerDrawCall),
      (std::vector<std::string>{
          "draw 1: glCullFace(GL_BACK) with glFrontFace(GL_CCW), but the scene declares no face "
          "culling for mesh \"floor\" (cull and frontFace, SceneBuilder::faceCulling)",
          "draw 2: no face culling, but the scene declares glCullFace(GL_BACK) with "
          "glFrontFace(GL_CCW) for mesh \"box\" (cull and frontFace, SceneBuilder::faceCulling)"}));
  // Three draws, meshes culled differently: no draw can be paired with a mesh.
  draws.push_back(draws[0]);
  EXPECT_TRUE(engine::appStateNotes(draws, kZeroToOne, scene, AppIds::Written).empty());
  // GL_FRONT_AND_BACK draws nothing.
  draws[2].cull = CullFace::None;
  draws[2].cullsEverything = true;
  EXPECT_EQ(engine::appStateNotes(draws, kZeroToOne, scene, AppIds::Written),
            std::vector<std::string>{"draw 3: glCullFace(GL_FRONT_AND_BACK) with culling enabled: "
                                     "the draw shows nothing"});
}

TEST(AppStateNotes, TheDepthTestMustKeepTheNearerSurface) {
  const Scene scene = twoMeshes(CullFace::None, CullFace::None);
  std::vector<gl::AppDrawState> draws(2, rightUnderZeroToOne());
  draws[0].depthTest = false;
  EXPECT_EQ(engine::appStateNotes(draws, kZeroToOneReversed, scene, AppIds::Written),
            (std::vector<std::string>{"draw 1: the depth test is off; the run expects GL_GREATER "
                                      "(the nearer surface has the greater depth)",
                                      "draw 2: glDepthFunc(GL_LESS), but under zo-reversed the "
                                      "nearer surface has the greater depth: GL_GREATER"}));
}

}  // namespace
}  // namespace clipray
