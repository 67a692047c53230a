#pragma once
// Random scenes in front of a camera (the hard-case cameras, HardCases.hpp): icospheres,
// heightfield patches, coplanar twin quads, and analytic primitives, placed where the camera sees
// them at a size that covers part of its screen. meshesOnly leaves the primitives out.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <variant>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/rays/HardCases.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/scene/Scene.hpp"
#include "support/TestScenes.hpp"

namespace clipray::testing {

// A point the camera sees and a size that covers part of the screen there: along the ray of a
// random pixel, at a random fraction of the way to the far plane (log-uniform, so near, middle
// and far all come up), or a random multiple of the near distance when the far plane is at
// infinity; a sixth of them on the near plane itself. The size is the distance to the ray of a
// pixel a tenth of the screen away, at the same ray parameter: right for telephoto, orthographic
// and far-from-origin cameras alike.
struct Placement {
  glm::dvec3 centre;
  double size = 0.0;
};

inline std::optional<Placement> randomPlacement(const glm::dmat4& clipFromWorld,
                                                const RobustRayGenerator& generator,
                                                Viewport viewport, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> column(0, viewport.width - 1), row(0, viewport.height - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int x = column(rng), y = row(rng);
  const int step = std::max(1, viewport.width / 10);
  const Ray ray = generator.generateForPixel(x, y, viewport);
  const Ray aside =
      generator.generateForPixel(x + step < viewport.width ? x + step : x - step, y, viewport);
  if (!(ray.tMax > 0.0) || !(aside.tMax > 0.0)) return std::nullopt;  // no ray at this pixel
  double t = 0.0;
  if (unit(rng) < 1.0 / 6.0) {
    // On the near plane, cut by it: rays that start inside a shape or on its surface.
  } else if (std::isfinite(ray.tMax)) {
    t = ray.tMax * std::pow(10.0, -2.5 * unit(rng));
  } else {
    // An infinite far plane (a perspective camera): 2 to 300 times the distance from the eye,
    // clip (0, 0, 1, 0) mapped back to the world, to the near plane.
    const glm::dvec4 eye = glm::inverse(clipFromWorld) * glm::dvec4(0.0, 0.0, 1.0, 0.0);
    const double nearDistance = glm::length(ray.origin - glm::dvec3(eye) / eye.w);
    t = std::pow(10.0, 0.3 + 2.2 * unit(rng)) * nearDistance / glm::length(ray.direction);
  }
  const glm::dvec3 centre = ray.origin + t * ray.direction;
  const glm::dvec3 besides = aside.origin + t * aside.direction;
  const double size = glm::length(besides - centre) * (0.3 + 1.2 * unit(rng));
  if (!std::isfinite(centre.x + centre.y + centre.z) || !(size > 0.0) || !std::isfinite(size)) {
    return std::nullopt;
  }
  return Placement{centre, size};
}

inline glm::dmat4 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
  glm::dvec3 axis(normal(rng), normal(rng), normal(rng));
  if (glm::length(axis) < 1e-6) axis = {0.0, 1.0, 0.0};
  return glm::rotate(glm::dmat4(1.0), angle(rng), glm::normalize(axis));
}

inline AnalyticPrimitive primitive(std::string name, PrimitiveKind kind,
                                   const glm::dmat4& worldFromLocal) {
  AnalyticPrimitive p;
  p.name = std::move(name);
  p.kind = kind;
  p.worldFromLocal = worldFromLocal;
  p.localFromWorld = glm::inverse(worldFromLocal);
  return p;
}

// A heightfield patch of cells x cells quads with shared vertices, tilted at random.
inline MeshObject patch(const std::string& name, const Placement& at, int cells,
                        std::mt19937_64& rng) {
  std::uniform_real_distribution<double> height(-0.15, 0.15);
  const glm::dmat4 rotation = randomRotation(rng);
  MeshObject mesh;
  mesh.name = name;
  const int n = cells + 1;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const glm::dvec3 local(-1.0 + 2.0 * i / cells, height(rng), -1.0 + 2.0 * j / cells);
      mesh.worldPositions.push_back(at.centre +
                                    at.size * glm::dvec3(rotation * glm::dvec4(local, 0.0)));
    }
  }
  mesh.triangles = gridTriangles(cells);
  return mesh;
}

