// PLY (Stanford polygon files): a small strict reader of our own. Libraries we tried either hang on
// malformed headers (assimp waits forever for end_header) or skip validation, and the format is
// small enough to check every count and byte ourselves.
//
// Reads ascii, binary_little_endian and binary_big_endian; the "vertex" element's x, y, z of any
// scalar type; the "face" element's list "vertex_indices" (or "vertex_index") with any count and
// index types, fanned into triangles. Every other element and property is read and skipped.

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "clipray/scene/loaders/MeshFileCommon.hpp"

namespace clipray::meshfiles {

namespace {

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

enum class ScalarType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct ScalarTypeName {
  std::string_view name;
  ScalarType type;
};
constexpr ScalarTypeName kScalarTypeNames[] = {
    {"char", ScalarType::Int8},      {"int8", ScalarType::Int8},
    {"uchar", ScalarType::UInt8},    {"uint8", ScalarType::UInt8},
    {"short", ScalarType::Int16},    {"int16", ScalarType::Int16},
    {"ushort", ScalarType::UInt16},  {"uint16", ScalarType::UInt16},
    {"int", ScalarType::Int32},      {"int32", ScalarType::Int32},
    {"uint", ScalarType::UInt32},    {"uint32", ScalarType::UInt32},
    {"float", ScalarType::Float32},  {"float32", ScalarType::Float32},
    {"double", ScalarType::Float64}, {"float64", ScalarType::Float64},
};

std::size_t byteSize(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
    case ScalarType::UInt8:
      return 1;
    case ScalarType::Int16:
    case ScalarType::UInt16:
      return 2;
    case ScalarType::Int32:
    case ScalarType::UInt32:
    case ScalarType::Float32:
      return 4;
    case ScalarType::Float64:
      return 8;
  }
  return 0;
}

bool isInteger(ScalarType type) {
  return type != ScalarType::Float32 && type != ScalarType::Float64;
}

struct Property {
  std::string name;
  ScalarType type = ScalarType::Float32;
  bool isList = false;
  ScalarType countType = ScalarType::UInt8;  // lists only
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

struct Header {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<Element> elements;
  std::size_t bodyOffset = 0;       // first byte after "end_header\n"
  std::uint64_t bodyFirstLine = 0;  // line number of the first body line (ascii messages)
};

class PlyReader {
 public:
  PlyReader(std::string_view bytes, const std::string& path) : bytes_(bytes), path_(path) {}

  MeshFileContents read(const glm::dmat4& worldFromFile) {
    parseHeader();
    readBody();
    MeshFileContents contents;
    const std::string stem = std::filesystem::path(path_).stem().string();
    if (!ignoredLines_.empty()) {
      std::string lines;
      for (const int line : ignoredLines_)
        lines += (lines.empty() ? "" : ", ") + std::to_string(line);
      contents.warnings.push_back(path_ + ": header line" +
                                  (ignoredLines_.size() == 1 ? " " : "s ") + lines +
                                  ": unknown keyword, ignored as a comment");
    }
    addObject(contents, path_, "object " + quotedText(stem), std::move(object_), worldFromFile);
    contents.objects.back().name = stem.empty() ? "ply" : stem;
    return contents;
  }

 private:
  [[noreturn]] void failAt(const std::string& element, const std::string& message) const {
    fail(path_, element, message);
  }

  // ---- Header ------------------------------------------------------------------------------

