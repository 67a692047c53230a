#pragma once
// Reading a call's arguments as the GL state needs them, with a message naming the call and the
// argument where the dump holds something else (GlTraceState, UniformBuffers).

#include <cstdint>
#include <string_view>
#include <vector>

#include "clipray/trace/DumpLine.hpp"

namespace clipray::trace {

// Each throws std::invalid_argument "glFoo: ..." when the argument is missing or not what is
// asked for.
const DumpValue& argument(const DumpCall& call, std::string_view name);
double numberArgument(const DumpCall& call, std::string_view name);
// An integer within [low, high] (GL names, locations, sizes): anything else is refused before a
// conversion that would be undefined.
std::int64_t integerArgument(const DumpCall& call, std::string_view name, double low, double high);
// A GL object name (an unsigned 32-bit integer).
std::uint32_t objectArgument(const DumpCall& call, std::string_view name);
// A size or offset in bytes, or an address as apitrace writes pointers ("0x55efe46b80c0").
std::uint64_t byteArgument(const DumpCall& call, std::string_view name);
// The same for a call's result (glMapBufferRange's address).
std::uint64_t byteValue(const DumpCall& call, std::string_view what, const DumpValue& value);
// The numbers of a list argument (a single number as a list of one).
std::vector<double> numbers(const DumpCall& call, std::string_view name);

}  // namespace clipray::trace
