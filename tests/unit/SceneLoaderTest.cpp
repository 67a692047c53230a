// Scene files: what a valid scene turns into (bad input: SceneLoaderErrorsTest.cpp).

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <variant>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "clipray/InputError.hpp"
#include "clipray/math/Projections.hpp"
#include "clipray/scene/Scene.hpp"

#include "support/SceneText.hpp"

namespace clipray {
namespace {

using ::testing::StartsWith;
using namespace clipray::testing;

// ------------------------------------------------------------------------------------------------
// Valid scenes

TEST(SceneLoader, ReadsAllFields) {
  const Scene scene = parseScene(R"({
    "version": 1,
    "comment": "one triangle",
    "conventions": ["zo-reversed", "no"],
    "cameras": [)" + std::string(kCamera) +
                                     R"(],
    "objects": [)" + std::string(kObject) +
                                     R"(]
  })",
                                 "scenes/one-triangle.json");
  EXPECT_EQ(scene.path, "scenes/one-triangle.json");
  EXPECT_EQ(scene.name, "one-triangle");
  EXPECT_EQ(scene.comment, "one triangle");
  EXPECT_EQ(scene.version, 1);
  ASSERT_EQ(scene.conventions.size(), 2u);
  EXPECT_EQ(scene.conventions[0], kZeroToOneReversed);
  EXPECT_EQ(scene.conventions[1], kNegativeOneToOne);
  ASSERT_EQ(scene.cameras.size(), 1u);
  const Camera& camera = scene.cameras[0];
  EXPECT_EQ(camera.name, "main");
  EXPECT_EQ(camera.viewport, (Viewport{640, 480}));
  EXPECT_FALSE(camera.rawClipFromWorld.has_value());
  EXPECT_FALSE(camera.builtFor.has_value());
  const auto* perspective = std::get_if<PerspectiveProjection>(&camera.projection);
  ASSERT_NE(perspective, nullptr);
  EXPECT_EQ(perspective->fovYDegrees, 60.0);
  EXPECT_FALSE(perspective->aspect.has_value());
  EXPECT_EQ(perspective->nearDistance, 0.1);
  EXPECT_EQ(perspective->farDistance, 100.0);
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_EQ(scene.objects[0].name, "tri");
  ASSERT_EQ(scene.objects[0].triangles.size(), 1u);
  EXPECT_EQ(scene.objects[0].triangles[0], glm::u32vec3(0, 1, 2));
  EXPECT_EQ(scene.triangleCount(), 1u);
}

TEST(SceneLoader, OptionalFieldsDefault) {
  const Scene scene = parseScene(
      R"({"version": 1, "cameras": [)" + std::string(kCamera) + R"(], "objects": []})", kFile);
  EXPECT_EQ(scene.name, "a");
  EXPECT_EQ(scene.comment, "");
  EXPECT_TRUE(scene.conventions.empty());
  EXPECT_TRUE(scene.objects.empty());
  EXPECT_EQ(scene.triangleCount(), 0u);
}

TEST(SceneLoader, AppliesTransformExactly) {
  // world = T * R * S * p; quarter turns are exact.
  const Scene scene = parseScene(withObject(R"({
    "name": "axes", "type": "mesh", "positions": [1, 0, 0, 0, 1, 0, 0, 0, 1], "indices": [0, 1, 2],
    "transform": {"translate": [1, 2, 3], "rotateDegrees": {"axis": [0, 0, 2], "angle": 90},
                  "scale": [2, 3, 4]}
  })"),
                                 kFile);
  const std::vector<glm::dvec3> expected = {{1, 4, 3}, {-2, 2, 3}, {1, 2, 7}};
  EXPECT_EQ(scene.objects.at(0).worldPositions, expected);
}

TEST(SceneLoader, AppliesUniformScaleAndNegativeQuarterTurn) {
  const Scene scene = parseScene(withObject(R"({
    "name": "axes", "type": "mesh", "positions": [1, 0, 0, 0, 1, 0, 0, 0, 1], "indices": [0, 1, 2],
    "transform": {"rotateDegrees": {"axis": [1, 0, 0], "angle": -450}, "scale": 0.5}
  })"),
                                 kFile);
  // -450 degrees about x is -90 degrees: y -> -z, z -> y.
  const std::vector<glm::dvec3> expected = {{0.5, 0, 0}, {0, 0, -0.5}, {0, 0.5, 0}};
  EXPECT_EQ(scene.objects.at(0).worldPositions, expected);
}

