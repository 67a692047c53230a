// glTF and GLB files: what the shipped test files and generated documents turn into, exactly,
// and the message for every kind of bad input (OBJ, PLY and what all formats share:
// MeshFileTest.cpp).

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/scene/MeshFiles.hpp"
#include "support/MeshFileChecks.hpp"

namespace clipray {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::StartsWith;
using json = nlohmann::json;
using testing::errorOf;
using testing::kMeshDataDir;
using testing::positionsOf;

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string text;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t group = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size())
      group |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) group |= static_cast<unsigned char>(bytes[i + 2]);
    text += kAlphabet[(group >> 18) & 63];
    text += kAlphabet[(group >> 12) & 63];
    text += i + 1 < bytes.size() ? kAlphabet[(group >> 6) & 63] : '=';
    text += i + 2 < bytes.size() ? kAlphabet[group & 63] : '=';
  }
  return text;
}

template <typename T>
std::string bytesOf(const std::vector<T>& values) {
  std::string bytes(values.size() * sizeof(T), '\0');
  std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

// One triangle (indexed with unsigned shorts) in an embedded buffer: tests break one field.
json triangleGltf(const std::vector<float>& positions = {0, 0, 0, 1, 0, 0, 0, 1, 0},
                  const std::vector<std::uint16_t>& indices = {0, 1, 2}) {
  const std::string buffer = bytesOf(positions) + bytesOf(indices);
  const auto positionBytes = positions.size() * sizeof(float);
  return {
      {"asset", {{"version", "2.0"}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes",
       {{{"name", "Tri"}, {"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"buffers",
       {{{"uri", "data:application/octet-stream;base64," + base64(buffer)},
         {"byteLength", buffer.size()}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", positionBytes}},
        {{"buffer", 0}, {"byteOffset", positionBytes}, {"byteLength", indices.size() * 2}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", positions.size() / 3},
         {"type", "VEC3"}},
        {{"bufferView", 1},
         {"componentType", 5123},
         {"count", indices.size()},
         {"type", "SCALAR"}}}},
  };
}

// ---- Good files ------------------------------------------------------------------------------

TEST(MeshFileGltf, HierarchyWithExternalBufferAppliesTrsAndMatrixExactly) {
  const MeshFileContents contents = loadMeshFile(kMeshDataDir + "hierarchy.gltf");
  ASSERT_EQ(contents.objects.size(), 2u);
  // Quad: child translate (0,0,-1) under parent T(1,2,3) * R(180 deg about z) * S(2).
  EXPECT_EQ(contents.objects[0].name, "Quad/0");
  EXPECT_THAT(positionsOf(contents.objects[0]),
              ElementsAre(glm::dvec3(1, 2, 1), glm::dvec3(-1, 2, 1), glm::dvec3(-1, 0, 1),
                          glm::dvec3(1, 0, 1)));
  EXPECT_THAT(contents.objects[0].triangles,
              ElementsAre(glm::u32vec3(0, 1, 2), glm::u32vec3(0, 2, 3)));
  // Triangle: not indexed, placed by a matrix (x, y, z) -> (10 - y, 20 + x, 30 + z).
  EXPECT_EQ(contents.objects[1].name, "Triangle/0");
  EXPECT_THAT(positionsOf(contents.objects[1]),
              ElementsAre(glm::dvec3(10, 20, 30), glm::dvec3(10, 22, 30), glm::dvec3(8, 20, 30)));
  EXPECT_THAT(contents.objects[1].triangles, ElementsAre(glm::u32vec3(0, 1, 2)));
  EXPECT_TRUE(contents.warnings.empty());
}

TEST(MeshFileGltf, CamerasKeepTheirProjectionAndViewFromWorld) {
  const MeshFileContents contents = loadMeshFile(kMeshDataDir + "hierarchy.gltf");
  ASSERT_EQ(contents.cameras.size(), 3u);

  const Camera& withFar = contents.cameras[0];
  EXPECT_EQ(withFar.name, "persp");
  EXPECT_EQ(withFar.viewport, (Viewport{320, 240}));
  const auto& perspective = std::get<PerspectiveProjection>(withFar.projection);
  EXPECT_DOUBLE_EQ(perspective.fovYDegrees, 0.5 * 180.0 / std::numbers::pi);
  EXPECT_FALSE(perspective.aspect.has_value());
  EXPECT_EQ(perspective.nearDistance, 0.25);
  EXPECT_EQ(perspective.farDistance, 100.0);
  EXPECT_EQ(withFar.viewFromWorld, glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, -5)));

  const Camera& infinite = contents.cameras[1];
  EXPECT_EQ(infinite.name, "camera1");                 // the node has no name
  EXPECT_EQ(infinite.viewport, (Viewport{360, 240}));  // aspectRatio 1.5
  const auto& infinitePerspective = std::get<PerspectiveProjection>(infinite.projection);
  EXPECT_DOUBLE_EQ(infinitePerspective.fovYDegrees, 180.0 / std::numbers::pi);
  EXPECT_EQ(infinitePerspective.aspect, 1.5);
  EXPECT_EQ(infinitePerspective.nearDistance, 0.5);
  EXPECT_FALSE(infinitePerspective.farDistance.has_value());
  EXPECT_EQ(infinite.viewFromWorld, glm::translate(glm::dmat4(1.0), glm::dvec3(0, -1, 0)));

  const Camera& ortho = contents.cameras[2];
  EXPECT_EQ(ortho.name, "ortho");
  const auto& box = std::get<OrthographicProjection>(ortho.projection);
  EXPECT_EQ(box.left, -3.0);
  EXPECT_EQ(box.right, 3.0);
  EXPECT_EQ(box.bottom, -2.0);
  EXPECT_EQ(box.top, 2.0);
  EXPECT_EQ(box.nearDistance, 0.0);
  EXPECT_EQ(box.farDistance, 16.0);
  EXPECT_EQ(ortho.viewFromWorld, glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, -8)));
}

TEST(MeshFileGltf, WorldFromFileGoesOnTopOfNodeTransforms) {
  const glm::dmat4 worldFromFile = glm::translate(glm::dmat4(1.0), glm::dvec3(100, 0, 0));
  const MeshFileContents contents = loadMeshFile(kMeshDataDir + "hierarchy.gltf", worldFromFile);
  EXPECT_EQ(contents.objects[1].worldPositions[0], glm::dvec3(110, 20, 30));
  EXPECT_EQ(contents.cameras[0].viewFromWorld,
            glm::translate(glm::dmat4(1.0), glm::dvec3(-100, 0, -5)));
}

TEST(MeshFileGltf, EmbeddedBufferWithoutScenesLoadsEveryRootNode) {
  const MeshFileContents external = loadMeshFile(kMeshDataDir + "hierarchy.gltf");
  const MeshFileContents embedded = loadMeshFile(kMeshDataDir + "embedded.gltf");
  ASSERT_EQ(embedded.objects.size(), external.objects.size());
  for (std::size_t i = 0; i < external.objects.size(); ++i) {
    EXPECT_EQ(embedded.objects[i].name, external.objects[i].name);
    EXPECT_EQ(embedded.objects[i].worldPositions, external.objects[i].worldPositions);
    EXPECT_EQ(embedded.objects[i].triangles, external.objects[i].triangles);
  }
  EXPECT_EQ(embedded.cameras.size(), 3u);
}

TEST(MeshFileGltf, GlbWithStrideKeepsAndReportsDegenerateTriangles) {
  const std::string path = kMeshDataDir + "strided.glb";
  const MeshFileContents contents = loadMeshFile(path);
  ASSERT_EQ(contents.objects.size(), 1u);
  EXPECT_EQ(contents.objects[0].name, "Strided/0");
  EXPECT_THAT(positionsOf(contents.objects[0]),
              ElementsAre(glm::dvec3(0, 0, -2), glm::dvec3(4, 0, -2), glm::dvec3(0, 4, -2),
                          glm::dvec3(4, 4, -2)));
  EXPECT_THAT(contents.objects[0].triangles,
              ElementsAre(glm::u32vec3(0, 1, 2), glm::u32vec3(1, 1, 3)));
  EXPECT_THAT(contents.warnings,
              ElementsAre(path + ": mesh \"Strided\" primitive 0: 1 degenerate triangle kept "
                                 "(first: triangle 1)"));
  EXPECT_TRUE(contents.cameras.empty());
}

TEST(MeshFileGltf, ExtensionIsCaseInsensitiveAndNamesAreUnique) {
  json document = triangleGltf();
  document["nodes"] = {{{"mesh", 0}}, {{"mesh", 0}, {"translation", {0, 0, 1}}}};
  document["scenes"][0]["nodes"] = {0, 1};
  const MeshFileContents contents = parseMeshFile(document.dump(), "twice.GLTF");
  ASSERT_EQ(contents.objects.size(), 2u);
  EXPECT_EQ(contents.objects[0].name, "Tri/0");
  EXPECT_EQ(contents.objects[1].name, "Tri/0#2");
  EXPECT_EQ(contents.objects[1].worldPositions[1], glm::dvec3(1, 0, 1));
}

// ---- Bad files: glTF -------------------------------------------------------------------------

TEST(MeshFileErrors, GltfMalformedJsonAndGlbHeader) {
  EXPECT_THAT(errorOf("{\"asset\": ", "bad.gltf"),
              StartsWith("bad.gltf: gltf: tinygltf rejected the file: "));
  auto glbHeader = [](std::uint32_t version, std::uint32_t length) {
    std::string header = "glTF";
    const std::uint32_t fields[2] = {version, length};
    header.append(reinterpret_cast<const char*>(fields), sizeof fields);
    return header;
  };
  const std::string jsonChunk = std::string("\x04\0\0\0JSON{}  ", 12);
  EXPECT_EQ(errorOf(glbHeader(1, 24) + jsonChunk, "bad.glb"),
            "bad.glb: glb header: version 1: glTF 1.0 is not supported; clipray reads glTF 2.0 "
            "(convert the file, e.g. with Blender or gltf-pipeline)");
  EXPECT_EQ(errorOf(glbHeader(3, 24) + jsonChunk, "bad.glb"),
            "bad.glb: glb header: version must be 2, got 3");
  EXPECT_EQ(errorOf(glbHeader(2, 99) + jsonChunk, "bad.glb"),
            "bad.glb: glb header: length 99 differs from the file size 24");
  EXPECT_EQ(errorOf(glbHeader(2, 24) + std::string("\x05\0\0\0JSON{}  ", 12), "bad.glb"),
            "bad.glb: glb chunk 0: length 5 exceeds the 4 bytes left");
  EXPECT_EQ(errorOf("not a glb at all", "bad.glb"),
            "bad.glb: glb header: a GLB needs at least 20 bytes (header and JSON chunk header), "
            "got 16");
  EXPECT_THAT(errorOf(glbHeader(2, 24) + jsonChunk, "bad.glb"),
              StartsWith("bad.glb: glb: tinygltf rejected the file: "));
}

TEST(MeshFileErrors, GltfMissingExternalBuffer) {
  json document = triangleGltf();
  document["buffers"][0]["uri"] = "missing.bin";
  const std::string message = errorOf(document.dump(), kMeshDataDir + "missing.gltf");
  EXPECT_THAT(message,
              StartsWith(kMeshDataDir + "missing.gltf: gltf: tinygltf rejected the file: "));
  EXPECT_THAT(message, HasSubstr("missing.bin"));
}

TEST(MeshFileErrors, GltfBufferShorterThanItsByteLength) {
  json document = triangleGltf();
  document["buffers"][0]["byteLength"] = 400;
  EXPECT_THAT(errorOf(document.dump(), "short.gltf"),
              StartsWith("short.gltf: gltf: tinygltf rejected the file: "));
}

TEST(MeshFileErrors, GltfEmptyBufferIsRejectedBeforeTinygltfCopiesIt) {
  // tinygltf 2.7.0 throws std::out_of_range on a GLB buffer of byteLength 0 (found by fuzz_glb).
  json document = triangleGltf();
  document["buffers"][0]["byteLength"] = 0;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: buffers[0].byteLength: expected an integer of at least 1, got 0");
  std::string jsonChunk = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":0}]})";
  jsonChunk.append(-jsonChunk.size() % 4, ' ');
  std::string glb = "glTF";
  const std::uint32_t header[4] = {2, static_cast<std::uint32_t>(20 + jsonChunk.size() + 12),
                                   static_cast<std::uint32_t>(jsonChunk.size()), 0x4E4F534A};
  glb.append(reinterpret_cast<const char*>(header), sizeof header);
  glb += jsonChunk;
  glb += std::string("\4\0\0\0BIN\0\0\0\0\0", 12);
  EXPECT_EQ(errorOf(glb, "m.glb"),
            "m.glb: buffers[0].byteLength: expected an integer of at least 1, got 0");
}

TEST(MeshFileErrors, GltfNegativeOrFractionalSizesAreRefusedNotReadAsZero) {
  json document = triangleGltf();
  document["bufferViews"][1]["byteOffset"] = -4;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: bufferViews[1].byteOffset: expected a non-negative integer, got -4");
  document = triangleGltf();
  document["accessors"][0]["count"] = 2.5;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: accessors[0].count: expected a non-negative integer, got 2.5");
  document = triangleGltf();
  document["accessors"][1]["byteOffset"] = -2;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: accessors[1].byteOffset: expected a non-negative integer, got -2");
}

TEST(MeshFileErrors, GltfBufferViewBeyondItsBuffer) {
  json document = triangleGltf();
  document["bufferViews"][1]["byteLength"] = 60;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: bufferViews[1]: byteOffset 36 + byteLength 60 exceeds buffers[0] length 42");
}

TEST(MeshFileErrors, GltfAccessorBeyondItsBufferView) {
  json document = triangleGltf();
  document["accessors"][0]["count"] = 4;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: accessors[0] (POSITION of meshes[0].primitives[0]): count 4 x stride 12 + "
            "offset 0 exceeds bufferViews[0] length 36");
  document = triangleGltf();
  document["accessors"][1]["byteOffset"] = 2;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: accessors[1] (indices of meshes[0].primitives[0]): count 3 x stride 2 + "
            "offset 2 exceeds bufferViews[1] length 6");
}

