#version 450 core
// The raster pass. aPosition is what the vertex mode uploads:
//   world:           float world position (w = 1), uClipFromInput = float(clipFromWorld)
//   camera-relative: float(position - reference), uClipFromInput = float(clipFromWorld * T(reference))
//   pretransformed:  float(clip coordinates computed in double), uClipFromInput = identity
layout(location = 0) in vec4 aPosition;
uniform mat4 uClipFromInput;

void main() { gl_Position = uClipFromInput * aPosition; }
