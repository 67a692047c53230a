// SceneBuilder: the app's arrays written as a scene document (format 1) and read back by the scene
// file reader, so that code and files share one validation and one set of messages.

#include "clipray/SceneBuilder.hpp"

#include <utility>

#include "clipray/io/LocatedJson.hpp"
#include "clipray/scene/Scene.hpp"
#include "clipray/scene/SceneReader.hpp"

namespace clipray {

namespace {

using Json = detail::json;

Json vector3(glm::dvec3 v) {
  return Json::array({v.x, v.y, v.z});
}

// 16 numbers, column-major (element 4 * column + row), as the scene format reads matrices.
Json matrix(const glm::dmat4& m) {
  Json values = Json::array();
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) values.push_back(m[column][row]);
  }
  return values;
}

template <typename Position, typename Index>
Json meshObject(std::string name, std::span<const Position> positions,
                std::span<const Index> indices, const glm::dmat4& worldFromObject) {
  Json positionValues = Json::array();
  positionValues.get_ref<Json::array_t&>().reserve(positions.size());
  for (const Position p : positions) positionValues.push_back(static_cast<double>(p));
  Json indexValues = Json::array();
  indexValues.get_ref<Json::array_t&>().reserve(indices.size());
  for (const Index i : indices) indexValues.push_back(static_cast<std::uint64_t>(i));
  return {{"name", std::move(name)},
          {"type", "mesh"},
          {"worldFromObject", matrix(worldFromObject)},
          {"positions", std::move(positionValues)},
          {"indices", std::move(indexValues)}};
}

Json placed(Json object, const glm::dmat4& worldFromObject) {
  if (worldFromObject != glm::dmat4(1.0)) object["worldFromObject"] = matrix(worldFromObject);
  return object;
}

Json viewportValue(Viewport viewport) {
  return Json::array({viewport.width, viewport.height});
}

}  // namespace

struct SceneBuilder::Document {
  Json root = {{"version", 1}, {"objects", Json::array()}, {"cameras", Json::array()}};
  Json& objects() { return root["objects"]; }
  Json& cameras() { return root["cameras"]; }
};

SceneBuilder::SceneBuilder(std::string name)
    : name_(std::move(name)), document_(std::make_unique<Document>()) {}
SceneBuilder::~SceneBuilder() = default;
SceneBuilder::SceneBuilder(SceneBuilder&&) noexcept = default;
SceneBuilder& SceneBuilder::operator=(SceneBuilder&&) noexcept = default;

SceneBuilder& SceneBuilder::comment(std::string text) {
  document_->root["comment"] = std::move(text);
  return *this;
}

SceneBuilder& SceneBuilder::depthRange(double nearDepth, double farDepth) {
  document_->root["depthRange"] = Json::array({nearDepth, farDepth});
  return *this;
}

SceneBuilder& SceneBuilder::depthClamp(bool enabled) {
  document_->root["depthClamp"] = enabled;
  return *this;
}

SceneBuilder& SceneBuilder::samples(int count) {
  document_->root["samples"] = count;
  return *this;
}

SceneBuilder& SceneBuilder::faceCulling(CullFace cull, FrontFace frontFace) {
  if (document_->objects().empty()) {
    throw InputError("SceneBuilder " + detail::jsonString(name_) +
                     ": faceCulling() applies to the mesh added last, and no object was added yet");
  }
  Json& object = document_->objects().back();
  object["cull"] = cullFaceName(cull);
  object["frontFace"] = frontFaceName(frontFace);
  return *this;
}

SceneBuilder& SceneBuilder::objectDepthRange(double nearDepth, double farDepth) {
  if (document_->objects().empty()) {
    throw InputError(
        "SceneBuilder " + detail::jsonString(name_) +
        ": objectDepthRange() applies to the mesh added last, and no object was added yet");
  }
  document_->objects().back()["depthRange"] = Json::array({nearDepth, farDepth});
  return *this;
}

namespace {

// Clip planes as the scene format writes them: [[a, b, c, d], ...].
Json planesJson(const std::vector<glm::dvec4>& planes) {
  Json values = Json::array();
  for (const glm::dvec4& plane : planes) values.push_back({plane.x, plane.y, plane.z, plane.w});
  return values;
}

}  // namespace

