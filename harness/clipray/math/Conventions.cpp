#include "clipray/Conventions.hpp"

#include <cmath>
#include <limits>

namespace clipray {

namespace {

constexpr std::string_view kUpperLeftSuffix = "-upper-left";

}  // namespace

std::string DepthMode::name() const {
  std::string base;
  if (convention == DepthConvention::NegativeOneToOne) {
    base = reversed ? "no-reversed" : "no";
  } else {
    base = reversed ? "zo-reversed" : "zo";
  }
  return origin == ClipOrigin::UpperLeft ? base + std::string(kUpperLeftSuffix) : base;
}

std::optional<DepthMode> DepthMode::parse(std::string_view text) {
  ClipOrigin origin = ClipOrigin::LowerLeft;
  if (text.size() > kUpperLeftSuffix.size() && text.ends_with(kUpperLeftSuffix)) {
    text.remove_suffix(kUpperLeftSuffix.size());
    origin = ClipOrigin::UpperLeft;
  }
  std::optional<DepthMode> mode;
  if (text == "no") mode = kNegativeOneToOne;
  if (text == "zo") mode = kZeroToOne;
  if (text == "zo-reversed") mode = kZeroToOneReversed;
  if (mode) mode->origin = origin;
  return mode;
}

glm::dmat4 lowerLeftClipFromWorld(glm::dmat4 clipFromWorld, ClipOrigin origin) {
  if (origin == ClipOrigin::UpperLeft) {
    for (int column = 0; column < 4; ++column) clipFromWorld[column][1] = -clipFromWorld[column][1];
  }
  return clipFromWorld;
}

glm::dvec2 clipXYOfPixelCentre(int i, int j, Viewport viewport) {
  return {(2.0 * i + 1.0) / viewport.width - 1.0, (2.0 * j + 1.0) / viewport.height - 1.0};
}

std::string depthFormatName(DepthFormat format) {
  switch (format) {
    case DepthFormat::Unorm16:
      return "16";
    case DepthFormat::Unorm24:
      return "24";
    case DepthFormat::Float32:
      return "32f";
  }
  return "?";
}

std::optional<DepthFormat> parseDepthFormat(std::string_view text) {
  if (text == "16") return DepthFormat::Unorm16;
  if (text == "24") return DepthFormat::Unorm24;
  if (text == "32f") return DepthFormat::Float32;
  return std::nullopt;
}

double depthQuantum(DepthFormat format, double windowDepth) {
  switch (format) {
    case DepthFormat::Unorm16:
      return std::ldexp(1.0, -16);
    case DepthFormat::Unorm24:
      return std::ldexp(1.0, -24);
    case DepthFormat::Float32: {
      // The spacing of floats at d (the ulp); at d = 0 the smallest normal spacing is a fair floor.
      const float d = static_cast<float>(std::fabs(windowDepth));
      const float next = std::nextafter(d, std::numeric_limits<float>::infinity());
      return std::max(static_cast<double>(next - d),
                      static_cast<double>(std::numeric_limits<float>::min()));
    }
  }
  return 0.0;
}

std::string vertexModeName(VertexMode mode) {
  switch (mode) {
    case VertexMode::World:
      return "world";
    case VertexMode::CameraRelative:
      return "camera-relative";
    case VertexMode::Pretransformed:
      return "pretransformed";
  }
  return "?";
}

std::optional<VertexMode> parseVertexMode(std::string_view text) {
  if (text == "world") return VertexMode::World;
  if (text == "camera-relative") return VertexMode::CameraRelative;
  if (text == "pretransformed") return VertexMode::Pretransformed;
  return std::nullopt;
}

std::string cullFaceName(CullFace cull) {
  switch (cull) {
    case CullFace::None:
      return "none";
    case CullFace::Back:
      return "back";
    case CullFace::Front:
      return "front";
  }
  return "?";
}

std::optional<CullFace> parseCullFace(std::string_view text) {
  if (text == "none") return CullFace::None;
  if (text == "back") return CullFace::Back;
  if (text == "front") return CullFace::Front;
  return std::nullopt;
}

std::string frontFaceName(FrontFace front) {
  return front == FrontFace::Ccw ? "ccw" : "cw";
}

std::optional<FrontFace> parseFrontFace(std::string_view text) {
  if (text == "ccw") return FrontFace::Ccw;
  if (text == "cw") return FrontFace::Cw;
  return std::nullopt;
}

}  // namespace clipray
