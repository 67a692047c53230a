#pragma once
// The GL enums `clipray check --trace` reads from a dump: their values (from Khronos' gl.xml, the
// registry glcorearb.h is generated from: the core has no GL headers), the names apitrace writes
// them by, and bitmasks as apitrace writes them.

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include "clipray/trace/DumpLine.hpp"

namespace clipray::trace {

// GL enum values (Khronos OpenGL-Registry, xml/gl.xml).
inline constexpr std::uint32_t kGlNever = 0x0200;
inline constexpr std::uint32_t kGlLess = 0x0201;
inline constexpr std::uint32_t kGlEqual = 0x0202;
inline constexpr std::uint32_t kGlLequal = 0x0203;
inline constexpr std::uint32_t kGlGreater = 0x0204;
inline constexpr std::uint32_t kGlNotequal = 0x0205;
inline constexpr std::uint32_t kGlGequal = 0x0206;
inline constexpr std::uint32_t kGlAlways = 0x0207;
inline constexpr std::uint32_t kGlDepthTest = 0x0B71;
inline constexpr std::uint32_t kGlCullFace = 0x0B44;
inline constexpr std::uint32_t kGlDepthClamp = 0x864F;
inline constexpr std::uint32_t kGlPolygonOffsetFill = 0x8037;
// GL_CLIP_DISTANCE0..7 (GL 3.0; the same values as GL 1.0's GL_CLIP_PLANE0..5).
inline constexpr std::uint32_t kGlClipDistance0 = 0x3000;
inline constexpr int kGlClipDistances = 8;
inline constexpr std::uint32_t kGlFront = 0x0404;
inline constexpr std::uint32_t kGlBack = 0x0405;
inline constexpr std::uint32_t kGlFrontAndBack = 0x0408;
inline constexpr std::uint32_t kGlCw = 0x0900;
inline constexpr std::uint32_t kGlCcw = 0x0901;
inline constexpr std::uint32_t kGlModelview = 0x1700;
inline constexpr std::uint32_t kGlProjection = 0x1701;
inline constexpr std::uint32_t kGlTexture = 0x1702;
inline constexpr std::uint32_t kGlLowerLeft = 0x8CA1;
inline constexpr std::uint32_t kGlUpperLeft = 0x8CA2;
inline constexpr std::uint32_t kGlNegativeOneToOne = 0x935E;
inline constexpr std::uint32_t kGlZeroToOne = 0x935F;
inline constexpr std::uint32_t kGlDepthBufferBit = 0x00000100;
inline constexpr std::uint32_t kGlDepth = 0x1801;  // glClearBuffer's buffer
inline constexpr std::uint32_t kGlDepthStencil = 0x84F9;
inline constexpr std::uint32_t kGlFramebuffer = 0x8D40;
inline constexpr std::uint32_t kGlReadFramebuffer = 0x8CA8;
inline constexpr std::uint32_t kGlDrawFramebuffer = 0x8CA9;
inline constexpr std::uint32_t kGlDepthAttachment = 0x8D00;
inline constexpr std::uint32_t kGlDepthStencilAttachment = 0x821A;
inline constexpr std::uint32_t kGlDepthComponent16 = 0x81A5;
inline constexpr std::uint32_t kGlDepthComponent24 = 0x81A6;
inline constexpr std::uint32_t kGlDepthComponent32 = 0x81A7;
inline constexpr std::uint32_t kGlDepthComponent32F = 0x8CAC;
inline constexpr std::uint32_t kGlDepth24Stencil8 = 0x88F0;
inline constexpr std::uint32_t kGlDepth32FStencil8 = 0x8CAD;
inline constexpr std::uint32_t kGlTrue = 1;
inline constexpr std::uint32_t kGlCompile = 0x1300;       // glNewList mode
inline constexpr std::uint32_t kGlVertexShader = 0x8B31;  // glCreateShader type
// glPushAttrib's groups that hold state followed here (OpenGL 2.1, table 6.3 and on).
inline constexpr std::uint32_t kGlPolygonBit = 0x00000008;
inline constexpr std::uint32_t kGlViewportBit = 0x00000800;
inline constexpr std::uint32_t kGlTransformBit = 0x00001000;
inline constexpr std::uint32_t kGlEnableBit = 0x00002000;

// The value of an enum argument as apitrace writes it (a name, or a number where apitrace's
// tables lack the name); nullopt for a name clipray does not know.
std::optional<std::uint32_t> glEnumValue(const DumpValue& value);
// "GL_LESS" for the values above; the hex value otherwise.
std::string glEnumName(std::uint32_t value);

// An enum argument's value; 0xFFFFFFFF (which matches no enum) for a name clipray does not know.
std::uint32_t enumArgument(const DumpCall& call, std::string_view name);

// Whether a bitmask as apitrace writes it ("GL_DEPTH_BUFFER_BIT | GL_COLOR_BUFFER_BIT", "0x100")
// holds `bit`, which the flags named in `names` include.
bool maskHasBit(const DumpValue& value, std::uint64_t bit,
                std::initializer_list<std::string_view> names);

// GL_CLIP_DISTANCEi, or GL_CLIP_PLANEi as compatibility-profile traces name the same enums:
// i, or -1 for any other capability.
int clipDistanceIndex(std::uint32_t cap);

}  // namespace clipray::trace
