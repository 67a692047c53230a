#version 450 core
// The raster pass. aPosition is what the vertex mode uploads:
//   world:           float world position (w = 1), uClipFromInput = float(clipFromWorld)
//   camera-relative: float(position - reference), uClipFromInput = float(clipFromWorld * T(reference))
//   pretransformed:  float(clip coordinates computed in double), uClipFromInput = identity
// uClipPlanes: the camera's user clip planes in the same input space (world-space plane P times
// worldFromInput, computed in double and rounded to float), gl_ClipDistance[i] = dot(P_i, p); the
// renderer enables GL_CLIP_DISTANCE0 + i for the first uClipPlaneCount of them.
// vLogDepthArgument: 1 + C w for log_depth.frag (three.js's vFragDepth = 1.0 + gl_Position.w, C
// = 1; Outerra's C); raster.frag reads none. The uniforms' locations are explicit so that the two
// mesh programs (raster.frag, log_depth.frag) share them.
layout(location = 0) in vec4 aPosition;
layout(location = 0) uniform mat4 uClipFromInput;
layout(location = 1) uniform vec4 uClipPlanes[8];
layout(location = 9) uniform int uClipPlaneCount;
layout(location = 10) uniform float uLogDepthConstant;

out float gl_ClipDistance[8];
out float vLogDepthArgument;

void main() {
  gl_Position = uClipFromInput * aPosition;
  for (int i = 0; i < 8; ++i) {
    gl_ClipDistance[i] = i < uClipPlaneCount ? dot(uClipPlanes[i], aPosition) : 1.0;
  }
  vLogDepthArgument = 1.0 + uLogDepthConstant * gl_Position.w;
}
