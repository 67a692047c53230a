// Scene files, version 1: the document and its objects read with validation (messages name the
// file, the JSON pointer and the offending value), and the public entry points. The per-type
// readers live beside it (SceneCameras, SceneMeshObjects, ScenePrimitiveObjects).

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "clipray/InputError.hpp"
#include "clipray/io/InputFile.hpp"
#include "clipray/scene/AutoCameras.hpp"
#include "clipray/scene/MeshFiles.hpp"
#include "clipray/scene/Scene.hpp"
#include "clipray/scene/SceneReader.hpp"

namespace clipray {

namespace detail {

namespace {

constexpr int kFormatVersion = 1;

// Rotation about a unit axis, exact for multiples of 90 degrees (cos 90 is 0, not 6e-17).
glm::dmat4 rotationDegrees(const glm::dvec3& unitAxis, double degrees) {
  double c = 0.0;
  double s = 0.0;
  double turn = std::fmod(degrees, 360.0);
  if (turn < 0) turn += 360.0;
  if (turn == 0.0) {
    c = 1.0;
  } else if (turn == 90.0) {
    s = 1.0;
  } else if (turn == 180.0) {
    c = -1.0;
  } else if (turn == 270.0) {
    s = -1.0;
  } else {
    const double radians = degrees * (std::numbers::pi / 180.0);
    c = std::cos(radians);
    s = std::sin(radians);
  }
  // Rodrigues: R = c I + s [k]x + (1 - c) k k^T, stored column-major (m[column][row]).
  const glm::dvec3 k = unitAxis;
  const double cross[3][3] = {{0, -k.z, k.y}, {k.z, 0, -k.x}, {-k.y, k.x, 0}};  // [row][col]
  glm::dmat4 m(1.0);
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      m[col][row] = (row == col ? c : 0.0) + s * cross[row][col] + (1.0 - c) * k[row] * k[col];
    }
  }
  return m;
}

// The object types of the format. To add one (sphere, disk, quad, box): list its keys and reader.
struct ObjectType {
  std::string_view name;
  std::vector<std::string_view> keys;  // besides the keys every object has
  bool triangles;                      // drawn as triangles: "cull" and "frontFace" apply
  void (SceneReader::*read)(const json&, const Pointer&, const glm::dmat4&, std::string,
                            Scene&) const;
};

const std::vector<std::string_view>& commonObjectKeys() {
  static const std::vector<std::string_view> keys = {"name", "type", "transform",
                                                     "worldFromObject"};
  return keys;
}

const std::vector<ObjectType>& objectTypes() {
  static const std::vector<ObjectType> types = {
      {"mesh", {"positions", "indices"}, true, &SceneReader::readMesh},
      {"meshFile", {"path", "useCameras"}, true, &SceneReader::readMeshFile},
      {"terrain", {"triangles", "seed"}, true, &SceneReader::readTerrain},
      {"sphere", {"centre", "radius"}, false, &SceneReader::readSphere},
      {"disk", {"centre", "normal", "radius"}, false, &SceneReader::readDisk},
      {"quad", {"centre", "halfEdges"}, false, &SceneReader::readQuad},
      {"box", {"min", "max", "centre", "halfExtents"}, false, &SceneReader::readBox},
      {"plane", {"point", "normal"}, false, &SceneReader::readPlane},
  };
  return types;
}

}  // namespace