TEST(MeshFileErrors, GltfWrongAccessorTypes) {
  json document = triangleGltf();
  document["accessors"][0]["componentType"] = 5123;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: accessors[0] (POSITION of meshes[0].primitives[0]): expected componentType "
            "5126 (FLOAT), got 5123 (UNSIGNED_SHORT); integer positions need "
            "KHR_mesh_quantization in extensionsUsed");
  document["extensionsUsed"] = {"KHR_mesh_quantization"};
  document["accessors"][0]["componentType"] = 5125;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: accessors[0] (POSITION of meshes[0].primitives[0]): expected componentType "
            "5126 (FLOAT) or an 8- or 16-bit integer type (KHR_mesh_quantization), got 5125 "
            "(UNSIGNED_INT)");
  document = triangleGltf();
  document["accessors"][1]["normalized"] = true;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: accessors[1] (indices of meshes[0].primitives[0]): normalized accessors are "
            "not supported here");
  document = triangleGltf();
  document["accessors"][1]["componentType"] = 5122;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: accessors[1] (indices of meshes[0].primitives[0]): expected componentType "
            "5121 (UNSIGNED_BYTE) or 5123 (UNSIGNED_SHORT) or 5125 (UNSIGNED_INT), got 5122 "
            "(SHORT)");
  document = triangleGltf();
  document["meshes"][0]["primitives"][0]["indices"] = 7;
  // tinygltf checks this index itself.
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: gltf: tinygltf rejected the file: primitive indices accessor out of bounds");
}

