// The fixed-function matrices follow the OpenGL 2.1 specification, section 2.11.2 (glFrustum,
// glOrtho, glRotate, glTranslate, glScale), rounded to float after each operation as Mesa stores
// them (mesa/mesa, src/mesa/math/m_matrix.c: GLfloat matrices).

#include "clipray/trace/GlTraceState.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "clipray/trace/DumpArguments.hpp"

namespace clipray::trace {

namespace {

using namespace std::string_view_literals;

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

std::uint32_t enumArgument(const DumpCall& call, std::string_view name) {
  const DumpValue& value = argument(call, name);
  const auto parsed = glEnumValue(value);
  return parsed ? *parsed : 0xFFFFFFFFu;  // an enum clipray does not know: matches none
}

// Whether a bitmask as apitrace writes it ("GL_DEPTH_BUFFER_BIT | GL_COLOR_BUFFER_BIT", "0x100")
// holds `bit`, which the flags named in `names` include.
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

bool maskHasDepthBit(const DumpValue& value) {
  return maskHasBit(value, kGlDepthBufferBit, {"GL_DEPTH_BUFFER_BIT"sv});
}

// glUseProgramStages' stages: GL_VERTEX_SHADER_BIT is 0x1; GL_ALL_SHADER_BITS includes it.
bool stagesHaveVertexShader(const DumpValue& value) {
  return maskHasBit(value, 0x1u, {"GL_VERTEX_SHADER_BIT"sv, "GL_ALL_SHADER_BITS"sv});
}

glm::dmat4 columnMajor(const double* values, bool transpose) {
  glm::dmat4 matrix(0.0);
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) matrix[column][row] = values[column * 4 + row];
  }
  return transpose ? glm::transpose(matrix) : matrix;
}

glm::dmat4 roundedToFloat(glm::dmat4 matrix) {
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) {
      matrix[column][row] = static_cast<double>(static_cast<float>(matrix[column][row]));
    }
  }
  return matrix;
}

glm::dmat4 matrixArgument(const DumpCall& call, bool transpose) {
  const std::vector<double> values = numbers(call, "m");
  if (values.size() != 16) {
    throw std::invalid_argument(call.name + ": m holds " + std::to_string(values.size()) +
                                " numbers, not 16");
  }
  return columnMajor(values.data(), transpose);
}

// OpenGL 2.1, 2.11.2: glFrustum. Built for NEGATIVE_ONE_TO_ONE: near -> z_ndc -1, far -> 1.
glm::dmat4 frustum(double l, double r, double b, double t, double n, double f) {
  glm::dmat4 m(0.0);
  m[0][0] = 2.0 * n / (r - l);
  m[1][1] = 2.0 * n / (t - b);
  m[2][0] = (r + l) / (r - l);
  m[2][1] = (t + b) / (t - b);
  m[2][2] = -(f + n) / (f - n);
  m[2][3] = -1.0;
  m[3][2] = -2.0 * f * n / (f - n);
  return m;
}

// OpenGL 2.1, 2.11.2: glOrtho, also NEGATIVE_ONE_TO_ONE.
glm::dmat4 ortho(double l, double r, double b, double t, double n, double f) {
  glm::dmat4 m(1.0);
  m[0][0] = 2.0 / (r - l);
  m[1][1] = 2.0 / (t - b);
  m[2][2] = -2.0 / (f - n);
  m[3][0] = -(r + l) / (r - l);
  m[3][1] = -(t + b) / (t - b);
  m[3][2] = -(f + n) / (f - n);
  return m;
}

// OpenGL 2.1, 2.11.2: glRotate, angle in degrees about the normalized axis.
glm::dmat4 rotation(double degrees, glm::dvec3 axis) {
  const double length = glm::length(axis);
  if (length == 0.0) return glm::dmat4(1.0);
  axis /= length;
  const double radians = degrees * 3.14159265358979323846 / 180.0;
  const double c = std::cos(radians), s = std::sin(radians), k = 1.0 - c;
  const double x = axis.x, y = axis.y, z = axis.z;
  glm::dmat4 m(1.0);
  m[0][0] = x * x * k + c;
  m[1][0] = x * y * k - z * s;
  m[2][0] = x * z * k + y * s;
  m[0][1] = y * x * k + z * s;
  m[1][1] = y * y * k + c;
  m[2][1] = y * z * k - x * s;
  m[0][2] = x * z * k - y * s;
  m[1][2] = y * z * k + x * s;
  m[2][2] = z * z * k + c;
  return m;
}

