// A page's recorded WebGL calls as dump lines for the trace checker (PageCalls.hpp).
//
// Numbers are written as apitrace writes them (apitrace/apitrace, lib/trace/trace_dump.cpp):
// integers as integers, floats with 7 significant digits (digits10 + 1 of float). WebGL's
// floats (matrices, clear depth, depth range) are float32 values, so the checker reads a page's
// matrix at the same precision as a traced app's.

#include "clipray/page/PageCalls.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>

#include "clipray/InputError.hpp"

namespace clipray::page {

namespace {

using nlohmann::json;

constexpr std::uint32_t kGlDepthBufferBit = 0x100;
constexpr long long kPolygonOffsetFill = 0x8037;
// A bufferData(target, size) larger than this is not written out as zeros (the recorder keeps
// no buffer data past 1 MiB either).
constexpr long long kMaxZeroFilledBytes = 1 << 20;

// An integer argument; nullopt for anything else (a NaN the page passed, a string).
std::optional<long long> integerAt(const json& record, std::size_t index) {
  if (index >= record.size() || !record[index].is_number()) return std::nullopt;
  const double value = record[index].get<double>();
  if (!std::isfinite(value) || value != std::floor(value) || std::fabs(value) > 9.0e15) {
    return std::nullopt;
  }
  return static_cast<long long>(value);
}

std::optional<std::string> floatText(const json& value) {
  if (!value.is_number()) return std::nullopt;
  const double number = value.get<double>();
  if (!std::isfinite(number)) return std::nullopt;
  char text[32];
  std::snprintf(text, sizeof text, "%.7g", number);
  return std::string(text);
}

// A GLSL name as a C string literal (the names are ASCII; anything else is escaped).
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (byte < 0x20 || byte > 0x7E) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\%03o", byte);
      out += escaped;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string line(std::uint64_t call, const std::string& function, const std::string& arguments) {
  std::string out = std::to_string(call);
  out += ' ';
  out += function;
  out += '(';
  out += arguments;
  out += ')';
  return out;
}

// The GL function each recorded call stands for and its argument names, for the calls whose
// arguments are all integers (enums and object numbers).
const std::map<std::string, std::pair<std::string, std::vector<const char*>>>& integerCalls() {
  static const std::map<std::string, std::pair<std::string, std::vector<const char*>>> calls = {
      {"enable", {"glEnable", {"cap"}}},
      {"disable", {"glDisable", {"cap"}}},
      {"depthFunc", {"glDepthFunc", {"func"}}},
      {"cullFace", {"glCullFace", {"mode"}}},
      {"frontFace", {"glFrontFace", {"mode"}}},
      {"clear", {"glClear", {"mask"}}},
      {"useProgram", {"glUseProgram", {"program"}}},
      {"linkProgram", {"glLinkProgram", {"program"}}},
      {"clipControl", {"glClipControl", {"origin", "depth"}}},
      {"bindFramebuffer", {"glBindFramebuffer", {"target", "framebuffer"}}},
      {"bindRenderbuffer", {"glBindRenderbuffer", {"target", "renderbuffer"}}},
      {"renderbufferStorage", {"glRenderbufferStorage", {"target", "internalformat"}}},
      {"framebufferRenderbuffer",
       {"glFramebufferRenderbuffer",
        {"target", "attachment", "renderbuffertarget", "renderbuffer"}}},
      {"framebufferTexture2D",
       {"glFramebufferTexture2D", {"target", "attachment", "textarget", "texture", "level"}}},
      {"activeTexture", {"glActiveTexture", {"texture"}}},
      {"bindTexture", {"glBindTexture", {"target", "texture"}}},
      {"texImage2D", {"glTexImage2D", {"target", "level", "internalformat"}}},
      {"texStorage2D", {"glTexStorage2D", {"target", "levels", "internalformat"}}},
      {"viewport", {"glViewport", {"x", "y", "width", "height"}}},
      {"attachShader", {"glAttachShader", {"program", "shader"}}},
      {"detachShader", {"glDetachShader", {"program", "shader"}}},
      {"bindBuffer", {"glBindBuffer", {"target", "buffer"}}},
      {"bindBufferBase", {"glBindBufferBase", {"target", "index", "buffer"}}},
      {"bindBufferRange", {"glBindBufferRange", {"target", "index", "buffer", "offset", "size"}}},
      {"uniformBlockBinding",
       {"glUniformBlockBinding", {"program", "uniformBlockIndex", "uniformBlockBinding"}}},
      {"drawArrays", {"glDrawArrays", {}}},
      {"drawElements", {"glDrawElements", {}}},
      {"drawArraysInstanced", {"glDrawArraysInstanced", {}}},
      {"drawElementsInstanced", {"glDrawElementsInstanced", {}}},
      {"drawRangeElements", {"glDrawRangeElements", {}}},
  };
  return calls;
}

std::string integerCallLine(const json& record, std::uint64_t call, const std::string& function,
                            const std::vector<const char*>& names) {
  std::string out;
  std::size_t index = 2;
  for (const char* name : names) {
    const auto value = integerAt(record, index++);
    if (!value) return "";
    // A negative viewport size is INVALID_VALUE in WebGL: nothing changes.
    if (function == "glViewport" && index > 4 && *value < 0) return "";
    if (!out.empty()) out += ", ";
    out += name;
    out += " = ";
    out += std::to_string(*value);
  }
  return line(call, function, out);
}

}  // namespace

std::string dumpLineFor(const json& record, std::uint64_t call) {
  if (!record.is_array() || record.size() < 2 || !record[1].is_string()) return "";
  const std::string name = record[1].get<std::string>();
  if (name == "frame") return line(call, "glFrameTerminatorGREMEDY", "");
  const auto& calls = integerCalls();
  if (const auto found = calls.find(name); found != calls.end()) {
    return integerCallLine(record, call, found->second.first, found->second.second);
  }
  if (name == "clearDepth") {
    const auto depth = record.size() > 2 ? floatText(record[2]) : std::nullopt;
    return depth ? line(call, "glClearDepth", "depth = " + *depth) : "";
  }
  if (name == "depthRange") {
    const auto n = record.size() > 3 ? floatText(record[2]) : std::nullopt;
    const auto f = record.size() > 3 ? floatText(record[3]) : std::nullopt;
    if (!n || !f) return "";
    // WebGL 1.0, 6.12: zNear greater than zFar is INVALID_OPERATION; nothing changes (a reversed
    // depth range, GL's other way to reversed-Z, does not exist in WebGL).
    if (record[2].get<double>() > record[3].get<double>()) return "";
    return line(call, "glDepthRangef", "n = " + *n + ", f = " + *f);
  }
  if (name == "clearBufferfv") {
    const auto buffer = integerAt(record, 2);
    const auto drawBuffer = integerAt(record, 3);
    const auto depth = record.size() > 4 ? floatText(record[4]) : std::nullopt;
    if (!buffer || !drawBuffer || !depth) return "";
    return line(call, "glClearBufferfv",
                "buffer = " + std::to_string(*buffer) +
                    ", drawbuffer = " + std::to_string(*drawBuffer) + ", value = {" + *depth + "}");
  }
  if (name == "clearBufferfi") {
    const auto buffer = integerAt(record, 2);
    const auto drawBuffer = integerAt(record, 3);
    const auto depth = record.size() > 4 ? floatText(record[4]) : std::nullopt;
    const auto stencil = integerAt(record, 5);
    if (!buffer || !drawBuffer || !depth || !stencil) return "";
    return line(call, "glClearBufferfi",
                "buffer = " + std::to_string(*buffer) +
                    ", drawbuffer = " + std::to_string(*drawBuffer) + ", depth = " + *depth +
                    ", stencil = " + std::to_string(*stencil));
  }
  if (name == "getUniformLocation") {
    const auto program = integerAt(record, 2);
    const auto location = integerAt(record, 4);
    if (!program || !location || record.size() < 5 || !record[3].is_string()) return "";
    return line(call, "glGetUniformLocation",
                "program = " + std::to_string(*program) +
                    ", name = " + quoted(record[3].get<std::string>())) +
           " = " + std::to_string(*location);
  }
  if (name == "createShader") {
    const auto type = integerAt(record, 2);
    const auto shader = integerAt(record, 3);
    if (!type || !shader) return "";
    return line(call, "glCreateShader", "type = " + std::to_string(*type)) + " = " +
           std::to_string(*shader);
  }
  if (name == "shaderSource") {
    const auto shader = integerAt(record, 2);
    if (!shader || record.size() < 4 || !record[3].is_string()) return "";
    return line(call, "glShaderSource",
                "shader = " + std::to_string(*shader) + ", count = 1, string = {" +
                    quoted(record[3].get<std::string>()) + "}, length = NULL");
  }
  if (name == "getUniformBlockIndex") {
    const auto program = integerAt(record, 2);
    const auto index = integerAt(record, 4);
    if (!program || !index || record.size() < 5 || !record[3].is_string()) return "";
    return line(call, "glGetUniformBlockIndex",
                "program = " + std::to_string(*program) +
                    ", uniformBlockName = " + quoted(record[3].get<std::string>())) +
           " = " + std::to_string(*index);
  }
  if (name == "uniformMatrix4fv") {
    const auto location = integerAt(record, 2);
    const auto transpose = integerAt(record, 3);
    if (!location || !transpose || record.size() < 5 || !record[4].is_array()) return "";
    const json& values = record[4];
    if (values.empty() || values.size() % 16 != 0) return "";  // INVALID_VALUE in WebGL
    std::string list;
    for (const json& value : values) {
      const auto text = floatText(value);
      if (!text) return "";
      if (!list.empty()) list += ", ";
      list += *text;
    }
    return line(call, "glUniformMatrix4fv",
                "location = " + std::to_string(*location) +
                    ", count = " + std::to_string(values.size() / 16) + ", transpose = " +
                    (*transpose != 0 ? "GL_TRUE" : "GL_FALSE") + ", value = {" + list + "}");
  }
  return "";
}

std::optional<std::string> base64Decoded(const std::string& text) {
  std::string out;
  unsigned value = 0;
  int bits = 0;
  for (const char c : text) {
    int digit = -1;
    if (c >= 'A' && c <= 'Z') digit = c - 'A';
    if (c >= 'a' && c <= 'z') digit = c - 'a' + 26;
    if (c >= '0' && c <= '9') digit = c - '0' + 52;
    if (c == '+') digit = 62;
    if (c == '/') digit = 63;
    if (c == '=') break;
    if (digit < 0) return std::nullopt;
    value = (value << 6) | static_cast<unsigned>(digit);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((value >> bits) & 0xFFu);
    }
  }
  return out;
}

