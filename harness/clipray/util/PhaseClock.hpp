#pragma once
// Times one phase of a run two ways: wall time, and the CPU time the whole process spent in it
// (every thread's: the GL driver's own threads in the raster pass, clipray's workers in its
// passes). CPU time over wall time is how many cores a phase kept busy, so the two together tell
// whether a ratio of wall times comes from the work done or from how well it was spread.

#include <chrono>
#include <ctime>

namespace clipray {

class PhaseClock {
 public:
  PhaseClock() : wallStart_(std::chrono::steady_clock::now()), cpuStart_(std::clock()) {}

  double wallMilliseconds() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wallStart_)
        .count();
  }
  // The process's CPU time since the start (std::clock: all threads on POSIX systems).
  double cpuMilliseconds() const {
    return 1000.0 * static_cast<double>(std::clock() - cpuStart_) / CLOCKS_PER_SEC;
  }

 private:
  std::chrono::steady_clock::time_point wallStart_;
  std::clock_t cpuStart_;
};

}  // namespace clipray
