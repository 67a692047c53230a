#pragma once
// Internal to scene/: the reader of a scene file's JSON document, one member per part of the
// format (cameras, object placement, one reader per object "type"), each appending to the Scene.
// Matrices produced: viewFromWorld and worldFromObject column-major, p' = M * p.

#include <cstdint>
#include <map>
#include <string>
#include <variant>

#include <glm/glm.hpp>

#include "clipray/scene/Scene.hpp"
#include "clipray/scene/SceneValidation.hpp"

namespace clipray::detail {

class SceneReader : public SceneValidator {
 public:
  using SceneValidator::SceneValidator;

  // The whole document: version, comment, conventions, cameras, objects (SceneLoader.cpp).
  Scene read(const json& root);

  // Object readers, one per "type"; each appends to the scene. worldFromObject is the object's
  // placement ("transform" or "worldFromObject").
  // Meshes (SceneMeshObjects.cpp):
  void readMesh(const json& object, const Pointer& at, const glm::dmat4& worldFromObject,
                std::string name, Scene& scene) const;
  void readMeshFile(const json& object, const Pointer& at, const glm::dmat4& worldFromObject,
                    std::string name, Scene& scene) const;
  void readTerrain(const json& object, const Pointer& at, const glm::dmat4& worldFromObject,
                   std::string name, Scene& scene) const;
  // Analytic primitives (ScenePrimitiveObjects.cpp):
  void readSphere(const json& object, const Pointer& at, const glm::dmat4& worldFromObject,
                  std::string name, Scene& scene) const;
  void readDisk(const json& object, const Pointer& at, const glm::dmat4& worldFromObject,
                std::string name, Scene& scene) const;
  void readQuad(const json& object, const Pointer& at, const glm::dmat4& worldFromObject,
                std::string name, Scene& scene) const;
  void readBox(const json& object, const Pointer& at, const glm::dmat4& worldFromObject,
               std::string name, Scene& scene) const;
  void readPlane(const json& object, const Pointer& at, const glm::dmat4& worldFromObject,
                 std::string name, Scene& scene) const;

 private:
  // Cameras (SceneCameras.cpp).
  Camera camera(const json& value, const Pointer& at, std::map<std::string, Pointer>& names) const;
  glm::dmat4 lookAt(const json& value, const Pointer& at) const;
  std::vector<glm::dvec4> clipPlanes(const json& value, const Pointer& at) const;
  std::vector<std::string> expectedFindings(const json& value, const Pointer& at) const;
  // A camera's "logarithmicDepth": {"form": "threejs" | "outerra", "far", "constant"} (far and,
  // for outerra only, constant required, each positive and finite).
  LogarithmicDepth logarithmicDepth(const json& value, const Pointer& at) const;
  // Fails at `at` (the camera's "logarithmicDepth") for what the scene has beside it that the
  // model of a shader-written depth leaves out (SceneLoader.cpp).
  void refuseUnmodelledLogDepth(const Scene& scene, const Camera& camera, const Pointer& at) const;
  std::variant<PerspectiveProjection, OrthographicProjection, std::monostate> projection(
      const json& value, const Pointer& at) const;
  // One object: its type's reader with its placement (SceneLoader.cpp).
  void object(const json& value, const Pointer& at, std::map<std::string, Pointer>& names,
              Scene& scene) const;
  glm::dmat4 placement(const json& object, const Pointer& at) const;
  // A triangle object's "cull" and "frontFace" (default none, ccw).
  struct FaceCulling {
    CullFace cull = CullFace::None;
    FrontFace frontFace = FrontFace::Ccw;
  };
  FaceCulling faceCulling(const json& object, const Pointer& at) const;
  // An object's "polygonOffset": {"factor", "units", "clamp"}, each finite, each default 0 (a
  // negative clamp bounds a negative offset: GL 4.6 14.6.5).
  PolygonOffset polygonOffset(const json& value, const Pointer& at) const;
  glm::dmat4 transform(const json& value, const Pointer& at) const;  // world = T * R * S * p
  // A unit direction from a non-zero vector3.
  glm::dvec3 direction(const json& value, const Pointer& at) const;
  void addPrimitive(PrimitiveKind kind, const glm::dmat4& worldFromLocal, const Pointer& at,
                    std::string name, Scene& scene) const;

  mutable std::uint64_t terrainTriangles_ = 0;  // generated so far (see readTerrain)
};

}  // namespace clipray::detail
