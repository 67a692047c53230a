// JSON with locations: a SAX parser that knows where it is (nlohmann's DOM parser would keep a
// duplicate key silently and report an overflowing number without its pointer), and the message
// helpers that quote locations and values.

#include "clipray/io/LocatedJson.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "clipray/InputError.hpp"
#include "clipray/io/InputFile.hpp"

namespace clipray::detail {

namespace {

// Values quoted in messages are cut to this many characters.
constexpr std::size_t kMaxQuotedChars = 80;

// The value as dump() prints it, but only its first `limit` characters or a few more: a message
// quotes 80 characters of a value that may hold a whole mesh.
std::string boundedDump(const json& value, std::size_t limit) {
  if (!value.is_structured()) return value.dump();
  std::string text = value.is_array() ? "[" : "{";
  bool first = true;
  for (auto item = value.begin(); item != value.end() && text.size() <= limit; ++item) {
    if (!first) text += ",";
    first = false;
    if (value.is_object()) text += json(item.key()).dump() + ":";
    text += boundedDump(item.value(), limit - std::min(limit, text.size()));
  }
  if (text.size() <= limit) text += value.is_array() ? "]" : "}";
  return text;
}

}  // namespace

// The root is written "/" so that messages never show an empty location.
std::string pointerText(const Pointer& pointer) {
  return pointer.empty() ? std::string("/") : pointer.to_string();
}

std::string jsonString(std::string_view text) {
  return json(std::string(text)).dump();
}

// A value as JSON prints it, cut to kMaxQuotedChars. JSON cannot print inf or NaN (nlohmann writes
// null), so those are spelled out.
std::string describe(const json& value) {
  if (value.is_number_float()) {
    const double x = value.get<double>();
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  }
  std::string text = boundedDump(value, kMaxQuotedChars + 1);
  if (text.size() > kMaxQuotedChars) {
    std::size_t cut = kMaxQuotedChars - 3;
    while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0u) == 0x80u) --cut;  // UTF-8
    text = text.substr(0, cut) + "...";
  }
  return text;
}

std::string shortNumber(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", x);
  return buffer;
}

// "a", "b", "c"
std::string quotedList(const std::vector<std::string_view>& names) {
  std::string list;
  for (std::string_view name : names) {
    if (!list.empty()) list += ", ";
    list += jsonString(name);
  }
  return list;
}

class LocatingSax {
 public:
  LocatingSax(const std::string& file, const std::string& text) : file_(file), text_(text) {}

  json takeResult() { return std::move(root_); }

  bool null() { return store(nullptr); }
  bool boolean(bool value) { return store(value); }
  bool number_integer(json::number_integer_t value) { return store(value); }
  bool number_unsigned(json::number_unsigned_t value) { return store(value); }
  bool number_float(json::number_float_t value, const json::string_t& /*text*/) {
    return store(value);
  }
  bool string(json::string_t& value) { return store(std::move(value)); }
  bool binary(json::binary_t& value) { return store(json::binary(std::move(value))); }

  bool start_object(std::size_t /*elements*/) {
    checkDepth();
    open_.push_back({add(json::object()), {}});
    return true;
  }
  bool key(json::string_t& name) {
    Frame& top = open_.back();
    if (top.node->contains(name)) {
      throw InputError(file_, pointerText(pathOfOpenNode() / name),
                       "duplicate key " + jsonString(name));
    }
    top.key = std::move(name);
    return true;
  }
  bool end_object() {
    open_.pop_back();
    return true;
  }
  bool start_array(std::size_t /*elements*/) {
    checkDepth();
    open_.push_back({add(json::array()), {}});
    return true;
  }
  bool end_array() {
    open_.pop_back();
    return true;
  }

  bool parse_error(std::size_t position, const std::string& lastToken,
                   const json::exception& error) {
    if (error.id == 406) {  // out_of_range.406: a number that overflows double, e.g. 1e999
      throw InputError(file_, pointerText(pathOfNextValue()),
                       "expected a finite number, got " + lastToken);
    }
    // `position` counts the characters read, so the offending one is at index position - 1.
    const std::size_t offset = std::min(position > 0 ? position - 1 : 0, text_.size());
    const std::string_view before(text_.data(), offset);
    const std::size_t line =
        1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
    const std::size_t lastNewline = before.rfind('\n');
    const std::size_t column =
        lastNewline == std::string_view::npos ? offset + 1 : offset - lastNewline;
    throw InputError(file_ + ": line " + std::to_string(line) + ", column " +
                     std::to_string(column) + ": malformed JSON: " + reason(error.what()));
  }

 private:
  struct Frame {
    json* node;       // an array or object still being filled
    std::string key;  // objects: the key of the value being read
  };

  // nlohmann's message without its prefix
  // "[json.exception.parse_error.101] parse error at line L, column C: ".
  static std::string reason(std::string_view what) {
    const std::size_t at = what.find("parse error");
    if (at == std::string_view::npos) return std::string(what);
    const std::size_t colon = what.find(": ", at);
    return std::string(colon == std::string_view::npos ? what : what.substr(colon + 2));
  }

  void checkDepth() const {
    if (open_.size() >= kMaxJsonDepth) {
      throw InputError(file_, pointerText(pathOfNextValue()),
                       "nested deeper than " + std::to_string(kMaxJsonDepth) +
                           " levels; clipray's files need a few");
    }
  }

  bool store(json&& value) {
    add(std::move(value));
    return true;
  }

  // Adds a value to the innermost open container (or makes it the root). Pointers to open
  // containers stay valid: an array only grows while none of its elements is open.
  json* add(json&& value) {
    if (open_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    Frame& top = open_.back();
    if (top.node->is_array()) {
      top.node->push_back(std::move(value));
      return &top.node->back();
    }
    json& slot = (*top.node)[top.key];
    slot = std::move(value);
    return &slot;
  }

  Pointer pathOfOpenNode() const {
    Pointer path;
    for (std::size_t i = 0; i + 1 < open_.size(); ++i) path = childPath(path, open_[i], true);
    return path;
  }
  Pointer pathOfNextValue() const {
    if (open_.empty()) return Pointer();
    return childPath(pathOfOpenNode(), open_.back(), false);
  }
  static Pointer childPath(const Pointer& parent, const Frame& frame, bool childIsOpen) {
    if (frame.node->is_array()) return parent / (frame.node->size() - (childIsOpen ? 1 : 0));
    return parent / frame.key;
  }

  const std::string& file_;
  const std::string& text_;
  json root_;
  std::vector<Frame> open_;
};

json parseJson(const std::string& text, const std::string& file) {
  requireNoNulBytes(text, file);
  LocatingSax sax(file, text);
  if (!json::sax_parse(text, &sax)) {
    throw InputError(file + ": malformed JSON");  // every failing path throws before this
  }
  return sax.takeResult();
}

}  // namespace clipray::detail
