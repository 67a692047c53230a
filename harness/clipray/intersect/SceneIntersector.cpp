#include "clipray/intersect/SceneIntersector.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <system_error>
#include <thread>

#if defined(__linux__)
#endif

#include "clipray/intersect/FrameBins.hpp"
#include "clipray/intersect/PacketKernels.hpp"
#include "clipray/intersect/PrimitiveKernels.hpp"
#include "clipray/intersect/Primitives.hpp"
#include "clipray/intersect/Watertight.hpp"
#include "clipray/math/Facing.hpp"
#include "clipray/util/HugePages.hpp"

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

SceneIntersector::SceneIntersector(const Scene& scene, const glm::dvec3& reference,
                                   BvhBuild bvhBuild,
                                   const std::optional<glm::dmat4>& drawnClipFromWorld)
    : reference_(reference), primitives_(scene.primitives) {
  const PrimitiveIdTable ids(scene);
  firstAnalyticId_ = ids.firstAnalyticId;
  reserveOnHugePages(triangles_, scene.triangleCount());
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
  triangleIdCount_ = triangles_.size();
  if (drawnClipFromWorld) cullTriangles(scene, *drawnClipFromWorld);
  boxPad_ = extent * 0x1p-30 + std::numeric_limits<double>::min();
  if (!std::isfinite(boxPad_)) boxPad_ = kInf;
  wantsBvh_ = triangles_.size() > kBvhThreshold;
  if (wantsBvh_ && bvhBuild == BvhBuild::Now) ensureBvh();
}

void SceneIntersector::cullTriangles(const Scene& scene, const glm::dmat4& drawnClipFromWorld) {
  const bool anyCulling = std::any_of(scene.objects.begin(), scene.objects.end(),
                                      [](const MeshObject& o) { return o.cull != CullFace::None; });
  if (!anyCulling) return;
  culled_.assign(triangles_.size(), 0);
  std::size_t slot = 0;
  for (const MeshObject& object : scene.objects) {
    for (const glm::u32vec3& tri : object.triangles) {
      // Facing from the world positions in double, as the matrix draws them (GL rounds them to
      // float first: a triangle seen within rounding of edge-on covers almost no pixel).
      const auto clip = [&](std::uint32_t v) {
        return drawnClipFromWorld * glm::dvec4(object.worldPositions[v], 1.0);
      };
      const double orientation = clipOrientation(clip(tri.x), clip(tri.y), clip(tri.z));
      if (!drawnUnderCulling(orientation, object.cull, object.frontFace)) culled_[slot] = 1;
      ++slot;
    }
  }
  if (std::find(culled_.begin(), culled_.end(), 1) == culled_.end()) {
    culled_.clear();
    return;
  }
  allTriangles_ = std::move(triangles_);
  triangles_ = {};
  reserveOnHugePages(triangles_, allTriangles_.size());
  for (std::size_t i = 0; i < allTriangles_.size(); ++i) {
    if (!culled_[i]) triangles_.push_back(allTriangles_[i]);
  }
}

std::array<glm::dvec3, 3> SceneIntersector::worldTriangle(std::uint32_t primitiveId) const {
  const Triangle& tri = triangleOfId(primitiveId);
  return {tri.a + reference_, tri.b + reference_, tri.c + reference_};
}

