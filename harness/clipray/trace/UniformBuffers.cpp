// Argument names are apitrace 11.1's (specs/glapi.py), as its dump writes them.

#include "clipray/trace/UniformBuffers.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <unordered_set>

#include "clipray/trace/DumpArguments.hpp"
#include "clipray/trace/FragDepthWrite.hpp"
#include "clipray/trace/GlEnums.hpp"

namespace clipray::trace {

namespace {

constexpr std::uint32_t kMat4Bytes = 64;

bool isUniformBufferTarget(const DumpValue& target) {
  if (target.text == "GL_UNIFORM_BUFFER") return true;
  const auto number = target.number();
  return number && *number == 0x8A11;  // GL_UNIFORM_BUFFER, where apitrace writes the number
}

// GLSL names are ASCII; a damaged trace's bytes must not reach the reports (JSON is UTF-8).
std::string printable(std::string text) {
  for (char& c : text) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7E) c = '?';
  }
  return text;
}

// The text of a string argument, or of a list of strings joined (glShaderSource's `string`).
std::string joinedStrings(const DumpValue& value) {
  if (value.isString) return value.text;
  std::string joined;
  for (const DumpValue& item : value.items) {
    if (item.isString) joined += item.text;
  }
  return joined;
}

}  // namespace

bool UniformBuffers::needs(std::string_view function) {
  // The ARB_shader_objects entry points at the end (GL 1.5 programs, and OpenSceneGraph's on
  // drivers without GL 2.0) are followed as their core twins, with the extension's argument names.
  static const std::unordered_set<std::string_view> functions = {
      "glBindBuffer",           "glBindBufferBase",         "glBindBufferRange",
      "glBindBuffersBase",      "glBindBuffersRange",       "glDeleteBuffers",
      "glBufferData",           "glNamedBufferData",        "glBufferStorage",
      "glNamedBufferStorage",   "glBufferSubData",          "glNamedBufferSubData",
      "glCopyBufferSubData",    "glCopyNamedBufferSubData", "glMapBuffer",
      "glMapBufferRange",       "glMapNamedBuffer",         "glMapNamedBufferRange",
      "glUnmapBuffer",          "glUnmapNamedBuffer",       "memcpy",
      "glShaderSource",         "glCreateShaderProgramv",   "glCreateShader",
      "glAttachShader",         "glDetachShader",           "glLinkProgram",
      "glGetUniformBlockIndex", "glUniformBlockBinding",    "glGetActiveUniformBlockName",
      "glShaderSourceARB",      "glCreateShaderObjectARB",  "glAttachObjectARB",
      "glDetachObjectARB",      "glLinkProgramARB"};
  return functions.contains(function);
}

std::uint32_t UniformBuffers::bufferAt(const DumpCall& call,
                                       std::string_view targetArgument) const {
  const auto found = targets_.find(argument(call, targetArgument).text);
  return found == targets_.end() ? 0u : found->second;
}

void UniformBuffers::note(const std::string& key, const std::string& message) {
  if (notedKeys_.contains(key) || notes_.size() >= kMaxUnreadNotes) return;
  notedKeys_.emplace(key, notes_.size());
  notes_.push_back(message);
}

std::optional<std::vector<std::uint8_t>> UniformBuffers::blobBytes(const DumpCall& call,
                                                                   const DumpValue& data,
                                                                   std::uint64_t size,
                                                                   std::string& why) const {
  const std::string where = call.name + " at call " + std::to_string(call.number);
  if (data.text == "NULL") {
    why = where + " gave no data";
    return std::nullopt;
  }
  const auto name = blobFileName(data);
  if (!name || !blobDirectory_) {
    why = where +
          ": the bytes are not in the dump text (they are only in the blob files of "
          "`apitrace dump --blobs`)";
    return std::nullopt;
  }
  std::ifstream file(*blobDirectory_ / *name, std::ios::binary);
  if (!file) {
    why = where + ": blob file " + *name + " is missing";
    return std::nullopt;
  }
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size) + 1);  // + 1: a longer file shows
  file.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  const auto got = static_cast<std::uint64_t>(file.gcount());
  if (got != size) {
    why = where + ": blob file " + *name + " holds " +
          (got > size ? std::string("more than ") : std::string()) +
          std::to_string(std::min(got, size)) + " bytes, not the " + std::to_string(size) +
          " written";
    return std::nullopt;
  }
  bytes.resize(static_cast<std::size_t>(size));
  return bytes;
}