Scene SceneReader::read(const json& root) {
  const Pointer top;
  expectObject(root, top);
  const json& version = required(root, top, "version");
  if (!version.is_number_integer() || version != kFormatVersion) {
    fail(top / "version", "unsupported version " + describe(version) +
                              "; this clipray reads version " + std::to_string(kFormatVersion));
  }
  expectKnownKeys(root, top,
                  {"version", "comment", "conventions", "depthRange", "depthClamp", "samples",
                   "cameras", "objects"});

  Scene scene;
  scene.version = kFormatVersion;
  if (const json* comment = optional(root, "comment")) {
    scene.comment = string(*comment, top / "comment");
  }
  if (const json* modes = optional(root, "conventions")) {
    scene.conventions = conventions(*modes, top / "conventions");
  }
  if (const json* range = optional(root, "depthRange")) {
    scene.depthRange = depthRange(*range, top / "depthRange");
  }
  if (const json* clamp = optional(root, "depthClamp")) {
    if (!clamp->is_boolean()) {
      fail(top / "depthClamp", "expected true or false (GL_DEPTH_CLAMP), got " + describe(*clamp));
    }
    scene.depthClamp = clamp->get<bool>();
  }
  if (const json* samples = optional(root, "samples")) {
    if (!samples->is_number_integer() || *samples < 1 || *samples > 64) {
      fail(top / "samples",
           "expected a sample count from 1 to 64 (samples per pixel), got " + describe(*samples));
    }
    scene.samples = samples->get<int>();
  }

  const json& cameras = required(root, top, "cameras");
  // "auto": the automatic cameras, framed once every object is read (AutoCameras.hpp).
  const bool automatic = cameras.is_string() && cameras.get<std::string>() == "auto";
  // Empty is allowed here when a meshFile object brings its cameras (checked below).
  if (!cameras.is_array() && !automatic) {
    fail(top / "cameras",
         "expected a non-empty array of cameras or \"auto\", got " + describe(cameras));
  }
  std::map<std::string, Pointer> cameraNames;
  for (std::size_t i = 0; !automatic && i < cameras.size(); ++i) {
    scene.cameras.push_back(camera(cameras[i], top / "cameras" / i, cameraNames));
  }

  const json& objects = required(root, top, "objects");
  if (!objects.is_array()) fail(top / "objects", "expected an array, got " + describe(objects));
  std::map<std::string, Pointer> objectNames;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    object(objects[i], top / "objects" / i, objectNames, scene);
  }
  if (automatic) {
    if (!scene.cameras.empty()) {
      fail(top / "cameras",
           "\"auto\" and a meshFile object with \"useCameras\": true; "
           "choose one");
    }
    try {
      scene.cameras = autoCameras(scene);
    } catch (const InputError&) {
      fail(top / "cameras", "\"auto\" needs finite geometry to frame, and the scene has none");
    }
  }
  if (scene.cameras.empty()) {
    fail(top / "cameras", "expected a non-empty array of cameras, got " + describe(cameras) +
                              " (and no meshFile object with \"useCameras\": true)");
  }
  for (std::size_t i = 0; i < scene.cameras.size() && !scene.primitives.empty(); ++i) {
    if (scene.cameras[i].clipPlanes.empty()) continue;
    fail(top / "cameras" / i / "clipPlanes",
         "clip planes with analytic primitives (\"" + scene.primitives[0].name +
             "\") are not modelled: their fragment shader traces the ray from the near plane, "
             "not the clipped interval; use triangle meshes");
  }
  if (scene.depthClamp && !scene.primitives.empty()) {
    fail(top / "depthClamp",
         "depth clamp with analytic primitives (\"" + scene.primitives[0].name +
             "\") is not modelled: their fragment shader traces the ray from the near plane, "
             "and depth clamp draws what lies in front of it; use triangle meshes");
  }
  if (scene.samples > 1 && !scene.primitives.empty()) {
    fail(top / "samples", "multisampling with analytic primitives (\"" + scene.primitives[0].name +
                              "\") is not modelled: their fragment shader writes one depth per "
                              "pixel, at its centre; use triangle meshes");
  }
  for (std::size_t i = 0; i < scene.cameras.size() && scene.samples > 1; ++i) {
    if (!scene.cameras[i].logarithmicDepth) continue;
    fail(top / "samples", "multisampling with a logarithmic depth (camera \"" +
                              scene.cameras[i].name +
                              "\") is not modelled: its fragment shader writes one depth per "
                              "pixel, at its centre");
  }
  // GL_MAX_CLIP_DISTANCES holds the camera's and an object's planes together.
  for (const MeshObject& object : scene.objects) {
    for (const Camera& camera : scene.cameras) {
      if (object.clipPlanes.size() + camera.clipPlanes.size() <= Camera::kMaxClipPlanes) continue;
      fail(top / "objects", "object \"" + object.name + "\" has " +
                                std::to_string(object.clipPlanes.size()) +
                                " clip planes and camera \"" + camera.name + "\" " +
                                std::to_string(camera.clipPlanes.size()) + ": at most " +
                                std::to_string(Camera::kMaxClipPlanes) +
                                " together (gl_ClipDistance; GL_MAX_CLIP_DISTANCES is at least 8)");
    }
  }
  const auto ownRange = std::find_if(scene.objects.begin(), scene.objects.end(),
                                     [](const MeshObject& o) { return o.depthRange.has_value(); });
  if (scene.depthClamp && ownRange != scene.objects.end()) {
    fail(top / "depthClamp",
         "depth clamp with an object drawn in a depth range of its own (\"" + ownRange->name +
             "\") is not modelled: use the scene's depthRange for every object");
  }
  for (std::size_t i = 0; i < scene.cameras.size(); ++i) {
    if (scene.cameras[i].logarithmicDepth) {
      refuseUnmodelledLogDepth(scene, scene.cameras[i], top / "cameras" / i / "logarithmicDepth");
    }
  }
  if (scene.triangleCount() + scene.primitives.size() > PrimitiveIdTable::kMaxPrimitives) {
    fail(top / "objects", "too many primitives for 32-bit primitive ids: " +
                              std::to_string(scene.triangleCount() + scene.primitives.size()));
  }
  return scene;
}

