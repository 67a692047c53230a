#include "clipray/trace/DumpArguments.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

namespace clipray::trace {

const DumpValue& argument(const DumpCall& call, std::string_view name) {
  const DumpValue* value = call.argument(name);
  if (!value) {
    throw std::invalid_argument(call.name + ": no argument \"" + std::string(name) + "\"");
  }
  return *value;
}

double numberArgument(const DumpCall& call, std::string_view name) {
  const DumpValue& value = argument(call, name);
  const auto number = value.number();
  if (!number) {
    throw std::invalid_argument(call.name + ": " + std::string(name) + " = " + value.text +
                                " is not a number");
  }
  return *number;
}

std::int64_t integerArgument(const DumpCall& call, std::string_view name, double low, double high) {
  const double value = numberArgument(call, name);
  if (!(value >= low && value <= high) || value != std::floor(value)) {
    throw std::invalid_argument(call.name + ": " + std::string(name) + " = " +
                                argument(call, name).text + " is not an integer in range");
  }
  return static_cast<std::int64_t>(value);
}

std::uint32_t objectArgument(const DumpCall& call, std::string_view name) {
  return static_cast<std::uint32_t>(integerArgument(call, name, 0.0, 4294967295.0));
}

std::uint64_t byteArgument(const DumpCall& call, std::string_view name) {
  return byteValue(call, name, argument(call, name));
}

std::uint64_t byteValue(const DumpCall& call, std::string_view what, const DumpValue& value) {
  // Pointers are hex; a double would round those above 2^53.
  const std::string& text = value.text;
  std::uint64_t parsed = 0;
  const bool hex = text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X');
  const char* begin = text.data() + (hex ? 2 : 0);
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(begin, end, parsed, hex ? 16 : 10);
  if (value.isList || value.isString || error != std::errc() || stop != end || begin == end) {
    throw std::invalid_argument(call.name + ": " + std::string(what) + " = " + text +
                                " is not a byte count or address");
  }
  return parsed;
}

std::vector<double> numbers(const DumpCall& call, std::string_view name) {
  const DumpValue& value = argument(call, name);
  std::vector<double> result;
  if (!value.isList) {
    if (const auto single = value.number()) result.push_back(*single);
    return result;
  }
  result.reserve(value.items.size());
  for (const DumpValue& item : value.items) {
    const auto number = item.number();
    if (!number) {
      throw std::invalid_argument(call.name + ": " + std::string(name) + " holds " + item.text +
                                  ", not a number");
    }
    result.push_back(*number);
  }
  return result;
}

}  // namespace clipray::trace
