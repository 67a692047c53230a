// Screen-space decisions for the closest triangle of each pixel (ScreenEvaluator.hpp), with the
// bounds of ScreenTriangleSetup.cpp. A tile's pixels keep, per pixel, the nearest upper depth key
// of a surely crossed triangle, the two smallest lower keys of those (and the first one's slot)
// and the smallest lower key of a triangle perhaps crossed: enough to tell one nearest triangle
// (its watertight test gives t), several within the order margin (the watertight tests of the
// tile's triangles not surely outside the pixel decide, with closestHit's rule) and a pixel a
// margin cannot decide (traced), without a list per pixel. Four pixel centres of a tile
// row are evaluated per step, on AVX2 lanes where the CPU has them and the SIMD kernels are chosen
// (KernelChoice.hpp), else on the baseline's: the same operations, and every decision certified
// either way, so the hits are the ray path's bits on both.

#include "clipray/compare/ScreenEvaluator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "clipray/compare/ScreenTriangleSetup.hpp"
#include "clipray/intersect/FrameBins.hpp"
#include "clipray/intersect/PacketKernels.hpp"
#include "clipray/rays/RobustRays.hpp"

namespace clipray {

namespace detail {
struct ScreenTriangles {
  // The triangles the bins' slots index (SceneIntersector's storage, culled ones left out).
  static const std::vector<BvhTriangle>& of(const SceneIntersector& intersector) {
    return intersector.triangles_;
  }
};
}  // namespace detail

namespace {

using namespace screen;

constexpr int kTile = FrameBins::kTile;
constexpr int kTilePixels = kTile * kTile;
constexpr int kLanes = 4;
static_assert(kTile % kLanes == 0);

// Four doubles and four lane masks (each lane all ones or zero), in GCC's vector extensions: the
// walk below compiles to AVX2 inside walkTileAvx2 and to pairs of SSE2 operations elsewhere. No
// function takes or returns one by value (that ABI differs between the two).
using Lanes = double __attribute__((vector_size(32)));
using Mask = long long __attribute__((vector_size(32)));

// A tile's pixels while its triangles are walked, a field per array (four neighbours per load).
struct alignas(32) TileState {
  double nearestHigh[kTilePixels];  // the smallest upper key of a surely crossed triangle
  double firstLow[kTilePixels];     // the smallest lower key of a surely crossed triangle,
  double firstSlot[kTilePixels];    //   that triangle's slot (exact in a double),
  double secondLow[kTilePixels];    //   and the second smallest
  double unsureLow[kTilePixels];    // the smallest lower key of one perhaps crossed; -inf: any