void UniformBuffers::allocate(std::uint32_t buffer, std::uint64_t size, bool asUniform,
                              const DumpCall& call, const DumpValue& data) {
  if (buffer == 0) return;  // nothing bound: a GL error
  Buffer& target = buffers_[buffer];
  if (target.followed) followedBytes_ -= target.bytes.size();
  const bool uniform = target.uniform || asUniform;
  target = Buffer{};
  target.size = size;
  target.uniform = uniform;
  // Vertex and index data need not be held: a buffer is followed once it is a uniform buffer, or
  // (glNamedBuffer* of a DSA app, which binds it later) when it is no larger than a block can be.
  if (!uniform && !(call.name.starts_with("glNamed") && size <= kMaxUniformBlockBytes)) return;
  follow(buffer, call.name + " at call " + std::to_string(call.number) + " gave no data");
  write(buffer, 0, size, call, data);
}

void UniformBuffers::followFromNowOn(std::uint32_t buffer, const DumpCall& call) {
  const auto found = buffers_.find(buffer);
  if (found == buffers_.end()) {
    buffers_[buffer].uniform = true;  // no data store yet: followed from its glBufferData on
  } else if (!found->second.uniform) {
    follow(buffer, "its data was written before " + call.name + " at call " +
                       std::to_string(call.number) + " made it a uniform buffer");
  }
}

void UniformBuffers::follow(std::uint32_t buffer, const std::string& unwrittenWhy) {
  Buffer& target = buffers_[buffer];
  target.uniform = true;
  if (target.followed || target.size > kMaxFollowedBufferBytes ||
      followedBytes_ + target.size > kMaxFollowedBufferTotal) {
    return;  // noted when a block reads from it
  }
  target.followed = true;
  target.bytes.assign(static_cast<std::size_t>(target.size), 0);
  target.written.assign(static_cast<std::size_t>(target.size), false);
  target.unwrittenWhy = unwrittenWhy;
  followedBytes_ += target.size;
}

void UniformBuffers::write(std::uint32_t buffer, std::uint64_t offset, std::uint64_t size,
                           const DumpCall& call, const DumpValue& data) {
  const auto found = buffers_.find(buffer);
  if (found == buffers_.end() || !found->second.followed || size == 0) return;
  Buffer& target = found->second;
  if (offset > target.size || size > target.size - offset) return;  // a GL error: no effect
  const auto begin = static_cast<std::ptrdiff_t>(offset);
  const auto end = static_cast<std::ptrdiff_t>(offset + size);
  const auto bytes = blobBytes(call, data, size, target.unwrittenWhy);
  if (!bytes) {
    std::fill(target.written.begin() + begin, target.written.begin() + end, false);
    return;
  }
  std::copy(bytes->begin(), bytes->end(), target.bytes.begin() + begin);
  std::fill(target.written.begin() + begin, target.written.begin() + end, true);
}

