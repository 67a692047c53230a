#include "clipray/rays/HardCases.hpp"

#include <cmath>
#include <limits>

#include <glm/ext/matrix_clip_space.hpp>

#include "clipray/math/Projections.hpp"

namespace clipray {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct PerspectiveSpec {
  glm::dvec3 eye;
  glm::dvec3 target;
  double fovYDegrees;
  double nearDistance;
  double farDistance;  // kInfinity: infinite far plane
  bool mirrored = false;
};

struct OrthographicSpec {
  glm::dvec3 eye;
  glm::dvec3 target;
  double halfHeight;
  double nearDistance;
  double farDistance;
};

glm::dmat4 lookAt(const glm::dvec3& eye, const glm::dvec3& target, bool mirrored) {
  glm::dmat4 view = viewFromWorldLookAt(eye, target, {0.0, 1.0, 0.0});
  if (mirrored) {
    glm::dmat4 mirror(1.0);
    mirror[0][0] = -1.0;  // view-space x flipped: a mirrored image, det < 0
    view = mirror * view;
  }
  return view;
}

double aspectOf(Viewport viewport) {
  return static_cast<double>(viewport.width) / static_cast<double>(viewport.height);
}

HardCase perspectiveCase(std::string name, std::string description, const PerspectiveSpec& spec,
                         DepthMode builtFor, DepthMode drawnUnder, Viewport viewport) {
  const double aspect = aspectOf(viewport);
  const glm::dmat4 view = lookAt(spec.eye, spec.target, spec.mirrored);
  const std::optional<double> far =
      std::isfinite(spec.farDistance) ? std::optional<double>(spec.farDistance) : std::nullopt;
  const glm::dmat4 projection = perspectiveClipFromView(glm::radians(spec.fovYDegrees), aspect,
                                                        spec.nearDistance, far, builtFor);
  HardCase c;
  c.name = std::move(name);
  c.description = std::move(description);
  c.viewport = viewport;
  c.fovYDegrees = spec.fovYDegrees;
  c.inputs.clipFromWorld = projection * view;
  c.inputs.mode = drawnUnder;
  c.inputs.clipFromView = projection;
  c.inputs.viewFromWorld = view;
  c.inputs.perspective =
      PerspectiveScalars{glm::radians(spec.fovYDegrees), aspect, spec.nearDistance,
                         spec.farDistance, glm::inverse(view)};
  return c;
}

HardCase orthographicCase(std::string name, std::string description, const OrthographicSpec& spec,
                          DepthMode mode, Viewport viewport) {
  const double halfWidth = spec.halfHeight * aspectOf(viewport);
  const glm::dmat4 view = lookAt(spec.eye, spec.target, false);
  const glm::dmat4 projection =
      orthographicClipFromView(-halfWidth, halfWidth, -spec.halfHeight, spec.halfHeight,
                               spec.nearDistance, spec.farDistance, mode);
  HardCase c;
  c.name = std::move(name);
  c.description = std::move(description);
  c.viewport = viewport;
  c.inputs.clipFromWorld = projection * view;
  c.inputs.mode = mode;
  c.inputs.clipFromView = projection;
  c.inputs.viewFromWorld = view;
  return c;
}

// A perspective camera whose projection is given directly (off-axis, oblique): no fov scalars.
HardCase matrixCase(std::string name, std::string description, const glm::dmat4& projection,
                    const glm::dmat4& view, DepthMode mode, Viewport viewport, double fovY) {
  HardCase c;
  c.name = std::move(name);
  c.description = std::move(description);
  c.viewport = viewport;
  c.fovYDegrees = fovY;
  c.inputs.clipFromWorld = projection * view;
  c.inputs.mode = mode;
  c.inputs.clipFromView = projection;
  c.inputs.viewFromWorld = view;
  return c;
}

// Lengyel's oblique near-plane clipping ("Oblique View Frustum Depth Projection and Clipping",
// 2005): replaces row 2 so that the view-space plane `clipPlane` (camera on its negative side)
// becomes the near plane, keeping the far corners. NegativeOneToOne: row2 = 2 C / (C.q) - row3;
// ZeroToOne: row2 = C / (C.q), with q the far corner opposite the plane.
glm::dmat4 obliqueNear(glm::dmat4 projection, const glm::dvec4& clipPlane, DepthMode mode) {
  auto sign = [](double v) { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); };
  const glm::dvec4 q =
      glm::inverse(projection) * glm::dvec4(sign(clipPlane.x), sign(clipPlane.y), 1.0, 1.0);
  const double scale =
      (mode.convention == DepthConvention::ZeroToOne ? 1.0 : 2.0) / glm::dot(clipPlane, q);
  for (int column = 0; column < 4; ++column) {
    const double row3 = projection[column][3];
    projection[column][2] =
        clipPlane[column] * scale - (mode.convention == DepthConvention::ZeroToOne ? 0.0 : row3);
  }
  return projection;
}

}  // namespace