TEST(MeshFileErrors, GltfPositionAccessorOutOfRange) {
  json document = triangleGltf();
  document["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 7;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: POSITION of meshes[0].primitives[0]: accessor index 7 out of range for 2 "
            "accessors");
}

TEST(MeshFileErrors, GltfIndexOutOfRange) {
  EXPECT_EQ(errorOf(triangleGltf({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 3}).dump(), "m.gltf"),
            "m.gltf: meshes[0].primitives[0].indices: index 2 is 3, out of range for 3 vertices");
}

TEST(MeshFileErrors, GltfNonFinitePosition) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(errorOf(triangleGltf({0, 0, 0, 1, nan, 0, 0, 1, 0}).dump(), "m.gltf"),
            "m.gltf: accessors[0] (POSITION of meshes[0].primitives[0]): vertex 1 is not finite, "
            "got (1, nan, 0)");
  EXPECT_EQ(errorOf(triangleGltf({0, 0, 0, 1, 0, 0, 0, 1, -inf}).dump(), "m.gltf"),
            "m.gltf: accessors[0] (POSITION of meshes[0].primitives[0]): vertex 2 is not finite, "
            "got (0, 1, -inf)");
}

TEST(MeshFileErrors, GltfUnsupportedMode) {
  json document = triangleGltf();
  document["meshes"][0]["primitives"][0]["mode"] = 1;
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: meshes[0].primitives[0].mode: mode 1 (LINES) is not supported; only "
            "TRIANGLES (4), TRIANGLE_STRIP (5) and TRIANGLE_FAN (6): clipray compares surfaces, "
            "and points and lines have none");
}

