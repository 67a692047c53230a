#pragma once
// Scenes built in code from an app's own arrays, for its tests. A SceneBuilder writes the scene
// file the JSON format describes (docs/scene-format.md) and validates it with the same reader as
// `clipray reconcile scene.json`: every mistake throws InputError with the same message a file
// would get, naming the builder, the JSON pointer (objects and cameras in the order added) and the
// value. json() gives that file, so a failing test can be reproduced on the command line.
//
// Matrices are glm's column-major dmat4: worldFromObject places a mesh or primitive (affine,
// p_world = worldFromObject * p_object); a camera's clipFromWorld is what the app multiplies
// vertices by (p_clip = clipFromWorld * p_world), drawn as it is under every convention a run uses.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/InputError.hpp"

namespace clipray {

struct Scene;  // clipray's internal model (clipray/scene/Scene.hpp)

// A validated scene: from a SceneBuilder or a file. Cheap to copy (shared, immutable).
class TestScene {
 public:
  // A scene file (JSON), or a glTF / OBJ / PLY asset seen from its own or automatic cameras.
  // Throws InputError naming the file, the field and the value.
  static TestScene load(const std::string& path);

  const std::string& name() const;
  std::vector<std::string> cameraNames() const;
  std::vector<std::string> objectNames() const;  // meshes, then analytic primitives
  std::size_t triangleCount() const;
  // What the reader accepted but wants known (degenerate triangles, ...).
  const std::vector<std::string>& warnings() const;

  // clipray's own model of the scene (for code that includes clipray's internal headers).
  const Scene& model() const { return *scene_; }

 private:
  explicit TestScene(std::shared_ptr<const Scene> scene) : scene_(std::move(scene)) {}
  std::shared_ptr<const Scene> scene_;
  friend class SceneBuilder;
};

class SceneBuilder {
 public:
  // `name` names the scene in reports and messages ("SceneBuilder \"name\": /objects/0/...").
  explicit SceneBuilder(std::string name = "scene");
  ~SceneBuilder();
  SceneBuilder(SceneBuilder&&) noexcept;
  SceneBuilder& operator=(SceneBuilder&&) noexcept;

  SceneBuilder& comment(std::string text);
  // The conventions a reconcile runs when its options name none (default: zo).
  SceneBuilder& conventions(std::vector<DepthMode> modes);
  // glDepthRange(nearDepth, farDepth) the scene is drawn with (default 0, 1); (1, 0) is the
  // reversed-Z of apps without clip control: a NO projection, GL_GREATER, clear 0.
  SceneBuilder& depthRange(double nearDepth, double farDepth);
  // glEnable(GL_DEPTH_CLAMP) (default off): nothing is clipped at the near and far planes, and
  // what lies in front of the near plane is drawn at the near end of the depth range.
  SceneBuilder& depthClamp(bool enabled);
  // Samples per pixel the app draws with (MSAA): reconcile then draws every frame multisampled and
  // compares each sample (ReconcileOptions::samples, which overrides it). Triangle meshes only,
  // and no logarithmic depth (both write one depth per fragment).
  SceneBuilder& samples(int count);

  // A triangle mesh from the app's arrays: x, y, z per vertex and 3 indices per triangle, in the
  // order the app draws them (triangle k gets id firstId + k, as gl_PrimitiveID counts).
  SceneBuilder& mesh(std::string name, std::span<const float> positions,
                     std::span<const std::uint32_t> indices,
                     const glm::dmat4& worldFromObject = glm::dmat4(1.0));
  SceneBuilder& mesh(std::string name, std::span<const float> positions,
                     std::span<const std::uint16_t> indices,
                     const glm::dmat4& worldFromObject = glm::dmat4(1.0));
  SceneBuilder& mesh(std::string name, std::span<const double> positions,
                     std::span<const std::uint32_t> indices,
                     const glm::dmat4& worldFromObject = glm::dmat4(1.0));