void SceneReader::refuseUnmodelledLogDepth(const Scene& scene, const Camera& camera,
                                           const Pointer& at) const {
  // What the model of a depth written by the mesh shader leaves out (docs/reconcile.md): the
  // analytic primitives write their own projective depth; depth clamp, glDepthRange and polygon
  // offset act on the rasterizer's depth, which gl_FragDepth replaces; a parallel projection has
  // one w everywhere (three.js falls back to gl_FragCoord.z there).
  const auto refuse = [&](const std::string& what) {
    fail(at, "a logarithmic depth with " + what + " is not modelled; use triangle meshes drawn " +
                 "with the default depth range, no depth clamp and no polygon offset, seen " +
                 "through a perspective projection");
  };
  if (!scene.primitives.empty()) {
    refuse(std::string("a ") + primitiveKindName(scene.primitives[0].kind) + " (\"" +
           scene.primitives[0].name + "\")");
  }
  if (scene.depthClamp) refuse("depth clamp");
  if (scene.depthRange != glm::dvec2(0.0, 1.0)) refuse("the scene's depthRange");
  for (const MeshObject& object : scene.objects) {
    if (object.depthRange) refuse("a depth range per object (\"" + object.name + "\")");
    if (object.polygonOffset) refuse("a polygon offset (\"" + object.name + "\")");
  }
  const bool parallel =
      std::holds_alternative<OrthographicProjection>(camera.projection) ||
      (camera.rawClipFromWorld &&
       glm::dvec3((*camera.rawClipFromWorld)[0][3], (*camera.rawClipFromWorld)[1][3],
                  (*camera.rawClipFromWorld)[2][3]) == glm::dvec3(0.0));
  if (parallel) refuse("a parallel projection (clip w is 1 everywhere)");
  // Past the log far, L(w) > 1: GL clamps the written depth to the depth range, and the depth
  // test against the cleared far value then hides it, which the rays do not model.
  if (const auto* perspective = std::get_if<PerspectiveProjection>(&camera.projection)) {
    const double logFar = camera.logarithmicDepth->far;
    if (!perspective->farDistance || *perspective->farDistance > logFar) {
      fail(at / "far", "a logarithmic depth whose far (" + shortNumber(logFar) +
                           ") lies before the projection's far plane (" +
                           (perspective->farDistance ? shortNumber(*perspective->farDistance)
                                                     : std::string("infinite")) +
                           ") is not modelled: what lies between is written at a depth past 1, "
                           "which GL clamps and the depth test then hides; give both the same far, "
                           "as three.js's logarithmicDepthBuffer does (camera.far)");
    }
  }
}

