// A tiny headless GL app for `clipray check --trace`: it draws one triangle per frame into an FBO
// on an EGL pbuffer (Mesa's surfaceless platform: no display, no GPU needed), with the matrix and
// depth state of one convention or one classic mistake. CI records it with `apitrace trace` and
// checks what clipray reads from the trace. It links libEGL and libOpenGL/libGL directly, like a
// real app, so apitrace's egltrace.so (LD_PRELOAD) sees every call.
//
//   clipray_trace_app CASE [FRAMES]
//
// CASE: no, zo, reversed-infinite (correct apps); no-under-zo, reversed-with-less,
// row-major-untransposed, vulkan-flip, fixed-function-frustum-under-zo (classic mistakes);
// identity (draws without a projection), clear-only (frames without draws); zo-ubo and
// no-under-zo-ubo (the camera in a std140 uniform block instead of a uniform); zo-depth-texture
// (zo into a GL_DEPTH_COMPONENT24 depth texture instead of a 32F renderbuffer);
// no-under-zo-pipeline (separable programs in a program pipeline, no glUseProgram);
// d3d-style-culled (a y-down projection under GL_UPPER_LEFT, back faces culled, GL_CW) and its
// twin d3d-style-culled-ccw (glFrontFace left at GL_CCW: the insides are kept); zo-depth-clamp
// (zo with GL_DEPTH_CLAMP enabled); arb-shader-objects (no, the camera a GLSL 1.10 uniform set
// through the ARB_shader_objects entry points); overlap-reversed (reversed-Z done right, two
// draws: the triangle, then a larger one behind it) and its twin overlap-reversed-with-less
// (GL_LESS over a clear of 1: the one behind wins where they overlap); zo-shadow-pass (zo, the
// triangle first drawn into a 32x32 shadow map of its own, then into the app's framebuffer).
// Capture mode: with CLIPRAY_CAPTURE_RDC naming a file and RenderDoc's librenderdoc.so preloaded
// (LD_PRELOAD), the app captures everything it draws after creating its context (all FRAMES) as
// one RenderDoc frame through the in-app API and writes it to that file (`clipray check
// --capture`'s tests). The in-app API, because injection with target control captures nothing
// from a pbuffer app: it never presents to a window (issue #39).
// Every matrix is a glm-style camera: perspective fov 60 deg, aspect 4/3, near 0.1, far 100,
// looking from (0, 2, 5) at the origin, built in float as apps do.

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <dlfcn.h>
#include <renderdoc_app.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

using Matrix = std::array<float, 16>;  // column-major: element (row r, column c) at [c * 4 + r]

constexpr float kFovY = 1.04719755f;  // 60 degrees
constexpr float kAspect = 4.0f / 3.0f;
constexpr float kNear = 0.1f;
constexpr float kFar = 100.0f;

Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix product{};
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      float sum = 0.0f;
      for (int k = 0; k < 4; ++k) sum += a[k * 4 + r] * b[c * 4 + k];
      product[c * 4 + r] = sum;
    }
  }
  return product;
}

// glm::lookAtRH (glm/ext/matrix_transform.inl), eye (0, 2, 5), centre 0, up +Y.
Matrix viewFromWorld() {
  const float eye[3] = {0.0f, 2.0f, 5.0f};
  float forward[3] = {-eye[0], -eye[1], -eye[2]};
  const float length =
      std::sqrt(forward[0] * forward[0] + forward[1] * forward[1] + forward[2] * forward[2]);
  for (float& v : forward) v /= length;
  // side = normalize(cross(forward, up)), up = (0, 1, 0)
  float side[3] = {-forward[2], 0.0f, forward[0]};
  const float sideLength = std::sqrt(side[0] * side[0] + side[2] * side[2]);
  for (float& v : side) v /= sideLength;
  const float up[3] = {side[1] * forward[2] - side[2] * forward[1],
                       side[2] * forward[0] - side[0] * forward[2],
                       side[0] * forward[1] - side[1] * forward[0]};
  Matrix view{};
  for (int i = 0; i < 3; ++i) {
    view[i * 4 + 0] = side[i];
    view[i * 4 + 1] = up[i];
    view[i * 4 + 2] = -forward[i];
  }
  view[12] = -(side[0] * eye[0] + side[1] * eye[1] + side[2] * eye[2]);
  view[13] = -(up[0] * eye[0] + up[1] * eye[1] + up[2] * eye[2]);
  view[14] = forward[0] * eye[0] + forward[1] * eye[1] + forward[2] * eye[2];
  view[15] = 1.0f;
  return view;
}