std::vector<HardCase> hardCases(Viewport size) {
  std::vector<HardCase> cases;
  const PerspectiveSpec standard{{3.0, 2.5, 5.0}, {0.0, 0.5, 0.0}, 60.0, 0.1, 100.0};
  for (const DepthMode mode : {kNegativeOneToOne, kZeroToOne}) {
    auto add = [&](std::string name, std::string description, const PerspectiveSpec& spec,
                   Viewport viewport) {
      cases.push_back(
          perspectiveCase(std::move(name), std::move(description), spec, mode, mode, viewport));
    };
    add("standard", "plain perspective, fov 60, near 0.1, far 100", standard, size);
    add("seed002_renderer", "seed 002's renderer: near 0.01, eye ~280 units from the origin",
        {{200.0, 140.0, 130.0}, {0.0, 5.0, 0.0}, 60.0, 0.01, 1000.0}, size);
    const glm::dvec3 eye5(60000.0, 30000.0, 74000.0), eye7(6.0e6, 3.0e6, 7.4e6);
    const glm::dvec3 look(-1.0, -0.2, -0.5);
    add("eye_1e5", "eye 1e5 from the origin, near 1, far 1e4",
        {eye5, eye5 + 100.0 * look, 60.0, 1.0, 1.0e4}, size);
    add("eye_1e7", "eye 1e7 from the origin, near 10, far 1e6",
        {eye7, eye7 + 1000.0 * look, 60.0, 10.0, 1.0e6}, size);
    // Listing 4's infinite-far sign rests on the sign of a zero: dot(mw - mz, d) is +0 unless
    // every component of its (backward-pointing) d is negative, i.e. the view direction lies in
    // the all-positive octant for the whole image (fov 30 keeps it there).
    add("infinite_far_eye_ppp", "infinite far plane, eye at (+,+,+) looking at the origin",
        {{300.0, 300.0, 300.0}, {0.0, 0.0, 0.0}, 30.0, 0.1, kInfinity}, size);
    add("infinite_far_eye_mmm",
        "infinite far plane, eye at (-,-,-): the zero in listing 4 turns negative",
        {{-300.0, -300.0, -300.0}, {0.0, 0.0, 0.0}, 30.0, 0.1, kInfinity}, size);
    add("telephoto", "fov 0.05 degrees, near 1, far 1e4",
        {{300.0, 200.0, 250.0}, {0.0, 5.0, 0.0}, 0.05, 1.0, 1.0e4}, size);
    PerspectiveSpec mirrored = standard;
    mirrored.mirrored = true;
    add("mirrored", "view with x flipped (det < 0): a mirrored image", mirrored, size);
    add("aspect_32_9", "32:9 viewport", standard, {size.width, std::max(1, size.width * 9 / 32)});
    add("viewport_7x3", "a 7x3 viewport", standard, {7, 3});

    const OrthographicSpec orthoFar{{5000.0, 3000.0, 4000.0}, {0.0, 0.0, 0.0}, 6.0, 6000.0, 8000.0};
    cases.push_back(orthographicCase("ortho_far",
                                     "orthographic, eye 7000 from the origin, near 6000, far 8000",
                                     orthoFar, mode, size));
    cases.push_back(orthographicCase(
        "ortho_symmetric_depth", "orthographic with near + far = 0 (near -50, far 50)",
        {{3.0, 2.5, 5.0}, {0.0, 0.5, 0.0}, 4.0, -50.0, 50.0}, mode, size));
    cases.push_back(
        orthographicCase("ortho_negative_near", "orthographic with a negative near (-20, far 100)",
                         {{3.0, 2.5, 5.0}, {0.0, 0.5, 0.0}, 4.0, -20.0, 100.0}, mode, size));

    const glm::dmat4 view = lookAt(standard.eye, standard.target, false);
    const double aspect = aspectOf(size);
    const glm::dmat4 offAxis =
        mode.convention == DepthConvention::ZeroToOne
            ? glm::frustumRH_ZO(-0.02 * aspect, 0.1 * aspect, -0.01, 0.05, 0.1, 100.0)
            : glm::frustumRH_NO(-0.02 * aspect, 0.1 * aspect, -0.01, 0.05, 0.1, 100.0);
    cases.push_back(
        matrixCase("off_axis", "off-axis frustum (l -0.02a, r 0.1a, b -0.01, t 0.05, near 0.1)",
                   offAxis, view, mode, size, glm::degrees(std::atan(0.5) + std::atan(0.1))));
    // Near plane tilted: through view-space z = -0.5 on the axis, normal (0, 0.2, -1).
    const glm::dmat4 oblique =
        obliqueNear(perspectiveClipFromView(glm::radians(60.0), aspect, 0.1, 100.0, mode),
                    {0.0, 0.2, -1.0, -0.5}, mode);
    cases.push_back(matrixCase("oblique_near", "oblique near plane (Lengyel), tilted 11 degrees",
                               oblique, view, mode, size, 60.0));
    // A water reflection pass without its mirror: the eye 3 below the water plane y = 0 looks up
    // 11.8 degrees (fov 60) through it, Lengyel's near plane at the water. The horizon crosses the
    // image: the pixels below it look away from the water and have no ray (the raster shows
    // nothing there). Right-handed, fov 60: rows x, y and w are the plain projection's.
    const glm::dmat4 underWater = lookAt({0.0, -3.0, 12.0}, {0.0, -0.5, 0.0}, false);
    const glm::dvec4 waterInView =
        glm::transpose(glm::inverse(underWater)) * glm::dvec4(0.0, 1.0, 0.0, 0.0);
    const glm::dmat4 horizon = obliqueNear(
        perspectiveClipFromView(glm::radians(60.0), aspect, 0.1, 1000.0, mode), waterInView, mode);
    cases.push_back(matrixCase(
        "oblique_horizon",
        "oblique near plane at the water level, horizon in view: pixels below it have no ray",
        horizon, underWater, mode, size, 60.0));
  }
  cases.push_back(perspectiveCase("reversed_z_infinite", "reversed-Z with an infinite far plane",
                                  {{3.0, 2.5, 5.0}, {0.0, 0.5, 0.0}, 60.0, 0.1, kInfinity},
                                  kZeroToOneReversed, kZeroToOneReversed, size));
  cases.push_back(perspectiveCase(
      "no_matrix_under_zo",
      "built for NO (near 1, far 100), drawn under ZO: the near plane moves to 2fn/(f+n)",
      {{3.0, 2.5, 5.0}, {0.0, 0.5, 0.0}, 60.0, 1.0, 100.0}, kNegativeOneToOne, kZeroToOne, size));
  return cases;
}

std::vector<std::string> hardCaseNames() {
  std::vector<std::string> names;
  for (const HardCase& c : hardCases({16, 9})) {
    bool seen = false;
    for (const std::string& n : names) seen = seen || n == c.name;
    if (!seen) names.push_back(c.name);
  }
  return names;
}

}  // namespace clipray