TEST(SceneLoader, WorldFromObjectIsColumnMajor) {
  const Scene scene = parseScene(
      withPlacement(R"("worldFromObject": [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 10, 20, 30, 1])"),
      kFile);
  const std::vector<glm::dvec3> expected = {{10, 20, 30}, {12, 20, 30}, {10, 22, 30}};
  EXPECT_EQ(scene.objects.at(0).worldPositions, expected);
}

TEST(SceneLoader, AllowsDegenerateTriangles) {
  const Scene scene = parseScene(withObject(R"({
    "name": "flat", "type": "mesh", "positions": [0, 0, 0, 1, 0, 0, 2, 0, 0], "indices": [0, 1, 2, 1, 1, 1]
  })"),
                                 kFile);
  EXPECT_EQ(scene.triangleCount(), 2u);
}

TEST(SceneLoader, LoadsFile) {
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "clipray-scene-loader-test.json";
  {
    std::ofstream out(path);
    out << withObject(kObject);
  }
  const Scene scene = loadScene(path.string());
  std::filesystem::remove(path);
  EXPECT_EQ(scene.path, path.string());
  EXPECT_EQ(scene.name, "clipray-scene-loader-test");
  EXPECT_EQ(scene.triangleCount(), 1u);
}

// ------------------------------------------------------------------------------------------------
// Cameras

TEST(SceneCamera, PerspectiveEqualsHandBuiltProduct) {
  const Camera camera = parseScene(withCamera(kCamera), kFile).cameras.at(0);
  const glm::dmat4 viewFromWorld = viewFromWorldLookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
  expectSameMatrix(camera.viewFromWorld, viewFromWorld);
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    SCOPED_TRACE(mode.name());
    expectSameMatrix(camera.clipFromWorld(mode, {640, 480}),
                     perspectiveClipFromView(glm::radians(60.0), 640.0 / 480.0, 0.1, 100.0, mode) *
                         viewFromWorld);
  }
}

TEST(SceneCamera, AspectDefaultsToTheViewportDrawnAt) {
  const Camera camera = parseScene(withCamera(kCamera), kFile).cameras.at(0);
  const glm::dmat4 viewFromWorld = viewFromWorldLookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
  expectSameMatrix(
      camera.clipFromWorld(kZeroToOne, {800, 400}),
      perspectiveClipFromView(glm::radians(60.0), 2.0, 0.1, 100.0, kZeroToOne) * viewFromWorld);
}

TEST(SceneCamera, ExplicitAspectBuiltForAndInfiniteFar) {
  const Camera camera = parseScene(withCamera(R"({"name": "main", "viewport": [640, 480],
    "viewFromWorld": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1], "builtFor": "no",
    "projection": {"type": "perspective", "fovYDegrees": 90, "aspect": 1.5, "near": 0.5}})"),
                                   kFile)
                            .cameras.at(0);
  ASSERT_EQ(camera.builtFor, kNegativeOneToOne);
  const auto& perspective = std::get<PerspectiveProjection>(camera.projection);
  EXPECT_FALSE(perspective.farDistance.has_value());
  glm::dmat4 viewFromWorld(1.0);
  viewFromWorld[3][2] = -5.0;
  // Drawn under zo, but built for no.
  expectSameMatrix(
      camera.clipFromWorld(kZeroToOne, {100, 100}),
      perspectiveClipFromView(glm::radians(90.0), 1.5, 0.5, std::nullopt, kNegativeOneToOne) *
          viewFromWorld);
}

TEST(SceneCamera, OrthographicEqualsHandBuiltProduct) {
  const Camera camera = parseScene(withProjection(R"({"type": "orthographic",
    "left": -2, "right": 2, "bottom": -1, "top": 1, "near": -1, "far": 10})"),
                                   kFile)
                            .cameras.at(0);
  const glm::dmat4 viewFromWorld = viewFromWorldLookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    SCOPED_TRACE(mode.name());
    expectSameMatrix(camera.clipFromWorld(mode, {640, 480}),
                     orthographicClipFromView(-2, 2, -1, 1, -1, 10, mode) * viewFromWorld);
  }
}

TEST(SceneCamera, RawClipFromWorldIsReturnedAsIs) {
  const Camera camera =
      parseScene(withClipFromWorld("[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, -1, 0, 0, -0.2, 0]"), kFile)
          .cameras.at(0);
  EXPECT_TRUE(std::holds_alternative<std::monostate>(camera.projection));
  glm::dmat4 expected(1.0);
  expected[2] = glm::dvec4(0, 0, -1, -1);
  expected[3] = glm::dvec4(0, 0, -0.2, 0);
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    expectSameMatrix(camera.clipFromWorld(mode, {1, 1}), expected);
  }
}

