#pragma once
// What a scene models: cameras and geometry, nothing else (no materials, no lights).
// The JSON format (version 1) is documented in README.md, section "Scene format".

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/math/Conventions.hpp"

namespace clipray {

struct PerspectiveProjection {
  double fovYDegrees = 60.0;
  std::optional<double> aspect;  // nullopt: viewport width / height
  double nearDistance = 0.1;
  std::optional<double> farDistance;  // nullopt: infinite far plane
};

struct OrthographicProjection {
  double left = -1, right = 1, bottom = -1, top = 1;
  double nearDistance = 0.1;
  double farDistance = 100.0;
};

struct Camera {
  std::string name;
  Viewport viewport;
  // Either a parametric projection with a view, or a raw clipFromWorld matrix.
  std::variant<PerspectiveProjection, OrthographicProjection, std::monostate> projection;
  glm::dmat4 viewFromWorld{1.0};
  std::optional<glm::dmat4> rawClipFromWorld;
  // The convention a parametric projection is built for; nullopt: built for whatever convention
  // the frame is drawn under (the app does the right thing). Set it to draw a matrix built for
  // one convention under another (e.g. built for "no", drawn under "zo").
  std::optional<DepthMode> builtFor;

  // The matrix the app would hand GL when drawing under `drawnUnder` at `viewport`.
  glm::dmat4 clipFromWorld(DepthMode drawnUnder, Viewport viewport) const;
};

// A triangle mesh with its object transform already applied (in double) at load time.
struct MeshObject {
  std::string name;
  std::vector<glm::dvec3> worldPositions;
  std::vector<glm::u32vec3> triangles;  // indices into worldPositions
};

struct Scene {
  std::string path;     // as given by the user; used in messages
  std::string name;     // file stem, used in reports
  std::string comment;  // what the scene tests
  int version = 1;
  std::vector<Camera> cameras;
  std::vector<MeshObject> objects;
  // Conventions this scene is reconciled under when the command line does not name any.
  std::vector<DepthMode> conventions;

  std::size_t triangleCount() const;
};

// Primitive ids: 0 is background; object k's triangle t has id firstPrimitiveId(k) + t.
// The raster pass writes these to the R32UI attachment; the analytic pass returns the same.
struct PrimitiveIdTable {
  std::vector<std::uint32_t> firstIdOfObject;  // one per object, starting at 1
  explicit PrimitiveIdTable(const Scene& scene);
  struct Decoded {
    int object = -1;  // -1: background
    std::uint32_t triangle = 0;
  };
  Decoded decode(std::uint32_t id) const;
};

// Loads and validates a scene file; throws InputError naming file, JSON pointer and value.
Scene loadScene(const std::string& path);
// Same, from text already in memory (the path is used in messages and to resolve relative paths).
Scene parseScene(const std::string& jsonText, const std::string& path);

}  // namespace clipray