// The binding a texture target names: a cube map's faces are set through its face targets.
std::string textureTarget(const std::string& target) {
  return target.starts_with("GL_TEXTURE_CUBE_MAP_") && !target.starts_with("GL_TEXTURE_CUBE_MAP_A")
             ? std::string("GL_TEXTURE_CUBE_MAP")
             : target;
}

bool isDraw(std::string_view name) {
  if (name.starts_with("glDrawBuffer") || name.starts_with("glDrawPixels")) return false;
  return name.starts_with("glDraw") || name.starts_with("glMultiDraw") || name == "glBegin" ||
         name == "glCallList" || name == "glCallLists";
}

bool endsFrame(std::string_view name) {
  return name == "eglSwapBuffers" || name == "eglSwapBuffersWithDamageKHR" ||
         name == "eglSwapBuffersWithDamageEXT" || name == "glXSwapBuffers" ||
         name == "wglSwapBuffers" || name == "wglSwapLayerBuffers" || name == "CGLFlushDrawable" ||
         name == "glFrameTerminatorGREMEDY";
}

const std::unordered_set<std::string_view>& stateFunctions() {
  static const std::unordered_set<std::string_view> functions = [] {
    std::unordered_set<std::string_view> table;
    for (std::string_view name : {"glNewList",
                                  "glEndList",
                                  "glClipControl",
                                  "glEnable",
                                  "glDisable",
                                  "glDepthFunc",
                                  "glCullFace",
                                  "glFrontFace",
                                  "glDepthRange",
                                  "glDepthRangef",
                                  "glDepthRangeIndexed",
                                  "glClearDepth",
                                  "glClearDepthf",
                                  "glClear",
                                  "glClearBufferfv",
                                  "glClearBufferfi",
                                  "glClearNamedFramebufferfv",
                                  "glClearNamedFramebufferfi",
                                  "glViewport",
                                  "glUseProgram",
                                  "glUseProgramObjectARB",
                                  "glBindProgramPipeline",
                                  "glUseProgramStages",
                                  "glActiveShaderProgram",
                                  "glLinkProgram",
                                  "glLinkProgramARB",
                                  "glGetUniformLocation",
                                  "glGetUniformLocationARB",
                                  "glUniformMatrix4fv",
                                  "glUniformMatrix4fvARB",
                                  "glUniformMatrix4dv",
                                  "glProgramUniformMatrix4fv",
                                  "glProgramUniformMatrix4fvEXT",
                                  "glProgramUniformMatrix4dv",
                                  "glMatrixMode",
                                  "glLoadIdentity",
                                  "glLoadMatrixf",
                                  "glLoadMatrixd",
                                  "glMultMatrixf",
                                  "glMultMatrixd",
                                  "glLoadTransposeMatrixf",
                                  "glLoadTransposeMatrixd",
                                  "glMultTransposeMatrixf",
                                  "glMultTransposeMatrixd",
                                  "glFrustum",
                                  "glOrtho",
                                  "glTranslatef",
                                  "glTranslated",
                                  "glRotatef",
                                  "glRotated",
                                  "glScalef",
                                  "glScaled",
                                  "glPushMatrix",
                                  "glPopMatrix",
                                  "glBindFramebuffer",
                                  "glBindFramebufferEXT",
                                  "glBindRenderbuffer",
                                  "glBindRenderbufferEXT",
                                  "glRenderbufferStorage",
                                  "glRenderbufferStorageEXT",
                                  "glRenderbufferStorageMultisample",
                                  "glNamedRenderbufferStorage",
                                  "glNamedRenderbufferStorageMultisample",
                                  "glFramebufferRenderbuffer",
                                  "glFramebufferRenderbufferEXT",
                                  "glNamedFramebufferRenderbuffer",
                                  "glFramebufferTexture",
                                  "glFramebufferTexture2D",
                                  "glFramebufferTexture2DEXT",
                                  "glNamedFramebufferTexture",
                                  "glFramebufferTextureLayer",
                                  "glNamedFramebufferTextureLayer",
                                  "glActiveTexture",
                                  "glBindTexture",
                                  "glTexImage2D",
                                  "glTexImage3D",
                                  "glTexImage2DMultisample",
                                  "glTexStorage2D",
                                  "glTexStorage3D",
                                  "glTexStorage2DMultisample",
                                  "glTextureStorage2D",
                                  "glTextureStorage3D",
                                  "glTextureStorage2DMultisample"}) {
      table.insert(name);
    }
    return table;
  }();
  return functions;
}

