// Every ray method on every hard case against the __float128 reference. Bounds come from the
// error analysis (unit roundoff u of the precision times a condition number), not from tuning.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "clipray/math/Projections.hpp"
#include "clipray/rays/HardCases.hpp"
#include "clipray/rays/QuadReference.hpp"
#include "clipray/rays/RayErrors.hpp"
#include "clipray/rays/RayMethods.hpp"
#include "support/Conditioning.hpp"

namespace clipray {
namespace {

constexpr Viewport kSmall{32, 18};
// The pixels of oblique_horizon at kSmall whose line of sight points below the water (no ray).
constexpr int kObliqueHorizonNoRay = 6 * 32;
template <typename T>
constexpr double kUnitRoundoff = std::numeric_limits<T>::epsilon() / 2;

using testing::conditionNumber;

template <typename T>
glm::dmat4 entriesOf(const glm::dmat4& m) {
  return glm::dmat4(glm::mat<4, 4, T>(m));
}

// Per-pixel measurements of one method against the reference of the entries it was handed.
template <typename T>
struct Measured {
  double angleRadMax = 0.0;  // over finite directions
  double anglePxMax = 0.0;
  double lateralMax = 0.0;  // world units
  int nonfinite = 0;
  int backward = 0;
  int noRay = 0;          // pixels without an exact ray (beyond an oblique near plane's horizon)
  int noRayDisagree = 0;  // the method gives a ray (t_max >= 0) iff the exact one does not exist
};

template <typename T>
Measured<T> measure(RayMethod method, const HardCase& c) {
  const auto generator = makeRayGenerator<T>(method, c.inputs, c.viewport);
  const QuadReference reference(entriesOf<T>(c.inputs.clipFromWorld), c.inputs.mode, c.viewport);
  Measured<T> m;
  std::vector<ReferenceRay> row;
  RayBuffer<T> rays(static_cast<std::size_t>(c.viewport.width));
  for (int j = 0; j < c.viewport.height; ++j) {
    reference.row(j, row);
    generator->generateRow(j, rays.all());
    for (int i = 0; i < c.viewport.width; ++i) {
      const CameraRay<T> ray = rays.all().load(i);
      const ReferenceRay& exact = row[static_cast<std::size_t>(i)];
      if (!exact.hasRay() || ray.tMax < T(0)) {
        m.noRay += exact.hasRay() ? 0 : 1;
        m.noRayDisagree += exact.hasRay() == (ray.tMax < T(0)) ? 1 : 0;
        continue;
      }
      const glm::dvec3 d(ray.direction), o(ray.origin);
      const bool finite = std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z) &&
                          std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z);
      if (!finite) {
        ++m.nonfinite;
        continue;
      }
      const ReferenceRay& ref = row[static_cast<std::size_t>(i)];
      if (glm::dot(d, glm::dvec3(ref.direction[0].hi, ref.direction[1].hi, ref.direction[2].hi)) <
          0) {
        ++m.backward;
      }
      const double angle = angleToReference(d, ref);
      m.angleRadMax = std::max(m.angleRadMax, angle);
      m.anglePxMax = std::max(m.anglePxMax, angle / ref.pixelAngle);
      m.lateralMax = std::max(m.lateralMax, lateralDistanceToReference(o, ref));
    }
  }
  return m;
}

// Failures the sources are known for (DESIGN.md section 2 and seed 002); every other method/case
// pair must meet the error bound.
bool knownFailure(RayMethod method, const HardCase& c) {
  const bool infiniteFar = c.name.rfind("infinite_far", 0) == 0 || c.name == "reversed_z_infinite";
  const bool orthographic = !c.fovYDegrees.has_value();
  switch (method) {
    case RayMethod::UnprojectGlm:
    case RayMethod::TwoPoint:
      // The far point is at infinity; with an oblique near plane (Lengyel) the far plane tilts
      // too and some pixel rays meet it behind the eye, so far - near points backwards.
      return infiniteFar || c.name.rfind("oblique", 0) == 0;
    case RayMethod::InversePv:
      return orthographic || c.name == "reversed_z_infinite";
    case RayMethod::PlaneCross:
    case RayMethod::PlaneCrossPre:
      // No sign fix: u x v points backwards for a right-handed y-up GL camera (seed 002 writes
      // for a y-down clip space), forwards only for the mirrored one.
      return c.name != "mirrored";
    case RayMethod::Full:
      // The sign comes from the far plane: lost when it is at infinity, wrong for reversed-Z,
      // and wrong where an oblique projection's far plane is crossed behind the eye.
      return c.name == "infinite_far_eye_mmm" || c.name == "reversed_z_infinite" ||
             c.name.rfind("oblique", 0) == 0;
    default:
      return false;
  }
}

