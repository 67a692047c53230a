// Wavefront OBJ through tinyobjloader (compiled in here, in double precision), wrapped in a scan of
// our own: tinyobjloader reads "nan" as 0, only warns about out-of-range indices and silently drops
// faces with fewer than 3 vertices, so the scan checks every "v" and "f" line first, reports the
// line, and hands tinyobjloader only the lines clipray needs. Polygons are fanned into triangles
// here (tinyobjloader's own triangulation indexes the vertex array before checking the indices).

#define TINYOBJLOADER_IMPLEMENTATION
#define TINYOBJLOADER_USE_DOUBLE
#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "clipray/io/InputFile.hpp"
#include "clipray/scene/loaders/MeshFileCommon.hpp"
#include "clipray/scene/loaders/PolygonTriangulation.hpp"

namespace clipray::meshfiles {

namespace {

// OBJ is ASCII text, but some exporters write it as UTF-16 with a byte order mark, or put a
// UTF-8 byte order mark first; assimp reads both (its BaseImporter converts to UTF-8), so clipray
// does too. Returns the text to scan: `bytes` itself, or the UTF-8 decoding kept in `storage`.
std::string_view objText(std::string_view bytes, const std::string& path, std::string& storage) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(bytes[i]); };
  if (bytes.size() >= 3 && byte(0) == 0xEF && byte(1) == 0xBB && byte(2) == 0xBF) {
    return bytes.substr(3);
  }
  const bool bigEndian = bytes.size() >= 2 && byte(0) == 0xFE && byte(1) == 0xFF;
  const bool littleEndian = bytes.size() >= 2 && byte(0) == 0xFF && byte(1) == 0xFE;
  if (!bigEndian && !littleEndian) return bytes;
  const std::string encoding = bigEndian ? "UTF-16BE" : "UTF-16LE";
  if (bytes.size() % 2 != 0) {
    fail(path, encoding,
         "a UTF-16 file needs an even number of bytes, got " + std::to_string(bytes.size()));
  }
  const auto unit = [&](std::size_t i) -> std::uint32_t {
    return bigEndian ? (byte(i) << 8 | byte(i + 1)) : (byte(i + 1) << 8 | byte(i));
  };
  storage.reserve(bytes.size() / 2);
  for (std::size_t i = 2; i < bytes.size(); i += 2) {
    std::uint32_t code = unit(i);
    if (code >= 0xD800 && code <= 0xDBFF && i + 2 < bytes.size() && unit(i + 2) >= 0xDC00 &&
        unit(i + 2) <= 0xDFFF) {
      code = 0x10000 + ((code - 0xD800) << 10) + (unit(i + 2) - 0xDC00);
      i += 2;
    } else if (code >= 0xD800 && code <= 0xDFFF) {
      fail(path, encoding + " byte " + std::to_string(i), "an unpaired surrogate");
    }
    if (code < 0x80) {
      storage += static_cast<char>(code);
    } else if (code < 0x800) {
      storage += static_cast<char>(0xC0 | code >> 6);
      storage += static_cast<char>(0x80 | (code & 0x3F));
    } else if (code < 0x10000) {
      storage += static_cast<char>(0xE0 | code >> 12);
      storage += static_cast<char>(0x80 | (code >> 6 & 0x3F));
      storage += static_cast<char>(0x80 | (code & 0x3F));
    } else {
      storage += static_cast<char>(0xF0 | code >> 18);
      storage += static_cast<char>(0x80 | (code >> 12 & 0x3F));
      storage += static_cast<char>(0x80 | (code >> 6 & 0x3F));
      storage += static_cast<char>(0x80 | (code & 0x3F));
    }
  }
  return storage;
}

// The checks tinyobjloader does not do, with the line each problem is on.
class ObjScan {
 public:
  ObjScan(std::string_view text, const std::string& path) : text_(text), path_(path) {
    sanitized_.reserve(text.size() + 1);
  }

  // The file as tinyobjloader gets it: only "v x y z", "f v1 v2 v3 ..." (vertex indices only),
  // "o" and "g" lines, every other line emptied. clipray needs nothing else, and tinyobjloader's
  // other paths are where fuzzing found trouble (its "vw" extension casts any float to int).
  const std::string& sanitized() const { return sanitized_; }

  // The line of a face whose "v/vt/vn" corners name texture coordinates or normals the file does
  // not define (0: none): clipray reads positions only, so these are ignored, and said so once.
  std::uint64_t lineNamingMissingAttributes() const { return lineNamingMissingAttributes_; }

  struct MaterialLibrary {
    std::string name;
    std::uint64_t line = 0;
  };
  const std::vector<MaterialLibrary>& materialLibraries() const { return materialLibraries_; }