void SceneReader::object(const json& value, const Pointer& at,
                         std::map<std::string, Pointer>& names, Scene& scene) const {
  expectObject(value, at);
  const json& type = required(value, at, "type");
  const ObjectType* kind = nullptr;
  for (const ObjectType& candidate : objectTypes()) {
    if (type.is_string() && type.get<std::string>() == candidate.name) kind = &candidate;
  }
  if (!kind) {
    std::vector<std::string_view> typeNames;
    for (const ObjectType& candidate : objectTypes()) typeNames.push_back(candidate.name);
    fail(at / "type", "expected one of " + quotedList(typeNames) + ", got " + describe(type));
  }
  std::vector<std::string_view> keys = commonObjectKeys();
  keys.insert(keys.end(), kind->keys.begin(), kind->keys.end());
  for (const std::string_view key :
       {"cull", "frontFace", "depthRange", "clipPlanes", "polygonOffset"}) {
    if (kind->triangles) {
      keys.push_back(key);
    } else if (key == "clipPlanes" && optional(value, key)) {
      fail(at / std::string(key),
           "clip planes per object apply to triangle meshes (mesh, meshFile, terrain); a " +
               std::string(kind->name) +
               " is ray-traced by its fragment shader from the near plane, not the clipped "
               "interval");
    } else if (key == "polygonOffset" && optional(value, key)) {
      fail(at / std::string(key),
           "polygon offset applies to triangle meshes (mesh, meshFile, terrain); a " +
               std::string(kind->name) +
               " writes its own depth from its fragment shader, which no offset moves");
    } else if (key == "depthRange" && optional(value, key)) {
      fail(at / std::string(key),
           "a depth range per object applies to triangle meshes (mesh, meshFile, terrain); a " +
               std::string(kind->name) +
               " is drawn with the scene's (its fragment shader writes its depth)");
    } else if (optional(value, key)) {
      fail(at / std::string(key),
           "face culling applies to triangle meshes (mesh, meshFile, "
           "terrain); a " +
               std::string(kind->name) +
               " is ray-traced by its fragment shader and has no winding");
    }
  }
  expectKnownKeys(value, at, keys);
  std::string objectName = name(value, at, "object", names);
  const std::size_t firstObject = scene.objects.size();
  (this->*kind->read)(value, at, placement(value, at), std::move(objectName), scene);
  if (kind->triangles) {
    const FaceCulling culling = faceCulling(value, at);
    for (std::size_t k = firstObject; k < scene.objects.size(); ++k) {
      scene.objects[k].cull = culling.cull;
      scene.objects[k].frontFace = culling.frontFace;
    }
    if (const json* range = optional(value, "depthRange")) {
      const glm::dvec2 objectRange = depthRange(*range, at / "depthRange");
      // One depth test for the frame: whether the nearer surface has the greater depth must not
      // change from object to object.
      if ((objectRange.x > objectRange.y) != (scene.depthRange.x > scene.depthRange.y)) {
        fail(at / "depthRange",
             "expected a range that runs the way the scene's " +
                 describe(json::array({scene.depthRange.x, scene.depthRange.y})) +
                 " does (one depth test for the frame), got " + describe(*range));
      }
      for (std::size_t k = firstObject; k < scene.objects.size(); ++k) {
        scene.objects[k].depthRange = objectRange;
      }
    }
    if (const json* planes = optional(value, "clipPlanes")) {
      const std::vector<glm::dvec4> objectPlanes = clipPlanes(*planes, at / "clipPlanes");
      for (std::size_t k = firstObject; k < scene.objects.size(); ++k) {
        scene.objects[k].clipPlanes = objectPlanes;
      }
    }
    if (const json* offset = optional(value, "polygonOffset")) {
      const PolygonOffset parsed = polygonOffset(*offset, at / "polygonOffset");
      for (std::size_t k = firstObject; k < scene.objects.size(); ++k) {
        scene.objects[k].polygonOffset = parsed;
      }
    }
  }
}

PolygonOffset SceneReader::polygonOffset(const json& value, const Pointer& at) const {
  if (!value.is_object()) {
    fail(at, "expected {\"factor\", \"units\", \"clamp\"} of glPolygonOffsetClamp, got " +
                 describe(value));
  }
  expectKnownKeys(value, at, {"factor", "units", "clamp"});
  PolygonOffset offset;
  if (const json* factor = optional(value, "factor"))
    offset.factor = number(*factor, at / "factor");
  if (const json* units = optional(value, "units")) offset.units = number(*units, at / "units");
  if (const json* clamp = optional(value, "clamp")) offset.clamp = number(*clamp, at / "clamp");
  return offset;
}

SceneReader::FaceCulling SceneReader::faceCulling(const json& object, const Pointer& at) const {
  FaceCulling culling;
  if (const json* cull = optional(object, "cull")) {
    const std::optional<CullFace> parsed =
        cull->is_string() ? parseCullFace(cull->get<std::string>()) : std::nullopt;
    if (!parsed) {
      fail(at / "cull",
           "expected one of \"none\", \"back\", \"front\" (glCullFace), got " + describe(*cull));
    }
    culling.cull = *parsed;
  }
  if (const json* front = optional(object, "frontFace")) {
    const std::optional<FrontFace> parsed =
        front->is_string() ? parseFrontFace(front->get<std::string>()) : std::nullopt;
    if (!parsed) {
      fail(at / "frontFace",
           "expected one of \"ccw\", \"cw\" (glFrontFace), got " + describe(*front));
    }
    culling.frontFace = *parsed;
  }
  return culling;
}

