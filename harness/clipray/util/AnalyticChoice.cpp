#include "clipray/util/AnalyticChoice.hpp"

#include <atomic>

namespace clipray {

namespace {

std::atomic<AnalyticPath> chosen{AnalyticPath::Auto};

}  // namespace

void chooseAnalyticPath(AnalyticPath path) {
  chosen.store(path, std::memory_order_relaxed);
}

AnalyticPath chosenAnalyticPath() {
  return chosen.load(std::memory_order_relaxed);
}

std::string_view analyticPathName(AnalyticPath path) {
  return path == AnalyticPath::Auto ? "auto" : path == AnalyticPath::Rays ? "rays" : "screen";
}

std::optional<AnalyticPath> analyticPathNamed(std::string_view name) {
  if (name == "auto") return AnalyticPath::Auto;
  if (name == "rays") return AnalyticPath::Rays;
  if (name == "screen") return AnalyticPath::Screen;
  return std::nullopt;
}

}  // namespace clipray
