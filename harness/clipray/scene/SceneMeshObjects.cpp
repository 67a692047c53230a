// The mesh objects of a scene file: an inline mesh, a glTF/OBJ/PLY file (and its cameras), and the
// generated terrain.

#include <cmath>
#include <filesystem>
#include <optional>
#include <utility>

#include "clipray/InputError.hpp"
#include "clipray/scene/MeshFiles.hpp"
#include "clipray/scene/SceneReader.hpp"
#include "clipray/scene/Terrain.hpp"

namespace clipray::detail {

namespace {

// The largest terrain the format builds (32-bit ids leave room; this keeps memory sane).
constexpr std::uint64_t kMaxTerrainTriangles = 20'000'000;

}  // namespace

void SceneReader::readMesh(const json& value, const Pointer& at, const glm::dmat4& worldFromObject,
                           std::string meshName, Scene& scene) const {
  MeshObject mesh;
  mesh.name = std::move(meshName);

  const Pointer pAt = at / "positions";
  const json& positions = required(value, at, "positions");
  if (!positions.is_array() || positions.size() % 3 != 0 || positions.size() < 9) {
    fail(pAt, "expected a flat array of x, y, z coordinates of at least 3 vertices, got " +
                  describe(positions));
  }
  const std::size_t vertexCount = positions.size() / 3;
  mesh.worldPositions.reserve(vertexCount);
  for (std::size_t v = 0; v < vertexCount; ++v) {
    const glm::dvec3 p(number(positions[3 * v], pAt / (3 * v)),
                       number(positions[3 * v + 1], pAt / (3 * v + 1)),
                       number(positions[3 * v + 2], pAt / (3 * v + 2)));
    const glm::dvec3 world(worldFromObject * glm::dvec4(p, 1.0));
    if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z)) {
      fail(pAt / (3 * v), "vertex " + std::to_string(v) +
                              " has a world position that overflows double after the transform");
    }
    mesh.worldPositions.push_back(world);
  }

  const Pointer iAt = at / "indices";
  const json& indices = required(value, at, "indices");
  if (!indices.is_array() || indices.empty() || indices.size() % 3 != 0) {
    fail(iAt, "expected a flat array of vertex indices, 3 per triangle, at least 1 triangle, got " +
                  describe(indices));
  }
  mesh.triangles.reserve(indices.size() / 3);
  for (std::size_t t = 0; t < indices.size() / 3; ++t) {
    glm::u32vec3 triangle;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t i = 3 * t + k;
      const std::optional<std::uint64_t> index = unsignedInteger(indices[i]);
      if (!index) fail(iAt / i, "expected an unsigned integer, got " + describe(indices[i]));
      if (*index >= vertexCount) {
        fail(iAt / i, "index " + std::to_string(*index) + " out of range for " +
                          std::to_string(vertexCount) + " vertices");
      }
      triangle[static_cast<int>(k)] = static_cast<std::uint32_t>(*index);
    }
    mesh.triangles.push_back(triangle);
  }
  scene.objects.push_back(std::move(mesh));
}

// A glTF/OBJ/PLY file, by a path relative to the scene file. Its objects are named
// "<name>/<object>"; with "useCameras": true its cameras join the scene as "<name>/<camera>".
void SceneReader::readMeshFile(const json& value, const Pointer& at,
                               const glm::dmat4& worldFromObject, std::string fileName,
                               Scene& scene) const {
  const json& pathValue = required(value, at, "path");
  const std::string relative = string(pathValue, at / "path");
  if (relative.empty()) fail(at / "path", "expected a non-empty path, got \"\"");
  const std::filesystem::path resolved =
      std::filesystem::path(file_).parent_path() / std::filesystem::path(relative);
  std::error_code error;
  if (!std::filesystem::is_regular_file(resolved, error)) {
    fail(at / "path", "cannot open mesh file " + describe(pathValue) + " (looked for " +
                          jsonString(resolved.string()) + ")");
  }
  bool useCameras = false;
  if (const json* cameras = optional(value, "useCameras")) {
    if (!cameras->is_boolean()) {
      fail(at / "useCameras", "expected true or false, got " + describe(*cameras));
    }
    useCameras = cameras->get<bool>();
  }
  MeshFileContents contents;
  try {
    contents = loadMeshFile(resolved.string(), worldFromObject);
  } catch (const InputError& meshFileError) {
    fail(at / "path",
         meshFileError.what());  // which object of the scene, then the file's own message
  }
  for (MeshObject& object : contents.objects) {
    object.name = fileName + "/" + object.name;
    scene.objects.push_back(std::move(object));
  }
  if (useCameras) {
    if (contents.cameras.empty()) {
      fail(at / "useCameras", "the mesh file " + jsonString(relative) + " has no cameras");
    }
    // The file's cameras are placed in the file's frame: move them with the object.
    const glm::dmat4 objectFromWorld = glm::inverse(worldFromObject);
    for (Camera& camera : contents.cameras) {
      camera.name = fileName + "/" + camera.name;
      camera.viewFromWorld = camera.viewFromWorld * objectFromWorld;
      scene.cameras.push_back(std::move(camera));
    }
  }
  scene.warnings.insert(scene.warnings.end(), contents.warnings.begin(), contents.warnings.end());
}

void SceneReader::readTerrain(const json& value, const Pointer& at,
                              const glm::dmat4& worldFromObject, std::string terrainName,
                              Scene& scene) const {
  const json& count = required(value, at, "triangles");
  const std::optional<std::uint64_t> triangles = unsignedInteger(count);
  if (!triangles || *triangles < 2 || *triangles > kMaxTerrainTriangles) {
    fail(at / "triangles", "expected an integer in [2, " + std::to_string(kMaxTerrainTriangles) +
                               "], got " + describe(count));
  }
  std::uint64_t seed = 0;
  if (const json* seedValue = optional(value, "seed")) {
    const std::optional<std::uint64_t> n = unsignedInteger(*seedValue);
    if (!n) fail(at / "seed", "expected an unsigned integer, got " + describe(*seedValue));
    seed = *n;
  }
  // The generator rounds up to 2 n^2 triangles; bound what every terrain of the scene builds
  // before building it, so a small file cannot ask for gigabytes.
  const std::uint64_t cells =
      static_cast<std::uint64_t>(std::ceil(std::sqrt(static_cast<double>(*triangles) / 2.0)));
  terrainTriangles_ += 2 * cells * cells;
  if (terrainTriangles_ > kMaxTerrainTriangles + kMaxTerrainTriangles / 100) {
    fail(at / "triangles", "the scene's terrains would hold " + std::to_string(terrainTriangles_) +
                               " triangles; at most " + std::to_string(kMaxTerrainTriangles) +
                               " in all");
  }
  MeshObject mesh = makeTerrainMesh(*triangles, seed, std::move(terrainName));
  for (glm::dvec3& p : mesh.worldPositions) p = glm::dvec3(worldFromObject * glm::dvec4(p, 1.0));
  scene.objects.push_back(std::move(mesh));
}

}  // namespace clipray::detail