template <typename T>
void checkEveryMethodOnEveryCase() {
  for (const HardCase& c : hardCases(kSmall)) {
    for (const RayMethod method : kRayMethods) {
      if (!missingInputs(method, c.inputs).empty() || knownFailure(method, c)) continue;
      SCOPED_TRACE(c.name + " " + c.convention() + " " + rayMethodName(method));
      const Measured<T> m = measure<T>(method, c);
      EXPECT_EQ(m.nonfinite, 0);
      EXPECT_EQ(m.backward, 0);
      // Any method that goes through an inverse of the matrix in precision T loses at most a
      // small multiple of u * cond(M) (relative); the direction is a difference of such points.
      const double kappa = conditionNumber(entriesOf<T>(c.inputs.clipFromWorld));
      EXPECT_LE(m.angleRadMax, 64.0 * kUnitRoundoff<T> * kappa);
    }
  }
}

TEST(RayMethods, EveryMethodOnEveryCaseWithinItsConditionBoundFloat) {
  checkEveryMethodOnEveryCase<float>();
}
TEST(RayMethods, EveryMethodOnEveryCaseWithinItsConditionBoundDouble) {
  checkEveryMethodOnEveryCase<double>();
}

// robust: the direction d = x' P + y' Q + R is evaluated in double from coefficients rounded
// once from quad (at0, perI, perJ; then one FMA for the row and one for the pixel): a few double
// roundings relative to kappa_d = (|P| + |Q| + |R|) / |d| (the cancellation in the sum), at most
// 8 u_double kappa_d of angle. It is then scaled by a T-precision 1 / |d| -- common to the three
// components, so it does not turn the ray -- and rounded to T once per component: each component
// moves by at most u_T of itself, the vector by at most u_T of its length, so the angle by at most
// u_T. Hence angle <= u_T + 8 u_double kappa_d: for float, the exact ray rounded once.
// The origin N.xyz / N.w carries about 4 u_T of (|c0| + |c1| + |c23|) / |N.w| per component.
template <typename T>
void checkRobust() {
  for (const HardCase& c : hardCases(kSmall)) {
    SCOPED_TRACE(c.name + " " + c.convention());
    const glm::dmat4 entries = entriesOf<T>(c.inputs.clipFromWorld);
    const glm::dvec3 mx(matrixRow(entries, 0)), my(matrixRow(entries, 1)),
        mw(matrixRow(entries, 3));
    const glm::dvec3 p = glm::cross(my, mw), q = glm::cross(mw, mx), r = glm::cross(mx, my);
    const glm::dmat4 worldFromClip = glm::inverse(entries);
    const glm::dvec4 c23 = c.inputs.mode.nearNdcZ() * worldFromClip[2] + worldFromClip[3];
    double kappaDirection = 0.0, originScale = 0.0;
    for (const double x : {-1.0, 1.0}) {
      for (const double y : {-1.0, 1.0}) {
        const glm::dvec3 d = x * p + y * q + r;
        kappaDirection = std::max(
            kappaDirection, (glm::length(p) + glm::length(q) + glm::length(r)) / glm::length(d));
      }
    }
    // Over the pixels with a ray: N.w is linear in (x', y') and, with an oblique near plane's
    // horizon in view, small near the horizon, not at a corner.
    for (int j = 0; j < c.viewport.height; ++j) {
      for (int i = 0; i < c.viewport.width; ++i) {
        const glm::dvec2 xy = clipXYOfPixelCentre(i, j, c.viewport);
        const glm::dvec4 n = xy.x * worldFromClip[0] + xy.y * worldFromClip[1] + c23;
        if (!(n.w > 0.0)) continue;
        originScale = std::max(originScale, (glm::length(glm::dvec3(worldFromClip[0])) +
                                             glm::length(glm::dvec3(worldFromClip[1])) +
                                             glm::length(glm::dvec3(c23))) /
                                                n.w);
      }
    }
    const Measured<T> m = measure<T>(RayMethod::Robust, c);
    EXPECT_EQ(m.nonfinite, 0);
    EXPECT_EQ(m.backward, 0);
    // No ray exactly where the exact ray does not exist: 6 of 18 rows of 32 lie below the
    // horizon of oblique_horizon's water plane; every other case has a ray at every pixel.
    EXPECT_EQ(m.noRayDisagree, 0);
    EXPECT_EQ(m.noRay, c.name == "oblique_horizon" ? kObliqueHorizonNoRay : 0);
    EXPECT_LE(m.angleRadMax, kUnitRoundoff<T> + 8.0 * kUnitRoundoff<double> * kappaDirection);
    EXPECT_LE(m.lateralMax, 8.0 * kUnitRoundoff<T> * originScale);
  }
}

