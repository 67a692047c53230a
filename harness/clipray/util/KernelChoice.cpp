#include "clipray/util/KernelChoice.hpp"

#include <atomic>

namespace clipray {

namespace {

std::atomic<KernelChoice> chosen{KernelChoice::Simd};

}  // namespace

void chooseKernels(KernelChoice choice) {
  chosen.store(choice, std::memory_order_relaxed);
}

KernelChoice chosenKernels() {
  return chosen.load(std::memory_order_relaxed);
}

bool simdKernelsChosen() {
  return chosenKernels() == KernelChoice::Simd;
}

std::string_view kernelChoiceName(KernelChoice choice) {
  return choice == KernelChoice::Simd ? "simd" : "portable";
}

}  // namespace clipray
