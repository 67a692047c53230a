// Analytic primitives (Primitives.hpp): closed-form hits of each canonical shape under affine
// placements, accuracy of the stable sphere quadratic against the naive one, and their place in
// SceneIntersector (ids after the triangles, ties, every query path bit-identical).
//
// Error bounds are in units of u = 2^-53 (the unit roundoff of double).

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/intersect/Primitives.hpp"
#include "clipray/intersect/SceneIntersector.hpp"
#include "support/TestScenes.hpp"

namespace clipray {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kU = 0x1p-53;

AnalyticPrimitive primitive(PrimitiveKind kind, const glm::dmat4& worldFromLocal,
                            const std::string& name = "p") {
  AnalyticPrimitive p;
  p.name = name;
  p.kind = kind;
  p.worldFromLocal = worldFromLocal;
  p.localFromWorld = glm::inverse(worldFromLocal);
  return p;
}

glm::dmat4 placed(const glm::dvec3& position, const glm::dvec3& scale) {
  return glm::scale(glm::translate(glm::dmat4(1.0), position), scale);
}

AnalyticPrimitive sphere(const glm::dvec3& centre, double radius) {
  return primitive(PrimitiveKind::Sphere, placed(centre, glm::dvec3(radius)));
}

double hitT(const AnalyticPrimitive& p, const glm::dvec3& origin, const glm::dvec3& direction,
            double tMax = kInf) {
  return intersectPrimitive(p, Ray{origin, direction, tMax});
}

double relativeError(double computed, double exact) {
  return std::abs(computed - exact) / std::abs(exact);
}

// References in binary128 (113-bit significand, GCC's software __float128): products of doubles
// are exact in it, so its results are exact to ~1e-33 relative, far below the u ~ 1e-16 checked.
__extension__ typedef __float128 Quad;

Quad quadSqrt(Quad x) {
  if (!(x > 0)) return 0;
  Quad s = static_cast<Quad>(std::sqrt(static_cast<double>(x)));
  for (int i = 0; i < 3; ++i) s = (s + x / s) / 2;  // Newton: 53 -> 106 -> 113 bits
  return s;
}

// The near intersection of the world ray with the sphere (centre, radius), by the stable form in
// binary128: the reference the double results are held to.
double referenceSphereT(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& centre,
                        double radius) {
  const Quad ox = Quad(o.x) - centre.x, oy = Quad(o.y) - centre.y, oz = Quad(o.z) - centre.z;
  const Quad a = Quad(d.x) * d.x + Quad(d.y) * d.y + Quad(d.z) * d.z;
  const Quad b = ox * d.x + oy * d.y + oz * d.z;
  const Quad c = ox * ox + oy * oy + oz * oz - Quad(radius) * radius;
  const Quad root = quadSqrt(b * b - a * c);  // no cancellation that matters at 113 bits here
  const Quad q = b < 0 ? root - b : -(b + root);
  const Quad t0 = c / q, t1 = q / a;
  return static_cast<double>(t0 < t1 ? t0 : t1);
}

// The textbook quadratic in world coordinates: what the stable form is compared against.
double naiveSphereT(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& centre,
                    double radius) {
  const glm::dvec3 oc = o - centre;
  const double a = glm::dot(d, d);
  const double b = 2.0 * glm::dot(oc, d);
  const double c = glm::dot(oc, oc) - radius * radius;
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return kInf;
  return (-b - std::sqrt(disc)) / (2.0 * a);
}

// ---------------------------------------------------------------------------------------------
// Spheres

TEST(PrimitiveSphere, HitFromOutsideIsDistanceMinusRadius) {
  const AnalyticPrimitive s = sphere({0, 0, -10}, 2.0);
  EXPECT_EQ(hitT(s, {0, 0, 0}, {0, 0, -1}), 8.0);
  EXPECT_EQ(hitT(s, {0, 0, 0}, {0, 0, -0.5}), 16.0);  // t is in units of the direction's length
  // An oblique ray aimed at the centre: the direction is normalised in double (relative error
  // <= 2u per component) and the stable quadratic adds a few u: relative error <= 16u.
  const glm::dvec3 centre(3.0, 4.0, -12.0);  // |centre| = 13
  const glm::dvec3 direction = glm::normalize(centre);
  EXPECT_LE(relativeError(hitT(sphere(centre, 1.0), {0, 0, 0}, direction), 12.0), 16 * kU);
  EXPECT_EQ(hitT(s, {0, 0, 0}, {0, 0, 1}), kInf);  // the sphere is behind
  EXPECT_EQ(hitT(s, {0, 0, 0}, {1, 0, 0}), kInf);  // passes beside it
}

TEST(PrimitiveSphere, FromInsideHitsTheFarRoot) {
  const AnalyticPrimitive s = sphere({0, 0, -10}, 2.0);
  EXPECT_EQ(hitT(s, {0, 0, -10}, {0, 0, -1}), 2.0);  // from the centre
  EXPECT_EQ(hitT(s, {1, 0, -10}, {1, 0, 0}), 1.0);
  EXPECT_EQ(hitT(s, {1, 0, -10}, {-1, 0, 0}), 3.0);
  // Exactly on the surface: heading in hits the far side, heading out misses.
  EXPECT_EQ(hitT(s, {0, 0, -8}, {0, 0, -1}), 4.0);
  EXPECT_EQ(hitT(s, {0, 0, -8}, {0, 0, 1}), kInf);
}

TEST(PrimitiveSphere, TangentRayHitsAndTheNextOneOutMisses) {
  const AnalyticPrimitive s = sphere({0, 0, 0}, 1.0);
  // Closest approach exactly 1 (every quantity exact): disc == 0, a grazing hit at t = 5.
  EXPECT_EQ(hitT(s, {1, 0, 5}, {0, 0, -1}), 5.0);
  EXPECT_EQ(hitT(s, {0, -1, 5}, {0, 0, -1}), 5.0);
  EXPECT_EQ(hitT(s, {std::nextafter(1.0, 2.0), 0, 5}, {0, 0, -1}), kInf);
  // Tangent at the origin itself: the only root is t = 0, which is not a hit.
  EXPECT_EQ(hitT(s, {1, 0, 0}, {0, 0, -1}), kInf);
}

TEST(PrimitiveSphere, EllipsoidByNonUniformScale) {
  const AnalyticPrimitive e = primitive(PrimitiveKind::Sphere, placed({0, 0, -10}, {2, 1, 0.5}));
  EXPECT_EQ(hitT(e, {0, 0, 0}, {0, 0, -1}), 9.5);
  EXPECT_EQ(hitT(e, {-10, 0, -10}, {1, 0, 0}), 8.0);
  EXPECT_EQ(hitT(e, {0, -5, -10}, {0, 1, 0}), 4.0);
  EXPECT_EQ(hitT(e, {2.5, 0, 0}, {0, 0, -1}), kInf);  // beyond the 2-long semi-axis
  // Point (2 cos a, sin a, -10) of the equator, approached along -z from above: a hit within
  // relative 16u of the exact t (the scale is exact, the local origin is rounded once).
  const double angle = 0.7;
  const glm::dvec3 target(2 * std::cos(angle) * 0.999, std::sin(angle) * 0.999, -10.0);
  const double local = 1.0 - 0.999 * 0.999;  // (z/0.5)^2 at the hit
  const double exact = 10.0 - 0.5 * std::sqrt(local);
  EXPECT_LE(relativeError(hitT(e, {target.x, target.y, 0}, {0, 0, -1}), exact), 16 * kU);
}

// Scale invariance of the stable form, and what the textbook form makes of small spheres far
// away. Both spheres sit 10^6 radii from the origin: a tiny one (r = 1e-3 at distance 1e3) and a
// huge one (r = 1e6 at distance 1e12), the same configuration at scales 10^9 apart.
TEST(PrimitiveSphere, TinyAndHugeSpheresAreAccurateWhereTheNaiveQuadraticIsNot) {
  struct Case {
    double radius, distance;
  };
  for (const Case& k : {Case{1e-3, 1e3}, Case{1e6, 1e12}}) {
    SCOPED_TRACE(k.radius);
    const glm::dvec3 centre(0, 0, -k.distance);
    const AnalyticPrimitive s = sphere(centre, k.radius);
    // Straight at the centre: exact t = distance - radius (one rounding). Stable quadratic: the
    // near root c / q, with c and q each within a few u (c compensated, q a sum of same-sign
    // terms), plus the rounding of the inverse matrix and of the local origin (~4u): <= 8u.
    const double exact = k.distance - k.radius;
    const double t = hitT(s, {0, 0, 0}, {0, 0, -1});
    EXPECT_LE(relativeError(t, exact), 8 * kU);
    // The textbook form: b^2 and 4ac are ~4 distance^2 and cancel down to ~4 radius^2, so the
    // discriminant's relative error is ~u (distance / radius)^2 = 1e12 u ~ 1e-4: the hit is off
    // by 1e4 to 1e6 ulp (measured: 3e4 and 3e5 on axis, 4e5 and 1e6 off axis).
    EXPECT_GT(relativeError(naiveSphereT({0, 0, 0}, {0, 0, -1}, centre, k.radius), exact),
              1e4 * kU);

    // Off-centre, through the surface point at 0.6 radius from the axis, against the binary128
    // reference for the same (rounded) direction. The local origin and direction are rounded by
    // a few u of |o - centre| ~ t, which moves the hit by a few u of t (incidence cosine 0.8),
    // plus the quadratic's own few u: <= 16u.
    const glm::dvec3 target = centre + k.radius * glm::dvec3(0.6, 0.0, 0.8);
    const glm::dvec3 direction = glm::normalize(target);
    const double reference = referenceSphereT({0, 0, 0}, direction, centre, k.radius);
    EXPECT_LE(relativeError(hitT(s, {0, 0, 0}, direction), reference), 16 * kU);
    EXPECT_GT(relativeError(naiveSphereT({0, 0, 0}, direction, centre, k.radius), reference),
              1e4 * kU);
  }
  // At 10^9 radii the textbook discriminant is pure rounding noise (4ac rounds to b^2 or past
  // it): a wrong grazing hit or a miss. The stable form is still within a few u.
  const glm::dvec3 centre(0, 0, -1e6);
  const AnalyticPrimitive tiny = sphere(centre, 1e-3);
  const double exact = 1e6 - 1e-3;
  EXPECT_LE(relativeError(hitT(tiny, {0, 0, 0}, {0, 0, -1}), exact), 8 * kU);
  const double naive = naiveSphereT({0, 0, 0}, {0, 0, -1}, centre, 1e-3);
  EXPECT_TRUE(!(naive < kInf) || relativeError(naive, exact) > 1e6 * kU) << naive;
}

TEST(PrimitiveSphere, HugeSphereSeenFromJustAboveIsExactToItsOwnScale) {
  // A planet (r = 1e6) seen from 1 unit above its surface. The local frame is 1e-6 world units
  // per local unit and 1e-6 is not a double: the local origin carries a rounding of ~4u of
  // |o - centre| ~ r, i.e. a few ulp of the radius, which the hit inherits (divided by the cosine
  // of the incidence angle). Bound: 8u * r / cos + 8u * t (the quadratic's own error).
  const glm::dvec3 centre(0, -1e6, 0);
  const AnalyticPrimitive planet = sphere(centre, 1e6);
  for (const double slope : {0.0, 0.25, 1.0}) {
    const glm::dvec3 direction = glm::normalize(glm::dvec3(slope, -1.0, 0.3 * slope));
    const double reference = referenceSphereT({0, 1, 0}, direction, centre, 1e6);
    const double cosine = -direction.y;
    const double bound = 8 * kU * 1e6 / cosine + 8 * kU * reference;
    EXPECT_NEAR(hitT(planet, {0, 1, 0}, direction), reference, bound) << slope;
  }
  // A power-of-two radius makes the local frame exact, and then the compensated c keeps the near
  // root within a few u even though c = |o|^2 - 1 ~ 2^-19 is a difference of numbers near 1.
  const AnalyticPrimitive exactPlanet = sphere({0, -0x1p20, 0}, 0x1p20);
  const glm::dvec3 direction = glm::normalize(glm::dvec3(0.25, -1.0, 0.1));
  const double reference = referenceSphereT({0, 1, 0}, direction, {0, -0x1p20, 0}, 0x1p20);
  EXPECT_LE(relativeError(hitT(exactPlanet, {0, 1, 0}, direction), reference), 16 * kU);
}

TEST(PrimitiveSphere, CompensatedConstantTerm) {
  // |v|^2 - 1 near the unit sphere, against binary128. Plain double arithmetic would be off by
  // ~u |v|^2 ~ 1e-16 absolute, i.e. ~1e-9 relative to c ~ 1e-7.
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double worstPlain = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const glm::dvec3 v =
        glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng))) * (1.0 + 1e-7 * unit(rng));
    const Quad exact = Quad(v.x) * v.x + Quad(v.y) * v.y + Quad(v.z) * v.z - 1;  // exact
    const double c = lengthSquaredMinusOne(v);
    // One final rounding (u) plus terms of order u^2 |v|^2 (~1e-32, << u |c| ~ 1e-23).
    EXPECT_LE(std::abs(c - static_cast<double>(exact)), 2 * kU * std::abs(c) + 1e-30) << k;
    const double plain = glm::dot(v, v) - 1.0;
    worstPlain = std::max(worstPlain, std::abs(plain - c) / std::abs(c));
  }
  EXPECT_GT(worstPlain, 1e4 * kU);
}