// glm::perspectiveRH_NO / perspectiveRH_ZO (glm/ext/matrix_clip_space.inl): the NO matrix maps
// near to z_ndc -1, the ZO matrix maps near to 0; both map far to 1.
Matrix perspective(bool zeroToOne) {
  const float focal = 1.0f / std::tan(kFovY / 2.0f);
  Matrix projection{};
  projection[0] = focal / kAspect;
  projection[5] = focal;
  projection[11] = -1.0f;
  if (zeroToOne) {
    projection[10] = kFar / (kNear - kFar);
    projection[14] = -(kFar * kNear) / (kFar - kNear);
  } else {
    projection[10] = -(kFar + kNear) / (kFar - kNear);
    projection[14] = -(2.0f * kFar * kNear) / (kFar - kNear);
  }
  return projection;
}

// Reversed-Z with an infinite far plane, for ZERO_TO_ONE: near -> 1, infinity -> 0
// (z_clip = near, w_clip = -z_view).
Matrix reversedInfinitePerspective() {
  const float focal = 1.0f / std::tan(kFovY / 2.0f);
  Matrix projection{};
  projection[0] = focal / kAspect;
  projection[5] = focal;
  projection[11] = -1.0f;
  projection[14] = kNear;
  return projection;
}

Matrix transposed(const Matrix& m) {
  Matrix t{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) t[r * 4 + c] = m[c * 4 + r];
  }
  return t;
}

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "clipray_trace_app: %s\n", what.c_str());
  std::exit(2);
}

struct Context {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLSurface surface = EGL_NO_SURFACE;
};

// A pbuffer (not a surfaceless context) so that eglSwapBuffers marks the end of each frame in
// the trace, as a windowed app's swaps do.
Context createContext(bool compatibility) {
  auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!getPlatformDisplay) fail("eglGetPlatformDisplayEXT missing");
  Context context;
  context.display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (context.display == EGL_NO_DISPLAY || !eglInitialize(context.display, nullptr, nullptr)) {
    fail("no EGL surfaceless display");
  }
  const EGLint configAttributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  if (!eglChooseConfig(context.display, configAttributes, &config, 1, &count) || count == 0) {
    fail("no EGL pbuffer config");
  }
  const EGLint surfaceAttributes[] = {EGL_WIDTH, 64, EGL_HEIGHT, 48, EGL_NONE};
  context.surface = eglCreatePbufferSurface(context.display, config, surfaceAttributes);
  if (context.surface == EGL_NO_SURFACE) fail("cannot create a pbuffer");
  eglBindAPI(EGL_OPENGL_API);
  const EGLint profile = compatibility ? EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT
                                       : EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT;
  const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                      4,
                                      EGL_CONTEXT_MINOR_VERSION,
                                      5,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      profile,
                                      EGL_NONE};
  EGLContext glContext =
      eglCreateContext(context.display, config, EGL_NO_CONTEXT, contextAttributes);
  if (glContext == EGL_NO_CONTEXT) fail("cannot create a GL 4.5 context");
  if (!eglMakeCurrent(context.display, context.surface, context.surface, glContext)) {
    fail("eglMakeCurrent failed");
  }
  return context;
}

