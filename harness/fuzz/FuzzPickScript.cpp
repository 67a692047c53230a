// libFuzzer target: clipray-pick's --script files. Any input may be rejected with an InputError;
// anything else (a crash, a sanitizer report, another exception, a hang) is a bug in the parser.

#include <cstddef>
#include <cstdint>
#include <string>

#include "PickScript.hpp"
#include "clipray/InputError.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)clipray::demo::parseScript(text, "fuzz.script");
  } catch (const clipray::InputError&) {
    // Rejecting bad input with a message is the expected outcome.
  }
  return 0;
}