// ---------------------------------------------------------------------------------------------
// Disks, quads, planes

TEST(PrimitiveDisk, InsideOutsideAndOnTheRim) {
  const AnalyticPrimitive disk = primitive(PrimitiveKind::Disk, placed({0, 0, -5}, {2, 2, 1}));
  const glm::dvec3 down(0, 0, -1);
  EXPECT_EQ(hitT(disk, {1, 0.5, 0}, down), 5.0);
  EXPECT_EQ(hitT(disk, {0, 0, 0}, down), 5.0);
  EXPECT_EQ(hitT(disk, {2.5, 0, 0}, down), kInf);
  EXPECT_EQ(hitT(disk, {1.5, 1.5, 0}, down), kInf);  // inside the bounding square only
  // The rim counts as a hit; one ulp outside does not.
  EXPECT_EQ(hitT(disk, {2, 0, 0}, down), 5.0);
  EXPECT_EQ(hitT(disk, {0, -2, 0}, down), 5.0);
  EXPECT_EQ(hitT(disk, {std::nextafter(2.0, 3.0), 0, 0}, down), kInf);
  // From below (two-sided), parallel (also within the plane), and behind.
  EXPECT_EQ(hitT(disk, {0, 0, -7}, {0, 0, 1}), 2.0);
  EXPECT_EQ(hitT(disk, {0, 0, 0}, {1, 0, 0}), kInf);
  EXPECT_EQ(hitT(disk, {-5, 0, -5}, {1, 0, 0}), kInf);
  EXPECT_EQ(hitT(disk, {0, 0, -6}, down), kInf);
  // Oblique: (-4, 0, 0) + t (1, 0, -1) reaches z = -5 at t = 5, x = 1: inside; from (-1, 0, 0)
  // it reaches x = 4: outside.
  EXPECT_EQ(hitT(disk, {-4, 0, 0}, {1, 0, -1}), 5.0);
  EXPECT_EQ(hitT(disk, {-1, 0, 0}, {1, 0, -1}), kInf);
}