// An FBO of the pbuffer's size with a 32-bit float depth renderbuffer, or (depthTexture) a
// GL_DEPTH_COMPONENT24 texture as a shadow-map pass would attach (glTexImage2D for the first
// mip level, glTexStorage2D for an immutable one).
void bindDepthFramebuffer(bool depthTexture) {
  GLuint framebuffer = 0, colour = 0, depth = 0;
  glGenFramebuffers(1, &framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glGenRenderbuffers(1, &colour);
  glBindRenderbuffer(GL_RENDERBUFFER, colour);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, 64, 48);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
  if (depthTexture) {
    GLuint unused = 0;  // a texture on another unit, so the unit's binding is what counts
    glGenTextures(1, &unused);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, unused);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT16, 64, 48, 0, GL_DEPTH_COMPONENT,
                 GL_UNSIGNED_SHORT, nullptr);
    glActiveTexture(GL_TEXTURE0);
    glGenTextures(1, &depth);
    glBindTexture(GL_TEXTURE_2D, depth);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT24, 64, 48);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
  } else {
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, 64, 48);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
  }
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    fail("framebuffer incomplete");
  }
  glViewport(0, 0, 64, 48);
}

GLuint compile(GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) fail("shader does not compile");
  return shader;
}

// Every case's fragment stage: white.
const char* const kFragmentSource =
    "#version 450 core\n"
    "out vec4 colour;\n"
    "void main() { colour = vec4(1.0); }\n";

// A program of vertexSource and kFragmentSource, linked and in use.
GLuint useProgram(const char* vertexSource) {
  const GLuint program = glCreateProgram();
  glAttachShader(program, compile(GL_VERTEX_SHADER, vertexSource));
  glAttachShader(program, compile(GL_FRAGMENT_SHADER, kFragmentSource));
  glLinkProgram(program);
  glUseProgram(program);
  return program;
}

// The triangle every case draws: at world z = 0.
constexpr float kTriangle[9] = {-1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f};

// A triangle (kTriangle unless told) in a vertex array (attribute 0), bound for the draws.
GLuint bindTriangle(const float (&triangle)[9] = kTriangle) {
  GLuint vertexArray = 0, buffer = 0;
  glGenVertexArrays(1, &vertexArray);
  glBindVertexArray(vertexArray);
  glGenBuffers(1, &buffer);
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glBufferData(GL_ARRAY_BUFFER, sizeof triangle, triangle, GL_STATIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  return vertexArray;
}

// The shader path's program, in use: its `clipFromWorld` uniform's location.
GLint useCameraProgram() {
  const char* vertexSource =
      "#version 450 core\n"
      "layout(location = 0) in vec3 position;\n"
      "uniform mat4 clipFromWorld;\n"
      "void main() { gl_Position = clipFromWorld * vec4(position, 1.0); }\n";
  return glGetUniformLocation(useProgram(vertexSource), "clipFromWorld");
}

// The shader path: a program with a `clipFromWorld` uniform and one triangle at world z = 0.
void drawWithShaders(const Matrix& uploaded, GLboolean transpose, int frames, Context context) {
  const GLint location = useCameraProgram();
  bindTriangle();
  for (int frame = 0; frame < frames; ++frame) {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUniformMatrix4fv(location, 1, transpose, uploaded.data());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    eglSwapBuffers(context.display, context.surface);
  }
}

// A shadow-map pass before the frame's own: the triangle drawn into a 32x32 depth-only
// framebuffer of its own (cleared, its own viewport), then into the app's framebuffer as
// drawWithShaders draws it. The camera is the same in both: what matters is which depth buffer
// each draw writes.
void drawWithShadowPass(const Matrix& uploaded, int frames, Context context) {
  GLint appFramebuffer = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &appFramebuffer);
  GLuint shadow = 0, shadowDepth = 0;
  glGenFramebuffers(1, &shadow);
  glBindFramebuffer(GL_FRAMEBUFFER, shadow);
  glGenTextures(1, &shadowDepth);
  glBindTexture(GL_TEXTURE_2D, shadowDepth);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, 32, 32);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadowDepth, 0);
  glDrawBuffer(GL_NONE);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    fail("shadow framebuffer incomplete");
  }
  const GLint location = useCameraProgram();
  bindTriangle();
  for (int frame = 0; frame < frames; ++frame) {
    glUniformMatrix4fv(location, 1, GL_FALSE, uploaded.data());
    glBindFramebuffer(GL_FRAMEBUFFER, shadow);
    glViewport(0, 0, 32, 32);
    glClear(GL_DEPTH_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(appFramebuffer));
    glViewport(0, 0, 64, 48);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    eglSwapBuffers(context.display, context.surface);
  }
}