  void reset() {
    std::fill(std::begin(nearestHigh), std::end(nearestHigh), kInf);
    std::fill(std::begin(firstLow), std::end(firstLow), kInf);
    std::fill(std::begin(firstSlot), std::end(firstSlot), 0.0);
    std::fill(std::begin(secondLow), std::end(secondLow), kInf);
    std::fill(std::begin(unsureLow), std::end(unsureLow), kInf);
  }
};

// One tile's walk over the triangles its bins list.
struct TileWalk {
  const FrameTerms* terms;
  const TriangleSetup* setups;
  // kMaxClipCuts per slot, where the camera has user clip planes; else null.
  const ClipEdge* clipEdges;
  const FrameBins* bins;
  const double* clipX;  // NDC x of every pixel column's centre, padded to whole tiles
  const double* clipY;  // NDC y of every pixel row's centre
  int tileX, tileY;
  int rows, columns;  // of the tile inside the viewport
  TileState* state;
};

[[gnu::always_inline]] inline void load(Lanes& lanes, const double* p) {
  std::memcpy(&lanes, p, sizeof lanes);
}
[[gnu::always_inline]] inline void store(double* p, const Lanes& lanes) {
  std::memcpy(p, &lanes, sizeof lanes);
}
[[gnu::always_inline]] inline bool everyLane(const Mask& mask) {
  return (mask[0] & mask[1] & mask[2] & mask[3]) != 0;
}

// Every triangle the tile's bins list, at the pixel centres of its bounds that the tile holds,
// four centres of a row at a time: the decisions of ScreenTriangleSetup.hpp per lane.
[[gnu::always_inline]] inline void walkTile(const TileWalk& walk) {
  const FrameTerms& frame = *walk.terms;
  TileState& s = *walk.state;
  const Lanes inf = Lanes{} + kInf;
  const Lanes minusInf = Lanes{} - kInf;
  const double farOut = frame.keyFar + kRangeMargin, farIn = frame.keyFar - kRangeMargin;
  const double nearIn = frame.keyNearIn, nearOut = frame.keyNearOut;
  const int x0 = walk.tileX * kTile, y0 = walk.tileY * kTile;
  for (int chunk = 0; chunk < walk.bins->listChunkCount(); ++chunk) {
    for (const BinnedTriangle& entry : walk.bins->list(chunk, walk.tileX, walk.tileY)) {
      const TriangleSetup& t = walk.setups[entry.slot];
      const int ly0 = std::max(0, t.y0 - y0), ly1 = std::min(walk.rows - 1, t.y1 - y0);
      const int lx0 = std::max(0, t.x0 - x0), lx1 = std::min(walk.columns - 1, t.x1 - x0);
      if (ly0 > ly1 || lx0 > lx1) continue;
      const Lanes slot = Lanes{} + static_cast<double>(entry.slot);
      for (int ly = ly0; ly <= ly1; ++ly) {
        const double y = walk.clipY[y0 + ly];
        const double c0 = t.b[0] * y + t.c[0], c1 = t.b[1] * y + t.c[1], c2 = t.b[2] * y + t.c[2];
        const double zRow = t.zb * y + t.zc;
        // The clip planes that cut the triangle (at most kMaxClipCuts: their edges), kept and
        // clipped away per pixel.
        const ClipEdge* cuts = t.clipped && walk.clipEdges
                                   ? walk.clipEdges + std::size_t{entry.slot} * kMaxClipCuts
                                   : nullptr;
        static_assert(kMaxClipCuts == 2);
        const ClipEdge* cut = cuts && cuts[0].used ? &cuts[0] : nullptr;
        const ClipEdge* cut2 = cuts && cuts[1].used ? &cuts[1] : nullptr;
        const double keepRow = cut ? cut->kb * y + cut->kc : 0.0;
        const double clipAwayRow = cut ? cut->cb * y + cut->cc : 0.0;
        const double keepRow2 = cut2 ? cut2->kb * y + cut2->kc : 0.0;
        const double clipAwayRow2 = cut2 ? cut2->cb * y + cut2->cc : 0.0;
        for (int lx = lx0 - lx0 % kLanes; lx <= lx1; lx += kLanes) {
          const int i = ly * kTile + lx;
          Lanes x;
          load(x, walk.clipX + x0 + lx);
          const Lanes e0 = t.a[0] * x + c0, e1 = t.a[1] * x + c1, e2 = t.a[2] * x + c2;
          if (t.sign == 0.0) {
            // The orientation is not certain: only edge functions of both signs say outside.
            const Mask positive = (e0 > t.margin[0]) | (e1 > t.margin[1]) | (e2 > t.margin[2]);
            const Mask negative = (e0 < -t.margin[0]) | (e1 < -t.margin[1]) | (e2 < -t.margin[2]);
            Lanes unsureLow;
            load(unsureLow, s.unsureLow + i);
            store(s.unsureLow + i, (positive & negative) ? unsureLow : minusInf);
            continue;
          }
          // Outside an edge over the ray's whole reach; inside every edge over it.
          Mask outside = (e0 < -t.margin[0]) | (e1 < -t.margin[1]) | (e2 < -t.margin[2]);
          if (cut) outside |= cut->ca * x + clipAwayRow < -cut->clipAwayError;
          if (cut2) outside |= cut2->ca * x + clipAwayRow2 < -cut2->clipAwayError;
          if (everyLane(outside)) continue;
          const Mask inside = (e0 > t.margin[0]) & (e1 > t.margin[1]) & (e2 > t.margin[2]);
          const Lanes key = frame.sigma * ((t.za * x + zRow) - frame.zNear);
          const Lanes low = key - t.depthError, high = key + t.depthError;
          const Mask outOfRange = (high < nearOut) | (low > farOut);
          // A triangle a clip plane may cut is never surely crossed: perhaps, where it is.
          Mask sure = inside & (low > nearIn) & (high < farIn);
          if (cut) {
            sure &= cut->ka * x + keepRow > cut->keepError;
            if (cut2) sure &= cut2->ka * x + keepRow2 > cut2->keepError;
          } else if (t.clipped) {
            sure = Mask{};
          }
          const Mask perhaps = ~(outside | outOfRange | sure);

          Lanes nearestHigh, firstLow, firstSlot, secondLow, unsureLow;
          load(nearestHigh, s.nearestHigh + i);
          load(firstLow, s.firstLow + i);
          load(firstSlot, s.firstSlot + i);
          load(secondLow, s.secondLow + i);
          load(unsureLow, s.unsureLow + i);
          const Lanes lowSure = sure ? low : inf, highSure = sure ? high : inf;
          const Mask first = lowSure < firstLow;
          const Lanes second = first ? firstLow : lowSure;
          store(s.nearestHigh + i, highSure < nearestHigh ? highSure : nearestHigh);
          store(s.secondLow + i, second < secondLow ? second : secondLow);
          store(s.firstLow + i, first ? lowSure : firstLow);
          store(s.firstSlot + i, first ? slot : firstSlot);
          // A lower key that is not a number (a depth plane out of double's range) bounds nothing.
          const Lanes lowOrAny = ((low > minusInf) & (low < inf)) ? low : minusInf;
          const Lanes unsure = perhaps ? lowOrAny : inf;
          store(s.unsureLow + i, unsure < unsureLow ? unsure : unsureLow);
        }
      }
    }
  }
}

// The hit of a pixel with several triangles within the depth margin of the nearest: each of the
// tile's listed triangles whose edges do not put the pixel centre surely outside (a superset of
// those that may be the nearest: the pixel has no uncertain triangle within reach) tested with
// the watertight test, the closest kept by closestHit's rule (the smaller t, ties to the smaller
// id). The BVH is not needed.
Hit closestOfListed(const TileWalk& walk, int lx, int ly, const SceneIntersector& intersector,
                    const Ray& ray) {
  const int px = walk.tileX * kTile + lx, py = walk.tileY * kTile + ly;
  const double x = walk.clipX[px], y = walk.clipY[py];
  Hit best;
  for (int chunk = 0; chunk < walk.bins->listChunkCount(); ++chunk) {
    for (const BinnedTriangle& entry : walk.bins->list(chunk, walk.tileX, walk.tileY)) {
      const TriangleSetup& t = walk.setups[entry.slot];
      if (px < t.x0 || px > t.x1 || py < t.y0 || py > t.y1) continue;
      bool outside = false;
      for (int k = 0; k < 3 && t.sign != 0.0; ++k) {
        outside = outside || t.a[k] * x + (t.b[k] * y + t.c[k]) < -t.margin[k];
      }
      if (outside) continue;
      const Hit candidate = intersector.intersectOne(t.primitiveId, ray);
      if (candidate.hit() &&
          (!best.hit() || candidate.t < best.t ||
           (candidate.t == best.t && candidate.primitiveId < best.primitiveId))) {
        best = candidate;
      }
    }
  }
  return best;
}

// The finish of four neighbouring pixels of a tile row (state index i .. i + 3) where each is
// background or decided alone from its planes, as the finish loop decides them one by one
// (traced: an uncertain triangle may be the nearest; background: no triangle surely crossed;
// alone: no second crossing within the order margin); false, nothing written, otherwise.
bool finishFour(const TileState& s, int i, const std::uint32_t* idOfSlot, Hit* hits,
                ScreenEvaluation& counts) {
  Lanes nearestHigh, firstLow, secondLow, unsureLow;
  load(nearestHigh, s.nearestHigh + i);
  load(firstLow, s.firstLow + i);
  load(secondLow, s.secondLow + i);
  load(unsureLow, s.unsureLow + i);
  const Lanes reach = nearestHigh + kOrderMargin * (nearestHigh < 0.0 ? -nearestHigh : nearestHigh);
  const Mask traced = (unsureLow < kInf) & (unsureLow <= reach);
  const Mask background = ~traced & (firstLow == kInf);
  const Mask alone = ~traced & (firstLow < kInf) & ~(secondLow <= reach);
  if (!everyLane(background | alone)) return false;
  for (int l = 0; l < kLanes; ++l) {
    if (background[l] != 0) {
      hits[l] = Hit{};
      ++counts.background;
    } else {
      hits[l] = Hit{std::numeric_limits<double>::quiet_NaN(),
                    idOfSlot[static_cast<std::size_t>(s.firstSlot[i + l])]};
      ++counts.decided;
    }
  }
  return true;
}

void walkTilePortable(const TileWalk& walk) {
  walkTile(walk);
}

#if defined(__x86_64__) || defined(__i386__)
__attribute__((target("avx2,fma"))) void walkTileAvx2(const TileWalk& walk) {
  walkTile(walk);
}
#endif

// Whether every pixel centre of a tile surely has a robust ray: its near point lies in front of
// the eye (RobustRayGenerator::finishRay), clip w 1 / w_near > 0, and is finite. w_near =
// worldFromClip row 3 . (x, y, z_n, 1) is affine in (x, y), so its least value over the tile is at
// a corner; the generator's rounding of it is below gamma(4) of its terms' sizes, far below the
// margin asked (10^-9 of them), and a w_near above that margin keeps the near point, at most
// 4 max |worldFromClip entry| / margin, finite (nearPointW asks that of the matrix).
struct NearPointW {
  double a = 0.0, b = 0.0, c = 0.0;  // w_near = a x + b y + c
  double margin = kInf;
};

NearPointW nearPointW(const RobustRayGenerator& generator) {
  const glm::dmat4& p = generator.worldFromClip();
  const double zNear = generator.mode().nearNdcZ();
  NearPointW w{p[0][3], p[1][3], p[2][3] * zNear + p[3][3], kInf};
  double largest = 0.0;  // the largest |entry| of worldFromClip: a near point's size over |w_near|
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) largest = std::max(largest, std::abs(p[c][r]));
  }
  const double size =
      std::abs(p[0][3]) + std::abs(p[1][3]) + std::abs(p[2][3] * zNear) + std::abs(p[3][3]);
  const double margin = 1e-9 * size;
  // Outside that range the near points' size over the margin might overflow: no tile is sure.
  if (margin > 0.0 && std::isfinite(margin) && 4.0 * largest / margin < 1e300) w.margin = margin;
  return w;
}

