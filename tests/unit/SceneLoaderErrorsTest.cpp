// The scene loader on bad input: every message names the file, the JSON pointer and the value.

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
// Bad input: files and JSON

TEST(SceneLoaderErrors, MissingFile) {
  const std::string path = std::string(CLIPRAY_SOURCE_DIR) + "/scenes/does-not-exist.json";
  try {
    loadScene(path);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), path + ": cannot open file");
  }
}

TEST(SceneLoaderErrors, MalformedJson) {
  EXPECT_EQ(errorOf("{\n  \"version\": 1,\n  x\n}"),
            "scenes/a.json: line 3, column 3: malformed JSON: syntax error while parsing object "
            "key - invalid literal; last read: '1,<U+000A>  x'; expected string literal");
  EXPECT_EQ(errorOf("{\"version\": 1,\n \"cameras\": [\n"),
            "scenes/a.json: line 3, column 1: malformed JSON: syntax error while parsing value - "
            "unexpected end of input; expected '[', '{', or a literal");
  EXPECT_EQ(errorOf(""),
            "scenes/a.json: line 1, column 1: malformed JSON: syntax error while parsing value - "
            "unexpected end of input; expected '[', '{', or a literal");
}

TEST(SceneLoaderErrors, DuplicateKey) {
  EXPECT_EQ(errorOf(withProjection(
                R"({"type": "perspective", "fovYDegrees": 60, "near": 0.1, "near": 1})")),
            "scenes/a.json: /cameras/0/projection/near: duplicate key \"near\"");
}

TEST(SceneLoaderErrors, NumberOverflowsDouble) {
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "type": "mesh",
    "positions": [0, 0, 0, 1, 1e999, 0, 0, 1, 0], "indices": [0, 1, 2]})")),
            "scenes/a.json: /objects/0/positions/4: expected a finite number, got 1e999");
  EXPECT_EQ(errorOf(withClipFromWorld("[1, 0, 0, 0, 0, -1e999, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]")),
            "scenes/a.json: /cameras/0/clipFromWorld/5: expected a finite number, got -1e999");
}

TEST(SceneLoaderErrors, RootAndVersion) {
  EXPECT_EQ(errorOf("[]"), "scenes/a.json: /: expected an object, got []");
  EXPECT_EQ(errorOf(R"({"cameras": [], "objects": []})"),
            "scenes/a.json: /: missing required field \"version\"");
  EXPECT_EQ(errorOf(R"({"version": 2, "cameras": [], "objects": []})"),
            "scenes/a.json: /version: unsupported version 2; this clipray reads version 1");
  EXPECT_EQ(errorOf(R"({"version": "1", "cameras": [], "objects": []})"),
            "scenes/a.json: /version: unsupported version \"1\"; this clipray reads version 1");
}

TEST(SceneLoaderErrors, UnknownKeys) {
  EXPECT_EQ(errorOf(R"({"version": 1, "camera": [], "objects": []})"),
            "scenes/a.json: /camera: unknown key \"camera\"; valid keys are \"version\", "
            "\"comment\", \"conventions\", \"depthRange\", \"depthClamp\", \"samples\", "
            "\"cameras\", \"objects\"");
  // A misspelt key is reported as unknown, not as a missing required field.
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main", "veiwport": [640, 480]})")),
            "scenes/a.json: /cameras/0/veiwport: unknown key \"veiwport\"; valid keys are "
            "\"name\", \"viewport\", \"clipFromWorld\", \"view\", \"viewFromWorld\", "
            "\"projection\", \"builtFor\", \"clipPlanes\", \"expectedFindings\", "
            "\"logarithmicDepth\"");
  EXPECT_EQ(errorOf(withProjection(R"({"type": "perspective", "fovY": 60, "near": 0.1})")),
            "scenes/a.json: /cameras/0/projection/fovY: unknown key \"fovY\"; valid keys are "
            "\"type\", \"fovYDegrees\", \"aspect\", \"near\", \"far\"");
  EXPECT_EQ(errorOf(withPlacement(R"("transform": {"rotate": 90})")),
            "scenes/a.json: /objects/0/transform/rotate: unknown key \"rotate\"; valid keys are "
            "\"translate\", \"rotateDegrees\", \"scale\"");
  EXPECT_EQ(errorOf(withPlacement(R"("color": [1, 0, 0])")),
            "scenes/a.json: /objects/0/color: unknown key \"color\"; valid keys are \"name\", "
            "\"type\", \"transform\", \"worldFromObject\", \"positions\", \"indices\", "
            "\"cull\", \"frontFace\", \"depthRange\", \"clipPlanes\", \"polygonOffset\"");
}

TEST(SceneLoaderErrors, WrongTypes) {
  EXPECT_EQ(errorOf(R"({"version": 1, "comment": 3, "cameras": [], "objects": []})"),
            "scenes/a.json: /comment: expected a string, got 3");
  EXPECT_EQ(errorOf(withProjection(R"({"type": "perspective", "fovYDegrees": 60, "near": "0.1"})")),
            "scenes/a.json: /cameras/0/projection/near: expected a number, got \"0.1\"");
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "type": "mesh",
    "positions": [0, 0, 0, 1, 0, 0, 0, true, 0], "indices": [0, 1, 2]})")),
            "scenes/a.json: /objects/0/positions/7: expected a number, got true");
  EXPECT_EQ(errorOf(withCamera("\"main\"")),
            "scenes/a.json: /cameras/0: expected an object, got \"main\"");
  EXPECT_EQ(errorOf(withView(R"("view": {"eye": [0, 0], "target": [0, 0, 0], "up": [0, 1, 0]})")),
            "scenes/a.json: /cameras/0/view/eye: expected an array of 3 numbers, got [0,0]");
}