// Two draws of the shader path per frame: the triangle at world z = 0, then a larger one at
// z = -1 behind it that covers it on screen (the depth test decides what the overlap shows).
void drawOverlapping(const Matrix& uploaded, int frames, Context context) {
  const GLint location = useCameraProgram();
  const float behind[9] = {-3.0f, -1.0f, -1.0f, 3.0f, -1.0f, -1.0f, 0.0f, 3.0f, -1.0f};
  const GLuint behindArray = bindTriangle(behind);
  const GLuint front = bindTriangle();
  for (int frame = 0; frame < frames; ++frame) {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUniformMatrix4fv(location, 1, GL_FALSE, uploaded.data());
    glBindVertexArray(front);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(behindArray);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    eglSwapBuffers(context.display, context.surface);
  }
}

// The program-pipeline path (GL 4.1 separable programs): glCreateShaderProgramv per stage,
// glUseProgramStages into one pipeline, the camera set on the vertex stage's program with
// glProgramUniformMatrix4fv, and no glUseProgram at all.
void drawWithPipeline(const Matrix& uploaded, int frames, Context context) {
  const char* vertexSource =
      "#version 450 core\n"
      "layout(location = 0) in vec3 position;\n"
      "uniform mat4 clipFromWorld;\n"
      "out gl_PerVertex { vec4 gl_Position; };\n"
      "void main() { gl_Position = clipFromWorld * vec4(position, 1.0); }\n";
  const char* fragmentSource = kFragmentSource;
  const GLuint vertexProgram = glCreateShaderProgramv(GL_VERTEX_SHADER, 1, &vertexSource);
  const GLuint fragmentProgram = glCreateShaderProgramv(GL_FRAGMENT_SHADER, 1, &fragmentSource);
  for (const GLuint program : {vertexProgram, fragmentProgram}) {
    GLint linked = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (!linked) fail("a separable program does not link");
  }
  GLuint pipeline = 0;
  glGenProgramPipelines(1, &pipeline);
  glUseProgramStages(pipeline, GL_VERTEX_SHADER_BIT, vertexProgram);
  glUseProgramStages(pipeline, GL_FRAGMENT_SHADER_BIT, fragmentProgram);
  glBindProgramPipeline(pipeline);
  const GLint location = glGetUniformLocation(vertexProgram, "clipFromWorld");
  bindTriangle();
  for (int frame = 0; frame < frames; ++frame) {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glProgramUniformMatrix4fv(vertexProgram, location, 1, GL_FALSE, uploaded.data());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    eglSwapBuffers(context.display, context.surface);
  }
}

