#include "clipray/intersect/FrameBins.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <thread>

#include "clipray/intersect/SceneIntersector.hpp"

namespace clipray {

namespace {

// A triangle's padded pixel bounds, inclusive; empty when x0 > x1.
struct PixelRect {
  int x0 = 1, x1 = 0, y0 = 1, y1 = 0;
  float nearestW = 0.0f;
};

struct ClipPoint {
  double x, y, w;
};

// Sums of the magnitudes of the terms of a corner's clip x, y and w (their rounding is below
// 2^-50 of these: four terms).
struct ClipMagnitude {
  double x, y, w;
};

// Pixel index whose centre is at NDC coordinate `ndc`: i = (ndc + 1) * size / 2 - 1/2.
double pixelCoordinate(double ndc, int size) {
  return (ndc + 1.0) * (0.5 * size) - 0.5;
}

// Inclusive pixel range [first, last] of the interval padded by `pad`, clamped to the viewport.
// NaN (a triangle whose projection overflowed) covers the whole range: conservative.
void pixelRange(double low, double high, double pad, int size, int& first, int& last) {
  if (std::isnan(low) || std::isnan(high) || std::isnan(pad)) {
    first = 0;
    last = size - 1;
    return;
  }
  low = std::clamp(low - pad, -1.0, double(size));
  high = std::clamp(high + pad, -1.0, double(size));
  first = std::max(0, static_cast<int>(std::ceil(low)));
  last = std::min(size - 1, static_cast<int>(std::floor(high)));
}

// The part of the triangle with w >= wClip (one plane clips a triangle into at most a quad),
// projected; its padded pixel bounds.
PixelRect triangleRect(const glm::dmat4& m, const detail::BvhTriangle& tri, double wClip,
                       Viewport viewport) {
  std::array<ClipPoint, 3> corner;
  std::array<ClipMagnitude, 3> magnitude;
  const glm::dvec3* vertices[3] = {&tri.a, &tri.b, &tri.c};
  int inside = 0;
  double wError = 0.0;  // bound on the rounding of the corners' w
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3& v = *vertices[k];
    // Rows 0, 1 and 3 of the column-major matrix: clip x, y and w.
    corner[k] = {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z + m[3][0],
                 m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z + m[3][1],
                 m[0][3] * v.x + m[1][3] * v.y + m[2][3] * v.z + m[3][3]};
    magnitude[k] = {std::abs(m[0][0] * v.x) + std::abs(m[1][0] * v.y) + std::abs(m[2][0] * v.z) +
                        std::abs(m[3][0]),
                    std::abs(m[0][1] * v.x) + std::abs(m[1][1] * v.y) + std::abs(m[2][1] * v.z) +
                        std::abs(m[3][1]),
                    std::abs(m[0][3] * v.x) + std::abs(m[1][3] * v.y) + std::abs(m[2][3] * v.z) +
                        std::abs(m[3][3])};
    wError = std::max(wError, magnitude[k].w);
    inside += corner[k].w >= wClip ? 1 : 0;
  }
  wError *= 0x1p-48;  // 4 roundings of at most 2^-53 each, with a wide margin
  PixelRect rect;
  if (inside == 0) return rect;  // wholly where no binned ray goes
  std::array<ClipPoint, 4> polygon;
  int count = 0;
  for (int k = 0; k < 3; ++k) {
    const ClipPoint& p = corner[k];
    const ClipPoint& q = corner[(k + 1) % 3];
    const bool pIn = p.w >= wClip, qIn = q.w >= wClip;
    if (pIn) polygon[count++] = p;
    if (pIn != qIn) {
      const double s = (p.w - wClip) / (p.w - q.w);
      polygon[count++] = {p.x + s * (q.x - p.x), p.y + s * (q.y - p.y), wClip};
    }
  }
  double xMin = std::numeric_limits<double>::infinity(), xMax = -xMin;
  double yMin = xMin, yMax = -xMin;
  double wMin = std::numeric_limits<double>::infinity();
  bool nan = false;
  for (int k = 0; k < count; ++k) {
    wMin = std::min(wMin, polygon[k].w);
    // w >= wClip > 0 here, except the clipped points whose w is wClip up to rounding.
    const double inverseW = 1.0 / std::max(polygon[k].w, wClip);
    const double x = polygon[k].x * inverseW, y = polygon[k].y * inverseW;
    nan = nan || std::isnan(x) || std::isnan(y);
    xMin = std::min(xMin, x);
    xMax = std::max(xMax, x);
    yMin = std::min(yMin, y);
    yMax = std::max(yMax, y);
  }
  if (nan) xMin = xMax = yMin = yMax = std::numeric_limits<double>::quiet_NaN();
  // Lowered by the corners' rounding and by 2^-22 of itself before the conversion to float rounds
  // it by at most 2^-24 of itself: a lower bound (wMin >= wClip > 0). NaN (never for finite
  // vertices) would disable the depth test.
  wMin = wMin - wError - wMin * 0x1p-22;
  rect.nearestW = std::isnan(wMin) ? -std::numeric_limits<float>::infinity()
                                   : static_cast<float>(std::max(wMin, 0.0));
  // The padding: kRayTolerancePx + kMarginPx plus a bound on the rounding of the projected
  // corners in pixels when the triangle is whole (inside == 3: its projection is the triangle of
  // the projected corners), kClippedPaddingPx when w = wClip cut it. A corner's clip x is off by
  // at most 2^-50 magnitude.x (likewise w), so x / w by (2^-50 (magnitude.x + |x / w|
  // magnitude.w) / w + u |x / w|), and the pixel coordinate by size / 2 times that plus a few
  // roundings of (|x / w| + 1) size / 2: 2^-48 covers them all with room.
  double padX = FrameBins::kClippedPaddingPx, padY = FrameBins::kClippedPaddingPx;
  if (inside == 3) {
    double errorX = 0.0, errorY = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double inverseW = 1.0 / corner[k].w;
      const double ndcX = std::abs(corner[k].x * inverseW), ndcY = std::abs(corner[k].y * inverseW);
      errorX = std::max(errorX, (magnitude[k].x + ndcX * magnitude[k].w) * inverseW + ndcX + 1.0);
      errorY = std::max(errorY, (magnitude[k].y + ndcY * magnitude[k].w) * inverseW + ndcY + 1.0);
    }
    const double base = FrameBins::kRayTolerancePx + FrameBins::kMarginPx;
    padX = base + 0x1p-48 * (0.5 * viewport.width) * errorX;
    padY = base + 0x1p-48 * (0.5 * viewport.height) * errorY;
  }
  pixelRange(pixelCoordinate(xMin, viewport.width), pixelCoordinate(xMax, viewport.width), padX,
             viewport.width, rect.x0, rect.x1);
  pixelRange(pixelCoordinate(yMin, viewport.height), pixelCoordinate(yMax, viewport.height), padY,
             viewport.height, rect.y0, rect.y1);
  return rect;
}

