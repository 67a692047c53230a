#include "clipray/compare/Frames.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>

#include "clipray/intersect/FrameBins.hpp"
#include "clipray/rays/RobustRays.hpp"
#include "clipray/util/Check.hpp"
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
    PickingCamera camera;  // as drawn: the generator keeps it as a lower-left origin sees it
  };
  auto cache = std::make_shared<Cache>();
  return [cache](int x, int y, const PickingCamera& camera) -> std::optional<Ray> {
    if (!cache->generator || cache->camera.clipFromWorld != camera.clipFromWorld ||
        cache->camera.mode != camera.mode || cache->camera.clipPlanes != camera.clipPlanes ||
        cache->camera.depthClamp != camera.depthClamp ||
        cache->camera.depthClampReach != camera.depthClampReach ||
        cache->camera.depthClampBeyondFar != camera.depthClampBeyondFar) {
      cache->generator.emplace(camera.clipFromWorld, camera.mode, camera.clipPlanes,
                               depthClampRays(camera));
      cache->camera = camera;
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
  // It is the caller's code and may throw on any pixel: the first exception stops the workers and
  // is rethrown here, on the caller's thread (an exception leaving a worker would terminate).
  std::exception_ptr firstError;
  std::mutex errorMutex;
  std::atomic<bool> failed = false;
  parallelForRows(viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
    try {
      for (int y = rowBegin; y < rowEnd && !failed.load(std::memory_order_relaxed); ++y) {
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
    } catch (...) {
      const std::lock_guard<std::mutex> lock(errorMutex);
      if (!firstError) firstError = std::current_exception();
      failed = true;
    }
  });
  if (firstError) std::rethrow_exception(firstError);
  return frame;
}

AnalyticFrame generateRobustRays(const PickingCamera& camera, unsigned threadCount) {
  const Viewport viewport = camera.viewport;
  const PixelCentreRays pixelCentreRays(camera.clipFromWorld, camera.mode, viewport,
                                        camera.clipPlanes, depthClampRays(camera));
  AnalyticFrame frame;
  frame.viewport = viewport;
  frame.rays.resize(frame.pixelCount());
  parallelForRows(viewport.height, threadCount, [&](int rowBegin, int rowEnd) {
    for (int y = rowBegin; y < rowEnd; ++y) {
      pixelCentreRays.row(y, 0, viewport.width,
                          frame.rays.data() + static_cast<std::size_t>(y) * viewport.width);
    }
  });
  return frame;
}

AnalyticFrame robustRayFrame(const PickingCamera& camera) {
  AnalyticFrame frame;
  frame.viewport = camera.viewport;
  frame.pixelCentreRays =
      std::make_shared<const PixelCentreRays>(camera.clipFromWorld, camera.mode, camera.viewport,
                                              camera.clipPlanes, depthClampRays(camera));
  return frame;
}

namespace {

// How many tiles' rays a worker computes at once when the frame computes them: eight rows of
// 64 pixels (28 KB of rays), so that each row piece pays the generator's per-call work once for
// eight tiles.
constexpr int kTilesPerGroup = 8;

// Runs trace(tileX, tileY, rays, hits, rowStride, columns, rows) on each kTile x kTile tile of the
// frame, tile rows split across the threads, and sums what it returns. Stored rays are traced
// where they lie (prefetched a few tiles ahead); computed rays are computed kTilesPerGroup tiles
// at a time into the worker's buffers, and their hits copied out.
template <typename TraceTile>
std::size_t forEachTile(AnalyticFrame& frame, int kTile, unsigned threadCount,
                        const TraceTile& trace) {
  const Viewport viewport = frame.viewport;
  const int width = viewport.width;
  // Every tile writes every hit of its pixels: no need to initialize them first.
  frame.hits.resize(frame.pixelCount());
  const int tileRows = (viewport.height + kTile - 1) / kTile;
  const int groupWidth = kTilesPerGroup * kTile;
  std::atomic<std::size_t> total{0};
  parallelForRows(tileRows, threadCount, [&](int tileRowBegin, int tileRowEnd) {
    std::size_t sum = 0;
    std::vector<Ray> groupRays;
    std::vector<Hit> groupHits;
    if (frame.pixelCentreRays) {
      groupRays.resize(static_cast<std::size_t>(kTile) * groupWidth);
      groupHits.resize(static_cast<std::size_t>(kTile) * groupWidth);
    }
    for (int tileY = tileRowBegin; tileY < tileRowEnd; ++tileY) {
      const int y0 = tileY * kTile;
      const int rows = std::min(kTile, viewport.height - y0);
      if (!frame.pixelCentreRays) {
        for (int tileX = 0; tileX * kTile < width; ++tileX) {
          const int x0 = tileX * kTile;
          const std::size_t first = static_cast<std::size_t>(y0) * width + x0;
          if (x0 + kPrefetchTiles * kTile < width) {
            prefetchTileRays(frame.rays.data() + first + kPrefetchTiles * kTile,
                             static_cast<std::size_t>(width),
                             std::min(kTile, width - x0 - kPrefetchTiles * kTile), rows);
          }
          sum += trace(tileX, tileY, frame.rays.data() + first, frame.hits.data() + first,
                       static_cast<std::size_t>(width), std::min(kTile, width - x0), rows);
        }
        continue;
      }
      for (int groupX = 0; groupX < width; groupX += groupWidth) {
        const int groupColumns = std::min(groupWidth, width - groupX);
        for (int y = 0; y < rows; ++y) {
          frame.pixelCentreRays->row(y0 + y, groupX, groupColumns,
                                     groupRays.data() + static_cast<std::size_t>(y) * groupWidth);
        }
        for (int x0 = 0; x0 < groupColumns; x0 += kTile) {
          sum +=
              trace((groupX + x0) / kTile, tileY, groupRays.data() + x0, groupHits.data() + x0,
                    static_cast<std::size_t>(groupWidth), std::min(kTile, groupColumns - x0), rows);
        }
        for (int y = 0; y < rows; ++y) {
          std::memcpy(frame.hits.data() + static_cast<std::size_t>(y0 + y) * width + groupX,
                      groupHits.data() + static_cast<std::size_t>(y) * groupWidth,
                      static_cast<std::size_t>(groupColumns) * sizeof(Hit));
        }
      }
    }
    total += sum;
  });
  return total.load();
}

void requireRays(const AnalyticFrame& frame) {
  CLIPRAY_CHECK(frame.hasRays(),
                "intersectFrame: the frame needs one ray per pixel, stored or computed (not both)");
}

}  // namespace

void intersectFrame(AnalyticFrame& frame, const SceneIntersector& intersector,
                    unsigned threadCount) {
  requireRays(frame);
  // Tiles of 8x8 neighbouring pixels: their rays are coherent, and closestHits traces each tile
  // as SIMD packets sharing one BVH walk (bit-identical to closestHit per ray). A pixel without
  // a ray (tMax < 0) gets the empty hit, as closestHit gives it.
  constexpr int kTile = 8;
  static_assert(kTile * kTile <= SceneIntersector::kMaxPacket);
  forEachTile(
      frame, kTile, threadCount,
      [&](int, int, const Ray* rays, Hit* hits, std::size_t rowStride, int columns, int rows) {
        intersector.closestHitsTile(rays, hits, rowStride, columns, rows);
        return std::size_t{0};
      });
}

std::size_t intersectFrame(AnalyticFrame& frame, const SceneIntersector& intersector,
                           const PickingCamera& camera, unsigned threadCount) {
  const Viewport viewport = frame.viewport;
  if (intersector.primitiveIdCount() == 0 || !SceneIntersector::packetKernelsAvailable() ||
      viewport.width != camera.viewport.width || viewport.height != camera.viewport.height) {
    intersectFrame(frame, intersector, threadCount);
    return 0;
  }
  requireRays(frame);
  const FrameBins bins(intersector, camera.clipFromWorld, camera.mode, viewport, threadCount);
  return forEachTile(frame, FrameBins::kTile, threadCount,
                     [&](int tileX, int tileY, const Ray* rays, Hit* hits, std::size_t rowStride,
                         int columns, int rows) {
                       return intersector.closestHitsTileBinned(bins, tileX, tileY, rays, hits,
                                                                rowStride, columns, rows)
                                  ? std::size_t{1}
                                  : std::size_t{0};
                     });
}

}  // namespace clipray