// The uniform-buffer path: the camera in a std140 block, as engines upload it. Beside the
// clip-from-world matrix the block holds a view matrix (a mat4 that is no projection) and the
// projection's four columns as a vec4[4] (frustum data, not a matrix: clipray must not read it
// as one), after a vec3 + float pair that std140 packs into one 16-byte slot.
//   zo-ubo: `binding = 0` in the shader, glBindBufferBase, glBufferSubData every frame.
//   no-under-zo-ubo: no binding in the shader, glGetUniformBlockIndex + glUniformBlockBinding to
//   binding 3, glBindBufferRange at offset 256, the block written through glMapBufferRange.
void drawWithUniformBlock(const Matrix& clipFromWorld, const Matrix& view, bool mapped, int frames,
                          Context context) {
  const char* vertexSource =
      mapped ? "#version 450 core\n"
               "layout(location = 0) in vec3 position;\n"
               "layout(std140) uniform Camera {\n"
               "  vec3 eye;\n"
               "  float exposure;\n"
               "  mat4 viewFromWorld;\n"
               "  vec4 frustumColumns[4];\n"
               "  mat4 clipFromWorld;\n"
               "} camera;\n"
               "void main() { gl_Position = camera.clipFromWorld * vec4(position, 1.0); }\n"
             : "#version 450 core\n"
               "layout(location = 0) in vec3 position;\n"
               "layout(std140, binding = 0) uniform Camera {\n"
               "  vec3 eye;\n"
               "  float exposure;\n"
               "  mat4 viewFromWorld;\n"
               "  vec4 frustumColumns[4];\n"
               "  mat4 clipFromWorld;\n"
               "};\n"
               "void main() { gl_Position = clipFromWorld * vec4(position, 1.0); }\n";
  const GLuint program = useProgram(vertexSource);
  // std140 offsets: eye 0, exposure 12, viewFromWorld 16, frustumColumns 80, clipFromWorld 144.
  constexpr GLsizeiptr kBlockSize = 208;
  constexpr GLintptr kRangeOffset = 256;  // a multiple of every GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT
  float block[kBlockSize / 4] = {};
  block[0] = 0.0f;
  block[1] = 2.0f;
  block[2] = 5.0f;
  block[3] = 1.0f;
  std::memcpy(block + 4, view.data(), sizeof(float) * 16);
  std::memcpy(block + 20, clipFromWorld.data(), sizeof(float) * 16);
  std::memcpy(block + 36, clipFromWorld.data(), sizeof(float) * 16);
  GLuint uniforms = 0;
  glGenBuffers(1, &uniforms);
  glBindBuffer(GL_UNIFORM_BUFFER, uniforms);
  glBufferData(GL_UNIFORM_BUFFER, kRangeOffset + kBlockSize, nullptr, GL_DYNAMIC_DRAW);
  if (mapped) {
    const GLuint blockIndex = glGetUniformBlockIndex(program, "Camera");
    glUniformBlockBinding(program, blockIndex, 3);
    glBindBufferRange(GL_UNIFORM_BUFFER, 3, uniforms, kRangeOffset, kBlockSize);
  } else {
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, uniforms);
  }
  bindTriangle();
  for (int frame = 0; frame < frames; ++frame) {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glBindBuffer(GL_UNIFORM_BUFFER, uniforms);
    if (mapped) {
      void* target = glMapBufferRange(GL_UNIFORM_BUFFER, kRangeOffset, kBlockSize,
                                      GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_RANGE_BIT);
      if (!target) fail("glMapBufferRange failed");
      std::memcpy(target, block, sizeof block);
      glUnmapBuffer(GL_UNIFORM_BUFFER);
    } else {
      glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof block, block);
    }
    glDrawArrays(GL_TRIANGLES, 0, 3);
    eglSwapBuffers(context.display, context.surface);
  }
}

// The fixed-function path (compatibility profile): glFrustum for the same camera, classic GL
// (built for NEGATIVE_ONE_TO_ONE).
void drawFixedFunction(int frames, Context context) {
  const double top = kNear * std::tan(kFovY / 2.0);
  const double right = top * kAspect;
  for (int frame = 0; frame < frames; ++frame) {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-right, right, -top, top, kNear, kFar);
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixf(viewFromWorld().data());
    glPushMatrix();
    glTranslatef(0.0f, 0.0f, -1.0f);
    glBegin(GL_TRIANGLES);
    glVertex3f(-1.0f, 0.0f, 0.0f);
    glVertex3f(1.0f, 0.0f, 0.0f);
    glVertex3f(0.0f, 1.0f, 0.0f);
    glEnd();
    glPopMatrix();
    eglSwapBuffers(context.display, context.surface);
  }
}

// One triangle at view z = -1 through glFrustum for the same camera as drawFixedFunction's.
void drawFrustumTriangle() {
  const double top = kNear * std::tan(kFovY / 2.0);
  const double right = top * kAspect;
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glFrustum(-right, right, -top, top, kNear, kFar);
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixf(viewFromWorld().data());
  glBegin(GL_TRIANGLES);
  glVertex3f(-1.0f, 0.0f, 0.0f);
  glVertex3f(1.0f, 0.0f, 0.0f);
  glVertex3f(0.0f, 1.0f, 0.0f);
  glEnd();
}