// What the walk and depth clamp read of an analytic primitive's local box (the square of a disk
// or quad), over its corners: in front of the eye z / w is quasi-linear, so its least depth key
// (FrameTerms: sigma (z_ndc - z_near)) over the box lies at a corner. Each is lowered by far more
// than the corners' rounding: keyLow by 2^-30 of the key's terms, wLow (the least clip w) by
// 2^-40 of its. A plane, or a box reaching behind the eye, has both -inf. A pixel's ray may hit
// the primitive only where the nearest triangle's key could reach keyLow.
struct PrimitiveBoxDepth {
  double keyLow = kInf, wLow = kInf;
};

std::vector<PrimitiveBoxDepth> primitiveBoxDepths(const SceneIntersector& intersector,
                                                  const glm::dmat4& clipFromWorld, DepthMode mode) {
  const glm::dvec4 rowZ(clipFromWorld[0][2], clipFromWorld[1][2], clipFromWorld[2][2],
                        clipFromWorld[3][2]);
  const glm::dvec4 rowW(clipFromWorld[0][3], clipFromWorld[1][3], clipFromWorld[2][3],
                        clipFromWorld[3][3]);
  const double sigma = mode.farNdcZ() > mode.nearNdcZ() ? 1.0 : -1.0;  // FrameTerms::sigma
  const std::uint32_t first = static_cast<std::uint32_t>(intersector.triangleCount()) + 1;
  std::vector<PrimitiveBoxDepth> depths;
  for (std::size_t p = 0; p < intersector.analyticCount(); ++p) {
    const AnalyticPrimitive& primitive =
        intersector.analyticPrimitive(first + static_cast<std::uint32_t>(p));
    PrimitiveBoxDepth& box = depths.emplace_back();
    const bool flat =
        primitive.kind == PrimitiveKind::Disk || primitive.kind == PrimitiveKind::Quad;
    for (int k = 0; k < 8 && primitive.kind != PrimitiveKind::Plane; ++k) {
      const glm::dvec4 local((k & 1) ? 1.0 : -1.0, (k & 2) ? 1.0 : -1.0,
                             flat ? 0.0 : ((k & 4) ? 1.0 : -1.0), 1.0);
      const glm::dvec4 world = primitive.worldFromLocal * local;
      const double z = glm::dot(rowZ, world), w = glm::dot(rowW, world);
      const double zSize = glm::dot(glm::abs(rowZ), glm::abs(world));
      const double wSize = glm::dot(glm::abs(rowW), glm::abs(world));
      const double wLow = w - 0x1p-40 * wSize;
      if (!(wLow > 0.0)) {
        box = {-kInf, -kInf};
        break;
      }
      const double key = sigma * (z / w - mode.nearNdcZ());
      const double rounding = (zSize + std::abs(z / w) * wSize) / w;
      box.keyLow = std::min(box.keyLow, key - 0x1p-30 * (rounding + std::abs(key) + 1.0));
      box.wLow = std::min(box.wLow, wLow);
    }
    if (primitive.kind == PrimitiveKind::Plane || std::isnan(box.keyLow)) box = {-kInf, -kInf};
  }
  return depths;
}