std::string formatNameOf(std::uint32_t internalFormat) {
  switch (internalFormat) {
    case kGlDepthComponent16:
      return "16";
    case kGlDepthComponent24:
    case kGlDepth24Stencil8:
      return "24";
    case kGlDepthComponent32F:
    case kGlDepth32FStencil8:
      return "32f";
    case kGlDepthComponent32:
      return "32";
    default:
      return "unknown";
  }
}

}  // namespace

std::optional<std::uint32_t> glEnumValue(const DumpValue& value) {
  if (value.isList || value.isString) return std::nullopt;
  const auto& names = enumNames();
  if (const auto found = names.find(value.text); found != names.end()) return found->second;
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

std::string TraceDepthState::key() const {
  char text[256];
  std::snprintf(text, sizeof text, "%d%d%d %u %a %a %a %d %dx%d %s %d %u %u", clipZeroToOne,
                clipUpperLeft, depthTest, depthFunc, depthRange.x, depthRange.y,
                clearedDepth ? *clearedDepth : -1.0, clearedDepth.has_value(), viewport.width,
                viewport.height, depthFormatName.c_str(), cullFace, cullFaceMode, frontFace);
  return text;
}

bool hasProjectionStructure(const glm::dmat4& m) {
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) {
      if (!std::isfinite(m[column][row])) return false;
    }
  }
  // Singular to float precision (|det| against the product of the row lengths, which bounds it):
  // a planar shadow projection (rank 3, as glmark2's "ideas" scene multiplies into its modelview)
  // projects onto a plane and is no camera. 64 float roundings: far below any camera's ratio
  // short of a near plane a million times smaller than the scene's units.
  double rowLengths = 1.0;
  for (int row = 0; row < 4; ++row) {
    rowLengths *= glm::length(glm::dvec4(m[0][row], m[1][row], m[2][row], m[3][row]));
  }
  if (!(std::abs(glm::determinant(m)) > 64.0 * 0x1p-24 * rowLengths)) return false;
  const bool perspective = m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0;
  const glm::dmat3 linear(m);
  if (perspective) {
    // A normal matrix, transpose(inverse(modelView)) as a mat4, has the modelview's translation
    // in row 3 and none in column 3: the transpose of an orientation-preserving affine map, no
    // camera. (A perspective projection maps depth through column 3: z_clip = a z + b w, b != 0.)
    const bool transposedAffine = m[3][0] == 0.0 && m[3][1] == 0.0 && m[3][2] == 0.0 &&
                                  m[3][3] != 0.0 && glm::determinant(linear) > 0.0;
    return !transposedAffine;
  }
  if (glm::determinant(linear) >= 0.0) return false;
  // A mirrored model or view matrix (a reflection, scale(1, -1, 1)) also reverses orientation,
  // but it scales every direction alike: its columns are orthogonal and of one length. An
  // orthographic projection scales x, y and depth by 2/width, 2/height and 2/depth, which differ
  // unless its view volume is a cube (glOrtho(-1, 1, -1, 1, -1, 1)). Such a cube volume is told
  // from a mirror by glOrtho's own shape: on-axis, with z alone flipped (x and y kept), where a
  // reflection in a floor or wall flips x or y. (A model matrix scale(1, 1, -1) has that shape
  // too and is taken for a projection; a cube volume times a rotating view is still missed.)
  const glm::dmat3 gram = glm::transpose(linear) * linear;
  const double scale = (gram[0][0] + gram[1][1] + gram[2][2]) / 3.0;
  const double tolerance = 1e-5 * scale;  // 7-digit decimals of the dump
  bool similarity = true;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (std::abs(gram[i][j] - (i == j ? scale : 0.0)) > tolerance) similarity = false;
    }
  }
  if (!similarity) return true;
  const bool onAxis = std::abs(linear[0][1]) + std::abs(linear[0][2]) + std::abs(linear[1][0]) +
                          std::abs(linear[1][2]) + std::abs(linear[2][0]) +
                          std::abs(linear[2][1]) <=
                      1e-5 * std::sqrt(scale);
  return onAxis && linear[0][0] > 0.0 && linear[1][1] > 0.0 && linear[2][2] < 0.0;
}

