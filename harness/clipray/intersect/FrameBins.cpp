#include "clipray/intersect/FrameBins.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <thread>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "clipray/intersect/SceneIntersector.hpp"

namespace clipray {

namespace {

// A triangle's padded pixel bounds, inclusive; empty when x0 > x1. A whole triangle (no clipping)
// whose projection has a certain orientation also keeps its projected corners in pixel
// coordinates, counter-clockwise, and its padding (forEachTile's edge tests).
struct PixelRect {
  int x0 = 1, x1 = 0, y0 = 1, y1 = 0;
  float nearestW = 0.0f;
  bool hasCorners = false;
  double padX = 0.0, padY = 0.0;
  glm::dvec2 corner[3];
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
  // ceil and floor of values in [-1, size] by truncation (no library call per triangle).
  const int lowInt = static_cast<int>(low), highInt = static_cast<int>(high);
  first = std::max(0, lowInt + (low > lowInt ? 1 : 0));
  last = std::min(size - 1, highInt - (high < highInt ? 1 : 0));
}

// The part of the triangle with w >= wClip (one plane clips a triangle into at most a quad),
// projected; its padded pixel bounds.
void triangleRect(const glm::dmat4& m, const detail::BvhTriangle& tri, double wClip,
                  Viewport viewport, PixelRect& rect) {
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
  rect.x0 = rect.y0 = 1;
  rect.x1 = rect.y1 = 0;
  rect.hasCorners = false;
  if (inside == 0) return;  // wholly where no binned ray goes
  std::array<ClipPoint, 4> polygon;
  int count = 0;
  // Where w = wClip cuts an edge, the cut point's clip x and y are off by the corners' rounding
  // (2^-50 of their magnitudes) and the interpolation's (a few u of |p.x| + |q.x|), and its w by
  // the corners' w rounding, which moves the cut along the edge by dx/dw times that: over wClip,
  // 2^-46 of these bounds the cut point's NDC error with room (clippedErrorX, Y).
  double clippedErrorX = 0.0, clippedErrorY = 0.0;
  for (int k = 0; k < 3; ++k) {
    const ClipPoint& p = corner[k];
    const ClipPoint& q = corner[(k + 1) % 3];
    const bool pIn = p.w >= wClip, qIn = q.w >= wClip;
    if (pIn) polygon[count++] = p;
    if (pIn != qIn) {
      const double s = (p.w - wClip) / (p.w - q.w);
      polygon[count++] = {p.x + s * (q.x - p.x), p.y + s * (q.y - p.y), wClip};
      const ClipMagnitude& mp = magnitude[k];
      const ClipMagnitude& mq = magnitude[(k + 1) % 3];
      const double wMove = (mp.w + mq.w) / std::abs(p.w - q.w);
      clippedErrorX = std::max(clippedErrorX, mp.x + mq.x + std::abs(q.x - p.x) * wMove);
      clippedErrorY = std::max(clippedErrorY, mp.y + mq.y + std::abs(q.y - p.y) * wMove);
    }
  }
  double xMin = std::numeric_limits<double>::infinity(), xMax = -xMin;
  double yMin = xMin, yMax = -xMin;
  double wMin = std::numeric_limits<double>::infinity();
  bool nan = false;
  glm::dvec2 ndc[4];
  double inverseWs[4];
  for (int k = 0; k < count; ++k) {
    wMin = std::min(wMin, polygon[k].w);
    // w >= wClip > 0 here, except the clipped points whose w is wClip up to rounding.
    const double inverseW = 1.0 / std::max(polygon[k].w, wClip);
    const double x = polygon[k].x * inverseW, y = polygon[k].y * inverseW;
    ndc[k] = {x, y};
    inverseWs[k] = inverseW;
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
  if (inside != 3) {
    // A cut at a small wClip (depth clamp's, near the eye) may round by more than the fixed
    // padding: the bound above in pixels, with the rays' tolerance (NaN: the whole range).
    const double base = FrameBins::kRayTolerancePx + FrameBins::kMarginPx;
    padX = std::max(padX, base + 0x1p-46 * (0.5 * viewport.width) * clippedErrorX / wClip);
    padY = std::max(padY, base + 0x1p-46 * (0.5 * viewport.height) * clippedErrorY / wClip);
  } else {
    double errorX = 0.0, errorY = 0.0;
    for (int k = 0; k < 3; ++k) {
      // Unclipped: polygon k is corner k, w >= wClip, so its projection is already at hand.
      const double inverseW = inverseWs[k];
      const double ndcX = std::abs(ndc[k].x), ndcY = std::abs(ndc[k].y);
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
  if (inside == 3 && !nan && rect.x0 <= rect.x1 && rect.y0 <= rect.y1) {
    // The projection is the triangle of the projected corners. Its orientation is trusted only
    // when the signed area is far above the rounding of its evaluation (a sliver whose sign
    // rounding could flip keeps its bounds alone). Rounding of the corners themselves is within
    // the padding, as for the bounds.
    for (int k = 0; k < 3; ++k) {  // unclipped: the polygon is the corners, in order
      rect.corner[k] = {pixelCoordinate(ndc[k].x, viewport.width),
                        pixelCoordinate(ndc[k].y, viewport.height)};
    }
    const glm::dvec2 e = rect.corner[1] - rect.corner[0];
    const glm::dvec2 f = rect.corner[2] - rect.corner[0];
    const double twiceArea = e.x * f.y - e.y * f.x;
    if (std::isfinite(twiceArea) &&
        std::abs(twiceArea) > 0x1p-40 * (std::abs(e.x * f.y) + std::abs(e.y * f.x))) {
      if (twiceArea < 0.0) std::swap(rect.corner[1], rect.corner[2]);
      rect.hasCorners = true;
      rect.padX = padX;
      rect.padY = padY;
    }
  }
}

// Bit r set where row r of a tile row lies outside one of the three edges at x: A' x + rowPart
// (B' y + C') < 0 for some edge (see forEachTile). NaN (not for finite corners) counts as inside:
// conservative. No branches: which half rows a triangle covers is what a predictor cannot guess.
inline unsigned rowsOutside(const double (&rowPart)[3][FrameBins::kTile], const double (&edgeA)[3],
                            double x) {
  unsigned outside = 0;
#if defined(__SSE2__)
  static_assert(FrameBins::kTile % 2 == 0);
  for (int k = 0; k < 3; ++k) {  // two rows per instruction
    const __m128d columnPart = _mm_set1_pd(edgeA[k] * x);
    for (int row = 0; row < FrameBins::kTile; row += 2) {
      const __m128d sum = _mm_add_pd(columnPart, _mm_load_pd(&rowPart[k][row]));
      outside |= static_cast<unsigned>(_mm_movemask_pd(_mm_cmplt_pd(sum, _mm_setzero_pd()))) << row;
    }
  }
#else
  for (int k = 0; k < 3; ++k) {
    const double columnPart = edgeA[k] * x;
    for (int row = 0; row < FrameBins::kTile; ++row) {
      outside |= static_cast<unsigned>(columnPart + rowPart[k][row] < 0.0) << row;
    }
  }
#endif
  return outside;
}

// Calls emit(tileX, tileY, groupMask) for every tile the rect's triangle may be hit in, with the
// half rows (FrameBins's group bits) it may be hit in: those its padded bounds touch and, where the
// rect has its corners, those whose padded centres the triangle may cover.
//
// The edge test of a half row: with E(p) = e x (p - a) = A p_x + B p_y + C for each edge (A = -e_y,
// B = e_x, positive inside: the corners run counter-clockwise), the four centres (x, y) ..
// (x + 3, y) padded by padX and padY can reach the triangle only if, for every edge, the largest E
// over that box is >= 0: E(x + 1.5, y) + |A| (1.5 + padX) + |B| padY. Its evaluation (and that of
// e, A, B, C) rounds by less than 2^-48 of M = |A| (x + 1.5 + |a_x| + 4) + |B| (y + |a_y| + 4) +
// |C| + that padded reach; adding 2^-40 M, which pixel coordinates x, y >= 0 let fold into the
// coefficients, keeps every half row a hit can come from.
template <class Emit>
void forEachTile(const PixelRect& r, Emit&& emit) {
  constexpr int kTile = FrameBins::kTile;
  constexpr double kMargin = 0x1p-40;
  double edgeA[3] = {}, edgeB[3] = {}, edgeC[3] = {};
  if (r.hasCorners) {
    for (int k = 0; k < 3; ++k) {
      const glm::dvec2& a = r.corner[k];
      const glm::dvec2 e = r.corner[k == 2 ? 0 : k + 1] - a;
      const double A = -e.y, B = e.x, C = e.y * a.x - e.x * a.y;
      const double reach = std::abs(A) * (1.5 + r.padX) + std::abs(B) * r.padY;
      edgeA[k] = A + kMargin * std::abs(A);
      edgeB[k] = B + kMargin * std::abs(B);
      edgeC[k] = C + reach +
                 kMargin * (std::abs(A) * (std::abs(a.x) + 4.0) +
                            std::abs(B) * (std::abs(a.y) + 4.0) + std::abs(C) + reach);
    }
  }
  static_assert(kTile == 8, "a tile row's rows are the 8 bits of rowsOutside");
  for (int ty = r.y0 / kTile; ty <= r.y1 / kTile; ++ty) {
    const int rowBegin = std::max(r.y0, ty * kTile),
              rowEnd = std::min(r.y1, ty * kTile + kTile - 1);
    // The tile row's rows the bounds keep, one bit each.
    const unsigned rowsKept =
        ((1u << (rowEnd - ty * kTile + 1)) - 1u) & ~((1u << (rowBegin - ty * kTile)) - 1u);
    // B' y + C' of each edge, for all 8 rows of the tile row (those outside the bounds are
    // dropped by rowsKept).
    alignas(16) double rowPart[3][kTile];
    if (r.hasCorners) {
      for (int k = 0; k < 3; ++k) {
        for (int row = 0; row < kTile; ++row) {
          rowPart[k][row] = edgeB[k] * (ty * kTile + row) + edgeC[k];
        }
      }
    }
    for (int tx = r.x0 / kTile; tx <= r.x1 / kTile; ++tx) {
      const int left = tx * kTile;
      const std::uint32_t halves = (r.x0 <= left + 3 ? 1u : 0u) | (r.x1 >= left + 4 ? 2u : 0u);
      std::uint32_t mask = 0;
      if (!r.hasCorners) {
        for (int y = rowBegin; y <= rowEnd; ++y) mask |= halves << (2 * (y - ty * kTile));
      } else {
        for (int half = 0; half < 2; ++half) {
          if ((halves & (1u << half)) == 0) continue;
          const unsigned outside = rowsOutside(rowPart, edgeA, left + 4 * half + 1.5);
          // Row bits to the mask's layout: row r's half rows are bits 2 r and 2 r + 1.
          std::uint32_t inside = ~outside & rowsKept;
          inside = (inside | (inside << 4)) & 0x0f0fu;
          inside = (inside | (inside << 2)) & 0x3333u;
          inside = (inside | (inside << 1)) & 0x5555u;
          mask |= inside << half;
        }
      }
      if (mask != 0) emit(tx, ty, static_cast<std::uint16_t>(mask));
    }
  }
}

// The corners of an analytic primitive's local box (the square for a disk or quad) in clip space.
std::array<glm::dvec4, 8> boxCorners(const AnalyticPrimitive& primitive,
                                     const glm::dmat4& clipFromRelative,
                                     const glm::dvec3& reference) {
  const bool flat = primitive.kind == PrimitiveKind::Disk || primitive.kind == PrimitiveKind::Quad;
  std::array<glm::dvec4, 8> corner;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec4 local((k & 1) ? 1.0 : -1.0, (k & 2) ? 1.0 : -1.0,
                           flat ? 0.0 : ((k & 4) ? 1.0 : -1.0), 1.0);
    const glm::dvec4 world = primitive.worldFromLocal * local;
    corner[k] = clipFromRelative * glm::dvec4(glm::dvec3(world) - reference, 1.0);
  }
  return corner;
}

// The box's corners with w >= wClip and the points where its edges cross w = wClip, into kept
// (8 corners + 12 edge crossings at most); their count.
int keptBoxPoints(const std::array<glm::dvec4, 8>& corner, double wClip,
                  std::array<glm::dvec4, 20>& kept) {
  int count = 0;
  for (int k = 0; k < 8; ++k) {
    if (corner[k].w >= wClip) kept[count++] = corner[k];
    for (int axis = 0; axis < 3; ++axis) {
      const int other = k | (1 << axis);  // each edge once, from its lower end
      if (other == k) continue;
      const glm::dvec4& a = corner[k];
      const glm::dvec4& b = corner[other];
      if ((a.w >= wClip) != (b.w >= wClip)) {
        kept[count++] = a + (b - a) * ((wClip - a.w) / (b.w - a.w));
      }
    }
  }
  return count;
}

// The bounding rectangle of projected points in pixel coordinates; all NaN when a projection is.
struct PixelBox {
  double xMin, xMax, yMin, yMax;
};

PixelBox projectedBox(const std::array<glm::dvec4, 20>& kept, int count, double wClip,
                      Viewport viewport) {
  double xMin = std::numeric_limits<double>::infinity(), xMax = -xMin, yMin = xMin, yMax = -xMin;
  for (int k = 0; k < count; ++k) {
    const double w = std::max(kept[k].w, wClip);
    const double x = pixelCoordinate(kept[k].x / w, viewport.width);
    const double y = pixelCoordinate(kept[k].y / w, viewport.height);
    xMin = std::min(xMin, x);
    xMax = std::max(xMax, x);
    yMin = std::min(yMin, y);
    yMax = std::max(yMax, y);
    if (std::isnan(x) || std::isnan(y)) xMin = xMax = yMin = yMax = std::nan("");
  }
  return {xMin, xMax, yMin, yMax};
}

// Chunk c of the triangle binning takes the blocks c, c + chunkCount, ... of kBlock triangles:
// every chunk samples the whole mesh (a mesh's triangles near the camera cover many tiles and cost
// more), and its slots still increase. A block's rects are made, counted against the budget, then
// placed.
constexpr std::size_t kBlock = 1024;

// What every chunk's binning reads: the triangles, the frame's projection and tile grid, and how
// the triangles are shared out and bounded.
struct BinningInput {
  const std::vector<detail::BvhTriangle>& triangles;
  const glm::dmat4& clipFromRelative;
  double wClip;
  Viewport viewport;
  int tilesAcross;
  std::size_t tileCount;
  unsigned chunkCount;
  std::uint64_t entryBudget;
};

// A triangle's entry with the tile whose list it goes to, before the lists are gathered.
struct PlacedEntry {
  std::uint32_t tile;
  BinnedTriangle entry;
};

// The rects of triangles [first, end) (rects[s - first]); adds the tile entries they ask for to
// total.
void measureBlock(const BinningInput& in, std::size_t first, std::size_t end,
                  std::vector<PixelRect>& rects, std::uint64_t& total) {
  constexpr int kTile = FrameBins::kTile;
  for (std::size_t s = first; s < end; ++s) {
    PixelRect& r = rects[s - first];
    triangleRect(in.clipFromRelative, in.triangles[s], in.wClip, in.viewport, r);
    if (r.x0 > r.x1 || r.y0 > r.y1) continue;
    total += std::uint64_t(r.x1 / kTile - r.x0 / kTile + 1) * (r.y1 / kTile - r.y0 / kTile + 1);
  }
}

// The entries of triangles [first, end), with their tiles, appended to placed; each tile's count
// added to offsets[tile + 1].
void placeBlock(const BinningInput& in, std::size_t first, std::size_t end,
                const std::vector<PixelRect>& rects, FrameVector<std::uint32_t>& offsets,
                FrameVector<PlacedEntry>& placed) {
  for (std::size_t s = first; s < end; ++s) {
    const PixelRect& r = rects[s - first];
    if (r.x0 > r.x1 || r.y0 > r.y1) continue;
    forEachTile(r, [&](int tx, int ty, std::uint16_t mask) {
      const auto tile = static_cast<std::uint32_t>(ty * in.tilesAcross + tx);
      ++offsets[tile + 1];
      placed.push_back({tile, {static_cast<std::uint32_t>(s), mask, r.nearestW}});
    });
  }
}

// The placed entries scattered into their tiles' lists: offsets, the counts until then, become
// each tile's first entry.
void gatherEntries(const FrameVector<PlacedEntry>& placed, std::size_t tileCount,
                   FrameVector<std::uint32_t>& offsets, FrameVector<BinnedTriangle>& entries) {
  for (std::size_t t = 0; t < tileCount; ++t) offsets[t + 1] += offsets[t];
  entries.resize(offsets[tileCount]);
  FrameVector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
  for (const PlacedEntry& p : placed) entries[fill[p.tile]++] = p.entry;
}

// Chunk c's tile lists: offsets (tile -> first entry; tileCount + 1 values) and entries. False,
// with both released, when the chunk's entries would pass the budget.
bool binChunk(const BinningInput& in, unsigned c, FrameVector<std::uint32_t>& offsets,
              FrameVector<BinnedTriangle>& entries) {
  const std::size_t triangleCount = in.triangles.size();
  offsets.assign(in.tileCount + 1, 0);
  // Every triangle's tiles and half rows, then scattered into the tiles' lists. Room for the
  // whole budget up front (address space: only what is placed is touched), so it never grows.
  FrameVector<PlacedEntry> placed;
  placed.reserve(in.entryBudget);
  std::vector<PixelRect> rects(std::min(kBlock, triangleCount));
  std::uint64_t total = 0;
  for (std::size_t first = c * kBlock; first < triangleCount; first += in.chunkCount * kBlock) {
    const std::size_t end = std::min(triangleCount, first + kBlock);
    measureBlock(in, first, end, rects, total);
    if (total > in.entryBudget) {
      offsets = FrameVector<std::uint32_t>{};
      entries = FrameVector<BinnedTriangle>{};
      return false;
    }
    placeBlock(in, first, end, rects, offsets, placed);
  }
  gatherEntries(placed, in.tileCount, offsets, entries);
  return true;
}

// Runs work(c) for every c < count: 0 on this thread, the others on threads of their own, or
// here as well once no more threads can be started.
template <class Work>
void runChunks(unsigned count, const Work& work) {
  std::vector<std::thread> workers;
  try {
    for (unsigned c = 1; c < count; ++c) workers.emplace_back(work, c);
  } catch (const std::system_error&) {
    for (unsigned c = static_cast<unsigned>(workers.size()) + 1; c < count; ++c) work(c);
  }
  work(0);
  for (std::thread& worker : workers) worker.join();
}

}  // namespace

// The near plane's clip w: the world point unprojected from (x, y, z_near) has homogeneous
// weight Pw = row 3 of worldFromClip . (x, y, z_near, 1), and clip w = 1 / Pw. Pw is affine in
// (x, y), so across the viewport its extremes are at the corners. Rays that start on the near
// plane have w >= wNear there. None when the near plane is not in front of the camera across the
// viewport.
std::optional<double> FrameBins::nearPlaneW(const glm::dmat4& clipFromWorld, DepthMode mode) {
  const glm::dmat4 worldFromClip = glm::inverse(clipFromWorld);
  const double zNear = mode.nearNdcZ();
  double wNear = std::numeric_limits<double>::infinity();
  for (const double x : {-1.0, 1.0}) {
    for (const double y : {-1.0, 1.0}) {
      const double pw = worldFromClip[0][3] * x + worldFromClip[1][3] * y +
                        worldFromClip[2][3] * zNear + worldFromClip[3][3];
      if (!(pw > 0.0) || !std::isfinite(pw)) return std::nullopt;
      wNear = std::min(wNear, 1.0 / pw);
    }
  }
  if (!(wNear > 0.0) || !std::isfinite(wNear)) return std::nullopt;
  return wNear;
}

FrameBins::FrameBins(const SceneIntersector& scene, const glm::dmat4& clipFromWorld, DepthMode mode,
                     Viewport viewport, unsigned threadCount, std::optional<double> wClip)
    : viewport_(viewport) {
  if (viewport.width <= 0 || viewport.height <= 0) return;
  tilesAcross_ = (viewport.width + kTile - 1) / kTile;
  tilesUp_ = (viewport.height + kTile - 1) / kTile;
  // Triangles are stored relative to the reference point: fold it into the translation column.
  clipFromRelative_ = clipFromWorld;
  clipFromRelative_[3] = clipFromWorld * glm::dvec4(scene.reference(), 1.0);
  if (wClip) {
    if (!(*wClip > 0.0) || !std::isfinite(*wClip)) return;
    wClip_ = *wClip;
  } else {
    const std::optional<double> wNear = nearPlaneW(clipFromWorld, mode);
    if (!wNear) return;     // no near plane in front: no bins
    wClip_ = 0.5 * *wNear;  // half the rays' smallest w: a factor 2 of margin
  }
  boundPrimitives(scene);
  usable_ = binTriangles(scene, threadCount);
}

void FrameBins::boundPrimitives(const SceneIntersector& scene) {
  for (const AnalyticPrimitive& primitive : scene.primitives_) {
    PixelBounds& bounds = primitiveBounds_.emplace_back();
    if (primitive.kind == PrimitiveKind::Plane) {
      bounds = {0, viewport_.width - 1, 0, viewport_.height - 1};
      continue;
    }
    std::array<glm::dvec4, 20> kept;
    const int count =
        keptBoxPoints(boxCorners(primitive, clipFromRelative_, scene.reference()), wClip_, kept);
    if (count == 0) continue;  // wholly where no binned ray goes: empty bounds
    const PixelBox box = projectedBox(kept, count, wClip_, viewport_);
    const auto padded = [](double value) {
      return FrameBins::kPrimitivePaddingPx + 0x1p-30 * std::abs(value);
    };
    pixelRange(box.xMin, box.xMax, std::max(padded(box.xMin), padded(box.xMax)), viewport_.width,
               bounds.x0, bounds.x1);
    pixelRange(box.yMin, box.yMax, std::max(padded(box.yMin), padded(box.yMax)), viewport_.height,
               bounds.y0, bounds.y1);
  }
}

bool FrameBins::binTriangles(const SceneIntersector& scene, unsigned threadCount) {
  const std::size_t triangleCount = scene.triangles_.size();
  const std::size_t tileCount = static_cast<std::size_t>(tilesAcross_) * tilesUp_;
  unsigned chunkCount = threadCount == 0 ? std::thread::hardware_concurrency() : threadCount;
  chunkCount = std::clamp<unsigned>(chunkCount, 1u, 64u);
  if (triangleCount < 4096) chunkCount = 1;
  chunks_.resize(chunkCount);
  // Triangles that cover many tiles each (big, overlapping, or seen from up close) can ask for
  // more entries than the bins pay for: past this many per chunk the frame walks the BVH instead.
  const std::uint64_t entryBudget = std::min<std::uint64_t>(
      std::uint64_t{1} << 27, 16 * (std::uint64_t{triangleCount} / chunkCount + tileCount));
  const BinningInput input{scene.triangles_, clipFromRelative_, wClip_,     viewport_,
                           tilesAcross_,     tileCount,         chunkCount, entryBudget};
  std::vector<char> overBudget(chunkCount, 0);
  // A chunk that cannot get its memory is treated as over budget (the frame walks the BVH).
  runChunks(chunkCount, [&](unsigned c) {
    Chunk& chunk = chunks_[c];
    try {
      if (binChunk(input, c, chunk.offsets, chunk.entries)) return;
    } catch (const std::bad_alloc&) {
      chunk = Chunk{};
    }
    overBudget[c] = 1;
  });
  if (std::find(overBudget.begin(), overBudget.end(), 1) != overBudget.end()) {
    chunks_.clear();
    return false;
  }
  return true;
}

std::size_t FrameBins::entryCount() const {
  std::size_t count = 0;
  for (const Chunk& chunk : chunks_) count += chunk.entries.size();
  return count;
}

}  // namespace clipray
