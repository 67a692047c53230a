#version 450 core
// Exact raster of an analytic primitive: drawn on a proxy that covers it (raster.vert), each
// fragment intersects the true surface with its own camera ray (camera_rays.glsl) and writes the
// hit's depth and the primitive id; fragments whose ray misses are discarded.
uniform mat4 uClipFromLocal;  // clipFromWorld * worldFromLocal, rounded to float once
uniform vec2 uViewportSize;
uniform float uNearNdcZ;  // -1 (NO), 0 (ZO) or 1 (reversed-Z)
uniform float uFacingSign;  // RobustRayGenerator::facingSign() of the camera (camera_rays.glsl)
uniform bool uParallel;     // the camera's w row has no xyz part
uniform float uClipMinZ;  // z_n of the clip volume: window depth = (z_ndc - z_n) / (1 - z_n)
uniform vec2 uDepthRange;  // glDepthRange(n, f): gl_FragDepth is stored as written, so mapped here
uniform bool uDefaultDepthRange;  // (0, 1): the depth as it is
uniform int uKind;
uniform uint uPrimitiveId;
layout(location = 0) out uint outPrimitiveId;

void main() {
  vec2 ndc = 2.0 * gl_FragCoord.xy / uViewportSize - 1.0;
  CameraRay ray = cameraRayThroughNdc(uClipFromLocal, ndc, uNearNdcZ, uFacingSign, uParallel);
  if (!ray.hasRay) discard;
  float t = intersectPrimitive(uKind, ray.origin, ray.direction);
  if (t == kNoHit) discard;
  vec4 hit = vec4(ray.origin + t * ray.direction, 1.0);
  float clipZ = dot(matrixRow(uClipFromLocal, 2), hit);
  float clipW = dot(matrixRow(uClipFromLocal, 3), hit);
  float depth = (clipZ / clipW - uClipMinZ) / (1.0 - uClipMinZ);
  // Beyond the far plane (or behind the eye): the CPU ray's t_max cuts it off too.
  if (!(clipW > 0.0) || !(depth >= 0.0 && depth <= 1.0)) discard;
  gl_FragDepth = uDefaultDepthRange ? depth : uDepthRange.x + (uDepthRange.y - uDepthRange.x) * depth;
  outPrimitiveId = uPrimitiveId;
}