bool GlTraceState::needs(std::string_view function) {
  return isDraw(function) || endsFrame(function) || stateFunctions().contains(function) ||
         UniformBuffers::needs(function);
}

glm::dmat4& GlTraceState::stackTop(std::uint32_t mode) {
  std::vector<glm::dmat4>& stack = stacks_[mode];
  if (stack.empty()) stack.emplace_back(1.0);
  return stack.back();
}

void GlTraceState::updateDepthFormat() {
  const auto found = framebufferDepth_.find(drawFramebuffer_);
  const std::uint32_t format = found == framebufferDepth_.end() ? 0u : found->second;
  depth_.depthFormatName = formatNameOf(format);
  depth_.depthFormat = parseDepthFormat(depth_.depthFormatName);
}

void GlTraceState::applyMatrixStack(const DumpCall& call) {
  const std::string_view name = call.name;
  if (name == "glMatrixMode") {
    matrixMode_ = enumArgument(call, "mode");
    return;
  }
  glm::dmat4& top = stackTop(matrixMode_);
  const auto multiplyBy = [&](const glm::dmat4& m) { top = roundedToFloat(top * m); };
  if (name == "glLoadIdentity") {
    top = glm::dmat4(1.0);
  } else if (name == "glLoadMatrixf" || name == "glLoadMatrixd") {
    top = roundedToFloat(matrixArgument(call, false));
  } else if (name == "glLoadTransposeMatrixf" || name == "glLoadTransposeMatrixd") {
    top = roundedToFloat(matrixArgument(call, true));
  } else if (name == "glMultMatrixf" || name == "glMultMatrixd") {
    multiplyBy(matrixArgument(call, false));
  } else if (name == "glMultTransposeMatrixf" || name == "glMultTransposeMatrixd") {
    multiplyBy(matrixArgument(call, true));
  } else if (name == "glFrustum" || name == "glOrtho") {
    const double l = numberArgument(call, "left"), r = numberArgument(call, "right");
    const double b = numberArgument(call, "bottom"), t = numberArgument(call, "top");
    const double n = numberArgument(call, "zNear"), f = numberArgument(call, "zFar");
    multiplyBy(name == "glFrustum" ? frustum(l, r, b, t, n, f) : ortho(l, r, b, t, n, f));
  } else if (name == "glTranslatef" || name == "glTranslated") {
    glm::dmat4 m(1.0);
    m[3] = glm::dvec4(numberArgument(call, "x"), numberArgument(call, "y"),
                      numberArgument(call, "z"), 1.0);
    multiplyBy(m);
  } else if (name == "glScalef" || name == "glScaled") {
    glm::dmat4 m(1.0);
    m[0][0] = numberArgument(call, "x");
    m[1][1] = numberArgument(call, "y");
    m[2][2] = numberArgument(call, "z");
    multiplyBy(m);
  } else if (name == "glRotatef" || name == "glRotated") {
    multiplyBy(rotation(
        numberArgument(call, "angle"),
        {numberArgument(call, "x"), numberArgument(call, "y"), numberArgument(call, "z")}));
  } else if (name == "glPushMatrix") {
    const glm::dmat4 copy = top;
    stacks_[matrixMode_].push_back(copy);
  } else if (name == "glPopMatrix") {
    std::vector<glm::dmat4>& stack = stacks_[matrixMode_];
    if (stack.size() > 1) stack.pop_back();  // a stack underflow is a GL error: no effect
  }
}

