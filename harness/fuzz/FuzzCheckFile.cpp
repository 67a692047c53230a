// libFuzzer target: `clipray check` files, through the whole check (the file's fields, the matrix
// and number parsing the command line shares, the analysis and both report forms). Any input may
// be rejected with an InputError; anything else (a crash, a sanitizer report, another exception,
// a hang) is a bug.

#include <cstddef>
#include <cstdint>
#include <string>

#include "clipray/InputError.hpp"
#include "clipray/check/CheckFields.hpp"
#include "clipray/check/ConventionCheck.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const clipray::CheckFields fields = clipray::parseCheckFile(text, "fuzz.json");
    const clipray::CheckInput input = clipray::checkInputFrom(fields, "fuzz.json: ");
    const clipray::CheckReport report = clipray::checkConventions(input);
    (void)clipray::checkReportText(report, input);
    (void)clipray::checkReportJson(report, input).dump();
  } catch (const clipray::InputError&) {
    // Rejecting bad input with a message is the expected outcome.
  }
  return 0;
}