TEST(SceneLoaderErrors, Conventions) {
  EXPECT_EQ(errorOf(R"({"version": 1, "conventions": "no", "cameras": [], "objects": []})"),
            "scenes/a.json: /conventions: expected an array of convention names, got \"no\"");
  EXPECT_EQ(errorOf(R"({"version": 1, "conventions": ["zo", "no-reversed"], "cameras": []})"),
            "scenes/a.json: /conventions/1: expected one of \"no\", \"zo\", \"zo-reversed\", "
            "\"no-upper-left\", \"zo-upper-left\", \"zo-reversed-upper-left\", got "
            "\"no-reversed\"");
  EXPECT_EQ(errorOf(R"({"version": 1, "conventions": ["zo", "zo"], "cameras": []})"),
            "scenes/a.json: /conventions/1: duplicate convention \"zo\"");
}

TEST(SceneLoaderErrors, CamerasAndObjectsArrays) {
  EXPECT_EQ(
      errorOf(R"({"version": 1, "cameras": [], "objects": []})"),
      "scenes/a.json: /cameras: expected a non-empty array of cameras, got [] (and no meshFile "
      "object with \"useCameras\": true)");
  EXPECT_EQ(errorOf(R"({"version": 1, "cameras": [)" + std::string(kCamera) + "]}"),
            "scenes/a.json: /: missing required field \"objects\"");
  EXPECT_EQ(
      errorOf(R"({"version": 1, "cameras": [)" + std::string(kCamera) + R"(], "objects": {}})"),
      "scenes/a.json: /objects: expected an array, got {}");
}

TEST(SceneLoaderErrors, AutomaticCameras) {
  const Scene scene = parseScene(
      R"({"version": 1, "cameras": "auto", "objects": [{"name": "ball", "type": "sphere",
          "centre": [0, 0, 0], "radius": 1}]})",
      kFile);
  ASSERT_EQ(scene.cameras.size(), 4u);
  EXPECT_EQ(scene.cameras[2].name, "auto_orthographic_x");  // a sphere: the first of equals
  EXPECT_EQ(errorOf(R"({"version": 1, "cameras": "auto", "objects": []})"),
            "scenes/a.json: /cameras: \"auto\" needs finite geometry to frame, and the scene "
            "has none");
  EXPECT_EQ(errorOf(R"({"version": 1, "cameras": "front", "objects": []})"),
            "scenes/a.json: /cameras: expected a non-empty array of cameras or \"auto\", got "
            "\"front\"");
}

TEST(SceneLoaderErrors, Names) {
  EXPECT_EQ(errorOf(withCamera(R"({"name": "", "viewport": [640, 480]})")),
            "scenes/a.json: /cameras/0/name: expected a non-empty string, got \"\"");
  EXPECT_EQ(errorOf(withCamera(R"({"viewport": [640, 480]})")),
            "scenes/a.json: /cameras/0: missing required field \"name\"");
  EXPECT_EQ(errorOf(withCamera(std::string(kCamera) + ", " + kCamera)),
            "scenes/a.json: /cameras/1/name: duplicate camera name \"main\" (first used at "
            "/cameras/0)");
  EXPECT_EQ(errorOf(withObject(std::string(kObject) + ", " + kObject)),
            "scenes/a.json: /objects/1/name: duplicate object name \"tri\" (first used at "
            "/objects/0)");
}

// ------------------------------------------------------------------------------------------------
// Bad input: cameras

TEST(SceneLoaderErrors, Viewport) {
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main"})")),
            "scenes/a.json: /cameras/0: missing required field \"viewport\"");
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main", "viewport": [0, 480]})")),
            "scenes/a.json: /cameras/0/viewport/0: expected an integer in [1, 16384], got 0");
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main", "viewport": [640, 16385]})")),
            "scenes/a.json: /cameras/0/viewport/1: expected an integer in [1, 16384], got 16385");
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main", "viewport": [640.5, 480]})")),
            "scenes/a.json: /cameras/0/viewport/0: expected an integer in [1, 16384], got 640.5");
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main", "viewport": [640]})")),
            "scenes/a.json: /cameras/0/viewport: expected an array of 2 integers [width, height], "
            "got [640]");
}

TEST(SceneLoaderErrors, PerspectiveProjection) {
  EXPECT_EQ(errorOf(withProjection(R"({"type": "perspective", "fovYDegrees": 60, "near": -1})")),
            "scenes/a.json: /cameras/0/projection/near: expected a positive number, got -1");
  EXPECT_EQ(errorOf(withProjection(R"({"type": "perspective", "fovYDegrees": 60, "near": 0})")),
            "scenes/a.json: /cameras/0/projection/near: expected a positive number, got 0");
  EXPECT_EQ(
      errorOf(withProjection(R"({"type": "perspective", "fovYDegrees": 60, "near": 1, "far": 1})")),
      "scenes/a.json: /cameras/0/projection/far: expected a number greater than \"near\" "
      "(1), got 1");
  EXPECT_EQ(errorOf(withProjection(R"({"type": "perspective", "fovYDegrees": 0, "near": 1})")),
            "scenes/a.json: /cameras/0/projection/fovYDegrees: expected a number in (0, 180), got "
            "0");
  EXPECT_EQ(errorOf(withProjection(R"({"type": "perspective", "fovYDegrees": 180.0, "near": 1})")),
            "scenes/a.json: /cameras/0/projection/fovYDegrees: expected a number in (0, 180), got "
            "180.0");
  EXPECT_EQ(errorOf(withProjection(
                R"({"type": "perspective", "fovYDegrees": 60, "aspect": 0, "near": 1})")),
            "scenes/a.json: /cameras/0/projection/aspect: expected a positive number, got 0");
  EXPECT_EQ(errorOf(withProjection(R"({"type": "perspective", "near": 1})")),
            "scenes/a.json: /cameras/0/projection: missing required field \"fovYDegrees\"");
}