std::size_t SceneIntersector::memoryBytes() const {
  std::size_t bytes = (triangles_.capacity() + allTriangles_.capacity()) * sizeof(Triangle) +
                      culled_.capacity() + primitives_.capacity() * sizeof(AnalyticPrimitive);
  if (bvhBuilt()) {
    bytes += bvh_->nodes.capacity() * sizeof(Node) + bvh_->triangles.capacity() * sizeof(Triangle);
  }
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

  // Builds the subtree of order_[first, first + count) depth-first into nodes_ and returns the
  // index of its root.
  std::uint32_t build(std::uint32_t first, std::uint32_t count, int depth = 0) {
    const auto index = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
    const Split split = splitNode(first, count, depth, nodes_[index]);
    if (split.leaf) return index;
    build(first, split.firstCount, depth + 1);
    const std::uint32_t second =
        build(first + split.firstCount, count - split.firstCount, depth + 1);
    nodes_[index].first = second;
    return index;
  }

  // How a node was made: a leaf, or an inner node whose first child holds firstCount triangles.
  struct Split {
    bool leaf = true;
    std::uint32_t firstCount = 0;
  };
  // Fills node (bounds; leaf range or split axis) and partitions order_[first, first + count)
  // between the children; an inner node's second-child index is left to the caller.
  Split splitNode(std::uint32_t first, std::uint32_t count, int depth, NodeT& node) {
    Box bounds, centroids;
    for (std::uint32_t i = first; i < first + count; ++i) {
      const PrimRef& ref = refs_[order_[i]];
      bounds.grow(ref.box);
      centroids.grow(ref.centroid);
    }
    for (int k = 0; k < 3; ++k) {
      node.lower[k] = roundedDown(bounds.lower[k] - pad_);
      node.upper[k] = roundedUp(bounds.upper[k] + pad_);
    }
    if (count <= 2) return makeLeaf(node, first, count);

    // Best split over three axes of binned centroids.
    const glm::dvec3 extent = centroids.upper - centroids.lower;
    double bestCost = kInf;
    int bestAxis = -1, bestBin = 0;
    // The bins of all three axes in one pass over the triangles (one read of each reference
    // instead of three; each bin grows in the same order, so the same boxes).
    Box binBoxes[3][kBins];
    std::uint32_t binCounts[3][kBins] = {};
    double binScale[3];
    for (int axis = 0; axis < 3; ++axis) binScale[axis] = kBins * (1.0 - 1e-9) / extent[axis];
    const bool binned[3] = {extent.x > 0.0, extent.y > 0.0, extent.z > 0.0};
    for (std::uint32_t i = first; i < first + count; ++i) {
      const PrimRef& ref = refs_[order_[i]];
      for (int axis = 0; axis < 3; ++axis) {
        if (!binned[axis]) continue;
        const int b = binOf(ref.centroid[axis], centroids.lower[axis], binScale[axis]);
        binBoxes[axis][b].grow(ref.box);
        ++binCounts[axis][b];
      }
    }
    for (int axis = 0; axis < 3; ++axis) {
      if (!binned[axis]) continue;
      const Box* binBox = binBoxes[axis];
      const std::uint32_t* binCount = binCounts[axis];
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
      return makeLeaf(node, first, count);
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
    node.count = 0;
    node.axis = static_cast<std::uint16_t>(axis);
    return {false, half};
  }

 private:
  static int binOf(double c, double lower, double scale) {
    const int b = static_cast<int>((c - lower) * scale);
    return std::clamp(b, 0, kBins - 1);
  }
  static Split makeLeaf(NodeT& node, std::uint32_t first, std::uint32_t count) {
    node.first = first;
    node.count = static_cast<std::uint16_t>(count);
    node.axis = 0;
    return {};
  }

  const std::vector<PrimRef>& refs_;
  std::vector<std::uint32_t>& order_;
  std::vector<NodeT>& nodes_;
  double pad_;
};

// The tree BvhBuilder::build makes, built by several threads: the top levels on the calling
// thread, the subtrees below kParallelDepth by workers into their own node lists, then spliced in
// depth-first order. Each node is decided exactly as in build, from the same triangle range, so
// the nodes and their order are the same as one depth-first build's.
template <typename NodeT>
void buildInParallel(const std::vector<PrimRef>& refs, std::vector<std::uint32_t>& order,
                     std::vector<NodeT>& nodes, double pad) {
  constexpr int kParallelDepth = 3;  // up to 8 subtrees: room to balance uneven halves
  struct TopNode {
    NodeT node{};
    bool leaf = false;
    int firstChild = -1, secondChild = -1;
    int subtree = -1;  // >= 0: built by a worker
  };
  struct Subtree {
    std::uint32_t first, count;
    int depth;
    std::vector<NodeT> nodes;
  };
  std::vector<TopNode> top;
  std::vector<Subtree> subtrees;
  std::vector<NodeT> unused;
  BvhBuilder<NodeT> planner(refs, order, unused, pad);
  const auto plan = [&](auto& self, std::uint32_t first, std::uint32_t count, int depth) -> int {
    const int id = static_cast<int>(top.size());
    top.push_back({});
    if (depth == kParallelDepth) {
      top[id].subtree = static_cast<int>(subtrees.size());
      subtrees.push_back({first, count, depth, {}});
      return id;
    }
    NodeT node{};
    const auto split = planner.splitNode(first, count, depth, node);
    top[id].node = node;
    top[id].leaf = split.leaf;
    if (!split.leaf) {
      const int a = self(self, first, split.firstCount, depth + 1);
      const int b = self(self, first + split.firstCount, count - split.firstCount, depth + 1);
      top[id].firstChild = a;
      top[id].secondChild = b;
    }
    return id;
  };
  plan(plan, 0, static_cast<std::uint32_t>(order.size()), 0);

  // Subtrees touch disjoint ranges of order and only read refs.
  std::atomic<std::size_t> next{0};
  const auto worker = [&] {
    for (std::size_t k; (k = next.fetch_add(1)) < subtrees.size();) {
      Subtree& subtree = subtrees[k];
      subtree.nodes.reserve(subtree.count);
      BvhBuilder<NodeT> builder(refs, order, subtree.nodes, pad);
      builder.build(subtree.first, subtree.count, subtree.depth);
    }
  };
  std::vector<std::thread> threads;
  const unsigned threadCount = std::max(1u, std::thread::hardware_concurrency());
  try {
    for (unsigned k = 1; k < std::min<std::size_t>(threadCount, subtrees.size()); ++k) {
      threads.emplace_back(worker);
    }
  } catch (const std::system_error&) {
    // The system refused a thread: the calling thread builds the rest.
  }
  worker();
  for (std::thread& thread : threads) thread.join();

  const auto emit = [&](auto& self, int id) -> std::uint32_t {
    const auto index = static_cast<std::uint32_t>(nodes.size());
    const TopNode& t = top[id];
    if (t.subtree >= 0) {
      // Its node indices were relative to its root: an inner node's second child moves along.
      for (NodeT node : subtrees[t.subtree].nodes) {
        if (node.count == 0) node.first += index;
        nodes.push_back(node);
      }
      return index;
    }
    nodes.push_back(t.node);
    if (t.leaf) return index;
    self(self, t.firstChild);
    const std::uint32_t second = self(self, t.secondChild);
    nodes[index].first = second;
    return index;
  };
  emit(emit, 0);
}

}  // namespace

