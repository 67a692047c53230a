// Side-by-side timings of exact primary-ray intersection on a generated terrain (issue 5):
// clipray's packet fast path (closestHits over 8x8 tiles, as intersectFrame runs it), clipray one
// ray at a time (closestHit), clipray brute force (closestHitLinear) on a small scene, and Embree 3
// rtcIntersect1 / rtcIntersect16 (4x4 tiles) on the same rays when the bench was built with it.
// Every timed row runs in the same process, round-robin, and reports the median of --runs runs,
// so the ratios hold even on a busy machine. Then the scaling table: 10k, 100k, 1M triangles at
// 1920x1080 and 3840x2160, each case in a child process so that its peak memory is its own.
//
//   build/release/clipray_intersect_bench                  # table + scaling
//   build/release/clipray_intersect_bench --write-scene /tmp/terrain.json --triangles 100000
//   (then: build/release/clipray reconcile /tmp/terrain.json   for the raster/rays/... split)

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "clipray/compare/Frames.hpp"
#include "clipray/intersect/SceneIntersector.hpp"

#if CLIPRAY_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace clipray {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

double peakRssMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// ---------------------------------------------------------------------------------------------
// Terrain: a fixed-seed heightfield of at least `triangles` triangles over [-50, 50]^2, with
// rolling hills (sines) and value noise from a 64-bit LCG, so it is the same on every platform.

struct Terrain {
  MeshObject mesh;
  int cells = 0;
};

Terrain makeTerrain(std::size_t triangles) {
  Terrain terrain;
  terrain.cells = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(triangles) / 2.0)));
  const int n = terrain.cells + 1;
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  auto random01 = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1p-53;
  };
  std::vector<double> noise(static_cast<std::size_t>(17 * 17));
  for (double& x : noise) x = random01();
  auto noiseAt = [&](double u, double v) {  // bilinear value noise on a 16x16 lattice
    const double fu = u * 16.0, fv = v * 16.0;
    const int i = std::min(15, static_cast<int>(fu)), j = std::min(15, static_cast<int>(fv));
    const double su = fu - i, sv = fv - j;
    auto at = [&](int a, int b) { return noise[static_cast<std::size_t>(b * 17 + a)]; };
    return (at(i, j) * (1 - su) + at(i + 1, j) * su) * (1 - sv) +
           (at(i, j + 1) * (1 - su) + at(i + 1, j + 1) * su) * sv;
  };
  terrain.mesh.name = "terrain";
  terrain.mesh.worldPositions.reserve(static_cast<std::size_t>(n) * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double u = static_cast<double>(i) / terrain.cells;
      const double v = static_cast<double>(j) / terrain.cells;
      const double x = -50.0 + 100.0 * u, z = -50.0 + 100.0 * v;
      const double h = 3.0 * std::sin(x * 0.11) * std::cos(z * 0.07) +
                       1.5 * std::sin(x * 0.31 + 1.0) + 6.0 * noiseAt(u, v) + 0.3 * random01();
      terrain.mesh.worldPositions.emplace_back(x, h, z);
    }
  }
  terrain.mesh.triangles.reserve(static_cast<std::size_t>(terrain.cells) * terrain.cells * 2);
  for (int j = 0; j < terrain.cells; ++j) {
    for (int i = 0; i < terrain.cells; ++i) {
      const auto k = static_cast<std::uint32_t>(j * n + i);
      const auto row = static_cast<std::uint32_t>(n);
      terrain.mesh.triangles.emplace_back(k, k + row, k + 1);
      terrain.mesh.triangles.emplace_back(k + 1, k + row, k + row + 1);
    }
  }
  return terrain;
}

const glm::dvec3 kEye(0.0, 28.0, 62.0);
const glm::dvec3 kTarget(0.0, 0.0, -8.0);
constexpr double kFovY = 55.0, kNear = 0.1, kFar = 1000.0;

PickingCamera terrainCamera(Viewport viewport) {
  Camera camera;
  camera.viewport = viewport;
  PerspectiveProjection projection;
  projection.fovYDegrees = kFovY;
  projection.nearDistance = kNear;
  projection.farDistance = kFar;
  camera.projection = projection;
  camera.viewFromWorld = glm::lookAt(kEye, kTarget, glm::dvec3(0, 1, 0));
  PickingCamera picking;
  picking.mode = kNegativeOneToOne;
  picking.viewport = viewport;
  picking.clipFromWorld = camera.clipFromWorld(picking.mode, viewport);
  return picking;
}

