#pragma once
// Shared by the mesh file readers (internal to clipray_core): number formatting for messages,
// transform checks and the final validation every object goes through. Transforms are
// column-major, p' = M * p (worldFromObject, worldFromFile).

#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/scene/MeshFiles.hpp"

namespace clipray::meshfiles {

// Primitive ids are 32-bit and 0 is background, so no file may hold more triangles than this.
inline constexpr std::uint64_t kMaxTriangles = 0xFFFFFFFFull - 1u;
// tinygltf takes sizes as unsigned int; the other readers share the limit.
inline constexpr std::uint64_t kMaxFileBytes = 0xFFFFFFFFull;

// Shortest text that reads back as the same double; "nan", "inf" and "-inf" spelled out.
std::string formatNumber(double value);
// "(1, 2, 3)"
std::string formatVector(const glm::dvec3& value);

// Text quoted for a message: control and non-ASCII bytes as \xNN, cut to 80 characters.
std::string quotedText(std::string_view text);
// Words of a line separated by spaces and tabs.
std::vector<std::string_view> splitWords(std::string_view line);

// Reads a whole word as a double, locale-independent; a leading '+' is accepted.
enum class NumberParse { Ok, NotANumber, Overflow };
NumberParse parseDouble(std::string_view word, double& value);

// Throws InputError(path + ": " + element + ": " + message).
[[noreturn]] void fail(const std::string& path, const std::string& element,
                       const std::string& message);

// Empty when the affine matrix is usable as an object or node transform; otherwise why not
// (non-finite entry, row 3 not 0 0 0 1, or a singular 3x3 part).
std::string whyNotInvertibleAffine(const glm::dmat4& matrix);

// Maps the object's positions through worldFromObject, checks that every index is in range and
// every world position finite, and records degenerate (zero-area) triangles as one warning.
// `element` names the object in messages ("mesh \"Cube\" primitive 0", "object \"body\"").
void addObject(MeshFileContents& contents, const std::string& path, const std::string& element,
               MeshObject object, const glm::dmat4& worldFromObject);

// Hands out names that are unique within one file: "<base>", then "<base>#2", "<base>#3", ...
class UniqueNames {
 public:
  std::string claim(const std::string& base);

 private:
  std::unordered_set<std::string> taken_;
  std::unordered_map<std::string, int> nextSuffix_;  // keeps claiming a repeated base linear
};

MeshFileContents parseGltf(std::string_view bytes, const std::string& path, bool binary,
                           const glm::dmat4& worldFromFile);
MeshFileContents parseObj(std::string_view bytes, const std::string& path,
                          const glm::dmat4& worldFromFile);
MeshFileContents parsePly(std::string_view bytes, const std::string& path,
                          const glm::dmat4& worldFromFile);

}  // namespace clipray::meshfiles