TEST(SceneLoaderErrors, OrthographicProjection) {
  EXPECT_EQ(errorOf(withProjection(R"({"type": "orthographic",
    "left": 1, "right": 1, "bottom": -1, "top": 1, "near": 0, "far": 10})")),
            "scenes/a.json: /cameras/0/projection/right: expected a number different from "
            "\"left\" (1), got 1");
  EXPECT_EQ(errorOf(withProjection(R"({"type": "orthographic",
    "left": -1, "right": 1, "bottom": 0.5, "top": 0.5, "near": 0, "far": 10})")),
            "scenes/a.json: /cameras/0/projection/top: expected a number different from "
            "\"bottom\" (0.5), got 0.5");
  EXPECT_EQ(errorOf(withProjection(R"({"type": "orthographic",
    "left": -1, "right": 1, "bottom": -1, "top": 1, "near": 10, "far": -10})")),
            "scenes/a.json: /cameras/0/projection/far: expected a number greater than \"near\" "
            "(10), got -10");
  EXPECT_EQ(errorOf(withProjection(R"({"type": "orthographic",
    "left": -1, "right": 1, "bottom": -1, "top": 1, "near": 0})")),
            "scenes/a.json: /cameras/0/projection: missing required field \"far\"");
}

TEST(SceneLoaderErrors, ProjectionType) {
  EXPECT_EQ(errorOf(withProjection(R"({"type": "fisheye"})")),
            "scenes/a.json: /cameras/0/projection/type: expected one of \"perspective\", "
            "\"orthographic\", got \"fisheye\"");
  EXPECT_EQ(errorOf(withProjection(R"({"fovYDegrees": 60, "near": 0.1})")),
            "scenes/a.json: /cameras/0/projection: missing required field \"type\"");
}

TEST(SceneLoaderErrors, ProjectionOverflowsDouble) {
  EXPECT_EQ(errorOf(withProjection(
                R"({"type": "perspective", "fovYDegrees": 1e-300, "aspect": 1e-10, "near": 1})")),
            "scenes/a.json: /cameras/0: the camera's clipFromWorld overflows double when drawn "
            "under \"no\"");
}

TEST(SceneLoaderErrors, ClipFromWorld) {
  EXPECT_EQ(errorOf(withClipFromWorld("[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0]")),
            "scenes/a.json: /cameras/0/clipFromWorld: expected an array of 16 numbers "
            "(column-major), got [1,0,0,0,0,1,0,0,0,0,1,0,0,0,0]");
  EXPECT_EQ(errorOf(withClipFromWorld("[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, \"x\", 1]")),
            "scenes/a.json: /cameras/0/clipFromWorld/14: expected a number, got \"x\"");
  // Row 3 (w) all zero.
  EXPECT_EQ(errorOf(withClipFromWorld("[0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]")),
            "scenes/a.json: /cameras/0/clipFromWorld: expected a projective matrix whose row 3 "
            "(w) is positive somewhere, got row 3 = [0,0,0,0]");
  // Row 3 a negative constant: every point has w < 0 and is clipped.
  EXPECT_EQ(errorOf(withClipFromWorld("[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1]")),
            "scenes/a.json: /cameras/0/clipFromWorld: expected a projective matrix whose row 3 "
            "(w) is positive somewhere, got row 3 = [0,0,0,-1]");
  // Column 1 is zero.
  EXPECT_EQ(errorOf(withClipFromWorld("[1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]")),
            "scenes/a.json: /cameras/0/clipFromWorld: expected an invertible matrix, got a "
            "singular one (scaled determinant 0)");
  // Nearly singular: column 1 equals column 0 to 1e-13.
  EXPECT_THAT(
      errorOf(withClipFromWorld("[1, 1, 0, 0, 1, 1.0000000000001, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]")),
      StartsWith("scenes/a.json: /cameras/0/clipFromWorld: expected an invertible "
                 "matrix, got a singular one (scaled determinant "));
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main", "viewport": [640, 480],
    "clipFromWorld": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1],
    "projection": {"type": "perspective", "fovYDegrees": 60, "near": 0.1}})")),
            "scenes/a.json: /cameras/0: expected either \"clipFromWorld\" or \"projection\", got "
            "both");
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main", "viewport": [640, 480],
    "clipFromWorld": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], "builtFor": "zo"})")),
            "scenes/a.json: /cameras/0: expected either \"clipFromWorld\" or \"builtFor\", got "
            "both");
}

TEST(SceneLoaderErrors, ViewFromWorld) {
  EXPECT_EQ(
      errorOf(withView(R"("viewFromWorld": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, -1, 0, 0, 0, 0])")),
      "scenes/a.json: /cameras/0/viewFromWorld: expected an affine matrix (row 3 = "
      "[0,0,0,1]), got row 3 = [0,0,-1,0]");
  EXPECT_EQ(
      errorOf(withView(R"("viewFromWorld": [1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1])")),
      "scenes/a.json: /cameras/0/viewFromWorld: expected an invertible matrix, got a "
      "singular one (scaled determinant 0)");
  EXPECT_EQ(errorOf(withView(R"("view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
    "viewFromWorld": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1])")),
            "scenes/a.json: /cameras/0: expected either \"view\" or \"viewFromWorld\", got both");
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main", "viewport": [640, 480],
    "projection": {"type": "perspective", "fovYDegrees": 60, "near": 0.1}})")),
            "scenes/a.json: /cameras/0: missing required field \"view\" or \"viewFromWorld\"");
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main", "viewport": [640, 480],
    "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]}})")),
            "scenes/a.json: /cameras/0: missing required field \"projection\"");
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main", "viewport": [640, 480]})")),
            "scenes/a.json: /cameras/0: missing required field \"clipFromWorld\", or "
            "\"projection\" with \"view\" or \"viewFromWorld\"");
  EXPECT_EQ(errorOf(withView(R"("viewFromWorld": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1],
    "builtFor": "zo-rev")")),
            "scenes/a.json: /cameras/0/builtFor: expected one of \"no\", \"zo\", \"zo-reversed\", "
            "\"no-upper-left\", \"zo-upper-left\", \"zo-reversed-upper-left\", got \"zo-rev\"");
}

