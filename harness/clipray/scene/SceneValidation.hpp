#pragma once
// Internal to scene/: the validation helpers of the scene loader. Each reads one value of the
// expected shape or throws InputError with the file, the JSON pointer and the offending value.
// Matrices are read column-major (16 numbers, element 4 * column + row).

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/io/LocatedJson.hpp"

namespace clipray::detail {

// A matrix is singular when its scaled determinant (scaledDeterminant, Projections.hpp) is below
// this: that measure is 1 for an orthogonal matrix and does not shrink with large translations.
inline constexpr double kSingularThreshold = 1e-12;
// Directions are parallel when |sin(angle)| is below this.
inline constexpr double kParallelThreshold = 1e-9;

// Whether every element of m is finite.
bool allFinite(const glm::dmat4& m);
// v / |v| without overflow for huge components; v must be non-zero and finite.
glm::dvec3 safeNormalize(const glm::dvec3& v);

class SceneValidator {
 public:
  explicit SceneValidator(const std::string& file) : file_(file) {}

 protected:
  // Throws InputError naming the file, the pointer and the message.
  [[noreturn]] void fail(const Pointer& at, const std::string& message) const;
  void expectObject(const json& value, const Pointer& at) const;
  // Typo protection: every key must be one of `valid`.
  void expectKnownKeys(const json& object, const Pointer& at,
                       const std::vector<std::string_view>& valid) const;
  const json& required(const json& object, const Pointer& at, std::string_view key) const;
  // nullptr where the key is absent.
  static const json* optional(const json& object, std::string_view key);

  // Values of one JSON type, failing with what was found instead.
  double number(const json& value, const Pointer& at) const;  // finite
  double positiveNumber(const json& value, const Pointer& at) const;
  std::string string(const json& value, const Pointer& at) const;
  static std::optional<std::uint64_t> unsignedInteger(const json& value);  // nullopt: not one
  glm::dvec3 vector3(const json& value, const Pointer& at) const;
  // [n, f] of glDepthRange: each in [0, 1] (GL clamps them there), n != f.
  glm::dvec2 depthRange(const json& value, const Pointer& at) const;
  // 16 numbers, column-major: element 4 * column + row.
  glm::dmat4 matrix(const json& value, const Pointer& at) const;
  // Row 3 of a 16-number matrix array, for messages.
  static json row3(const json& value);
  void expectInvertible(double scaledDet, const Pointer& at) const;
  // viewFromWorld, worldFromObject: row 3 is exactly (0, 0, 0, 1) and the linear part invertible.
  glm::dmat4 affineMatrix(const json& value, const Pointer& at) const;
  // clipFromWorld: invertible, and w_clip (row 3) positive somewhere.
  glm::dmat4 clipMatrix(const json& value, const Pointer& at) const;
  DepthMode depthMode(const json& value, const Pointer& at) const;  // "no", "zo", "zo-reversed"
  // A non-empty name not used before by another of its kind (seen maps names to where).
  std::string name(const json& object, const Pointer& at, std::string_view kind,
                   std::map<std::string, Pointer>& seen) const;
  Viewport viewport(const json& value, const Pointer& at) const;  // [width, height]
  std::vector<DepthMode> conventions(const json& value, const Pointer& at) const;

  const std::string& file_;
};

}  // namespace clipray::detail
