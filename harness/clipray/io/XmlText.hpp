#pragma once
// Text as XML or HTML character data or attribute values: one escaping for every markup file the
// report writes (JUnit XML, index.html, SVG plots).

#include <string>

namespace clipray {

// &, <, >, " and ' escaped; control characters XML 1.0 forbids (all below 0x20 but tab, newline
// and carriage return) replaced by '?'. Other bytes (UTF-8) pass through.
std::string xmlEscaped(const std::string& text);

}  // namespace clipray