TEST(PrimitiveQuad, CornersAndEdgesCount) {
  // Half-sizes 2 x 0.5 at z = -4 (powers of two: the local frame is exact, so are the corners).
  const AnalyticPrimitive quad = primitive(PrimitiveKind::Quad, placed({0, 0, -4}, {2, 0.5, 1}));
  const glm::dvec3 down(0, 0, -1);
  for (const double sx : {-2.0, 2.0}) {
    for (const double sy : {-0.5, 0.5}) {
      EXPECT_EQ(hitT(quad, {sx, sy, 0}, down), 4.0) << sx << " " << sy;
      EXPECT_EQ(hitT(quad, {std::nextafter(sx, 2 * sx), sy, 0}, down), kInf);
      EXPECT_EQ(hitT(quad, {sx, std::nextafter(sy, 2 * sy), 0}, down), kInf);
    }
  }
  EXPECT_EQ(hitT(quad, {1.9, 0.45, 0}, down), 4.0);  // a disk would miss here: corners are kept
  // Rotated a quarter turn about z (an exact matrix: x -> y, y -> -x): the long side is now y.
  glm::dmat4 turn(0.0);
  turn[0] = {0, 1, 0, 0};
  turn[1] = {-1, 0, 0, 0};
  turn[2] = {0, 0, 1, 0};
  turn[3] = {0, 0, -4, 1};
  const AnalyticPrimitive turned =
      primitive(PrimitiveKind::Quad, turn * glm::scale(glm::dmat4(1.0), {2, 0.5, 1}));
  EXPECT_EQ(hitT(turned, {0.5, 2, 0}, down), 4.0);
  EXPECT_EQ(hitT(turned, {-0.5, -2, 0}, down), 4.0);
  EXPECT_EQ(hitT(turned, {2, 0.5, 0}, down), kInf);
}

