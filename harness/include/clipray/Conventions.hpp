#pragma once
// Depth conventions, window depth, pixel centres and depth formats: the vocabulary every other part
// of clipray speaks. Matrices are column-major with p_clip = clipFromWorld * p_world.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <glm/glm.hpp>

namespace clipray {

// Where the near clip plane sits in NDC z: -1 for classic GL, 0 for glClipControl(GL_ZERO_TO_ONE).
enum class DepthConvention { NegativeOneToOne, ZeroToOne };

// Where glClipControl puts NDC y = -1: on the framebuffer's bottom row (LowerLeft, GL's default)
// or its top row (UpperLeft, Direct3D's and Vulkan's, GL 4.6 13.8.1: y_w = -(p_y / 2) y_d + o_y).
// An app that draws D3D-style flips y in its projection and draws under UpperLeft: the picture
// is upright either way, only clip space is upside down.
enum class ClipOrigin { LowerLeft, UpperLeft };

// The conventions a frame is drawn under: glClipControl's depth mode and origin, plus reversed-Z
// (near -> 1, far -> 0, depth test GREATER, clear 0). Reversed-Z is only meaningful with ZeroToOne.
struct DepthMode {
  DepthConvention convention = DepthConvention::NegativeOneToOne;
  bool reversed = false;
  ClipOrigin origin = ClipOrigin::LowerLeft;

  // z_n: the clip volume is z_n * w <= z <= w.
  double clipVolumeMinZ() const { return convention == DepthConvention::ZeroToOne ? 0.0 : -1.0; }
  // NDC z of the clip plane the rasterizer meets first along a view ray (1 for reversed-Z).
  double nearNdcZ() const { return reversed ? 1.0 : clipVolumeMinZ(); }
  // NDC z of the far clip plane (0 for reversed-Z; the plane may lie at infinity).
  double farNdcZ() const { return reversed ? clipVolumeMinZ() : 1.0; }
  // The same depth conventions with a lower-left origin.
  DepthMode lowerLeft() const { return {convention, reversed, ClipOrigin::LowerLeft}; }

  // "no", "zo", "zo-reversed", each with "-upper-left" for that origin (the names used on the
  // command line and in reports).
  std::string name() const;
  // Parses those names; nullopt for anything else (including the meaningless "no-reversed").
  static std::optional<DepthMode> parse(std::string_view text);

  friend bool operator==(const DepthMode&, const DepthMode&) = default;
};

// A clipFromWorld as a lower-left origin sees the framebuffer rows `origin` draws: its y row
// negated for UpperLeft (exact, in float too), unchanged for LowerLeft. A frame drawn with M under
// UpperLeft shows exactly what lowerLeftClipFromWorld(M, UpperLeft) shows under LowerLeft: the
// matrix the analytic side traces.
glm::dmat4 lowerLeftClipFromWorld(glm::dmat4 clipFromWorld, ClipOrigin origin);

inline constexpr DepthMode kNegativeOneToOne{DepthConvention::NegativeOneToOne, false};
inline constexpr DepthMode kZeroToOne{DepthConvention::ZeroToOne, false};
inline constexpr DepthMode kZeroToOneReversed{DepthConvention::ZeroToOne, true};

// Window depth with glDepthRange(0, 1): d = (z_ndc - z_n) / (1 - z_n).
// Inline: the compare pass calls them for every pixel.
inline double windowDepthFromNdc(double zNdc, DepthConvention convention) {
  const double zn = convention == DepthConvention::ZeroToOne ? 0.0 : -1.0;
  return (zNdc - zn) / (1.0 - zn);
}
inline double ndcFromWindowDepth(double windowDepth, DepthConvention convention) {
  const double zn = convention == DepthConvention::ZeroToOne ? 0.0 : -1.0;
  return windowDepth * (1.0 - zn) + zn;
}

struct Viewport {
  int width = 0;
  int height = 0;
  friend bool operator==(const Viewport&, const Viewport&) = default;
};

// Clip-space xy of the centre of pixel (i, j), lower-left origin:
// x' = (2i + 1) / W - 1, y' = (2j + 1) / H - 1.
glm::dvec2 clipXYOfPixelCentre(int i, int j, Viewport viewport);

// Where a window's y coordinate counts from: GL's framebuffer and glViewport count rows from the
// lower left; mouse positions in GLFW, SDL, Qt and browsers count from the upper left.
enum class WindowOrigin { LowerLeft, UpperLeft };

// Depth attachment formats a frame can be rendered with.
enum class DepthFormat { Unorm16, Unorm24, Float32 };
std::string depthFormatName(DepthFormat format);  // "16", "24", "32f"
std::optional<DepthFormat> parseDepthFormat(std::string_view text);
// One quantum of the stored depth at window depth d: 2^-bits for UNORM, the float ulp at d for 32F.
double depthQuantum(DepthFormat format, double windowDepth);

// Face culling, per object: glEnable(GL_CULL_FACE) with glCullFace(GL_BACK or GL_FRONT), or
// disabled (None). GL_FRONT_AND_BACK draws no triangle at all and is not modelled.
enum class CullFace { None, Back, Front };
std::string cullFaceName(CullFace cull);  // "none", "back", "front"
std::optional<CullFace> parseCullFace(std::string_view text);
// glFrontFace: the winding in window coordinates that faces front (GL 4.6 14.6.1).
enum class FrontFace { Ccw, Cw };
std::string frontFaceName(FrontFace front);  // "ccw", "cw"
std::optional<FrontFace> parseFrontFace(std::string_view text);

// How vertex positions reach the GPU (the rounding differs, so the tolerances differ):
// World: float clipFromWorld uniform, float world positions (what most apps do).
// CameraRelative: translation to a reference point removed in double on the CPU.
// Pretransformed: clip coordinates computed in double, uploaded as float.
enum class VertexMode { World, CameraRelative, Pretransformed };
std::string vertexModeName(VertexMode mode);  // "world", "camera-relative", "pretransformed"
std::optional<VertexMode> parseVertexMode(std::string_view text);

}  // namespace clipray