glm::dvec3 nearCentre(const PickingCamera& camera) {
  const glm::dvec4 p =
      glm::inverse(camera.clipFromWorld) * glm::dvec4(0.0, 0.0, camera.mode.nearNdcZ(), 1.0);
  return glm::dvec3(p) / p.w;
}

void writeScene(const std::string& path, const Terrain& terrain, Viewport viewport) {
  std::ofstream out(path);
  char buffer[128];
  out << "{\"version\": 1, \"comment\": \"Generated by clipray_intersect_bench: a fixed-seed "
         "terrain heightfield of "
      << terrain.mesh.triangles.size() << " triangles.\",\n \"cameras\": [{\"name\": \"main\", "
      << "\"viewport\": [" << viewport.width << ", " << viewport.height
      << "], \"view\": {\"eye\": [" << kEye.x << ", " << kEye.y << ", " << kEye.z
      << "], \"target\": [" << kTarget.x << ", " << kTarget.y << ", " << kTarget.z
      << "], \"up\": [0, 1, 0]}, \"projection\": {\"type\": "
      << "\"perspective\", \"fovYDegrees\": " << kFovY << ", \"near\": " << kNear
      << ", \"far\": " << kFar
      << "}}],\n \"objects\": [{\"name\": \"terrain\", \"type\": \"mesh\", "
      << "\"positions\": [";
  bool first = true;
  for (const glm::dvec3& p : terrain.mesh.worldPositions) {
    std::snprintf(buffer, sizeof buffer, "%s%.17g,%.17g,%.17g", first ? "" : ",", p.x, p.y, p.z);
    out << buffer;
    first = false;
  }
  out << "],\n \"indices\": [";
  first = true;
  for (const glm::u32vec3& t : terrain.mesh.triangles) {
    out << (first ? "" : ",") << t.x << ',' << t.y << ',' << t.z;
    first = false;
  }
  out << "]}]}\n";
}

// ---------------------------------------------------------------------------------------------
// Embree 3 on the same rays (float, camera-relative like clipray's double data).

#if CLIPRAY_HAVE_EMBREE
struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  double buildMs = 0.0;
  EmbreeScene(const MeshObject& mesh, const glm::dvec3& reference, unsigned threads) {
    const std::string config = "threads=" + std::to_string(threads);
    device = rtcNewDevice(config.c_str());
    const auto start = Clock::now();
    scene = rtcNewScene(device);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), mesh.worldPositions.size()));
    for (std::size_t i = 0; i < mesh.worldPositions.size(); ++i) {
      const glm::dvec3 p = mesh.worldPositions[i] - reference;
      vertices[3 * i] = static_cast<float>(p.x);
      vertices[3 * i + 1] = static_cast<float>(p.y);
      vertices[3 * i + 2] = static_cast<float>(p.z);
    }
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), mesh.triangles.size()));
    std::memcpy(indices, mesh.triangles.data(), mesh.triangles.size() * 3 * sizeof(unsigned));
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
    buildMs = msSince(start);
  }
  ~EmbreeScene() {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
};

void embreeSingle(const EmbreeScene& es, const AnalyticFrame& frame, const glm::dvec3& reference,
                  std::vector<std::uint32_t>& ids, unsigned threads) {
  const Viewport vp = frame.viewport;
  parallelForRows(vp.height, threads, [&](int y0, int y1) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (std::size_t i = static_cast<std::size_t>(y0) * vp.width;
         i < static_cast<std::size_t>(y1) * vp.width; ++i) {
      const Ray& ray = frame.rays[i];
      const glm::dvec3 o = ray.origin - reference;
      RTCRayHit rh{};
      rh.ray.org_x = static_cast<float>(o.x);
      rh.ray.org_y = static_cast<float>(o.y);
      rh.ray.org_z = static_cast<float>(o.z);
      rh.ray.dir_x = static_cast<float>(ray.direction.x);
      rh.ray.dir_y = static_cast<float>(ray.direction.y);
      rh.ray.dir_z = static_cast<float>(ray.direction.z);
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = static_cast<float>(ray.tMax);
      rh.ray.mask = ~0u;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(es.scene, &context, &rh);
      ids[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? 0 : rh.hit.primID + 1;
    }
  });
}

