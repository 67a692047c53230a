#include "clipray/compare/Frames.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>

#include "clipray/intersect/FrameBins.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/util/HugePages.hpp"

namespace clipray {

unsigned parallelWorkerCount(int rows, unsigned threadCount) {
  if (threadCount == 0) threadCount = std::max(1u, std::thread::hardware_concurrency());
  return std::min<unsigned>(threadCount, static_cast<unsigned>(std::max(rows, 1)));
}

void parallelForRowsByWorker(int rows, unsigned threadCount,
                             const std::function<void(unsigned, int, int)>& body) {
  threadCount = parallelWorkerCount(rows, threadCount);
  // Rows are handed out in small chunks so that uneven rows (sky vs. geometry) balance out.
  const int chunk = std::max(1, rows / static_cast<int>(threadCount * 8));
  std::atomic<int> next{0};
  auto worker = [&](unsigned index) {
    for (;;) {
      const int begin = next.fetch_add(chunk);
      if (begin >= rows) return;
      body(index, begin, std::min(rows, begin + chunk));
    }
  };
  std::vector<std::thread> threads;
  try {
    for (unsigned k = 1; k < threadCount; ++k) threads.emplace_back(worker, k);
  } catch (const std::system_error&) {
    // The system refused a thread (process limits): carry on with those that started.
  }
  worker(0);
  for (std::thread& t : threads) t.join();
}

void parallelForRows(int rows, unsigned threadCount, const std::function<void(int, int)>& body) {
  parallelForRowsByWorker(rows, threadCount,
                          [&](unsigned, int begin, int end) { body(begin, end); });
}

namespace {

// How many tiles ahead prefetchTileRays runs. Into L2, not L1: a tile's 64 lines asked into L1 at
// once wait behind each other. On the dev machine two tiles ahead was as good as four and better
// than one.
constexpr int kPrefetchTiles = 2;

// Starts loading the rays of the tile kPrefetchTiles to the right (its rows are kTile separate
// streams a frame row apart, which the hardware prefetchers follow too late): a tile's rays are
// read once, and waiting for them was a third of the binned pass on the 100k terrain.
void prefetchTileRays(const Ray* first, std::size_t rowStride, int columns, int rows) {
  for (int y = 0; y < rows; ++y) {
    const char* row =
        reinterpret_cast<const char*>(first + static_cast<std::size_t>(y) * rowStride);
    const std::size_t bytes = static_cast<std::size_t>(columns) * sizeof(Ray);
    for (std::size_t b = 0; b < bytes; b += 64) __builtin_prefetch(row + b, 0, 2);
    __builtin_prefetch(row + bytes - 1, 0, 2);
  }
}

}  // namespace

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
          slot = Ray{};  // resize left the slot unwritten
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
  // clipXYOfPixelCentre's x depends on the column only and y on the row only: computed once each
  // (the same arithmetic, so the same rays as generateForPixel), and generateRow hoists what the
  // generator computes per row.
  std::vector<double> clipXOfColumn(static_cast<std::size_t>(std::max(viewport.width, 0)));
  for (int x = 0; x < viewport.width; ++x) clipXOfColumn[x] = clipXYOfPixelCentre(x, 0, viewport).x;
  parallelForRows(viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
    for (int y = rowBegin; y < rowEnd; ++y) {
      Ray* row = frame.rays.data() + static_cast<std::size_t>(y) * viewport.width;
      generator.generateRow(clipXYOfPixelCentre(0, y, viewport).y, clipXOfColumn, row);
    }
  });
  return frame;
}

void intersectFrame(AnalyticFrame& frame, const SceneIntersector& intersector,
                    unsigned threadCount) {
  // Tiles of 8x8 neighbouring pixels: their rays are coherent, and closestHits traces each tile
  // as SIMD packets sharing one BVH walk (bit-identical to closestHit per ray). A pixel without
  // a ray (tMax < 0) gets the empty hit, as closestHit gives it.
  constexpr int kTile = 8;
  static_assert(kTile * kTile <= SceneIntersector::kMaxPacket);
  const Viewport viewport = frame.viewport;
  const int width = viewport.width;
  // Every tile writes every hit of its pixels: no need to initialize them first.
  frame.hits.resize(frame.rays.size());
  const int tileRows = (viewport.height + kTile - 1) / kTile;
  parallelForRows(tileRows, threadCount, [&](int tileRowBegin, int tileRowEnd) {
    for (int y0 = tileRowBegin * kTile; y0 < std::min(viewport.height, tileRowEnd * kTile);
         y0 += kTile) {
      const int rows = std::min(kTile, viewport.height - y0);
      for (int x0 = 0; x0 < width; x0 += kTile) {
        const std::size_t first = static_cast<std::size_t>(y0) * width + x0;
        intersector.closestHitsTile(frame.rays.data() + first, frame.hits.data() + first,
                                    static_cast<std::size_t>(width), std::min(kTile, width - x0),
                                    rows);
      }
    }
  });
}

std::size_t intersectFrame(AnalyticFrame& frame, const SceneIntersector& intersector,
                           const PickingCamera& camera, unsigned threadCount) {
  constexpr int kTile = FrameBins::kTile;
  const Viewport viewport = frame.viewport;
  if (intersector.primitiveIdCount() == 0 || !SceneIntersector::packetKernelsAvailable() ||
      viewport.width != camera.viewport.width || viewport.height != camera.viewport.height) {
    intersectFrame(frame, intersector, threadCount);
    return 0;
  }
  const FrameBins bins(intersector, camera.clipFromWorld, camera.mode, viewport, threadCount);
  const int width = viewport.width;
  frame.hits.resize(frame.rays.size());
  const int tileRows = (viewport.height + kTile - 1) / kTile;
  std::atomic<std::size_t> binnedTiles{0};
  parallelForRows(tileRows, threadCount, [&](int tileRowBegin, int tileRowEnd) {
    std::size_t binned = 0;
    for (int tileY = tileRowBegin; tileY < tileRowEnd; ++tileY) {
      const int y0 = tileY * kTile;
      const int rows = std::min(kTile, viewport.height - y0);
      for (int tileX = 0; tileX * kTile < width; ++tileX) {
        const int x0 = tileX * kTile;
        const std::size_t first = static_cast<std::size_t>(y0) * width + x0;
        if (x0 + kPrefetchTiles * kTile < width) {
          prefetchTileRays(frame.rays.data() + first + kPrefetchTiles * kTile,
                           static_cast<std::size_t>(width),
                           std::min(kTile, width - x0 - kPrefetchTiles * kTile), rows);
        }
        binned += intersector.closestHitsTileBinned(
                      bins, tileX, tileY, frame.rays.data() + first, frame.hits.data() + first,
                      static_cast<std::size_t>(width), std::min(kTile, width - x0), rows)
                      ? 1
                      : 0;
      }
    }
    binnedTiles += binned;
  });
  return binnedTiles.load();
}

}  // namespace clipray
