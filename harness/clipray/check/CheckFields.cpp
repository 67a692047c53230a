// What `clipray check` is told, as text: from the command line or a check file.

#include "clipray/check/CheckFields.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "clipray/InputError.hpp"
#include "clipray/io/LocatedJson.hpp"
#include "clipray/util/OptionValues.hpp"

namespace clipray {

namespace {

// The valid name the value spells, in any case (the report writes NO, ZO; users type them so).
std::string requireOneOf(const std::string& value, const std::string& what,
                         const std::vector<std::string>& valid) {
  std::string lower = value;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const std::string& v : valid) {
    if (v == lower) return v;
  }
  throw InputError(what + ": unknown value \"" + value +
                   "\"; expected one of: " + joinNames(valid));
}

}  // namespace

// The same fields from a JSON file (keys in camelCase, matrices as arrays of 16 numbers).
CheckFields parseCheckFile(const std::string& text, const std::string& file) {
  CheckFields fields;
  // The scene files' parser: line and column for malformed JSON; duplicate keys, NUL bytes and
  // deep nesting refused.
  nlohmann::json doc = detail::parseJson(text, file);
  if (!doc.is_object()) throw InputError(file, "/", "expected an object");
  auto textOf = [&](const char* key) -> std::string {
    const auto& value = doc[key];
    if (value.is_string()) return value.get<std::string>();
    if (value.is_array()) {
      std::string joined;
      for (const auto& item : value) {
        if (!item.is_number())
          throw InputError(file, std::string("/") + key,
                           "expected numbers, got " + detail::describe(item));
        joined += item.dump() + " ";
      }
      return joined;
    }
    throw InputError(file, std::string("/") + key,
                     "expected a string or an array of numbers, got " + detail::describe(value));
  };
  for (const auto& [key, value] : doc.items()) {
    if (key == "clipFromWorld")
      fields.clipFromWorld = textOf("clipFromWorld");
    else if (key == "projection")
      fields.projection = textOf("projection");
    else if (key == "view")
      fields.view = textOf("view");
    else if (key == "sceneExtent")
      fields.sceneExtent = textOf("sceneExtent");
    else if (key == "depthRange")
      fields.depthRange = textOf("depthRange");
    else if (key == "near" && value.is_number())
      fields.nearPlane = value.dump();
    else if (key == "far" && value.is_number())
      fields.farPlane = value.dump();
    else if (key == "precision" && value.is_string())
      fields.precision = value.get<std::string>();
    else if (key == "layout" && value.is_string())
      fields.layout = value.get<std::string>();
    else if (key == "declaredDepth" && value.is_string())
      fields.declaredDepth = value.get<std::string>();
    else if (key == "origin" && value.is_string())
      fields.origin = value.get<std::string>();
    else if (key == "viewport" && value.is_string())
      fields.viewport = value.get<std::string>();
    else if (key == "viewport" && value.is_array() && value.size() == 2 &&
             value[0].is_number_integer() &&
             value[1].is_number_integer())  // [W, H], as scene files write it
      fields.viewport = value[0].dump() + "x" + value[1].dump();
    else if (key == "depthBits" && value.is_string())
      fields.depthBits = value.get<std::string>();
    else if (key == "depthBits" && value.is_number_integer())  // 16 or 24 as a number
      fields.depthBits = value.dump();
    else if (key == "cull" && value.is_string())
      fields.cull = value.get<std::string>();
    else if (key == "frontFace" && value.is_string())
      fields.frontFace = value.get<std::string>();
    else if (key == "reversed" && value.is_boolean())
      fields.reversed = value.get<bool>();
    else if (key == "depthClamp" && value.is_boolean())
      fields.depthClamp = value.get<bool>();
    else if (key == "comment")
      continue;
    else {
      throw InputError(
          file, "/" + key,
          "unknown key or wrong type (" + detail::describe(value) +
              "); valid keys: clipFromWorld, projection, view, layout, declaredDepth, reversed, "
              "depthRange, origin, viewport, depthBits, sceneExtent, precision, near, far, cull, "
              "frontFace, depthClamp, comment");
    }
  }
  return fields;
}