TEST(MeshFileErrors, GltfFeaturesClipryDoesNotReadAreNamed) {
  const std::string kConvert =
      "glTF 1.0 is not supported; clipray reads glTF 2.0 (convert the file, e.g. with Blender or "
      "gltf-pipeline)";
  json old = triangleGltf();
  old["asset"]["version"] = "1.0";
  EXPECT_EQ(errorOf(old.dump(), "m.gltf"), "m.gltf: asset.version: " + kConvert);
  // glTF 1.0 without "asset", its meshes a dictionary; and with the version as a number (as
  // collada2gltf wrote it: CesiumMilkTruck in assimp's models).
  EXPECT_EQ(errorOf(R"({"meshes": {"truck": {"primitives": []}}})", "m.gltf"),
            "m.gltf: asset.version: " + kConvert);
  old["asset"]["version"] = 1;
  EXPECT_EQ(errorOf(old.dump(), "m.gltf"), "m.gltf: asset.version: " + kConvert);
  json draco = triangleGltf();
  draco["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  draco["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  EXPECT_EQ(errorOf(draco.dump(), "m.gltf"),
            "m.gltf: extensionsRequired: compressed geometry (KHR_draco_mesh_compression) is not "
            "supported; decompress it first (e.g. gltf-transform or gltfpack)");
  json objectPrimitives = triangleGltf();
  objectPrimitives["meshes"][0]["primitives"] = {{"attributes", {{"POSITION", 0}}}};
  EXPECT_EQ(errorOf(objectPrimitives.dump(), "m.gltf"),
            "m.gltf: meshes[0].primitives: expected an array of primitives, got "
            "{\"attributes\":{\"POSITION\":0}}");
}

// A triangle whose positions are 16-bit integers (KHR_mesh_quantization): `components` holds
// the nine raw values as bytes of `componentType`.
json quantizedTriangleGltf(const std::string& components, int componentType, bool normalized) {
  json document = triangleGltf();
  const std::string indices = bytesOf(std::vector<std::uint16_t>{0, 1, 2});
  const std::size_t vertexBytes = components.size() / 3;
  // Each vertex padded to 4 bytes, as the extension requires of byteStride.
  const std::size_t stride = (vertexBytes + 3) / 4 * 4;
  std::string positions;
  for (int v = 0; v < 3; ++v) {
    positions += components.substr(v * vertexBytes, vertexBytes);
    positions += std::string(stride - vertexBytes, '\0');
  }
  const std::string buffer = positions + indices;
  document["buffers"][0] = {{"uri", "data:application/octet-stream;base64," + base64(buffer)},
                            {"byteLength", buffer.size()}};
  document["bufferViews"][0] = {
      {"buffer", 0}, {"byteOffset", 0}, {"byteLength", positions.size()}, {"byteStride", stride}};
  document["bufferViews"][1] = {
      {"buffer", 0}, {"byteOffset", positions.size()}, {"byteLength", indices.size()}};
  document["accessors"][0]["componentType"] = componentType;
  document["accessors"][0]["normalized"] = normalized;
  document["extensionsUsed"] = {"KHR_mesh_quantization"};
  document["extensionsRequired"] = {"KHR_mesh_quantization"};
  return document;
}

TEST(MeshFileGltf, QuantizedPositionsAreDecodedAsGlDecodesThem) {
  const std::string shorts =
      bytesOf(std::vector<std::int16_t>{0, 0, 0, 32767, -32768, -16384, 100, 200, -300});
  const MeshFileContents normalized =
      parseMeshFile(quantizedTriangleGltf(shorts, 5122, true).dump(), "q.gltf");
  ASSERT_EQ(normalized.objects.size(), 1u);
  // max(c / 32767, -1): -32768 clamps to -1.
  EXPECT_THAT(positionsOf(normalized.objects[0]),
              ElementsAre(glm::dvec3(0, 0, 0), glm::dvec3(1, -1, -16384 / 32767.0),
                          glm::dvec3(100 / 32767.0, 200 / 32767.0, -300 / 32767.0)));
  EXPECT_TRUE(normalized.warnings.empty());
  const MeshFileContents integers =
      parseMeshFile(quantizedTriangleGltf(shorts, 5122, false).dump(), "q.gltf");
  EXPECT_THAT(positionsOf(integers.objects[0]),
              ElementsAre(glm::dvec3(0, 0, 0), glm::dvec3(32767, -32768, -16384),
                          glm::dvec3(100, 200, -300)));
  const std::string unsignedShorts =
      bytesOf(std::vector<std::uint16_t>{0, 0, 0, 65535, 1, 0, 0, 65535, 32768});
  EXPECT_THAT(
      positionsOf(parseMeshFile(quantizedTriangleGltf(unsignedShorts, 5123, true).dump(), "q.gltf")
                      .objects[0]),
      ElementsAre(glm::dvec3(0, 0, 0), glm::dvec3(1, 1 / 65535.0, 0),
                  glm::dvec3(0, 1, 32768 / 65535.0)));
  const std::string bytes = bytesOf(std::vector<std::int8_t>{0, 0, 0, 127, -128, 1, -1, 64, 0});
  EXPECT_THAT(
      positionsOf(
          parseMeshFile(quantizedTriangleGltf(bytes, 5120, true).dump(), "q.gltf").objects[0]),
      ElementsAre(glm::dvec3(0, 0, 0), glm::dvec3(1, -1, 1 / 127.0),
                  glm::dvec3(-1 / 127.0, 64 / 127.0, 0)));
  const std::string unsignedBytes = bytesOf(std::vector<std::uint8_t>{0, 0, 0, 255, 1, 0, 0, 2, 3});
  EXPECT_THAT(
      positionsOf(parseMeshFile(quantizedTriangleGltf(unsignedBytes, 5121, false).dump(), "q.gltf")
                      .objects[0]),
      ElementsAre(glm::dvec3(0, 0, 0), glm::dvec3(255, 1, 0), glm::dvec3(0, 2, 3)));
}

TEST(MeshFileGltf, ExtensionsThatMoveNoGeometryAreIgnoredWithAWarningOthersAreNamed) {
  json shaded = triangleGltf();
  shaded["extensionsUsed"] = {"KHR_materials_clearcoat", "KHR_texture_transform",
                              "EXT_mesh_gpu_instancing"};
  shaded["extensionsRequired"] = {"KHR_texture_transform"};
  const MeshFileContents contents = parseMeshFile(shaded.dump(), "m.gltf");
  ASSERT_EQ(contents.objects.size(), 1u);
  EXPECT_EQ(contents.warnings,
            std::vector<std::string>{
                "m.gltf: the extensions KHR_materials_clearcoat, KHR_texture_transform, "
                "EXT_mesh_gpu_instancing ignored: clipray compares the static geometry in its "
                "bind pose"});
  json instanced = triangleGltf();
  instanced["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  instanced["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  EXPECT_EQ(errorOf(instanced.dump(), "m.gltf"),
            "m.gltf: extensionsRequired: \"EXT_mesh_gpu_instancing\" is not supported: it may "
            "change what is drawn where (clipray reads KHR_mesh_quantization and ignores "
            "material, texture and light extensions)");
}

TEST(MeshFileGltf, TexturesSkinsMorphsAndAnimationsAreIgnoredWithOneWarning) {
  EXPECT_TRUE(parseMeshFile(triangleGltf().dump(), "m.gltf").warnings.empty());
  json document = triangleGltf();
  document["images"] = json::array({{{"uri", "missing.png"}}});
  document["textures"] = json::array({{{"source", 0}}, {{"source", 0}}});
  document["meshes"][0]["primitives"][0]["targets"] = json::array({{{"POSITION", 0}}});
  const MeshFileContents contents = parseMeshFile(document.dump(), "m.gltf");
  ASSERT_EQ(contents.objects.size(), 1u);
  EXPECT_EQ(
      contents.warnings,
      std::vector<std::string>{"m.gltf: 2 textures and 1 primitives with morph targets "
                               "ignored: clipray compares the static geometry in its bind pose"});
}

TEST(MeshFileGltf, StripsAndFansAreTriangulatedAsTheSpecSays) {
  // Five vertices, indexed 0..4 (and, the third time, 4, 3, 2, 1).
  const std::vector<float> five = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0};
  json strip = triangleGltf(five, {0, 1, 2, 3, 4});
  strip["meshes"][0]["primitives"][0]["mode"] = 5;
  EXPECT_THAT(parseMeshFile(strip.dump(), "m.gltf").objects[0].triangles,
              ElementsAre(glm::u32vec3(0, 1, 2), glm::u32vec3(1, 3, 2), glm::u32vec3(2, 3, 4)));
  json fan = triangleGltf(five, {0, 1, 2, 3, 4});
  fan["meshes"][0]["primitives"][0]["mode"] = 6;
  EXPECT_THAT(parseMeshFile(fan.dump(), "m.gltf").objects[0].triangles,
              ElementsAre(glm::u32vec3(1, 2, 0), glm::u32vec3(2, 3, 0), glm::u32vec3(3, 4, 0)));
  json indexedFan = triangleGltf(five, {4, 3, 2, 1});
  indexedFan["meshes"][0]["primitives"][0]["mode"] = 6;
  EXPECT_THAT(parseMeshFile(indexedFan.dump(), "m.gltf").objects[0].triangles,
              ElementsAre(glm::u32vec3(3, 2, 4), glm::u32vec3(2, 1, 4)));
  json tooShort = triangleGltf(five, {0, 1});
  tooShort["meshes"][0]["primitives"][0]["mode"] = 5;
  EXPECT_EQ(errorOf(tooShort.dump(), "m.gltf"),
            "m.gltf: meshes[0].primitives[0].indices: TRIANGLE_STRIP needs at least 3 vertices, "
            "got 2");
}

TEST(MeshFileErrors, GltfNonInvertibleNodeTransforms) {
  json document = triangleGltf();
  document["nodes"][0]["scale"] = {1, 0, 1};
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: nodes[0].scale: a zero scale factor makes the transform non-invertible, got "
            "(1, 0, 1)");
  document = triangleGltf();
  document["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 0, 1};
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: nodes[0].matrix: the transform is not invertible (its 3x3 part has "
            "determinant 0)");
}

TEST(MeshFileErrors, GltfNodeCycleIsRejected) {
  json document = triangleGltf();
  document["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}};
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: nodes[0]: the node is reached twice (a cycle, or a child of two parents, or "
            "listed twice)");
}

TEST(MeshFileErrors, GltfCameraChecks) {
  json document = triangleGltf();
  document["nodes"][0]["camera"] = 0;
  document["cameras"] = {
      {{"type", "perspective"}, {"perspective", {{"yfov", 1}, {"znear", 2}, {"zfar", 1}}}}};
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: cameras[0].perspective.zfar: expected a number greater than znear (2), got 1");
}

TEST(MeshFileErrors, FileWithoutTriangles) {
  json document = triangleGltf();
  document["nodes"][0].erase("mesh");
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: scene: no node places any of the file's 1 meshes: nothing to draw");
  document.erase("scenes");
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"),
            "m.gltf: nodes: no node places any of the file's 1 meshes: nothing to draw");
  // assimp's TestNoRootNode/NoScene.gltf: a scene index, and nothing else.
  EXPECT_EQ(errorOf(R"({"asset": {"version": "2.0"}, "scene": 0})", "m.gltf"),
            "m.gltf: meshes: the file has no meshes: nothing to draw");
  document = triangleGltf();
  document["meshes"][0]["primitives"] = json::array();
  EXPECT_EQ(errorOf(document.dump(), "m.gltf"), "m.gltf: the file holds no triangles");
}

}  // namespace
}  // namespace clipray
