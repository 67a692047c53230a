#pragma once
// Triangle meshes from glTF 2.0 (.gltf, .glb), Wavefront OBJ (.obj) and PLY (.ply) files, validated
// as strictly as scene files: every problem is an InputError that names the file, the element and
// the offending value. No GL here; the result feeds the same MeshObject/Camera types as scenes.
// worldFromFile: column-major, p_world = worldFromFile * p_file.

#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/scene/Scene.hpp"

namespace clipray {

struct MeshFileContents {
  // One object per glTF primitive instance (named "<mesh>/<primitive>"), one per OBJ shape, one
  // per PLY file. Positions are in world space: file transforms and worldFromFile are applied in
  // double.
  std::vector<MeshObject> objects;
  // glTF cameras placed by the nodes of the loaded scene (empty for OBJ and PLY).
  std::vector<Camera> cameras;
  // Things kept but worth knowing, e.g.
  // "model.glb: mesh \"Cube\" primitive 0: 2 degenerate triangles kept (first: triangle 17)".
  std::vector<std::string> warnings;
};

// Loads .gltf, .glb, .obj or .ply, chosen by the extension (case-insensitive). worldFromFile is
// applied on top of the file's own transforms. Throws InputError
// ("<path>: <element>: <what is wrong>, got <value>").
MeshFileContents loadMeshFile(const std::string& path,
                              const glm::dmat4& worldFromFile = glm::dmat4(1.0));

// The same from bytes already in memory (the fuzzers use it): `path` names the file in messages,
// its extension picks the format, and external glTF buffers are resolved relative to its folder.
MeshFileContents parseMeshFile(std::string_view bytes, const std::string& path,
                               const glm::dmat4& worldFromFile = glm::dmat4(1.0));

}  // namespace clipray