CheckInput checkInputFrom(const CheckFields& fields, const std::string& where) {
  if (fields.clipFromWorld.empty() == fields.projection.empty()) {
    throw InputError(
        where +
        (fields.clipFromWorld.empty()
             ? "give the matrix: --clip-from-world \"16 numbers\", or --projection (with --view)"
             : "--clip-from-world and --projection are exclusive: give one"));
  }
  if (!fields.view.empty() && fields.projection.empty()) {
    throw InputError(
        where + "--view needs --projection (for a combined matrix use --clip-from-world alone)");
  }
  // xmmatrix: a DirectXMath matrix in memory is the column-major listing of the GL matrix.
  const bool rowMajor = requireOneOf(fields.layout, where + "--layout",
                                     {"column-major", "row-major", "xmmatrix"}) == "row-major";
  CheckInput input;
  input.listedRowMajor = rowMajor;
  if (!fields.clipFromWorld.empty()) {
    input.clipFromWorld =
        parseMatrixOption(fields.clipFromWorld, rowMajor, where + "--clip-from-world");
  } else {
    input.projection = parseMatrixOption(fields.projection, rowMajor, where + "--projection");
    input.view = fields.view.empty() ? glm::dmat4(1.0)
                                     : parseMatrixOption(fields.view, rowMajor, where + "--view");
    input.clipFromWorld = *input.projection * *input.view;
  }
  input.declaredReversed = fields.reversed;
  if (!fields.declaredDepth.empty()) {
    // The depth modes' names, as reconcile, pick and bench take them: zo-reversed is ZO with
    // the reversed depth test (--reversed).
    const std::string depth =
        requireOneOf(fields.declaredDepth, where + "--declared-depth", {"no", "zo", "zo-reversed"});
    input.declaredDepth =
        depth == "no" ? DepthConvention::NegativeOneToOne : DepthConvention::ZeroToOne;
    input.declaredReversed = input.declaredReversed || depth == "zo-reversed";
  }
  if (!fields.depthRange.empty()) {
    const std::vector<double> range = parseNumberList(fields.depthRange, where + "--depth-range");
    // Written so that NaN fails too.
    if (range.size() != 2 || !(range[0] >= 0 && range[0] <= 1 && range[1] >= 0 && range[1] <= 1)) {
      throw InputError(where + "--depth-range: expected NEAR,FAR in [0, 1], got \"" +
                       fields.depthRange + "\"");
    }
    input.depthRange = {range[0], range[1]};
  }
  if (!fields.origin.empty()) {
    input.origin = requireOneOf(fields.origin, where + "--origin", {"lower-left", "upper-left"}) ==
                           "upper-left"
                       ? WindowOrigin::UpperLeft
                       : WindowOrigin::LowerLeft;
  }
  if (!fields.cull.empty()) {
    input.cull =
        parseCullFace(requireOneOf(fields.cull, where + "--cull", {"none", "back", "front"}));
  }
  if (!fields.frontFace.empty()) {
    if (fields.cull.empty()) {
      throw InputError(where +
                       "--front-face needs --cull (back or front): without culling the "
                       "front face changes nothing a depth check sees");
    }
    input.frontFace =
        *parseFrontFace(requireOneOf(fields.frontFace, where + "--front-face", {"ccw", "cw"}));
  }
  if (fields.depthClamp) input.depthClampEnabledAt = "--depth-clamp";
  input.viewport = parseViewportOption(fields.viewport, where + "--viewport");
  input.depthFormat = *parseDepthFormat(
      requireOneOf(fields.depthBits, where + "--depth-bits", {"16", "24", "32f"}));
  if (!fields.sceneExtent.empty()) {
    const std::vector<double> e = parseNumberList(fields.sceneExtent, where + "--scene-extent");
    const bool finite = std::all_of(e.begin(), e.end(), [](double v) { return std::isfinite(v); });
    if (e.size() != 6 || !finite || e[0] > e[3] || e[1] > e[4] || e[2] > e[5]) {
      throw InputError(
          where +
          "--scene-extent: expected \"minx miny minz maxx maxy maxz\", finite, min <= max, got \"" +
          fields.sceneExtent + "\"");
    }
    input.sceneExtent = std::make_pair(glm::dvec3(e[0], e[1], e[2]), glm::dvec3(e[3], e[4], e[5]));
  }
  if (!fields.precision.empty()) {
    input.precision =
        requireOneOf(fields.precision, where + "--precision", {"float", "double"}) == "float"
            ? EntryPrecision::Arithmetic::Float32
            : EntryPrecision::Arithmetic::Double;
  }
  const auto plane = [&](const std::string& text, const std::string& what) {
    const std::vector<double> value = parseNumberList(text, where + what);
    if (value.size() != 1 || !std::isfinite(value[0])) {
      throw InputError(where + what + ": expected one finite number, got \"" + text + "\"");
    }
    return value[0];
  };
  if (!fields.nearPlane.empty()) input.statedNear = plane(fields.nearPlane, "--near");
  if (!fields.farPlane.empty()) input.statedFar = plane(fields.farPlane, "--far");
  if (input.statedNear && input.statedFar && !(*input.statedFar > *input.statedNear)) {
    throw InputError(where + "--far: expected a number greater than --near (" + fields.nearPlane +
                     "), got " + fields.farPlane);
  }
  if (!input.declaredDepth && input.declaredReversed) {
    // Reversed-Z without a declared depth mode: the GL default, NEGATIVE_ONE_TO_ONE, is what runs.
    input.declaredDepth = DepthConvention::NegativeOneToOne;
  }
  return input;
}

}  // namespace clipray
