#pragma once
// Whether a traced fragment shader writes gl_FragDepth: then the depth buffer holds what the shader
// computes (three.js's logarithmicDepthBuffer, Outerra's and Cesium's log depth), not the
// projective depth of the matrix the draw uses.

#include <string_view>

namespace clipray::trace {

// Whether the GLSL source assigns gl_FragDepth (=, or a compound assignment) in code the
// preprocessor keeps: comments left out; #define / #undef followed, #ifdef, #ifndef, #if and #elif
// of defined(NAME), !defined(NAME), 0 or 1 evaluated, any other condition taken as true (so
// three.js's `#if defined( USE_LOGDEPTHBUF )` chunk counts only where the program defines it). A
// redeclaration (`layout(depth_greater) out float gl_FragDepth;`) is no write.
bool writesFragDepth(std::string_view source);

}  // namespace clipray::trace