  void run() {
    requireNoNulBytes(text_, path_);
    std::size_t position = 0;
    std::uint64_t lineNumber = 0;
    while (position < text_.size()) {
      // tinyobjloader ends lines at "\n", "\r\n" and a lone "\r"; so does this scan.
      std::size_t end = text_.find_first_of("\r\n", position);
      if (end == std::string_view::npos) end = text_.size();
      const std::string_view line = text_.substr(position, end - position);
      position = end + 1;
      if (end + 1 < text_.size() && text_[end] == '\r' && text_[end + 1] == '\n') ++position;
      ++lineNumber;
      const std::vector<std::string_view> words = splitWords(line);
      if (!words.empty() && words[0] == "v") {
        checkVertex(words, lineNumber);
        sanitized_.append("v ").append(words[1]).append(" ").append(words[2]).append(" ");
        sanitized_.append(words[3]);
      } else if (!words.empty() && words[0] == "f") {
        checkFace(words, lineNumber);
        sanitized_.append("f");
        for (std::size_t corner = 1; corner < words.size(); ++corner) {
          sanitized_.append(" ").append(words[corner].substr(0, words[corner].find('/')));
        }
      } else if (!words.empty() && (words[0] == "o" || words[0] == "g")) {
        sanitized_.append(line);
      } else if (!words.empty() && (words[0] == "vt" || words[0] == "vn")) {
        ++(words[0] == "vt" ? texCoordCount_ : normalCount_);
      } else if (!words.empty() && words[0] == "mtllib" && words.size() > 1) {
        // The name is the rest of the line: exporters write names with spaces unquoted.
        const std::size_t start = line.find(words[1]);
        std::string_view name = line.substr(start);
        while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.remove_suffix(1);
        materialLibraries_.push_back({std::string(name), lineNumber});
      } else if (!words.empty() && (words[0] == "p" || words[0] == "l")) {
        ++(words[0] == "p" ? pointElements_ : lineElements_);
      }
      sanitized_.append("\n");  // every line stays, so tinyobjloader's line numbers match
    }
    for (const auto& [largest, count, line] :
         {std::tuple{largestTexCoordIndex_, texCoordCount_, lineOfLargestTexCoordIndex_},
          std::tuple{largestNormalIndex_, normalCount_, lineOfLargestNormalIndex_}}) {
      if (largest > count &&
          (lineNamingMissingAttributes_ == 0 || line < lineNamingMissingAttributes_)) {
        lineNamingMissingAttributes_ = line;
      }
    }
    if (faceCount_ == 0) {
      // Say what the file holds instead: a point cloud, a wireframe or nothing at all.
      fail(path_, "obj",
           "no faces (\"f\" lines), only " + std::to_string(vertexCount_) + " vertices, " +
               std::to_string(pointElements_) + " point (\"p\") and " +
               std::to_string(lineElements_) +
               " line (\"l\") elements: clipray compares surfaces, and points and lines have "
               "none");
    }
    if (largestPositiveIndex_ > vertexCount_) {
      fail(path_, "line " + std::to_string(lineOfLargestIndex_),
           "vertex index " + std::to_string(largestPositiveIndex_) + " out of range for " +
               std::to_string(vertexCount_) + " vertices");
    }
  }

 private:
  void checkVertex(const std::vector<std::string_view>& words, std::uint64_t lineNumber) {
    // Vertices are numbered from 1, as OBJ face indices count them.
    const std::string at =
        "line " + std::to_string(lineNumber) + ": vertex " + std::to_string(vertexCount_ + 1);
    if (words.size() < 4) {
      fail(path_, at, "expected \"v x y z\", got " + std::to_string(words.size() - 1) + " numbers");
    }
    static constexpr const char* kAxes[] = {"x", "y", "z"};
    for (int axis = 0; axis < 3; ++axis) {
      const std::string_view word = words[static_cast<std::size_t>(axis) + 1];
      double value = 0.0;
      const NumberParse parse = parseDouble(word, value);
      if (parse == NumberParse::NotANumber) {
        fail(path_, at, std::string(kAxes[axis]) + " is not a number, got " + quotedText(word));
      }
      if (parse == NumberParse::Overflow) {
        fail(path_, at,
             std::string(kAxes[axis]) + " does not fit a double, got " + quotedText(word));
      }
      if (!std::isfinite(value)) {
        fail(path_, at, std::string(kAxes[axis]) + " is not finite, got " + quotedText(word));
      }
    }
    ++vertexCount_;
  }

