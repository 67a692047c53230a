// Scene files, version 1: parsing with locations, validation with messages that name the file, the
// JSON pointer and the offending value, and the few scene computations that belong with the data.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "clipray/math/Projections.hpp"
#include "clipray/scene/InputError.hpp"
#include "clipray/scene/MeshFiles.hpp"
#include "clipray/scene/Scene.hpp"
#include "clipray/scene/Terrain.hpp"

namespace clipray {

namespace {

using json = nlohmann::json;
using Pointer = json::json_pointer;

constexpr int kFormatVersion = 1;
constexpr std::uint64_t kMaxViewportDimension = 16384;
// A matrix is singular when its scaled determinant (see scaledDeterminant) is below this.
constexpr double kSingularThreshold = 1e-12;
// Look-at: up is parallel to the view direction when |sin(angle)| is below this.
constexpr double kParallelThreshold = 1e-9;
// Values quoted in messages are cut to this many characters.
constexpr std::size_t kMaxQuotedChars = 80;
// Primitive ids are 32-bit and 0 is background.
constexpr std::uint64_t kMaxTriangles = std::numeric_limits<std::uint32_t>::max() - 1u;

// ---------------------------------------------------------------------------------------------
// Message helpers

// The root is written "/" so that messages never show an empty location.
std::string pointerText(const Pointer& pointer) {
  return pointer.empty() ? std::string("/") : pointer.to_string();
}

std::string jsonString(std::string_view text) {
  return json(std::string(text)).dump();
}

// A value as JSON prints it, cut to kMaxQuotedChars. JSON cannot print inf or NaN (nlohmann writes
// null), so those are spelled out.
std::string describe(const json& value) {
  if (value.is_number_float()) {
    const double x = value.get<double>();
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  }
  std::string text = value.dump();
  if (text.size() > kMaxQuotedChars) {
    std::size_t cut = kMaxQuotedChars - 3;
    while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0u) == 0x80u) --cut;  // UTF-8
    text = text.substr(0, cut) + "...";
  }
  return text;
}

std::string shortNumber(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", x);
  return buffer;
}

// "a", "b", "c"
std::string quotedList(const std::vector<std::string_view>& names) {
  std::string list;
  for (std::string_view name : names) {
    if (!list.empty()) list += ", ";
    list += jsonString(name);
  }
  return list;
}

// ---------------------------------------------------------------------------------------------
// JSON parsing that knows where it is: line and column for malformed text, a JSON pointer for
// numbers that overflow double (1e999) and for duplicate keys (which plain nlohmann would keep
// silently, last one wins).

class LocatingSax {
 public:
  LocatingSax(const std::string& file, const std::string& text) : file_(file), text_(text) {}

  json takeResult() { return std::move(root_); }

  bool null() { return store(nullptr); }
  bool boolean(bool value) { return store(value); }
  bool number_integer(json::number_integer_t value) { return store(value); }
  bool number_unsigned(json::number_unsigned_t value) { return store(value); }
  bool number_float(json::number_float_t value, const json::string_t& /*text*/) {
    return store(value);
  }
  bool string(json::string_t& value) { return store(std::move(value)); }
  bool binary(json::binary_t& value) { return store(json::binary(std::move(value))); }

  bool start_object(std::size_t /*elements*/) {
    open_.push_back({add(json::object()), {}});
    return true;
  }
  bool key(json::string_t& name) {
    Frame& top = open_.back();
    if (top.node->contains(name)) {
      throw InputError(file_, pointerText(pathOfOpenNode() / name),
                       "duplicate key " + jsonString(name));
    }
    top.key = std::move(name);
    return true;
  }
  bool end_object() {
    open_.pop_back();
    return true;
  }
  bool start_array(std::size_t /*elements*/) {
    open_.push_back({add(json::array()), {}});
    return true;
  }
  bool end_array() {
    open_.pop_back();
    return true;
  }

  bool parse_error(std::size_t position, const std::string& lastToken,
                   const json::exception& error) {
    if (error.id == 406) {  // out_of_range.406: a number that overflows double, e.g. 1e999
      throw InputError(file_, pointerText(pathOfNextValue()),
                       "expected a finite number, got " + lastToken);
    }
    // `position` counts the characters read, so the offending one is at index position - 1.
    const std::size_t offset = std::min(position > 0 ? position - 1 : 0, text_.size());
    const std::string_view before(text_.data(), offset);
    const std::size_t line =
        1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
    const std::size_t lastNewline = before.rfind('\n');
    const std::size_t column =
        lastNewline == std::string_view::npos ? offset + 1 : offset - lastNewline;
    throw InputError(file_ + ": line " + std::to_string(line) + ", column " +
                     std::to_string(column) + ": malformed JSON: " + reason(error.what()));
  }