TEST(SceneCamera, RawClipFromWorldFarFromTheOriginIsNotSingular) {
  // A perspective camera 1e6 units from the origin: the translation dwarfs the near plane.
  const glm::dmat4 clipFromWorld =
      perspectiveClipFromView(glm::radians(60.0), 1.0, 0.1, std::nullopt, kNegativeOneToOne) *
      viewFromWorldLookAt({0, 0, 1e6}, {0, 0, 0}, {0, 1, 0});
  std::string text = "[";
  for (int i = 0; i < 16; ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(clipFromWorld[i / 4][i % 4]);
  }
  EXPECT_EQ(errorOf(withClipFromWorld(text + "]")), "no error");
}

// ------------------------------------------------------------------------------------------------
// Primitive ids

TEST(ScenePrimitiveIds, DecodesBackgroundFirstAndLast) {
  Scene scene;
  scene.objects.resize(3);
  scene.objects[0].triangles.resize(2);
  scene.objects[1].triangles.resize(0);  // shares its first id with the next object
  scene.objects[2].triangles.resize(3);
  EXPECT_EQ(scene.triangleCount(), 5u);
  const PrimitiveIdTable table(scene);
  EXPECT_EQ(table.firstIdOfObject, (std::vector<std::uint32_t>{1, 3, 3}));

  const auto expectDecoded = [&](std::uint32_t id, int object, std::uint32_t triangle) {
    const PrimitiveIdTable::Decoded decoded = table.decode(id);
    EXPECT_EQ(decoded.object, object) << "id " << id;
    EXPECT_EQ(decoded.triangle, triangle) << "id " << id;
  };
  expectDecoded(0, -1, 0);  // background
  expectDecoded(1, 0, 0);   // first
  expectDecoded(2, 0, 1);
  expectDecoded(3, 2, 0);
  expectDecoded(5, 2, 2);  // last
}

TEST(ScenePrimitiveIds, EmptySceneDecodesEverythingAsBackground) {
  const PrimitiveIdTable table{Scene{}};
  EXPECT_TRUE(table.firstIdOfObject.empty());
  EXPECT_EQ(table.decode(0).object, -1);
  EXPECT_EQ(table.decode(7).object, -1);
}

// ------------------------------------------------------------------------------------------------
// Analytic primitives, terrain and mesh files

// The local point of a primitive mapped to world.
glm::dvec3 worldOf(const AnalyticPrimitive& primitive, glm::dvec3 local) {
  return glm::dvec3(primitive.worldFromLocal * glm::dvec4(local, 1.0));
}