SceneBuilder& SceneBuilder::objectClipPlanes(std::vector<glm::dvec4> planes) {
  if (document_->objects().empty()) {
    throw InputError(
        "SceneBuilder " + detail::jsonString(name_) +
        ": objectClipPlanes() applies to the mesh added last, and no object was added yet");
  }
  document_->objects().back()["clipPlanes"] = planesJson(planes);
  return *this;
}

SceneBuilder& SceneBuilder::objectPolygonOffset(double factor, double units, double clamp) {
  if (document_->objects().empty()) {
    throw InputError(
        "SceneBuilder " + detail::jsonString(name_) +
        ": objectPolygonOffset() applies to the mesh added last, and no object was added yet");
  }
  document_->objects().back()["polygonOffset"] =
      Json::object({{"factor", factor}, {"units", units}, {"clamp", clamp}});
  return *this;
}

SceneBuilder& SceneBuilder::clipPlanes(std::vector<glm::dvec4> planes) {
  if (document_->cameras().empty()) {
    throw InputError(
        "SceneBuilder " + detail::jsonString(name_) +
        ": clipPlanes() applies to the camera added last, and no camera was added yet");
  }
  document_->cameras().back()["clipPlanes"] = planesJson(planes);
  return *this;
}

SceneBuilder& SceneBuilder::expectedFindings(std::vector<std::string> codes) {
  if (document_->cameras().empty()) {
    throw InputError(
        "SceneBuilder " + detail::jsonString(name_) +
        ": expectedFindings() applies to the camera added last, and no camera was added yet");
  }
  document_->cameras().back()["expectedFindings"] = std::move(codes);
  return *this;
}

SceneBuilder& SceneBuilder::threeJsLogarithmicDepth(double far) {
  if (document_->cameras().empty()) {
    throw InputError("SceneBuilder " + detail::jsonString(name_) +
                     ": threeJsLogarithmicDepth() applies to the camera added last, and no camera "
                     "was added yet");
  }
  document_->cameras().back()["logarithmicDepth"] =
      Json::object({{"form", "threejs"}, {"far", far}});
  return *this;
}

SceneBuilder& SceneBuilder::outerraLogarithmicDepth(double constant, double far) {
  if (document_->cameras().empty()) {
    throw InputError("SceneBuilder " + detail::jsonString(name_) +
                     ": outerraLogarithmicDepth() applies to the camera added last, and no camera "
                     "was added yet");
  }
  document_->cameras().back()["logarithmicDepth"] =
      Json::object({{"form", "outerra"}, {"far", far}, {"constant", constant}});
  return *this;
}

SceneBuilder& SceneBuilder::conventions(std::vector<DepthMode> modes) {
  Json names = Json::array();
  for (const DepthMode& mode : modes) names.push_back(mode.name());
  document_->root["conventions"] = std::move(names);
  return *this;
}

SceneBuilder& SceneBuilder::mesh(std::string name, std::span<const float> positions,
                                 std::span<const std::uint32_t> indices,
                                 const glm::dmat4& worldFromObject) {
  document_->objects().push_back(meshObject(std::move(name), positions, indices, worldFromObject));
  return *this;
}

SceneBuilder& SceneBuilder::mesh(std::string name, std::span<const float> positions,
                                 std::span<const std::uint16_t> indices,
                                 const glm::dmat4& worldFromObject) {
  document_->objects().push_back(meshObject(std::move(name), positions, indices, worldFromObject));
  return *this;
}

SceneBuilder& SceneBuilder::mesh(std::string name, std::span<const double> positions,
                                 std::span<const std::uint32_t> indices,
                                 const glm::dmat4& worldFromObject) {
  document_->objects().push_back(meshObject(std::move(name), positions, indices, worldFromObject));
  return *this;
}

SceneBuilder& SceneBuilder::sphere(std::string name, glm::dvec3 centre, double radius,
                                   const glm::dmat4& worldFromObject) {
  document_->objects().push_back(placed({{"name", std::move(name)},
                                         {"type", "sphere"},
                                         {"centre", vector3(centre)},
                                         {"radius", radius}},
                                        worldFromObject));
  return *this;
}

