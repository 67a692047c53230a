#pragma once
// The GL state a trace sets, call by call, as far as `clipray check --trace` needs it: the depth
// state in force at each draw (glClipControl, depth test and func, depth range, the depth clear,
// face culling, depth clamp and clip distances, viewport, the depth format of the draw
// framebuffer's renderbuffer or texture; glPushAttrib/glPopAttrib of those), the 4x4 matrices
// uploaded as uniforms (glUniformMatrix4fv, glProgramUniformMatrix4fv, named by
// glGetUniformLocation; ARB_shader_objects' twins of these and of the program calls alike) or
// kept in std140 uniform blocks (UniformBuffers.hpp), and the
// fixed-function matrix stacks. At each draw it hands over every matrix in force that has a
// projection's structure (ProjectionStructure.hpp). The enums: GlEnums.hpp.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/trace/DumpLine.hpp"
#include "clipray/trace/GlEnums.hpp"
#include "clipray/trace/ProjectionStructure.hpp"
#include "clipray/trace/UniformBuffers.hpp"

namespace clipray::trace {

// The depth state in force at a draw. Call numbers say where each part was set (0: GL's default).
struct TraceDepthState {
  bool clipZeroToOne = false;  // glClipControl depth: GL_ZERO_TO_ONE (default NEGATIVE_ONE_TO_ONE)
  bool clipUpperLeft = false;  // glClipControl origin: GL_UPPER_LEFT (default LOWER_LEFT)
  bool depthTest = false;      // glEnable(GL_DEPTH_TEST)
  std::uint32_t depthFunc = kGlLess;
  glm::dvec2 depthRange{0.0, 1.0};
  // The value the last depth clear wrote (glClear with the depth bit uses glClearDepth's value;
  // glClearBuffer*(GL_DEPTH...) its own); none before the first depth clear.
  std::optional<double> clearedDepth;
  Viewport viewport{0, 0};
  std::optional<DepthFormat> depthFormat;   // of the draw framebuffer's depth attachment, if known
  std::string depthFormatName = "unknown";  // "32f", "24", "16", "32" (unorm), "unknown"

  // Face culling: glEnable(GL_CULL_FACE), glCullFace's mode, glFrontFace's winding.
  bool cullFace = false;
  std::uint32_t cullFaceMode = kGlBack;
  std::uint32_t frontFace = kGlCcw;

  // GL_DEPTH_CLAMP (GL 3.2): no clipping at the near and far planes; fragments beyond them get
  // the depth range's nearer or farther end.
  bool depthClamp = false;
  // GL_CLIP_DISTANCE0..7 enabled: bit i for gl_ClipDistance[i].
  std::uint8_t clipDistances = 0;
  // The program drawing writes gl_ClipDistance (its shaders' text mentions it).
  bool writesClipDistance = false;
  // The program drawing (its number; 0: none) writes gl_FragDepth (FragDepthWrite.hpp): the depth
  // it stores is the shader's, not the matrix's projective depth.
  std::uint32_t fragDepthProgram = 0;
  // glEnable(GL_POLYGON_OFFSET_FILL), and the last glPolygonOffset / glPolygonOffsetClamp(EXT)'s
  // factor, units and clamp (GL 4.6 14.6.5; GL's defaults are 0).
  bool polygonOffsetFill = false;
  double offsetFactor = 0.0, offsetUnits = 0.0, offsetClamp = 0.0;

  std::uint64_t clipControlCall = 0, depthFuncCall = 0, depthRangeCall = 0, clearCall = 0;
  // The last glEnable/glDisable(GL_CULL_FACE), glCullFace and glFrontFace.
  std::uint64_t cullFaceCall = 0, cullFaceModeCall = 0, frontFaceCall = 0;
  // The last glEnable/glDisable of GL_DEPTH_CLAMP, and of any GL_CLIP_DISTANCEi.
  std::uint64_t depthClampCall = 0, clipDistancesCall = 0;
  // The last glEnable/glDisable(GL_POLYGON_OFFSET_FILL), and glPolygonOffset(Clamp).
  std::uint64_t polygonOffsetFillCall = 0, polygonOffsetCall = 0;

  // glDepthMask: whether the draw writes depth (GL's default: it does), and where it was set. Not
  // part of key(): it changes what a draw leaves in the depth buffer, not how depth is computed.
  bool depthWrite = true;
  std::uint64_t depthMaskCall = 0;