TEST(PrimitivePlane, HitParallelAndBehind) {
  // The plane y = -1 (local z maps to world y; an exact permutation matrix).
  glm::dmat4 m(0.0);
  m[0] = {1, 0, 0, 0};
  m[1] = {0, 0, -1, 0};
  m[2] = {0, 1, 0, 0};
  m[3] = {0, -1, 0, 1};
  const AnalyticPrimitive plane = primitive(PrimitiveKind::Plane, m);
  EXPECT_EQ(hitT(plane, {0, 3, 0}, {0, -1, 0}), 4.0);
  EXPECT_EQ(hitT(plane, {1e6, 3, -1e6}, {0, -1, 0}), 4.0);  // unbounded
  EXPECT_EQ(hitT(plane, {0, -3, 0}, {0, 1, 0}), 2.0);       // from below
  EXPECT_EQ(hitT(plane, {0, 3, 0}, {0, 1, 0}), kInf);       // behind
  EXPECT_EQ(hitT(plane, {0, 3, 0}, {1, 0, 0}), kInf);       // parallel
  EXPECT_EQ(hitT(plane, {0, -1, 0}, {1, 0, 0}), kInf);      // within the plane
  EXPECT_EQ(hitT(plane, {0, -1, 0}, {0, -1, 0}), kInf);     // starting on it: t = 0 is no hit
  EXPECT_EQ(hitT(plane, {0, 1, 0}, {3, -4, 0}), 0.5);
}

// ---------------------------------------------------------------------------------------------
// Boxes

