// libFuzzer target: `clipray check --trace`'s reader of apitrace dump text, line by line through
// the GL state, the matrix analysis of every pair and both report forms. Any input may be
// rejected with an InputError; anything else (a crash, a sanitizer report, another exception, a
// hang) is a bug.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "clipray/InputError.hpp"
#include "clipray/trace/TraceCheck.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    clipray::trace::TraceCheckCollector collector("fuzz.trace", {});
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
