// The validation helpers of the scene loader: one JSON value of the expected shape each, or an
// InputError that names the file, the JSON pointer and what was found.

#include "clipray/scene/SceneValidation.hpp"

#include <algorithm>
#include <cmath>

#include "clipray/InputError.hpp"
#include "clipray/math/Projections.hpp"

namespace clipray::detail {

namespace {

constexpr std::uint64_t kMaxViewportDimension = 16384;

}  // namespace

bool allFinite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) return false;
    }
  }
  return true;
}

glm::dvec3 safeNormalize(const glm::dvec3& v) {
  const double largest = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  return glm::normalize(v / largest);
}

void SceneValidator::fail(const Pointer& at, const std::string& message) const {
  throw InputError(file_, pointerText(at), message);
}

void SceneValidator::expectObject(const json& value, const Pointer& at) const {
  if (!value.is_object()) fail(at, "expected an object, got " + describe(value));
}

void SceneValidator::expectKnownKeys(const json& object, const Pointer& at,
                                     const std::vector<std::string_view>& valid) const {
  for (const auto& [key, value] : object.items()) {
    if (std::find(valid.begin(), valid.end(), key) != valid.end()) continue;
    fail(at / key, "unknown key " + jsonString(key) + "; valid keys are " + quotedList(valid));
  }
}

const json& SceneValidator::required(const json& object, const Pointer& at,
                                     std::string_view key) const {
  const auto it = object.find(std::string(key));
  if (it == object.end()) fail(at, "missing required field " + jsonString(key));
  return *it;
}

const json* SceneValidator::optional(const json& object, std::string_view key) {
  const auto it = object.find(std::string(key));
  return it == object.end() ? nullptr : &*it;
}

double SceneValidator::number(const json& value, const Pointer& at) const {
  if (!value.is_number()) fail(at, "expected a number, got " + describe(value));
  const double x = value.get<double>();
  if (!std::isfinite(x)) fail(at, "expected a finite number, got " + describe(value));
  return x;
}

glm::dvec2 SceneValidator::depthRange(const json& value, const Pointer& at) const {
  if (!value.is_array() || value.size() != 2) {
    fail(at, "expected [near, far] of glDepthRange, got " + describe(value));
  }
  glm::dvec2 range;
  for (int k = 0; k < 2; ++k) {
    range[k] = number(value[static_cast<std::size_t>(k)], at / k);
    // GL clamps both to [0, 1] (without NV_depth_buffer_float's unclamped glDepthRangedNV).
    if (!(range[k] >= 0.0 && range[k] <= 1.0)) {
      fail(at / k, "expected a number in [0, 1] (GL clamps glDepthRange to it), got " +
                       describe(value[static_cast<std::size_t>(k)]));
    }
  }
  if (range.x == range.y) {
    fail(at, "near and far are both " + describe(value[0]) + "; every depth would be equal");
  }
  return range;
}

double SceneValidator::positiveNumber(const json& value, const Pointer& at) const {
  const double x = number(value, at);
  if (!(x > 0.0)) fail(at, "expected a positive number, got " + describe(value));
  return x;
}

std::string SceneValidator::string(const json& value, const Pointer& at) const {
  if (!value.is_string()) fail(at, "expected a string, got " + describe(value));
  return value.get<std::string>();
}

std::optional<std::uint64_t> SceneValidator::unsignedInteger(const json& value) {
  // The parser stores non-negative integers as unsigned; a document built in code (SceneBuilder)
  // may hold them signed: the same value either way.
  if (value.is_number_unsigned()) return value.get<std::uint64_t>();
  if (value.is_number_integer() && value.get<std::int64_t>() >= 0) {
    return static_cast<std::uint64_t>(value.get<std::int64_t>());
  }
  return std::nullopt;
}

glm::dvec3 SceneValidator::vector3(const json& value, const Pointer& at) const {
  if (!value.is_array() || value.size() != 3) {
    fail(at, "expected an array of 3 numbers, got " + describe(value));
  }
  return {number(value[0], at / 0), number(value[1], at / 1), number(value[2], at / 2)};
}

// 16 numbers, column-major: element 4 * column + row.
glm::dmat4 SceneValidator::matrix(const json& value, const Pointer& at) const {
  if (!value.is_array() || value.size() != 16) {
    fail(at, "expected an array of 16 numbers (column-major), got " + describe(value));
  }
  glm::dmat4 m;
  for (std::size_t i = 0; i < 16; ++i) {
    m[static_cast<int>(i / 4)][static_cast<int>(i % 4)] = number(value[i], at / i);
  }
  return m;
}

json SceneValidator::row3(const json& value) {
  return json::array({value[3], value[7], value[11], value[15]});
}

void SceneValidator::expectInvertible(double scaledDet, const Pointer& at) const {
  if (!(scaledDet >= kSingularThreshold)) {
    fail(at, "expected an invertible matrix, got a singular one (scaled determinant " +
                 shortNumber(scaledDet) + ")");
  }
}

// viewFromWorld, worldFromObject: row 3 is exactly (0, 0, 0, 1) and the linear part invertible.
glm::dmat4 SceneValidator::affineMatrix(const json& value, const Pointer& at) const {
  const glm::dmat4 m = matrix(value, at);
  if (matrixRow(m, 3) != glm::dvec4(0.0, 0.0, 0.0, 1.0)) {
    fail(at, "expected an affine matrix (row 3 = [0,0,0,1]), got row 3 = " + describe(row3(value)));
  }
  expectInvertible(scaledDeterminant(glm::dmat3(m)), at);
  return m;
}

glm::dmat4 SceneValidator::clipMatrix(const json& value, const Pointer& at) const {
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

DepthMode SceneValidator::depthMode(const json& value, const Pointer& at) const {
  std::optional<DepthMode> mode;
  if (value.is_string()) mode = DepthMode::parse(value.get<std::string>());
  if (!mode) {
    fail(at, "expected one of " +
                 quotedList({"no", "zo", "zo-reversed", "no-upper-left", "zo-upper-left",
                             "zo-reversed-upper-left"}) +
                 ", got " + describe(value));
  }
  return *mode;
}

std::string SceneValidator::name(const json& object, const Pointer& at, std::string_view kind,
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

Viewport SceneValidator::viewport(const json& value, const Pointer& at) const {
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

std::vector<DepthMode> SceneValidator::conventions(const json& value, const Pointer& at) const {
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

}  // namespace clipray::detail
