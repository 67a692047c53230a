// libFuzzer target: `clipray check --trace`'s reader of apitrace dump text, line by line through
// the GL state, the matrix analysis of every pair and both report forms. Any input may be
// rejected with an InputError; anything else (a crash, a sanitizer report, another exception, a
// hang) is a bug.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "clipray/InputError.hpp"
#include "clipray/trace/TraceCheck.hpp"

namespace {

// A blob folder as `apitrace dump --blobs` leaves it, holding the 208-byte camera block of the
// no-under-zo-ubo seed (blob_call55.bin), so that inputs naming it reach the uniform-buffer
// reads. One fixed folder, rewritten by every run: libFuzzer ends without running atexit
// handlers, so a folder of its own per run would be left behind each time.
const std::filesystem::path& blobFolder() {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / "clipray-fuzz-trace-blobs";
    std::error_code ignored;
    std::filesystem::create_directories(path, ignored);
    std::vector<float> block(52, 0.0f);
    for (std::size_t k = 0; k < block.size(); ++k) block[k] = 0.25f * static_cast<float>(k);
    std::ofstream(path / "blob_call55.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(block.data()),
               static_cast<std::streamsize>(block.size() * sizeof(float)));
    return path;
  }();
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    clipray::trace::TraceCheckCollector collector("fuzz.trace", {});
    collector.setBlobDirectory(blobFolder());
    std::size_t start = 0;
    while (start <= text.size()) {
      const std::size_t end = std::min(text.find('\n', start), text.size());
      if (!collector.addLine(text.substr(start, end - start))) break;
      start = end + 1;
    }
    const clipray::trace::TraceCheckResult result = collector.finish();
    (void)clipray::trace::traceCheckText(result);
    (void)clipray::trace::traceCheckJson(result).dump();
  } catch (const clipray::InputError&) {
    // Rejecting bad input with a message is the expected outcome.
  }
  return 0;
}