TEST(PrimitiveBox, AxisAlignedFromOutsideInsideAndAlongAxes) {
  // Half-extents (1, 2, 4) centred at (0, 0, -5) (powers of two: an exact local frame).
  const AnalyticPrimitive box = primitive(PrimitiveKind::Box, placed({0, 0, -5}, {1, 2, 4}));
  // From outside along -z (two zero direction components): the face z = -1.
  EXPECT_EQ(hitT(box, {0, 0, 0}, {0, 0, -1}), 1.0);
  EXPECT_EQ(hitT(box, {0.5, -1.5, 0}, {0, 0, -1}), 1.0);
  EXPECT_EQ(hitT(box, {1.5, 0, 0}, {0, 0, -1}), kInf);  // outside the x slab: no 0 * inf NaN
  // On the x slab's boundary exactly, moving within the face plane x = 1: the face counts.
  EXPECT_EQ(hitT(box, {1, 0, 0}, {0, 0, -1}), 1.0);
  EXPECT_EQ(hitT(box, {std::nextafter(1.0, 2.0), 0, 0}, {0, 0, -1}), kInf);
  // From inside: the exit.
  EXPECT_EQ(hitT(box, {0, 0, -5}, {0, 0, 1}), 4.0);
  EXPECT_EQ(hitT(box, {0, 0, -5}, {1, 0, 0}), 1.0);
  EXPECT_EQ(hitT(box, {0, 0, -5}, {0, -1, 0}), 2.0);
  EXPECT_EQ(hitT(box, {0.5, 1, -4}, {-1, 0, 0}), 1.5);
  // Behind, and pointing away from inside-the-slabs positions.
  EXPECT_EQ(hitT(box, {0, 0, 0}, {0, 0, 1}), kInf);
  EXPECT_EQ(hitT(box, {0, 0, -10}, {0, 0, -1}), kInf);
  EXPECT_EQ(hitT(box, {0, 0, -9}, {0, 0, -1}), kInf);  // on the face, leaving: t = 0 is no hit
  // An oblique entry through the face x = -1: (-3, 0, -5) + t (1, 0.5, 0.25): x = -1 at t = 2.
  EXPECT_EQ(hitT(box, {-3, 0, -5}, {1, 0.5, 0.25}), 2.0);
}

TEST(PrimitiveBox, EdgeOnThroughAnEdge) {
  const AnalyticPrimitive box = primitive(PrimitiveKind::Box, placed({0, 0, -5}, {1, 2, 4}));
  // In the plane z = -5, diagonally through the edge x = 1, y = 2: entry and exit coincide (the
  // slabs touch at t = 1 exactly); the boundary counts.
  EXPECT_EQ(hitT(box, {0, 3, -5}, {1, -1, 0}), 1.0);
  // Through the corner (1, 2, -1) from outside.
  EXPECT_EQ(hitT(box, {0, 3, 0}, {1, -1, -1}), 1.0);
  // Shifted off the edge by a little: passes beside the box.
  EXPECT_EQ(hitT(box, {0, 3.0000001, -5}, {1, -1, 0}), kInf);
  // Shifted into the box by a little: enters through the face y = 2 just before the edge.
  const double t = hitT(box, {0, 2.9999999, -5}, {1, -1, 0});
  EXPECT_NEAR(t, 0.9999999, 1e-15);
}

TEST(PrimitiveBox, OrientedBox) {
  // A unit cube turned 45 degrees about z, centred at (0, 0, -5): an edge faces -x at x = -sqrt 2.
  const double pi = std::acos(-1.0);
  const glm::dmat4 m = glm::rotate(glm::translate(glm::dmat4(1.0), {0, 0, -5}), pi / 4, {0, 0, 1});
  const AnalyticPrimitive box = primitive(PrimitiveKind::Box, m);
  // The rotation's entries are rounded (cos 45 is not a double), so the box is perturbed by a few
  // u of its size; the slab divisions add a few u: within 16u of t = 10 - sqrt 2.
  const double edge = hitT(box, {-10, 0, -5}, {1, 0, 0});
  EXPECT_LE(relativeError(edge, 10.0 - std::sqrt(2.0)), 16 * kU);
  // Turned 30 degrees: a ray along the face normal (cos 30, sin 30, 0) meets the face at t = 9.
  const glm::dmat4 m30 =
      glm::rotate(glm::translate(glm::dmat4(1.0), {0, 0, -5}), pi / 6, {0, 0, 1});
  const AnalyticPrimitive box30 = primitive(PrimitiveKind::Box, m30);
  const glm::dvec3 normal(std::cos(pi / 6), std::sin(pi / 6), 0.0);
  EXPECT_LE(relativeError(hitT(box30, glm::dvec3(0, 0, -5) - 10.0 * normal, normal), 9.0), 16 * kU);
  // From the centre along the normal: the exit at t = 1.
  EXPECT_LE(relativeError(hitT(box30, {0, 0, -5}, normal), 1.0), 16 * kU);
  // A parallelepiped (shear): local x = world x - 0.5 world y. At y = 0.5 the faces x = -1 and
  // x = 1 are at world x = -0.75 and 1.25: from (-5, 0.5, 0) along +x the entry is at t = 4.25,
  // from inside the exit.
  glm::dmat4 shear(1.0);
  shear[1][0] = 0.5;  // world x += 0.5 * local y
  const AnalyticPrimitive sheared = primitive(PrimitiveKind::Box, shear);
  EXPECT_EQ(hitT(sheared, {-5, 0.5, 0}, {1, 0, 0}), 4.25);
  EXPECT_EQ(hitT(sheared, {0, 0.5, 0}, {1, 0, 0}), 1.25);
}

// ---------------------------------------------------------------------------------------------
// Bounds on t, and rays that are not rays