void embreePackets(const EmbreeScene& es, const AnalyticFrame& frame, const glm::dvec3& reference,
                   std::vector<std::uint32_t>& ids, unsigned threads) {
  const Viewport vp = frame.viewport;
  const int tileRows = (vp.height + 3) / 4;
  parallelForRows(tileRows, threads, [&](int r0, int r1) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[16];
    std::size_t index[16];
    for (int r = r0; r < r1; ++r) {
      for (int x0 = 0; x0 < vp.width; x0 += 4) {
        int n = 0;
        for (int y = r * 4; y < std::min(vp.height, r * 4 + 4); ++y) {
          for (int x = x0; x < std::min(vp.width, x0 + 4); ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * vp.width + x;
            const Ray& ray = frame.rays[i];
            const glm::dvec3 o = ray.origin - reference;
            rh.ray.org_x[n] = static_cast<float>(o.x);
            rh.ray.org_y[n] = static_cast<float>(o.y);
            rh.ray.org_z[n] = static_cast<float>(o.z);
            rh.ray.dir_x[n] = static_cast<float>(ray.direction.x);
            rh.ray.dir_y[n] = static_cast<float>(ray.direction.y);
            rh.ray.dir_z[n] = static_cast<float>(ray.direction.z);
            rh.ray.tnear[n] = 0.0f;
            rh.ray.tfar[n] = static_cast<float>(ray.tMax);
            rh.ray.mask[n] = ~0u;
            rh.ray.flags[n] = 0;
            rh.hit.geomID[n] = RTC_INVALID_GEOMETRY_ID;
            valid[n] = -1;
            index[n] = i;
            ++n;
          }
        }
        for (int k = n; k < 16; ++k) valid[k] = 0;
        rtcIntersect16(valid, es.scene, &context, &rh);
        for (int k = 0; k < n; ++k) {
          ids[index[k]] = rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID ? 0 : rh.hit.primID[k] + 1;
        }
      }
    }
  });
}
#endif

// ---------------------------------------------------------------------------------------------

struct Row {
  std::string name;
  std::size_t triangles;
  Viewport size;
  unsigned threads;
  std::function<void()> run;
  std::vector<double> ms;
};

