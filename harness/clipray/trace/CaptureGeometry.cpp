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

}  // namespace clipray::trace