 private:
  struct Frame {
    json* node;       // an array or object still being filled
    std::string key;  // objects: the key of the value being read
  };

  // nlohmann's message without its prefix
  // "[json.exception.parse_error.101] parse error at line L, column C: ".
  static std::string reason(std::string_view what) {
    const std::size_t at = what.find("parse error");
    if (at == std::string_view::npos) return std::string(what);
    const std::size_t colon = what.find(": ", at);
    return std::string(colon == std::string_view::npos ? what : what.substr(colon + 2));
  }

  bool store(json&& value) {
    add(std::move(value));
    return true;
  }

  // Adds a value to the innermost open container (or makes it the root). Pointers to open
  // containers stay valid: an array only grows while none of its elements is open.
  json* add(json&& value) {
    if (open_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    Frame& top = open_.back();
    if (top.node->is_array()) {
      top.node->push_back(std::move(value));
      return &top.node->back();
    }
    json& slot = (*top.node)[top.key];
    slot = std::move(value);
    return &slot;
  }

  Pointer pathOfOpenNode() const {
    Pointer path;
    for (std::size_t i = 0; i + 1 < open_.size(); ++i) path = childPath(path, open_[i], true);
    return path;
  }
  Pointer pathOfNextValue() const {
    if (open_.empty()) return Pointer();
    return childPath(pathOfOpenNode(), open_.back(), false);
  }
  static Pointer childPath(const Pointer& parent, const Frame& frame, bool childIsOpen) {
    if (frame.node->is_array()) return parent / (frame.node->size() - (childIsOpen ? 1 : 0));
    return parent / frame.key;
  }

  const std::string& file_;
  const std::string& text_;
  json root_;
  std::vector<Frame> open_;
};

json parseJson(const std::string& text, const std::string& file) {
  LocatingSax sax(file, text);
  if (!json::sax_parse(text, &sax)) {
    throw InputError(file + ": malformed JSON");  // every failing path throws before this
  }
  return sax.takeResult();
}

// ---------------------------------------------------------------------------------------------
// Matrix checks

// |det| after scaling every column to max-abs 1 and then every row to unit length: 1 for an
// orthogonal matrix, 0 for a singular one. Column scaling (right-multiplying by a positive
// diagonal matrix, which keeps the rank) removes the dependence on large translations, so a camera
// far from the origin is not called singular.

bool allFinite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) return false;
    }
  }
  return true;
}

// v / |v| without overflow for huge components; v must be non-zero and finite.
glm::dvec3 safeNormalize(const glm::dvec3& v) {
  const double largest = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  return glm::normalize(v / largest);
}

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

// ---------------------------------------------------------------------------------------------
// Validation

class SceneReader {
 public:
  explicit SceneReader(const std::string& file) : file_(file) {}

  Scene read(const json& root);

  // Object readers, one per "type"; each appends to the scene.
  void readMesh(const json& object, const Pointer& at, const glm::dmat4& worldFromObject,
                std::string name, Scene& scene) const;
  void readMeshFile(const json& object, const Pointer& at, const glm::dmat4& worldFromObject,
                    std::string name, Scene& scene) const;
  void readTerrain(const json& object, const Pointer& at, const glm::dmat4& worldFromObject,
                   std::string name, Scene& scene) const;
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
  [[noreturn]] void fail(const Pointer& at, const std::string& message) const {
    throw InputError(file_, pointerText(at), message);
  }

  void expectObject(const json& value, const Pointer& at) const {
    if (!value.is_object()) fail(at, "expected an object, got " + describe(value));
  }

  // Typo protection: every key must be one of `valid`.
  void expectKnownKeys(const json& object, const Pointer& at,
                       const std::vector<std::string_view>& valid) const {
    for (const auto& [key, value] : object.items()) {
      if (std::find(valid.begin(), valid.end(), key) != valid.end()) continue;
      fail(at / key, "unknown key " + jsonString(key) + "; valid keys are " + quotedList(valid));
    }
  }

  const json& required(const json& object, const Pointer& at, std::string_view key) const {
    const auto it = object.find(std::string(key));
    if (it == object.end()) fail(at, "missing required field " + jsonString(key));
    return *it;
  }

  static const json* optional(const json& object, std::string_view key) {
    const auto it = object.find(std::string(key));
    return it == object.end() ? nullptr : &*it;
  }

