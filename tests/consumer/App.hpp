#pragma once
// "The app": what a GL project that consumes clipray has of its own, written as such a project
// would write it, with nothing from clipray. A box on a floor, a camera built with glm for
// glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), mouse picking with glm::unProjectZO from window
// coordinates with an upper-left origin on a HiDPI window, and a renderer with its own shaders.
// The Direct3D-style app (Style::Direct3D) builds its projection with y down and draws under
// glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE), as an engine ported from Direct3D or Vulkan does,
// and its picking takes the mouse's y as it comes. The reversed-depth-range app
// (Style::ReversedDepthRange) does reversed-Z as it was done before clip control: a NO projection,
// glDepthRange(1, 0), GL_GREATER, depth cleared to 0. Any of them may cull back faces (its meshes
// are wound counter-clockwise seen from outside; the Direct3D-style app's y-down projection
// reverses that on screen, so it sets glFrontFace(GL_CW)). An app may also hang a one-sided sign
// between the camera and the box, its back to the camera: culling leaves it out of the picture,
// and the app's own picking (pickHit: its own ray-triangle test) must leave it out too. An app may
// put a decal on the box's front face, drawn last with glPolygonOffset to come forward out of the
// face it lies on: negative under GL_LESS, positive under the reversed depth range's GL_GREATER.
// The renderer draws into whatever framebuffer it is handed, multisampled or not. Each has a knob
// for a classic bug, so the tests can show that clipray catches it.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

namespace app {

struct Mesh {
  std::vector<float> positions;  // x, y, z per vertex, world space
  std::vector<std::uint32_t> indices;
};

struct Window {
  int width = 400, height = 300;  // window units (the mouse's)
  double pixelRatio = 2.0;        // framebuffer pixels per window unit
  int framebufferWidth() const { return static_cast<int>(width * pixelRatio); }
  int framebufferHeight() const { return static_cast<int>(height * pixelRatio); }
};

enum class Style { OpenGl, Direct3D, ReversedDepthRange };

struct Camera {
  glm::dmat4 viewFromWorld{1.0};
  // Built for ZERO_TO_ONE depth (y down for Direct3D); NEGATIVE_ONE_TO_ONE for the reversed depth
  // range.
  glm::dmat4 clipFromView{1.0};
  glm::ivec4 viewport{0};  // glViewport(x, y, width, height), framebuffer pixels
};

struct PickRay {
  glm::dvec3 origin{0.0}, direction{0.0};
};

// HitsCulledFaces: pickHit tests every triangle, the back faces the draw culls included.
enum class PickingBug { None, MouseYNotFlipped, UnprojectsNegativeOneToOne, HitsCulledFaces };

// What pickHit found: the mesh (0 floor, 1 box, 2 sign) and triangle, and where along the ray
// (in units of its direction's length).
struct PickedTriangle {
  PickRay ray;
  std::size_t mesh = 0;
  std::uint32_t triangle = 0;
  double t = 0.0;
};
// NoClipControl: no glClipControl at all. LowerLeftOrigin (Direct3D style): GL_ZERO_TO_ONE set
// but the origin left at GL_LOWER_LEFT, so the y-down projection draws the picture upside down.
// DepthFuncLess (reversed depth range): glDepthRange(1, 0) with the depth test left at GL_LESS.
// FrontFaceNotFlipped (Direct3D style, culling back faces): glFrontFace left at GL_CCW, so the
// y-down projection's reversed winding culls the outsides and keeps the insides.
// DecalOffsetNotFlipped (reversed depth range): the decal keeps GL_LESS's glPolygonOffset(-1, -1),
// which under GL_GREATER pushes it into the face behind it.
// FragDepthWritten: the fragment shader writes gl_FragDepth = gl_FragCoord.z (as a shader that
// passes depth through, or a log-depth shader's fallback, does): one depth per fragment, which in
// a multisampled frame every covered sample gets, where fixed-function depth is each sample's own.
enum class RenderBug {
  None,
  NoClipControl,
  DepthFuncGreater,
  LowerLeftOrigin,
  DepthFuncLess,
  FrontFaceNotFlipped,
  DecalOffsetNotFlipped,
  FragDepthWritten
};

struct App {
  Style style = Style::OpenGl;
  bool cullBackFaces = false;  // glEnable(GL_CULL_FACE), glCullFace(GL_BACK)
  Window window;
  Camera camera;
  Mesh floor, box;
  std::optional<Mesh> sign;   // drawn third, wound counter-clockwise seen from the box
  std::optional<Mesh> decal;  // drawn last, on the box's front face (z = 0.7), facing +z
  // The decal's glPolygonOffset(factor, units): toward the camera under the app's depth test.
  double decalOffset() const { return style == Style::ReversedDepthRange ? 1.0 : -1.0; }

  explicit App(Style style = Style::OpenGl, bool cullBackFaces = false, bool withSign = false,
               bool withDecal = false);
  // The ray under the mouse at (x, y) window units, origin upper left.
  std::optional<PickRay> pick(glm::dvec2 mouse, PickingBug bug = PickingBug::None) const;
  // The nearest triangle under the mouse, culling back faces as the draw does (cullBackFaces);
  // nullopt where the ray hits nothing.
  std::optional<PickedTriangle> pickHit(glm::dvec2 mouse, PickingBug bug = PickingBug::None) const;
  // The meshes in draw order.
  std::vector<const Mesh*> meshes() const;
};

// GL entry points, loaded through the function the context gives (as glad or epoxy would).
using GlFunction = void (*)();
using GetProcAddress = GlFunction (*)(const char* name);
// Draws the meshes (one draw call each, in meshes()' order) into the bound framebuffer with the
// app's shaders; with writeIds, the fragment shader also writes firstIds[mesh] + gl_PrimitiveID to
// colour attachment 1 (the app's picking id buffer).
void render(const App& app, GetProcAddress getProcAddress,
            const std::vector<std::uint32_t>& firstIds, RenderBug bug = RenderBug::None,
            bool writeIds = true);

}  // namespace app
