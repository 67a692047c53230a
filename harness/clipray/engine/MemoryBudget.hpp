#pragma once
// How much memory a reconcile may plan for, and what its scenes and runs take: the guard that
// refuses a run before it would exhaust memory, and decides whether scenes stay loaded between
// their runs or are loaded one at a time.

#include <cstdint>
#include <string>

namespace clipray::engine {

// Measured on the 2-core dev machine with /usr/bin/time (max RSS) at 64x48 and at 1080p:
// a run holds ~128 B per pixel (rays, hits, raster frame, comparison) plus up to two earlier
// runs' comparisons waiting for the image encoder, and ~146 B per triangle of its scene (the
// scene, the GL upload, the intersector's bins and BVH, the tolerance model's polygons): terrain
// of 1M and 4M triangles peaked at 314 and 753 MB. A scene kept loaded between its runs holds
// its positions and indices, ~36 B per triangle (24 for a heightfield's shared vertices).
inline constexpr double kRunBytesPerPixel = 210.0;
inline constexpr double kRunBytesPerTriangle = 150.0;
inline constexpr double kLoadedBytesPerTriangle = 36.0;
// A multisampled run holds every sample's analytic pass, comparison and raster beside the first:
// standard.json at 1920x1080 peaked at 210 MB with 1 sample and 536 MB with 4 (llvmpipe), 52 B
// per pixel for each sample past the first; planned with the same margin as a run's.
inline constexpr double kSampleBytesPerPixel = 80.0;
inline constexpr double runBytesPerPixel(int samples) {
  return kRunBytesPerPixel + kSampleBytesPerPixel * (samples > 1 ? samples - 1 : 0);
}

// Bytes this process may use: MemAvailable from /proc/meminfo, or less where a cgroup (a
// container, a CI job) limits the process (memory.max - memory.current). 0 when unknown: then no
// memory check is made.
double availableMemoryBytes();

// What a reconcile may take, and how its messages say where that figure came from.
struct MemoryBudget {
  double bytes = 0.0;  // 0: unknown, no memory check is made
  std::string text;    // "1.50 GiB is available", "--max-memory allows 512.0 MiB"
};
// availableMemoryBytes(), said as "... is available".
MemoryBudget machineMemoryBudget();

// "8G", "512M", "64K" (powers of 1024) or a number of bytes. Throws InputError naming the option.
double parseMemorySize(const std::string& text, const std::string& option);

// "1.50 GiB", "15.7 MiB"
std::string memoryText(double bytes);

}  // namespace clipray::engine