// The half rows of tile (tileX, tileY) that the rect touches, as FrameBins's group bits.
std::uint16_t groupMask(const PixelRect& r, int tileX, int tileY) {
  constexpr int kTile = FrameBins::kTile;
  const int x0 = std::max(r.x0 - tileX * kTile, 0), x1 = std::min(r.x1 - tileX * kTile, kTile - 1);
  const int y0 = std::max(r.y0 - tileY * kTile, 0), y1 = std::min(r.y1 - tileY * kTile, kTile - 1);
  std::uint32_t halves = 0;
  if (x0 <= 3) halves |= 1u;
  if (x1 >= 4) halves |= 2u;
  std::uint32_t mask = 0;
  for (int y = y0; y <= y1; ++y) mask |= halves << (2 * y);
  return static_cast<std::uint16_t>(mask);
}

}  // namespace

FrameBins::FrameBins(const SceneIntersector& scene, const glm::dmat4& clipFromWorld, DepthMode mode,
                     Viewport viewport, unsigned threadCount)
    : viewport_(viewport) {
  if (viewport.width <= 0 || viewport.height <= 0) return;
  tilesAcross_ = (viewport.width + kTile - 1) / kTile;
  tilesUp_ = (viewport.height + kTile - 1) / kTile;
  // Triangles are stored relative to the reference point: fold it into the translation column.
  clipFromRelative_ = clipFromWorld;
  clipFromRelative_[3] = clipFromWorld * glm::dvec4(scene.reference(), 1.0);

  // The near plane's clip w: the world point unprojected from (x, y, z_near) has homogeneous
  // weight Pw = row 3 of worldFromClip . (x, y, z_near, 1), and clip w = 1 / Pw. Pw is affine in
  // (x, y), so across the viewport its extremes are at the corners. Rays that start on the near
  // plane have w >= wNear there; bins clip triangles at half of it (a factor 2 of margin).
  const glm::dmat4 worldFromClip = glm::inverse(clipFromWorld);
  const double zNear = mode.nearNdcZ();
  double wNear = std::numeric_limits<double>::infinity();
  for (const double x : {-1.0, 1.0}) {
    for (const double y : {-1.0, 1.0}) {
      const double pw = worldFromClip[0][3] * x + worldFromClip[1][3] * y +
                        worldFromClip[2][3] * zNear + worldFromClip[3][3];
      if (!(pw > 0.0) || !std::isfinite(pw)) return;  // no near plane in front: no bins
      wNear = std::min(wNear, 1.0 / pw);
    }
  }
  if (!(wNear > 0.0) || !std::isfinite(wNear)) return;
  wClip_ = 0.5 * wNear;

  const auto& triangles = scene.triangles_;
  const std::size_t triangleCount = triangles.size();
  const std::size_t tileCount = static_cast<std::size_t>(tilesAcross_) * tilesUp_;
  unsigned chunkCount = threadCount == 0 ? std::thread::hardware_concurrency() : threadCount;
  chunkCount = std::clamp<unsigned>(chunkCount, 1u, 64u);
  if (triangleCount < 4096) chunkCount = 1;
  chunks_.resize(chunkCount);
  // Triangles that cover many tiles each (big, overlapping, or seen from up close) can ask for
  // more entries than the bins pay for: past this many per chunk the frame walks the BVH instead.
  const std::uint64_t entryBudget = std::min<std::uint64_t>(
      std::uint64_t{1} << 27, 16 * (std::uint64_t{triangleCount} / chunkCount + tileCount));
  std::vector<char> overBudget(chunkCount, 0);
  auto binChunk = [&](unsigned c) {
    Chunk& chunk = chunks_[c];
    const std::size_t begin = triangleCount * c / chunkCount;
    const std::size_t end = triangleCount * (c + 1) / chunkCount;
    FrameVector<PixelRect> rects;
    rects.resize(end - begin);  // every element is written below
    chunk.offsets.assign(tileCount + 1, 0);
    std::uint64_t total = 0;
    for (std::size_t s = begin; s < end; ++s) {
      const PixelRect r = triangleRect(clipFromRelative_, triangles[s], wClip_, viewport_);
      rects[s - begin] = r;
      if (r.x0 > r.x1 || r.y0 > r.y1) continue;
      total += std::uint64_t(r.x1 / kTile - r.x0 / kTile + 1) * (r.y1 / kTile - r.y0 / kTile + 1);
      if (total > entryBudget) {
        overBudget[c] = 1;
        chunk = Chunk{};
        return;
      }
      for (int ty = r.y0 / kTile; ty <= r.y1 / kTile; ++ty) {
        for (int tx = r.x0 / kTile; tx <= r.x1 / kTile; ++tx) {
          ++chunk.offsets[static_cast<std::size_t>(ty) * tilesAcross_ + tx + 1];
        }
      }
    }
    for (std::size_t t = 0; t < tileCount; ++t) chunk.offsets[t + 1] += chunk.offsets[t];
    chunk.entries.resize(chunk.offsets[tileCount]);
    FrameVector<std::uint32_t> fill(chunk.offsets.begin(), chunk.offsets.end() - 1);
    for (std::size_t s = begin; s < end; ++s) {
      const PixelRect& r = rects[s - begin];
      if (r.x0 > r.x1 || r.y0 > r.y1) continue;
      for (int ty = r.y0 / kTile; ty <= r.y1 / kTile; ++ty) {
        for (int tx = r.x0 / kTile; tx <= r.x1 / kTile; ++tx) {
          const std::size_t tile = static_cast<std::size_t>(ty) * tilesAcross_ + tx;
          chunk.entries[fill[tile]++] = {static_cast<std::uint32_t>(s), groupMask(r, tx, ty),
                                         r.nearestW};
        }
      }
    }
  };
  std::vector<std::thread> workers;
  try {
    for (unsigned c = 1; c < chunkCount; ++c) workers.emplace_back(binChunk, c);
  } catch (const std::system_error&) {
    // No more threads: the remaining chunks are binned here.
    for (unsigned c = static_cast<unsigned>(workers.size()) + 1; c < chunkCount; ++c) binChunk(c);
  }
  binChunk(0);
  for (std::thread& worker : workers) worker.join();
  if (std::find(overBudget.begin(), overBudget.end(), 1) != overBudget.end()) {
    chunks_.clear();
    return;
  }
  usable_ = true;
}

std::size_t FrameBins::entryCount() const {
  std::size_t count = 0;
  for (const Chunk& chunk : chunks_) count += chunk.entries.size();
  return count;
}

}  // namespace clipray
