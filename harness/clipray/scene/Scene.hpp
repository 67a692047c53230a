#pragma once
// What a scene models: cameras and geometry, nothing else (no materials, no lights).
// The JSON format (version 1) is documented in docs/scene-format.md. Matrices are column-major,
// p' = M * p: Camera::viewFromWorld, rawClipFromWorld and clipFromWorld (built for a DepthMode),
// AnalyticPrimitive::worldFromLocal.

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"

namespace clipray {

struct PerspectiveProjection {
  double fovYDegrees = 60.0;
  std::optional<double> aspect;  // nullopt: viewport width / height
  double nearDistance = 0.1;
  std::optional<double> farDistance;  // nullopt: infinite far plane
};

struct OrthographicProjection {
  double left = -1, right = 1, bottom = -1, top = 1;
  double nearDistance = 0.1;
  double farDistance = 100.0;
};

// A depth the mesh fragment shader writes itself (gl_FragDepth) from the fragment's clip w, in
// place of the projective window depth: L(w) = log2(1 + C w) / log2(1 + C far).
//   threejs: WebGLRenderer's logarithmicDepthBuffer, C = 1 (vFragDepth = 1.0 + gl_Position.w;
//            gl_FragDepth = log2(vFragDepth) * logDepthBufFC * 0.5, logDepthBufFC =
//            2.0 / log2(camera.far + 1.0): mrdoob/three.js
//            src/renderers/shaders/ShaderChunk/logdepthbuf_vertex.glsl.js and
//            logdepthbuf_fragment.glsl.js, the uniform in src/renderers/WebGLRenderer.js).
//   outerra: Outerra's log depth with the constant C of its first version (log(C w + 1) /
//            log(C far + 1)), written per fragment as its 2013 "Logarithmic Depth Buffer
//            Optimizations & Fixes" writes its C = 1 form (flogz = 1.0 + gl_Position.w
//            interpolated, gl_FragDepth = log2(flogz) * Fcoef_half, Fcoef = 2.0 /
//            log2(farplane + 1.0)); here flogz = 1.0 + C gl_Position.w and Fcoef = 2.0 /
//            log2(C far + 1.0).
// Under reversed-Z (GL_GREATER, clear 0) the shader writes 1 - L (near stays the greater).
enum class LogDepthForm : std::uint8_t { ThreeJs, Outerra };
struct LogarithmicDepth {
  LogDepthForm form = LogDepthForm::ThreeJs;
  double far = 1.0;       // where L reaches 1 (three.js: camera.far); positive, finite
  double constant = 1.0;  // C: positive, finite; 1 for three.js (its formula has none)
  bool operator==(const LogarithmicDepth&) const = default;
};
const char* logDepthFormName(LogDepthForm form);

struct Camera {
  std::string name;
  Viewport viewport;
  // Either a parametric projection with a view, or a raw clipFromWorld matrix.
  std::variant<PerspectiveProjection, OrthographicProjection, std::monostate> projection;
  glm::dmat4 viewFromWorld{1.0};
  std::optional<glm::dmat4> rawClipFromWorld;
  // The convention a parametric projection is built for; nullopt: built for whatever convention
  // the frame is drawn under (the app does the right thing). Set it to draw a matrix built for
  // one convention under another (e.g. built for "no", drawn under "zo").
  std::optional<DepthMode> builtFor;
  // User clip planes the camera draws with (gl_ClipDistance[i] = dot(plane, (p_world, 1)), each
  // enabled with GL_CLIP_DISTANCE0 + i): a point is kept where every plane's value is >= 0. At
  // most kMaxClipPlanes; each normal (xyz) non-zero.
  std::vector<glm::dvec4> clipPlanes;
  static constexpr std::size_t kMaxClipPlanes = 8;  // GL's minimum GL_MAX_CLIP_DISTANCES
  // Codes of `clipray check` findings (errors and warnings) the scene shows on purpose with this
  // camera ("depth-convention-mismatch" for a matrix built for NO drawn under ZO): a reconcile run
  // notes them as expected instead of failing with the verdict convention-error.
  std::vector<std::string> expectedFindings;
  // The depth the meshes' fragment shader writes in place of the projective one, if any (three.js
  // sets logDepthBufFC per camera from camera.far): triangle meshes under a perspective
  // projection only (the loader refuses the rest).
  std::optional<LogarithmicDepth> logarithmicDepth;