TEST(RayMethods, RobustFloatMeetsItsRoundingBoundOnEveryCase) {
  checkRobust<float>();
}
TEST(RayMethods, RobustDoubleMeetsItsRoundingBoundOnEveryCase) {
  checkRobust<double>();
}

TEST(RayMethods, RobustTMaxIsInfiniteExactlyForInfiniteFarPlanes) {
  for (const HardCase& c : hardCases(kSmall)) {
    // An oblique projection's far plane is tilted: some rays never reach it (t_max = +inf); and
    // oblique_horizon's bottom row lies below its horizon (no ray).
    if (c.name.rfind("oblique", 0) == 0) continue;
    const bool infinite = c.name.find("infinite") != std::string::npos;
    const auto generator = makeRayGenerator<float>(RayMethod::Robust, c.inputs, c.viewport);
    const CameraRay<float> ray = generator->pixelRay(c.viewport.width / 2, 0);
    EXPECT_EQ(std::isinf(ray.tMax), infinite) << c.name << " " << c.convention();
    EXPECT_GT(ray.tMax, 0.f) << c.name;
  }
}

// robust's batch does the scalar call's operations (explicit FMAs, IEEE sqrt, division and
// conversions), so every batch code path this CPU has agrees with the scalar call bit for bit; the
// other methods' dispatched batches may contract a * b + c into FMAs.
class BatchCodePathLimit {
 public:
  explicit BatchCodePathLimit(BatchCodePath path) { limitBatchCodePath(path); }
  ~BatchCodePathLimit() { limitBatchCodePath(std::nullopt); }
};

TEST(RayMethods, RobustScalarAndBatchAgreeBitForBitOnEveryCodePath) {
  for (const BatchCodePath path : supportedBatchCodePaths()) {
    const BatchCodePathLimit limit(path);
    SCOPED_TRACE(batchCodePathName(path));
    EXPECT_EQ(batchCodePath(), batchCodePathName(path));
    // 21 = two blocks of 8 and a tail of 5.
    for (const HardCase& c : hardCases({21, 5})) {
      const auto generator = makeRayGenerator<float>(RayMethod::Robust, c.inputs, c.viewport);
      ASSERT_TRUE(generator);
      RayBuffer<float> rays(21);
      for (int j = 0; j < c.viewport.height; ++j) {
        generator->generateRow(j, rays.all());
        for (int i = 0; i < c.viewport.width; ++i) {
          const CameraRay<float> a = generator->pixelRay(i, j), b = rays.all().load(i);
          const bool same = (a.direction == b.direction || std::isnan(a.direction.x)) &&
                            (a.origin == b.origin || std::isnan(a.origin.x)) &&
                            (a.tMax == b.tMax || std::isnan(a.tMax));
          EXPECT_TRUE(same) << c.name << " " << i << "," << j;
        }
      }
    }
  }
}