TEST(Primitive, TMaxCutsOffAndNegativeTMaxNeverHits) {
  const AnalyticPrimitive s = sphere({0, 0, -10}, 2.0);
  EXPECT_EQ(hitT(s, {0, 0, 0}, {0, 0, -1}, 8.0), 8.0);  // t == tMax is a hit
  EXPECT_EQ(hitT(s, {0, 0, 0}, {0, 0, -1}, std::nextafter(8.0, 0.0)), kInf);
  // From inside, the far root beyond tMax: no hit (the near root is behind the origin).
  EXPECT_EQ(hitT(s, {0, 0, -10}, {0, 0, -1}, 1.5), kInf);
  // The near root beyond tMax means no hit, even though t is computed before the comparison.
  EXPECT_EQ(hitT(s, {0, 0, 0}, {0, 0, -1}, 7.0), kInf);

  const std::vector<AnalyticPrimitive> all = {
      s,
      primitive(PrimitiveKind::Disk, placed({0, 0, -5}, {2, 2, 1})),
      primitive(PrimitiveKind::Quad, placed({0, 0, -5}, {2, 2, 1})),
      primitive(PrimitiveKind::Box, placed({0, 0, -5}, {1, 1, 1})),
      primitive(PrimitiveKind::Plane, placed({0, 0, -5}, {1, 1, 1})),
  };
  for (const AnalyticPrimitive& p : all) {
    SCOPED_TRACE(primitiveKindName(p.kind));
    EXPECT_LT(hitT(p, {0, 0, 0}, {0, 0, -1}), kInf);
    EXPECT_EQ(hitT(p, {0, 0, 0}, {0, 0, -1}, kNoRayTMax), kInf);
    EXPECT_EQ(hitT(p, {0, 0, 0}, {0, 0, -1}, -kInf), kInf);
    EXPECT_EQ(hitT(p, {0, 0, 0}, {0, 0, -1}, 0.0), kInf);
    EXPECT_EQ(hitT(p, {0, 0, 0}, {0, 0, -1}, std::nan("")), kInf);
    EXPECT_EQ(hitT(p, {0, 0, 0}, {0, 0, -1}, 1.0), kInf);  // every hit is further than 1
    EXPECT_EQ(hitT(p, {0, std::nan(""), 0}, {0, 0, -1}), kInf);
    EXPECT_EQ(hitT(p, {0, 0, 0}, {0, 0, -kInf}), kInf);
    EXPECT_EQ(hitT(p, {0, 0, 0}, {0, 0, 0}), kInf);  // no direction
  }
}

// ---------------------------------------------------------------------------------------------
// In SceneIntersector

Scene mixedScene(bool withBvh) {
  Scene scene;
  scene.objects.push_back(
      testing::quad("floor", {-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}));  // y = 0
  scene.objects.push_back(testing::icosphere("ball", {-1.5, 1.0, 0.5}, 0.7, withBvh ? 3 : 0));
  scene.primitives.push_back(primitive(PrimitiveKind::Sphere, placed({1.5, 1, 0}, {1, 1, 1}), "s"));
  scene.primitives.push_back(
      primitive(PrimitiveKind::Box,
                glm::rotate(placed({0, 0.5, -2}, {0.8, 0.5, 0.6}), 0.4, glm::dvec3(0, 1, 0)), "b"));
  glm::dmat4 upright(0.0);  // local z -> world y, local y -> world -z
  upright[0] = {1, 0, 0, 0};
  upright[1] = {0, 0, -1, 0};
  upright[2] = {0, 1, 0, 0};
  upright[3] = {0, 0, 0, 1};
  // A disk lying exactly on the floor (y = 0): ties with the floor's triangles.
  scene.primitives.push_back(
      primitive(PrimitiveKind::Disk, upright * glm::scale(glm::dmat4(1.0), {1.5, 1.5, 1}), "d"));
  scene.primitives.push_back(
      primitive(PrimitiveKind::Quad, glm::translate(glm::dmat4(1.0), {0, 0.75, 2}) * upright, "q"));
  // Two identical spheres: ties between analytic primitives go to the smaller id.
  scene.primitives.push_back(sphere({0, 2.5, 0}, 0.5));
  scene.primitives.push_back(sphere({0, 2.5, 0}, 0.5));
  scene.primitives.push_back(
      primitive(PrimitiveKind::Plane, placed({0, 0, -6}, {1, 1, 1}), "wall"));
  return scene;
}