void UniformBuffers::link(std::uint32_t program) {
  std::vector<LinkedBlock>& blocks = programBlocks_[program];
  blocks.clear();
  std::erase_if(blockIndexNames_, [&](const auto& entry) { return entry.first.first == program; });
  programsWritingClipDistance_.erase(program);
  programsWritingFragDepth_.erase(program);
  programsFixedFunction_.erase(program);
  const std::vector<std::uint32_t>& attached = attachedShaders_[program];
  bool typesKnown = !attached.empty(), hasVertexShader = false;
  for (const std::uint32_t shader : attached) {
    const auto type = shaderTypes_.find(shader);
    typesKnown = typesKnown && type != shaderTypes_.end();
    hasVertexShader =
        hasVertexShader || (type != shaderTypes_.end() && type->second == kGlVertexShader);
  }
  if (typesKnown && !hasVertexShader) programsFixedFunction_[program] = "it has no vertex shader";
  for (const std::uint32_t shader : attached) {
    const auto source = shaderSources_.find(shader);
    if (source == shaderSources_.end()) continue;
    if (mentionsClipDistance(source->second)) programsWritingClipDistance_.insert(program);
    if (trace::writesFragDepth(source->second)) programsWritingFragDepth_.insert(program);
    const auto type = shaderTypes_.find(shader);
    const bool vertexStage = type == shaderTypes_.end() || type->second == kGlVertexShader;
    if (const std::string read = fixedFunctionTransformRead(source->second);
        vertexStage && !read.empty() && !programsFixedFunction_.contains(program)) {
      programsFixedFunction_[program] = read == "ftransform()"
                                            ? "its vertex shader calls ftransform()"
                                            : "its vertex shader reads " + read;
    }
    for (UniformBlockDeclaration& declaration : parseUniformBlocks(source->second)) {
      // One block seen by several stages is one block of the program.
      const bool known = std::any_of(blocks.begin(), blocks.end(), [&](const LinkedBlock& b) {
        return b.declaration.blockName == declaration.blockName;
      });
      if (known) continue;
      const std::uint32_t binding = declaration.binding.value_or(0);
      blocks.push_back({std::move(declaration), binding});
    }
  }
}

void UniformBuffers::bindBuffer(const DumpCall& call) {
  const std::uint32_t buffer = objectArgument(call, "buffer");
  targets_[argument(call, "target").text] = buffer;
  if (buffer != 0 && isUniformBufferTarget(argument(call, "target"))) {
    followFromNowOn(buffer, call);
  }
}

void UniformBuffers::bindBufferBaseOrRange(const DumpCall& call) {
  const std::uint32_t buffer = objectArgument(call, "buffer");
  targets_[argument(call, "target").text] = buffer;
  if (!isUniformBufferTarget(argument(call, "target"))) return;
  if (buffer != 0) followFromNowOn(buffer, call);
  Range range{buffer, 0, std::nullopt};
  if (call.name == "glBindBufferRange") {
    range.offset = byteArgument(call, "offset");
    range.size = byteArgument(call, "size");
  }
  uniformBindings_[objectArgument(call, "index")] = range;
}

void UniformBuffers::bindBuffersBaseOrRange(const DumpCall& call) {
  // GL 4.4 multi-bind: bindings first .. first + count - 1; buffers = NULL unbinds them all.
  if (!isUniformBufferTarget(argument(call, "target"))) return;
  const std::uint32_t first = objectArgument(call, "first");
  const std::uint32_t count = objectArgument(call, "count");
  const bool ranged = call.name == "glBindBuffersRange";
  const bool none = argument(call, "buffers").text == "NULL";
  const std::vector<double> buffers = none ? std::vector<double>{} : numbers(call, "buffers");
  const std::vector<double> offsets = ranged && !none ? numbers(call, "offsets") : buffers;
  const std::vector<double> sizes = ranged && !none ? numbers(call, "sizes") : buffers;
  if (!none && (buffers.size() != count || offsets.size() != count || sizes.size() != count)) {
    throw std::invalid_argument(call.name + ": count = " + std::to_string(count) +
                                " but the arrays hold other numbers of values");
  }
  const auto wholeNumber = [&](double value, std::string_view what, double most) {
    if (!(value >= 0.0 && value <= most) || value != std::floor(value)) {
      throw std::invalid_argument(call.name + ": " + std::string(what) +
                                  " holds a value out of range");
    }
    return static_cast<std::uint64_t>(value);
  };
  for (std::uint32_t k = 0; k < count && k < kMaxMultiBindCount; ++k) {
    const std::uint32_t buffer =
        none ? 0u : static_cast<std::uint32_t>(wholeNumber(buffers[k], "buffers", 4294967295.0));
    if (buffer != 0) followFromNowOn(buffer, call);
    Range range{buffer, 0, std::nullopt};
    if (ranged && !none) {
      range.offset = wholeNumber(offsets[k], "offsets", 9007199254740992.0);
      range.size = wholeNumber(sizes[k], "sizes", 9007199254740992.0);
    }
    uniformBindings_[first + k] = range;
  }
}