  // The state asks for polygon-offset-toward-camera: GL_POLYGON_OFFSET_FILL with an offset whose
  // every non-zero term is positive under GL_GREATER/GEQUAL with the depth test on.
  friend bool offsetTowardCameraUnderGreater(const TraceDepthState& depth) {
    if (!depth.polygonOffsetFill || !depth.depthTest) return false;
    if (depth.depthFunc != kGlGreater && depth.depthFunc != kGlGequal) return false;
    const double f = depth.offsetFactor, u = depth.offsetUnits;
    return f >= 0.0 && u >= 0.0 && (f > 0.0 || u > 0.0);
  }
  // A reversed-Z frame: the depth test keeps the greater depth over a depth cleared to 0, the far
  // value. (GL_GREATER over a clear of 1 is a multi-pass draw of far surfaces, as OpenSCAD's CSG
  // preview makes, under a projection that is not reversed.)
  friend bool reversedDepthFrame(const TraceDepthState& depth) {
    return depth.depthTest && (depth.depthFunc == kGlGreater || depth.depthFunc == kGlGequal) &&
           depth.clearedDepth == 0.0;
  }
  // The same state, call numbers aside (the key of a distinct (matrix, state) pair).
  std::string key() const;
};

// A matrix in force at a draw, with the structure of a projection.
struct TracedMatrix {
  // "uniform clipFromWorld (program 1)", "ubo Camera.clipFromWorld (program 1)" or
  // "fixed-function GL_PROJECTION".
  std::string source;
  bool fixedFunction = false;
  glm::dmat4 matrix{1.0};  // column-major as the GL applies it (transpose flag undone)
};

struct TraceDraw {
  std::uint64_t frame = 0;
  std::uint64_t call = 0;
  // The call after which the draw's fragments are all written (the state a replay can dump):
  // the draw itself, or the glEnd that closes a glBegin.
  std::uint64_t completedAtCall = 0;
  std::string function;  // "glDrawArrays"
  TraceDepthState depth;
  std::vector<TracedMatrix> matrices;
};

class GlTraceState {
 public:
  // Feeds one call. Returns true when the call ended a frame (eglSwapBuffers, glXSwapBuffers, ...).
  // Throws std::invalid_argument when a call the state needs has arguments it cannot read.
  bool apply(const DumpCall& call, const std::function<void(const TraceDraw&)>& onDraw);

  // Whether the state needs this function at all (the others need not be parsed).
  static bool needs(std::string_view function);

  std::uint64_t frame() const { return frame_; }

  // Hands over a glBegin's draw whose glEnd the trace never reached (a glBegin's draw waits for
  // its glEnd, the call a replay can dump the depth buffer at). Called once the trace is read.
  void finish(const std::function<void(const TraceDraw&)>& onDraw);

  // Where `apitrace dump --blobs` writes buffer data (UniformBuffers::setBlobDirectory).
  void setBlobDirectory(std::filesystem::path directory) {
    uniformBuffers_.setBlobDirectory(std::move(directory));
  }
  // Why uniform blocks' matrices were not read (UniformBuffers::unreadNotes).
  const std::vector<std::string>& unreadUniformBlocks() const {
    return uniformBuffers_.unreadNotes();
  }

 private:
  // One part of the state each: it takes the calls of its functions (true) and leaves every other
  // call alone (false). apply tries them in this order, then the matrix stacks.
  // glClipControl, the depth test, depth range and clears, the viewport.
  bool applyDepthState(const DumpCall& call);
  // Programs, program pipelines, uniform names and matrices.
  bool applyProgramState(const DumpCall& call);
  // Framebuffers, renderbuffers and textures: what the draw framebuffer's depth is stored in.
  bool applyAttachmentState(const DumpCall& call);
  // Fixed function: glMatrixMode, glLoadMatrix*, glFrustum, glPushMatrix, ...
  void applyMatrixStack(const DumpCall& call);
  // glPushAttrib/glPopAttrib: the followed state of the groups pushed.
  void applyAttributeStack(const DumpCall& call);
  // The draw a call makes, with the state and matrices in force.
  TraceDraw drawAt(const DumpCall& call);
  void setUniformMatrices(std::uint32_t program, const DumpCall& call);
  // The program whose uniforms a draw reads for its vertices: glUseProgram's, which takes
  // precedence, else the bound program pipeline's vertex-stage program (0: fixed function).
  std::uint32_t drawProgram() const;

  TraceDepthState depth_;
  std::uint64_t frame_ = 0;

  std::uint32_t currentProgram_ = 0;
  // Separable programs (GL 4.1): the bound pipeline, each pipeline's vertex-stage program and
  // the program its glUniform* calls go to (glActiveShaderProgram).
  std::uint32_t boundPipeline_ = 0;
  std::map<std::uint32_t, std::uint32_t> pipelineVertexProgram_, pipelineActiveProgram_;
  std::map<std::pair<std::uint32_t, std::int64_t>, std::string> uniformNames_;
  std::map<std::pair<std::uint32_t, std::int64_t>, glm::dmat4> uniformMatrices_;
  UniformBuffers uniformBuffers_;

  bool compilingList_ = false;  // inside glNewList(..., GL_COMPILE): draws are recorded only
  struct PushedAttributes {
    std::uint32_t mask = 0;
    TraceDepthState depth;
    double clearDepthValue = 1.0;
    std::uint32_t matrixMode = 0;
  };
  std::vector<PushedAttributes> attributeStack_;
  // The glBegin draws of the trace whose glEnd has not come yet (GlTraceState::apply).
  std::optional<TraceDraw> openBegin_;
  std::uint32_t matrixMode_ = kGlModelview;
  std::map<std::uint32_t, std::vector<glm::dmat4>> stacks_;  // mode -> stack, top at the back

  std::uint32_t boundRenderbuffer_ = 0;
  std::uint32_t drawFramebuffer_ = 0;
  std::map<std::uint32_t, std::uint32_t> renderbufferFormats_;  // renderbuffer -> internalformat
  std::map<std::uint32_t, std::uint32_t> framebufferDepth_;     // framebuffer -> internalformat
  std::string activeTextureUnit_ = "GL_TEXTURE0";               // as apitrace writes it
  // (texture unit, target; as written) -> texture; texture -> internalformat of level 0.
  std::map<std::pair<std::string, std::string>, std::uint32_t> boundTextures_;
  std::map<std::uint32_t, std::uint32_t> textureFormats_;
  glm::dmat4& stackTop(std::uint32_t mode);
  void updateDepthFormat();
  double clearDepthValue_ = 1.0;  // glClearDepth
};

}  // namespace clipray::trace