namespace {

// The folder the buffers' bytes are written to as apitrace's blob files (blob_call<N>.bin), which
// the state model reads (UniformBuffers.hpp); removed with its files.
class BlobFolder {
 public:
  BlobFolder() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "clipray-page-blobs-XXXXXX").string();
    if (!mkdtemp(pattern.data())) {
      throw InputError("cannot create a temporary folder for the page's buffer data: " +
                       std::string(std::strerror(errno)));
    }
    path_ = pattern;
  }
  ~BlobFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  BlobFolder(const BlobFolder&) = delete;
  BlobFolder& operator=(const BlobFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

  // The data argument for these bytes of the call: blob("blob_call<N>.bin").
  std::string write(std::uint64_t call, const std::string& bytes) {
    const std::string name = "blob_call" + std::to_string(call) + ".bin";
    std::ofstream file(path_ / name, std::ios::binary);
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!file) throw InputError("cannot write the page's buffer data to " + path_.string());
    return "blob(\"" + name + "\")";
  }

 private:
  std::filesystem::path path_;
};

// bufferData and bufferSubData of UNIFORM_BUFFER: their bytes go to a blob file (NULL data where
// the recorder kept none: the state model then notes the block as not read).
std::string bufferLine(const json& record, std::uint64_t call, BlobFolder& blobs) {
  const bool sub = record[1] == "bufferSubData";
  const auto target = integerAt(record, 2);
  const auto offset = sub ? integerAt(record, 3) : std::optional<long long>(0);
  const auto size = integerAt(record, sub ? 4 : 3);
  const std::size_t dataAt = sub ? 5 : 4;
  if (!target || !offset || !size || *size < 0 || *offset < 0 || record.size() <= dataAt) {
    return "";
  }
  std::string data = "NULL";
  if (record[dataAt].is_string()) {
    if (const auto bytes = base64Decoded(record[dataAt].get<std::string>())) {
      data = blobs.write(call, *bytes);
    }
  } else if (!sub && *size <= kMaxZeroFilledBytes) {
    // bufferData(target, size): the store is zero-filled (WebGL 1.0, 5.14.5).
    data = blobs.write(call, std::string(static_cast<std::size_t>(*size), '\0'));
  }
  std::string arguments = "target = " + std::to_string(*target);
  if (sub) arguments += ", offset = " + std::to_string(*offset);
  arguments += ", size = " + std::to_string(*size) + ", data = " + data;
  return line(call, sub ? "glBufferSubData" : "glBufferData", arguments);
}

}  // namespace

