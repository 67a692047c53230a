// Per-ray cost of every ray method x precision at 1920x1080 on the `standard` hard case (the cost
// does not depend on the camera), rays written row by row into one cache-resident row buffer as a
// tracer consuming them would. One core. Also the per-camera precompute, timed separately.
//   build/release/clipray_ray_benchmarks --benchmark_filter=robust

#include <benchmark/benchmark.h>

#include <string>

#include "clipray/rays/HardCases.hpp"
#include "clipray/rays/RayMethods.hpp"

namespace clipray {
namespace {

constexpr Viewport kSize{1920, 1080};

const HardCase& standardCase() {
  static const HardCase c = hardCases(kSize).front();
  return c;
}

template <typename T>
void rowsOfOneFrame(benchmark::State& state, RayMethod method) {
  const auto generator = makeRayGenerator<T>(method, standardCase().inputs, kSize);
  RayBuffer<T> row(static_cast<std::size_t>(kSize.width));
  const RaySpan<T> span = row.span(0, kSize.width);
  for (auto _ : state) {
    for (int j = 0; j < kSize.height; ++j) {
      generator->generateRow(j, span);
      benchmark::ClobberMemory();
    }
  }
  state.SetItemsProcessed(state.iterations() * kSize.width * kSize.height);
  state.counters["ns_per_ray"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * kSize.width * kSize.height,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.SetLabel(batchCodePath());
}

template <typename T>
void precompute(benchmark::State& state, RayMethod method) {
  for (auto _ : state) {
    auto generator = makeRayGenerator<T>(method, standardCase().inputs, kSize);
    benchmark::DoNotOptimize(generator.get());
  }
}

const bool registered = [] {
  for (const RayMethod method : kRayMethods) {
    const std::string name = rayMethodName(method);
    benchmark::RegisterBenchmark((name + "/float/row_1920x1080").c_str(), [method](
                                                                              benchmark::State& s) {
      rowsOfOneFrame<float>(s, method);
    })->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(
        (name + "/double/row_1920x1080").c_str(),
        [method](benchmark::State& s) { rowsOfOneFrame<double>(s, method); })
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark((name + "/float/precompute").c_str(), [method](
                                                                           benchmark::State& s) {
      precompute<float>(s, method);
    })->Unit(benchmark::kMicrosecond);
  }
  // robust float on each slower batch code path this CPU has, for the side-by-side figure.
  for (const BatchCodePath path : supportedBatchCodePaths()) {
    if (path == supportedBatchCodePaths().back()) continue;  // the default row above
    benchmark::RegisterBenchmark(("robust/float/row_1920x1080/" + batchCodePathName(path)).c_str(),
                                 [path](benchmark::State& s) {
                                   limitBatchCodePath(path);
                                   rowsOfOneFrame<float>(s, RayMethod::Robust);
                                   limitBatchCodePath(std::nullopt);
                                 })
        ->Unit(benchmark::kMillisecond);
  }
  return true;
}();

}  // namespace
}  // namespace clipray

BENCHMARK_MAIN();
