// autoCameras: four cameras framed on a scene's bounds (see AutoCameras.hpp).

#include "clipray/scene/AutoCameras.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/InputError.hpp"

namespace clipray {
namespace {

struct Bounds {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  void add(const glm::dvec3& p) {
    if (!std::isfinite(p.x + p.y + p.z)) return;
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool empty() const { return !(lo.x <= hi.x); }
};

Bounds sceneBounds(const Scene& scene) {
  Bounds bounds;
  for (const MeshObject& mesh : scene.objects) {
    for (const glm::u32vec3& t : mesh.triangles) {
      for (int k = 0; k < 3; ++k) bounds.add(mesh.worldPositions[t[k]]);
    }
  }
  for (const AnalyticPrimitive& primitive : scene.primitives) {
    if (primitive.kind == PrimitiveKind::Plane) continue;
    const bool flat =
        primitive.kind == PrimitiveKind::Disk || primitive.kind == PrimitiveKind::Quad;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec4 local((corner & 1) ? 1.0 : -1.0, (corner & 2) ? 1.0 : -1.0,
                             flat ? 0.0 : ((corner & 4) ? 1.0 : -1.0), 1.0);
      bounds.add(glm::dvec3(primitive.worldFromLocal * local));
    }
  }
  return bounds;
}

// The height of the lowest large upward-facing surface: up-facing triangles (counter-clockwise
// normal within 30 deg of +y, glTF's front faces) sorted by height, the height at which a fifth
// of their area lies at or below it. A mesh wound the other way (OBJ and PLY promise nothing) has
// none: then horizontal triangles facing either way count. The bounding box's floor when there
// are none of those either.
double lowestLargeSurface(const Scene& scene, const Bounds& bounds, bool eitherWay = false) {
  struct Piece {
    double height, area;
  };
  std::vector<Piece> pieces;
  double total = 0.0;
  for (const MeshObject& mesh : scene.objects) {
    for (const glm::u32vec3& t : mesh.triangles) {
      const glm::dvec3 a = mesh.worldPositions[t[0]], b = mesh.worldPositions[t[1]],
                       c = mesh.worldPositions[t[2]];
      const glm::dvec3 n = glm::cross(b - a, c - a);
      const double twiceArea = glm::length(n);
      if (!(twiceArea > 0.0) || !std::isfinite(twiceArea)) continue;
      if ((eitherWay ? std::abs(n.y) : n.y) < std::cos(glm::radians(30.0)) * twiceArea) continue;
      pieces.push_back({(a.y + b.y + c.y) / 3.0, twiceArea / 2.0});
      total += twiceArea / 2.0;
    }
  }
  if (pieces.empty() || !(total > 0.0)) {
    return eitherWay ? bounds.lo.y : lowestLargeSurface(scene, bounds, true);
  }
  std::sort(pieces.begin(), pieces.end(),
            [](const Piece& p, const Piece& q) { return p.height < q.height; });
  double below = 0.0;
  for (const Piece& piece : pieces) {
    below += piece.area;
    if (below >= 0.2 * total) return piece.height;
  }
  return pieces.back().height;
}

Camera perspective(const std::string& name, Viewport viewport, const glm::dvec3& eye,
                   const glm::dvec3& target, const glm::dvec3& up, double fovY, double near,
                   double far) {
  Camera camera;
  camera.name = name;
  camera.viewport = viewport;
  PerspectiveProjection projection;
  projection.fovYDegrees = fovY;
  projection.nearDistance = near;
  projection.farDistance = far;
  camera.projection = projection;
  camera.viewFromWorld = glm::lookAtRH(eye, target, up);
  return camera;
}

}  // namespace

std::vector<Camera> autoCameras(const Scene& scene, Viewport viewport) {
  const Bounds bounds = sceneBounds(scene);
  if (bounds.empty()) {
    throw InputError(scene.path +
                     ": no cameras, and no finite geometry to frame automatic cameras on");
  }
  const glm::dvec3 centre = 0.5 * (bounds.lo + bounds.hi);
  const glm::dvec3 halfExtent = 0.5 * (bounds.hi - bounds.lo);
  // The bounding sphere's radius; a single point (or a flat model's zero thickness) still gets a
  // view of a size relative to where it is.
  const double scale = std::max({glm::length(centre), 1e-30});
  const double radius = std::max(glm::length(halfExtent), 1e-6 * scale);
  const glm::dvec3 yUp(0.0, 1.0, 0.0);
  const double aspect = static_cast<double>(viewport.width) / viewport.height;
  // The distance at which a sphere of this radius fills a 45 deg (vertical) view, or the
  // narrower of the vertical and horizontal ones.
  const double halfFov = glm::radians(22.5);
  const double narrowest = std::min(halfFov, std::atan(std::tan(halfFov) * aspect));
  const double frameDistance = 1.05 * radius / std::sin(narrowest);

  std::vector<Camera> cameras;
  // Three-quarter: from above front-right.
  const glm::dvec3 threeQuarter = glm::normalize(glm::dvec3(1.0, 0.8, 1.4));
  cameras.push_back(perspective("auto_three_quarter", viewport,
                                centre + threeQuarter * frameDistance, centre, yUp, 45.0,
                                0.5 * (frameDistance - radius), frameDistance + 2.0 * radius));

  // Grazing: the eye 1% of the radius above the lowest large upward surface, at framing
  // distance, looking horizontally across it towards the centre.
  const double surface = lowestLargeSurface(scene, bounds);
  const glm::dvec3 across = glm::normalize(glm::dvec3(1.0, 0.0, 0.3));
  const glm::dvec3 grazingEye(centre.x + across.x * frameDistance, surface + 0.01 * radius,
                              centre.z + across.z * frameDistance);
  cameras.push_back(perspective("auto_grazing", viewport, grazingEye,
                                glm::dvec3(centre.x, surface + 0.01 * radius, centre.z), yUp, 45.0,
                                0.01 * radius, frameDistance + 2.0 * radius));

  // Orthographic along the thinnest axis, from its positive side.
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (halfExtent[k] < halfExtent[axis]) axis = k;
  }
  glm::dvec3 along(0.0);
  along[axis] = 1.0;
  // Up: world y, or -z when looking down y (x then points right).
  const glm::dvec3 orthoUp = axis == 1 ? glm::dvec3(0.0, 0.0, -1.0) : yUp;
  const glm::dvec3 right = glm::cross(-along, orthoUp);
  double halfWidth = 1.05 * std::abs(glm::dot(halfExtent, glm::abs(right)));
  double halfHeight = 1.05 * std::abs(glm::dot(halfExtent, glm::abs(orthoUp)));
  const double minimum = 1e-3 * radius;
  halfWidth = std::max(halfWidth, minimum);
  halfHeight = std::max(halfHeight, minimum);
  if (halfWidth / halfHeight < aspect) {
    halfWidth = halfHeight * aspect;
  } else {
    halfHeight = halfWidth / aspect;
  }
  Camera ortho;
  ortho.name = std::string("auto_orthographic_") + "xyz"[axis];
  ortho.viewport = viewport;
  OrthographicProjection box;
  box.left = -halfWidth;
  box.right = halfWidth;
  box.bottom = -halfHeight;
  box.top = halfHeight;
  // The eye 2 radii out along the axis: the model lies within [r, 3r] of it.
  box.nearDistance = 0.5 * radius;
  box.farDistance = 3.5 * radius;
  ortho.projection = box;
  ortho.viewFromWorld = glm::lookAtRH(centre + along * (2.0 * radius), centre, orthoUp);
  cameras.push_back(ortho);

  // Near cut: the near plane through the centre, the model clipped open.
  const double cutDistance = 1.5 * radius;
  cameras.push_back(perspective("auto_near_cut", viewport, centre + threeQuarter * cutDistance,
                                centre, yUp, 60.0, cutDistance, cutDistance + 2.0 * radius));
  return cameras;
}

}  // namespace clipray