void sideBySide(std::size_t triangleTarget, Viewport viewport, int runs) {
  const Terrain terrain = makeTerrain(triangleTarget);
  Scene scene;
  scene.objects.push_back(terrain.mesh);
  const Terrain smallTerrain = makeTerrain(1000);
  Scene smallScene;
  smallScene.objects.push_back(smallTerrain.mesh);
  const PickingCamera camera = terrainCamera(viewport);
  const glm::dvec3 reference = nearCentre(camera);
  const Viewport smallViewport{480, 270};
  const PickingCamera smallCamera = terrainCamera(smallViewport);

  auto start = Clock::now();
  const SceneIntersector intersector(scene, reference);
  const double buildMs = msSince(start);
  const SceneIntersector smallIntersector(smallScene, nearCentre(smallCamera));
  AnalyticFrame frame = generateRobustRays(camera, 2);
  AnalyticFrame smallFrame = generateRobustRays(smallCamera, 2);
  const double pixels = static_cast<double>(viewport.width) * viewport.height;
  const double smallPixels = static_cast<double>(smallViewport.width) * smallViewport.height;

  std::vector<Row> rows;
  auto add = [&](std::string name, std::size_t tris, Viewport size, unsigned threads,
                 std::function<void()> run) {
    rows.push_back({std::move(name), tris, size, threads, std::move(run), {}});
  };
  const std::size_t tris = intersector.triangleCount();
  add("rays: generateRobustRays", tris, viewport, 2,
      [&] { frame = generateRobustRays(camera, 2); });
  add("clipray fast path (8x8 packets, AVX2)", tris, viewport, 2,
      [&] { intersectFrame(frame, intersector, 2); });
  add("clipray fast path (8x8 packets, AVX2)", tris, viewport, 1,
      [&] { intersectFrame(frame, intersector, 1); });
  AnalyticFrame single = frame;
  add("clipray closestHit (one ray at a time)", tris, viewport, 2, [&] {
    single.hits.resize(single.rays.size());
    parallelForRows(viewport.height, 2, [&](int y0, int y1) {
      for (std::size_t i = static_cast<std::size_t>(y0) * viewport.width;
           i < static_cast<std::size_t>(y1) * viewport.width; ++i) {
        single.hits[i] = intersector.closestHit(single.rays[i]);
      }
    });
  });
  add("clipray closestHit (one ray at a time)", tris, viewport, 1, [&] {
    single.hits.resize(single.rays.size());
    for (std::size_t i = 0; i < single.rays.size(); ++i) {
      single.hits[i] = intersector.closestHit(single.rays[i]);
    }
  });
  add("clipray brute force (closestHitLinear), small", smallIntersector.triangleCount(),
      smallViewport, 2, [&] {
        smallFrame.hits.resize(smallFrame.rays.size());
        parallelForRows(smallViewport.height, 2, [&](int y0, int y1) {
          for (std::size_t i = static_cast<std::size_t>(y0) * smallViewport.width;
               i < static_cast<std::size_t>(y1) * smallViewport.width; ++i) {
            smallFrame.hits[i] = smallIntersector.closestHitLinear(smallFrame.rays[i]);
          }
        });
      });
  AnalyticFrame smallFast = smallFrame;
  add("clipray fast path, small", smallIntersector.triangleCount(), smallViewport, 2,
      [&] { intersectFrame(smallFast, smallIntersector, 2); });
#if CLIPRAY_HAVE_EMBREE
  const EmbreeScene embree(terrain.mesh, reference, 2);
  std::vector<std::uint32_t> embreeIds1(frame.rays.size()), embreeIds16(frame.rays.size());
  add("Embree 3 rtcIntersect1 (float)", tris, viewport, 2,
      [&] { embreeSingle(embree, frame, reference, embreeIds1, 2); });
  add("Embree 3 rtcIntersect1 (float)", tris, viewport, 1,
      [&] { embreeSingle(embree, frame, reference, embreeIds1, 1); });
  add("Embree 3 rtcIntersect16 (float, 4x4)", tris, viewport, 2,
      [&] { embreePackets(embree, frame, reference, embreeIds16, 2); });
  add("Embree 3 rtcIntersect16 (float, 4x4)", tris, viewport, 1,
      [&] { embreePackets(embree, frame, reference, embreeIds16, 1); });
#endif
  for (Row& row : rows) row.run();  // warm-up
  for (int r = 0; r < runs; ++r) {
    for (Row& row : rows) {
      const auto t0 = Clock::now();
      row.run();
      row.ms.push_back(msSince(t0));
    }
  }

  std::printf("\nSide by side, one process, median of %d round-robin runs (2-core machine):\n",
              runs);
  std::printf("%-48s %9s %10s %7s %10s %9s\n", "method", "triangles", "frame", "threads",
              "ms/frame", "ns/ray");
  for (const Row& row : rows) {
    const double m = median(row.ms);
    const double n = static_cast<double>(row.size.width) * row.size.height;
    char size[32];
    std::snprintf(size, sizeof size, "%dx%d", row.size.width, row.size.height);
    std::printf("%-48s %9zu %10s %7u %10.2f %9.1f\n", row.name.c_str(), row.triangles, size,
                row.threads, m, m * 1e6 / n * row.threads);
  }
  std::printf("(ns/ray is CPU time per ray: ms x threads / rays)\n");
  std::printf("clipray BVH build (binned SAH, double): %.2f ms, %zu nodes, %.1f MiB\n", buildMs,
              intersector.nodeCount(), static_cast<double>(intersector.memoryBytes()) / 1048576.0);
#if CLIPRAY_HAVE_EMBREE
  std::printf("Embree build (2 threads): %.2f ms\n", embree.buildMs);
#endif

  // Agreement: fast path vs closestHit on every ray, vs closestHitLinear on a sample.
  intersectFrame(frame, intersector, 2);
  std::size_t differ = 0, hits = 0;
  for (std::size_t i = 0; i < frame.rays.size(); ++i) {
    const Hit h = intersector.closestHit(frame.rays[i]);
    hits += h.hit();
    differ += h.primitiveId != frame.hits[i].primitiveId || h.t != frame.hits[i].t;
  }
  std::size_t linearDiffer = 0, sampled = 0;
  for (std::size_t i = 0; i < frame.rays.size(); i += frame.rays.size() / 1500 + 1, ++sampled) {
    const Hit h = intersector.closestHitLinear(frame.rays[i]);
    linearDiffer += h.primitiveId != frame.hits[i].primitiveId || h.t != frame.hits[i].t;
  }
  std::size_t smallDiffer = 0;
  for (std::size_t i = 0; i < smallFrame.rays.size(); ++i) {
    smallDiffer += smallFrame.hits[i].primitiveId != smallFast.hits[i].primitiveId ||
                   smallFrame.hits[i].t != smallFast.hits[i].t;
  }
  std::printf(
      "hits: %zu of %.0f pixels; fast path vs closestHit: %zu differ; vs closestHitLinear"
      " on %zu sampled rays: %zu differ; small scene fast vs brute force (%.0f rays): "
      "%zu differ\n",
      hits, pixels, differ, sampled, linearDiffer, smallPixels, smallDiffer);
#if CLIPRAY_HAVE_EMBREE
  std::size_t same1 = 0, same16 = 0;
  for (std::size_t i = 0; i < frame.rays.size(); ++i) {
    same1 += embreeIds1[i] == frame.hits[i].primitiveId;
    same16 += embreeIds16[i] == frame.hits[i].primitiveId;
  }
  std::printf(
      "Embree (float) primitive ids equal to clipray's: rtcIntersect1 %.4f%%, "
      "rtcIntersect16 %.4f%%\n",
      100.0 * static_cast<double>(same1) / pixels, 100.0 * static_cast<double>(same16) / pixels);
#else
  std::printf("Embree: not built (no embree 3 found at configure time)\n");
#endif
  std::printf("peak RSS of this process: %.0f MiB\n", peakRssMiB());
}