TEST(SceneIntersectorPrimitives, IdsFollowTheTriangles) {
  const Scene scene = mixedScene(true);
  const SceneIntersector intersector(scene, {0.0, 3.0, 6.0});
  const PrimitiveIdTable ids(scene);
  ASSERT_TRUE(intersector.usesBvh());
  EXPECT_EQ(intersector.triangleCount(), scene.triangleCount());
  EXPECT_EQ(intersector.analyticCount(), scene.primitives.size());
  EXPECT_EQ(intersector.primitiveIdCount(), scene.triangleCount() + scene.primitives.size());
  EXPECT_EQ(ids.firstAnalyticId, scene.triangleCount() + 1);
  EXPECT_FALSE(intersector.isAnalytic(0));
  EXPECT_FALSE(intersector.isAnalytic(1));
  EXPECT_FALSE(intersector.isAnalytic(ids.firstAnalyticId - 1));
  EXPECT_TRUE(intersector.isAnalytic(ids.firstAnalyticId));
  EXPECT_TRUE(intersector.isAnalytic(intersector.primitiveIdCount()));
  EXPECT_FALSE(intersector.isAnalytic(intersector.primitiveIdCount() + 1));
  EXPECT_EQ(intersector.analyticPrimitive(ids.firstAnalyticId + 1).name, "b");
  EXPECT_EQ(intersector.analyticPrimitive(ids.firstAnalyticId + 6).name, "wall");

  // Straight down onto the analytic sphere (primitive 0): t = 3 - 2 = 1 from y = 3.
  const Ray down{{1.5, 3, 0}, {0, -1, 0}, kInf};
  const Hit hit = intersector.closestHit(down);
  EXPECT_EQ(hit.primitiveId, ids.firstAnalyticId);
  EXPECT_EQ(hit.t, 1.0);
  EXPECT_EQ(ids.decode(hit.primitiveId).analytic, 0);
  // With tMax short of it, nothing; past the sphere's far side (disabled by tMax): the floor.
  EXPECT_FALSE(intersector.closestHit({{1.5, 3, 0}, {0, -1, 0}, 0.5}).hit());
  const Hit floor = intersector.closestHit({{3.5, 3, 3.5}, {0, -1, 0}, kInf});
  EXPECT_EQ(floor.t, 3.0);
  EXPECT_EQ(ids.decode(floor.primitiveId).object, 0);
  Scene trianglesOnly;
  trianglesOnly.objects = scene.objects;
  EXPECT_GT(intersector.memoryBytes(), SceneIntersector(trianglesOnly, {0, 3, 6}).memoryBytes());
}

TEST(SceneIntersectorPrimitives, TiesGoToTheSmallerId) {
  const Scene scene = mixedScene(false);
  const SceneIntersector intersector(scene, {0, 0, 0});
  const PrimitiveIdTable ids(scene);
  // The floor's triangles and the disk coincide at y = 0: both give t = 2 exactly; the triangle
  // has the smaller id.
  const Ray onDisk{{0.3, 2.0, 0.6}, {0, -1, 0}, kInf};
  const std::uint32_t disk = ids.firstAnalyticId + 2;
  EXPECT_EQ(intersector.intersectOne(disk, onDisk).t, 2.0);
  const Hit hit = intersector.closestHit(onDisk);
  EXPECT_EQ(hit.t, 2.0);
  EXPECT_EQ(ids.decode(hit.primitiveId).object, 0);
  EXPECT_EQ(intersector.closestHitLinear(onDisk).primitiveId, hit.primitiveId);
  // Two identical spheres: the first.
  const Ray onSpheres{{0, 5, 0}, {0, -1, 0}, kInf};
  const Hit sphereHit = intersector.closestHit(onSpheres);
  EXPECT_EQ(sphereHit.primitiveId, ids.firstAnalyticId + 4);
  EXPECT_EQ(sphereHit.t, 2.0);
  EXPECT_EQ(intersector.intersectOne(ids.firstAnalyticId + 5, onSpheres).t, sphereHit.t);
}

TEST(SceneIntersectorPrimitives, IntersectOneAnswersForEachPrimitive) {
  const Scene scene = mixedScene(true);
  const SceneIntersector intersector(scene, {0.0, 3.0, 6.0});
  EXPECT_FALSE(intersector.intersectOne(0, {{1.5, 3, 0}, {0, -1, 0}, kInf}).hit());
  EXPECT_FALSE(
      intersector.intersectOne(intersector.primitiveIdCount() + 1, {{1.5, 3, 0}, {0, -1, 0}, kInf})
          .hit());
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int checked = 0;
  for (int k = 0; k < 300; ++k) {
    const glm::dvec3 origin(unit(rng), 3.0 + unit(rng), 6.0 + unit(rng));
    const glm::dvec3 target(2.5 * unit(rng), 0.5 + unit(rng), 2.0 * unit(rng) - 1.0);
    const Ray ray{origin, glm::normalize(target - origin), k % 3 == 0 ? 7.0 : kInf};
    const Hit closest = intersector.closestHit(ray);
    // Every primitive (triangle or analytic) answers a t that is not before the closest hit, and
    // the closest one answers the same t bit for bit.
    for (std::uint32_t id = 1; id <= intersector.primitiveIdCount(); ++id) {
      const Hit one = intersector.intersectOne(id, ray);
      if (!one.hit()) continue;
      ASSERT_EQ(one.primitiveId, id);
      ASSERT_LE(one.t, ray.tMax);
      ASSERT_TRUE(closest.hit());
      ASSERT_TRUE(one.t > closest.t || (one.t == closest.t && id >= closest.primitiveId)) << id;
    }
    if (!closest.hit()) continue;
    const Hit again = intersector.intersectOne(closest.primitiveId, ray);
    ASSERT_EQ(again.primitiveId, closest.primitiveId);
    ASSERT_EQ(std::bit_cast<std::uint64_t>(again.t), std::bit_cast<std::uint64_t>(closest.t));
    checked += intersector.isAnalytic(closest.primitiveId);
  }
  EXPECT_GT(checked, 10);
}

