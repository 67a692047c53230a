#include "clipray/intersect/SceneIntersector.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "clipray/intersect/PacketKernels.hpp"
#include "clipray/intersect/Primitives.hpp"
#include "clipray/intersect/Watertight.hpp"

namespace clipray {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double maxAbs(const glm::dvec3& p) {
  return std::max(std::abs(p.x), std::max(std::abs(p.y), std::abs(p.z)));
}

bool finiteRay(const Ray& ray) {
  const double sum = ray.origin.x + ray.origin.y + ray.origin.z + ray.direction.x +
                     ray.direction.y + ray.direction.z;
  return std::isfinite(sum);
}

}  // namespace

SceneIntersector::SceneIntersector(const Scene& scene, const glm::dvec3& reference)
    : reference_(reference), primitives_(scene.primitives) {
  const PrimitiveIdTable ids(scene);
  firstAnalyticId_ = ids.firstAnalyticId;
  triangles_.reserve(scene.triangleCount());
  double extent = 0.0;
  for (std::size_t k = 0; k < scene.objects.size(); ++k) {
    const MeshObject& object = scene.objects[k];
    for (std::size_t t = 0; t < object.triangles.size(); ++t) {
      const glm::u32vec3 tri = object.triangles[t];
      const Triangle relative{object.worldPositions[tri.x] - reference,
                              object.worldPositions[tri.y] - reference,
                              object.worldPositions[tri.z] - reference,
                              ids.firstIdOfObject[k] + static_cast<std::uint32_t>(t)};
      extent = std::max(
          extent, std::max(maxAbs(relative.a), std::max(maxAbs(relative.b), maxAbs(relative.c))));
      triangles_.push_back(relative);
    }
  }
  // Boxes are padded by far more than the rounding of the slab test and of the watertight test
  // (both are relative to the coordinates' size, at most `extent`): rounding never culls a box
  // holding a triangle that the linear scan would report.
  boxPad_ = extent * 0x1p-30 + std::numeric_limits<double>::min();
  if (!std::isfinite(boxPad_)) boxPad_ = kInf;
  if (triangles_.size() > kBvhThreshold) buildBvh();
  slotOfPrimitive_.assign(triangles_.size(), 0);
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    slotOfPrimitive_[triangles_[i].primitiveId - 1] = static_cast<std::uint32_t>(i);
  }
}

std::array<glm::dvec3, 3> SceneIntersector::worldTriangle(std::uint32_t primitiveId) const {
  const Triangle& tri = triangles_[slotOfPrimitive_[primitiveId - 1]];
  return {tri.a + reference_, tri.b + reference_, tri.c + reference_};
}

std::size_t SceneIntersector::memoryBytes() const {
  std::size_t bytes = triangles_.capacity() * sizeof(Triangle) + nodes_.capacity() * sizeof(Node) +
                      slotOfPrimitive_.capacity() * sizeof(std::uint32_t) +
                      primitives_.capacity() * sizeof(AnalyticPrimitive);
  // Names longer than the small-string buffer live on the heap.
  for (const AnalyticPrimitive& primitive : primitives_) {
    if (primitive.name.capacity() > std::string().capacity())
      bytes += primitive.name.capacity() + 1;
  }
  return bytes;
}

// ---------------------------------------------------------------------------------------------
// Binned SAH build (Wald 2007): 16 bins per axis on triangle centroids, leaves of at most 4
// triangles (2 or fewer always become leaves), object-median fallback when centroids coincide.