bool PageCheckResult::hasErrors() const {
  for (const CanvasCheck& canvas : canvases) {
    if (canvas.result && canvas.result->hasErrors()) return true;
  }
  return false;
}

namespace {

// What a context's calls need beyond the lines: the WebGL rules PageCalls.hpp lists.
struct ContextLines {
  trace::TraceCheckCollector collector;
  bool implicitClear = false;  // a depth buffer, not preserved between frames
  std::int64_t drawFramebuffer = 0;
  std::string clearDepth = "1";  // the page's clearDepth, as written
  std::uint64_t calls = 0, draws = 0;
  bool depthMask = true, polygonOffsetFill = false;
  double factor = 0.0, units = 0.0;  // polygonOffset's
  std::uint64_t drawsWithoutDepthWrites = 0, drawsWithPolygonOffset = 0;
  double offsetFactor = 0.0, offsetUnits = 0.0;  // at the last draw with the offset on

  void add(const std::string& text) {
    if (!text.empty()) collector.addLine(text);
  }
  // The drawing buffer's depth format, from the context's DEPTH_BITS: the state model reads the
  // depth format from the draw framebuffer's attachment, and framebuffer 0's is set as a
  // renderbuffer 0 attached to it (a renderbuffer the page cannot name: WebGL has no object 0).
  void describeDrawingBuffer(std::uint64_t call, int depthBits) {
    const std::uint32_t format = depthBits == 16 ? 0x81A5u : depthBits == 24 ? 0x81A6u : 0u;
    if (format == 0) return;
    add(line(call, "glBindRenderbuffer", "target = 36161, renderbuffer = 0"));
    add(line(call, "glRenderbufferStorage",
             "target = 36161, internalformat = " + std::to_string(format)));
    add(line(call, "glFramebufferRenderbuffer",
             "target = 36160, attachment = 36096, renderbuffertarget = 36161, renderbuffer = 0"));
  }
  // The drawing buffer as WebGL hands it to a frame: depth cleared to 1.0.
  void clearDrawingBuffer(std::uint64_t call) {
    if (!implicitClear || drawFramebuffer != 0) return;
    add(line(call, "glClearDepth", "depth = 1"));
    add(line(call, "glClear", "mask = " + std::to_string(kGlDepthBufferBit)));
    add(line(call, "glClearDepth", "depth = " + clearDepth));
  }
};

}  // namespace