TEST(SceneLoaderErrors, DepthRange) {
  const auto withRange = [](const std::string& range) {
    return errorOf(R"({"version": 1, "depthRange": )" + range + R"(, "cameras": []})");
  };
  EXPECT_EQ(withRange("0.5"),
            "scenes/a.json: /depthRange: expected [near, far] of glDepthRange, got 0.5");
  EXPECT_EQ(withRange("[0, 0.5, 1]"),
            "scenes/a.json: /depthRange: expected [near, far] of glDepthRange, got [0,0.5,1]");
  EXPECT_EQ(withRange("[0, 1.5]"),
            "scenes/a.json: /depthRange/1: expected a number in [0, 1] (GL clamps glDepthRange to "
            "it), got 1.5");
  EXPECT_EQ(withRange("[-0.1, 1]"),
            "scenes/a.json: /depthRange/0: expected a number in [0, 1] (GL clamps glDepthRange to "
            "it), got -0.1");
  EXPECT_EQ(withRange("[\"0\", 1]"), "scenes/a.json: /depthRange/0: expected a number, got \"0\"");
  EXPECT_EQ(withRange("[0.3, 0.3]"),
            "scenes/a.json: /depthRange: near and far are both 0.3; every depth would be equal");
}

TEST(SceneLoaderErrors, ObjectDepthRange) {
  const auto mesh = [](const std::string& sceneKeys, const std::string& keys) {
    std::string text = withObject(R"({"name": "weapon", "type": "mesh",
      "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2], )" +
                                  keys + "}");
    text.insert(text.find('{') + 1, sceneKeys);
    return errorOf(text);
  };
  EXPECT_EQ(mesh("", R"("depthRange": [0, 1.5])"),
            "scenes/a.json: /objects/0/depthRange/1: expected a number in [0, 1] (GL clamps "
            "glDepthRange to it), got 1.5");
  EXPECT_EQ(mesh("", R"("depthRange": 0.1)"),
            "scenes/a.json: /objects/0/depthRange: expected [near, far] of glDepthRange, got 0.1");
  EXPECT_EQ(mesh("", R"("depthRange": [0.1, 0])"),
            "scenes/a.json: /objects/0/depthRange: expected a range that runs the way the scene's "
            "[0.0,1.0] does (one depth test for the frame), got [0.1,0]");
  EXPECT_EQ(mesh(R"("depthRange": [1, 0.1], )", R"("depthRange": [0, 0.1])"),
            "scenes/a.json: /objects/0/depthRange: expected a range that runs the way the scene's "
            "[1.0,0.1] does (one depth test for the frame), got [0,0.1]");
  EXPECT_EQ(mesh(R"("depthClamp": true, )", R"("depthRange": [0, 0.1])"),
            "scenes/a.json: /depthClamp: depth clamp with an object drawn in a depth range of its "
            "own (\"weapon\") is not modelled: use the scene's depthRange for every object");
  EXPECT_EQ(errorOf(withObject(
                R"({"name": "ball", "type": "sphere", "centre": [0, 0, 0], "radius": 1,
                    "depthRange": [0, 0.1]})")),
            "scenes/a.json: /objects/0/depthRange: a depth range per object applies to triangle "
            "meshes (mesh, meshFile, terrain); a sphere is drawn with the scene's (its fragment "
            "shader writes its depth)");
}

TEST(SceneLoaderErrors, ObjectClipPlanes) {
  const auto mesh = [](const std::string& keys) {
    return errorOf(withObject(R"({"name": "house", "type": "mesh",
      "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2], )" +
                              keys + "}"));
  };
  EXPECT_EQ(mesh(R"("clipPlanes": [[0, 0, 0, 1]])"),
            "scenes/a.json: /objects/0/clipPlanes/0: expected a plane with a non-zero normal [a, "
            "b, c], got [0,0,0,1]");
  EXPECT_EQ(mesh(R"("clipPlanes": [[1, 0, 0]])"),
            "scenes/a.json: /objects/0/clipPlanes/0: expected a plane [a, b, c, d] (kept where a "
            "x + b y + c z + d >= 0), got [1,0,0]");
  EXPECT_EQ(mesh(R"("clipPlanes": [[1, 0, 0, 1e999]])"),
            "scenes/a.json: /objects/0/clipPlanes/0/3: expected a finite number, got 1e999");
  EXPECT_EQ(errorOf(withObject(
                R"({"name": "ball", "type": "sphere", "centre": [0, 0, 0], "radius": 1,
                    "clipPlanes": [[1, 0, 0, 0]]})")),
            "scenes/a.json: /objects/0/clipPlanes: clip planes per object apply to triangle meshes "
            "(mesh, meshFile, terrain); a sphere is ray-traced by its fragment shader from the "
            "near plane, not the clipped interval");
  // Eight with the camera's: one too many.
  std::string eight = "[";
  for (int k = 0; k < 8; ++k) eight += std::string(k ? ", " : "") + "[1, 0, 0, 1]";
  eight += "]";
  std::string text = sceneWith(R"({"name": "main", "viewport": [640, 480],
      "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
      "projection": {"type": "perspective", "fovYDegrees": 60, "near": 0.1},
      "clipPlanes": [[0, 1, 0, 0]]})",
                               R"({"name": "house", "type": "mesh",
      "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2], "clipPlanes": )" +
                                   eight + "}");
  EXPECT_EQ(errorOf(text),
            "scenes/a.json: /objects: object \"house\" has 8 clip planes and camera \"main\" 1: at "
            "most 8 together (gl_ClipDistance; GL_MAX_CLIP_DISTANCES is at least 8)");
}

