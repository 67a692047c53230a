#include "clipray/trace/CaptureGeometry.hpp"

#include <cmath>
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

ClipFit fitsClipPositions(const glm::dmat4& clipFromWorld, const std::vector<glm::dvec4>& clip) {
  // Rows of a column-major glm matrix: row r is (m[0][r], m[1][r], m[2][r], m[3][r]).
  const glm::dvec4 rowZ(clipFromWorld[0][2], clipFromWorld[1][2], clipFromWorld[2][2],
                        clipFromWorld[3][2]);
  const glm::dvec4 rowW(clipFromWorld[0][3], clipFromWorld[1][3], clipFromWorld[2][3],
                        clipFromWorld[3][3]);
  const glm::dvec3 zPart(rowZ), wPart(rowW);
  const double wLength2 = glm::dot(wPart, wPart);
  if (clip.empty() || !(wLength2 > 0.0)) return ClipFit::CannotTell;
  // The least-squares A of zPart = A wPart; the matrix has the structure where the rest is noise
  // (its float32 entries: a relative 1e-5 leaves room for their rounding through V M).
  const double a = glm::dot(zPart, wPart) / wLength2;
  if (glm::length(zPart - a * wPart) > 1e-5 * glm::length(zPart)) return ClipFit::CannotTell;
  const double b = rowZ.w - a * rowW.w;
  // Each position as the vertex shader wrote it (float32): z against A w + B, within a tolerance
  // of float rounding through a few operations on terms of those sizes.
  for (const glm::dvec4& p : clip) {
    const double scale = std::abs(p.z) + std::abs(a * p.w) + std::abs(b);
    if (std::abs(p.z - (a * p.w + b)) > 1e-4 * scale) return ClipFit::DoesNotFit;
  }
  return ClipFit::Fits;
}

}  // namespace clipray::trace
