// The fixed-function matrices follow the OpenGL 2.1 specification, section 2.11.2 (glFrustum,
// glOrtho, glRotate, glTranslate, glScale), rounded to float after each operation as Mesa stores
// them (mesa/mesa, src/mesa/math/m_matrix.c: GLfloat matrices).

#include "clipray/trace/GlTraceState.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string_view>
#include <unordered_set>

#include "clipray/trace/DumpArguments.hpp"

namespace clipray::trace {

namespace {

using namespace std::string_view_literals;

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
  // glEvalMesh1/2 draw an evaluator's grid (OpenGL 2.1, 5.1), as osgteapot does.
  return name.starts_with("glDraw") || name.starts_with("glMultiDraw") || name == "glBegin" ||
         name == "glCallList" || name == "glCallLists" || name == "glEvalMesh1" ||
         name == "glEvalMesh2";
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
                                  "glEnd",
                                  "glPushAttrib",
                                  "glPopAttrib",
                                  "glClipControl",
                                  "glEnable",
                                  "glDisable",
                                  "glDepthFunc",
                                  "glDepthMask",
                                  "glCullFace",
                                  "glFrontFace",
                                  "glPolygonOffset",
                                  "glPolygonOffsetEXT",
                                  "glPolygonOffsetClamp",
                                  "glPolygonOffsetClampEXT",
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

std::string TraceDepthState::key() const {
  char text[400];
  std::snprintf(text, sizeof text,
                "%d%d%d %u %a %a %a %d %dx%d %s %d %u %u %d %u %d %d %a %a %a %u", clipZeroToOne,
                clipUpperLeft, depthTest, depthFunc, depthRange.x, depthRange.y,
                clearedDepth ? *clearedDepth : -1.0, clearedDepth.has_value(), viewport.width,
                viewport.height, depthFormatName.c_str(), cullFace, cullFaceMode, frontFace,
                depthClamp, static_cast<unsigned>(clipDistances), writesClipDistance,
                // The offset only where it is named (so draws that differ in an offset nothing
                // reports on stay one group).
                offsetTowardCameraUnderGreater(*this),
                offsetTowardCameraUnderGreater(*this) ? offsetFactor : 0.0,
                offsetTowardCameraUnderGreater(*this) ? offsetUnits : 0.0, 0.0, fragDepthProgram);
  return text;
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

TraceDraw GlTraceState::drawAt(const DumpCall& call) {
  TraceDraw draw;
  draw.frame = frame_;
  draw.call = call.number;
  draw.completedAtCall = call.number;
  draw.function = call.name;
  draw.depth = depth_;
  const std::uint32_t program = drawProgram();
  if (program != 0) {
    // The program's uniform matrices that have `structure`, named by uniform.
    const auto addUniforms = [&](bool (*structure)(const glm::dmat4&)) {
      for (auto it = uniformMatrices_.lower_bound({program, INT64_MIN});
           it != uniformMatrices_.end() && it->first.first == program; ++it) {
        if (!structure(it->second)) continue;
        const auto named = uniformNames_.find(it->first);
        const std::string name = named != uniformNames_.end()
                                     ? named->second
                                     : "at location " + std::to_string(it->first.second);
        draw.matrices.push_back(
            {"uniform " + name + " (program " + std::to_string(program) + ")", false, it->second});
      }
    };
    addUniforms(hasProjectionStructure);
    for (UniformBlockMatrix& read : uniformBuffers_.matrices(program, call.number)) {
      if (hasProjectionStructure(read.matrix)) {
        draw.matrices.push_back({std::move(read.source), false, read.matrix});
      }
    }
    // In a reversed-Z frame, a reversed-Z orthographic projection (orientation-preserving)
    // where nothing else is one.
    if (draw.matrices.empty() && reversedDepthFrame(depth_)) {
      addUniforms(hasReversedOrthographicStructure);
    }
    // The compatibility profile's built-ins: such a program transforms through the
    // fixed-function stacks as a draw without a program does.
    if (const std::string why = uniformBuffers_.fixedFunctionTransform(program); !why.empty()) {
      const glm::dmat4 projection = stackTop(kGlProjection);
      if (hasProjectionStructure(projection)) {
        draw.matrices.push_back(
            {"fixed-function GL_PROJECTION (program " + std::to_string(program) + ": " + why + ")",
             true, projection});
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
  draw.depth.writesClipDistance = program != 0 && uniformBuffers_.writesClipDistance(program);
  draw.depth.fragDepthProgram =
      program != 0 && uniformBuffers_.writesFragDepth(program) ? program : 0;
  return draw;
}

void GlTraceState::finish(const std::function<void(const TraceDraw&)>& onDraw) {
  if (openBegin_) onDraw(*openBegin_);
  openBegin_.reset();
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
    if (cap == kGlDepthClamp) {
      depth_.depthClamp = name == "glEnable";
      depth_.depthClampCall = call.number;
    }
    if (cap == kGlPolygonOffsetFill) {
      depth_.polygonOffsetFill = name == "glEnable";
      depth_.polygonOffsetFillCall = call.number;
    }
    if (const int index = clipDistanceIndex(cap); index >= 0) {
      const auto bit = static_cast<std::uint8_t>(1u << index);
      depth_.clipDistances =
          name == "glEnable" ? depth_.clipDistances | bit : depth_.clipDistances & ~bit;
      depth_.clipDistancesCall = call.number;
    }
  } else if (name == "glCullFace") {
    depth_.cullFaceMode = enumArgument(call, "mode");
    depth_.cullFaceModeCall = call.number;
  } else if (name == "glFrontFace") {
    depth_.frontFace = enumArgument(call, "mode");
    depth_.frontFaceCall = call.number;
  } else if (name == "glPolygonOffset" || name == "glPolygonOffsetClamp" ||
             name == "glPolygonOffsetClampEXT") {
    depth_.offsetFactor = numberArgument(call, "factor");
    depth_.offsetUnits = numberArgument(call, "units");
    // GL 4.6 14.6.5: glPolygonOffset(factor, units) is glPolygonOffsetClamp(factor, units, 0).
    depth_.offsetClamp = call.argument("clamp") ? numberArgument(call, "clamp") : 0.0;
    depth_.polygonOffsetCall = call.number;
  } else if (name == "glPolygonOffsetEXT") {
    // EXT_polygon_offset (GL 1.0): the units as a bias in depth, not in r (no longer core).
    depth_.offsetFactor = numberArgument(call, "factor");
    depth_.offsetUnits = numberArgument(call, "bias");
    depth_.offsetClamp = 0.0;
    depth_.polygonOffsetCall = call.number;
  } else if (name == "glDepthFunc") {
    depth_.depthFunc = enumArgument(call, "func");
    depth_.depthFuncCall = call.number;
  } else if (name == "glDepthMask") {
    depth_.depthWrite = enumArgument(call, "flag") != 0;
    depth_.depthMaskCall = call.number;
  } else if (name == "glDepthRange" || name == "glDepthRangef" ||
             (name == "glDepthRangeIndexed" && numberArgument(call, "index") == 0.0)) {
    // apitrace names the arguments zNear/zFar (glDepthRange) or n/f (glDepthRangef, GLES).
    // GL clamps both to [0, 1] (OpenGL 4.6, 13.8.1): glDepthRange(-100000, 100000) is (0, 1).
    const bool longNames = call.argument("zNear") != nullptr;
    depth_.depthRange = {std::clamp(numberArgument(call, longNames ? "zNear" : "n"), 0.0, 1.0),
                         std::clamp(numberArgument(call, longNames ? "zFar" : "f"), 0.0, 1.0)};
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

// OpenGL 2.1, 6.1.21 and table 6.3 on (with ARB_depth_clamp's and ARB_clip_control's additions):
// which attribute group holds each part of the followed state.
void GlTraceState::applyAttributeStack(const DumpCall& call) {
  if (call.name == "glPushAttrib") {
    const DumpValue& mask = argument(call, "mask");
    const auto has = [&](std::uint32_t bit, std::string_view bitName) {
      return maskHasBit(mask, bit, {bitName, "GL_ALL_ATTRIB_BITS"sv});
    };
    std::uint32_t groups = 0;
    if (has(kGlDepthBufferBit, "GL_DEPTH_BUFFER_BIT"sv)) groups |= kGlDepthBufferBit;
    if (has(kGlPolygonBit, "GL_POLYGON_BIT"sv)) groups |= kGlPolygonBit;
    if (has(kGlViewportBit, "GL_VIEWPORT_BIT"sv)) groups |= kGlViewportBit;
    if (has(kGlTransformBit, "GL_TRANSFORM_BIT"sv)) groups |= kGlTransformBit;
    if (has(kGlEnableBit, "GL_ENABLE_BIT"sv)) groups |= kGlEnableBit;
    // GL's attribute stack is at least 16 deep; a deeper push is GL_STACK_OVERFLOW, no effect.
    if (attributeStack_.size() < 64) {
      attributeStack_.push_back({groups, depth_, clearDepthValue_, matrixMode_});
    }
    return;
  }
  if (attributeStack_.empty()) return;  // a stack underflow is a GL error: no effect
  const PushedAttributes pushed = attributeStack_.back();
  attributeStack_.pop_back();
  const TraceDepthState& saved = pushed.depth;
  const auto restores = [&](std::uint32_t bit) { return (pushed.mask & bit) != 0; };
  if (restores(kGlDepthBufferBit)) {
    depth_.depthTest = saved.depthTest;
    depth_.depthFunc = saved.depthFunc;
    depth_.depthFuncCall = saved.depthFuncCall;
    depth_.depthWrite = saved.depthWrite;
    depth_.depthMaskCall = saved.depthMaskCall;
    clearDepthValue_ = pushed.clearDepthValue;
  }
  if (restores(kGlEnableBit)) {
    depth_.depthTest = saved.depthTest;
    depth_.cullFace = saved.cullFace;
    depth_.cullFaceCall = saved.cullFaceCall;
  }
  if (restores(kGlEnableBit) || restores(kGlTransformBit)) {
    depth_.depthClamp = saved.depthClamp;
    depth_.depthClampCall = saved.depthClampCall;
    depth_.clipDistances = saved.clipDistances;
    depth_.clipDistancesCall = saved.clipDistancesCall;
  }
  if (restores(kGlEnableBit) || restores(kGlPolygonBit)) {
    depth_.polygonOffsetFill = saved.polygonOffsetFill;
    depth_.polygonOffsetFillCall = saved.polygonOffsetFillCall;
  }
  if (restores(kGlPolygonBit)) {
    depth_.offsetFactor = saved.offsetFactor;
    depth_.offsetUnits = saved.offsetUnits;
    depth_.offsetClamp = saved.offsetClamp;
    depth_.polygonOffsetCall = saved.polygonOffsetCall;
    depth_.cullFace = saved.cullFace;
    depth_.cullFaceCall = saved.cullFaceCall;
    depth_.cullFaceMode = saved.cullFaceMode;
    depth_.cullFaceModeCall = saved.cullFaceModeCall;
    depth_.frontFace = saved.frontFace;
    depth_.frontFaceCall = saved.frontFaceCall;
  }
  if (restores(kGlViewportBit)) {
    depth_.viewport = saved.viewport;
    depth_.depthRange = saved.depthRange;
    depth_.depthRangeCall = saved.depthRangeCall;
  }
  if (restores(kGlTransformBit)) {
    matrixMode_ = pushed.matrixMode;
    depth_.clipUpperLeft = saved.clipUpperLeft;
    depth_.clipZeroToOne = saved.clipZeroToOne;
    depth_.clipControlCall = saved.clipControlCall;
  }
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
    // A glBegin left open is a GL error; its draw still belongs to the frame it began in.
    finish(onDraw);
    ++frame_;
    return true;
  }
  if (UniformBuffers::needs(name)) {
    uniformBuffers_.apply(call);
    // Linking also resets the program's uniforms (applyProgramState).
    if (name != "glLinkProgram" && name != "glLinkProgramARB") return false;
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
  if (name == "glEnd") {
    // The glBegin's fragments are all written now: a replay can dump the depth buffer here.
    if (openBegin_) {
      openBegin_->completedAtCall = call.number;
      finish(onDraw);
    }
    return false;
  }
  if (isDraw(name)) {
    if (compilingList_) return false;
    if (name == "glBegin") {
      finish(onDraw);  // a glBegin without its glEnd before it
      openBegin_ = drawAt(call);
    } else {
      onDraw(drawAt(call));
    }
    return false;
  }
  if (name == "glPushAttrib" || name == "glPopAttrib") {
    applyAttributeStack(call);
    return false;
  }
  if (!applyDepthState(call) && !applyProgramState(call) && !applyAttachmentState(call)) {
    applyMatrixStack(call);
  }
  return false;
}

}  // namespace clipray::trace
