#include "clipray/compare/Frames.hpp"

#include <algorithm>
#include <atomic>
#include <memory>
#include <thread>

#include "clipray/rays/RobustRays.hpp"

namespace clipray {

void parallelForRows(int rows, unsigned threadCount, const std::function<void(int, int)>& body) {
  if (threadCount == 0) threadCount = std::max(1u, std::thread::hardware_concurrency());
  threadCount = std::min<unsigned>(threadCount, static_cast<unsigned>(std::max(rows, 1)));
  // Rows are handed out in small chunks so that uneven rows (sky vs. geometry) balance out.
  const int chunk = std::max(1, rows / static_cast<int>(threadCount * 8));
  std::atomic<int> next{0};
  auto worker = [&] {
    for (;;) {
      const int begin = next.fetch_add(chunk);
      if (begin >= rows) return;
      body(begin, std::min(rows, begin + chunk));
    }
  };
  std::vector<std::thread> threads;
  for (unsigned k = 1; k < threadCount; ++k) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
}

PickRayFunction robustPickRays() {
  // One generator per camera: precompute once, reuse for every pixel of that camera.
  struct Cache {
    std::optional<RobustRayGenerator> generator;
  };
  auto cache = std::make_shared<Cache>();
  return [cache](int x, int y, const PickingCamera& camera) -> std::optional<Ray> {
    if (!cache->generator || cache->generator->clipFromWorld() != camera.clipFromWorld ||
        cache->generator->mode() != camera.mode) {
      cache->generator.emplace(camera.clipFromWorld, camera.mode);
    }
    return cache->generator->generateForPixel(x, y, camera.viewport);
  };
}

AnalyticFrame generateRays(const PickingCamera& camera, const PickRayFunction& rayFunction,
                           unsigned threadCount) {
  const Viewport viewport = camera.viewport;
  AnalyticFrame frame;
  frame.viewport = viewport;
  frame.rays.resize(static_cast<std::size_t>(viewport.width) * viewport.height);
  // The ray function may keep per-camera state; warm it once before threads share it.
  (void)rayFunction(0, 0, camera);
  parallelForRows(viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
    for (int y = rowBegin; y < rowEnd; ++y) {
      for (int x = 0; x < viewport.width; ++x) {
        const std::optional<Ray> ray = rayFunction(x, y, camera);
        Ray& slot = frame.rays[static_cast<std::size_t>(y) * viewport.width + x];
        if (ray) {
          slot = *ray;
        } else {
          slot.tMax = kNoRayTMax;
        }
      }
    }
  });
  return frame;
}

AnalyticFrame generateRobustRays(const PickingCamera& camera, unsigned threadCount) {
  const Viewport viewport = camera.viewport;
  const RobustRayGenerator generator(camera.clipFromWorld, camera.mode);
  AnalyticFrame frame;
  frame.viewport = viewport;
  frame.rays.resize(static_cast<std::size_t>(viewport.width) * viewport.height);
  parallelForRows(viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
    for (int y = rowBegin; y < rowEnd; ++y) {
      Ray* row = frame.rays.data() + static_cast<std::size_t>(y) * viewport.width;
      for (int x = 0; x < viewport.width; ++x) row[x] = generator.generateForPixel(x, y, viewport);
    }
  });
  return frame;
}

void intersectFrame(AnalyticFrame& frame, const SceneIntersector& intersector,
                    unsigned threadCount) {
  const Viewport viewport = frame.viewport;
  frame.hits.assign(frame.rays.size(), Hit{});
  parallelForRows(viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
    const std::size_t begin = static_cast<std::size_t>(rowBegin) * viewport.width;
    const std::size_t end = static_cast<std::size_t>(rowEnd) * viewport.width;
    for (std::size_t i = begin; i < end; ++i) {
      if (frame.rays[i].tMax >= 0.0) frame.hits[i] = intersector.closestHit(frame.rays[i]);
    }
  });
}

}  // namespace clipray
