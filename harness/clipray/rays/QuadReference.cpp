#include "clipray/rays/QuadReference.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

namespace clipray {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

Float128 quadAbs(Float128 q) {
  return q < 0 ? -q : q;
}

DoubleDouble split(Float128 q) {
  DoubleDouble result;
  result.hi = static_cast<double>(q);
  result.lo =
      std::isfinite(result.hi) ? static_cast<double>(q - static_cast<Float128>(result.hi)) : 0.0;
  return result;
}

QuadVec3 scale(const QuadVec3& v, Float128 s) {
  return {v.x * s, v.y * s, v.z * s};
}
QuadVec3 add(const QuadVec3& a, const QuadVec3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
QuadVec4 scale(const QuadVec4& v, Float128 s) {
  return {v.x * s, v.y * s, v.z * s, v.w * s};
}
QuadVec4 add(const QuadVec4& a, const QuadVec4& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w};
}
QuadVec4 sub(const QuadVec4& a, const QuadVec4& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w};
}

// Component of v across the unit vector u, its length.
double acrossLength(const glm::dvec3& v, const glm::dvec3& u) {
  return glm::length(v - glm::dot(v, u) * u);
}

// 3x3 determinant of the xyz columns selected from three 4-vectors.
Float128 minor3(const QuadVec4& a, const QuadVec4& b, const QuadVec4& c, int skip) {
  Float128 ra[3], rb[3], rc[3];
  const Float128 va[4] = {a.x, a.y, a.z, a.w}, vb[4] = {b.x, b.y, b.z, b.w},
                 vc[4] = {c.x, c.y, c.z, c.w};
  int k = 0;
  for (int col = 0; col < 4; ++col) {
    if (col == skip) continue;
    ra[k] = va[col];
    rb[k] = vb[col];
    rc[k] = vc[col];
    ++k;
  }
  return ra[0] * (rb[1] * rc[2] - rb[2] * rc[1]) - ra[1] * (rb[0] * rc[2] - rb[2] * rc[0]) +
         ra[2] * (rb[0] * rc[1] - rb[1] * rc[0]);
}

}  // namespace

QuadMat4 toQuad(const glm::dmat4& matrix) {
  QuadMat4 q;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) q.m[c][r] = matrix[c][r];
  }
  return q;
}

std::optional<QuadMat4> inverseQuad(const QuadMat4& matrix) {
  // Row-major working copy [A | I].
  Float128 a[4][8];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      a[r][c] = matrix.m[c][r];
      a[r][c + 4] = r == c ? 1 : 0;
    }
  }
  for (int col = 0; col < 4; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 4; ++r) {
      if (quadAbs(a[r][col]) > quadAbs(a[pivot][col])) pivot = r;
    }
    if (a[pivot][col] == 0) return std::nullopt;
    if (pivot != col) {
      for (int c = 0; c < 8; ++c) std::swap(a[pivot][c], a[col][c]);
    }
    const Float128 inv = 1 / a[col][col];
    for (int c = 0; c < 8; ++c) a[col][c] *= inv;
    for (int r = 0; r < 4; ++r) {
      if (r == col || a[r][col] == 0) continue;
      const Float128 f = a[r][col];
      for (int c = 0; c < 8; ++c) a[r][c] -= f * a[col][c];
    }
  }
  QuadMat4 inverse;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) inverse.m[c][r] = a[r][c + 4];
  }
  return inverse;
}