// OpenCSG's passes as `openscad --preview` draws them (compatibility profile): the nearest
// surfaces with GL_LESS into depth cleared to 1, then the far surfaces of a subtracted volume with
// GL_GREATER into depth cleared to 0, the same matrix in both. Correct: no error.
void drawOpenCsgPasses(int frames, Context context) {
  for (int frame = 0; frame < frames; ++frame) {
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDepthFunc(GL_LESS);
    drawFrustumTriangle();
    glClearDepth(0.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glDepthFunc(GL_GREATER);
    drawFrustumTriangle();
    eglSwapBuffers(context.display, context.surface);
  }
}

// A GLSL 1.20 program that transforms with ftransform(): through the fixed-function matrix stack
// the app sets with glFrustum, as osgtext's and osgshadow's programs do.
void drawWithFtransformProgram(int frames, Context context) {
  const GLuint program = glCreateProgram();
  glAttachShader(program, compile(GL_VERTEX_SHADER,
                                  "#version 120\nvoid main() { gl_Position = ftransform(); }\n"));
  glAttachShader(program, compile(GL_FRAGMENT_SHADER,
                                  "#version 120\nvoid main() { gl_FragColor = vec4(1.0); }\n"));
  glLinkProgram(program);
  glUseProgram(program);
  glDepthFunc(GL_LESS);
  for (int frame = 0; frame < frames; ++frame) {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    drawFrustumTriangle();
    eglSwapBuffers(context.display, context.surface);
  }
}

// The camera as a GLSL 1.10 uniform through the ARB_shader_objects entry points (GL 1.5 era code;
// OpenSceneGraph and others still call them on drivers without GL 2.0): glCreateShaderObjectARB,
// glShaderSourceARB, glAttachObjectARB, glLinkProgramARB, glUseProgramObjectARB,
// glGetUniformLocationARB, glUniformMatrix4fvARB. libOpenGL exports none of them: they come from
// eglGetProcAddress, as apitrace's tracer hands them out.
template <typename Function>
Function arbEntryPoint(const char* name) {
  const auto address = eglGetProcAddress(name);
  if (!address) fail(std::string("no ") + name);
  return reinterpret_cast<Function>(address);
}

void drawWithArbShaderObjects(const Matrix& uploaded, int frames, Context context) {
  const auto createShader =
      arbEntryPoint<PFNGLCREATESHADEROBJECTARBPROC>("glCreateShaderObjectARB");
  const auto shaderSource = arbEntryPoint<PFNGLSHADERSOURCEARBPROC>("glShaderSourceARB");
  const auto compileShader = arbEntryPoint<PFNGLCOMPILESHADERARBPROC>("glCompileShaderARB");
  const auto createProgram =
      arbEntryPoint<PFNGLCREATEPROGRAMOBJECTARBPROC>("glCreateProgramObjectARB");
  const auto attach = arbEntryPoint<PFNGLATTACHOBJECTARBPROC>("glAttachObjectARB");
  const auto link = arbEntryPoint<PFNGLLINKPROGRAMARBPROC>("glLinkProgramARB");
  const auto use = arbEntryPoint<PFNGLUSEPROGRAMOBJECTARBPROC>("glUseProgramObjectARB");
  const auto location = arbEntryPoint<PFNGLGETUNIFORMLOCATIONARBPROC>("glGetUniformLocationARB");
  const auto uniformMatrix = arbEntryPoint<PFNGLUNIFORMMATRIX4FVARBPROC>("glUniformMatrix4fvARB");
  const GLcharARB* sources[2] = {
      "#version 110\nuniform mat4 clipFromWorld;\n"
      "void main() { gl_Position = clipFromWorld * gl_Vertex; }\n",
      "#version 110\nvoid main() { gl_FragColor = vec4(1.0); }\n"};
  const GLenum stages[2] = {GL_VERTEX_SHADER_ARB, GL_FRAGMENT_SHADER_ARB};
  const GLhandleARB program = createProgram();
  for (int k = 0; k < 2; ++k) {
    const GLhandleARB shader = createShader(stages[k]);
    shaderSource(shader, 1, &sources[k], nullptr);
    compileShader(shader);
    attach(program, shader);
  }
  link(program);
  use(program);
  const GLint camera = location(program, "clipFromWorld");
  if (camera < 0) fail("the ARB program does not link");
  glDepthFunc(GL_LESS);
  for (int frame = 0; frame < frames; ++frame) {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    uniformMatrix(camera, 1, GL_FALSE, uploaded.data());
    glBegin(GL_TRIANGLES);
    glVertex3f(-1.0f, 0.0f, 0.0f);
    glVertex3f(1.0f, 0.0f, 0.0f);
    glVertex3f(0.0f, 1.0f, 0.0f);
    glEnd();
    eglSwapBuffers(context.display, context.surface);
  }
}

// RenderDoc's in-app API (renderdoc_app.h): present when librenderdoc.so is loaded into the app.
struct Capture {
  RENDERDOC_API_1_4_2* api = nullptr;
  std::string path;
};

Capture startCapture() {
  Capture capture;
  const char* path = std::getenv("CLIPRAY_CAPTURE_RDC");
  if (!path || !*path) return capture;
  // RTLD_NOLOAD: only the library preloaded into the app (renderdoc_app.h, "RENDERDOC_GetAPI").
  void* library = dlopen("librenderdoc.so", RTLD_NOW | RTLD_NOLOAD);
  if (!library) fail("CLIPRAY_CAPTURE_RDC is set but librenderdoc.so is not preloaded");
  const auto getApi = reinterpret_cast<pRENDERDOC_GetAPI>(dlsym(library, "RENDERDOC_GetAPI"));
  if (!getApi ||
      getApi(eRENDERDOC_API_Version_1_4_2, reinterpret_cast<void**>(&capture.api)) != 1) {
    fail("RenderDoc's in-app API 1.4.2 is not available");
  }
  capture.path = path;
  const std::string stem = capture.path + ".capturing";
  capture.api->SetCaptureFilePathTemplate(stem.c_str());
  // Device and window NULL: the one context current (renderdoc_app.h, StartFrameCapture).
  capture.api->StartFrameCapture(nullptr, nullptr);
  return capture;
}

void endCapture(const Capture& capture) {
  if (!capture.api) return;
  if (capture.api->EndFrameCapture(nullptr, nullptr) != 1) fail("RenderDoc captured nothing");
  // RenderDoc names the file after the template (stem_frameN.rdc): it is moved to the path asked.
  char written[4096];
  std::uint32_t length = sizeof written;
  if (capture.api->GetCapture(capture.api->GetNumCaptures() - 1, written, &length, nullptr) != 1) {
    fail("RenderDoc lists no capture");
  }
  if (std::rename(written, capture.path.c_str()) != 0) {
    fail("cannot move " + std::string(written) + " to " + capture.path);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) fail("usage: clipray_trace_app CASE [FRAMES]");
  const std::string name = argv[1];
  const int frames = argc == 3 ? std::atoi(argv[2]) : 3;
  if (frames < 1) fail("FRAMES must be a positive number");
  const bool fixedFunction = name == "fixed-function-frustum-under-zo";
  const Context context =
      createContext(fixedFunction || name == "opencsg-passes" || name == "ftransform-program" ||
                    name == "arb-shader-objects");
  const Capture capture = startCapture();
  bindDepthFramebuffer(name == "zo-depth-texture");
  glEnable(GL_DEPTH_TEST);
  const Matrix view = viewFromWorld();
  if (name == "no") {
    glDepthFunc(GL_LESS);
    drawWithShaders(multiply(perspective(false), view), GL_FALSE, frames, context);
  } else if (name == "zo") {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    drawWithShaders(multiply(perspective(true), view), GL_FALSE, frames, context);
  } else if (name == "zo-depth-clamp") {
    // Correct ZO drawing with GL_DEPTH_CLAMP on (as for shadow-map pancaking or a sky box): a
    // note on picking, no error.
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    glEnable(GL_DEPTH_CLAMP);
    drawWithShaders(multiply(perspective(true), view), GL_FALSE, frames, context);
  } else if (name == "zo-shadow-pass") {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    drawWithShadowPass(multiply(perspective(true), view), frames, context);
  } else if (name == "zo-depth-texture") {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    drawWithShaders(multiply(perspective(true), view), GL_FALSE, frames, context);
  } else if (name == "reversed-infinite") {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_GREATER);
    glClearDepth(0.0);
    drawWithShaders(multiply(reversedInfinitePerspective(), view), GL_FALSE, frames, context);
  } else if (name == "no-under-zo") {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    drawWithShaders(multiply(perspective(false), view), GL_FALSE, frames, context);
  } else if (name == "reversed-with-less") {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    drawWithShaders(multiply(reversedInfinitePerspective(), view), GL_FALSE, frames, context);
  } else if (name == "overlap-reversed") {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_GREATER);
    glClearDepth(0.0);
    drawOverlapping(multiply(reversedInfinitePerspective(), view), frames, context);
  } else if (name == "overlap-reversed-with-less") {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    drawOverlapping(multiply(reversedInfinitePerspective(), view), frames, context);
  } else if (name == "row-major-untransposed") {
    // The matrix written out row by row (a C array m[row][col]) uploaded as if column-major.
    glDepthFunc(GL_LESS);
    drawWithShaders(transposed(multiply(perspective(false), view)), GL_FALSE, frames, context);
  } else if (name == "vulkan-flip") {
    Matrix flipped = perspective(true);
    flipped[5] = -flipped[5];  // Vulkan's y points down: proj[1][1] *= -1
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    drawWithShaders(multiply(flipped, view), GL_FALSE, frames, context);
  } else if (name == "d3d-style-culled" || name == "d3d-style-culled-ccw") {
    // Direct3D-style: y down in the projection, glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE),
    // back faces culled. The y flip reverses the winding on screen: GL_CW keeps the outsides of
    // meshes wound counter-clockwise; the -ccw twin leaves glFrontFace at GL_CCW (the mistake).
    Matrix flipped = perspective(true);
    for (int column = 0; column < 4; ++column) flipped[column * 4 + 1] = -flipped[column * 4 + 1];
    glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    if (name == "d3d-style-culled") glFrontFace(GL_CW);
    drawWithShaders(multiply(flipped, view), GL_FALSE, frames, context);
  } else if (name == "zo-ubo") {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    drawWithUniformBlock(multiply(perspective(true), view), view, false, frames, context);
  } else if (name == "no-under-zo-ubo") {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    drawWithUniformBlock(multiply(perspective(false), view), view, true, frames, context);
  } else if (name == "no-under-zo-pipeline") {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LESS);
    drawWithPipeline(multiply(perspective(false), view), frames, context);
  } else if (name == "identity") {
    // Draws, but with no projection: clip = world.
    glDepthFunc(GL_LESS);
    drawWithShaders(Matrix{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, GL_FALSE, frames,
                    context);
  } else if (name == "clear-only") {
    // Frames without a single draw.
    for (int frame = 0; frame < frames; ++frame) {
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      eglSwapBuffers(context.display, context.surface);
    }
  } else if (name == "opencsg-passes") {
    drawOpenCsgPasses(frames, context);
  } else if (name == "ftransform-program") {
    drawWithFtransformProgram(frames, context);
  } else if (name == "arb-shader-objects") {
    drawWithArbShaderObjects(multiply(perspective(false), view), frames, context);
  } else if (fixedFunction) {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_LEQUAL);
    drawFixedFunction(frames, context);
  } else {
    fail("unknown case " + name);
  }
  glFinish();
  endCapture(capture);
  return 0;
}