  void parseHeader() {
    std::size_t position = 0;
    int lineNumber = 0;
    bool sawFormat = false;
    auto nextLine = [&]() -> std::optional<std::string_view> {
      if (position >= bytes_.size()) return std::nullopt;
      const std::size_t end = bytes_.find('\n', position);
      if (end == std::string_view::npos) {
        // The header's last line must end with a newline; a file that stops mid-header has none.
        return std::nullopt;
      }
      std::string_view line = bytes_.substr(position, end - position);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      position = end + 1;
      ++lineNumber;
      return line;
    };
    const auto magic = nextLine();
    if (!magic || *magic != "ply") {
      failAt("line 1", "expected the magic line \"ply\", got " +
                           quotedText(bytes_.substr(0, std::min<std::size_t>(bytes_.size(), 16))));
    }
    while (true) {
      const auto line = nextLine();
      if (!line) {
        failAt("header", "no \"end_header\" line before the end of the file (after line " +
                             std::to_string(lineNumber) + ")");
      }
      const std::string at = "line " + std::to_string(lineNumber);
      const std::vector<std::string_view> words = splitWords(*line);
      if (words.empty()) failAt(at, "empty header line");
      const std::string_view keyword = words[0];
      if (keyword == "comment" || keyword == "obj_info") continue;
      if (keyword == "end_header") {
        if (words.size() != 1)
          failAt(at, "unexpected words after end_header, got " + quotedText(*line));
        break;
      }
      if (keyword == "format") {
        if (sawFormat) failAt(at, "duplicate format line, got " + quotedText(*line));
        if (words.size() != 3 || words[2] != "1.0") {
          failAt(at,
                 "expected \"format <ascii|binary_little_endian|binary_big_endian> 1.0\", got " +
                     quotedText(*line));
        }
        if (words[1] == "ascii") {
          header_.format = PlyFormat::Ascii;
        } else if (words[1] == "binary_little_endian") {
          header_.format = PlyFormat::BinaryLittleEndian;
        } else if (words[1] == "binary_big_endian") {
          header_.format = PlyFormat::BinaryBigEndian;
        } else {
          failAt(at, "unknown format " + quotedText(words[1]) +
                         "; expected ascii, binary_little_endian or binary_big_endian");
        }
        sawFormat = true;
        continue;
      }
      if (!sawFormat) failAt(at, "expected the format line first, got " + quotedText(*line));
      if (keyword == "element") {
        parseElementLine(words, at, *line);
        continue;
      }
      if (keyword == "property") {
        parsePropertyLine(words, at, *line);
        continue;
      }
      // A line no PLY reader knows (Blender 2.4's exporter wrote its credit without "comment"):
      // the common readers skip it; so does clipray, saying so.
      ignoredLines_.push_back(lineNumber);
      continue;
    }
    if (!sawFormat) failAt("header", "missing the format line");
    header_.bodyOffset = position;
    header_.bodyFirstLine = lineNumber + 1;
    checkRequiredProperties();
  }

  void parseElementLine(const std::vector<std::string_view>& words, const std::string& at,
                        std::string_view line) {
    if (words.size() != 3)
      failAt(at, "expected \"element <name> <count>\", got " + quotedText(line));
    Element element;
    element.name = std::string(words[1]);
    const std::string_view countText = words[2];
    const auto result =
        std::from_chars(countText.data(), countText.data() + countText.size(), element.count);
    if (result.ec != std::errc() || result.ptr != countText.data() + countText.size()) {
      failAt(at, "element " + quotedText(words[1]) +
                     ": count must be a non-negative integer, got " + quotedText(countText));
    }
    for (const Element& existing : header_.elements) {
      if (existing.name == element.name) failAt(at, "duplicate element " + quotedText(words[1]));
    }
    header_.elements.push_back(std::move(element));
  }

  ScalarType scalarType(std::string_view name, const std::string& at) const {
    for (const ScalarTypeName& entry : kScalarTypeNames) {
      if (entry.name == name) return entry.type;
    }
    failAt(at, "unknown property type " + quotedText(name));
  }

  void parsePropertyLine(const std::vector<std::string_view>& words, const std::string& at,
                         std::string_view line) {
    if (header_.elements.empty())
      failAt(at, "property before any element, got " + quotedText(line));
    Property property;
    if (words.size() >= 2 && words[1] == "list") {
      if (words.size() != 5) {
        failAt(at, "expected \"property list <count type> <item type> <name>\", got " +
                       quotedText(line));
      }
      property.isList = true;
      property.countType = scalarType(words[2], at);
      if (!isInteger(property.countType)) {
        failAt(at, "a list count must have an integer type, got " + quotedText(words[2]));
      }
      property.type = scalarType(words[3], at);
      property.name = std::string(words[4]);
    } else {
      if (words.size() != 3)
        failAt(at, "expected \"property <type> <name>\", got " + quotedText(line));
      property.type = scalarType(words[1], at);
      property.name = std::string(words[2]);
    }
    Element& element = header_.elements.back();
    for (const Property& existing : element.properties) {
      if (existing.name == property.name) {
        failAt(at, "element " + quotedText(element.name) + ": duplicate property " +
                       quotedText(property.name));
      }
    }
    element.properties.push_back(std::move(property));
  }

