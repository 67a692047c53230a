#version 450 core
// Copies sample uSample of every pixel of the multisample depth and id attachments into
// single-sample targets: glReadPixels cannot read a multisample buffer (GL 4.6 18.2.2,
// INVALID_OPERATION where SAMPLE_BUFFERS is 1), and a resolve blit of depth keeps one sample of
// the implementation's choosing. The depth arrives as the float the texture stores or converts to.
uniform sampler2DMS uDepth;
uniform usampler2DMS uIds;
uniform int uSample;
layout(location = 0) out float outDepth;
layout(location = 1) out uint outPrimitiveId;

void main() {
  const ivec2 pixel = ivec2(gl_FragCoord.xy);
  outDepth = texelFetch(uDepth, pixel, uSample).r;
  outPrimitiveId = texelFetch(uIds, pixel, uSample).r;
}