bool tileRaysExist(const NearPointW& w, double xLow, double xHigh, double yLow, double yHigh) {
  const double lowest = std::min({w.a * xLow + w.b * yLow, w.a * xLow + w.b * yHigh,
                                  w.a * xHigh + w.b * yLow, w.a * xHigh + w.b * yHigh}) +
                        w.c;
  return lowest > w.margin;
}

}  // namespace

ScreenEvaluation intersectFrameInScreenSpace(AnalyticFrame& frame,
                                             const SceneIntersector& intersector,
                                             const PickingCamera& camera, unsigned threadCount,
                                             ScreenDepths* depths, DecidedHits decided) {
  ScreenEvaluation result;
  frame.planesById.reset();
  if (depths) {
    depths->ndcZ.assign(frame.pixelCount(), std::numeric_limits<double>::quiet_NaN());
    depths->bound.assign(frame.pixelCount(), std::numeric_limits<double>::quiet_NaN());
  }
  const auto traceByRays = [&](std::string reason) {
    result.reason = std::move(reason);
    intersectFrame(frame, intersector, camera, threadCount);
    return result;
  };
  if (!frame.pixelCentreRays || !frame.rays.empty()) {
    return traceByRays("the frame's rays are not the camera's robust rays computed per pixel");
  }
  if (intersector.analyticCount() != 0 && intersector.triangleCount() == 0) {
    return traceByRays("analytic primitives stay on rays");
  }
  const RobustRayGenerator& generator = frame.pixelCentreRays->generator();
  const Viewport viewport = frame.viewport;
  const std::span<const glm::dvec4> rayPlanes = generator.clipPlanes();
  if (generator.clipFromWorld() != camera.clipFromWorld || generator.mode() != camera.mode ||
      viewport.width != camera.viewport.width || viewport.height != camera.viewport.height ||
      !std::equal(rayPlanes.begin(), rayPlanes.end(), camera.clipPlanes.begin(),
                  camera.clipPlanes.end())) {
    return traceByRays("the frame's rays are not the camera's");
  }
  if (intersector.triangleCount() == 0 || viewport.width <= 0 || viewport.height <= 0) {
    return traceByRays("nothing to evaluate");
  }
  const std::vector<detail::BvhTriangle>& triangles = detail::ScreenTriangles::of(intersector);
  // The scene's extent about the reference, which the clip planes' margins and cut need.
  double sceneExtent = 0.0;
  if (!camera.clipPlanes.empty()) {
    for (const detail::BvhTriangle& t : triangles) {
      for (const glm::dvec3& v : {t.a, t.b, t.c}) {
        sceneExtent = std::max({sceneExtent, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
      }
    }
  }
  std::string reason;
  // Depth clamp's rays start at the eye (a parallel camera's behind the near plane): their own
  // Delta, and the bins cut near the eye instead of at the near plane.
  std::optional<DepthClampReach> clamp;
  if (camera.depthClamp) {
    clamp = depthClampDeviation(generator, reason);
    if (!clamp) return traceByRays(reason);
  }
  const std::vector<PrimitiveBoxDepth> primitiveBoxes =
      primitiveBoxDepths(intersector, camera.clipFromWorld, camera.mode);
  // Under depth clamp no ray may reach a primitive nearer the eye than the eye box.
  if (clamp && clamp->eyeBoxW > 0.0 &&
      std::any_of(primitiveBoxes.begin(), primitiveBoxes.end(),
                  [&](const PrimitiveBoxDepth& box) { return !(box.wLow >= clamp->eyeBoxW); })) {
    return traceByRays("an analytic primitive reaches the depth-clamped rays near the eye");
  }
  const std::optional<double> rayDelta =
      clamp ? std::optional<double>(clamp->delta) : rayDeviation(generator, reason);
  if (!rayDelta) return traceByRays(reason);
  const std::optional<double> cutDelta = clipCutDeviation(
      generator, intersector.reference(), sceneExtent, reason, clamp ? &*clamp : nullptr);
  if (!cutDelta) return traceByRays(reason);
  const double delta = *rayDelta + *cutDelta;
  // The bins list the triangles rays within kRayTolerancePx of their pixels can hit.
  const double deltaPixels = delta * 0.5 * std::max(viewport.width, viewport.height);
  if (!(deltaPixels < 0.5 * FrameBins::kRayTolerancePx)) {
    return traceByRays("the rays may stray " + std::to_string(deltaPixels) +
                       " pixels from their centres");
  }
  const FrameBins bins(intersector, camera.clipFromWorld, camera.mode, viewport, threadCount,
                       clamp ? std::optional<double>(clamp->wLeast) : std::nullopt);
  if (!bins.usable()) return traceByRays("no screen bins for this camera");

  const FrameTerms terms =
      frameTerms(camera, generator, bins.clipFromRelative(), intersector.reference(), delta,
                 sceneExtent, clamp ? &*clamp : nullptr);

  frame.hits.resize(frame.pixelCount());
  const int tileRows = (viewport.height + kTile - 1) / kTile;
  std::mutex countsLock;  // the workers add their counts to result at the end
  const int tileColumns = (viewport.width + kTile - 1) / kTile;
  std::vector<double> clipX(static_cast<std::size_t>(tileColumns * kTile));
  for (int x = 0; x < tileColumns * kTile; ++x) {
    clipX[static_cast<std::size_t>(x)] = clipXYOfPixelCentre(x, 0, viewport).x;
  }
  std::vector<double> clipY(static_cast<std::size_t>(viewport.height));
  for (int y = 0; y < viewport.height; ++y) {
    clipY[static_cast<std::size_t>(y)] = clipXYOfPixelCentre(0, y, viewport).y;
  }
  // Each triangle's setup once (a triangle is listed in every tile it may cover), and where the
  // compare takes the planes, its planes by id (each id written by its own triangle's setup).
  const NearPointW nearW = nearPointW(generator);
  // Under depth clamp every pixel has a ray (from the eye), and the compare evaluates a perspective
  // camera's planes (a parallel one's rays reach behind the near plane: its distances are measured
  // along them, so its decided pixels are tested).
  const bool clampedParallel = camera.depthClamp && generator.isParallel();
  const bool fromPlanes = decided == DecidedHits::FromPlanes && !clampedParallel &&
                          (camera.depthClamp || nearW.margin < kInf);
  // The per-triangle arrays are frame buffers (FrameBuffers.hpp): each slot is written by its own
  // triangle's setup, and a terrain's 16 MB of setups are the pages the last frame released, not
  // fresh ones to fault in and zero. A triangle's planes are read only where it was decided.
  std::shared_ptr<FrameVector<TrianglePlanes>> planes;
  if (fromPlanes) {
    planes = std::make_shared<FrameVector<TrianglePlanes>>();
    planes->resize(std::size_t{intersector.primitiveIdCount()} + 1);
  }
  FrameVector<TriangleSetup> setups;
  setups.resize(triangles.size());
  FrameVector<ClipEdge> clipEdges;
  clipEdges.resize(camera.clipPlanes.empty() ? 0 : triangles.size() * kMaxClipCuts);
  // The ids by slot apart from the setups (a fraction of their size): what a decided pixel's hit
  // reads.
  FrameVector<std::uint32_t> idOfSlot;
  idOfSlot.resize(triangles.size());
  parallelForRows(
      static_cast<int>((triangles.size() + 1023) / 1024), threadCount,
      [&](int blockBegin, int blockEnd) {
        const std::size_t end =
            std::min(triangles.size(), static_cast<std::size_t>(blockEnd) * 1024);
        for (std::size_t k = static_cast<std::size_t>(blockBegin) * 1024; k < end; ++k) {
          idOfSlot[k] = triangles[k].primitiveId;
          setups[k] = setupTriangle(terms, triangles[k],
                                    planes ? &(*planes)[triangles[k].primitiveId] : nullptr,
                                    clipEdges.empty() ? nullptr : &clipEdges[k * kMaxClipCuts]);
        }
      });
  // A triangle that may meet depth clamp's eye box: a ray may hit it where neither the bins nor
  // Delta hold.
  if (std::any_of(setups.begin(), setups.end(), [](const TriangleSetup& t) { return t.nearEye; })) {
    return traceByRays("a triangle passes within the depth-clamped rays' reach of the eye");
  }
  frame.planesById = planes;
  result.rayDeviationNdc = delta;
  result.used = true;
  const bool avx2 = detail::PacketKernels::available();
  parallelForRows(tileRows, threadCount, [&](int tileRowBegin, int tileRowEnd) {
    ScreenEvaluation counts;
    TileState state;
    std::array<Ray, kTile> rayRow;
    for (int tileY = tileRowBegin; tileY < tileRowEnd; ++tileY) {
      const int y0 = tileY * kTile, rows = std::min(kTile, viewport.height - y0);
      for (int tileX = 0; tileX < tileColumns; ++tileX) {
        const int x0 = tileX * kTile, columns = std::min(kTile, viewport.width - x0);
        bool listed = false;
        for (int chunk = 0; chunk < bins.listChunkCount() && !listed; ++chunk) {
          listed = !bins.list(chunk, tileX, tileY).empty();
        }
        // An analytic primitive stays on rays: the pixels of a tile it may cover are traced.
        bool primitive = false;
        for (std::size_t p = 0; p < intersector.analyticCount() && !primitive; ++p) {
          primitive = bins.primitiveMayCover(p, tileX, tileY);
        }
        if (!listed && !primitive) {
          // No triangle can be hit in the tile (a terrain's sky): background, as the loop below
          // would find it pixel by pixel.
          for (int ly = 0; ly < rows; ++ly) {
            std::fill_n(frame.hits.data() + static_cast<std::size_t>(y0 + ly) * viewport.width + x0,
                        columns, Hit{});
          }
          counts.background += static_cast<std::size_t>(rows) * static_cast<std::size_t>(columns);
          continue;
        }
        state.reset();
        const TileWalk walk{&terms,  setups.data(), clipEdges.empty() ? nullptr : clipEdges.data(),
                            &bins,   clipX.data(),  clipY.data(),
                            tileX,   tileY,         rows,
                            columns, &state};
#if defined(__x86_64__) || defined(__i386__)
        if (avx2) {
          walkTileAvx2(walk);
        } else {
          walkTilePortable(walk);
        }
#else
        walkTilePortable(walk);
#endif
        // Each primitive's pixels may be its: traced where the nearest triangle may lie beyond it.
        for (std::size_t p = 0; p < intersector.analyticCount() && primitive; ++p) {
          const FrameBins::PixelBounds& b = bins.primitiveBounds(p);
          for (int ly = std::max(0, b.y0 - y0); ly <= std::min(rows - 1, b.y1 - y0); ++ly) {
            for (int lx = std::max(0, b.x0 - x0); lx <= std::min(columns - 1, b.x1 - x0); ++lx) {
              double& low = state.unsureLow[ly * kTile + lx];
              low = std::min(low, primitiveBoxes[p].keyLow);
            }
          }
        }
        // Decided pixels take their planes where every ray of the tile surely exists.
        const bool tileFromPlanes =
            fromPlanes &&
            (camera.depthClamp || tileRaysExist(nearW, clipX[static_cast<std::size_t>(x0)],
                                                clipX[static_cast<std::size_t>(x0 + columns - 1)],
                                                clipY[static_cast<std::size_t>(y0)],
                                                clipY[static_cast<std::size_t>(y0 + rows - 1)]));
        for (int ly = 0; ly < rows; ++ly) {
          bool raysMade = false;
          for (int lx = 0; lx < columns; ++lx) {
            const int i = ly * kTile + lx;
            if (lx % kLanes == 0 && lx + kLanes <= columns && tileFromPlanes && !depths) {
              // Four pixels at once where each is background or decided from its planes (most
              // of a frame): the scalar decisions below, per lane.
              const std::size_t first =
                  static_cast<std::size_t>(y0 + ly) * viewport.width + x0 + lx;
              if (finishFour(state, i, idOfSlot.data(), frame.hits.data() + first, counts)) {
                lx += kLanes - 1;
                continue;
              }
            }
            const double nearestHigh = state.nearestHigh[i];
            const std::size_t pixel = static_cast<std::size_t>(y0 + ly) * viewport.width + x0 + lx;
            Hit& hit = frame.hits[pixel];
            const bool traceIt =
                state.unsureLow[i] < kInf && mayBeNearest(state.unsureLow[i], nearestHigh);
            if (!traceIt && state.firstLow[i] == kInf) {
              hit = Hit{};
              ++counts.background;
              continue;
            }
            if (!traceIt && tileFromPlanes && !mayBeNearest(state.secondLow[i], nearestHigh)) {
              const TriangleSetup& nearest = setups[static_cast<std::size_t>(state.firstSlot[i])];
              hit = Hit{std::numeric_limits<double>::quiet_NaN(), nearest.primitiveId};
              ++counts.decided;
              if (depths) {
                const double y = clipY[static_cast<std::size_t>(y0 + ly)];
                depths->ndcZ[pixel] = nearest.za * clipX[static_cast<std::size_t>(x0 + lx)] +
                                      (nearest.zb * y + nearest.zc);
                depths->bound[pixel] = nearest.depthError;
              }
              continue;
            }
            if (!raysMade) {
              frame.pixelCentreRays->row(y0 + ly, x0, columns, rayRow.data());
              raysMade = true;
            }
            const Ray& ray = rayRow[static_cast<std::size_t>(lx)];
            if (ray.tMax < 0.0) {  // no ray at this pixel: nothing is hit
              hit = Hit{};
              ++(traceIt ? counts.traced : counts.decided);
              continue;
            }
            if (!traceIt) {
              const bool alone = !mayBeNearest(state.secondLow[i], nearestHigh);
              const TriangleSetup& nearest = setups[static_cast<std::size_t>(state.firstSlot[i])];
              hit = alone ? intersector.intersectOne(nearest.primitiveId, ray)
                          : closestOfListed(walk, lx, ly, intersector, ray);
              if (hit.hit()) {
                ++(alone ? counts.decided : counts.contested);
                if (alone && depths) {
                  // The depth plane as the walk evaluates it (ScreenTriangleSetup.hpp).
                  const double y = clipY[static_cast<std::size_t>(y0 + ly)];
                  depths->ndcZ[pixel] = nearest.za * clipX[static_cast<std::size_t>(x0 + lx)] +
                                        (nearest.zb * y + nearest.zc);
                  depths->bound[pixel] = nearest.depthError;
                }
                continue;
              }
              ++counts.boundMisses;
            }
            hit = intersector.closestHit(ray);
            ++counts.traced;
          }
        }
      }
    }
    const std::lock_guard lock(countsLock);
    result.background += counts.background;
    result.decided += counts.decided;
    result.contested += counts.contested;
    result.traced += counts.traced;
    result.boundMisses += counts.boundMisses;
  });
  return result;
}

}  // namespace clipray