QuadVec4 quadRow(const QuadMat4& matrix, int row) {
  return {matrix.m[0][row], matrix.m[1][row], matrix.m[2][row], matrix.m[3][row]};
}
QuadVec4 quadColumn(const QuadMat4& matrix, int column) {
  return {matrix.m[column][0], matrix.m[column][1], matrix.m[column][2], matrix.m[column][3]};
}
QuadVec3 cross(const QuadVec3& a, const QuadVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Float128 dot(const QuadVec3& a, const QuadVec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
Float128 dot(const QuadVec4& a, const QuadVec4& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
}
glm::dvec3 toDouble(const QuadVec3& v) {
  return {toDouble(v.x), toDouble(v.y), toDouble(v.z)};
}

Float128 determinantQuad(const QuadMat4& matrix) {
  const QuadVec4 rows[4] = {quadRow(matrix, 0), quadRow(matrix, 1), quadRow(matrix, 2),
                            quadRow(matrix, 3)};
  Float128 det = 0;
  const Float128 first[4] = {rows[0].x, rows[0].y, rows[0].z, rows[0].w};
  for (int k = 0; k < 4; ++k) {
    const Float128 cofactor = minor3(rows[1], rows[2], rows[3], k);
    det += (k % 2 == 0 ? first[k] : -first[k]) * cofactor;
  }
  return det;
}

int robustDirectionSign(const glm::dmat4& clipFromWorld, DepthMode mode) {
  // The near plane's value at the eye e (the cofactor vector of rows 0, 1, 3) is det(M) / e.w up
  // to a fixed sign, e.w = det(mx, my, mw) up to one too, and w grows along d by dot(mw, d) =
  // det(mx, my, mw): the product leaves sign(s det M) (+1 for glm::perspectiveRH_NO). A parallel
  // projection (mw = 0, w > 0) gets the near plane's own sign, s det(mx, my, mz).
  const Float128 det = determinantQuad(toQuad(clipFromWorld));
  if (det == 0) return 0;
  return (mode.reversed ? -det : det) > 0 ? 1 : -1;
}

ProjectionCheck describeProjection(const glm::dmat4& clipFromWorld, DepthMode mode) {
  ProjectionCheck check;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(clipFromWorld[c][r])) {
        std::ostringstream message;
        message << "element " << (4 * c + r) << " (column " << c << ", row " << r
                << ") is not a finite number";
        check.problem = message.str();
        return check;
      }
    }
  }
  const QuadMat4 m = toQuad(clipFromWorld);
  const std::optional<QuadMat4> inverse = inverseQuad(m);
  if (!inverse) {
    check.problem = "the matrix is singular (it has no inverse)";
    return check;
  }
  const QuadVec4 rowX = quadRow(m, 0), rowY = quadRow(m, 1), rowZ = quadRow(m, 2),
                 rowW = quadRow(m, 3);
  const QuadVec3 mx = xyz(rowX), my = xyz(rowY), mw = xyz(rowW);
  const Float128 zNear = mode.nearNdcZ(), zFar = mode.farNdcZ();
  const QuadVec3 p = cross(my, mw), q = cross(mw, mx), r = cross(mx, my);
  const QuadVec3 nearNormal = xyz(sub(rowZ, scale(rowW, zNear)));
  const Float128 nearSign = mode.reversed ? -1 : 1;
  const QuadVec4 c0 = quadColumn(*inverse, 0), c1 = quadColumn(*inverse, 1);
  const QuadVec4 c23 = add(scale(quadColumn(*inverse, 2), zNear), quadColumn(*inverse, 3));

  ProjectionFacts facts;
  facts.parallel = mw.x == 0 && mw.y == 0 && mw.z == 0;
  // The eye: the null vector of rows 0, 1, 3 (every pixel plane and the w = 0 plane meet there),
  // homogeneous; e[3] = 0 for a parallel projection.
  const Float128 e[4] = {minor3(rowX, rowY, rowW, 0), -minor3(rowX, rowY, rowW, 1),
                         minor3(rowX, rowY, rowW, 2), -minor3(rowX, rowY, rowW, 3)};
  Float128 flip = 1;
  if (facts.parallel) {
    // w is constant: the direction's sign comes from the near plane. Every pixel ray must cross
    // it, all the same way, at a finite point. Checking the four viewport corners suffices: both
    // quantities are linear in (x', y').
    Float128 orientation = 0, nearW = 0;
    for (const Float128 x : {Float128(-1), Float128(1)}) {
      for (const Float128 y : {Float128(-1), Float128(1)}) {
        const QuadVec3 d = add(add(scale(p, x), scale(q, y)), r);
        const Float128 g = dot(nearNormal, d);
        const Float128 w = x * c0.w + y * c1.w + c23.w;
        if (g == 0 || (orientation != 0 && (g > 0) != (orientation > 0))) {
          check.problem =
              "not a projection: some pixel rays run parallel to the near plane or cross it in "
              "opposite directions";
          return check;
        }
        if (w == 0 || (nearW != 0 && (w > 0) != (nearW > 0))) {
          check.problem = "not a projection: the near plane does not meet every pixel ray";
          return check;
        }
        orientation = g;
        nearW = w;
      }
    }
    flip = orientation * nearSign > 0 ? 1 : -1;
  } else {
    // Perspective: a line of sight points where clip w grows (in front of the eye): one sign for
    // every pixel (robustDirectionSign). The near plane may be oblique (Lengyel's clip plane:
    // water, mirrors, portals): the eye must lie on its clipped side, and the pixels whose line of
    // sight meets it behind the eye (N.w <= 0: beyond its horizon) have no ray, but at least one
    // pixel must have one.
    if (e[3] == 0) {
      check.problem = "not a projection: the x, y and w rows meet at no finite eye point";
      return check;
    }
    const Float128 spread = dot(mw, r);
    if (spread == 0 || (nearNormal.x == 0 && nearNormal.y == 0 && nearNormal.z == 0)) {
      check.problem =
          "not a projection: some pixel rays run parallel to the near plane or cross it in "
          "opposite directions";
      return check;
    }
    flip = robustDirectionSign(clipFromWorld, mode);
    // The near plane's value at the eye, signed to be positive inside the view volume.
    const QuadVec4 nearPlane = sub(rowZ, scale(rowW, zNear));
    const Float128 eyeSide =
        nearSign * dot(nearPlane, QuadVec4{e[0], e[1], e[2], e[3]}) * (e[3] > 0 ? 1 : -1);
    if (!(eyeSide < 0)) {
      check.problem = "not a projection: the near plane lies behind the eye";
      return check;
    }
    bool anyRay = false;
    for (const Float128 x : {Float128(-1), Float128(1)}) {
      for (const Float128 y : {Float128(-1), Float128(1)}) {
        anyRay = anyRay || x * c0.w + y * c1.w + c23.w > 0;
      }
    }
    if (!anyRay) {
      check.problem =
          "not a projection: no pixel's line of sight crosses the near plane in front of the eye";
      return check;
    }
  }
  const QuadVec3 centre = scale(r, flip);
  const Float128 centreLength = std::sqrt(toDouble(dot(centre, centre)));
  facts.forward = toDouble(centre) / toDouble(centreLength);
  facts.forward /= glm::length(facts.forward);
  // The centre pixel's near point; in front of the eye unless the centre lies beyond an oblique
  // near plane's horizon (then it has no ray: near and far read +inf).
  const bool centreRay = c23.w > 0 || facts.parallel;
  const glm::dvec3 nearCentre = toDouble(QuadVec3{c23.x / c23.w, c23.y / c23.w, c23.z / c23.w});

  // The far plane along the centre ray: t = (z_far - z_near) / (N.w * F.d) (seed 002).
  const QuadVec3 farNormal = xyz(sub(rowZ, scale(rowW, zFar)));
  const Float128 farDot = dot(farNormal, centre) / centreLength;
  const Float128 tFar = farDot == 0 ? Float128(-1) : (zFar - zNear) / (c23.w * farDot);
  const double tCentre = tFar > 0 ? toDouble(tFar) : kInfinity;

  facts.determinant = glm::determinant(clipFromWorld);
  // Mirrored: screen right x screen up points along the view direction (a right-handed camera
  // has right x up = backwards).
  facts.mirrored = toDouble(dot(cross(p, q), centre)) > 0;
  if (facts.parallel) {
    facts.nearDistance = 0.0;
    facts.farDistance = tCentre;
  } else {
    facts.eye = {toDouble(e[0] / e[3]), toDouble(e[1] / e[3]), toDouble(e[2] / e[3])};
    if (centreRay) {
      facts.nearDistance = glm::dot(nearCentre - facts.eye, facts.forward);
      if (!(facts.nearDistance > 0)) {
        check.problem = "not a projection: the near plane lies behind the eye";
        return check;
      }
      facts.farDistance = facts.nearDistance + tCentre;
    } else {
      facts.nearDistance = kInfinity;
      facts.farDistance = kInfinity;
    }
    const QuadVec3 bottom = scale(add(r, scale(q, -1)), flip), top = scale(add(r, q), flip);
    const glm::dvec3 b = glm::normalize(toDouble(bottom)), t = glm::normalize(toDouble(top));
    facts.fovYDegrees = glm::degrees(std::atan2(glm::length(glm::cross(b, t)), glm::dot(b, t)));
  }
  check.facts = facts;
  return check;
}