PageCheckResult checkRecording(const std::string& page, const json& recording,
                               bool requireProjection) {
  PageCheckResult result;
  result.page = page;
  result.url = recording.value("url", "");
  result.devicePixelRatio = recording.value("devicePixelRatio", 1.0);
  result.frames = recording.value("frames", std::uint64_t{0});
  result.draws = recording.value("draws", std::uint64_t{0});
  result.callsNotKept = recording.value("dropped", std::uint64_t{0});
  for (const json& error : recording.value("errors", json::array())) {
    if (error.is_string()) result.recorderErrors.push_back(error.get<std::string>());
  }
  for (const json& error : recording.value("pageErrors", json::array())) {
    if (error.is_string()) result.pageErrors.push_back(error.get<std::string>());
  }
  const json contexts = recording.value("contexts", json::array());
  if (contexts.empty()) {
    throw InputError(page + ": no WebGL context");
  }
  std::vector<ContextLines> lines;
  lines.reserve(contexts.size());
  std::vector<int> depthBits;
  for (const json& context : contexts) {
    const std::string name = context.value("name", "canvas");
    lines.push_back({trace::TraceCheckCollector(name, trace::FrameRange{})});
    lines.back().implicitClear =
        context.value("depth", false) && !context.value("preserveDrawingBuffer", false);
    depthBits.push_back(context.value("depth", false) ? context.value("depthBits", 0) : 0);
  }
  const json calls = recording.value("calls", json::array());
  std::unique_ptr<BlobFolder> blobs;  // made at the first buffer data
  std::uint64_t number = 0;
  for (const json& record : calls) {
    ++number;  // calls count from 1: 0 is the state a context starts with
    const auto index = integerAt(record, 0);
    if (!index || record.size() < 2 || !record[1].is_string()) continue;
    const std::string name = record[1].get<std::string>();
    if (*index < 0) {
      if (name != "frame") continue;
      for (ContextLines& context : lines) {
        context.add(dumpLineFor(record, number));
        context.clearDrawingBuffer(number);
      }
      continue;
    }
    if (static_cast<std::size_t>(*index) >= lines.size()) continue;
    ContextLines& context = lines[static_cast<std::size_t>(*index)];
    ++context.calls;
    if (name == "context") {
      const auto width = integerAt(record, 2);
      const auto height = integerAt(record, 3);
      if (width && height) {
        context.add(line(number, "glViewport",
                         "x = 0, y = 0, width = " + std::to_string(*width) +
                             ", height = " + std::to_string(*height)));
      }
      context.describeDrawingBuffer(number, depthBits[static_cast<std::size_t>(*index)]);
      context.clearDrawingBuffer(number);
      continue;
    }
    if (name == "bindFramebuffer") {
      if (const auto framebuffer = integerAt(record, 3)) context.drawFramebuffer = *framebuffer;
    } else if (name == "clearDepth" && record.size() > 2) {
      // WebGL clamps clearDepth to [0, 1] (WebGL 1.0, 6.13; GLclampf).
      if (const auto text = floatText(record[2])) context.clearDepth = *text;
    } else if (name.starts_with("draw")) {
      ++context.draws;
      if (!context.depthMask) ++context.drawsWithoutDepthWrites;
      if (context.polygonOffsetFill) {
        ++context.drawsWithPolygonOffset;
        context.offsetFactor = context.factor;
        context.offsetUnits = context.units;
      }
    } else if (name == "depthMask") {
      if (const auto mask = integerAt(record, 2)) context.depthMask = *mask != 0;
    } else if (name == "polygonOffset") {
      if (record.size() > 3 && record[2].is_number() && record[3].is_number()) {
        context.factor = record[2].get<double>();
        context.units = record[3].get<double>();
      }
    } else if ((name == "enable" || name == "disable") &&
               integerAt(record, 2) == kPolygonOffsetFill) {
      context.polygonOffsetFill = name == "enable";
    } else if (name == "bufferData" || name == "bufferSubData") {
      if (!blobs) {
        blobs = std::make_unique<BlobFolder>();
        for (ContextLines& each : lines) each.collector.setBlobDirectory(blobs->path());
      }
      context.add(bufferLine(record, number, *blobs));
      continue;
    }
    context.add(dumpLineFor(record, number));
  }

  std::string firstReason;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    CanvasCheck canvas;
    canvas.name = contexts[k].value("name", "canvas");
    canvas.type = contexts[k].value("type", "webgl");
    canvas.canvas = contexts[k];
    canvas.calls = lines[k].calls;
    canvas.draws = lines[k].draws;
    canvas.drawsWithoutDepthWrites = lines[k].drawsWithoutDepthWrites;
    canvas.drawsWithPolygonOffset = lines[k].drawsWithPolygonOffset;
    canvas.polygonOffsetFactor = lines[k].offsetFactor;
    canvas.polygonOffsetUnits = lines[k].offsetUnits;
    if (canvas.draws == 0) {
      canvas.notChecked = "no draws";
    } else {
      try {
        canvas.result = lines[k].collector.finish();
      } catch (const InputError& error) {
        canvas.notChecked = error.what();
      }
    }
    if (!canvas.result && firstReason.empty()) {
      // The trace checker's messages name the canvas already (its "trace" name).
      firstReason = canvas.notChecked.starts_with(canvas.name + ": ")
                        ? canvas.notChecked
                        : canvas.name + ": " + canvas.notChecked;
    }
    result.canvases.push_back(std::move(canvas));
  }
  if (result.draws == 0) {
    throw InputError(page + ": never drew (" + std::to_string(contexts.size()) +
                     (contexts.size() == 1 ? " WebGL context)" : " WebGL contexts)"));
  }
  const bool anyChecked = std::any_of(result.canvases.begin(), result.canvases.end(),
                                      [](const CanvasCheck& c) { return c.result.has_value(); });
  if (!anyChecked && requireProjection) throw InputError(page + ": " + firstReason);
  return result;
}

}  // namespace clipray::page