  double number(const json& value, const Pointer& at) const {
    if (!value.is_number()) fail(at, "expected a number, got " + describe(value));
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail(at, "expected a finite number, got " + describe(value));
    return x;
  }

  double positiveNumber(const json& value, const Pointer& at) const {
    const double x = number(value, at);
    if (!(x > 0.0)) fail(at, "expected a positive number, got " + describe(value));
    return x;
  }

  std::string string(const json& value, const Pointer& at) const {
    if (!value.is_string()) fail(at, "expected a string, got " + describe(value));
    return value.get<std::string>();
  }

  static std::optional<std::uint64_t> unsignedInteger(const json& value) {
    if (value.is_number_unsigned()) return value.get<std::uint64_t>();
    return std::nullopt;  // nlohmann stores non-negative integers as unsigned
  }

  glm::dvec3 vector3(const json& value, const Pointer& at) const {
    if (!value.is_array() || value.size() != 3) {
      fail(at, "expected an array of 3 numbers, got " + describe(value));
    }
    return {number(value[0], at / 0), number(value[1], at / 1), number(value[2], at / 2)};
  }

  // 16 numbers, column-major: element 4 * column + row.
  glm::dmat4 matrix(const json& value, const Pointer& at) const {
    if (!value.is_array() || value.size() != 16) {
      fail(at, "expected an array of 16 numbers (column-major), got " + describe(value));
    }
    glm::dmat4 m;
    for (std::size_t i = 0; i < 16; ++i) {
      m[static_cast<int>(i / 4)][static_cast<int>(i % 4)] = number(value[i], at / i);
    }
    return m;
  }

  static json row3(const json& value) {
    return json::array({value[3], value[7], value[11], value[15]});
  }

  void expectInvertible(double scaledDet, const Pointer& at) const {
    if (!(scaledDet >= kSingularThreshold)) {
      fail(at, "expected an invertible matrix, got a singular one (scaled determinant " +
                   shortNumber(scaledDet) + ")");
    }
  }

  // viewFromWorld, worldFromObject: row 3 is exactly (0, 0, 0, 1) and the linear part invertible.
  glm::dmat4 affineMatrix(const json& value, const Pointer& at) const {
    const glm::dmat4 m = matrix(value, at);
    if (matrixRow(m, 3) != glm::dvec4(0.0, 0.0, 0.0, 1.0)) {
      fail(at,
           "expected an affine matrix (row 3 = [0,0,0,1]), got row 3 = " + describe(row3(value)));
    }
    expectInvertible(scaledDeterminant(glm::dmat3(m)), at);
    return m;
  }

  glm::dmat4 clipMatrix(const json& value, const Pointer& at) const {
    const glm::dmat4 m = matrix(value, at);
    // Row 3 is w_clip. Zero everywhere (or a non-positive constant) clips every point.
    const glm::dvec4 w = matrixRow(m, 3);
    if (w.x == 0.0 && w.y == 0.0 && w.z == 0.0 && !(w.w > 0.0)) {
      fail(at, "expected a projective matrix whose row 3 (w) is positive somewhere, got row 3 = " +
                   describe(row3(value)));
    }
    expectInvertible(scaledDeterminant(m), at);
    return m;
  }

  DepthMode depthMode(const json& value, const Pointer& at) const {
    std::optional<DepthMode> mode;
    if (value.is_string()) mode = DepthMode::parse(value.get<std::string>());
    if (!mode) {
      fail(at, "expected one of " + quotedList({"no", "zo", "zo-reversed"}) + ", got " +
                   describe(value));
    }
    return *mode;
  }

  std::string name(const json& object, const Pointer& at, std::string_view kind,
                   std::map<std::string, Pointer>& seen) const {
    const Pointer namePointer = at / "name";
    const json& value = required(object, at, "name");
    if (!value.is_string() || value.get<std::string>().empty()) {
      fail(namePointer, "expected a non-empty string, got " + describe(value));
    }
    std::string text = value.get<std::string>();
    const auto [it, inserted] = seen.emplace(text, at);
    if (!inserted) {
      fail(namePointer, "duplicate " + std::string(kind) + " name " + jsonString(text) +
                            " (first used at " + pointerText(it->second) + ")");
    }
    return text;
  }

  Viewport viewport(const json& value, const Pointer& at) const {
    if (!value.is_array() || value.size() != 2) {
      fail(at, "expected an array of 2 integers [width, height], got " + describe(value));
    }
    int size[2] = {0, 0};
    for (std::size_t i = 0; i < 2; ++i) {
      const std::optional<std::uint64_t> n = unsignedInteger(value[i]);
      if (!n || *n < 1 || *n > kMaxViewportDimension) {
        fail(at / i, "expected an integer in [1, " + std::to_string(kMaxViewportDimension) +
                         "], got " + describe(value[i]));
      }
      size[i] = static_cast<int>(*n);
    }
    return {size[0], size[1]};
  }

