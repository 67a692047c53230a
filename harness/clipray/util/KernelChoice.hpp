#pragma once
// Which code computes the analytic side of a reconcile: the SIMD kernels (AVX2 packets traced
// through the screen bins, rays four pixels per instruction, analytic primitives four rays at a
// time, the compare four pixels at a time, the quantiles' counting pass four values at a time),
// or the portable code they reproduce bit for bit -- one ray and one pixel at a time in double,
// the BVH instead of the screen bins. The kernels are the default wherever the CPU has AVX2 and
// FMA; the portable code is what a CPU without them runs, and choosing it on any CPU shows that a
// reconcile gives the same report and images either way (`clipray reconcile --kernels portable`,
// the kernel sameness tests).
// Process-wide: choose before a reconcile starts, never while one runs.

#include <string>
#include <string_view>

namespace clipray {

enum class KernelChoice { Simd, Portable };

void chooseKernels(KernelChoice choice);
KernelChoice chosenKernels();
// True unless the portable code was chosen (whether the CPU can run the kernels is asked apart).
bool simdKernelsChosen();

std::string_view kernelChoiceName(KernelChoice choice);  // "simd", "portable"

}  // namespace clipray