TEST(SceneLoaderErrors, PolygonOffset) {
  const auto mesh = [](const std::string& offset) {
    return errorOf(withObject(R"({"name": "decal", "type": "mesh",
      "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2], "polygonOffset": )" +
                              offset + "}"));
  };
  EXPECT_EQ(mesh("-1"),
            "scenes/a.json: /objects/0/polygonOffset: expected {\"factor\", \"units\", "
            "\"clamp\"} of glPolygonOffsetClamp, got -1");
  EXPECT_EQ(mesh("[-1, -2]"),
            "scenes/a.json: /objects/0/polygonOffset: expected {\"factor\", \"units\", "
            "\"clamp\"} of glPolygonOffsetClamp, got [-1,-2]");
  EXPECT_EQ(mesh(R"({"factor": -1, "unit": -2})"),
            "scenes/a.json: /objects/0/polygonOffset/unit: unknown key \"unit\"; valid keys are "
            "\"factor\", \"units\", \"clamp\"");
  EXPECT_EQ(mesh(R"({"factor": 1e999})"),
            "scenes/a.json: /objects/0/polygonOffset/factor: expected a finite number, got 1e999");
  EXPECT_EQ(mesh(R"({"units": -1e999})"),
            "scenes/a.json: /objects/0/polygonOffset/units: expected a finite number, got -1e999");
  EXPECT_EQ(mesh(R"({"factor": -1, "clamp": "0.01"})"),
            "scenes/a.json: /objects/0/polygonOffset/clamp: expected a number, got \"0.01\"");
  EXPECT_EQ(errorOf(withObject(
                R"({"name": "ball", "type": "sphere", "centre": [0, 0, 0], "radius": 1,
                    "polygonOffset": {"factor": -1, "units": -2}})")),
            "scenes/a.json: /objects/0/polygonOffset: polygon offset applies to triangle meshes "
            "(mesh, meshFile, terrain); a sphere writes its own depth from its fragment shader, "
            "which no offset moves");
}

TEST(SceneLoaderErrors, LogarithmicDepth) {
  const auto camera = [](const std::string& logDepth) {
    return errorOf(withCamera(R"({"name": "main", "viewport": [640, 480],
      "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
      "projection": {"type": "perspective", "fovYDegrees": 60, "near": 0.1, "far": 100},
      "logarithmicDepth": )" + logDepth +
                              "}"));
  };
  EXPECT_EQ(camera(R"({"form": "threejs", "far": 100})"), "no error");
  EXPECT_EQ(camera(R"({"form": "outerra", "far": 100, "constant": 0.01})"), "no error");
  // Beyond the projection's far plane nothing is drawn; before it, past the log far, the written
  // depth would pass 1.
  EXPECT_EQ(camera(R"({"form": "threejs", "far": 1000})"), "no error");
  EXPECT_EQ(camera(R"({"form": "threejs", "far": 50})"),
            "scenes/a.json: /cameras/0/logarithmicDepth/far: a logarithmic depth whose far (50) "
            "lies before the projection's far plane (100) is not modelled: what lies between is "
            "written at a depth past 1, which GL clamps and the depth test then hides; give both "
            "the same far, as three.js's logarithmicDepthBuffer does (camera.far)");
  EXPECT_EQ(camera("true"),
            "scenes/a.json: /cameras/0/logarithmicDepth: expected {\"form\", \"far\", "
            "\"constant\"} of a logarithmic depth, got true");
  EXPECT_EQ(camera(R"({"form": "cesium", "far": 100})"),
            "scenes/a.json: /cameras/0/logarithmicDepth/form: expected one of \"threejs\", "
            "\"outerra\", got \"cesium\"");
  EXPECT_EQ(camera(R"({"form": "threejs", "far": 0})"),
            "scenes/a.json: /cameras/0/logarithmicDepth/far: expected a positive number, got 0");
  EXPECT_EQ(camera(R"({"form": "threejs", "far": -100})"),
            "scenes/a.json: /cameras/0/logarithmicDepth/far: expected a positive number, got "
            "-100");
  EXPECT_EQ(camera(R"({"form": "outerra", "far": 100, "constant": 0})"),
            "scenes/a.json: /cameras/0/logarithmicDepth/constant: expected a positive number, got "
            "0");
  EXPECT_EQ(camera(R"({"form": "outerra", "far": 100, "constant": -1})"),
            "scenes/a.json: /cameras/0/logarithmicDepth/constant: expected a positive number, got "
            "-1");
  EXPECT_EQ(camera(R"({"form": "outerra", "far": 100, "constant": 1e999})"),
            "scenes/a.json: /cameras/0/logarithmicDepth/constant: expected a finite number, got "
            "1e999");
  EXPECT_EQ(camera(R"({"form": "outerra", "far": 100})"),
            "scenes/a.json: /cameras/0/logarithmicDepth: missing required field \"constant\"");
  EXPECT_EQ(camera(R"({"form": "threejs", "far": 100, "constant": 2})"),
            "scenes/a.json: /cameras/0/logarithmicDepth/constant: three.js's logarithmic depth "
            "has no constant (log2(1 + w)); use \"form\": \"outerra\" for log2(1 + C w) / "
            "log2(1 + C far)");
  EXPECT_EQ(camera(R"({"form": "threejs", "far": 100, "near": 1})"),
            "scenes/a.json: /cameras/0/logarithmicDepth/near: unknown key \"near\"; valid keys "
            "are \"form\", \"far\", \"constant\"");
  // What the model leaves out: one line naming the field.
  const std::string logCamera = R"({"name": "main", "viewport": [640, 480],
      "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
      "projection": {"type": "perspective", "fovYDegrees": 60, "near": 0.1, "far": 100},
      "logarithmicDepth": {"form": "threejs", "far": 100}})";
  const std::string unmodelled =
      " is not modelled; use triangle meshes drawn with the default depth range, no depth clamp "
      "and no polygon offset, seen through a perspective projection";
  EXPECT_EQ(errorOf(sceneWith(logCamera, R"({"name": "ball", "type": "sphere", "centre": [0, 0, 0],
                                             "radius": 1})")),
            "scenes/a.json: /cameras/0/logarithmicDepth: a logarithmic depth with a sphere "
            "(\"ball\")" +
                unmodelled);
  EXPECT_EQ(errorOf(R"({"version": 1, "depthClamp": true, "cameras": [)" + logCamera +
                    R"(], "objects": [)" + kObject + "]}"),
            "scenes/a.json: /cameras/0/logarithmicDepth: a logarithmic depth with depth clamp" +
                unmodelled);
  EXPECT_EQ(errorOf(R"({"version": 1, "depthRange": [1, 0], "cameras": [)" + logCamera +
                    R"(], "objects": [)" + kObject + "]}"),
            "scenes/a.json: /cameras/0/logarithmicDepth: a logarithmic depth with the scene's "
            "depthRange" +
                unmodelled);
  EXPECT_EQ(errorOf(sceneWith(logCamera, R"({"name": "decal", "type": "mesh",
      "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2],
      "polygonOffset": {"factor": -1, "units": -2}})")),
            "scenes/a.json: /cameras/0/logarithmicDepth: a logarithmic depth with a polygon offset "
            "(\"decal\")" +
                unmodelled);
  EXPECT_EQ(errorOf(sceneWith(logCamera, R"({"name": "weapon", "type": "mesh",
      "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2], "depthRange": [0, 0.1]})")),
            "scenes/a.json: /cameras/0/logarithmicDepth: a logarithmic depth with a depth range "
            "per object (\"weapon\")" +
                unmodelled);
  EXPECT_EQ(errorOf(withCamera(R"({"name": "main", "viewport": [640, 480],
      "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
      "projection": {"type": "orthographic", "left": -1, "right": 1, "bottom": -1, "top": 1,
                     "near": 0.1, "far": 100},
      "logarithmicDepth": {"form": "threejs", "far": 100}})")),
            "scenes/a.json: /cameras/0/logarithmicDepth: a logarithmic depth with a parallel "
            "projection (clip w is 1 everywhere)" +
                unmodelled);
}

