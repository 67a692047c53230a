#version 450 core
// raster.frag's primitive id, and a logarithmic depth written by the shader (RenderRequest::logDepth,
// compare/LogarithmicDepth.hpp) as three.js writes it (mrdoob/three.js
// src/renderers/shaders/ShaderChunk/logdepthbuf_fragment.glsl.js):
//   gl_FragDepth = log2(vFragDepth) * logDepthBufFC * 0.5,
// vFragDepth = 1.0 + C gl_Position.w interpolated (raster.vert), logDepthBufFC = 2 / log2(1 + C far)
// rounded to a float uniform (C = 1 for three.js, Outerra's constant otherwise). Under reversed-Z
// (GL_GREATER, clear 0) it writes 1 - that, so that the nearest fragment still passes.
layout(location = 11) uniform uint uFirstId;
layout(location = 12) uniform float uLogDepthBufFC;
layout(location = 13) uniform bool uLogDepthReversed;
in float vLogDepthArgument;
layout(location = 0) out uint outPrimitiveId;

void main() {
  outPrimitiveId = uFirstId + uint(gl_PrimitiveID);
  float logDepth = log2(vLogDepthArgument) * uLogDepthBufFC * 0.5;
  gl_FragDepth = uLogDepthReversed ? 1.0 - logDepth : logDepth;
}
