// Mesh files: picking the reader by extension, reading the bytes, and the checks every reader
// shares (transforms, index ranges, finite positions, degenerate triangles).

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "clipray/InputError.hpp"
#include "clipray/io/InputFile.hpp"
#include "clipray/scene/MeshFiles.hpp"
#include "clipray/scene/loaders/MeshFileCommon.hpp"

namespace clipray {

namespace meshfiles {

namespace {

// The 3x3 part is singular when |det| / (|c0| |c1| |c2|) is below this: the volume spanned by the
// columns relative to a cube with the same edge lengths, so uniform scale does not matter.
constexpr double kSingularThreshold = 1e-12;

std::string lowerCaseExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) {
    return static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  });
  return extension;
}

}  // namespace

std::string formatNumber(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

std::string formatVector(const glm::dvec3& value) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) about "(" + std::string&&.
  std::string text = "(";
  text.append(formatNumber(value.x)).append(", ").append(formatNumber(value.y));
  text.append(", ").append(formatNumber(value.z)).append(")");
  return text;
}

std::string quotedText(std::string_view text) {
  constexpr std::size_t kMaxQuoted = 80;
  std::string result;
  for (char c : text.substr(0, kMaxQuoted)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte >= 0x7F || c == '"' || c == '\\') {
      static constexpr char kHex[] = "0123456789abcdef";
      result += "\\x";
      result += kHex[byte >> 4];
      result += kHex[byte & 15];
    } else {
      result += c;
    }
  }
  if (text.size() > kMaxQuoted) result += "...";
  return "\"" + result + "\"";
}

std::vector<std::string_view> splitWords(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t position = 0;
  while (position < line.size()) {
    while (position < line.size() && (line[position] == ' ' || line[position] == '\t')) {
      ++position;
    }
    const std::size_t start = position;
    while (position < line.size() && line[position] != ' ' && line[position] != '\t') ++position;
    if (position > start) words.push_back(line.substr(start, position - start));
  }
  return words;
}

NumberParse parseDouble(std::string_view word, double& value) {
  // from_chars rejects a leading '+'; strip one, but not a sign after it ("+-1").
  if (word.size() > 1 && word[0] == '+' && word[1] != '-' && word[1] != '+') word.remove_prefix(1);
  if (word.empty()) return NumberParse::NotANumber;
  const auto result = std::from_chars(word.data(), word.data() + word.size(), value);
  if (result.ptr != word.data() + word.size()) return NumberParse::NotANumber;
  if (result.ec == std::errc::result_out_of_range) {
    // from_chars leaves value alone when out of range; strtod tells overflow (HUGE_VAL) from
    // underflow (a denormal or zero, harmless). The word is a valid number, so strtod reads it
    // the same way.
    value = std::strtod(std::string(word).c_str(), nullptr);
    return std::isinf(value) ? NumberParse::Overflow : NumberParse::Ok;
  }
  return result.ec == std::errc() ? NumberParse::Ok : NumberParse::NotANumber;
}

void fail(const std::string& path, const std::string& element, const std::string& message) {
  throw InputError(path, element, message);
}

std::string whyNotInvertibleAffine(const glm::dmat4& matrix) {
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) {
      if (!std::isfinite(matrix[column][row])) {
        return "element " + std::to_string(4 * column + row) + " is not finite, got " +
               formatNumber(matrix[column][row]);
      }
    }
  }
  if (matrix[0][3] != 0.0 || matrix[1][3] != 0.0 || matrix[2][3] != 0.0 || matrix[3][3] != 1.0) {
    return "row 3 must be 0, 0, 0, 1 (an affine transform), got " + formatNumber(matrix[0][3]) +
           ", " + formatNumber(matrix[1][3]) + ", " + formatNumber(matrix[2][3]) + ", " +
           formatNumber(matrix[3][3]);
  }
  const glm::dmat3 linear(matrix);
  const double lengths = glm::length(linear[0]) * glm::length(linear[1]) * glm::length(linear[2]);
  const double determinant = glm::determinant(linear);
  if (!(lengths > 0.0) || !std::isfinite(lengths) ||
      !(std::abs(determinant) / lengths >= kSingularThreshold)) {
    return "the transform is not invertible (its 3x3 part has determinant " +
           formatNumber(determinant) + ")";
  }
  return {};
}

