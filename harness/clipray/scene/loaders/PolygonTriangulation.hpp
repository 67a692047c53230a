#pragma once
// Triangles for an OBJ face of more than three corners: ear clipping in the polygon's own plane,
// so that a concave polygon covers what it covers (a fan from its first corner covers the
// outside of every reflex corner too). Written here because tinyobjloader's ear clipping needs
// mapbox/earcut.hpp, which Debian 12 does not package, and its triangulation reads vertices
// before their indices are checked (ObjReader.cpp checks them first).

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace clipray::meshfiles {

struct PolygonTriangles {
  // Indices into the corners, in the polygon's winding.
  std::vector<std::array<std::size_t, 3>> triangles;
  // The largest distance of a corner from the polygon's mean plane (Newell's normal through the
  // centroid), relative to the polygon's diameter: 0 for a planar polygon.
  double nonPlanarity = 0.0;
  // Ear clipping found no ear before the end (a self-intersecting polygon): the rest is a fan.
  bool fanFallback = false;
};

// corners: a polygon of at least 3 corners, in order. Triangles: corners.size() - 2 of them.
PolygonTriangles triangulatePolygon(std::span<const glm::dvec3> corners);

}  // namespace clipray::meshfiles