// Six to twelve objects in front of the camera: icospheres, heightfield patches, a coplanar pair
// of quads (ties), spheres stretched into ellipsoids, disks, quads, oriented boxes, and now and
// then an unbounded plane.
inline Scene randomScene(const HardCase& hardCase, Viewport viewport, std::uint64_t seed,
                         bool meshesOnly = false) {
  std::mt19937_64 rng(seed);
  const RobustRayGenerator generator(hardCase.inputs.clipFromWorld, hardCase.inputs.mode);
  Scene scene;
  scene.name = hardCase.name + "_" + std::to_string(seed);
  std::uniform_int_distribution<int> kindOf(0, 7), count(6, 12);
  std::uniform_real_distribution<double> stretch(0.3, 1.5);
  const int objects = count(rng);
  for (int k = 0; k < objects; ++k) {
    const std::optional<Placement> at =
        randomPlacement(hardCase.inputs.clipFromWorld, generator, viewport, rng);
    if (!at) continue;
    const std::string name = "object" + std::to_string(k);
    const glm::dmat4 place = glm::translate(glm::dmat4(1.0), at->centre) * randomRotation(rng);
    const auto scaled = [&](glm::dvec3 scale) { return glm::scale(place, at->size * scale); };
    switch (kindOf(rng)) {
      case 0:
        scene.objects.push_back(icosphere(name, at->centre, at->size, 2));
        break;
      case 1:
        scene.objects.push_back(patch(name, *at, 6, rng));
        break;
      case 2: {  // two copies of one quad: the same depth at every pixel, the smaller id wins
        const glm::dvec3 a(place * glm::dvec4(-at->size, -at->size, 0.0, 1.0)),
            b(place * glm::dvec4(at->size, -at->size, 0.0, 1.0)),
            c(place * glm::dvec4(at->size, at->size, 0.0, 1.0)),
            d(place * glm::dvec4(-at->size, at->size, 0.0, 1.0));
        scene.objects.push_back(quad(name, a, b, c, d));
        scene.objects.push_back(quad(name + "_twin", a, b, c, d));
        break;
      }
      case 3:
        scene.primitives.push_back(primitive(name, PrimitiveKind::Sphere,
                                             scaled({stretch(rng), stretch(rng), stretch(rng)})));
        break;
      case 4:
        scene.primitives.push_back(primitive(name, PrimitiveKind::Disk, scaled({1.0, 1.0, 1.0})));
        break;
      case 5:
        scene.primitives.push_back(
            primitive(name, PrimitiveKind::Quad, scaled({stretch(rng), stretch(rng), 1.0})));
        break;
      case 6:
        scene.primitives.push_back(primitive(name, PrimitiveKind::Box,
                                             scaled({stretch(rng), stretch(rng), stretch(rng)})));
        break;
      default:
        if (rng() % 3 == 0) {
          scene.primitives.push_back(primitive(name, PrimitiveKind::Plane, place));
        } else {
          scene.primitives.push_back(primitive(name, PrimitiveKind::Sphere,
                                               scaled({stretch(rng), stretch(rng), stretch(rng)})));
        }
        break;
    }
  }
  if (meshesOnly) scene.primitives.clear();
  return scene;
}

// The scene camera of a hard case: its matrix as given (no projection to build), its viewport.
inline Camera hardCaseCamera(const HardCase& hardCase) {
  Camera camera;
  camera.name = hardCase.name;
  camera.viewport = hardCase.viewport;
  camera.projection = std::monostate{};
  camera.rawClipFromWorld = hardCase.inputs.clipFromWorld;
  return camera;
}

}  // namespace clipray::testing
