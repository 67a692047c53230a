#pragma once
// For the mesh-file tests: the shipped test meshes' folder, the message a bad file gets, and a
// loaded object's positions.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/InputError.hpp"
#include "clipray/scene/MeshFiles.hpp"

namespace clipray::testing {

// The files under tests/data/meshes come from generate.py.
inline const std::string kMeshDataDir = std::string(CLIPRAY_SOURCE_DIR) + "/tests/data/meshes/";

// The message of the InputError that parsing throws; fails the test when nothing is thrown.
inline std::string errorOf(const std::string& bytes, const std::string& path) {
  try {
    parseMeshFile(bytes, path);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError for " << path;
  return {};
}

inline std::vector<glm::dvec3> positionsOf(const MeshObject& object) {
  return object.worldPositions;
}

}  // namespace clipray::testing
