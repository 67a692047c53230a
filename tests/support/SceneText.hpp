#pragma once
// Scene text for the scene loader's tests: a valid camera and object, scenes with one of them
// swapped, and the message parseScene throws.

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "clipray/InputError.hpp"
#include "clipray/scene/Scene.hpp"

namespace clipray::testing {

inline constexpr const char* kFile = "scenes/a.json";

// A camera and an object that are valid on their own; tests swap one of them for a bad one.
inline constexpr const char* kCamera = R"({
  "name": "main", "viewport": [640, 480],
  "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]},
  "projection": {"type": "perspective", "fovYDegrees": 60, "near": 0.1, "far": 100}
})";
inline constexpr const char* kObject = R"({
  "name": "tri", "type": "mesh", "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2]
})";

inline std::string sceneWith(const std::string& camera, const std::string& object) {
  return R"({"version": 1, "cameras": [)" + camera + R"(], "objects": [)" + object + "]}";
}
inline std::string withCamera(const std::string& camera) {
  return sceneWith(camera, kObject);
}
inline std::string withObject(const std::string& object) {
  return sceneWith(kCamera, object);
}
// A camera with the look-at view of kCamera and the given projection.
inline std::string withProjection(const std::string& projection) {
  return withCamera(R"({"name": "main", "viewport": [640, 480],
    "view": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0]}, "projection": )" +
                    projection + "}");
}
// A camera with a raw clipFromWorld.
inline std::string withClipFromWorld(const std::string& matrix) {
  return withCamera(R"({"name": "main", "viewport": [640, 480], "clipFromWorld": )" + matrix + "}");
}
// A camera with the projection of kCamera and the given view fields.
inline std::string withView(const std::string& viewFields) {
  return withCamera(R"({"name": "main", "viewport": [640, 480], )" + viewFields +
                    R"(, "projection": {"type": "perspective", "fovYDegrees": 60, "near": 0.1}})");
}
// A triangle with the given extra fields (a transform).
inline std::string withPlacement(const std::string& fields) {
  return withObject(R"({"name": "tri", "type": "mesh", "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0],
    "indices": [0, 1, 2], )" +
                    fields + "}");
}

// The message parseScene throws for `text`, or "no error".
inline std::string errorOf(const std::string& text) {
  try {
    parseScene(text, kFile);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

inline void expectSameMatrix(const glm::dmat4& actual, const glm::dmat4& expected) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      EXPECT_EQ(actual[c][r], expected[c][r]) << "column " << c << ", row " << r;
    }
  }
}

}  // namespace clipray::testing
