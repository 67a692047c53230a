#version 450 core
// One triangle over the whole target (vertex ids 0..2, no buffers): the sample fetch pass draws
// every pixel once.
void main() {
  const vec2 corner = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
  gl_Position = vec4(corner, 0.0, 1.0);
}