void UniformBuffers::deleteBuffers(const DumpCall& call) {
  for (const double deleted : numbers(call, "buffers")) {
    if (!(deleted > 0.0 && deleted <= 4294967295.0)) continue;  // 0 and non-names: ignored
    const auto buffer = static_cast<std::uint32_t>(deleted);
    const auto found = buffers_.find(buffer);
    if (found != buffers_.end()) {
      if (found->second.followed) followedBytes_ -= found->second.bytes.size();
      buffers_.erase(found);
    }
    // Deleting a bound buffer unbinds it (OpenGL 4.6, 6.1.1); its name may come back new.
    std::erase_if(targets_, [&](const auto& entry) { return entry.second == buffer; });
    std::erase_if(uniformBindings_,
                  [&](const auto& entry) { return entry.second.buffer == buffer; });
    std::erase_if(mappings_, [&](const auto& entry) { return entry.second.buffer == buffer; });
  }
}

void UniformBuffers::copyBufferSubData(const DumpCall& call) {
  const bool named = call.name == "glCopyNamedBufferSubData";
  const std::uint32_t from =
      named ? objectArgument(call, "readBuffer") : bufferAt(call, "readTarget");
  const std::uint32_t to =
      named ? objectArgument(call, "writeBuffer") : bufferAt(call, "writeTarget");
  const std::uint64_t readOffset = byteArgument(call, "readOffset");
  const std::uint64_t writeOffset = byteArgument(call, "writeOffset");
  const std::uint64_t size = byteArgument(call, "size");
  const auto source = buffers_.find(from), destination = buffers_.find(to);
  if (destination == buffers_.end() || !destination->second.followed) return;
  Buffer& target = destination->second;
  if (writeOffset > target.size || size > target.size - writeOffset) return;
  const auto begin = static_cast<std::ptrdiff_t>(writeOffset);
  const auto end = static_cast<std::ptrdiff_t>(writeOffset + size);
  if (source == buffers_.end() || !source->second.followed || readOffset > source->second.size ||
      size > source->second.size - readOffset) {
    std::fill(target.written.begin() + begin, target.written.begin() + end, false);
    target.unwrittenWhy = call.name + " at call " + std::to_string(call.number) +
                          " copied from a buffer whose bytes clipray does not hold";
    return;
  }
  // Through a copy: source and destination may be the same buffer, overlapping.
  const Buffer& origin = source->second;
  const auto readBegin = static_cast<std::ptrdiff_t>(readOffset);
  const std::vector<std::uint8_t> bytes(origin.bytes.begin() + readBegin,
                                        origin.bytes.begin() + readBegin + (end - begin));
  const std::vector<bool> written(origin.written.begin() + readBegin,
                                  origin.written.begin() + readBegin + (end - begin));
  std::copy(bytes.begin(), bytes.end(), target.bytes.begin() + begin);
  std::copy(written.begin(), written.end(), target.written.begin() + begin);
}

void UniformBuffers::mapBuffer(const DumpCall& call) {
  const std::string_view name = call.name;
  const bool named = name.starts_with("glMapNamed");
  const std::uint32_t buffer = named ? objectArgument(call, "buffer") : bufferAt(call, "target");
  if (!call.result || call.result->text == "NULL") return;
  const std::uint64_t address = byteValue(call, "the result", *call.result);
  const bool ranged = name.ends_with("Range");
  const auto found = buffers_.find(buffer);
  const std::uint64_t size = found == buffers_.end() ? 0 : found->second.size;
  const std::uint64_t offset = ranged ? byteArgument(call, "offset") : 0;
  const std::uint64_t length = ranged ? byteArgument(call, "length") : size;
  std::erase_if(mappings_, [&](const auto& entry) { return entry.second.buffer == buffer; });
  mappings_[address] = {buffer, offset, length};
}