TEST(SceneLoaderPrimitives, EveryKindMapsItsCanonicalShapeOntoTheGivenOne) {
  const Scene scene = parseScene(R"({"version": 1, "cameras": [)" + std::string(kCamera) +
                                     R"(], "objects": [
    {"name": "ball", "type": "sphere", "centre": [1, 2, 3], "radius": 0.5},
    {"name": "disk", "type": "disk", "centre": [0, 1, 0], "normal": [0, 2, 0], "radius": 2},
    {"name": "card", "type": "quad", "centre": [0, 0, -1], "halfEdges": [[2, 0, 0], [0, 3, 0]]},
    {"name": "crate", "type": "box", "min": [-1, 0, -2], "max": [3, 1, 2]},
    {"name": "cube", "type": "box", "centre": [0, 0, 0], "halfExtents": [1, 1, 1],
     "transform": {"translate": [10, 0, 0], "rotateDegrees": {"axis": [0, 1, 0], "angle": 90}}},
    {"name": "ground", "type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0]}]})",
                                 kFile);
  ASSERT_EQ(scene.primitives.size(), 6u);
  EXPECT_EQ(scene.triangleCount(), 0u);
  const auto& p = scene.primitives;
  EXPECT_EQ(p[0].kind, PrimitiveKind::Sphere);
  EXPECT_EQ(worldOf(p[0], {0, 0, 0}), glm::dvec3(1, 2, 3));
  EXPECT_EQ(worldOf(p[0], {1, 0, 0}), glm::dvec3(1.5, 2, 3));
  // Disk: local z is the (normalized) normal, local xy spans the disk at the radius.
  EXPECT_EQ(p[1].kind, PrimitiveKind::Disk);
  EXPECT_EQ(worldOf(p[1], {0, 0, 1}), glm::dvec3(0, 3, 0));
  EXPECT_NEAR(glm::length(worldOf(p[1], {1, 0, 0}) - glm::dvec3(0, 1, 0)), 2.0, 1e-15);
  EXPECT_EQ(worldOf(p[1], {1, 0, 0}).y, 1.0);
  // Quad: the half edges are the local x and y axes.
  EXPECT_EQ(worldOf(p[2], {1, 1, 0}), glm::dvec3(2, 3, -1));
  EXPECT_EQ(worldOf(p[2], {-1, 1, 0}), glm::dvec3(-2, 3, -1));
  // Box from min/max: corners map onto the corners.
  EXPECT_EQ(worldOf(p[3], {-1, -1, -1}), glm::dvec3(-1, 0, -2));
  EXPECT_EQ(worldOf(p[3], {1, 1, 1}), glm::dvec3(3, 1, 2));
  // Oriented box: a quarter turn about y takes local +x to world -z (exact for 90 degrees).
  EXPECT_EQ(worldOf(p[4], {1, 0, 0}), glm::dvec3(10, 0, -1));
  EXPECT_EQ(p[5].kind, PrimitiveKind::Plane);
  EXPECT_EQ(worldOf(p[5], {0, 0, 0}), glm::dvec3(0, -1, 0));
  EXPECT_EQ(worldOf(p[5], {0, 0, 1}), glm::dvec3(0, 0, 0));
  for (const AnalyticPrimitive& primitive : p) {
    const glm::dmat4 identity = primitive.localFromWorld * primitive.worldFromLocal;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(identity[c][r], c == r ? 1.0 : 0.0, 1e-15);
    }
  }
  // Ids follow every triangle: here there are none, so the sphere is id 1.
  const PrimitiveIdTable ids(scene);
  EXPECT_EQ(ids.firstAnalyticId, 1u);
  EXPECT_EQ(ids.decode(3).analytic, 2);
  EXPECT_EQ(ids.decode(7).analytic, -1);
}

TEST(SceneLoaderPrimitives, IdsOfPrimitivesFollowTheTriangles) {
  const Scene scene = parseScene(R"({"version": 1, "cameras": [)" + std::string(kCamera) +
                                     R"(], "objects": [
    {"name": "ball", "type": "sphere", "centre": [1, 2, 3], "radius": 0.5}, )" +
                                     kObject + "]}",
                                 kFile);
  const PrimitiveIdTable ids(scene);
  EXPECT_EQ(ids.firstAnalyticId, 2u);
  EXPECT_EQ(ids.decode(1).object, 0);
  EXPECT_EQ(ids.decode(2).analytic, 0);
  EXPECT_EQ(ids.decode(2).object, -1);
}

TEST(SceneLoaderPrimitives, TerrainIsReproducible) {
  const std::string text = withObject(
      R"({"name": "hills", "type": "terrain", "triangles": 1000, "seed": 7,
          "transform": {"translate": [0, 5, 0]}})");
  const Scene a = parseScene(text, kFile);
  const Scene b = parseScene(text, kFile);
  // ceil(sqrt(1000 / 2)) = 23 cells a side: 2 * 23^2 triangles on 24^2 vertices.
  ASSERT_EQ(a.triangleCount(), 1058u);
  EXPECT_EQ(a.objects[0].worldPositions.size(), 576u);
  EXPECT_EQ(a.objects[0].worldPositions, b.objects[0].worldPositions);
  EXPECT_EQ(a.objects[0].worldPositions[0].x, -50.0);
  const Scene other = parseScene(withObject(R"({"name": "hills", "type": "terrain",
                                                "triangles": 1000, "seed": 8})"),
                                 kFile);
  EXPECT_NE(a.objects[0].worldPositions[5].y, other.objects[0].worldPositions[5].y + 5.0);
}

