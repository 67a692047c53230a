#include "clipray/trace/CaptureDraw.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "clipray/trace/FragDepthWrite.hpp"
#include "clipray/trace/ProjectionStructure.hpp"

namespace clipray::trace {

namespace {

const nlohmann::json& field(const nlohmann::json& object, const char* name) {
  if (!object.is_object() || !object.contains(name)) {
    throw std::invalid_argument(std::string("no \"") + name + "\" field");
  }
  return object[name];
}

template <typename T>
T value(const nlohmann::json& object, const char* name) {
  const nlohmann::json& found = field(object, name);
  try {
    return found.get<T>();
  } catch (const nlohmann::json::exception&) {
    throw std::invalid_argument(std::string("field \"") + name + "\" has the wrong type");
  }
}

std::uint32_t depthFuncOf(const std::string& name) {
  for (const std::uint32_t func :
       {kGlNever, kGlLess, kGlEqual, kGlLequal, kGlGreater, kGlNotequal, kGlGequal, kGlAlways}) {
    if (glEnumName(func) == name) return func;
  }
  throw std::invalid_argument("unknown depth function \"" + name + "\"");
}

std::uint32_t cullModeOf(const std::string& name) {
  for (const std::uint32_t mode : {kGlFront, kGlBack, kGlFrontAndBack}) {
    if (glEnumName(mode) == name) return mode;
  }
  throw std::invalid_argument("unknown cull mode \"" + name + "\"");
}

std::uint64_t callOf(const nlohmann::json& calls, const char* name) {
  return calls.contains(name) ? value<std::uint64_t>(calls, name) : 0;
}

bool mentionsClipDistance(const nlohmann::json& shaders, const char* stage) {
  return shaders.contains(stage) && shaders[stage].is_string() &&
         shaders[stage].get<std::string>().find("gl_ClipDistance") != std::string::npos;
}

// The reader writes a matrix row by row (RenderDoc keeps ShaderVariable values so): element
// (row r, column c) is rows[r][c]; glm indexes column first.
glm::dmat4 matrixOf(const nlohmann::json& rows) {
  if (!rows.is_array() || rows.size() != 4) throw std::invalid_argument("a matrix without 4 rows");
  glm::dmat4 matrix(1.0);
  for (int r = 0; r < 4; ++r) {
    if (!rows[r].is_array() || rows[r].size() != 4) {
      throw std::invalid_argument("a matrix row without 4 values");
    }
    for (int c = 0; c < 4; ++c) {
      if (!rows[r][c].is_number()) throw std::invalid_argument("a matrix value is no number");
      matrix[c][r] = rows[r][c].get<double>();
    }
  }
  return matrix;
}

}  // namespace

TraceDraw captureDrawOf(const nlohmann::json& line) {
  TraceDraw draw;
  draw.call = value<std::uint64_t>(line, "event");
  draw.completedAtCall = draw.call;
  draw.frame = value<std::uint64_t>(line, "frame");
  draw.function = value<std::string>(line, "name");
  const nlohmann::json& state = field(line, "state");
  const nlohmann::json& calls = field(line, "calls");
  TraceDepthState& depth = draw.depth;
  depth.clipZeroToOne = !value<bool>(state, "clip_negative_one_to_one");
  depth.clipUpperLeft = !value<bool>(state, "clip_lower_left");
  depth.depthTest = value<bool>(state, "depth_test");
  depth.depthFunc = depthFuncOf(value<std::string>(state, "depth_func"));
  const auto range = value<std::vector<double>>(state, "depth_range");
  if (range.size() != 2) throw std::invalid_argument("a depth range without 2 values");
  depth.depthRange = {range[0], range[1]};
  if (!field(state, "cleared_depth").is_null()) {
    depth.clearedDepth = value<double>(state, "cleared_depth");
  }
  const auto viewport = value<std::vector<double>>(state, "viewport");
  if (viewport.size() != 4) throw std::invalid_argument("a viewport without 4 values");
  depth.viewport = {static_cast<int>(std::lround(viewport[2])),
                    static_cast<int>(std::lround(viewport[3]))};
  depth.depthFormatName = value<std::string>(state, "depth_format");
  if (depth.depthFormatName == "none") depth.depthFormatName = "unknown";
  depth.depthFormat = parseDepthFormat(depth.depthFormatName);
  depth.cullFace = !field(state, "cull_face").is_null();
  if (depth.cullFace) depth.cullFaceMode = cullModeOf(value<std::string>(state, "cull_face"));
  depth.frontFace = value<bool>(state, "front_ccw") ? kGlCcw : kGlCw;
  depth.depthClamp = value<bool>(state, "depth_clamp");
  const auto clipDistances = value<std::uint32_t>(state, "clip_distances");
  if (clipDistances > 0xFFu) throw std::invalid_argument("more than 8 clip distances");
  depth.clipDistances = static_cast<std::uint8_t>(clipDistances);
  depth.depthWrite = value<bool>(state, "depth_write");
  // The offset's values as RenderDoc's state holds them; whether GL_POLYGON_OFFSET_FILL is on as
  // the capture's glEnable/glDisable left it (null: not set within the capture, GL's default off).
  const nlohmann::json& offset = field(state, "polygon_offset");
  depth.offsetFactor = value<double>(offset, "factor");
  depth.offsetUnits = value<double>(offset, "units");
  depth.offsetClamp = value<double>(offset, "clamp");
  if (state.contains("polygon_offset_fill") && !state["polygon_offset_fill"].is_null()) {
    depth.polygonOffsetFill = value<bool>(state, "polygon_offset_fill");
  }
  const nlohmann::json& shaders = field(line, "shaders");
  depth.writesClipDistance =
      mentionsClipDistance(shaders, "vertex") || mentionsClipDistance(shaders, "geometry");
  depth.clipControlCall = callOf(calls, "clip_control");
  depth.depthFuncCall = callOf(calls, "depth_func");
  depth.depthRangeCall = callOf(calls, "depth_range");
  depth.clearCall = callOf(calls, "clear");
  depth.cullFaceCall = callOf(calls, "cull_face");
  depth.cullFaceModeCall = callOf(calls, "cull_face_mode");
  depth.frontFaceCall = callOf(calls, "front_face");
  depth.depthClampCall = callOf(calls, "depth_clamp");
  depth.clipDistancesCall = callOf(calls, "clip_distances");
  depth.depthMaskCall = callOf(calls, "depth_mask");
  depth.polygonOffsetCall = callOf(calls, "polygon_offset");
  depth.polygonOffsetFillCall = callOf(calls, "polygon_offset_fill");
  const std::string program = value<std::string>(line, "program");
  // The trace names the program writing gl_FragDepth by its GL name; RenderDoc's resource name
  // ends in it ("Program 29").
  if (shaders.contains("fragment") && shaders["fragment"].is_string() &&
      writesFragDepth(shaders["fragment"].get<std::string>())) {
    const std::size_t digits = program.find_last_not_of("0123456789");
    const std::string number = digits == std::string::npos ? program : program.substr(digits + 1);
    depth.fragDepthProgram = number.empty() || number.size() > 9
                                 ? 1u
                                 : std::max(1u, static_cast<std::uint32_t>(std::stoul(number)));
  }
  for (const nlohmann::json& matrix : field(line, "matrices")) {
    const glm::dmat4 read = matrixOf(field(matrix, "rows"));
    if (!hasProjectionStructure(read)) continue;
    // Named as the trace checker names its sources: a plain uniform, or a block's member.
    const std::string name = value<std::string>(matrix, "name");
    // RenderDoc names a member of a block with an instance name (`uniform Camera { ... }
    // camera;`) as "Camera.member", one without as "member": the trace names both "Camera.member".
    const std::string block = value<std::string>(matrix, "block");
    const std::string source = !value<bool>(matrix, "buffer_backed") ? "uniform " + name
                               : name.starts_with(block + ".")       ? "ubo " + name
                                                                     : "ubo " + block + "." + name;
    draw.matrices.push_back({source + " (" + program + ")", false, read});
  }
  return draw;
}

}  // namespace clipray::trace