TEST(SceneLoaderErrors, FaceCulling) {
  const auto mesh = [](const std::string& keys) {
    return errorOf(withObject(R"({"name": "tri", "type": "mesh",
      "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2], )" +
                              keys + "}"));
  };
  EXPECT_EQ(mesh(R"("cull": "both")"),
            "scenes/a.json: /objects/0/cull: expected one of \"none\", \"back\", \"front\" "
            "(glCullFace), got \"both\"");
  EXPECT_EQ(mesh(R"("cull": "BACK")"),
            "scenes/a.json: /objects/0/cull: expected one of \"none\", \"back\", \"front\" "
            "(glCullFace), got \"BACK\"");
  EXPECT_EQ(mesh(R"("cull": true)"),
            "scenes/a.json: /objects/0/cull: expected one of \"none\", \"back\", \"front\" "
            "(glCullFace), got true");
  EXPECT_EQ(mesh(R"("cull": "back", "frontFace": "clockwise")"),
            "scenes/a.json: /objects/0/frontFace: expected one of \"ccw\", \"cw\" (glFrontFace), "
            "got \"clockwise\"");
  EXPECT_EQ(errorOf(withObject(
                R"({"name": "ball", "type": "sphere", "centre": [0, 0, 0], "radius": 1,
                    "cull": "back"})")),
            "scenes/a.json: /objects/0/cull: face culling applies to triangle meshes (mesh, "
            "meshFile, terrain); a sphere is ray-traced by its fragment shader and has no winding");
  EXPECT_EQ(errorOf(withObject(
                R"({"name": "lid", "type": "quad", "centre": [0, 0, 0],
                    "halfEdges": [[1, 0, 0], [0, 1, 0]], "frontFace": "cw"})")),
            "scenes/a.json: /objects/0/frontFace: face culling applies to triangle meshes (mesh, "
            "meshFile, terrain); a quad is ray-traced by its fragment shader and has no winding");
}

TEST(SceneLoaderErrors, DepthClamp) {
  EXPECT_EQ(errorOf(R"({"version": 1, "depthClamp": 1, "cameras": [], "objects": []})"),
            "scenes/a.json: /depthClamp: expected true or false (GL_DEPTH_CLAMP), got 1");
  const std::string ball = R"({"name": "ball", "type": "sphere", "centre": [0, 0, 0],
      "radius": 1})";
  std::string clamped = sceneWith(R"({"name": "main", "viewport": [640, 480],
      "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
      "projection": {"type": "perspective", "fovYDegrees": 60, "near": 0.1}})",
                                  ball);
  clamped.insert(clamped.find('{') + 1, R"("depthClamp": true, )");
  EXPECT_EQ(errorOf(clamped),
            "scenes/a.json: /depthClamp: depth clamp with analytic primitives (\"ball\") is not "
            "modelled: their fragment shader traces the ray from the near plane, and depth clamp "
            "draws what lies in front of it; use triangle meshes");
}