TEST(SceneLoaderErrors, Primitives) {
  EXPECT_EQ(errorOf(withObject(R"({"name": "b", "type": "sphere", "centre": [0, 0, 0],
                                   "radius": 0})")),
            "scenes/a.json: /objects/0/radius: expected a positive number, got 0");
  EXPECT_EQ(errorOf(withObject(R"({"name": "b", "type": "sphere", "centre": [0, 0, 0]})")),
            "scenes/a.json: /objects/0: missing required field \"radius\"");
  EXPECT_EQ(errorOf(withObject(R"({"name": "d", "type": "disk", "centre": [0, 0, 0],
                                   "normal": [0, 0, 0], "radius": 1})")),
            "scenes/a.json: /objects/0/normal: expected a non-zero direction, got [0,0,0]");
  EXPECT_EQ(errorOf(withObject(R"({"name": "q", "type": "quad", "centre": [0, 0, 0],
                                   "halfEdges": [[1, 0, 0], [2, 0, 0]]})")),
            "scenes/a.json: /objects/0/halfEdges: expected two non-zero, non-parallel half edges, "
            "got [[1,0,0],[2,0,0]]");
  EXPECT_EQ(errorOf(withObject(R"({"name": "q", "type": "quad", "centre": [0, 0, 0],
                                   "halfEdges": [[1, 0, 0]]})")),
            "scenes/a.json: /objects/0/halfEdges: expected an array of 2 vectors [[ux, uy, uz], "
            "[vx, vy, vz]], got [[1,0,0]]");
  EXPECT_EQ(
      errorOf(withObject(R"({"name": "c", "type": "box", "min": [0, 0, 0],
                                   "max": [1, 0, 1]})")),
      "scenes/a.json: /objects/0/max/1: expected a number greater than \"min\"[1] (0), got 0");
  EXPECT_EQ(errorOf(withObject(R"({"name": "c", "type": "box", "min": [0, 0, 0],
                                   "centre": [1, 0, 1]})")),
            "scenes/a.json: /objects/0: expected either \"min\" and \"max\" or \"centre\" and "
            "\"halfExtents\", got both");
  EXPECT_EQ(errorOf(withObject(R"({"name": "c", "type": "box", "centre": [0, 0, 0],
                                   "halfExtents": [1, -1, 1]})")),
            "scenes/a.json: /objects/0/halfExtents/1: expected a positive number, got -1");
  EXPECT_EQ(errorOf(withObject(R"({"name": "c", "type": "box"})")),
            "scenes/a.json: /objects/0: missing required fields \"min\" and \"max\" (or \"centre\" "
            "and \"halfExtents\")");
  // A singular worldFromObject flattens the sphere: its local frame has no inverse.
  EXPECT_EQ(errorOf(withObject(R"({"name": "b", "type": "sphere", "centre": [0, 0, 0],
    "radius": 1, "worldFromObject": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1]})")),
            "scenes/a.json: /objects/0/worldFromObject: expected an invertible matrix, got a "
            "singular one (scaled determinant 0)");
  // Sizes that are valid alone but whose product leaves no finite inverse.
  EXPECT_EQ(errorOf(withObject(R"({"name": "b", "type": "sphere", "centre": [0, 0, 0],
    "radius": 1e-300, "transform": {"scale": [1e300, 1, 1]}})")),
            "scenes/a.json: /objects/0: the sphere has a placement whose inverse overflows double");
  EXPECT_EQ(errorOf(withObject(R"({"name": "t", "type": "terrain", "triangles": 1})")),
            "scenes/a.json: /objects/0/triangles: expected an integer in [2, 20000000], got 1");
  EXPECT_EQ(errorOf(withObject(R"({"name": "t", "type": "terrain", "triangles": 10,
                                   "seed": -1})")),
            "scenes/a.json: /objects/0/seed: expected an unsigned integer, got -1");
}

TEST(SceneLoaderErrors, MeshFileReferences) {
  EXPECT_EQ(errorOf(withObject(R"({"name": "m", "type": "meshFile", "path": "missing.glb"})")),
            "scenes/a.json: /objects/0/path: cannot open mesh file \"missing.glb\" (looked for "
            "\"scenes/missing.glb\")");
  EXPECT_EQ(errorOf(withObject(R"({"name": "m", "type": "meshFile", "path": ""})")),
            "scenes/a.json: /objects/0/path: expected a non-empty path, got \"\"");
}