void UniformBuffers::unmapBuffer(const DumpCall& call) {
  const std::uint32_t buffer =
      call.name == "glUnmapNamedBuffer" ? objectArgument(call, "buffer") : bufferAt(call, "target");
  std::erase_if(mappings_, [&](const auto& entry) { return entry.second.buffer == buffer; });
}

void UniformBuffers::writeMapped(const DumpCall& call) {
  const std::uint64_t destination = byteArgument(call, "dest");
  const std::uint64_t size = byteArgument(call, "n");
  auto found = mappings_.upper_bound(destination);
  if (found == mappings_.begin()) return;
  --found;
  const Mapping& mapping = found->second;
  const std::uint64_t into = destination - found->first;
  if (into > mapping.length || size > mapping.length - into) return;
  write(mapping.buffer, mapping.offset + into, size, call, argument(call, "src"));
}

void UniformBuffers::createShaderProgram(const DumpCall& call) {
  const auto program = call.result ? call.result->number() : std::nullopt;
  if (!program || *program <= 0.0 || *program > 4294967295.0) return;
  const auto id = static_cast<std::uint32_t>(*program);
  // A separable program of one shader: keyed apart from glCreateShader's names.
  const std::uint32_t shader = 0xFFFFFFFFu - id;
  shaderSources_[shader] = joinedStrings(argument(call, "strings"));
  shaderTypes_[shader] = enumArgument(call, "type");
  attachedShaders_[id] = {shader};
  link(id);
}

void UniformBuffers::nameBlockIndex(const DumpCall& call) {
  if (call.name == "glGetActiveUniformBlockName") {
    // The name behind an index the app enumerated (0 to GL_ACTIVE_UNIFORM_BLOCKS - 1), as
    // OpenSceneGraph's osg::Program does: the index is the argument, the name the result.
    blockIndexNames_[{objectArgument(call, "program"), objectArgument(call, "uniformBlockIndex")}] =
        argument(call, "uniformBlockName").text;
    return;
  }
  const auto index = call.result ? call.result->number() : std::nullopt;
  if (!index || *index < 0.0 || *index >= 4294967295.0) return;  // GL_INVALID_INDEX
  blockIndexNames_[{objectArgument(call, "program"), static_cast<std::uint32_t>(*index)}] =
      argument(call, "uniformBlockName").text;
}

void UniformBuffers::bindUniformBlock(const DumpCall& call) {
  const std::uint32_t program = objectArgument(call, "program");
  const std::uint32_t index = objectArgument(call, "uniformBlockIndex");
  const std::uint32_t binding = objectArgument(call, "uniformBlockBinding");
  const auto named = blockIndexNames_.find({program, index});
  if (named == blockIndexNames_.end()) {
    note("unknown-block-index-" + std::to_string(program),
         "glUniformBlockBinding at call " + std::to_string(call.number) + ": block index " +
             std::to_string(index) + " of program " + std::to_string(program) +
             " was not named by glGetUniformBlockIndex or glGetActiveUniformBlockName in the "
             "trace: that block's binding is unknown");
    return;
  }
  for (LinkedBlock& block : programBlocks_[program]) {
    if (block.declaration.blockName == named->second) block.binding = binding;
  }
}