QuadReference::QuadReference(const glm::dmat4& clipFromWorld, DepthMode mode, Viewport viewport)
    : viewport_(viewport), mode_(mode) {
  const QuadMat4 m = toQuad(clipFromWorld);
  const QuadMat4 inverse = inverseQuad(m).value_or(m);
  const QuadVec4 rowX = quadRow(m, 0), rowY = quadRow(m, 1), rowZ = quadRow(m, 2),
                 rowW = quadRow(m, 3);
  const QuadVec3 mx = xyz(rowX), my = xyz(rowY), mw = xyz(rowW);
  parallel_ = mw.x == 0 && mw.y == 0 && mw.z == 0;
  p_ = cross(my, mw);
  q_ = cross(mw, mx);
  r_ = cross(mx, my);
  const Float128 zNear = mode.nearNdcZ(), zFar = mode.farNdcZ();
  // The sign rule of RobustRayGenerator: perspective, robustDirectionSign against w's growth
  // along d (dot(mw, d) keeps one sign over the frame); parallel (w constant), d enters the view
  // volume through the near plane.
  facingNormal_ = parallel_ ? xyz(sub(rowZ, scale(rowW, zNear))) : mw;
  facingSign_ = parallel_ ? (mode.reversed ? -1 : 1)
                          : robustDirectionSign(clipFromWorld, mode) * (dot(mw, r_) > 0 ? 1 : -1);
  farNormal_ = xyz(sub(rowZ, scale(rowW, zFar)));
  c0_ = quadColumn(inverse, 0);
  c1_ = quadColumn(inverse, 1);
  c23_ = add(scale(quadColumn(inverse, 2), zNear), quadColumn(inverse, 3));
}

