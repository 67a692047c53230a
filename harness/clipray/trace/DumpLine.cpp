// The grammar follows apitrace/apitrace lib/trace/trace_dump.cpp (Dumper::visit for each value
// kind) and lib/trace/trace_dump_internal.hpp (visitString's escapes).

#include "clipray/trace/DumpLine.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace clipray::trace {

namespace {

class LineParser {
 public:
  explicit LineParser(std::string_view line) : line_(line) {}

  DumpCall call() {
    DumpCall parsed;
    const auto head = dumpCallHead(line_);
    if (!head) fail("not a call line");
    parsed.number = head->first;
    parsed.name = std::string(head->second);
    position_ = static_cast<std::size_t>(head->second.data() - line_.data()) + head->second.size();
    expect('(');
    if (!consume(')')) {
      while (true) {
        std::string argumentName = nameBefore(" = ");
        position_ += 3;
        parsed.arguments.emplace_back(std::move(argumentName), value());
        if (consume(')')) break;
        expect(',');
        expect(' ');
      }
    }
    if (line_.substr(position_, 3) == " = ") {
      position_ += 3;
      parsed.result = value();
    }
    // What may follow: " // fake", " // incomplete" (apitrace's call flags), nothing else.
    if (position_ < line_.size() && line_.substr(position_, 4) != " // ") fail("unexpected text");
    return parsed;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument("column " + std::to_string(position_ + 1) + ": " + what);
  }

  bool consume(char c) {
    if (position_ < line_.size() && line_[position_] == c) {
      ++position_;
      return true;
    }
    return false;
  }

  void expect(char c) {
    if (!consume(c)) fail(std::string("expected '") + c + "'");
  }

  std::string nameBefore(std::string_view separator) {
    const std::size_t end = line_.find(separator, position_);
    if (end == std::string_view::npos) fail("expected an argument name");
    std::string name(line_.substr(position_, end - position_));
    position_ = end;
    return name;
  }

  DumpValue value() {
    if (position_ >= line_.size()) fail("expected a value");
    const char c = line_[position_];
    if (c == '&') {
      ++position_;  // a one-element array, written as its element
      return value();
    }
    if (c == '"') return string();
    if (c == 'L' && position_ + 1 < line_.size() && line_[position_ + 1] == '"') {
      ++position_;
      return string();
    }
    if (c == '{') return list();
    return scalar();
  }

  DumpValue string() {
    expect('"');
    DumpValue parsed;
    parsed.isString = true;
    while (true) {
      if (position_ >= line_.size()) fail("unterminated string");
      const char c = line_[position_++];
      if (c == '"') break;
      if (c != '\\') {
        parsed.text += c;
        continue;
      }
      if (position_ >= line_.size()) fail("unterminated string");
      const char escaped = line_[position_++];
      switch (escaped) {
        case 'n':
          parsed.text += '\n';
          break;
        case 'r':
          parsed.text += '\r';
          break;
        case 't':
          parsed.text += '\t';
          break;
        default:
          if (escaped >= '0' && escaped <= '7') {  // octal, up to three digits
            int code = escaped - '0';
            for (int k = 0; k < 2 && position_ < line_.size() && line_[position_] >= '0' &&
                            line_[position_] <= '7';
                 ++k) {
              code = code * 8 + (line_[position_++] - '0');
            }
            parsed.text += static_cast<char>(code);
          } else {
            parsed.text += escaped;  // \" \\ and anything else: the character itself
          }
      }
    }
    return parsed;
  }

  DumpValue list() {
    expect('{');
    // apitrace nests a few levels (arrays of structs); far deeper is no dump line.
    if (++depth_ > kMaxNesting) fail("values nested deeper than " + std::to_string(kMaxNesting));
    DumpValue parsed;
    parsed.isList = true;
    if (consume('}')) {
      --depth_;
      return parsed;
    }
    while (true) {
      DumpValue item = value();
      // A struct member is "name = value": keep the value.
      if (!item.isList && !item.isString && line_.substr(position_, 3) == " = ") {
        position_ += 3;
        item = value();
      }
      parsed.items.push_back(std::move(item));
      if (consume('}')) {
        --depth_;
        break;
      }
      expect(',');
      expect(' ');
    }
    return parsed;
  }