  void checkRequiredProperties() {
    bool sawVertex = false;
    bool sawFace = false;
    std::uint64_t vertexCount = 0;
    for (std::size_t e = 0; e < header_.elements.size(); ++e) {
      const Element& element = header_.elements[e];
      if (element.name == "vertex") {
        sawVertex = true;
        vertexCount = element.count;
        for (const char* axis : {"x", "y", "z"}) {
          const auto found =
              std::find_if(element.properties.begin(), element.properties.end(),
                           [&](const Property& property) { return property.name == axis; });
          if (found == element.properties.end()) {
            failAt("element \"vertex\"", std::string("missing property \"") + axis + "\"");
          }
          if (found->isList) {
            failAt("element \"vertex\"",
                   std::string("property \"") + axis + "\" must be a scalar, got a list");
          }
        }
      } else if (element.name == "face") {
        sawFace = true;
        int indexLists = 0;
        for (const Property& property : element.properties) {
          if (property.name != "vertex_indices" && property.name != "vertex_index") continue;
          ++indexLists;
          if (!property.isList || !isInteger(property.type)) {
            failAt("element \"face\"",
                   "property " + quotedText(property.name) + " must be a list of integers");
          }
        }
        if (indexLists != 1) {
          failAt("element \"face\"",
                 "expected exactly one list property \"vertex_indices\" or \"vertex_index\", got " +
                     std::to_string(indexLists));
        }
      }
    }
    if (!sawVertex) failAt("header", "missing element \"vertex\"");
    const auto isIndexList = [](const Property& property) {
      return property.isList &&
             (property.name == "vertex_indices" || property.name == "vertex_index");
    };
    for (const Element& element : header_.elements) {
      if (!sawFace && element.name == "vertex" &&
          std::any_of(element.properties.begin(), element.properties.end(), isIndexList)) {
        failAt("header",
               "missing element \"face\": the face lists are a property of element "
               "\"vertex\", where no reader looks for them (they belong in their own "
               "element \"face\")");
      }
    }
    if (!sawFace) {
      failAt("header", "missing element \"face\": a point cloud of " + std::to_string(vertexCount) +
                           " vertices; clipray compares surfaces, and points have none");
    }
  }

  // ---- Body --------------------------------------------------------------------------------

  // Where a value came from, for messages: "line 12: vertex 3" in ascii, "vertex 3" in binary.
  std::string location(const Element& element, std::uint64_t index) const {
    const std::string item = element.name + " " + std::to_string(index);
    if (header_.format != PlyFormat::Ascii) return item;
    return "line " + std::to_string(currentLine_) + ": " + item;
  }

  // Reads one value of `type` as a double (every PLY scalar fits a double exactly).
  double readScalar(ScalarType type, const Element& element, std::uint64_t index,
                    const std::string& propertyName) {
    if (header_.format == PlyFormat::Ascii)
      return readAsciiScalar(type, element, index, propertyName);
    const std::size_t size = byteSize(type);
    if (bytes_.size() - position_ < size) {
      failAt(location(element, index), "the file ends inside property " + quotedText(propertyName) +
                                           " (truncated after " + std::to_string(bytes_.size()) +
                                           " bytes)");
    }
    unsigned char raw[8];
    std::memcpy(raw, bytes_.data() + position_, size);
    position_ += size;
    const bool fileIsLittle = header_.format == PlyFormat::BinaryLittleEndian;
    if (fileIsLittle != (std::endian::native == std::endian::little)) std::reverse(raw, raw + size);
    switch (type) {
      case ScalarType::Int8:
        return static_cast<std::int8_t>(raw[0]);
      case ScalarType::UInt8:
        return raw[0];
      case ScalarType::Int16:
        return bitsAs<std::int16_t>(raw);
      case ScalarType::UInt16:
        return bitsAs<std::uint16_t>(raw);
      case ScalarType::Int32:
        return bitsAs<std::int32_t>(raw);
      case ScalarType::UInt32:
        return bitsAs<std::uint32_t>(raw);
      case ScalarType::Float32:
        return bitsAs<float>(raw);
      case ScalarType::Float64:
        return bitsAs<double>(raw);
    }
    return 0.0;
  }