  // Positive vt/vn indices beyond the counts so far may still be defined later; relative ones
  // are checked against the counts so far, as for positions. Unparsable parts count as missing.
  void noteAttributeReferences(std::string_view corner, std::uint64_t lineNumber) {
    const std::size_t slash = corner.find('/');
    if (slash == std::string_view::npos) return;
    const std::string_view rest = corner.substr(slash + 1);
    const std::size_t secondSlash = rest.find('/');
    const std::string_view texCoord = rest.substr(0, secondSlash);
    const std::string_view normal =
        secondSlash == std::string_view::npos ? std::string_view() : rest.substr(secondSlash + 1);
    const auto note = [&](std::string_view part, std::uint64_t countSoFar, std::uint64_t& largest,
                          std::uint64_t& lineOfLargest) {
      if (part.empty()) return;
      std::int64_t index = 0;
      const auto result = std::from_chars(part.data(), part.data() + part.size(), index);
      if (result.ec != std::errc() || result.ptr != part.data() + part.size() || index == 0 ||
          (index < 0 && static_cast<std::uint64_t>(-(index + 1)) >= countSoFar)) {
        if (lineNamingMissingAttributes_ == 0) lineNamingMissingAttributes_ = lineNumber;
      } else if (index > 0 && static_cast<std::uint64_t>(index) > largest) {
        largest = static_cast<std::uint64_t>(index);
        lineOfLargest = lineNumber;
      }
    };
    note(texCoord, texCoordCount_, largestTexCoordIndex_, lineOfLargestTexCoordIndex_);
    note(normal, normalCount_, largestNormalIndex_, lineOfLargestNormalIndex_);
  }

  void checkFace(const std::vector<std::string_view>& words, std::uint64_t lineNumber) {
    const std::string at =
        "line " + std::to_string(lineNumber) + ": face " + std::to_string(faceCount_++);
    if (words.size() < 4) {
      fail(path_, at, "a face needs at least 3 vertices, got " + std::to_string(words.size() - 1));
    }
    for (std::size_t corner = 1; corner < words.size(); ++corner) {
      const std::string_view word = words[corner];
      const std::string_view vertexPart = word.substr(0, word.find('/'));
      std::int64_t index = 0;
      const auto result =
          std::from_chars(vertexPart.data(), vertexPart.data() + vertexPart.size(), index);
      if (result.ec != std::errc() || result.ptr != vertexPart.data() + vertexPart.size() ||
          vertexPart.empty()) {
        fail(path_, at, "expected a vertex index, got " + quotedText(word));
      }
      if (index == 0) fail(path_, at, "vertex index 0 is invalid (OBJ indices start at 1)");
      if (index < 0) {
        // Relative: -1 is the last vertex defined so far.
        if (static_cast<std::uint64_t>(-(index + 1)) >= vertexCount_) {
          fail(path_, at,
               "relative vertex index " + std::to_string(index) + " out of range for " +
                   std::to_string(vertexCount_) + " vertices defined so far");
        }
      } else if (static_cast<std::uint64_t>(index) > largestPositiveIndex_) {
        // Positive indices may refer to vertices defined later, so they are checked at the end.
        largestPositiveIndex_ = static_cast<std::uint64_t>(index);
        lineOfLargestIndex_ = lineNumber;
      }
      noteAttributeReferences(word, lineNumber);
      // tinyobjloader keeps indices in int.
      if (index > 0x7FFFFFFF || index < -0x7FFFFFFF) {
        fail(path_, at, "vertex index out of range, got " + std::to_string(index));
      }
    }
  }

  std::string_view text_;
  const std::string& path_;
  std::uint64_t vertexCount_ = 0;
  std::uint64_t faceCount_ = 0;
  std::uint64_t pointElements_ = 0;
  std::uint64_t lineElements_ = 0;
  std::uint64_t largestPositiveIndex_ = 0;
  std::uint64_t lineOfLargestIndex_ = 0;
  std::string sanitized_;
  std::vector<MaterialLibrary> materialLibraries_;
  std::uint64_t texCoordCount_ = 0, normalCount_ = 0;
  std::uint64_t largestTexCoordIndex_ = 0, largestNormalIndex_ = 0;
  std::uint64_t lineOfLargestTexCoordIndex_ = 0, lineOfLargestNormalIndex_ = 0;
  std::uint64_t lineNamingMissingAttributes_ = 0;
};

}  // namespace