  // A number, a name, a bitmask "A | B", "blob(36)", "NULL": up to the next ',', ')' or '}' at
  // depth 0, or " = " (a struct member's name).
  DumpValue scalar() {
    const std::size_t start = position_;
    int depth = 0;
    while (position_ < line_.size()) {
      const char c = line_[position_];
      if (c == '(') ++depth;
      if (c == ')' && depth-- == 0) break;
      if (depth == 0 && (c == ',' || c == '}')) break;
      if (depth == 0 && line_.substr(position_, 3) == " = ") break;
      if (depth == 0 && line_.substr(position_, 4) == " // ") break;
      ++position_;
    }
    if (position_ == start) fail("expected a value");
    DumpValue parsed;
    parsed.text = std::string(line_.substr(start, position_ - start));
    return parsed;
  }

  static constexpr int kMaxNesting = 32;
  std::string_view line_;
  std::size_t position_ = 0;
  int depth_ = 0;
};

}  // namespace

std::optional<double> DumpValue::number() const {
  if (isList || isString || text.empty()) return std::nullopt;
  const char first = text[0];
  if (!(std::isdigit(static_cast<unsigned char>(first)) || first == '-' || first == '+' ||
        first == '.')) {
    // apitrace writes non-finite floats as std::ostream does: "inf", "-inf", "nan".
    if (text == "inf") return HUGE_VAL;
    if (text == "nan") return std::nan("");
    return std::nullopt;
  }
  if (text == "-inf") return -HUGE_VAL;
  if (text == "-nan") return std::nan("");
  if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
    unsigned long long value = 0;
    const auto [end, error] =
        std::from_chars(text.data() + 2, text.data() + text.size(), value, 16);
    if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return static_cast<double>(value);
  }
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

const DumpValue* DumpCall::argument(std::string_view argumentName) const {
  for (const auto& [argumentKey, value] : arguments) {
    if (argumentKey == argumentName) return &value;
  }
  return nullptr;
}

std::optional<std::pair<std::uint64_t, std::string_view>> dumpCallHead(std::string_view line) {
  std::size_t position = 0;
  while (position < line.size() && std::isdigit(static_cast<unsigned char>(line[position]))) {
    ++position;
  }
  if (position == 0 || position >= line.size() || line[position] != ' ') return std::nullopt;
  std::uint64_t number = 0;
  if (std::from_chars(line.data(), line.data() + position, number).ec != std::errc()) {
    return std::nullopt;
  }
  ++position;
  // "@7f12 " thread ids only with --thread-ids, which clipray does not pass.
  const std::size_t nameEnd = line.find('(', position);
  if (nameEnd == std::string_view::npos || nameEnd == position) return std::nullopt;
  return std::make_pair(number, line.substr(position, nameEnd - position));
}

namespace {

// apitrace's Dumper::visit(Blob*) (lib/trace/trace_dump.cpp) names the files "blob_call%u.bin".
bool isBlobFileName(std::string_view name) {
  constexpr std::string_view prefix = "blob_call", suffix = ".bin";
  if (!name.starts_with(prefix) || !name.ends_with(suffix)) return false;
  const std::string_view digits =
      name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  return !digits.empty() && digits.size() <= 20 &&
         std::all_of(digits.begin(), digits.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
}

}  // namespace

std::optional<std::string> blobFileName(const DumpValue& value) {
  std::string_view text = value.text;
  if (value.isList || value.isString || !text.starts_with("blob(\"") || !text.ends_with("\")")) {
    return std::nullopt;
  }
  text = text.substr(6, text.size() - 8);
  if (!isBlobFileName(text)) return std::nullopt;
  return std::string(text);
}

std::vector<std::string> blobFileNames(std::string_view line) {
  std::vector<std::string> names;
  std::size_t at = 0;
  while ((at = line.find("blob(\"", at)) != std::string_view::npos) {
    at += 6;
    const std::size_t end = line.find('"', at);
    if (end == std::string_view::npos) break;
    const std::string_view name = line.substr(at, end - at);
    if (isBlobFileName(name)) names.emplace_back(name);
    at = end;
  }
  return names;
}

DumpCall parseDumpCall(std::string_view line) {
  return LineParser(line).call();
}

}  // namespace clipray::trace