void GlTraceState::setUniformMatrices(std::uint32_t program, const DumpCall& call) {
  const std::int64_t location = integerArgument(call, "location", -2147483648.0, 2147483647.0);
  if (location < 0) return;  // location -1: silently ignored by GL
  const bool transpose = enumArgument(call, "transpose") == kGlTrue;
  const std::vector<double> values = numbers(call, "value");
  for (std::size_t k = 0; k + 16 <= values.size(); k += 16) {
    uniformMatrices_[{program, location + static_cast<std::int64_t>(k / 16)}] =
        columnMajor(values.data() + k, transpose);
  }
}

std::uint32_t GlTraceState::drawProgram() const {
  if (currentProgram_ != 0 || boundPipeline_ == 0) return currentProgram_;
  const auto stage = pipelineVertexProgram_.find(boundPipeline_);
  return stage != pipelineVertexProgram_.end() ? stage->second : 0;
}

void GlTraceState::emitDraw(const DumpCall& call,
                            const std::function<void(const TraceDraw&)>& onDraw) {
  TraceDraw draw;
  draw.frame = frame_;
  draw.call = call.number;
  draw.function = call.name;
  draw.depth = depth_;
  const std::uint32_t program = drawProgram();
  if (program != 0) {
    for (auto it = uniformMatrices_.lower_bound({program, INT64_MIN});
         it != uniformMatrices_.end() && it->first.first == program; ++it) {
      if (!hasProjectionStructure(it->second)) continue;
      const auto named = uniformNames_.find(it->first);
      const std::string name = named != uniformNames_.end()
                                   ? named->second
                                   : "at location " + std::to_string(it->first.second);
      draw.matrices.push_back(
          {"uniform " + name + " (program " + std::to_string(program) + ")", false, it->second});
    }
    for (UniformBlockMatrix& read : uniformBuffers_.matrices(program, call.number)) {
      if (hasProjectionStructure(read.matrix)) {
        draw.matrices.push_back({std::move(read.source), false, read.matrix});
      }
    }
  } else {
    // Fixed function: the projection stack is the projection; the modelview moves the camera
    // and cannot change the depth convention, so it is left out of the analysis.
    const glm::dmat4 projection = stackTop(kGlProjection);
    if (hasProjectionStructure(projection)) {
      draw.matrices.push_back({"fixed-function GL_PROJECTION", true, projection});
    }
  }
  onDraw(draw);
}

bool GlTraceState::applyDepthState(const DumpCall& call) {
  const std::string_view name = call.name;
  if (name == "glClipControl") {
    depth_.clipUpperLeft = enumArgument(call, "origin") == kGlUpperLeft;
    depth_.clipZeroToOne = enumArgument(call, "depth") == kGlZeroToOne;
    depth_.clipControlCall = call.number;
  } else if (name == "glEnable" || name == "glDisable") {
    const std::uint32_t cap = enumArgument(call, "cap");
    if (cap == kGlDepthTest) depth_.depthTest = name == "glEnable";
    if (cap == kGlCullFace) {
      depth_.cullFace = name == "glEnable";
      depth_.cullFaceCall = call.number;
    }
  } else if (name == "glCullFace") {
    depth_.cullFaceMode = enumArgument(call, "mode");
    depth_.cullFaceModeCall = call.number;
  } else if (name == "glFrontFace") {
    depth_.frontFace = enumArgument(call, "mode");
    depth_.frontFaceCall = call.number;
  } else if (name == "glDepthFunc") {
    depth_.depthFunc = enumArgument(call, "func");
    depth_.depthFuncCall = call.number;
  } else if (name == "glDepthRange" || name == "glDepthRangef" ||
             (name == "glDepthRangeIndexed" && numberArgument(call, "index") == 0.0)) {
    // apitrace names the arguments zNear/zFar (glDepthRange) or n/f (glDepthRangef, GLES).
    const bool longNames = call.argument("zNear") != nullptr;
    depth_.depthRange = {numberArgument(call, longNames ? "zNear" : "n"),
                         numberArgument(call, longNames ? "zFar" : "f")};
    depth_.depthRangeCall = call.number;
  } else if (name == "glClearDepth" || name == "glClearDepthf") {
    clearDepthValue_ = numberArgument(call, call.argument("depth") ? "depth" : "d");
  } else if (name == "glClear") {
    if (maskHasDepthBit(argument(call, "mask"))) {
      depth_.clearedDepth = std::clamp(clearDepthValue_, 0.0, 1.0);
      depth_.clearCall = call.number;
    }
  } else if (name == "glClearBufferfv" || name == "glClearNamedFramebufferfv") {
    if (enumArgument(call, "buffer") == kGlDepth) {
      const std::vector<double> value = numbers(call, "value");
      if (!value.empty()) {
        depth_.clearedDepth = value[0];
        depth_.clearCall = call.number;
      }
    }
  } else if (name == "glClearBufferfi" || name == "glClearNamedFramebufferfi") {
    if (enumArgument(call, "buffer") == kGlDepthStencil) {
      depth_.clearedDepth = numberArgument(call, "depth");
      depth_.clearCall = call.number;
    }
  } else if (name == "glViewport") {
    depth_.viewport = {static_cast<int>(integerArgument(call, "width", 0.0, 2147483647.0)),
                       static_cast<int>(integerArgument(call, "height", 0.0, 2147483647.0))};
  } else {
    return false;
  }
  return true;
}

