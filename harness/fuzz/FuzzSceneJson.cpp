// libFuzzer target: scene JSON text. Any input may be rejected with an InputError; anything else
// (a crash, a sanitizer report, another exception, a hang) is a bug in the scene loader.

#include <cstddef>
#include <cstdint>
#include <string>

#include "clipray/InputError.hpp"
#include "clipray/scene/Scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const clipray::Scene scene = clipray::parseScene(text, "fuzz.json");
    (void)scene;
  } catch (const clipray::InputError&) {
    // Rejecting bad input with a message is the expected outcome.
  }
  return 0;
}
