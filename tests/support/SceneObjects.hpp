#pragma once
// Finding a scene's objects and their primitive ids in GL tests.

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "clipray/scene/Scene.hpp"

namespace clipray::testing {

// The index of the object with that name; a test failure (and 0) where there is none.
inline std::size_t objectIndex(const Scene& scene, const std::string& name) {
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    if (scene.objects[k].name == name) return k;
  }
  ADD_FAILURE() << "no object " << name;
  return 0;
}

// Whether the primitive id is one of the object's triangles (PrimitiveIdTable's numbering).
inline bool ofObject(const Scene& scene, std::size_t object, std::uint32_t id) {
  const PrimitiveIdTable ids(scene);
  const std::uint32_t first = ids.firstIdOfObject[object];
  return id >= first && id < first + scene.objects[object].triangles.size();
}

}  // namespace clipray::testing