void QuadReference::row(int j, std::vector<ReferenceRay>& out) const {
  const int width = viewport_.width;
  out.resize(static_cast<std::size_t>(width));
  const Float128 y = Float128(2 * j + 1) / viewport_.height - 1;
  const QuadVec3 rowD = add(scale(q_, y), r_);
  const QuadVec4 rowN = add(scale(c1_, y), c23_);
  const Float128 depthSpan = Float128(mode_.farNdcZ()) - Float128(mode_.nearNdcZ());
  const glm::dvec3 pd = toDouble(p_), qd = toDouble(q_);
  const glm::dvec3 c0xyz = toDouble(xyz(c0_)), c1xyz = toDouble(xyz(c1_));
  for (int i = 0; i < width; ++i) {
    const Float128 x = Float128(2 * i + 1) / width - 1;  // exact pixel centre (to 1e-34)
    QuadVec3 d = add(scale(p_, x), rowD);
    // Sign: d points away from the eye (parallel: enters the frustum through the near plane).
    if (facingSign_ * dot(facingNormal_, d) < 0) d = scale(d, -1);
    const Float128 length2 = dot(d, d);
    const double guess = std::sqrt(toDouble(length2));
    const Float128 length = guess + (length2 - Float128(guess) * guess) / (2 * Float128(guess));
    const Float128 inverseLength = 1 / length;
    const QuadVec3 unit = scale(d, inverseLength);
    const QuadVec4 n = add(scale(c0_, x), rowN);
    ReferenceRay& ray = out[static_cast<std::size_t>(i)];
    if (!(n.w > 0)) {
      // The line of sight meets the near plane behind the eye (or at infinity): beyond the
      // horizon of an oblique near plane, nothing is visible and the pixel has no ray.
      ray = ReferenceRay{};
      ray.tMax = kNoRayTMax;
      continue;
    }
    const Float128 inverseW = 1 / n.w;
    const QuadVec3 origin = {n.x * inverseW, n.y * inverseW, n.z * inverseW};
    const Float128 farDot = dot(farNormal_, unit);
    const Float128 t = farDot == 0 ? Float128(-1) : depthSpan / (n.w * farDot);

    ray.origin[0] = split(origin.x);
    ray.origin[1] = split(origin.y);
    ray.origin[2] = split(origin.z);
    ray.direction[0] = split(unit.x);
    ray.direction[1] = split(unit.y);
    ray.direction[2] = split(unit.z);
    ray.tMax = t > 0 ? toDouble(t) : kInfinity;

    // Units, in double (they need a few digits, not all): one pixel step moves clip x by 2 / W.
    const glm::dvec3 u = toDouble(unit);
    const double lengthD = toDouble(length);
    const glm::dvec3 o = toDouble(origin);
    const double nw = toDouble(n.w);
    const double footprintX = 2.0 / width * acrossLength((c0xyz - o * toDouble(c0_.w)) / nw, u);
    const double footprintY =
        2.0 / viewport_.height * acrossLength((c1xyz - o * toDouble(c1_.w)) / nw, u);
    ray.pixelFootprint = std::min(footprintX, footprintY);
    if (parallel_) {
      ray.pixelAngle = ray.pixelFootprint / (std::isfinite(ray.tMax) ? ray.tMax : 1.0);
    } else {
      const double angleX = 2.0 / width * acrossLength(pd, u) / lengthD;
      const double angleY = 2.0 / viewport_.height * acrossLength(qd, u) / lengthD;
      ray.pixelAngle = std::min(angleX, angleY);
    }
  }
}

}  // namespace clipray