  std::vector<DepthMode> conventions(const json& value, const Pointer& at) const {
    if (!value.is_array()) {
      fail(at, "expected an array of convention names, got " + describe(value));
    }
    std::vector<DepthMode> modes;
    for (std::size_t i = 0; i < value.size(); ++i) {
      const DepthMode mode = depthMode(value[i], at / i);
      if (std::find(modes.begin(), modes.end(), mode) != modes.end()) {
        fail(at / i, "duplicate convention " + describe(value[i]));
      }
      modes.push_back(mode);
    }
    return modes;
  }

  Camera camera(const json& value, const Pointer& at, std::map<std::string, Pointer>& names) const;
  glm::dmat4 lookAt(const json& value, const Pointer& at) const;
  std::variant<PerspectiveProjection, OrthographicProjection, std::monostate> projection(
      const json& value, const Pointer& at) const;
  void object(const json& value, const Pointer& at, std::map<std::string, Pointer>& names,
              Scene& scene) const;
  glm::dmat4 placement(const json& object, const Pointer& at) const;
  glm::dmat4 transform(const json& value, const Pointer& at) const;
  glm::dvec3 direction(const json& value, const Pointer& at) const;
  void addPrimitive(PrimitiveKind kind, const glm::dmat4& worldFromLocal, const Pointer& at,
                    std::string name, Scene& scene) const;

  const std::string& file_;
  mutable std::uint64_t terrainTriangles_ = 0;  // generated so far (see readTerrain)
};

// The object types of the format. To add one (sphere, disk, quad, box): list its keys and reader.
struct ObjectType {
  std::string_view name;
  std::vector<std::string_view> keys;  // besides the keys every object has
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
      {"mesh", {"positions", "indices"}, &SceneReader::readMesh},
      {"meshFile", {"path", "useCameras"}, &SceneReader::readMeshFile},
      {"terrain", {"triangles", "seed"}, &SceneReader::readTerrain},
      {"sphere", {"centre", "radius"}, &SceneReader::readSphere},
      {"disk", {"centre", "normal", "radius"}, &SceneReader::readDisk},
      {"quad", {"centre", "halfEdges"}, &SceneReader::readQuad},
      {"box", {"min", "max", "centre", "halfExtents"}, &SceneReader::readBox},
      {"plane", {"point", "normal"}, &SceneReader::readPlane},
  };
  return types;
}

Scene SceneReader::read(const json& root) {
  const Pointer top;
  expectObject(root, top);
  const json& version = required(root, top, "version");
  if (!version.is_number_integer() || version != kFormatVersion) {
    fail(top / "version", "unsupported version " + describe(version) +
                              "; this clipray reads version " + std::to_string(kFormatVersion));
  }
  expectKnownKeys(root, top, {"version", "comment", "conventions", "cameras", "objects"});

  Scene scene;
  scene.version = kFormatVersion;
  if (const json* comment = optional(root, "comment")) {
    scene.comment = string(*comment, top / "comment");
  }
  if (const json* modes = optional(root, "conventions")) {
    scene.conventions = conventions(*modes, top / "conventions");
  }

  const json& cameras = required(root, top, "cameras");
  // Empty is allowed here when a meshFile object brings its cameras (checked below).
  if (!cameras.is_array()) {
    fail(top / "cameras", "expected a non-empty array of cameras, got " + describe(cameras));
  }
  std::map<std::string, Pointer> cameraNames;
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    scene.cameras.push_back(camera(cameras[i], top / "cameras" / i, cameraNames));
  }

  const json& objects = required(root, top, "objects");
  if (!objects.is_array()) fail(top / "objects", "expected an array, got " + describe(objects));
  std::map<std::string, Pointer> objectNames;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    object(objects[i], top / "objects" / i, objectNames, scene);
  }
  if (scene.cameras.empty()) {
    fail(top / "cameras", "expected a non-empty array of cameras, got " + describe(cameras) +
                              " (and no meshFile object with \"useCameras\": true)");
  }
  if (scene.triangleCount() + scene.primitives.size() > kMaxTriangles) {
    fail(top / "objects", "too many primitives for 32-bit primitive ids: " +
                              std::to_string(scene.triangleCount() + scene.primitives.size()));
  }
  return scene;
}

