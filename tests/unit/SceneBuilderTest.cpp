// SceneBuilder: a scene built in code is the scene its json() file loads, and every mistake is
// refused with the message the same mistake in a file gets.

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <variant>

#include <gtest/gtest.h>

#include "clipray/SceneBuilder.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray {
namespace {

const float kQuadPositions[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
const std::uint32_t kQuadIndices[] = {0, 1, 2, 0, 2, 3};

glm::dmat4 cameraMatrix() {
  return perspectiveClipFromView(glm::radians(60.0), 4.0 / 3.0, 0.1, 100.0, kZeroToOne) *
         viewFromWorldLookAt({0.5, 0.5, 3.0}, {0.5, 0.5, 0.0}, {0.0, 1.0, 0.0});
}

std::string messageOf(const SceneBuilder& builder) {
  try {
    builder.build();
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

std::string fileMessageOf(const SceneBuilder& builder) {
  try {
    parseScene(builder.json(), "scene.json");
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(SceneBuilder, BuildsTheSceneItsFileLoads) {
  glm::dmat4 placement(1.0);
  placement[3] = glm::dvec4(2.0, -1.0, 0.5, 1.0);
  const std::uint16_t shortIndices[] = {0, 2, 3};
  SceneBuilder builder("built");
  builder.comment("a quad, a triangle, a ball")
      .conventions({kNegativeOneToOne, kZeroToOneReversed})
      .mesh("quad", kQuadPositions, kQuadIndices, placement)
      .mesh("corner", kQuadPositions, shortIndices)
      .sphere("ball", {0.5, 0.5, -1.0}, 0.25)
      .camera("raw", cameraMatrix(), {64, 48})
      .perspectiveCamera("rebuilt",
                         viewFromWorldLookAt({0.5, 0.5, 3.0}, {0.5, 0.5, 0.0}, {0.0, 1.0, 0.0}),
                         60.0, 0.1, std::nullopt, {32, 24});
  const TestScene built = builder.build();
  const Scene file = parseScene(builder.json(), "built.json");
  const Scene& scene = built.model();

  EXPECT_EQ(built.name(), "built");
  EXPECT_EQ(scene.comment, "a quad, a triangle, a ball");
  EXPECT_EQ(scene.conventions, file.conventions);
  ASSERT_EQ(scene.conventions.size(), 2u);
  EXPECT_EQ(built.objectNames(), (std::vector<std::string>{"quad", "corner", "ball"}));
  EXPECT_EQ(built.cameraNames(), (std::vector<std::string>{"raw", "rebuilt"}));
  EXPECT_EQ(built.triangleCount(), 3u);
  ASSERT_EQ(scene.objects.size(), 2u);
  EXPECT_EQ(scene.objects[0].worldPositions, file.objects[0].worldPositions);
  EXPECT_EQ(scene.objects[0].worldPositions[2], glm::dvec3(3.0, 0.0, 0.5));  // placed in double
  EXPECT_EQ(scene.objects[1].triangles, (std::vector<glm::u32vec3>{{0, 2, 3}}));
  ASSERT_EQ(scene.primitives.size(), 1u);
  EXPECT_EQ(scene.primitives[0].worldFromLocal, file.primitives[0].worldFromLocal);
  // The raw camera is drawn as given under every convention; the rebuilt one is built for each.
  EXPECT_EQ(scene.cameras[0].clipFromWorld(kNegativeOneToOne, {64, 48}), cameraMatrix());
  EXPECT_EQ(scene.cameras[1].clipFromWorld(kZeroToOneReversed, {32, 24}),
            file.cameras[1].clipFromWorld(kZeroToOneReversed, {32, 24}));
  EXPECT_FALSE(std::get<PerspectiveProjection>(scene.cameras[1].projection).farDistance);
}

TEST(SceneBuilder, FaceCullingAppliesToTheMeshAddedLast) {
  SceneBuilder builder("culled");
  builder.mesh("open", kQuadPositions, kQuadIndices)
      .mesh("culled", kQuadPositions, kQuadIndices)
      .faceCulling(CullFace::Back, FrontFace::Cw);
  const TestScene built = builder.build();
  const Scene& scene = built.model();
  ASSERT_EQ(scene.objects.size(), 2u);
  EXPECT_EQ(scene.objects[0].cull, CullFace::None);
  EXPECT_EQ(scene.objects[0].frontFace, FrontFace::Ccw);
  EXPECT_EQ(scene.objects[1].cull, CullFace::Back);
  EXPECT_EQ(scene.objects[1].frontFace, FrontFace::Cw);
  const Scene file = parseScene(builder.json(), "culled.json");
  EXPECT_EQ(file.objects[1].cull, CullFace::Back);
  EXPECT_EQ(file.objects[1].frontFace, FrontFace::Cw);

  SceneBuilder empty("t");
  try {
    empty.faceCulling(CullFace::Front);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "SceneBuilder \"t\": faceCulling() applies to the mesh added last, and no object "
              "was added yet");
  }
  SceneBuilder sphere("t");
  sphere.sphere("ball", {0.0, 0.0, 0.0}, 1.0).faceCulling(CullFace::Back);
  EXPECT_EQ(messageOf(sphere),
            "SceneBuilder \"t\": /objects/0/cull: face culling applies to triangle meshes (mesh, "
            "meshFile, terrain); a sphere is ray-traced by its fragment shader and has no winding");
}

TEST(SceneBuilder, ClipPlanesApplyToTheCameraAddedLast) {
  SceneBuilder builder("clipped");
  builder.mesh("quad", kQuadPositions, kQuadIndices)
      .camera("open", cameraMatrix(), {64, 48})
      .camera("clipped", cameraMatrix(), {64, 48})
      .clipPlanes({{0.0, 1.0, 0.0, -0.5}, {1.0, 0.0, 0.0, 0.25}});
  const TestScene built = builder.build();
  const Scene& scene = built.model();
  ASSERT_EQ(scene.cameras.size(), 2u);
  EXPECT_TRUE(scene.cameras[0].clipPlanes.empty());
  EXPECT_EQ(scene.cameras[1].clipPlanes,
            (std::vector<glm::dvec4>{{0.0, 1.0, 0.0, -0.5}, {1.0, 0.0, 0.0, 0.25}}));
  EXPECT_EQ(parseScene(builder.json(), "clipped.json").cameras[1].clipPlanes,
            scene.cameras[1].clipPlanes);
  SceneBuilder none("t");
  try {
    none.clipPlanes({{0.0, 1.0, 0.0, 0.0}});
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "SceneBuilder \"t\": clipPlanes() applies to the camera added last, and no camera "
              "was added yet");
  }
  SceneBuilder flat("t");
  flat.mesh("quad", kQuadPositions, kQuadIndices)
      .camera("main", cameraMatrix(), {64, 48})
      .clipPlanes({{0.0, 0.0, 0.0, 1.0}});
  EXPECT_EQ(messageOf(flat),
            "SceneBuilder \"t\": /cameras/0/clipPlanes/0: expected a plane with a non-zero normal "
            "[a, b, c], got [0.0,0.0,0.0,1.0]");
}

TEST(SceneBuilder, DepthClampIsTheScenes) {
  SceneBuilder builder("clamped");
  builder.mesh("quad", kQuadPositions, kQuadIndices).camera("main", cameraMatrix(), {64, 48});
  EXPECT_FALSE(builder.build().model().depthClamp);
  builder.depthClamp(true);
  EXPECT_TRUE(builder.build().model().depthClamp);
  EXPECT_TRUE(parseScene(builder.json(), "clamped.json").depthClamp);
  builder.depthClamp(false);
  EXPECT_FALSE(builder.build().model().depthClamp);
}

TEST(SceneBuilder, ObjectDepthRangeIsTheLastMeshs) {
  SceneBuilder builder("weapon");
  EXPECT_THROW(builder.objectDepthRange(0.0, 0.1), InputError);
  builder.depthRange(0.1, 1.0)
      .mesh("world", kQuadPositions, kQuadIndices)
      .mesh("weapon", kQuadPositions, kQuadIndices)
      .objectDepthRange(0.0, 0.1)
      .camera("main", cameraMatrix(), {64, 48});
  const TestScene built = builder.build();
  const Scene& model = built.model();
  ASSERT_EQ(model.objects.size(), 2u);
  EXPECT_FALSE(model.objects[0].depthRange.has_value());
  EXPECT_EQ(model.objects[1].depthRange, glm::dvec2(0.0, 0.1));
  EXPECT_EQ(model.objects[0].depthRangeOr(model.depthRange), glm::dvec2(0.1, 1.0));
  EXPECT_EQ(parseScene(builder.json(), "weapon.json").objects[1].depthRange, glm::dvec2(0.0, 0.1));
  builder.objectDepthRange(0.2, 0.0);
  EXPECT_EQ(messageOf(builder),
            "SceneBuilder \"weapon\": /objects/1/depthRange: expected a range that runs the way "
            "the scene's [0.1,1.0] does (one depth test for the frame), got [0.2,0.0]");
}

TEST(SceneBuilder, ObjectClipPlanesAreTheLastMeshs) {
  SceneBuilder builder("section");
  EXPECT_THROW(builder.objectClipPlanes({{1.0, 0.0, 0.0, 0.0}}), InputError);
  builder.mesh("ground", kQuadPositions, kQuadIndices)
      .mesh("house", kQuadPositions, kQuadIndices)
      .objectClipPlanes({{-1.0, 0.0, 0.0, 0.3}})
      .camera("main", cameraMatrix(), {64, 48});
  const TestScene built = builder.build();
  const Scene& model = built.model();
  ASSERT_EQ(model.objects.size(), 2u);
  EXPECT_TRUE(model.objects[0].clipPlanes.empty());
  EXPECT_EQ(model.objects[1].clipPlanes, (std::vector<glm::dvec4>{{-1.0, 0.0, 0.0, 0.3}}));
  EXPECT_EQ(parseScene(builder.json(), "section.json").objects[1].clipPlanes,
            model.objects[1].clipPlanes);
  builder.objectClipPlanes({{0.0, 0.0, 0.0, 1.0}});
  EXPECT_EQ(messageOf(builder),
            "SceneBuilder \"section\": /objects/1/clipPlanes/0: expected a plane with a non-zero "
            "normal [a, b, c], got [0.0,0.0,0.0,1.0]");
}

TEST(SceneBuilder, ObjectPolygonOffsetIsTheLastMeshs) {
  SceneBuilder builder("decal");
  EXPECT_THROW(builder.objectPolygonOffset(-1.0, -2.0), InputError);
  builder.mesh("wall", kQuadPositions, kQuadIndices)
      .mesh("decal", kQuadPositions, kQuadIndices)
      .objectPolygonOffset(-1.0, -2.0, -0.01)
      .camera("main", cameraMatrix(), {64, 48});
  const TestScene built = builder.build();
  const Scene& model = built.model();
  ASSERT_EQ(model.objects.size(), 2u);
  EXPECT_FALSE(model.objects[0].polygonOffset.has_value());
  EXPECT_EQ(model.objects[1].polygonOffset, (PolygonOffset{-1.0, -2.0, -0.01}));
  EXPECT_EQ(parseScene(builder.json(), "decal.json").objects[1].polygonOffset,
            (PolygonOffset{-1.0, -2.0, -0.01}));
  builder.objectPolygonOffset(std::numeric_limits<double>::infinity(), -2.0);
  EXPECT_EQ(messageOf(builder),
            "SceneBuilder \"decal\": /objects/1/polygonOffset/factor: expected a finite number, "
            "got inf");
}

TEST(SceneBuilder, LogarithmicDepthIsTheLastCameras) {
  SceneBuilder builder("log");
  EXPECT_THROW(builder.threeJsLogarithmicDepth(100.0), InputError);
  EXPECT_THROW(builder.outerraLogarithmicDepth(0.01, 100.0), InputError);
  builder.mesh("quad", kQuadPositions, kQuadIndices)
      .camera("plain", cameraMatrix(), {64, 48})
      .camera("three", cameraMatrix(), {64, 48})
      .threeJsLogarithmicDepth(100.0)
      .camera("outerra", cameraMatrix(), {64, 48})
      .outerraLogarithmicDepth(0.01, 500.0);
  const TestScene built = builder.build();
  const Scene& model = built.model();
  ASSERT_EQ(model.cameras.size(), 3u);
  EXPECT_FALSE(model.cameras[0].logarithmicDepth.has_value());
  EXPECT_EQ(model.cameras[1].logarithmicDepth,
            (LogarithmicDepth{LogDepthForm::ThreeJs, 100.0, 1.0}));
  EXPECT_EQ(model.cameras[2].logarithmicDepth,
            (LogarithmicDepth{LogDepthForm::Outerra, 500.0, 0.01}));
  builder.outerraLogarithmicDepth(std::numeric_limits<double>::infinity(), 500.0);
  EXPECT_EQ(messageOf(builder),
            "SceneBuilder \"log\": /cameras/2/logarithmicDepth/constant: expected a finite "
            "number, got inf");
}

TEST(SceneBuilder, WithoutCamerasUsesTheAutomaticOnes) {
  const TestScene scene = SceneBuilder("auto").mesh("quad", kQuadPositions, kQuadIndices).build();
  EXPECT_EQ(scene.cameraNames().size(), 4u);
}

TEST(SceneBuilder, RefusesWhatAFileIsRefusedFor) {
  const std::uint32_t outOfRange[] = {0, 1, 99};
  SceneBuilder badIndex("t");
  badIndex.mesh("quad", kQuadPositions, outOfRange);
  EXPECT_EQ(messageOf(badIndex),
            "SceneBuilder \"t\": /objects/0/indices/2: index 99 out of range for 4 vertices");
  EXPECT_EQ(fileMessageOf(badIndex),
            "scene.json: /objects/0/indices/2: index 99 out of range for 4 vertices");

  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float withNan[] = {0, 0, 0, 1, nan, 0, 1, 1, 0, 0, 1, 0};
  SceneBuilder badPosition("t");
  badPosition.mesh("quad", withNan, kQuadIndices);
  EXPECT_EQ(messageOf(badPosition),
            "SceneBuilder \"t\": /objects/0/positions/4: expected a finite number, got nan");

  const float twoVertices[] = {0, 0, 0, 1, 0, 0};
  SceneBuilder tooFew("t");
  tooFew.mesh("line", twoVertices, kQuadIndices);
  EXPECT_EQ(
      messageOf(tooFew),
      "SceneBuilder \"t\": /objects/0/positions: expected a flat array of x, y, z coordinates "
      "of at least 3 vertices, got [0.0,0.0,0.0,1.0,0.0,0.0]");

  SceneBuilder zeroViewport("t");
  zeroViewport.mesh("quad", kQuadPositions, kQuadIndices).camera("main", cameraMatrix(), {0, 48});
  EXPECT_EQ(messageOf(zeroViewport),
            "SceneBuilder \"t\": /cameras/0/viewport/0: expected an integer in [1, 16384], got 0");
  EXPECT_EQ(fileMessageOf(zeroViewport),
            "scene.json: /cameras/0/viewport/0: expected an integer in [1, 16384], got 0");

  glm::dmat4 singular = cameraMatrix();
  singular[2] = singular[1];  // two equal columns
  SceneBuilder badCamera("t");
  badCamera.mesh("quad", kQuadPositions, kQuadIndices).camera("main", singular, {64, 48});
  EXPECT_EQ(messageOf(badCamera),
            "SceneBuilder \"t\": /cameras/0/clipFromWorld: expected an invertible matrix, got a "
            "singular one (scaled determinant 0)");

  SceneBuilder twice("t");
  twice.mesh("quad", kQuadPositions, kQuadIndices).sphere("quad", {0, 0, 0}, 1.0);
  EXPECT_EQ(messageOf(twice), fileMessageOf(twice).replace(0, 10, "SceneBuilder \"t\""));

  SceneBuilder negativeRadius("t");
  negativeRadius.sphere("ball", {0, 0, 0}, -1.0);
  EXPECT_EQ(messageOf(negativeRadius),
            "SceneBuilder \"t\": /objects/0/radius: expected a positive number, got -1.0");
}

}  // namespace
}  // namespace clipray