  // The matrix the app would hand GL when drawing under `drawnUnder` at `viewport`.
  glm::dmat4 clipFromWorld(DepthMode drawnUnder, Viewport viewport) const;
};

// One object's glPolygonOffsetClamp(factor, units, clamp); clamp 0 clamps nothing.
struct PolygonOffset {
  double factor = 0.0;
  double units = 0.0;
  double clamp = 0.0;
  bool operator==(const PolygonOffset&) const = default;
};

// A triangle mesh with its object transform already applied (in double) at load time.
struct MeshObject {
  std::string name;
  std::vector<glm::dvec3> worldPositions;
  std::vector<glm::u32vec3> triangles;  // indices into worldPositions
  // Face culling the object is drawn with; the winding is the triangles' index order as seen
  // through the drawn clipFromWorld (math/Facing.hpp), so mirrored transforms already count.
  CullFace cull = CullFace::None;
  FrontFace frontFace = FrontFace::Ccw;
  // glDepthRange(n, f) this object is drawn with; nullopt: the scene's (Scene::depthRange). A
  // first-person weapon in [0, 0.1] in front of a world in [0.1, 1]: what the frame shows is the
  // smallest window depth over the objects' own mappings, not the nearest surface. It runs the
  // way the scene's range does (one depth test for the frame).
  std::optional<glm::dvec2> depthRange;
  glm::dvec2 depthRangeOr(glm::dvec2 sceneRange) const { return depthRange.value_or(sceneRange); }
  // User clip planes this object is drawn with beside the camera's (Camera::clipPlanes, world
  // space, kept where a x + b y + c z + d >= 0): a section view that cuts one object only. The
  // camera's and the object's together at most Camera::kMaxClipPlanes.
  std::vector<glm::dvec4> clipPlanes{};
  // glPolygonOffsetClamp(factor, units, clamp) with GL_POLYGON_OFFSET_FILL this object is drawn
  // with; nullopt: no offset (a decal pushed toward the camera off the wall it lies on).
  std::optional<PolygonOffset> polygonOffset;
};

// An analytic surface: a canonical shape in its own local frame, placed by an affine
// worldFromLocal (any invertible affine map, so spheres may become ellipsoids and boxes
// parallelepipeds). Both sides intersect the canonical shape with the ray mapped to local
// coordinates: an affine map keeps the ray parameter t, so t is the world ray's t.
enum class PrimitiveKind : std::uint8_t {
  Sphere,  // x^2 + y^2 + z^2 <= 1
  Disk,    // z = 0, x^2 + y^2 <= 1
  Quad,    // z = 0, |x| <= 1, |y| <= 1
  Box,     // |x|, |y|, |z| <= 1 (its surface)
  Plane,   // z = 0, unbounded
};
const char* primitiveKindName(PrimitiveKind kind);

struct AnalyticPrimitive {
  std::string name;
  PrimitiveKind kind = PrimitiveKind::Sphere;
  glm::dmat4 worldFromLocal{1.0};
  glm::dmat4 localFromWorld{1.0};  // the inverse, computed in double at load time
};

struct Scene {
  std::string path;     // as given by the user; used in messages
  std::string name;     // file stem, used in reports
  std::string comment;  // what the scene tests
  int version = 1;
  std::vector<Camera> cameras;
  std::vector<MeshObject> objects;
  std::vector<AnalyticPrimitive> primitives;
  // Things the loaders kept but want the user to know (degenerate triangles, ...).
  std::vector<std::string> warnings;
  // Conventions this scene is reconciled under when the command line does not name any.
  std::vector<DepthMode> conventions;
  // glDepthRange(n, f) every object is drawn with: window depth n + (f - n) d, d the depth
  // glDepthRange(0, 1) would give. Reversed (n > f) is the reversed-Z of apps without clip
  // control (a NO projection, glDepthRange(1, 0), GL_GREATER, clear 0).
  glm::dvec2 depthRange{0.0, 1.0};
  // glEnable(GL_DEPTH_CLAMP) for every object: no clipping at the near and far planes; a fragment
  // in front of the near plane (or beyond the far plane) is drawn at the depth range's near (far)
  // end. Everything in front of the eye is drawn (GL 4.6 13.7, 13.8.1).
  bool depthClamp = false;
  // Samples per pixel the scene is drawn with ("samples"): above 1 reconcile draws it multisampled
  // and compares every sample (engine/MultisampleRun), unless --samples or
  // ReconcileOptions::samples says otherwise.
  int samples = 1;

  std::size_t triangleCount() const;
};

// Primitive ids: 0 is background; object k's triangle t has id firstIdOfObject[k] + t; analytic
// primitive p has id firstAnalyticId + p (after every triangle).
// The raster pass writes these to the R32UI attachment; the analytic pass returns the same.
struct PrimitiveIdTable {
  // The most primitives (triangles and analytic) a scene may hold: ids are 32-bit, 0 is background.
  static constexpr std::uint64_t kMaxPrimitives = std::numeric_limits<std::uint32_t>::max() - 1u;
  std::vector<std::uint32_t> firstIdOfObject;  // one per object, starting at 1
  std::uint32_t firstAnalyticId = 1;
  std::uint32_t analyticCount = 0;
  explicit PrimitiveIdTable(const Scene& scene);
  struct Decoded {
    int object = -1;  // -1: background or an analytic primitive
    std::uint32_t triangle = 0;
    int analytic = -1;  // index into Scene::primitives, or -1
  };
  Decoded decode(std::uint32_t id) const;
};

// Loads and validates a scene file; throws InputError naming file, JSON pointer and value. A
// .gltf/.glb path loads that asset as a scene seen from its own cameras (.obj/.ply have none).
Scene loadScene(const std::string& path);
// Whether loadScene reads the path as a mesh file (.gltf, .glb, .obj, .ply; any case).
bool isMeshFilePath(const std::string& path);
// Same, from text already in memory (the path is used in messages and to resolve relative paths).
Scene parseScene(const std::string& jsonText, const std::string& path);

}  // namespace clipray