// closestHit, closestHitLinear, closestHits and closestHitsTile agree bit for bit.
void expectAllPathsIdentical(const SceneIntersector& intersector, const std::vector<Ray>& rays,
                             int width) {
  std::vector<Hit> packet(rays.size());
  intersector.closestHits(rays, packet);
  // The same rays as a row-major frame of `width` columns traced in 8 x 8 tiles.
  std::vector<Hit> tiled(rays.size());
  const int height = static_cast<int>(rays.size()) / width;
  ASSERT_EQ(static_cast<std::size_t>(width * height), rays.size());
  for (int y0 = 0; y0 < height; y0 += 8) {
    for (int x0 = 0; x0 < width; x0 += 8) {
      const std::size_t first = static_cast<std::size_t>(y0) * width + x0;
      intersector.closestHitsTile(rays.data() + first, tiled.data() + first, width,
                                  std::min(8, width - x0), std::min(8, height - y0));
    }
  }
  int analytic = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Hit linear = intersector.closestHitLinear(rays[i]);
    const Hit single = intersector.closestHit(rays[i]);
    analytic += intersector.isAnalytic(linear.primitiveId);
    for (const Hit& other : {single, packet[i], tiled[i]}) {
      ASSERT_EQ(other.primitiveId, linear.primitiveId) << i;
      ASSERT_EQ(std::bit_cast<std::uint64_t>(other.t), std::bit_cast<std::uint64_t>(linear.t)) << i;
    }
  }
  EXPECT_GT(analytic, 0);
}

TEST(SceneIntersectorPrimitives, EveryQueryPathMatchesTheLinearScan) {
  for (const bool withBvh : {true, false}) {
    SCOPED_TRACE(withBvh);
    const Scene scene = mixedScene(withBvh);
    const glm::dvec3 eye(0.2, 3.0, 6.0);
    const SceneIntersector intersector(scene, eye);
    ASSERT_EQ(intersector.usesBvh(), withBvh);
    std::mt19937_64 rng(withBvh ? 4 : 5);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    // Primary rays of a 40 x 24 frame, some with a finite tMax, some without a ray.
    std::vector<Ray> primary;
    for (int y = 0; y < 24; ++y) {
      for (int x = 0; x < 40; ++x) {
        const glm::dvec3 target(-4.0 + 8.0 * (x + 0.5) / 40, 2.5 - 3.0 * (y + 0.5) / 24, 0.0);
        Ray ray{eye, glm::normalize(target - eye), (x + y) % 5 == 0 ? 7.5 : kInf};
        if ((x * 7 + y) % 23 == 0) ray.tMax = kNoRayTMax;
        primary.push_back(ray);
      }
    }
    expectAllPathsIdentical(intersector, primary, 40);
    // Incoherent rays from everywhere, including inside the primitives and along axes.
    std::vector<Ray> random;
    for (int k = 0; k < 64 * 40; ++k) {
      Ray ray;
      ray.origin = {3.0 * unit(rng), 1.0 + 2.0 * unit(rng), 3.0 * unit(rng)};
      ray.direction = glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)));
      if (k % 17 == 0) ray.direction = {0, -1, 0};
      if (k % 19 == 0) ray.direction = {0, 0, -1};
      ray.tMax = k % 4 == 0 ? 2.0 : kInf;
      if (k % 97 == 0) ray.origin.x = std::nan("");
      random.push_back(ray);
    }
    expectAllPathsIdentical(intersector, random, 64);
  }
}

TEST(SceneIntersectorPrimitives, PrimitivesWithoutTriangles) {
  Scene scene;
  scene.primitives.push_back(sphere({0, 0, -5}, 1.0));
  scene.primitives.push_back(primitive(PrimitiveKind::Plane, placed({0, 0, -8}, {1, 1, 1})));
  const SceneIntersector intersector(scene, {0, 0, 0});
  EXPECT_EQ(intersector.triangleCount(), 0u);
  EXPECT_EQ(intersector.primitiveIdCount(), 2u);
  EXPECT_TRUE(intersector.isAnalytic(1));
  const Hit hit = intersector.closestHit({{0, 0, 0}, {0, 0, -1}, kInf});
  EXPECT_EQ(hit.primitiveId, 1u);
  EXPECT_EQ(hit.t, 4.0);
  const Hit wall = intersector.closestHit({{3, 0, 0}, {0, 0, -1}, kInf});
  EXPECT_EQ(wall.primitiveId, 2u);
  EXPECT_EQ(wall.t, 8.0);
  EXPECT_FALSE(intersector.closestHit({{3, 0, 0}, {0, 0, 1}, kInf}).hit());
  std::vector<Ray> rays;
  for (int k = 0; k < 64; ++k) {
    rays.push_back({{0.1 * k - 3.2, 0.05 * k - 1.6, 0}, {0, 0, -1}, kInf});
  }
  expectAllPathsIdentical(intersector, rays, 8);
}

}  // namespace
}  // namespace clipray