void UniformBuffers::apply(const DumpCall& call) {
  const std::string_view name = call.name;
  // ARB_shader_objects names its arguments after GLhandleARB objects (apitrace's glapi.py, after
  // the extension's specification): shaderObj, containerObj, obj, programObj.
  const bool arb = name.ends_with("ARB");
  if (name == "glBindBuffer") {
    bindBuffer(call);
  } else if (name == "glBindBufferBase" || name == "glBindBufferRange") {
    bindBufferBaseOrRange(call);
  } else if (name == "glBindBuffersBase" || name == "glBindBuffersRange") {
    bindBuffersBaseOrRange(call);
  } else if (name == "glDeleteBuffers") {
    deleteBuffers(call);
  } else if (name == "glBufferData" || name == "glBufferStorage") {
    allocate(bufferAt(call, "target"), byteArgument(call, "size"),
             isUniformBufferTarget(argument(call, "target")), call, argument(call, "data"));
  } else if (name == "glNamedBufferData" || name == "glNamedBufferStorage") {
    allocate(objectArgument(call, "buffer"), byteArgument(call, "size"), false, call,
             argument(call, "data"));
  } else if (name == "glBufferSubData") {
    write(bufferAt(call, "target"), byteArgument(call, "offset"), byteArgument(call, "size"), call,
          argument(call, "data"));
  } else if (name == "glNamedBufferSubData") {
    write(objectArgument(call, "buffer"), byteArgument(call, "offset"), byteArgument(call, "size"),
          call, argument(call, "data"));
  } else if (name == "glCopyBufferSubData" || name == "glCopyNamedBufferSubData") {
    copyBufferSubData(call);
  } else if (name.starts_with("glMap")) {
    mapBuffer(call);
  } else if (name == "glUnmapBuffer" || name == "glUnmapNamedBuffer") {
    unmapBuffer(call);
  } else if (name == "memcpy") {
    writeMapped(call);
  } else if (name == "glShaderSource" || name == "glShaderSourceARB") {
    shaderSources_[objectArgument(call, arb ? "shaderObj" : "shader")] =
        joinedStrings(argument(call, "string"));
  } else if (name == "glCreateShaderProgramv") {
    createShaderProgram(call);
  } else if (name == "glCreateShader" || name == "glCreateShaderObjectARB") {
    const auto shader = call.result ? call.result->number() : std::nullopt;
    if (shader && *shader > 0.0 && *shader <= 4294967295.0) {
      shaderTypes_[static_cast<std::uint32_t>(*shader)] =
          enumArgument(call, arb ? "shaderType" : "type");
    }
  } else if (name == "glAttachShader" || name == "glAttachObjectARB") {
    attachedShaders_[objectArgument(call, arb ? "containerObj" : "program")].push_back(
        objectArgument(call, arb ? "obj" : "shader"));
  } else if (name == "glDetachShader" || name == "glDetachObjectARB") {
    std::erase(attachedShaders_[objectArgument(call, arb ? "containerObj" : "program")],
               objectArgument(call, arb ? "attachedObj" : "shader"));
  } else if (name == "glLinkProgram" || name == "glLinkProgramARB") {
    link(objectArgument(call, arb ? "programObj" : "program"));
  } else if (name == "glGetUniformBlockIndex" || name == "glGetActiveUniformBlockName") {
    nameBlockIndex(call);
  } else if (name == "glUniformBlockBinding") {
    bindUniformBlock(call);
  }
}

