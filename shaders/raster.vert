#version 450 core
// The raster pass. aPosition is what the vertex mode uploads:
//   world:           float world position (w = 1), uClipFromInput = float(clipFromWorld)
//   camera-relative: float(position - reference), uClipFromInput = float(clipFromWorld * T(reference))
//   pretransformed:  float(clip coordinates computed in double), uClipFromInput = identity
// uClipPlanes: the camera's user clip planes in the same input space (world-space plane P times
// worldFromInput, computed in double and rounded to float), gl_ClipDistance[i] = dot(P_i, p); the
// renderer enables GL_CLIP_DISTANCE0 + i for the first uClipPlaneCount of them.
layout(location = 0) in vec4 aPosition;
uniform mat4 uClipFromInput;
uniform vec4 uClipPlanes[8];
uniform int uClipPlaneCount;

out float gl_ClipDistance[8];

void main() {
  gl_Position = uClipFromInput * aPosition;
  for (int i = 0; i < 8; ++i) {
    gl_ClipDistance[i] = i < uClipPlaneCount ? dot(uClipPlanes[i], aPosition) : 1.0;
  }
}
