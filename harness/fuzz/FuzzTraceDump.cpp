// libFuzzer target: `clipray check --trace`'s reader of apitrace dump text, line by line through
// the GL state, the matrix analysis of every pair and both report forms. Any input may be
// rejected with an InputError; anything else (a crash, a sanitizer report, another exception, a
// hang) is a bug.

#include <stdlib.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
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
// reads; removed at exit.
const std::filesystem::path& blobFolder() {
  static const std::filesystem::path folder = [] {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "clipray-fuzz-blobs-XXXXXX").string();
    if (!mkdtemp(pattern.data())) return std::filesystem::path();
    std::vector<float> block(52, 0.0f);
    for (std::size_t k = 0; k < block.size(); ++k) block[k] = 0.25f * static_cast<float>(k);
    std::ofstream(std::filesystem::path(pattern) / "blob_call55.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(block.data()),
               static_cast<std::streamsize>(block.size() * sizeof(float)));
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(blobFolder(), ignored);
    });
    return std::filesystem::path(pattern);
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