bool GlTraceState::applyProgramState(const DumpCall& call) {
  const std::string_view name = call.name;
  if (name == "glUseProgram" || name == "glUseProgramObjectARB") {
    currentProgram_ = objectArgument(call, name == "glUseProgram" ? "program" : "programObj");
  } else if (name == "glBindProgramPipeline") {
    boundPipeline_ = objectArgument(call, "pipeline");
  } else if (name == "glUseProgramStages") {
    if (stagesHaveVertexShader(argument(call, "stages"))) {
      pipelineVertexProgram_[objectArgument(call, "pipeline")] = objectArgument(call, "program");
    }
  } else if (name == "glActiveShaderProgram") {
    pipelineActiveProgram_[objectArgument(call, "pipeline")] = objectArgument(call, "program");
  } else if (name == "glLinkProgram" || name == "glLinkProgramARB") {
    // Linking resets the program's uniforms (and may move their locations).
    const std::uint32_t program =
        objectArgument(call, name == "glLinkProgram" ? "program" : "programObj");
    std::erase_if(uniformMatrices_,
                  [&](const auto& entry) { return entry.first.first == program; });
    std::erase_if(uniformNames_, [&](const auto& entry) { return entry.first.first == program; });
  } else if (name == "glGetUniformLocation" || name == "glGetUniformLocationARB") {
    const std::uint32_t program =
        objectArgument(call, name == "glGetUniformLocation" ? "program" : "programObj");
    const auto location = call.result ? call.result->number() : std::nullopt;
    if (location && *location >= 0.0 && *location <= 2147483647.0) {
      std::string uniform = argument(call, "name").text;
      if (uniform.ends_with("[0]")) uniform.resize(uniform.size() - 3);
      // GLSL names are ASCII; a damaged trace's bytes must not reach the reports (JSON is UTF-8).
      for (char& c : uniform) {
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7E) c = '?';
      }
      uniformNames_[{program, static_cast<std::int64_t>(*location)}] = uniform;
    }
  } else if (name.starts_with("glUniformMatrix4")) {
    // Without glUseProgram's program, glUniform* goes to the bound pipeline's active program.
    std::uint32_t program = currentProgram_;
    if (program == 0 && boundPipeline_ != 0) {
      const auto active = pipelineActiveProgram_.find(boundPipeline_);
      if (active != pipelineActiveProgram_.end()) program = active->second;
    }
    if (program != 0) setUniformMatrices(program, call);
  } else if (name.starts_with("glProgramUniformMatrix4")) {
    setUniformMatrices(objectArgument(call, "program"), call);
  } else {
    return false;
  }
  return true;
}