TEST(SceneLoaderErrors, Samples) {
  const auto withSamples = [](const std::string& samples, const std::string& scene) {
    std::string text = scene;
    text.insert(text.find('{') + 1, "\"samples\": " + samples + ", ");
    return errorOf(text);
  };
  const std::string plain = withObject(kObject);
  EXPECT_EQ(withSamples("4", plain), "no error");
  for (const char* bad : {"0", "65", "2.5", "\"4\""}) {
    EXPECT_EQ(withSamples(bad, plain),
              std::string("scenes/a.json: /samples: expected a sample count from 1 to 64 (samples "
                          "per pixel), got ") +
                  bad)
        << bad;
  }
  const std::string ball = R"({"name": "ball", "type": "sphere", "centre": [0, 0, 0],
      "radius": 1})";
  EXPECT_EQ(withSamples("4", withObject(ball)),
            "scenes/a.json: /samples: multisampling with analytic primitives (\"ball\") is not "
            "modelled: their fragment shader writes one depth per pixel, at its centre; use "
            "triangle meshes");
  EXPECT_EQ(withSamples("1", withObject(ball)), "no error");
  const std::string logDepth = withCamera(R"({"name": "main", "viewport": [640, 480],
      "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
      "projection": {"type": "perspective", "fovYDegrees": 60, "near": 0.1, "far": 100},
      "logarithmicDepth": {"form": "threejs", "far": 100}})");
  EXPECT_EQ(withSamples("4", logDepth),
            "scenes/a.json: /samples: multisampling with a logarithmic depth (camera \"main\") is "
            "not modelled: its fragment shader writes one depth per pixel, at its centre");
}

TEST(SceneLoaderErrors, ClipPlanes) {
  const auto withPlanes = [](const std::string& planes) {
    return errorOf(withView(R"("view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
      "clipPlanes": )" + planes));
  };
  EXPECT_EQ(withPlanes("[0, 1, 0, 0]"),
            "scenes/a.json: /cameras/0/clipPlanes/0: expected a plane [a, b, c, d] (kept where a x "
            "+ b y + c z + d >= 0), got 0");
  EXPECT_EQ(withPlanes("{}"),
            "scenes/a.json: /cameras/0/clipPlanes: expected an array of at most 8 planes [a, b, c, "
            "d] (gl_ClipDistance; GL_MAX_CLIP_DISTANCES is at least 8), got {}");
  std::string nine = "[";
  for (int i = 0; i < 9; ++i)
    nine += std::string(i ? ", " : "") + "[0, 1, 0, " + std::to_string(i) + "]";
  EXPECT_EQ(withPlanes(nine + "]").substr(0, 88),
            "scenes/a.json: /cameras/0/clipPlanes: expected an array of at most 8 planes [a, b, c, "
            "d]");
  EXPECT_EQ(withPlanes("[[0, 1, 0]]"),
            "scenes/a.json: /cameras/0/clipPlanes/0: expected a plane [a, b, c, d] (kept where a x "
            "+ b y + c z + d >= 0), got [0,1,0]");
  EXPECT_EQ(
      withPlanes("[[0, 1, 0, 0], [0, 0, 0, 1]]"),
      "scenes/a.json: /cameras/0/clipPlanes/1: expected a plane with a non-zero normal [a, b, "
      "c], got [0,0,0,1]");
  EXPECT_EQ(withPlanes("[[0, 1e999, 0, 0]]"),
            "scenes/a.json: /cameras/0/clipPlanes/0/1: expected a finite number, got 1e999");
  EXPECT_EQ(withPlanes("[[0, \"1\", 0, 0]]"),
            "scenes/a.json: /cameras/0/clipPlanes/0/1: expected a number, got \"1\"");
  EXPECT_EQ(errorOf(sceneWith(R"({"name": "main", "viewport": [640, 480],
      "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
      "projection": {"type": "perspective", "fovYDegrees": 60, "near": 0.1},
      "clipPlanes": [[0, 1, 0, 0]]})",
                              R"({"name": "ball", "type": "sphere", "centre": [0, 0, 0],
      "radius": 1})")),
            "scenes/a.json: /cameras/0/clipPlanes: clip planes with analytic primitives (\"ball\") "
            "are not modelled: their fragment shader traces the ray from the near plane, not the "
            "clipped interval; use triangle meshes");
}

TEST(SceneLoaderErrors, LookAt) {
  EXPECT_EQ(
      errorOf(withView(R"("view": {"eye": [1, 2, 3], "target": [1, 2, 3], "up": [0, 1, 0]})")),
      "scenes/a.json: /cameras/0/view/target: expected a point different from \"eye\" "
      "([1,2,3]), got [1,2,3]");
  EXPECT_EQ(
      errorOf(withView(R"("view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 0, 0]})")),
      "scenes/a.json: /cameras/0/view/up: expected a non-zero direction, got [0,0,0]");
  EXPECT_EQ(
      errorOf(withView(R"("view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 0, 2]})")),
      "scenes/a.json: /cameras/0/view/up: expected a direction not parallel to the view "
      "direction (target - eye), got [0,0,2]");
  EXPECT_EQ(errorOf(withView(R"("view": {"eye": [0, 0, 5], "up": [0, 1, 0]})")),
            "scenes/a.json: /cameras/0/view: missing required field \"target\"");
}

// ------------------------------------------------------------------------------------------------
// Bad input: objects