std::string UniqueNames::claim(const std::string& base) {
  if (taken_.insert(base).second) return base;
  int& suffix = nextSuffix_.try_emplace(base, 2).first->second;
  std::string candidate;
  do {
    candidate = base + "#" + std::to_string(suffix++);
  } while (!taken_.insert(candidate).second);
  return candidate;
}

void addObject(MeshFileContents& contents, const std::string& path, const std::string& element,
               MeshObject object, const glm::dmat4& worldFromObject) {
  const std::size_t vertexCount = object.worldPositions.size();
  for (std::size_t t = 0; t < object.triangles.size(); ++t) {
    for (int corner = 0; corner < 3; ++corner) {
      if (object.triangles[t][corner] >= vertexCount) {
        fail(path, element,
             "triangle " + std::to_string(t) + " uses vertex " +
                 std::to_string(object.triangles[t][corner]) + ", out of range for " +
                 std::to_string(vertexCount) + " vertices");
      }
    }
  }
  for (std::size_t v = 0; v < vertexCount; ++v) {
    const glm::dvec3 local = object.worldPositions[v];
    const glm::dvec3 world = glm::dvec3(worldFromObject * glm::dvec4(local, 1.0));
    if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z)) {
      fail(path, element,
           "vertex " + std::to_string(v) + " is not finite in world space (file position " +
               formatVector(local) + "), got " + formatVector(world));
    }
    object.worldPositions[v] = world;
  }
  std::size_t degenerateCount = 0;
  std::size_t firstDegenerate = 0;
  for (std::size_t t = 0; t < object.triangles.size(); ++t) {
    const glm::u32vec3 triangle = object.triangles[t];
    const glm::dvec3 a = object.worldPositions[triangle.x];
    const glm::dvec3 normal =
        glm::cross(object.worldPositions[triangle.y] - a, object.worldPositions[triangle.z] - a);
    if (normal == glm::dvec3(0.0)) {
      if (degenerateCount == 0) firstDegenerate = t;
      ++degenerateCount;
    }
  }
  if (degenerateCount > 0) {
    contents.warnings.push_back(path + ": " + element + ": " + std::to_string(degenerateCount) +
                                " degenerate triangle" + (degenerateCount == 1 ? "" : "s") +
                                " kept (first: triangle " + std::to_string(firstDegenerate) + ")");
  }
  contents.objects.push_back(std::move(object));
}

}  // namespace meshfiles

MeshFileContents parseMeshFile(std::string_view bytes, const std::string& path,
                               const glm::dmat4& worldFromFile) {
  const std::string extension = meshfiles::lowerCaseExtension(path);
  const std::string why = meshfiles::whyNotInvertibleAffine(worldFromFile);
  if (!why.empty()) throw InputError(path + ": worldFromFile: " + why);
  MeshFileContents contents;
  if (extension == ".gltf") {
    contents = meshfiles::parseGltf(bytes, path, false, worldFromFile);
  } else if (extension == ".glb") {
    contents = meshfiles::parseGltf(bytes, path, true, worldFromFile);
  } else if (extension == ".obj") {
    contents = meshfiles::parseObj(bytes, path, worldFromFile);
  } else if (extension == ".ply") {
    contents = meshfiles::parsePly(bytes, path, worldFromFile);
  } else {
    throw InputError(path + ": unsupported mesh file extension \"" + extension +
                     "\"; clipray reads .gltf, .glb, .obj and .ply");
  }
  std::uint64_t triangleCount = 0;
  for (const MeshObject& object : contents.objects) triangleCount += object.triangles.size();
  if (triangleCount == 0) throw InputError(path + ": the file holds no triangles");
  if (triangleCount > meshfiles::kMaxTriangles) {
    throw InputError(path + ": " + std::to_string(triangleCount) +
                     " triangles exceed the 32-bit primitive id range (at most " +
                     std::to_string(meshfiles::kMaxTriangles) + ")");
  }
  return contents;
}

MeshFileContents loadMeshFile(const std::string& path, const glm::dmat4& worldFromFile) {
  return parseMeshFile(readInputFile(path, meshfiles::kMaxFileBytes, "mesh file"), path,
                       worldFromFile);
}

}  // namespace clipray