Camera SceneReader::camera(const json& value, const Pointer& at,
                           std::map<std::string, Pointer>& names) const {
  expectObject(value, at);
  expectKnownKeys(
      value, at,
      {"name", "viewport", "clipFromWorld", "view", "viewFromWorld", "projection", "builtFor"});
  Camera camera;
  camera.name = name(value, at, "camera", names);
  camera.viewport = viewport(required(value, at, "viewport"), at / "viewport");

  const json* raw = optional(value, "clipFromWorld");
  const json* view = optional(value, "view");
  const json* viewFromWorld = optional(value, "viewFromWorld");
  const json* projectionValue = optional(value, "projection");
  const json* builtFor = optional(value, "builtFor");

  if (raw) {
    for (std::string_view other : {"view", "viewFromWorld", "projection", "builtFor"}) {
      if (optional(value, other)) {
        fail(at, "expected either \"clipFromWorld\" or " + jsonString(other) + ", got both");
      }
    }
    camera.rawClipFromWorld = clipMatrix(*raw, at / "clipFromWorld");
    camera.projection = std::monostate{};
    return camera;
  }

  if (!view && !viewFromWorld && !projectionValue) {
    fail(at,
         "missing required field \"clipFromWorld\", or \"projection\" with \"view\" or "
         "\"viewFromWorld\"");
  }
  if (view && viewFromWorld) fail(at, "expected either \"view\" or \"viewFromWorld\", got both");
  if (!view && !viewFromWorld) fail(at, "missing required field \"view\" or \"viewFromWorld\"");
  camera.viewFromWorld =
      view ? lookAt(*view, at / "view") : affineMatrix(*viewFromWorld, at / "viewFromWorld");
  if (!projectionValue) fail(at, "missing required field \"projection\"");
  camera.projection = projection(*projectionValue, at / "projection");
  if (builtFor) camera.builtFor = depthMode(*builtFor, at / "builtFor");

  // Extreme but individually valid numbers can still overflow the product.
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne, kZeroToOneReversed}) {
    if (!allFinite(camera.clipFromWorld(mode, camera.viewport))) {
      fail(at, "the camera's clipFromWorld overflows double when drawn under " +
                   jsonString(mode.name()));
    }
  }
  return camera;
}

glm::dmat4 SceneReader::lookAt(const json& value, const Pointer& at) const {
  expectObject(value, at);
  expectKnownKeys(value, at, {"eye", "target", "up"});
  const glm::dvec3 eye = vector3(required(value, at, "eye"), at / "eye");
  const glm::dvec3 target = vector3(required(value, at, "target"), at / "target");
  const glm::dvec3 up = vector3(required(value, at, "up"), at / "up");
  if (target == eye) {
    fail(at / "target", "expected a point different from \"eye\" (" + describe(value["eye"]) +
                            "), got " + describe(value["target"]));
  }
  if (up == glm::dvec3(0.0))
    fail(at / "up", "expected a non-zero direction, got " + describe(value["up"]));
  const glm::dvec3 forward = target - eye;
  if (std::isfinite(forward.x) && std::isfinite(forward.y) && std::isfinite(forward.z) &&
      glm::length(glm::cross(safeNormalize(forward), safeNormalize(up))) < kParallelThreshold) {
    fail(at / "up", "expected a direction not parallel to the view direction (target - eye), got " +
                        describe(value["up"]));
  }
  return viewFromWorldLookAt(eye, target, up);
}