namespace {

constexpr int kBins = 16;
constexpr std::uint32_t kMaxLeaf = 4;
// Below this depth SAH splits; deeper, halves (at most 32 more levels for 2^32 triangles), so a
// traversal stack of 128 entries always suffices.
constexpr int kMaxDepth = 64;

struct Box {
  glm::dvec3 lower{kInf};
  glm::dvec3 upper{-kInf};
  void grow(const Box& b) {
    lower = glm::min(lower, b.lower);
    upper = glm::max(upper, b.upper);
  }
  void grow(const glm::dvec3& p) {
    lower = glm::min(lower, p);
    upper = glm::max(upper, p);
  }
  double halfArea() const {
    const glm::dvec3 e = upper - lower;
    return e.x < 0.0 ? 0.0 : e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

struct PrimRef {
  Box box;
  glm::dvec3 centroid;
};

float roundedDown(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float roundedUp(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

template <typename NodeT>
class BvhBuilder {
 public:
  BvhBuilder(const std::vector<PrimRef>& refs, std::vector<std::uint32_t>& order,
             std::vector<NodeT>& nodes, double pad)
      : refs_(refs), order_(order), nodes_(nodes), pad_(pad) {}

  std::uint32_t build(std::uint32_t first, std::uint32_t count, int depth = 0) {
    const auto index = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
    Box bounds, centroids;
    for (std::uint32_t i = first; i < first + count; ++i) {
      const PrimRef& ref = refs_[order_[i]];
      bounds.grow(ref.box);
      centroids.grow(ref.centroid);
    }
    for (int k = 0; k < 3; ++k) {
      nodes_[index].lower[k] = roundedDown(bounds.lower[k] - pad_);
      nodes_[index].upper[k] = roundedUp(bounds.upper[k] + pad_);
    }
    if (count <= 2) return makeLeaf(index, first, count);

    // Best split over three axes of binned centroids.
    const glm::dvec3 extent = centroids.upper - centroids.lower;
    double bestCost = kInf;
    int bestAxis = -1, bestBin = 0;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(extent[axis] > 0.0)) continue;
      const double scale = kBins * (1.0 - 1e-9) / extent[axis];
      Box binBox[kBins];
      std::uint32_t binCount[kBins] = {};
      for (std::uint32_t i = first; i < first + count; ++i) {
        const PrimRef& ref = refs_[order_[i]];
        const int b = binOf(ref.centroid[axis], centroids.lower[axis], scale);
        binBox[b].grow(ref.box);
        ++binCount[b];
      }
      double rightArea[kBins];
      std::uint32_t rightCount[kBins];
      Box right;
      std::uint32_t n = 0;
      for (int b = kBins - 1; b > 0; --b) {
        right.grow(binBox[b]);
        n += binCount[b];
        rightArea[b] = right.halfArea();
        rightCount[b] = n;
      }
      Box left;
      n = 0;
      for (int b = 1; b < kBins; ++b) {
        left.grow(binBox[b - 1]);
        n += binCount[b - 1];
        if (n == 0 || rightCount[b] == 0) continue;
        const double cost = left.halfArea() * n + rightArea[b] * rightCount[b];
        if (cost < bestCost) {
          bestCost = cost;
          bestAxis = axis;
          bestBin = b;
        }
      }
    }
    const double leafCost = static_cast<double>(count);
    const double splitCost = 0.25 + bestCost / std::max(bounds.halfArea(), 1e-300);
    if (count <= kMaxLeaf && (bestAxis < 0 || splitCost >= leafCost)) {
      return makeLeaf(index, first, count);
    }

    std::uint32_t half;
    int axis = bestAxis;
    if (depth > kMaxDepth) bestAxis = -1;  // keeps traversal stacks bounded
    if (bestAxis >= 0) {
      const double scale = kBins * (1.0 - 1e-9) / extent[axis];
      const double lower = centroids.lower[axis];
      const auto middle = std::partition(
          order_.begin() + first, order_.begin() + first + count,
          [&](std::uint32_t r) { return binOf(refs_[r].centroid[axis], lower, scale) < bestBin; });
      half = static_cast<std::uint32_t>(middle - order_.begin()) - first;
    } else {
      // All centroids coincide: split the list in two (keeps leaves small).
      axis = 0;
      half = count / 2;
    }
    build(first, half, depth + 1);
    const std::uint32_t second = build(first + half, count - half, depth + 1);
    nodes_[index].first = second;
    nodes_[index].count = 0;
    nodes_[index].axis = static_cast<std::uint16_t>(axis);
    return index;
  }

 private:
  static int binOf(double c, double lower, double scale) {
    const int b = static_cast<int>((c - lower) * scale);
    return std::clamp(b, 0, kBins - 1);
  }
  std::uint32_t makeLeaf(std::uint32_t index, std::uint32_t first, std::uint32_t count) {
    nodes_[index].first = first;
    nodes_[index].count = static_cast<std::uint16_t>(count);
    nodes_[index].axis = 0;
    return index;
  }

  const std::vector<PrimRef>& refs_;
  std::vector<std::uint32_t>& order_;
  std::vector<NodeT>& nodes_;
  double pad_;
};

}  // namespace

void SceneIntersector::buildBvh() {
  std::vector<PrimRef> refs(triangles_.size());
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    const Triangle& t = triangles_[i];
    Box box;
    box.grow(t.a);
    box.grow(t.b);
    box.grow(t.c);
    refs[i] = {box, (box.lower + box.upper) * 0.5};
  }
  std::vector<std::uint32_t> order(triangles_.size());
  std::iota(order.begin(), order.end(), 0u);
  nodes_.reserve(triangles_.size());
  BvhBuilder<Node> builder(refs, order, nodes_, boxPad_);
  builder.build(0, static_cast<std::uint32_t>(triangles_.size()));
  nodes_.shrink_to_fit();
  std::vector<Triangle> sorted(triangles_.size());
  for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = triangles_[order[i]];
  triangles_ = std::move(sorted);
}

// ---------------------------------------------------------------------------------------------
// One ray at a time.

namespace {
// Keeps the smallest (t, primitive id): the answer does not depend on the visiting order.
template <typename Triangle>
inline void testTriangle(const WatertightRay& ray, const Triangle& tri, Hit& best) {
  const auto t = intersectTriangle(ray, best.t, tri.a, tri.b, tri.c);
  if (!t) return;
  if (*t < best.t || best.primitiveId == 0 || tri.primitiveId < best.primitiveId) {
    best.t = *t;
    best.primitiveId = tri.primitiveId;
  }
}
}  // namespace

void SceneIntersector::closestAnalytic(const Ray& worldRay, Hit& best) const noexcept {
  Ray bounded = worldRay;
  for (std::size_t p = 0; p < primitives_.size(); ++p) {
    bounded.tMax = best.t;
    const double t = intersectPrimitive(primitives_[p], bounded);
    // A miss is +inf, which an infinite bound would let through; a hit is within the bound.
    if (!(t < kInf)) continue;
    const auto id = firstAnalyticId_ + static_cast<std::uint32_t>(p);
    if (t < best.t || best.primitiveId == 0 || id < best.primitiveId) {
      best.t = t;
      best.primitiveId = id;
    }
  }
}

Hit SceneIntersector::closestHitLinear(const Ray& worldRay) const noexcept {
  if (!finiteRay(worldRay)) return Hit{};
  const WatertightRay ray(worldRay.origin - reference_, worldRay.direction);
  Hit best;
  best.t = worldRay.tMax;
  for (const Triangle& tri : triangles_) testTriangle(ray, tri, best);
  closestAnalytic(worldRay, best);
  if (best.primitiveId == 0) best.t = kInf;
  return best;
}

Hit SceneIntersector::closestHit(const Ray& worldRay) const noexcept {
  // A ray function may hand us a non-finite ray (e.g. a near point unprojected at infinity):
  // it hits nothing, rather than producing a NaN "hit" from comparisons that are all false.
  if (!finiteRay(worldRay)) return Hit{};
  Hit best;
  best.t = worldRay.tMax;
  // Analytic primitives first: a hit there shortens the BVH walk (every t is computed before it
  // is compared with the bound, so the visiting order never changes the answer).
  closestAnalytic(worldRay, best);
  closestTriangle(worldRay, best);
  if (best.primitiveId == 0) best.t = kInf;
  return best;
}

Hit SceneIntersector::closestTriangleHit(const Ray& worldRay) const noexcept {
  if (!finiteRay(worldRay)) return Hit{};
  Hit best;
  best.t = worldRay.tMax;
  closestTriangle(worldRay, best);
  if (best.primitiveId == 0) best.t = kInf;
  return best;
}

Hit SceneIntersector::intersectOne(std::uint32_t primitiveId, const Ray& worldRay) const noexcept {
  if (primitiveId == 0 || !finiteRay(worldRay)) return Hit{};
  Hit best;
  best.t = worldRay.tMax;
  if (primitiveId <= triangles_.size()) {
    const WatertightRay ray(worldRay.origin - reference_, worldRay.direction);
    testTriangle(ray, triangles_[slotOfPrimitive_[primitiveId - 1]], best);
  } else if (isAnalytic(primitiveId)) {
    const double t = intersectPrimitive(analyticPrimitive(primitiveId), worldRay);
    if (t < kInf) best = Hit{t, primitiveId};
  }
  if (best.primitiveId == 0) best.t = kInf;
  return best;
}

void SceneIntersector::closestTriangle(const Ray& worldRay, Hit& best) const noexcept {
  const glm::dvec3 origin = worldRay.origin - reference_;
  const WatertightRay ray(origin, worldRay.direction);
  if (nodes_.empty()) {
    for (const Triangle& tri : triangles_) testTriangle(ray, tri, best);
    return;
  }
  // Rays starting far outside the scene get extra padding (rounding grows with |origin|).
  const double extraPad = std::max(0.0, maxAbs(origin) * 0x1p-30 - boxPad_);
  const glm::dvec3 inverseDirection = 1.0 / worldRay.direction;
  // Ize's robust slab test widens the far distance by 2 gamma(3); the relative slack on the
  // current best t keeps a box whose entry rounds just past it.
  auto slab = [&](const Node& node, double& entry) {
    double tNear = 0.0;
    double tFar = best.t * (1.0 + 0x1p-30);
    for (int k = 0; k < 3; ++k) {
      double t0 = (node.lower[k] - extraPad - origin[k]) * inverseDirection[k];
      double t1 = (node.upper[k] + extraPad - origin[k]) * inverseDirection[k];
      if (t0 > t1) std::swap(t0, t1);
      if (std::isnan(t0) || std::isnan(t1)) continue;  // 0 * inf: origin on the slab
      t1 *= 1.0 + 0x1p-40;
      tNear = t0 > tNear ? t0 : tNear;
      tFar = t1 < tFar ? t1 : tFar;
      if (tNear > tFar) return false;
    }
    entry = tNear;
    return true;
  };
  std::uint32_t stack[128];
  int top = 0;
  double entry = 0.0;
  if (slab(nodes_[0], entry)) stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        testTriangle(ray, triangles_[i], best);
      }
      continue;
    }
    const std::uint32_t left = static_cast<std::uint32_t>(&node - nodes_.data()) + 1;
    const std::uint32_t right = node.first;
    double entryLeft = 0.0, entryRight = 0.0;
    const bool hitLeft = slab(nodes_[left], entryLeft);
    const bool hitRight = slab(nodes_[right], entryRight);
    // Visit the nearer child first (pushed last).
    if (hitLeft && hitRight) {
      if (entryLeft <= entryRight) {
        stack[top++] = right;
        stack[top++] = left;
      } else {
        stack[top++] = left;
        stack[top++] = right;
      }
    } else if (hitLeft) {
      stack[top++] = left;
    } else if (hitRight) {
      stack[top++] = right;
    }
  }
}

