// libFuzzer target: command-line option values as a user types them. The first byte picks the
// parser, the rest is the value: viewport sizes, number lists, 16-number matrices in either
// layout, comma lists of conventions and depth formats, and the typo suggester. Any input may be
// rejected with an InputError; anything else is a bug.

#include <cstddef>
#include <cstdint>
#include <string>

#include "clipray/Conventions.hpp"
#include "clipray/InputError.hpp"
#include "clipray/util/OptionValues.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string value(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    switch (data[0] % 6) {
      case 0:
        (void)clipray::parseViewportOption(value, "--size");
        break;
      case 1:
        (void)clipray::parseNumberList(value, "--depth-range");
        break;
      case 2:
      case 3:
        (void)clipray::parseMatrixOption(value, data[0] % 6 == 3, "--clip-from-world");
        break;
      case 4:
        for (const std::string& item : clipray::splitCommaList(value)) {
          (void)clipray::DepthMode::parse(item);
          (void)clipray::parseDepthFormat(item);
        }
        break;
      default:
        (void)clipray::closestName(value, {"reconcile", "check", "bench"});
    }
  } catch (const clipray::InputError&) {
    // Rejecting bad input with a message is the expected outcome.
  }
  return 0;
}