glm::dmat4 SceneReader::placement(const json& object, const Pointer& at) const {
  const json* transformValue = optional(object, "transform");
  const json* worldFromObject = optional(object, "worldFromObject");
  if (transformValue && worldFromObject) {
    fail(at, "expected either \"transform\" or \"worldFromObject\", got both");
  }
  if (worldFromObject) return affineMatrix(*worldFromObject, at / "worldFromObject");
  if (transformValue) return transform(*transformValue, at / "transform");
  return glm::dmat4(1.0);
}

// world = T * R * S * p
glm::dmat4 SceneReader::transform(const json& value, const Pointer& at) const {
  expectObject(value, at);
  expectKnownKeys(value, at, {"translate", "rotateDegrees", "scale"});
  glm::dmat4 translation(1.0);
  glm::dmat4 rotation(1.0);
  glm::dmat4 scale(1.0);
  if (const json* t = optional(value, "translate")) {
    translation[3] = glm::dvec4(vector3(*t, at / "translate"), 1.0);
  }
  if (const json* r = optional(value, "rotateDegrees")) {
    const Pointer rAt = at / "rotateDegrees";
    expectObject(*r, rAt);
    expectKnownKeys(*r, rAt, {"axis", "angle"});
    const json& axisValue = required(*r, rAt, "axis");
    const glm::dvec3 axis = vector3(axisValue, rAt / "axis");
    if (axis == glm::dvec3(0.0)) {
      fail(rAt / "axis", "expected a non-zero direction, got " + describe(axisValue));
    }
    const double angle = number(required(*r, rAt, "angle"), rAt / "angle");
    rotation = rotationDegrees(safeNormalize(axis), angle);
  }
  if (const json* s = optional(value, "scale")) {
    const Pointer sAt = at / "scale";
    glm::dvec3 factors(1.0);
    if (s->is_number()) {
      factors = glm::dvec3(number(*s, sAt));
      if (factors.x == 0.0) fail(sAt, "expected a non-zero number, got " + describe(*s));
    } else if (s->is_array() && s->size() == 3) {
      factors = vector3(*s, sAt);
      for (std::size_t i = 0; i < 3; ++i) {
        if (factors[static_cast<int>(i)] == 0.0) {
          fail(sAt / i, "expected a non-zero number, got " + describe((*s)[i]));
        }
      }
    } else {
      fail(sAt, "expected a number or an array of 3 numbers, got " + describe(*s));
    }
    scale[0][0] = factors.x;
    scale[1][1] = factors.y;
    scale[2][2] = factors.z;
  }
  return translation * rotation * scale;
}

}  // namespace detail

Scene parseScene(const std::string& jsonText, const std::string& path) {
  const detail::json root = detail::parseJson(jsonText, path);
  Scene scene = detail::SceneReader(path).read(root);
  scene.path = path;
  scene.name = std::filesystem::path(path).stem().string();
  return scene;
}

bool isMeshFilePath(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".gltf" || extension == ".glb" || extension == ".obj" || extension == ".ply";
}

Scene loadScene(const std::string& path) {
  if (isMeshFilePath(path)) {
    // A mesh file on its own: its geometry seen from its own cameras (glTF), under the default
    // conventions.
    MeshFileContents contents = loadMeshFile(path);
    Scene scene;
    scene.path = path;
    scene.name = std::filesystem::path(path).stem().string();
    scene.comment = "mesh file " + path;
    scene.cameras = std::move(contents.cameras);
    scene.objects = std::move(contents.objects);
    scene.warnings = std::move(contents.warnings);
    if (scene.cameras.empty()) {
      // Most assets ship without a camera: frame the automatic ones on the geometry.
      scene.cameras = autoCameras(scene);
      std::string names;
      for (const Camera& camera : scene.cameras) names += (names.empty() ? "" : ", ") + camera.name;
      scene.warnings.push_back(path + ": the file has no cameras; using the automatic cameras " +
                               names + " (docs/scene-format.md)");
    }
    return scene;
  }
  return parseScene(readInputFile(path, kMaxSceneFileBytes, "scene file"), path);
}

}  // namespace clipray