// One scaling case, in this (child) process: build, rays, intersect (2 threads), median of runs.
void scalingCase(std::size_t triangleTarget, Viewport viewport, int runs) {
  const Terrain terrain = makeTerrain(triangleTarget);
  Scene scene;
  scene.objects.push_back(terrain.mesh);
  const PickingCamera camera = terrainCamera(viewport);
  std::vector<double> build, rays, intersect;
  std::size_t memory = 0;
  for (int r = 0; r < runs; ++r) {
    auto t0 = Clock::now();
    const SceneIntersector intersector(scene, nearCentre(camera));
    build.push_back(msSince(t0));
    memory = intersector.memoryBytes();
    t0 = Clock::now();
    AnalyticFrame frame = generateRobustRays(camera, 2);
    rays.push_back(msSince(t0));
    t0 = Clock::now();
    intersectFrame(frame, intersector, 2);
    intersect.push_back(msSince(t0));
  }
  std::printf("%9zu %10s %10.1f %9.1f %13.1f %14.1f %10.0f\n", scene.triangleCount(),
              (std::to_string(viewport.width) + "x" + std::to_string(viewport.height)).c_str(),
              median(build), median(rays), median(intersect),
              static_cast<double>(memory) / 1048576.0, peakRssMiB());
  std::fflush(stdout);
}

void scalingTable(int runs) {
  std::printf("\nScaling (terrain, 2 threads, median of %d; each case in its own process):\n",
              runs);
  std::printf("%9s %10s %10s %9s %13s %14s %10s\n", "triangles", "frame", "build ms", "rays ms",
              "intersect ms", "BVH+tris MiB", "peak MiB");
  std::fflush(stdout);
  const std::size_t counts[] = {10000, 100000, 1000000};
  const Viewport sizes[] = {{1920, 1080}, {3840, 2160}};
  for (const Viewport size : sizes) {
    for (const std::size_t count : counts) {
      const pid_t pid = fork();
      if (pid == 0) {
        scalingCase(count, size, runs);
        std::_Exit(0);
      }
      int status = 0;
      waitpid(pid, &status, 0);
    }
  }
}

int main(int argc, char** argv) {
  std::size_t triangles = 100000;
  Viewport size{1920, 1080};
  int runs = 7;
  bool scaling = true, table = true;
  std::string scenePath;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (arg == "--triangles") {
      triangles = std::stoul(next());
    } else if (arg == "--size") {
      const std::string s = next();
      size = {std::stoi(s.substr(0, s.find('x'))), std::stoi(s.substr(s.find('x') + 1))};
    } else if (arg == "--runs") {
      runs = std::stoi(next());
    } else if (arg == "--no-scaling") {
      scaling = false;
    } else if (arg == "--scaling-only") {
      table = false;
    } else if (arg == "--write-scene") {
      scenePath = next();
    } else {
      std::fprintf(stderr,
                   "usage: %s [--triangles N] [--size WxH] [--runs N] [--no-scaling] "
                   "[--scaling-only] [--write-scene FILE]\n",
                   argv[0]);
      return 2;
    }
  }
  if (!scenePath.empty()) {
    writeScene(scenePath, makeTerrain(triangles), size);
    std::printf("wrote %s\n", scenePath.c_str());
    return 0;
  }
  std::printf(
      "clipray intersect bench: terrain heightfield, perspective %.0f deg, AVX2 kernels: %s\n",
      kFovY, SceneIntersector::packetKernelsAvailable() ? "yes" : "no");
  if (table) sideBySide(triangles, size, runs);
  if (scaling) scalingTable(std::max(1, runs / 2));
  return 0;
}

}  // namespace
}  // namespace clipray

int main(int argc, char** argv) {
  return clipray::main(argc, argv);
}