MeshFileContents parseObj(std::string_view bytes, const std::string& path,
                          const glm::dmat4& worldFromFile) {
  std::string decoded;
  ObjScan scan(objText(bytes, path, decoded), path);
  scan.run();

  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // its triangulation reads vertices before checking indices
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // Materials are irrelevant to clipray; an empty .mtl text keeps the reader off the disk.
  if (!reader.ParseFromString(scan.sanitized(), std::string(), config)) {
    std::string error = reader.Error();
    while (!error.empty() && (error.back() == '\n' || error.back() == '.')) error.pop_back();
    fail(path, "obj", "tinyobjloader rejected the file: " + error);
  }
  const std::vector<tinyobj::real_t>& vertices = reader.GetAttrib().vertices;
  const std::size_t vertexCount = vertices.size() / 3;
  const std::string stem = std::filesystem::path(path).stem().string();

  MeshFileContents contents;
  UniqueNames names;
  std::uint64_t faceNumber = 0;
  // Polygons of more than 3 corners off their mean plane by more than this fraction of their
  // size (beyond what 6-7 printed digits explain), and those ear clipping could not finish.
  constexpr double kNonPlanarTolerance = 1e-4;
  std::uint64_t nonPlanar = 0, selfIntersecting = 0;
  double worstNonPlanarity = 0.0;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    MeshObject object;
    object.name = names.claim(shape.name.empty() ? (stem.empty() ? "obj" : stem) : shape.name);
    // Each object gets the vertices its faces use, in first-use order.
    std::unordered_map<int, std::uint32_t> objectIndexOfFileVertex;
    auto objectIndex = [&](int fileVertex) {
      if (fileVertex < 0 || static_cast<std::size_t>(fileVertex) >= vertexCount) {
        fail(path, "face " + std::to_string(faceNumber),
             "vertex index " + std::to_string(fileVertex + 1) + " out of range for " +
                 std::to_string(vertexCount) + " vertices");
      }
      const auto [entry, inserted] = objectIndexOfFileVertex.try_emplace(
          fileVertex, static_cast<std::uint32_t>(object.worldPositions.size()));
      if (inserted) {
        const std::size_t base = 3 * static_cast<std::size_t>(fileVertex);
        object.worldPositions.emplace_back(vertices[base], vertices[base + 1], vertices[base + 2]);
      }
      return entry->second;
    };
    std::size_t offset = 0;
    for (const unsigned int cornerCount : shape.mesh.num_face_vertices) {
      if (cornerCount < 3 || offset + cornerCount > shape.mesh.indices.size()) {
        fail(path, "face " + std::to_string(faceNumber),
             "a face needs at least 3 vertices, got " + std::to_string(cornerCount));
      }
      std::vector<std::uint32_t> cornerIndex(cornerCount);
      for (std::size_t corner = 0; corner < cornerCount; ++corner) {
        cornerIndex[corner] = objectIndex(shape.mesh.indices[offset + corner].vertex_index);
      }
      if (cornerCount == 3) {
        object.triangles.emplace_back(cornerIndex[0], cornerIndex[1], cornerIndex[2]);
      } else {
        // Concave polygons are common (a letter, a floor plan): ear clipping, not a fan.
        std::vector<glm::dvec3> corners(cornerCount);
        for (std::size_t corner = 0; corner < cornerCount; ++corner) {
          corners[corner] = object.worldPositions[cornerIndex[corner]];
        }
        const PolygonTriangles polygon = triangulatePolygon(corners);
        for (const auto& t : polygon.triangles) {
          object.triangles.emplace_back(cornerIndex[t[0]], cornerIndex[t[1]], cornerIndex[t[2]]);
        }
        if (polygon.nonPlanarity > kNonPlanarTolerance) {
          ++nonPlanar;
          worstNonPlanarity = std::max(worstNonPlanarity, polygon.nonPlanarity);
        }
        selfIntersecting += polygon.fanFallback ? 1 : 0;
      }
      offset += cornerCount;
      ++faceNumber;
    }
    if (object.triangles.empty()) continue;
    const std::string element = "object " + quotedText(object.name);
    addObject(contents, path, element, std::move(object), worldFromFile);
  }
  if (scan.lineNamingMissingAttributes() > 0) {
    contents.warnings.push_back(path + ": line " +
                                std::to_string(scan.lineNamingMissingAttributes()) +
                                " (and maybe others): a face names texture coordinates or normals "
                                "the file does not define; clipray reads positions only, ignored");
  }
  // Materials never change depth, so a missing library costs nothing; said once per library so
  // that a user who expected them knows.
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  for (const ObjScan::MaterialLibrary& library : scan.materialLibraries()) {
    std::error_code error;
    if (!std::filesystem::exists(folder / library.name, error)) {
      contents.warnings.push_back(path + ": line " + std::to_string(library.line) +
                                  ": material library " + quotedText(library.name) +
                                  " not found; materials do not change depth, ignored");
    }
  }
  if (nonPlanar > 0) {
    char worst[32];
    std::snprintf(worst, sizeof worst, "%.2g", worstNonPlanarity);
    contents.warnings.push_back(path + ": " + std::to_string(nonPlanar) +
                                " polygons are not planar (a corner up to " + worst +
                                " of the polygon's size off its mean plane); triangulated in that "
                                "plane, the triangles are one of several surfaces they could be");
  }
  if (selfIntersecting > 0) {
    contents.warnings.push_back(path + ": " + std::to_string(selfIntersecting) +
                                " polygons cross themselves; triangulated as far as ear clipping "
                                "goes, the rest as a fan");
  }
  return contents;
}

}  // namespace clipray::meshfiles
