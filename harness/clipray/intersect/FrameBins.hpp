#pragma once
// Screen-space bins of a scene's triangles for one camera and viewport: the fast path for a
// frame of primary rays (intersectFrame with a camera). clipFromWorld: column-major,
// p_clip = clipFromWorld * p_world, built for the DepthMode given.
//
// A ray that stays on its pixel centre's line of sight (every point of it projects within
// kRayTolerancePx of the centre) can only hit triangles whose projection covers that neighbourhood.
// So each triangle is projected once per frame (in double, clipped against w >= wClip), and its
// padded pixel bounds are recorded in the 8x8-pixel tiles they touch, with the groups of four
// pixels (half rows) they touch and the smallest clip w the triangle reaches (a depth bound: a
// tile's packet skips a triangle that lies behind each of its current best hits). A
// tile's packet then tests exactly the triangles of its bins instead of walking the BVH. Culling is
// conservative: the padding exceeds kRayTolerancePx by more than the rounding involved, and the hit
// of each tested triangle is the watertight test of Watertight.hpp, so the answer stays
// bit-identical to closestHitLinear.
//
// The packet kernels check every ray of a tile against its pixel centre before trusting the bins
// (a caller's picking function may cast any ray); a tile with a ray that strays, starts behind the
// near plane or whose w can fall below wClip is traced by the BVH instead.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"
#include "clipray/util/FrameBuffers.hpp"

namespace clipray {

class SceneIntersector;

struct BinnedTriangle {
  std::uint32_t slot;       // index into the intersector's triangle storage
  std::uint16_t groupMask;  // bit g: lanes 4g..4g+3 of a full 8x8 tile (row g/2, half g%2)
  // A lower bound of clip w over the part of the triangle a binned ray can hit (w >= wClip),
  // rounded down: a packet whose best hits all have a smaller w cannot be beaten by it.
  float nearestW;
};

class FrameBins {
 public:
  static constexpr int kTile = 8;
  // How far a ray may stray from its pixel centre's line of sight and still use the bins.
  static constexpr double kRayTolerancePx = 0.25;
  // A whole triangle's pixel bounds are padded by kRayTolerancePx + kMarginPx plus a bound on the
  // rounding of its projected corners (computed per triangle). The margin covers the rest: the
  // rounding of the packets' check that a ray stays within kRayTolerancePx (which they keep below
  // kMarginPx / 4) and how far outside the triangle a watertight hit can round.
  static constexpr double kMarginPx = 1.0 / 16.0;
  // A triangle cut by w = wClip: the clipped corners' projection rounds more (an interpolation
  // first), so a generous fixed padding.
  static constexpr double kClippedPaddingPx = 1.0;

  // Bins every triangle of `scene` (threadCount 0: hardware concurrency), clipped at wClip: by
  // default half the near plane's least w over the viewport (the rays start on the near plane),
  // else the given one (depth clamp's rays start at the eye; the caller answers for the part
  // below it). usable() is false when the camera has no near plane in front of it across the
  // viewport and no wClip is given, or the given one is not positive (then nothing is binned).
  FrameBins(const SceneIntersector& scene, const glm::dmat4& clipFromWorld, DepthMode mode,
            Viewport viewport, unsigned threadCount, std::optional<double> wClip = std::nullopt);
  // The near plane's least clip w over the viewport; none when the near plane is not in front of
  // the camera across it.
  static std::optional<double> nearPlaneW(const glm::dmat4& clipFromWorld, DepthMode mode);

  bool usable() const { return usable_; }
  Viewport viewport() const { return viewport_; }
  int tilesAcross() const { return tilesAcross_; }
  // clipFromWorld with the intersector's reference point folded in: applied to (vertex relative
  // to the reference, 1) and to (direction, 0). Column-major (glm).
  const glm::dmat4& clipFromRelative() const { return clipFromRelative_; }
  // The smallest clip w a ray that uses the bins may reach; triangles are clipped against it.
  double wClip() const { return wClip_; }
  // The triangles binned in tile (tileX, tileY) are listChunkCount() lists (one per binning
  // chunk), slots increasing in each.
  int listChunkCount() const { return static_cast<int>(chunks_.size()); }
  std::span<const BinnedTriangle> list(int chunk, int tileX, int tileY) const {
    const Chunk& c = chunks_[static_cast<std::size_t>(chunk)];
    const std::size_t tile = static_cast<std::size_t>(tileY) * tilesAcross_ + tileX;
    return {c.entries.data() + c.offsets[tile], c.offsets[tile + 1] - c.offsets[tile]};
  }
  std::size_t entryCount() const;
  // Whether analytic primitive p (SceneIntersector's order) may be hit by a ray of tile (tileX,
  // tileY) that stays on its pixels: its projection, padded by kPrimitivePaddingPx, touches the
  // tile. Bounded shapes are projected through the corners of their local [-1, 1] box (clipped
  // at w = wClip); a plane may cover any tile.
  bool primitiveMayCover(std::size_t p, int tileX, int tileY) const {
    const PixelBounds& b = primitiveBounds_[p];
    return b.x0 <= tileX * kTile + kTile - 1 && b.x1 >= tileX * kTile &&
           b.y0 <= tileY * kTile + kTile - 1 && b.y1 >= tileY * kTile;
  }
  // Far more than the rounding of a projected corner or of an analytic hit point near a
  // silhouette (primitives are few: a generous padding costs nothing).
  static constexpr double kPrimitivePaddingPx = 2.0;
  // Analytic primitive p's padded pixel bounds (primitiveMayCover's): a ray that stays on its
  // pixel's line of sight hits it only at pixels inside them.
  struct PixelBounds {
    int x0 = 1, x1 = 0, y0 = 1, y1 = 0;  // inclusive; empty when x0 > x1
  };
  const PixelBounds& primitiveBounds(std::size_t p) const { return primitiveBounds_[p]; }

 private:
  struct Chunk {
    // Frame-sized and rebuilt per camera: frame buffers (reused from run to run, not zeroed).
    FrameVector<std::uint32_t> offsets;  // tile -> first entry; tileCount + 1 values
    FrameVector<BinnedTriangle> entries;
  };
  Viewport viewport_;
  int tilesAcross_ = 0, tilesUp_ = 0;
  glm::dmat4 clipFromRelative_{1.0};
  double wClip_ = 0.0;
  bool usable_ = false;
  std::vector<Chunk> chunks_;
  std::vector<PixelBounds> primitiveBounds_;

  // The analytic primitives' padded pixel bounds: the corners of the local box (the square for a
  // disk or quad) in clip space, the points where the box's edges cross w = wClip, and the
  // bounding rectangle of those with w >= wClip, projected. The shape lies in the box, so the
  // part a binned ray can reach (w >= wClip) projects inside.
  void boundPrimitives(const SceneIntersector& scene);
  // The triangles' tile lists, in chunks binned on threadCount threads; false (no chunks) when a
  // chunk's entries would pass its budget or its memory cannot be had.
  bool binTriangles(const SceneIntersector& scene, unsigned threadCount);
};

}  // namespace clipray