// A homogeneous matrix scaled by a power of two is the same camera. robust's direction
// coefficients are P, Q, R = products of two rows (scaled by 2^2k); it rescales them by a power of
// two, so the rays are the same bits -- and |d|^2 (2^400 unscaled here) stays in float's range.
TEST(RayMethods, RobustIsBlindToAPowerOfTwoScaleOfTheMatrix) {
  for (const HardCase& c : hardCases({21, 5})) {
    SCOPED_TRACE(c.name + " " + c.convention());
    for (const double scale : {0x1p100, 0x1p-60}) {
      CameraInputs scaled = c.inputs;
      scaled.clipFromWorld = c.inputs.clipFromWorld * scale;
      const auto plain = makeRayGenerator<float>(RayMethod::Robust, c.inputs, c.viewport);
      const auto other = makeRayGenerator<float>(RayMethod::Robust, scaled, c.viewport);
      for (int j = 0; j < c.viewport.height; ++j) {
        for (int i = 0; i < c.viewport.width; ++i) {
          const CameraRay<float> a = plain->pixelRay(i, j), b = other->pixelRay(i, j);
          EXPECT_EQ(a.tMax, b.tMax) << scale << " " << i << "," << j;
          if (a.tMax < 0.f) continue;  // no ray: its origin lies behind the eye, meaningless
          EXPECT_EQ(a.direction, b.direction) << scale << " " << i << "," << j;
          if (c.name == "oblique_horizon") {
            // Its origins lie on the water plane y = 0: their y is rounding noise around zero,
            // which the scaled inverse's tiny float terms round differently (subnormals).
            EXPECT_LE(glm::length(glm::dvec3(a.origin - b.origin)),
                      1e-6 * glm::length(glm::dvec3(a.origin)));
            continue;
          }
          EXPECT_EQ(a.origin, b.origin) << scale << " " << i << "," << j;
          EXPECT_EQ(a.tMax, b.tMax) << scale << " " << i << "," << j;
        }
      }
    }
  }
}

// The accuracy target as the math gives it: robust float's worst angle is at most twice
// the float floor, the larger of what the float matrix costs (exact ray of the float entries
// against that of the double entries) and what storing the exact ray's direction in float costs.
TEST(RayMethods, RobustFloatStaysWithinTwiceTheFloatFloorOnEveryCase) {
  for (const HardCase& c : hardCases(kSmall)) {
    SCOPED_TRACE(c.name + " " + c.convention());
    const QuadReference floatReference(entriesOf<float>(c.inputs.clipFromWorld), c.inputs.mode,
                                       c.viewport);
    const QuadReference doubleReference(c.inputs.clipFromWorld, c.inputs.mode, c.viewport);
    double matrixFloor = 0.0, outputFloor = 0.0;
    std::vector<ReferenceRay> floatRow, doubleRow;
    for (int j = 0; j < c.viewport.height; ++j) {
      floatReference.row(j, floatRow);
      doubleReference.row(j, doubleRow);
      matrixFloor = std::max(matrixFloor, floorAngleRowMax(floatRow, doubleRow));
      outputFloor = std::max(outputFloor, outputFloorAngleRowMax<float>(floatRow));
    }
    EXPECT_GT(outputFloor, 0.0);
    EXPECT_LE(measure<float>(RayMethod::Robust, c).anglePxMax,
              2.0 * std::max(matrixFloor, outputFloor));
  }
}

// ---- The known failures, as the bench table shows them (at 192x108 so a pixel is small). ----

HardCase findCase(const std::string& name, DepthMode mode, Viewport size = {192, 108}) {
  for (const HardCase& c : hardCases(size)) {
    if (c.name == name && c.inputs.mode == mode) return c;
  }
  ADD_FAILURE() << "no case " << name;
  return {};
}

TEST(RayMethodsKnownFailures, TwoPointAndUnprojectCancelAboveOnePixelFarFromTheOrigin) {
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne}) {
    const HardCase c = findCase("eye_1e7", mode);
    EXPECT_GT(measure<float>(RayMethod::TwoPoint, c).anglePxMax, 1.0) << mode.name();
    EXPECT_GT(measure<float>(RayMethod::UnprojectGlm, c).anglePxMax, 1.0) << mode.name();
    EXPECT_LT(measure<float>(RayMethod::Robust, c).anglePxMax, 0.01) << mode.name();
  }
}

TEST(RayMethodsKnownFailures, TwoPointAndUnprojectAreNonFiniteWithAnInfiniteFarPlane) {
  const HardCase c = findCase("infinite_far_eye_ppp", kZeroToOne, kSmall);
  EXPECT_EQ(measure<float>(RayMethod::TwoPoint, c).nonfinite, kSmall.width * kSmall.height);
  EXPECT_EQ(measure<float>(RayMethod::UnprojectGlm, c).nonfinite, kSmall.width * kSmall.height);
}

TEST(RayMethodsKnownFailures, ListingFourPointsBackwardsForOneInfiniteFarEyePlacement) {
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne}) {
    EXPECT_EQ(
        measure<float>(RayMethod::Full, findCase("infinite_far_eye_ppp", mode, kSmall)).backward,
        0);
    EXPECT_EQ(
        measure<float>(RayMethod::Full, findCase("infinite_far_eye_mmm", mode, kSmall)).backward,
        kSmall.width * kSmall.height);
    EXPECT_EQ(
        measure<float>(RayMethod::Robust, findCase("infinite_far_eye_mmm", mode, kSmall)).backward,
        0);
  }
}