TEST(SceneLoaderErrors, ObjectType) {
  EXPECT_EQ(errorOf(withObject(R"({"name": "ball", "type": "ball", "radius": 1})")),
            "scenes/a.json: /objects/0/type: expected one of \"mesh\", \"meshFile\", \"terrain\", "
            "\"sphere\", \"disk\", \"quad\", \"box\", \"plane\", got \"ball\"");
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "positions": [], "indices": []})")),
            "scenes/a.json: /objects/0: missing required field \"type\"");
}

TEST(SceneLoaderErrors, Positions) {
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "type": "mesh",
    "positions": [0, 0, 0, 1, 0, 0, 0, 1], "indices": [0, 1, 2]})")),
            "scenes/a.json: /objects/0/positions: expected a flat array of x, y, z coordinates of "
            "at least 3 vertices, got [0,0,0,1,0,0,0,1]");
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "type": "mesh",
    "positions": [0, 0, 0, 1, 0, 0], "indices": [0, 1, 1]})")),
            "scenes/a.json: /objects/0/positions: expected a flat array of x, y, z coordinates of "
            "at least 3 vertices, got [0,0,0,1,0,0]");
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "type": "mesh", "indices": [0, 1, 2]})")),
            "scenes/a.json: /objects/0: missing required field \"positions\"");
}

TEST(SceneLoaderErrors, Indices) {
  EXPECT_EQ(errorOf(withObject(R"({"name": "box", "type": "mesh",
    "positions": [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1],
    "indices": [0, 1, 2, 0, 2, 3, 4, 12, 6]})")),
            "scenes/a.json: /objects/0/indices/7: index 12 out of range for 8 vertices");
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "type": "mesh",
    "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, -1, 2]})")),
            "scenes/a.json: /objects/0/indices/1: expected an unsigned integer, got -1");
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "type": "mesh",
    "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2.0]})")),
            "scenes/a.json: /objects/0/indices/2: expected an unsigned integer, got 2.0");
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "type": "mesh",
    "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": []})")),
            "scenes/a.json: /objects/0/indices: expected a flat array of vertex indices, 3 per "
            "triangle, at least 1 triangle, got []");
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "type": "mesh",
    "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2, 0]})")),
            "scenes/a.json: /objects/0/indices: expected a flat array of vertex indices, 3 per "
            "triangle, at least 1 triangle, got [0,1,2,0]");
}

TEST(SceneLoaderErrors, ObjectPlacement) {
  EXPECT_EQ(errorOf(withPlacement(R"("transform": {"scale": 2},
    "worldFromObject": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1])")),
            "scenes/a.json: /objects/0: expected either \"transform\" or \"worldFromObject\", got "
            "both");
  EXPECT_EQ(errorOf(withPlacement(
                R"("worldFromObject": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1])")),
            "scenes/a.json: /objects/0/worldFromObject: expected an invertible matrix, got a "
            "singular one (scaled determinant 0)");
  EXPECT_EQ(errorOf(withPlacement(
                R"("worldFromObject": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2])")),
            "scenes/a.json: /objects/0/worldFromObject: expected an affine matrix (row 3 = "
            "[0,0,0,1]), got row 3 = [0,0,0,2]");
  EXPECT_EQ(errorOf(withPlacement(
                R"("worldFromObject": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1e999])")),
            "scenes/a.json: /objects/0/worldFromObject/15: expected a finite number, got 1e999");
  EXPECT_EQ(errorOf(withPlacement(R"("transform": {"scale": 0})")),
            "scenes/a.json: /objects/0/transform/scale: expected a non-zero number, got 0");
  EXPECT_EQ(errorOf(withPlacement(R"("transform": {"scale": [1, 0.0, 1]})")),
            "scenes/a.json: /objects/0/transform/scale/1: expected a non-zero number, got 0.0");
  EXPECT_EQ(errorOf(withPlacement(R"("transform": {"scale": [1, 1]})")),
            "scenes/a.json: /objects/0/transform/scale: expected a number or an array of 3 "
            "numbers, got [1,1]");
  EXPECT_EQ(
      errorOf(withPlacement(R"("transform": {"rotateDegrees": {"axis": [0, 0, 0], "angle": 30}})")),
      "scenes/a.json: /objects/0/transform/rotateDegrees/axis: expected a non-zero "
      "direction, got [0,0,0]");
  EXPECT_EQ(errorOf(withPlacement(R"("transform": {"rotateDegrees": {"axis": [0, 0, 1]}})")),
            "scenes/a.json: /objects/0/transform/rotateDegrees: missing required field \"angle\"");
  EXPECT_EQ(errorOf(withPlacement(R"("transform": {"translate": [1, 2, "3"]})")),
            "scenes/a.json: /objects/0/transform/translate/2: expected a number, got \"3\"");
}

TEST(SceneLoaderErrors, WorldPositionOverflowsDouble) {
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "type": "mesh",
    "positions": [0, 0, 0, 1e300, 0, 0, 0, 1, 0], "indices": [0, 1, 2],
    "transform": {"scale": 1e300}})")),
            "scenes/a.json: /objects/0/positions/3: vertex 1 has a world position that overflows "
            "double after the transform");
}

TEST(SceneLoaderErrors, LongValuesAreCut) {
  std::string positions = "[";
  for (int i = 0; i < 40; ++i) {
    if (i > 0) positions += ",";
    positions += std::to_string(i);
  }
  EXPECT_EQ(errorOf(withObject(R"({"name": "tri", "type": "mesh", "positions": )" + positions +
                               R"(], "indices": [0, 1, 2]})")),
            "scenes/a.json: /objects/0/positions: expected a flat array of x, y, z coordinates of "
            "at least 3 vertices, got "
            "[0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28...");
}

}  // namespace
}  // namespace clipray
