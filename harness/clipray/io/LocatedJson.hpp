#pragma once
// JSON read with locations (line and column of malformed text, the JSON pointer of an overflowing
// number or a duplicate key), and the pieces of the readers' messages that quote locations and
// values: for the scene loader, the `check` file reader and the report reader.

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace clipray::detail {

using json = nlohmann::json;
using Pointer = json::json_pointer;

// Parses text; throws InputError naming file and where the text is malformed, for a duplicate key,
// a NUL byte and nesting deeper than kMaxJsonDepth (InputFile.hpp).
json parseJson(const std::string& text, const std::string& file);

// The root is written "/" so that messages never show an empty location.
std::string pointerText(const Pointer& pointer);
// text as a JSON string, quoted and escaped.
std::string jsonString(std::string_view text);
// A value as JSON prints it, cut to 80 characters; inf and NaN spelled out.
std::string describe(const json& value);
// x with three significant digits.
std::string shortNumber(double x);
// "a", "b", "c"
std::string quotedList(const std::vector<std::string_view>& names);

}  // namespace clipray::detail
