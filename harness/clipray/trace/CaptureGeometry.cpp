#include "clipray/trace/CaptureGeometry.hpp"

#include <cstring>
#include <stdexcept>

#include "clipray/trace/ReplayDepth.hpp"

namespace clipray::trace {

CapturedDrawGeometry capturedDrawGeometry(const nlohmann::json& line) {
  if (!line.is_object() || line.value("kind", "") != "geometry" || !line.contains("event")) {
    throw std::invalid_argument("not a geometry line of the capture reader");
  }
  CapturedDrawGeometry draw;
  draw.event = line["event"].get<std::uint64_t>();
  if (line.contains("skipped")) {
    draw.skipped = line["skipped"].get<std::string>();
    return draw;
  }
  draw.depthTarget = line.value("depth_target", std::string());
  draw.instances = line.value("instances", std::uint64_t{1});
  const std::uint64_t triangles = line.value("triangles", std::uint64_t{0});
  const std::string bytes = decodeBase64(line.value("clip", std::string()));
  if (bytes.size() != triangles * 3 * 4 * sizeof(float)) {
    throw std::invalid_argument("event " + std::to_string(draw.event) + ": " +
                                std::to_string(bytes.size()) + " bytes of clip coordinates for " +
                                std::to_string(triangles) + " triangles (48 bytes each)");
  }
  std::vector<float> values(bytes.size() / sizeof(float));
  std::memcpy(values.data(), bytes.data(), bytes.size());  // little-endian, as the host's
  draw.clip.reserve(values.size() / 4);
  for (std::size_t k = 0; k + 3 < values.size(); k += 4) {
    draw.clip.emplace_back(values[k], values[k + 1], values[k + 2], values[k + 3]);
  }
  return draw;
}

namespace {

// Keeps the part of `polygon` where dot(plane, p) >= 0 (Sutherland-Hodgman), the new vertices
// where an edge crosses the plane interpolated at its signed distances' zero.
std::vector<glm::dvec4> clipToPlane(const std::vector<glm::dvec4>& polygon,
                                    const glm::dvec4& plane) {
  std::vector<glm::dvec4> kept;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const glm::dvec4& p = polygon[k];
    const glm::dvec4& q = polygon[(k + 1) % polygon.size()];
    const double dp = glm::dot(plane, p), dq = glm::dot(plane, q);
    if (dp >= 0.0) kept.push_back(p);
    if ((dp >= 0.0) != (dq >= 0.0)) kept.push_back(p + (dp / (dp - dq)) * (q - p));
  }
  return kept;
}

}  // namespace

std::vector<NdcTriangle> ndcTrianglesInDepth(const glm::dvec4& a, const glm::dvec4& b,
                                             const glm::dvec4& c, DepthConvention convention) {
  const double zn = convention == DepthConvention::ZeroToOne ? 0.0 : -1.0;
  std::vector<glm::dvec4> polygon = {a, b, c};
  // z - z_n w >= 0 (the near plane under a classic range, the far one under reversed-Z) and
  // w - z >= 0; together they give (1 - z_n) w >= 0, so what is kept has w >= 0.
  for (const glm::dvec4& plane :
       {glm::dvec4(0.0, 0.0, 1.0, -zn), glm::dvec4(0.0, 0.0, -1.0, 1.0)}) {
    polygon = clipToPlane(polygon, plane);
    if (polygon.size() < 3) return {};
  }
  std::vector<glm::dvec3> ndc;
  for (const glm::dvec4& p : polygon) {
    // Only a polygon through the eye point itself (z = w = 0) reaches w = 0: what GL makes of it
    // is the implementation's, and it is left out.
    if (!(p.w > 0.0)) return {};
    ndc.push_back(glm::dvec3(p) / p.w);
  }
  std::vector<NdcTriangle> fan;
  for (std::size_t k = 1; k + 1 < ndc.size(); ++k) fan.push_back({ndc[0], ndc[k], ndc[k + 1]});
  return fan;
}

}  // namespace clipray::trace