std::vector<UniformBlockMatrix> UniformBuffers::matrices(std::uint32_t program,
                                                         std::uint64_t drawCall) {
  std::vector<UniformBlockMatrix> result;
  const auto blocks = programBlocks_.find(program);
  if (blocks == programBlocks_.end()) return result;
  const std::string ofProgram = " (program " + std::to_string(program) + ")";
  for (const LinkedBlock& block : blocks->second) {
    const UniformBlockDeclaration& declaration = block.declaration;
    const std::string blockName = "ubo " + printable(declaration.blockName);
    const std::string key = std::to_string(program) + "|" + declaration.blockName + "|";
    const std::string atDraw = " (first at the draw at call " + std::to_string(drawCall) + ")";
    for (const BlockMember& member : declaration.members) {
      if (member.type != "mat4") continue;  // only a mat4 is a candidate projection
      const std::string memberName = blockName + "." + printable(member.name);
      if (declaration.layout != BlockLayout::kStd140) {
        note(key + "layout",
             blockName + ofProgram + ": " + std::string(blockLayoutName(declaration.layout)) +
                 " layout: its offsets are the implementation's (apitrace records an app's "
                 "GL_UNIFORM_OFFSET query without its result), so its matrices are not read" +
                 atDraw);
        break;
      }
      if (!member.offset) {
        note(key + "offsets",
             memberName + ofProgram + ": not read: " + declaration.offsetsStop + atDraw);
        break;
      }
      const auto bound = uniformBindings_.find(block.binding);
      if (bound == uniformBindings_.end() || bound->second.buffer == 0) {
        note(key + "unbound", blockName + ofProgram +
                                  ": no buffer bound to uniform buffer binding " +
                                  std::to_string(block.binding) + atDraw);
        break;
      }
      const Range& range = bound->second;
      const auto buffer = buffers_.find(range.buffer);
      if (buffer == buffers_.end() || !buffer->second.followed) {
        note(key + "unfollowed",
             blockName + ofProgram + ": buffer " + std::to_string(range.buffer) +
                 (buffer == buffers_.end()
                      ? std::string(" has no data store in the trace")
                      : " (" + std::to_string(buffer->second.size) +
                            " bytes) is beyond the buffer sizes clipray follows") +
                 atDraw);
        break;
      }
      const Buffer& data = buffer->second;
      if (range.offset >= data.size) {
        note(key + "offset", blockName + ofProgram + ": the range bound at binding " +
                                 std::to_string(block.binding) + " starts at byte " +
                                 std::to_string(range.offset) + ", past the end of buffer " +
                                 std::to_string(range.buffer) + " (" + std::to_string(data.size) +
                                 " bytes)" + atDraw);
        break;
      }
      // Written so that no sum can wrap: every offset below stays under the buffer's size plus
      // a block's.
      const std::uint64_t rangeEnd = range.size && *range.size < data.size - range.offset
                                         ? range.offset + *range.size
                                         : data.size;
      const std::uint32_t count =
          member.arraySize == 0 ? 1 : std::min(member.arraySize, kMaxMatricesPerArray);
      for (std::uint32_t element = 0; element < count; ++element) {
        std::string elementName = memberName;
        if (member.arraySize != 0) {
          elementName += '[';
          elementName += std::to_string(element);
          elementName += ']';
        }
        const std::uint64_t at = range.offset + *member.offset +
                                 std::uint64_t{element} * std::max(member.arrayStride, kMat4Bytes);
        if (at + kMat4Bytes > rangeEnd) {
          note(key + elementName + "|short",
               elementName + ofProgram + ": the bound range of buffer " +
                   std::to_string(range.buffer) + " ends at byte " +
                   std::to_string(rangeEnd - std::min(rangeEnd, range.offset)) +
                   " of the block, before the matrix (bytes " + std::to_string(at - range.offset) +
                   " to " + std::to_string(at - range.offset + kMat4Bytes) + ")" + atDraw);
          break;
        }
        const auto begin = data.written.begin() + static_cast<std::ptrdiff_t>(at);
        if (!std::all_of(begin, begin + kMat4Bytes, [](bool written) { return written; })) {
          note(key + elementName + "|unwritten",
               elementName + ofProgram + ": buffer " + std::to_string(range.buffer) +
                   " holds bytes the trace does not show here (" +
                   (data.unwrittenWhy.empty() ? std::string("never written")
                                              : "last: " + data.unwrittenWhy) +
                   ")" + atDraw);
          continue;
        }
        float values[16];
        std::memcpy(values, data.bytes.data() + at, sizeof values);
        UniformBlockMatrix read{elementName + ofProgram, glm::dmat4(0.0)};
        for (int column = 0; column < 4; ++column) {
          for (int row = 0; row < 4; ++row) {
            read.matrix[column][row] =
                member.rowMajor ? values[row * 4 + column] : values[column * 4 + row];
          }
        }
        result.push_back(std::move(read));
      }
    }
  }
  return result;
}

}  // namespace clipray::trace