bool GlTraceState::applyAttachmentState(const DumpCall& call) {
  const std::string_view name = call.name;
  if (name == "glBindFramebuffer" || name == "glBindFramebufferEXT") {
    const std::uint32_t target = enumArgument(call, "target");
    if (target == kGlFramebuffer || target == kGlDrawFramebuffer) {
      drawFramebuffer_ = objectArgument(call, "framebuffer");
      updateDepthFormat();
    }
  } else if (name == "glBindRenderbuffer" || name == "glBindRenderbufferEXT") {
    boundRenderbuffer_ = objectArgument(call, "renderbuffer");
  } else if (name.starts_with("glRenderbufferStorage")) {
    renderbufferFormats_[boundRenderbuffer_] = enumArgument(call, "internalformat");
  } else if (name.starts_with("glNamedRenderbufferStorage")) {
    renderbufferFormats_[objectArgument(call, "renderbuffer")] =
        enumArgument(call, "internalformat");
  } else if (name == "glActiveTexture") {
    activeTextureUnit_ = argument(call, "texture").text;
  } else if (name == "glBindTexture") {
    boundTextures_[{activeTextureUnit_, textureTarget(argument(call, "target").text)}] =
        objectArgument(call, "texture");
  } else if (name.starts_with("glTexImage") || name.starts_with("glTexStorage")) {
    // The format of level 0 (glTexImage's other levels do not change what is attached).
    if (name.starts_with("glTexImage") && !name.ends_with("Multisample") &&
        numberArgument(call, "level") != 0.0) {
      return true;
    }
    const auto bound =
        boundTextures_.find({activeTextureUnit_, textureTarget(argument(call, "target").text)});
    if (bound != boundTextures_.end()) {
      textureFormats_[bound->second] = enumArgument(call, "internalformat");
    }
  } else if (name.starts_with("glTextureStorage")) {
    textureFormats_[objectArgument(call, "texture")] = enumArgument(call, "internalformat");
  } else if (name.starts_with("glFramebufferRenderbuffer") ||
             name == "glNamedFramebufferRenderbuffer" || name.starts_with("glFramebufferTexture") ||
             name.starts_with("glNamedFramebufferTexture")) {
    const std::uint32_t attachment = enumArgument(call, "attachment");
    if (attachment != kGlDepthAttachment && attachment != kGlDepthStencilAttachment) return true;
    const bool named = name.starts_with("glNamed");
    std::uint32_t framebuffer = drawFramebuffer_;
    if (named) framebuffer = objectArgument(call, "framebuffer");
    if (!named && enumArgument(call, "target") == kGlReadFramebuffer) return true;
    std::uint32_t format = 0;
    if (name.find("Renderbuffer") != std::string_view::npos) {
      const auto found = renderbufferFormats_.find(objectArgument(call, "renderbuffer"));
      if (found != renderbufferFormats_.end()) format = found->second;
    } else {
      const auto found = textureFormats_.find(objectArgument(call, "texture"));
      if (found != textureFormats_.end()) format = found->second;
    }
    framebufferDepth_[framebuffer] = format;
    updateDepthFormat();
  } else {
    return false;
  }
  return true;
}

bool GlTraceState::apply(const DumpCall& call,
                         const std::function<void(const TraceDraw&)>& onDraw) {
  const std::string_view name = call.name;
  if (endsFrame(name)) {
    ++frame_;
    return true;
  }
  if (UniformBuffers::needs(name)) {
    uniformBuffers_.apply(call);
    if (name != "glLinkProgram") return false;  // which resets the program's uniforms below too
  }
  if (name == "glNewList") {
    // GL_COMPILE (0x1300) records without drawing; GL_COMPILE_AND_EXECUTE draws as well.
    compilingList_ = enumArgument(call, "mode") == kGlCompile;
    return false;
  }
  if (name == "glEndList") {
    compilingList_ = false;
    return false;
  }
  if (isDraw(name)) {
    if (!compilingList_) emitDraw(call, onDraw);
    return false;
  }
  if (!applyDepthState(call) && !applyProgramState(call) && !applyAttachmentState(call)) {
    applyMatrixStack(call);
  }
  return false;
}

}  // namespace clipray::trace
