// Camera rays and analytic surfaces in GLSL (float), shared by every shader that needs them.
// The math mirrors the CPU side (harness/clipray/rays/RobustRays, intersect/Primitives) so that
// a reconcile compares the same construction in float against double.
//
// Every computation runs in the primitive's local frame: clipFromLocal = clipFromWorld *
// worldFromLocal is formed in double on the CPU and only then rounded to float, so a camera far
// from the origin costs no precision here.

// Row i of a column-major matrix: the clip coordinate i as a plane, clip_i = dot(row_i, (p, 1)).
vec4 matrixRow(mat4 m, int i) { return vec4(m[0][i], m[1][i], m[2][i], m[3][i]); }

struct CameraRay {
  vec3 origin;     // on the near plane, where the rasterizer clips
  vec3 direction;  // into the view volume, not normalized
  bool hasRay;     // false where the line of sight meets the near plane behind the eye
};

// The ray of the pixel whose NDC position is ndc ("robust" method, DESIGN.md section 2): the
// intersection line of the planes x_ndc = ndc.x and y_ndc = ndc.y, i.e. row0 - x row3 and
// row1 - y row3. No inverse matrix, so it holds for perspective, orthographic, oblique, mirrored
// and infinite-far matrices alike. Orientation and "no ray" are RobustRayGenerator's
// (harness/clipray/rays/RobustRays.cpp), so that the two sides agree on which pixels show nothing:
//   nearNdcZ:    NDC z of the near plane (-1 for GL_NEGATIVE_ONE_TO_ONE, 0 for GL_ZERO_TO_ONE,
//                1 for reversed-Z)
//   facingSign:  RobustRayGenerator::facingSign(): the direction d satisfies
//                facingSign * dot(facing, d) > 0, where facing is the xyz of row3 (perspective:
//                w grows along d, or falls for the one camera kind whose rays point at the eye),
//                or of the near plane row2 - nearNdcZ row3 (parallel: w is constant). Both tests
//                read the same in any frame (a local frame's rows are the world's times its
//                transform), so the local frame's rows serve.
//   parallel:    row3 has no xyz part.
// The origin is the point on the near plane; it must lie in front of the eye (clip w > 0). Beyond
// the horizon of an oblique near plane (Lengyel's water plane) the line of sight meets it behind
// the eye: no ray, and the rasterizer shows nothing there either.
CameraRay cameraRayThroughNdc(mat4 clipFromLocal, vec2 ndc, float nearNdcZ, float facingSign,
                              bool parallel) {
  vec4 row0 = matrixRow(clipFromLocal, 0), row1 = matrixRow(clipFromLocal, 1);
  vec4 row2 = matrixRow(clipFromLocal, 2), row3 = matrixRow(clipFromLocal, 3);
  vec4 planeX = row0 - ndc.x * row3;
  vec4 planeY = row1 - ndc.y * row3;
  vec4 planeNear = row2 - nearNdcZ * row3;
  vec3 xCrossY = cross(planeX.xyz, planeY.xyz);
  // The point on all three planes (Cramer's rule with cross products).
  vec3 yCrossNear = cross(planeY.xyz, planeNear.xyz);
  vec3 nearCrossX = cross(planeNear.xyz, planeX.xyz);
  float determinant = dot(planeX.xyz, yCrossNear);
  vec3 origin =
      -(planeX.w * yCrossNear + planeY.w * nearCrossX + planeNear.w * xCrossY) / determinant;
  vec3 facing = parallel ? planeNear.xyz : row3.xyz;
  vec3 direction = facingSign * dot(facing, xCrossY) < 0.0 ? -xCrossY : xCrossY;
  float originW = dot(row3, vec4(origin, 1.0));
  bool finiteOrigin = !any(isinf(origin)) && !any(isnan(origin));
  return CameraRay(origin, direction, originW > 0.0 && finiteOrigin);
}

const int kSphere = 0;
const int kDisk = 1;
const int kQuad = 2;
const int kBox = 3;
const int kPlane = 4;
const float kNoHit = -1.0;

// Unit sphere: the numerically stable quadratic. With half-b b = o.d and a = d.d, the
// discriminant b^2 - a c is computed as a (1 - |o - (b/a) d|^2), which does not cancel for a
// small sphere far away; the smaller-magnitude root comes from c / q, not -b + sqrt(...).
float intersectUnitSphere(vec3 o, vec3 d) {
  float a = dot(d, d);
  float b = dot(o, d);
  vec3 closest = o - (b / a) * d;
  float discriminant = a * (1.0 - dot(closest, closest));
  if (discriminant < 0.0) return kNoHit;
  float q = -(b + (b >= 0.0 ? 1.0 : -1.0) * sqrt(discriminant));
  float c = dot(o, o) - 1.0;
  float t0 = q / a, t1 = c / q;
  float near = min(t0, t1), far = max(t0, t1);
  return near > 0.0 ? near : (far > 0.0 ? far : kNoHit);
}

// z = 0 plane; `bounds` 0: unbounded, 1: unit disk, 2: square |x|, |y| <= 1.
float intersectLocalPlane(vec3 o, vec3 d, int bounds) {
  if (d.z == 0.0) return kNoHit;
  float t = -o.z / d.z;
  if (!(t > 0.0)) return kNoHit;
  vec2 p = o.xy + t * d.xy;
  if (bounds == 1 && dot(p, p) > 1.0) return kNoHit;
  if (bounds == 2 && max(abs(p.x), abs(p.y)) > 1.0) return kNoHit;
  return t;
}

// Surface of the cube |x|, |y|, |z| <= 1 by slabs; a zero direction component is handled
// without 0 * inf (the origin must then lie within that slab).
float intersectUnitBox(vec3 o, vec3 d) {
  float entry = -1.0 / 0.0, exit = 1.0 / 0.0;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (abs(o[i]) > 1.0) return kNoHit;
      continue;
    }
    float t0 = (-1.0 - o[i]) / d[i], t1 = (1.0 - o[i]) / d[i];
    entry = max(entry, min(t0, t1));
    exit = min(exit, max(t0, t1));
  }
  if (entry > exit) return kNoHit;
  return entry > 0.0 ? entry : (exit > 0.0 ? exit : kNoHit);
}

float intersectPrimitive(int kind, vec3 o, vec3 d) {
  if (kind == kSphere) return intersectUnitSphere(o, d);
  if (kind == kDisk) return intersectLocalPlane(o, d, 1);
  if (kind == kQuad) return intersectLocalPlane(o, d, 2);
  if (kind == kBox) return intersectUnitBox(o, d);
  return intersectLocalPlane(o, d, 0);
}