  template <typename T>
  static double bitsAs(const unsigned char* raw) {
    T value;
    std::memcpy(&value, raw, sizeof value);
    return static_cast<double>(value);
  }

  std::string_view nextAsciiToken() {
    while (position_ < bytes_.size()) {
      const char c = bytes_[position_];
      if (c == '\n') {
        ++currentLine_;
      } else if (c != ' ' && c != '\t' && c != '\r') {
        break;
      }
      ++position_;
    }
    const std::size_t start = position_;
    while (position_ < bytes_.size()) {
      const char c = bytes_[position_];
      if (c == ' ' || c == '\t' || c == '\r' || c == '\n') break;
      ++position_;
    }
    return bytes_.substr(start, position_ - start);
  }

  double readAsciiScalar(ScalarType type, const Element& element, std::uint64_t index,
                         const std::string& propertyName) {
    const std::string_view token = nextAsciiToken();
    if (token.empty()) {
      failAt(element.name + " " + std::to_string(index),
             "the file ends before property " + quotedText(propertyName) +
                 " (truncated after line " + std::to_string(lastTokenLine_) + ")");
    }
    lastTokenLine_ = currentLine_;
    const char* end = token.data() + token.size();
    if (isInteger(type)) {
      std::int64_t value = 0;
      const auto result = std::from_chars(token.data(), end, value);
      const double low = type == ScalarType::Int8    ? -128.0
                         : type == ScalarType::Int16 ? -32768.0
                         : type == ScalarType::Int32 ? -2147483648.0
                                                     : 0.0;
      const double high =
          static_cast<double>((std::uint64_t{1} << (8 * byteSize(type) - (low < 0 ? 1 : 0))) - 1);
      if (result.ec != std::errc() || result.ptr != end || static_cast<double>(value) < low ||
          static_cast<double>(value) > high) {
        failAt(location(element, index),
               "property " + quotedText(propertyName) + ": expected an integer in [" +
                   formatNumber(low) + ", " + formatNumber(high) + "], got " + quotedText(token));
      }
      return static_cast<double>(value);
    }
    double value = 0.0;
    const NumberParse parse = parseDouble(token, value);
    if (parse == NumberParse::NotANumber) {
      failAt(location(element, index), "property " + quotedText(propertyName) +
                                           ": expected a number, got " + quotedText(token));
    }
    if (parse == NumberParse::Overflow) {
      failAt(location(element, index), "property " + quotedText(propertyName) +
                                           ": the number does not fit a double, got " +
                                           quotedText(token));
    }
    return value;
  }

  void readBody() {
    position_ = header_.bodyOffset;
    currentLine_ = header_.bodyFirstLine;
    lastTokenLine_ = header_.bodyFirstLine - 1;
    for (const Element& element : header_.elements) {
      if (element.name == "vertex") {
        readVertices(element);
      } else if (element.name == "face") {
        readFaces(element);
      } else if (!element.properties.empty()) {
        // An element without properties takes no bytes, however large its count: nothing to skip
        // (and looping over a count of 2^64 would never end).
        for (std::uint64_t index = 0; index < element.count; ++index) skipInstance(element, index);
      }
    }
    const std::size_t end = position_;
    if (header_.format == PlyFormat::Ascii) {
      const std::string_view rest = nextAsciiToken();
      if (!rest.empty()) {
        failAt("line " + std::to_string(currentLine_),
               "unexpected data after the last element, got " + quotedText(rest));
      }
    } else if (end != bytes_.size()) {
      failAt("body", std::to_string(bytes_.size() - end) +
                         " unexpected bytes after the last element (the header's counts are " +
                         "smaller than the data)");
    }
    // Faces may come before vertices in the file, so indices are checked once both are read.
    const std::uint64_t vertexCount = object_.worldPositions.size();
    for (std::size_t t = 0; t < object_.triangles.size(); ++t) {
      for (int corner = 0; corner < 3; ++corner) {
        if (object_.triangles[t][corner] >= vertexCount) {
          failAt("face " + std::to_string(faceOfTriangle_[t]),
                 "vertex index " + std::to_string(object_.triangles[t][corner]) +
                     " out of range for " + std::to_string(vertexCount) + " vertices");
        }
      }
    }
  }