std::variant<PerspectiveProjection, OrthographicProjection, std::monostate> SceneReader::projection(
    const json& value, const Pointer& at) const {
  expectObject(value, at);
  const json& type = required(value, at, "type");
  const auto bigger = [&](const json& object, std::string_view lowKey, std::string_view highKey,
                          double low) {
    const json& high = required(object, at, highKey);
    const double x = number(high, at / std::string(highKey));
    if (!(x > low)) {
      fail(at / std::string(highKey), "expected a number greater than " + jsonString(lowKey) +
                                          " (" + describe(object[std::string(lowKey)]) + "), got " +
                                          describe(high));
    }
    return x;
  };
  const auto different = [&](const json& object, std::string_view firstKey,
                             std::string_view secondKey) {
    const double first = number(required(object, at, firstKey), at / std::string(firstKey));
    const json& second = required(object, at, secondKey);
    if (number(second, at / std::string(secondKey)) == first) {
      fail(at / std::string(secondKey), "expected a number different from " + jsonString(firstKey) +
                                            " (" + describe(object[std::string(firstKey)]) +
                                            "), got " + describe(second));
    }
    return std::pair{first, second.get<double>()};
  };

  if (type == "perspective") {
    expectKnownKeys(value, at, {"type", "fovYDegrees", "aspect", "near", "far"});
    PerspectiveProjection p;
    const json& fov = required(value, at, "fovYDegrees");
    p.fovYDegrees = number(fov, at / "fovYDegrees");
    if (!(p.fovYDegrees > 0.0 && p.fovYDegrees < 180.0)) {
      fail(at / "fovYDegrees", "expected a number in (0, 180), got " + describe(fov));
    }
    if (const json* aspect = optional(value, "aspect")) {
      p.aspect = positiveNumber(*aspect, at / "aspect");
    }
    p.nearDistance = positiveNumber(required(value, at, "near"), at / "near");
    if (value.contains("far")) p.farDistance = bigger(value, "near", "far", p.nearDistance);
    return p;
  }
  if (type == "orthographic") {
    expectKnownKeys(value, at, {"type", "left", "right", "bottom", "top", "near", "far"});
    OrthographicProjection o;
    std::tie(o.left, o.right) = different(value, "left", "right");
    std::tie(o.bottom, o.top) = different(value, "bottom", "top");
    o.nearDistance = number(required(value, at, "near"), at / "near");
    o.farDistance = bigger(value, "near", "far", o.nearDistance);
    return o;
  }
  fail(at / "type", "expected one of " + quotedList({"perspective", "orthographic"}) + ", got " +
                        describe(type));
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
  expectKnownKeys(value, at, keys);
  std::string objectName = name(value, at, "object", names);
  (this->*kind->read)(value, at, placement(value, at), std::move(objectName), scene);
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

// The largest terrain the format builds (32-bit ids leave room; this keeps memory sane).
constexpr std::uint64_t kMaxTerrainTriangles = 20'000'000;

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

glm::dvec3 SceneReader::direction(const json& value, const Pointer& at) const {
  const glm::dvec3 v = vector3(value, at);
  if (v == glm::dvec3(0.0)) fail(at, "expected a non-zero direction, got " + describe(value));
  return safeNormalize(v);
}

// A right-handed orthonormal frame whose z axis is `normal` (Duff et al. 2017, branchless).
glm::dmat4 frameAround(const glm::dvec3& normal) {
  const double sign = std::copysign(1.0, normal.z);
  const double a = -1.0 / (sign + normal.z);
  const double b = normal.x * normal.y * a;
  glm::dmat4 m(1.0);
  m[0] = glm::dvec4(1.0 + sign * normal.x * normal.x * a, sign * b, -sign * normal.x, 0.0);
  m[1] = glm::dvec4(b, sign + normal.y * normal.y * a, -normal.y, 0.0);
  m[2] = glm::dvec4(normal, 0.0);
  return m;
}

glm::dmat4 translationScale(const glm::dvec3& translation, const glm::dvec3& scale) {
  glm::dmat4 m(1.0);
  m[0][0] = scale.x;
  m[1][1] = scale.y;
  m[2][2] = scale.z;
  m[3] = glm::dvec4(translation, 1.0);
  return m;
}

void SceneReader::addPrimitive(PrimitiveKind kind, const glm::dmat4& worldFromLocal,
                               const Pointer& at, std::string primitiveName, Scene& scene) const {
  // Both sides intersect in the primitive's local frame, so the map must be invertible and its
  // inverse finite: the same scaled-determinant test as for matrices given in the file.
  const double scaledDet = scaledDeterminant(glm::dmat3(worldFromLocal));
  if (!allFinite(worldFromLocal) || !(scaledDet >= kSingularThreshold)) {
    fail(at, std::string("the ") + primitiveKindName(kind) +
                 " has a non-invertible placement (scaled determinant " + shortNumber(scaledDet) +
                 "); check \"transform\" / \"worldFromObject\" and the shape's sizes");
  }
  AnalyticPrimitive primitive;
  primitive.name = std::move(primitiveName);
  primitive.kind = kind;
  primitive.worldFromLocal = worldFromLocal;
  primitive.localFromWorld = glm::inverse(worldFromLocal);
  if (!allFinite(primitive.localFromWorld)) {
    fail(at, std::string("the ") + primitiveKindName(kind) +
                 " has a placement whose inverse overflows double");
  }
  scene.primitives.push_back(std::move(primitive));
}

void SceneReader::readSphere(const json& value, const Pointer& at,
                             const glm::dmat4& worldFromObject, std::string sphereName,
                             Scene& scene) const {
  const glm::dvec3 centre = vector3(required(value, at, "centre"), at / "centre");
  const double radius = positiveNumber(required(value, at, "radius"), at / "radius");
  addPrimitive(PrimitiveKind::Sphere,
               worldFromObject * translationScale(centre, glm::dvec3(radius)), at,
               std::move(sphereName), scene);
}

void SceneReader::readDisk(const json& value, const Pointer& at, const glm::dmat4& worldFromObject,
                           std::string diskName, Scene& scene) const {
  const glm::dvec3 centre = vector3(required(value, at, "centre"), at / "centre");
  const glm::dvec3 normal = direction(required(value, at, "normal"), at / "normal");
  const double radius = positiveNumber(required(value, at, "radius"), at / "radius");
  addPrimitive(PrimitiveKind::Disk,
               worldFromObject * translationScale(centre, glm::dvec3(1.0)) * frameAround(normal) *
                   translationScale(glm::dvec3(0.0), glm::dvec3(radius)),
               at, std::move(diskName), scene);
}

void SceneReader::readQuad(const json& value, const Pointer& at, const glm::dmat4& worldFromObject,
                           std::string quadName, Scene& scene) const {
  const glm::dvec3 centre = vector3(required(value, at, "centre"), at / "centre");
  const Pointer eAt = at / "halfEdges";
  const json& edges = required(value, at, "halfEdges");
  if (!edges.is_array() || edges.size() != 2) {
    fail(eAt,
         "expected an array of 2 vectors [[ux, uy, uz], [vx, vy, vz]], got " + describe(edges));
  }
  const glm::dvec3 u = vector3(edges[0], eAt / 0), v = vector3(edges[1], eAt / 1);
  // Unit vectors for the test, so that huge (finite) edges cannot overflow it.
  const bool nonZero = u != glm::dvec3(0.0) && v != glm::dvec3(0.0);
  const glm::dvec3 normal =
      nonZero ? glm::cross(safeNormalize(u), safeNormalize(v)) : glm::dvec3(0.0);
  const double scale = std::sqrt(glm::length(u)) * std::sqrt(glm::length(v));
  if (!(glm::length(normal) > kParallelThreshold)) {
    fail(eAt, "expected two non-zero, non-parallel half edges, got " + describe(edges));
  }
  // Local z only has to make the map invertible (the quad is z = 0): the unit normal scaled to
  // the quad's size keeps the map well conditioned.
  glm::dmat4 local(1.0);
  local[0] = glm::dvec4(u, 0.0);
  local[1] = glm::dvec4(v, 0.0);
  local[2] = glm::dvec4(safeNormalize(normal) * scale, 0.0);
  local[3] = glm::dvec4(centre, 1.0);
  addPrimitive(PrimitiveKind::Quad, worldFromObject * local, at, std::move(quadName), scene);
}

void SceneReader::readBox(const json& value, const Pointer& at, const glm::dmat4& worldFromObject,
                          std::string boxName, Scene& scene) const {
  const json* low = optional(value, "min");
  const json* high = optional(value, "max");
  const json* centreValue = optional(value, "centre");
  const json* extentValue = optional(value, "halfExtents");
  glm::dvec3 centre, halfExtents;
  if ((low || high) && (centreValue || extentValue)) {
    fail(at, "expected either \"min\" and \"max\" or \"centre\" and \"halfExtents\", got both");
  }
  if (low || high) {
    const glm::dvec3 lower = vector3(required(value, at, "min"), at / "min");
    const glm::dvec3 upper = vector3(required(value, at, "max"), at / "max");
    for (int i = 0; i < 3; ++i) {
      if (!(upper[i] > lower[i])) {
        fail(at / "max" / static_cast<std::size_t>(i),
             "expected a number greater than \"min\"[" + std::to_string(i) + "] (" +
                 describe(value["min"][static_cast<std::size_t>(i)]) + "), got " +
                 describe(value["max"][static_cast<std::size_t>(i)]));
      }
    }
    centre = 0.5 * lower + 0.5 * upper;
    halfExtents = 0.5 * upper - 0.5 * lower;
  } else {
    if (!centreValue && !extentValue) {
      fail(at, "missing required fields \"min\" and \"max\" (or \"centre\" and \"halfExtents\")");
    }
    centre = vector3(required(value, at, "centre"), at / "centre");
    const json& extents = required(value, at, "halfExtents");
    halfExtents = vector3(extents, at / "halfExtents");
    for (std::size_t i = 0; i < 3; ++i) {
      if (!(halfExtents[static_cast<int>(i)] > 0.0)) {
        fail(at / "halfExtents" / i, "expected a positive number, got " + describe(extents[i]));
      }
    }
  }
  addPrimitive(PrimitiveKind::Box, worldFromObject * translationScale(centre, halfExtents), at,
               std::move(boxName), scene);
}

void SceneReader::readPlane(const json& value, const Pointer& at, const glm::dmat4& worldFromObject,
                            std::string planeName, Scene& scene) const {
  const glm::dvec3 point = vector3(required(value, at, "point"), at / "point");
  const glm::dvec3 normal = direction(required(value, at, "normal"), at / "normal");
  addPrimitive(PrimitiveKind::Plane,
               worldFromObject * translationScale(point, glm::dvec3(1.0)) * frameAround(normal), at,
               std::move(planeName), scene);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Public interface

glm::dmat4 Camera::clipFromWorld(DepthMode drawnUnder, Viewport drawnAt) const {
  if (rawClipFromWorld) return *rawClipFromWorld;
  const DepthMode mode = builtFor.value_or(drawnUnder);
  if (const auto* p = std::get_if<PerspectiveProjection>(&projection)) {
    const double aspect = p->aspect.value_or(static_cast<double>(drawnAt.width) /
                                             static_cast<double>(drawnAt.height));
    return perspectiveClipFromView(glm::radians(p->fovYDegrees), aspect, p->nearDistance,
                                   p->farDistance, mode) *
           viewFromWorld;
  }
  if (const auto* o = std::get_if<OrthographicProjection>(&projection)) {
    return orthographicClipFromView(o->left, o->right, o->bottom, o->top, o->nearDistance,
                                    o->farDistance, mode) *
           viewFromWorld;
  }
  throw std::logic_error("camera \"" + name + "\" has neither a projection nor a clipFromWorld");
}

std::size_t Scene::triangleCount() const {
  std::size_t count = 0;
  for (const MeshObject& object : objects) count += object.triangles.size();
  return count;
}

const char* primitiveKindName(PrimitiveKind kind) {
  switch (kind) {
    case PrimitiveKind::Sphere:
      return "sphere";
    case PrimitiveKind::Disk:
      return "disk";
    case PrimitiveKind::Quad:
      return "quad";
    case PrimitiveKind::Box:
      return "box";
    case PrimitiveKind::Plane:
      return "plane";
  }
  return "?";
}

PrimitiveIdTable::PrimitiveIdTable(const Scene& scene) {
  std::uint64_t next = 1;  // 0 is background
  firstIdOfObject.reserve(scene.objects.size());
  for (const MeshObject& object : scene.objects) {
    firstIdOfObject.push_back(static_cast<std::uint32_t>(next));
    next += object.triangles.size();
  }
  if (next - 1 + scene.primitives.size() > kMaxTriangles) {
    throw std::length_error("scene has too many primitives for 32-bit primitive ids");
  }
  firstAnalyticId = static_cast<std::uint32_t>(next);
  analyticCount = static_cast<std::uint32_t>(scene.primitives.size());
}

PrimitiveIdTable::Decoded PrimitiveIdTable::decode(std::uint32_t id) const {
  if (id == 0) return {};
  if (id >= firstAnalyticId) {
    if (id - firstAnalyticId >= analyticCount) return {};
    return {-1, 0, static_cast<int>(id - firstAnalyticId)};
  }
  // The last object whose first id is <= id (objects without triangles share the next one's id).
  const auto after = std::upper_bound(firstIdOfObject.begin(), firstIdOfObject.end(), id);
  if (after == firstIdOfObject.begin()) return {};
  const auto object = std::prev(after);
  return {static_cast<int>(object - firstIdOfObject.begin()), id - *object, -1};
}

Scene parseScene(const std::string& jsonText, const std::string& path) {
  const json root = parseJson(jsonText, path);
  Scene scene = SceneReader(path).read(root);
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
    if (contents.cameras.empty()) {
      throw InputError(path +
                       ": the file has no cameras; give it one (glTF) or reference it from a "
                       "scene file with cameras (\"type\": \"meshFile\")");
    }
    Scene scene;
    scene.path = path;
    scene.name = std::filesystem::path(path).stem().string();
    scene.comment = "mesh file " + path;
    scene.cameras = std::move(contents.cameras);
    scene.objects = std::move(contents.objects);
    scene.warnings = std::move(contents.warnings);
    return scene;
  }
  std::ifstream in(path, std::ios::binary);
  std::error_code error;
  if (!in || std::filesystem::is_directory(path, error))
    throw InputError(path + ": cannot open file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path + ": cannot read file");
  return parseScene(text.str(), path);
}

}  // namespace clipray