SceneBuilder& SceneBuilder::box(std::string name, glm::dvec3 min, glm::dvec3 max,
                                const glm::dmat4& worldFromObject) {
  document_->objects().push_back(placed(
      {{"name", std::move(name)}, {"type", "box"}, {"min", vector3(min)}, {"max", vector3(max)}},
      worldFromObject));
  return *this;
}

SceneBuilder& SceneBuilder::quad(std::string name, glm::dvec3 centre, glm::dvec3 halfEdgeU,
                                 glm::dvec3 halfEdgeV, const glm::dmat4& worldFromObject) {
  document_->objects().push_back(
      placed({{"name", std::move(name)},
              {"type", "quad"},
              {"centre", vector3(centre)},
              {"halfEdges", Json::array({vector3(halfEdgeU), vector3(halfEdgeV)})}},
             worldFromObject));
  return *this;
}

SceneBuilder& SceneBuilder::disk(std::string name, glm::dvec3 centre, glm::dvec3 normal,
                                 double radius, const glm::dmat4& worldFromObject) {
  document_->objects().push_back(placed({{"name", std::move(name)},
                                         {"type", "disk"},
                                         {"centre", vector3(centre)},
                                         {"normal", vector3(normal)},
                                         {"radius", radius}},
                                        worldFromObject));
  return *this;
}

SceneBuilder& SceneBuilder::plane(std::string name, glm::dvec3 point, glm::dvec3 normal,
                                  const glm::dmat4& worldFromObject) {
  document_->objects().push_back(placed({{"name", std::move(name)},
                                         {"type", "plane"},
                                         {"point", vector3(point)},
                                         {"normal", vector3(normal)}},
                                        worldFromObject));
  return *this;
}

SceneBuilder& SceneBuilder::camera(std::string name, const glm::dmat4& clipFromWorld,
                                   Viewport viewport) {
  document_->cameras().push_back({{"name", std::move(name)},
                                  {"viewport", viewportValue(viewport)},
                                  {"clipFromWorld", matrix(clipFromWorld)}});
  return *this;
}

SceneBuilder& SceneBuilder::camera(std::string name, const glm::dmat4& viewFromWorld,
                                   const glm::dmat4& clipFromView, Viewport viewport) {
  return camera(std::move(name), clipFromView * viewFromWorld, viewport);
}

SceneBuilder& SceneBuilder::perspectiveCamera(std::string name, const glm::dmat4& viewFromWorld,
                                              double fovYDegrees, double nearDistance,
                                              std::optional<double> farDistance,
                                              Viewport viewport) {
  Json projection = {{"type", "perspective"}, {"fovYDegrees", fovYDegrees}, {"near", nearDistance}};
  if (farDistance) projection["far"] = *farDistance;
  document_->cameras().push_back({{"name", std::move(name)},
                                  {"viewport", viewportValue(viewport)},
                                  {"viewFromWorld", matrix(viewFromWorld)},
                                  {"projection", std::move(projection)}});
  return *this;
}

TestScene SceneBuilder::build() const {
  Json root = document_->root;
  if (root["cameras"].empty()) root["cameras"] = "auto";
  const std::string label = "SceneBuilder " + detail::jsonString(name_);
  auto scene = std::make_shared<Scene>(detail::SceneReader(label).read(root));
  scene->path = label;
  scene->name = name_;
  return TestScene(std::move(scene));
}

std::string SceneBuilder::json() const {
  detail::json root = document_->root;
  if (root["cameras"].empty()) root["cameras"] = "auto";
  return root.dump(2) + "\n";
}

TestScene TestScene::load(const std::string& path) {
  return TestScene(std::make_shared<Scene>(loadScene(path)));
}

const std::string& TestScene::name() const {
  return scene_->name;
}

std::vector<std::string> TestScene::cameraNames() const {
  std::vector<std::string> names;
  for (const Camera& camera : scene_->cameras) names.push_back(camera.name);
  return names;
}

std::vector<std::string> TestScene::objectNames() const {
  std::vector<std::string> names;
  for (const MeshObject& object : scene_->objects) names.push_back(object.name);
  for (const AnalyticPrimitive& primitive : scene_->primitives) names.push_back(primitive.name);
  return names;
}

std::size_t TestScene::triangleCount() const {
  return scene_->triangleCount();
}

const std::vector<std::string>& TestScene::warnings() const {
  return scene_->warnings;
}

}  // namespace clipray