void SceneIntersector::closestHits(std::span<const Ray> rays, std::span<Hit> hits) const noexcept {
  for (std::size_t begin = 0; begin < rays.size(); begin += kMaxPacket) {
    const auto count = static_cast<int>(std::min(kMaxPacket, rays.size() - begin));
    closestHitsTile(rays.data() + begin, hits.data() + begin, 0, count, 1);
  }
}

void SceneIntersector::closestHitsTile(const Ray* rays, Hit* hits, std::size_t rowStride, int width,
                                       int height) const noexcept {
  if (!nodes_.empty() && packetKernelsAvailable() && width * height <= int{kMaxPacket}) {
    // Triangles by packets, then the few analytic primitives one ray at a time, continuing from
    // the triangles' answer with closestHit's update rule: the same minimum, bit for bit.
    detail::PacketKernels::trace(*this, rays, hits, rowStride, width, height);
    if (primitives_.empty()) return;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * rowStride + x;
        if (!finiteRay(rays[i])) continue;  // closestHit answers Hit{}, as trace did
        Hit best = hits[i];
        if (!best.hit()) best.t = rays[i].tMax;
        closestAnalytic(rays[i], best);
        if (!best.hit()) best.t = kInf;
        hits[i] = best;
      }
    }
    return;
  }
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * rowStride + x;
      hits[i] = closestHit(rays[i]);
    }
  }
}

bool SceneIntersector::packetKernelsAvailable() {
  return detail::PacketKernels::available();
}

}  // namespace clipray
