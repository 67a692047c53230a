#pragma once
// Reading what `--version` prints ("<tool> 0.1.0 (git 0123456789ab[-dirty])\n", the part in
// parentheses only in a git checkout), and checking text against a character template, without
// std::regex (GCC 12 warns inside <regex> at some optimisation levels, and warnings are errors).

#include <cctype>
#include <optional>
#include <string>
#include <utility>

namespace clipray::testing {

// Each character of `shape` matches: '9' any digit, 'f' any lower-case hex digit, anything else
// itself.
inline bool hasShape(const std::string& text, const std::string& shape) {
  if (text.size() != shape.size()) return false;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const auto c = static_cast<unsigned char>(text[k]);
    const bool ok = shape[k] == '9'   ? std::isdigit(c) != 0
                    : shape[k] == 'f' ? (std::isdigit(c) != 0 || (c >= 'a' && c <= 'f'))
                                      : text[k] == shape[k];
    if (!ok) return false;
  }
  return true;
}

// {version number, git commit ("" when none)} of a --version line, or nullopt if it is not one.
inline std::optional<std::pair<std::string, std::string>> parseVersionLine(
    const std::string& out, const std::string& tool) {
  const std::string prefix = tool + " ";
  if (out.rfind(prefix, 0) != 0 || out.empty() || out.back() != '\n') return std::nullopt;
  const std::string rest = out.substr(prefix.size(), out.size() - prefix.size() - 1);
  const std::size_t space = rest.find(' ');
  const std::string number = rest.substr(0, space);
  int dots = 0;
  for (const char c : number) {
    if (c == '.') {
      ++dots;
    } else if (std::isdigit(static_cast<unsigned char>(c)) == 0) {
      return std::nullopt;
    }
  }
  if (dots != 2 || number.front() == '.' || number.back() == '.') return std::nullopt;
  if (space == std::string::npos) return std::make_pair(number, std::string());
  const std::string git = rest.substr(space);
  for (const std::string& shape :
       {std::string(" (git ffffffffffff)"), std::string(" (git ffffffffffff-dirty)")}) {
    if (hasShape(git, shape)) return std::make_pair(number, git.substr(6, git.size() - 7));
  }
  return std::nullopt;
}

}  // namespace clipray::testing
