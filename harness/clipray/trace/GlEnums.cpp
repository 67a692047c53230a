// GL enums as apitrace writes them (GlEnums.hpp).

#include "clipray/trace/GlEnums.hpp"

#include <algorithm>
#include <cstdio>
#include <unordered_map>

#include "clipray/trace/DumpArguments.hpp"

namespace clipray::trace {

namespace {

const std::unordered_map<std::string_view, std::uint32_t>& enumNames() {
  static const std::unordered_map<std::string_view, std::uint32_t> names = {
      {"GL_FALSE", 0},
      {"GL_TRUE", kGlTrue},
      {"GL_NEVER", kGlNever},
      {"GL_LESS", kGlLess},
      {"GL_EQUAL", kGlEqual},
      {"GL_LEQUAL", kGlLequal},
      {"GL_GREATER", kGlGreater},
      {"GL_NOTEQUAL", kGlNotequal},
      {"GL_GEQUAL", kGlGequal},
      {"GL_ALWAYS", kGlAlways},
      {"GL_DEPTH_TEST", kGlDepthTest},
      {"GL_CULL_FACE", kGlCullFace},
      {"GL_DEPTH_CLAMP", kGlDepthClamp},
      {"GL_POLYGON_OFFSET_FILL", kGlPolygonOffsetFill},
      {"GL_CLIP_DISTANCE0", kGlClipDistance0},
      {"GL_CLIP_DISTANCE1", kGlClipDistance0 + 1},
      {"GL_CLIP_DISTANCE2", kGlClipDistance0 + 2},
      {"GL_CLIP_DISTANCE3", kGlClipDistance0 + 3},
      {"GL_CLIP_DISTANCE4", kGlClipDistance0 + 4},
      {"GL_CLIP_DISTANCE5", kGlClipDistance0 + 5},
      {"GL_CLIP_DISTANCE6", kGlClipDistance0 + 6},
      {"GL_CLIP_DISTANCE7", kGlClipDistance0 + 7},
      {"GL_FRONT", kGlFront},
      {"GL_BACK", kGlBack},
      {"GL_FRONT_AND_BACK", kGlFrontAndBack},
      {"GL_CW", kGlCw},
      {"GL_CCW", kGlCcw},
      {"GL_MODELVIEW", kGlModelview},
      {"GL_PROJECTION", kGlProjection},
      {"GL_TEXTURE", kGlTexture},
      {"GL_LOWER_LEFT", kGlLowerLeft},
      {"GL_UPPER_LEFT", kGlUpperLeft},
      {"GL_NEGATIVE_ONE_TO_ONE", kGlNegativeOneToOne},
      {"GL_ZERO_TO_ONE", kGlZeroToOne},
      {"GL_DEPTH_BUFFER_BIT", kGlDepthBufferBit},
      {"GL_DEPTH", kGlDepth},
      {"GL_DEPTH_STENCIL", kGlDepthStencil},
      {"GL_COMPILE", kGlCompile},
      {"GL_VERTEX_SHADER", kGlVertexShader},
      {"GL_FRAMEBUFFER", kGlFramebuffer},
      {"GL_READ_FRAMEBUFFER", kGlReadFramebuffer},
      {"GL_DRAW_FRAMEBUFFER", kGlDrawFramebuffer},
      {"GL_DEPTH_ATTACHMENT", kGlDepthAttachment},
      {"GL_DEPTH_STENCIL_ATTACHMENT", kGlDepthStencilAttachment},
      {"GL_DEPTH_COMPONENT16", kGlDepthComponent16},
      {"GL_DEPTH_COMPONENT24", kGlDepthComponent24},
      {"GL_DEPTH_COMPONENT32", kGlDepthComponent32},
      {"GL_DEPTH_COMPONENT32F", kGlDepthComponent32F},
      {"GL_DEPTH24_STENCIL8", kGlDepth24Stencil8},
      {"GL_DEPTH32F_STENCIL8", kGlDepth32FStencil8},
  };
  return names;
}

}  // namespace

int clipDistanceIndex(std::uint32_t cap) {
  return cap >= kGlClipDistance0 && cap < kGlClipDistance0 + kGlClipDistances
             ? static_cast<int>(cap - kGlClipDistance0)
             : -1;
}

std::uint32_t enumArgument(const DumpCall& call, std::string_view name) {
  const DumpValue& value = argument(call, name);
  const auto parsed = glEnumValue(value);
  return parsed ? *parsed : 0xFFFFFFFFu;  // an enum clipray does not know: matches none
}

bool maskHasBit(const DumpValue& value, std::uint64_t bit,
                std::initializer_list<std::string_view> names) {
  std::string_view text = value.text;
  while (!text.empty()) {
    const std::size_t bar = text.find(" | ");
    const std::string_view flag = text.substr(0, bar);
    if (std::find(names.begin(), names.end(), flag) != names.end()) return true;
    DumpValue single;
    single.text = std::string(flag);
    if (const auto number = single.number()) {
      if (*number >= 0.0 && *number <= 4294967295.0 &&
          (static_cast<std::uint64_t>(*number) & bit) != 0) {
        return true;
      }
    }
    if (bar == std::string_view::npos) break;
    text.remove_prefix(bar + 3);
  }
  return false;
}

std::optional<std::uint32_t> glEnumValue(const DumpValue& value) {
  if (value.isList || value.isString) return std::nullopt;
  const auto& names = enumNames();
  if (const auto found = names.find(value.text); found != names.end()) return found->second;
  // GL 1.0's name for GL_CLIP_DISTANCEi (kept out of the table so that each value has one name).
  if (value.text.size() == 14 && value.text.starts_with("GL_CLIP_PLANE") && value.text[13] >= '0' &&
      value.text[13] <= '5') {
    return kGlClipDistance0 + static_cast<std::uint32_t>(value.text[13] - '0');
  }
  if (const auto number = value.number()) {
    if (*number >= 0.0 && *number <= 4294967295.0) return static_cast<std::uint32_t>(*number);
  }
  return std::nullopt;
}

std::string glEnumName(std::uint32_t value) {
  for (const auto& [name, known] : enumNames()) {
    if (known == value && value > kGlTrue) return std::string(name);
  }
  char hex[16];
  std::snprintf(hex, sizeof hex, "0x%X", value);
  return hex;
}

}  // namespace clipray::trace