TEST(SceneLoaderErrors, MeshFileProblemsNameTheSceneObjectAndTheFile) {
  // Paths resolve against the scene file's folder: here the test meshes.
  const std::string folder = std::string(CLIPRAY_SOURCE_DIR) + "/tests/data/meshes";
  const auto errorIn = [&](const std::string& object) {
    try {
      parseScene(sceneWith(kCamera, object), folder + "/scene.json");
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(errorIn(R"({"name": "m", "type": "meshFile", "path": "quads.obj",
                       "useCameras": true})"),
            folder +
                "/scene.json: /objects/0/useCameras: the mesh file \"quads.obj\" has no "
                "cameras");
  EXPECT_EQ(errorIn(R"({"name": "m", "type": "meshFile", "path": "generate.py"})"),
            folder + "/scene.json: /objects/0/path: " + folder +
                "/generate.py: unsupported mesh file extension \".py\"; clipray reads .gltf, "
                ".glb, .obj and .ply");
  EXPECT_EQ(errorIn(R"({"name": "m", "type": "meshFile", "path": "quads.obj",
                       "useCameras": 1})"),
            folder + "/scene.json: /objects/0/useCameras: expected true or false, got 1");
  // A good reference: the OBJ's objects join the scene under the object's name.
  const Scene scene =
      parseScene(sceneWith(kCamera, R"({"name": "m", "type": "meshFile", "path": "quads.obj"})"),
                 folder + "/scene.json");
  ASSERT_FALSE(scene.objects.empty());
  EXPECT_EQ(scene.objects[0].name.rfind("m/", 0), 0u);
}

TEST(SceneLoaderErrors, TerrainsAreBoundedBeforeTheyAreBuilt) {
  // 1.1e7 asks for ceil(sqrt(5.5e6)) = 2346 cells a side: 2 * 2346^2 = 11,007,432 triangles;
  // two of them exceed the scene's 2e7 (+1% for the rounding up) before the second is built.
  EXPECT_EQ(errorOf(withObject(R"({"name": "a", "type": "terrain", "triangles": 11000000},
                                  {"name": "b", "type": "terrain", "triangles": 11000000})")),
            "scenes/a.json: /objects/1/triangles: the scene's terrains would hold 22014864 "
            "triangles; at most 20000000 in all");
}

TEST(SceneLoaderPrimitives, HugeButFiniteQuadEdgesAreNotCalledParallel) {
  // |u| |v| = 1e320 overflows, but the edges are perpendicular: the parallel test works on unit
  // vectors, and such a placement is refused for what it is (its determinant overflows).
  EXPECT_EQ(errorOf(withObject(R"({"name": "q", "type": "quad", "centre": [0, 0, 0],
                                   "halfEdges": [[1e160, 0, 0], [0, 1e160, 0]]})")),
            "scenes/a.json: /objects/0: the quad has a non-invertible placement (scaled "
            "determinant 0); check \"transform\" / \"worldFromObject\" and the shape's sizes");
  const Scene scene = parseScene(withObject(R"({"name": "q", "type": "quad",
      "centre": [0, 0, 0], "halfEdges": [[1e100, 0, 0], [0, 1e100, 0]]})"),
                                 kFile);
  ASSERT_EQ(scene.primitives.size(), 1u);
  EXPECT_EQ(worldOf(scene.primitives[0], {1, 1, 0}), glm::dvec3(1e100, 1e100, 0));
}

TEST(SceneLoaderMeshFiles, AGltfAssetBringsItsCamerasAndObjects) {
  const Scene scene = loadScene(std::string(CLIPRAY_SOURCE_DIR) + "/scenes/gltf_asset.json");
  ASSERT_EQ(scene.cameras.size(), 2u);
  EXPECT_EQ(scene.cameras[0].name, "lantern/perspective_camera");
  EXPECT_EQ(scene.cameras[1].name, "lantern/orthographic_camera");
  const auto* perspective = std::get_if<PerspectiveProjection>(&scene.cameras[0].projection);
  ASSERT_NE(perspective, nullptr);
  EXPECT_FALSE(perspective->farDistance.has_value());  // no zfar: infinite far plane
  EXPECT_TRUE(std::holds_alternative<OrthographicProjection>(scene.cameras[1].projection));
  ASSERT_EQ(scene.objects.size(), 2u);
  EXPECT_EQ(scene.objects[0].name.rfind("lantern/", 0), 0u);
  // The same asset loaded on its own is the same geometry seen from the same cameras.
  const Scene alone = loadScene(std::string(CLIPRAY_SOURCE_DIR) + "/scenes/assets/lantern.gltf");
  ASSERT_EQ(alone.objects.size(), 2u);
  EXPECT_EQ(alone.objects[0].worldPositions, scene.objects[0].worldPositions);
  EXPECT_EQ(alone.cameras[0].viewFromWorld, scene.cameras[0].viewFromWorld);
}

}  // namespace
}  // namespace clipray
