// libFuzzer target: one mesh file format, picked by CLIPRAY_FUZZ_PATH (a fake file name such as
// "fuzz.ply" whose extension selects the reader). The same source builds fuzz_gltf, fuzz_glb,
// fuzz_obj and fuzz_ply. Any input may be rejected with an InputError; anything else (a crash, a
// sanitizer report, another exception, a hang, a huge allocation) is a bug in the readers.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "clipray/InputError.hpp"
#include "clipray/scene/MeshFiles.hpp"

#ifndef CLIPRAY_FUZZ_PATH
#error "CLIPRAY_FUZZ_PATH must name a fake mesh file, e.g. \"fuzz.ply\""
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const clipray::MeshFileContents contents = clipray::parseMeshFile(bytes, CLIPRAY_FUZZ_PATH);
    (void)contents;
  } catch (const clipray::InputError&) {
    // Rejecting bad input with a message is the expected outcome.
  }
  return 0;
}