TEST(RayMethodsKnownFailures, InversePvIsWrongForOrthographic) {
  const HardCase c = findCase("ortho_far", kZeroToOne);
  EXPECT_GT(measure<double>(RayMethod::InversePv, c).anglePxMax, 1.0);
  EXPECT_LT(measure<double>(RayMethod::Robust, c).anglePxMax, 1e-6);
}

// ---- The suite itself and the matrix analysis. ----

TEST(HardCases, EveryCaseIsAProjectionWithTheFactsItWasBuiltWith) {
  const std::vector<HardCase> cases = hardCases({1920, 1080});
  EXPECT_EQ(cases.size(), 2 * 16u + 2u);
  for (const HardCase& c : cases) {
    SCOPED_TRACE(c.name + " " + c.convention());
    const ProjectionCheck check = describeProjection(c.inputs.clipFromWorld, c.inputs.mode);
    ASSERT_TRUE(check.facts) << check.problem;
    EXPECT_EQ(check.facts->parallel, !c.fovYDegrees.has_value());
    EXPECT_EQ(check.facts->mirrored, c.name == "mirrored");
    if (c.inputs.perspective) {
      EXPECT_NEAR(check.facts->fovYDegrees, *c.fovYDegrees, 1e-9 * *c.fovYDegrees + 1e-9);
      const glm::dvec3 eye(c.inputs.perspective->worldFromView[3]);
      EXPECT_NEAR(glm::length(check.facts->eye - eye), 0.0, 1e-9 * (1.0 + glm::length(eye)));
    }
  }
  EXPECT_EQ(hardCases({640, 480}).back().viewport, (Viewport{640, 480}));
  for (const HardCase& c : cases) {
    if (c.name == "viewport_7x3") {
      EXPECT_EQ(c.viewport, (Viewport{7, 3}));
    }
    if (c.name == "aspect_32_9") {
      EXPECT_EQ(c.viewport, (Viewport{1920, 540}));
    }
  }
}

TEST(HardCases, ObliqueNearPlaneIsTheClipPlane) {
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne}) {
    const HardCase c = findCase("oblique_near", mode);
    // View-space points on the plane (0, 0.2, -1, -0.5) land on the near plane z_ndc = z_n.
    for (const glm::dvec3 p : {glm::dvec3(0, 0, -0.5), glm::dvec3(0.1, 0.5, -0.4)}) {
      const glm::dvec4 clip = *c.inputs.clipFromView * glm::dvec4(p, 1.0);
      EXPECT_NEAR(clip.z / clip.w, mode.clipVolumeMinZ(), 1e-12) << mode.name();
    }
  }
}

TEST(ProjectionCheck, RejectsWhatIsNotAProjection) {
  EXPECT_EQ(describeProjection(glm::dmat4(0.0), kZeroToOne).problem,
            "the matrix is singular (it has no inverse)");
  glm::dmat4 nan(1.0);
  nan[1][2] = std::nan("");
  EXPECT_EQ(describeProjection(nan, kZeroToOne).problem,
            "element 6 (column 1, row 2) is not a finite number");
  // Invertible, but under NO its near plane row2 + row3 = (0, 0, 0, 1) has no normal: no pixel
  // ray ever crosses it.
  glm::dmat4 noNearPlane(1.0);
  noNearPlane[2] = {0.0, 0.0, -1.0, 1.0};
  noNearPlane[3] = {0.0, 0.0, 1.0, 0.0};
  EXPECT_EQ(describeProjection(noNearPlane, kNegativeOneToOne).problem,
            "not a projection: some pixel rays run parallel to the near plane or cross it in "
            "opposite directions");
  // Identity: a valid (orthographic) projection of the unit cube.
  EXPECT_TRUE(describeProjection(glm::dmat4(1.0), kNegativeOneToOne).facts);
}

TEST(RayErrors, MedianOfTheLogHistogramIsWithinOneBin) {
  LogHistogram h;
  for (int k = 1; k <= 999; ++k) h.add(k * 1e-6);
  EXPECT_NEAR(h.median(), 500e-6, 500e-6 * 0.04);
}

}  // namespace
}  // namespace clipray