void SceneIntersector::buildBvh() const {
  std::vector<PrimRef> refs;
  reserveOnHugePages(refs, triangles_.size());
  refs.resize(triangles_.size());
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
  reserveOnHugePages(bvh_->nodes, triangles_.size());
  buildInParallel(refs, order, bvh_->nodes, boxPad_);
  bvh_->nodes.shrink_to_fit();
  reserveOnHugePages(bvh_->triangles, triangles_.size());
  bvh_->triangles.resize(triangles_.size());
  for (std::size_t i = 0; i < order.size(); ++i) bvh_->triangles[i] = triangles_[order[i]];
  bvh_->built.store(true, std::memory_order_release);
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

void SceneIntersector::testAnalytic(std::size_t p, Ray& bounded, Hit& best) const noexcept {
  bounded.tMax = best.t;
  const double t = intersectPrimitive(primitives_[p], bounded);
  // A miss is +inf, which an infinite bound would let through; a hit is within the bound.
  if (!(t < kInf)) return;
  const auto id = firstAnalyticId_ + static_cast<std::uint32_t>(p);
  if (t < best.t || best.primitiveId == 0 || id < best.primitiveId) {
    best.t = t;
    best.primitiveId = id;
  }
}

void SceneIntersector::closestAnalytic(const Ray& worldRay, Hit& best) const noexcept {
  Ray bounded = worldRay;
  for (std::size_t p = 0; p < primitives_.size(); ++p) testAnalytic(p, bounded, best);
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
  if (primitiveId <= triangleIdCount_) {
    if (culled(primitiveId)) return Hit{};
    const WatertightRay ray(worldRay.origin - reference_, worldRay.direction);
    testTriangle(ray, triangleOfId(primitiveId), best);
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
  if (!wantsBvh_) {
    for (const Triangle& tri : triangles_) testTriangle(ray, tri, best);
    return;
  }
  ensureBvh();
  const std::vector<Node>& nodes = bvh_->nodes;
  const std::vector<Triangle>& bvhTriangles = bvh_->triangles;
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
  if (slab(nodes[0], entry)) stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes[stack[--top]];
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        testTriangle(ray, bvhTriangles[i], best);
      }
      continue;
    }
    const std::uint32_t left = static_cast<std::uint32_t>(&node - nodes.data()) + 1;
    const std::uint32_t right = node.first;
    double entryLeft = 0.0, entryRight = 0.0;
    const bool hitLeft = slab(nodes[left], entryLeft);
    const bool hitRight = slab(nodes[right], entryRight);
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

void SceneIntersector::addAnalyticToTile(const Ray* rays, Hit* hits, std::size_t rowStride,
                                         int width, int height, const FrameBins* bins, int tileX,
                                         int tileY) const noexcept {
  // The few analytic primitives one ray at a time, continuing from the triangles' answer with
  // closestHit's update rule: the same minimum, bit for bit (the rule does not depend on the
  // order, so the primitives go in batches, and those the bins rule out are left out).
  constexpr std::size_t kBatch = 64;
  for (std::size_t first = 0; first < primitives_.size(); first += kBatch) {
    std::uint32_t batch[kBatch];
    std::size_t count = 0;
    for (std::size_t p = first; p < std::min(primitives_.size(), first + kBatch); ++p) {
      if (bins == nullptr || bins->primitiveMayCover(p, tileX, tileY)) {
        batch[count++] = static_cast<std::uint32_t>(p);
      }
    }
    if (count == 0) continue;
    const bool fourAtOnce = detail::primitiveKernelsAvailable();
    const AnalyticPrimitive* batchPrimitives[kBatch];
    std::uint32_t batchIds[kBatch];
    for (std::size_t k = 0; k < count; ++k) {
      batchPrimitives[k] = &primitives_[batch[k]];
      batchIds[k] = firstAnalyticId_ + batch[k];
    }
    for (int y = 0; y < height; ++y) {
      int x = 0;
      if (fourAtOnce) {
        for (; x + 4 <= width; x += 4) {
          const std::size_t i = static_cast<std::size_t>(y) * rowStride + x;
          detail::addPrimitivesToFour(batchPrimitives, batchIds, count, rays + i, hits + i);
        }
      }
      for (; x < width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * rowStride + x;
        if (!finiteRay(rays[i])) continue;  // closestHit answers Hit{}, as the packets did
        Hit best = hits[i];
        if (!best.hit()) best.t = rays[i].tMax;
        Ray bounded = rays[i];
        for (std::size_t k = 0; k < count; ++k) testAnalytic(batch[k], bounded, best);
        if (!best.hit()) best.t = kInf;
        hits[i] = best;
      }
    }
  }
}

bool SceneIntersector::closestHitsTileBinned(const FrameBins& bins, int tileX, int tileY,
                                             const Ray* rays, Hit* hits, std::size_t rowStride,
                                             int width, int height) const noexcept {
  // Any triangle count, none too: the bins need no BVH (a tile that strays builds one for its
  // packets), and their packets check that the rays stay on their pixels, which is what lets the
  // analytic primitives be culled per tile.
  if (!bins.usable() || !packetKernelsAvailable() || width > FrameBins::kTile ||
      height > FrameBins::kTile) {
    closestHitsTile(rays, hits, rowStride, width, height);
    return false;
  }
  const bool binned = detail::PacketKernels::traceBinned(*this, bins, tileX, tileY, rays, hits,
                                                         rowStride, width, height);
  addAnalyticToTile(rays, hits, rowStride, width, height, binned ? &bins : nullptr, tileX, tileY);
  return binned;
}

void SceneIntersector::closestHitsTile(const Ray* rays, Hit* hits, std::size_t rowStride, int width,
                                       int height) const noexcept {
  if (wantsBvh_ && packetKernelsAvailable() && width * height <= int{kMaxPacket}) {
    // Triangles by packets, then the analytic primitives.
    detail::PacketKernels::trace(*this, rays, hits, rowStride, width, height);
    addAnalyticToTile(rays, hits, rowStride, width, height);
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