  // Face culling for the mesh added last, as the app draws it: glEnable(GL_CULL_FACE),
  // glCullFace(cull), glFrontFace(frontFace); CullFace::None disables it (the default). The
  // winding is the triangles' index order seen through the matrix each run draws with
  // (docs/reconcile.md, Face culling). Analytic surfaces have no winding: build() refuses it there.
  SceneBuilder& faceCulling(CullFace cull, FrontFace frontFace = FrontFace::Ccw);
  // glDepthRange(nearDepth, farDepth) for the mesh added last (default: the scene's depthRange):
  // a first-person weapon drawn in [0, 0.1] in front of a world in [0.1, 1]. It runs the way the
  // scene's range does (one depth test for the frame); build() refuses it on analytic surfaces and
  // beside depth clamp.
  SceneBuilder& objectDepthRange(double nearDepth, double farDepth);
  // User clip planes for the mesh added last, beside the camera's (world space, [a, b, c, d]
  // keeping a x + b y + c z + d >= 0, as clipPlanes()): a section view that cuts one object.
  SceneBuilder& objectClipPlanes(std::vector<glm::dvec4> planes);
  // glPolygonOffsetClamp(factor, units, clamp) with GL_POLYGON_OFFSET_FILL for the mesh added
  // last (default: none): a decal on a wall pushed toward the camera, negative under GL_LESS,
  // positive under GL_GREATER (reversed-Z). Each finite; clamp 0 clamps nothing. build() refuses
  // it on analytic surfaces (they write their own depth).
  SceneBuilder& objectPolygonOffset(double factor, double units, double clamp = 0.0);

  // Analytic surfaces, rasterized exactly (docs/scene-format.md): placed by worldFromObject.
  SceneBuilder& sphere(std::string name, glm::dvec3 centre, double radius,
                       const glm::dmat4& worldFromObject = glm::dmat4(1.0));
  SceneBuilder& box(std::string name, glm::dvec3 min, glm::dvec3 max,
                    const glm::dmat4& worldFromObject = glm::dmat4(1.0));
  SceneBuilder& quad(std::string name, glm::dvec3 centre, glm::dvec3 halfEdgeU,
                     glm::dvec3 halfEdgeV, const glm::dmat4& worldFromObject = glm::dmat4(1.0));
  SceneBuilder& disk(std::string name, glm::dvec3 centre, glm::dvec3 normal, double radius,
                     const glm::dmat4& worldFromObject = glm::dmat4(1.0));
  SceneBuilder& plane(std::string name, glm::dvec3 point, glm::dvec3 normal,
                      const glm::dmat4& worldFromObject = glm::dmat4(1.0));

  // A camera as the app draws it: its clipFromWorld (drawn unchanged under every convention),
  // or its view and projection matrices (clipFromWorld = clipFromView * viewFromWorld, in double).
  SceneBuilder& camera(std::string name, const glm::dmat4& clipFromWorld, Viewport viewport);
  SceneBuilder& camera(std::string name, const glm::dmat4& viewFromWorld,
                       const glm::dmat4& clipFromView, Viewport viewport);
  // A perspective camera rebuilt for each convention a run uses (what an app that gets its
  // conventions right draws); farDistance nullopt: an infinite far plane.
  SceneBuilder& perspectiveCamera(std::string name, const glm::dmat4& viewFromWorld,
                                  double fovYDegrees, double nearDistance,
                                  std::optional<double> farDistance, Viewport viewport);
  // User clip planes for the camera added last, as the app draws with them: world-space planes
  // (a, b, c, d), gl_ClipDistance[i] = a x + b y + c z + d, kept where >= 0 (at most 8). Meshes
  // only: build() refuses them in a scene with analytic surfaces.
  SceneBuilder& clipPlanes(std::vector<glm::dvec4> planes);
  // `clipray check` findings (errors or warnings, by code: "depth-convention-mismatch") the camera
  // added last shows on purpose: a reconcile notes them as expected instead of failing the run
  // with the verdict convention-error (docs/scene-format.md, expectedFindings).
  SceneBuilder& expectedFindings(std::vector<std::string> codes);
  // A logarithmic depth the meshes' fragment shader writes (gl_FragDepth) when drawn from the
  // camera added last, L(w) = log2(1 + C w) / log2(1 + C far) of the fragment's clip w (1 - L
  // under reversed-Z): three.js's logarithmicDepthBuffer (C = 1, far its camera.far), or Outerra's
  // with its constant C. far and C positive and finite; build() refuses it beside analytic
  // surfaces, depth clamp, depth ranges, polygon offset and parallel projections.
  SceneBuilder& threeJsLogarithmicDepth(double far);
  SceneBuilder& outerraLogarithmicDepth(double constant, double far);
  // Without any camera, the scene is seen from four automatic ones framed on its geometry.

  // Validates and builds; throws InputError.
  TestScene build() const;
  // The scene file (JSON, format 1): `clipray reconcile` reads it as build() does.
  std::string json() const;

 private:
  struct Document;
  std::string name_;
  std::unique_ptr<Document> document_;  // nlohmann::json, kept out of this header
};

}  // namespace clipray