  void skipInstance(const Element& element, std::uint64_t index) {
    for (const Property& property : element.properties) readProperty(property, element, index);
  }

  // Reads one property (a scalar, or a whole list) and returns its values; lists are
  // bounded by the bytes left in the file, so a huge count cannot allocate before it fails.
  std::vector<double>& readProperty(const Property& property, const Element& element,
                                    std::uint64_t index) {
    values_.clear();
    if (!property.isList) {
      values_.push_back(readScalar(property.type, element, index, property.name));
      return values_;
    }
    const double count = readScalar(property.countType, element, index, property.name);
    if (count < 0) {
      failAt(location(element, index), "list " + quotedText(property.name) +
                                           ": negative item count, got " + formatNumber(count));
    }
    const auto itemCount = static_cast<std::uint64_t>(count);
    const std::uint64_t minimumBytesPerItem =
        header_.format == PlyFormat::Ascii ? 2 : byteSize(property.type);
    if (itemCount > (bytes_.size() - position_ + 1) / minimumBytesPerItem) {
      failAt(location(element, index),
             "list " + quotedText(property.name) + ": " + std::to_string(itemCount) +
                 " items do not fit in the rest of the file (truncated?)");
    }
    for (std::uint64_t item = 0; item < itemCount; ++item) {
      values_.push_back(readScalar(property.type, element, index, property.name));
    }
    return values_;
  }

  void readVertices(const Element& element) {
    for (std::uint64_t index = 0; index < element.count; ++index) {
      glm::dvec3 position(0.0);
      for (const Property& property : element.properties) {
        const std::vector<double>& values = readProperty(property, element, index);
        const int axis = property.name == "x"   ? 0
                         : property.name == "y" ? 1
                         : property.name == "z" ? 2
                                                : -1;
        if (axis < 0) continue;
        if (!std::isfinite(values[0])) {
          failAt(location(element, index), "property " + quotedText(property.name) +
                                               " is not finite, got " + formatNumber(values[0]));
        }
        position[axis] = values[0];
      }
      if (object_.worldPositions.size() >= 0xFFFFFFFFull) {
        failAt(location(element, index), "more vertices than 32-bit indices can address");
      }
      object_.worldPositions.push_back(position);
    }
  }

  void readFaces(const Element& element) {
    for (std::uint64_t index = 0; index < element.count; ++index) {
      for (const Property& property : element.properties) {
        const std::vector<double>& values = readProperty(property, element, index);
        if (property.name != "vertex_indices" && property.name != "vertex_index") continue;
        if (values.size() < 3) {
          failAt(location(element, index),
                 "a face needs at least 3 vertices, got " + std::to_string(values.size()));
        }
        for (double value : values) {
          if (value < 0 || value > 4294967295.0) {
            failAt(location(element, index),
                   "vertex index must be non-negative, got " + formatNumber(value));
          }
        }
        const auto first = static_cast<std::uint32_t>(values[0]);
        for (std::size_t corner = 1; corner + 1 < values.size(); ++corner) {
          if (object_.triangles.size() >= kMaxTriangles) {
            failAt(location(element, index), "more triangles than 32-bit primitive ids allow");
          }
          object_.triangles.emplace_back(first, static_cast<std::uint32_t>(values[corner]),
                                         static_cast<std::uint32_t>(values[corner + 1]));
          faceOfTriangle_.push_back(index);
        }
      }
    }
  }

  std::string_view bytes_;
  const std::string& path_;
  std::vector<int> ignoredLines_;  // header lines with a keyword no PLY reader knows
  Header header_;
  std::size_t position_ = 0;
  std::uint64_t currentLine_ = 0;
  std::uint64_t lastTokenLine_ = 0;  // where the file ends, for truncation messages
  MeshObject object_;
  std::vector<std::uint64_t> faceOfTriangle_;  // for messages about out-of-range indices
  std::vector<double> values_;                 // reused by readProperty
};

}  // namespace

MeshFileContents parsePly(std::string_view bytes, const std::string& path,
                          const glm::dmat4& worldFromFile) {
  return PlyReader(bytes, path).read(worldFromFile);
}

}  // namespace clipray::meshfiles
