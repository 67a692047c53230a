// GLSL is read as tokens, not parsed: a uniform block is `[layout(...)] [qualifiers] uniform Name
// { members } [instance];` at the top level of a source, and that shape is all this file needs.
// The std140 rules are those of the OpenGL 4.6 core specification, section 7.6.2.2, rules 1-8
// (scalars, vectors, arrays, column- and row-major matrices); structures (rule 9) stop the
// offsets, since their members' types would have to be followed too.

#include "clipray/trace/Std140Layout.hpp"

#include <cctype>
#include <charconv>

namespace clipray::trace {

namespace {

// The source without comments and preprocessor lines, which could otherwise hide or fake a block.
std::string withoutCommentsAndDirectives(std::string_view source) {
  std::string text;
  text.reserve(source.size());
  bool lineStart = true;
  for (std::size_t k = 0; k < source.size(); ++k) {
    const char c = source[k];
    if (c == '/' && k + 1 < source.size() && source[k + 1] == '/') {
      while (k < source.size() && source[k] != '\n') ++k;
      text += '\n';
      lineStart = true;
      continue;
    }
    if (c == '/' && k + 1 < source.size() && source[k + 1] == '*') {
      const std::size_t end = source.find("*/", k + 2);
      k = end == std::string_view::npos ? source.size() : end + 1;
      text += ' ';
      continue;
    }
    if (lineStart && c == '#') {
      // A directive runs to the end of the line, continued by a backslash before the newline.
      while (k < source.size() && !(source[k] == '\n' && source[k - 1] != '\\')) ++k;
      text += '\n';
      continue;
    }
    if (c == '\n') {
      lineStart = true;
    } else if (!std::isspace(static_cast<unsigned char>(c))) {
      lineStart = false;
    }
    text += c;
  }
  return text;
}

// Identifiers and numbers as one token each, any other non-space character as its own token.
std::vector<std::string> tokens(std::string_view text) {
  std::vector<std::string> result;
  std::size_t k = 0;
  const auto isWord = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  };
  while (k < text.size()) {
    const char c = text[k];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++k;
    } else if (isWord(c)) {
      const std::size_t start = k;
      while (k < text.size() && isWord(text[k])) ++k;
      result.emplace_back(text.substr(start, k - start));
    } else {
      result.emplace_back(1, c);
      ++k;
    }
  }
  return result;
}

std::optional<std::uint32_t> unsignedNumber(std::string_view token) {
  std::uint32_t value = 0;
  std::string_view digits = token;
  if (digits.ends_with('u') || digits.ends_with('U')) digits.remove_suffix(1);
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error != std::errc() || end != digits.data() + digits.size() || digits.empty()) {
    return std::nullopt;
  }
  return value;
}

bool isIdentifier(const std::string& token) {
  return !token.empty() && (std::isalpha(static_cast<unsigned char>(token[0])) || token[0] == '_');
}

// The qualifiers of one `layout(...)`: "std140", "row_major", "binding" (with its value).
struct LayoutQualifiers {
  std::optional<BlockLayout> layout;
  std::optional<bool> rowMajor;
  std::optional<std::uint32_t> binding;
  bool explicitOffset = false;  // offset = N / align = N (enhanced layouts): not followed
};

class BlockReader {
 public:
  explicit BlockReader(std::vector<std::string> tokens) : tokens_(std::move(tokens)) {}

  std::vector<UniformBlockDeclaration> read() {
    std::vector<UniformBlockDeclaration> blocks;
    while (position_ < tokens_.size()) readStatement(blocks);
    return blocks;
  }

 private:
  const std::string& peek(std::size_t ahead = 0) const {
    static const std::string end;
    return position_ + ahead < tokens_.size() ? tokens_[position_ + ahead] : end;
  }

  // `layout ( a, b = 3, ... )` after the word `layout`; the position moves past ')'.
  LayoutQualifiers readLayout() {
    LayoutQualifiers qualifiers;
    if (peek() != "(") return qualifiers;
    ++position_;
    while (position_ < tokens_.size() && peek() != ")") {
      const std::string name = peek();
      ++position_;
      std::optional<std::uint32_t> value;
      if (peek() == "=") {
        ++position_;
        value = unsignedNumber(peek());
        ++position_;
      }
      if (name == "std140") qualifiers.layout = BlockLayout::kStd140;
      if (name == "std430") qualifiers.layout = BlockLayout::kStd430;
      if (name == "shared") qualifiers.layout = BlockLayout::kShared;
      if (name == "packed") qualifiers.layout = BlockLayout::kPacked;
      if (name == "row_major") qualifiers.rowMajor = true;
      if (name == "column_major") qualifiers.rowMajor = false;
      if (name == "binding") qualifiers.binding = value;
      if (name == "offset" || name == "align") qualifiers.explicitOffset = true;
      if (peek() == ",") ++position_;
    }
    if (position_ < tokens_.size()) ++position_;  // ')'
    return qualifiers;
  }

  // Moves past the current statement: up to a ';' at brace depth 0, or past the '}' that closes
  // a function body.
  void skipStatement() {
    int depth = 0;
    while (position_ < tokens_.size()) {
      const std::string& token = tokens_[position_++];
      if (token == "{") ++depth;
      if (token == "}" && --depth <= 0) return;
      if (token == ";" && depth == 0) return;
    }
  }

  void readStatement(std::vector<UniformBlockDeclaration>& blocks) {
    LayoutQualifiers qualifiers;
    bool uniform = false;
    // Qualifiers before the block name: layout(...), uniform, and any storage / precision word.
    while (position_ < tokens_.size()) {
      if (peek() == "layout") {
        ++position_;
        const LayoutQualifiers more = readLayout();
        if (more.layout) qualifiers.layout = more.layout;
        if (more.rowMajor) qualifiers.rowMajor = more.rowMajor;
        if (more.binding) qualifiers.binding = more.binding;
        qualifiers.explicitOffset = qualifiers.explicitOffset || more.explicitOffset;
      } else if (peek() == "uniform") {
        uniform = true;
        ++position_;
      } else if (peek() == "highp" || peek() == "mediump" || peek() == "lowp" ||
                 peek() == "coherent" || peek() == "volatile" || peek() == "restrict" ||
                 peek() == "readonly" || peek() == "writeonly") {
        ++position_;
      } else {
        break;
      }
    }
    if (uniform && peek() == ";") {
      // `layout(std140, row_major) uniform;`: the default of every later block.
      if (qualifiers.layout) defaultLayout_ = *qualifiers.layout;
      if (qualifiers.rowMajor) defaultRowMajor_ = *qualifiers.rowMajor;
      ++position_;
      return;
    }
    if (!uniform || !isIdentifier(peek()) || peek(1) != "{") {
      skipStatement();
      return;
    }
    UniformBlockDeclaration block;
    block.blockName = peek();
    block.binding = qualifiers.binding;
    block.layout = qualifiers.layout.value_or(defaultLayout_);
    const bool blockRowMajor = qualifiers.rowMajor.value_or(defaultRowMajor_);
    position_ += 2;
    unknownExtent_.clear();
    offsetQualified_.clear();
    if (!readMembers(block, blockRowMajor)) {
      skipStatement();
      return;
    }
    if (isIdentifier(peek())) {
      block.instanceName = peek();
      ++position_;
    }
    if (peek() != ";") {
      // An array of blocks (`} lights[4];`): one binding per element, not followed.
      skipStatement();
      return;
    }
    ++position_;
    if (block.layout == BlockLayout::kStd140) placeStd140(block);
    blocks.push_back(std::move(block));
  }

  // The members up to and past the closing '}'; false when the text is no block after all.
  bool readMembers(UniformBlockDeclaration& block, bool blockRowMajor) {
    while (position_ < tokens_.size() && peek() != "}") {
      std::optional<bool> rowMajor;
      bool explicitOffset = false;
      while (peek() == "layout" || peek() == "highp" || peek() == "mediump" || peek() == "lowp" ||
             peek() == "precise" || peek() == "invariant") {
        if (peek() == "layout") {
          ++position_;
          const LayoutQualifiers member = readLayout();
          if (member.rowMajor) rowMajor = member.rowMajor;
          explicitOffset = explicitOffset || member.explicitOffset;
        } else {
          ++position_;
        }
      }
      if (!isIdentifier(peek())) return false;
      const std::string type = peek() == "mat4x4" ? "mat4" : peek();
      ++position_;
      // One or more declarators: name [N], name [N], ...;
      while (true) {
        if (!isIdentifier(peek())) return false;
        BlockMember member;
        member.name = peek();
        member.type = type;
        member.rowMajor = rowMajor.value_or(blockRowMajor);
        ++position_;
        if (peek() == "[" && peek(1) == "]") {
          unknownExtent_.push_back(member.name);  // unsized: the size of the buffer range
          position_ += 2;
        } else if (peek() == "[") {
          const auto size = unsignedNumber(peek(1));
          if (peek(2) != "]") return false;
          // An array sized by a macro or constant: its extent is unknown here.
          member.arraySize = size && *size > 0 ? *size : 0;
          if (!size || *size == 0) {
            unknownExtent_.push_back(member.name);
          }
          position_ += 3;
        }
        if (explicitOffset) offsetQualified_.push_back(member.name);
        block.members.push_back(std::move(member));
        if (peek() == ",") {
          ++position_;
          continue;
        }
        if (peek() != ";") return false;
        ++position_;
        break;
      }
    }
    if (peek() != "}") return false;
    ++position_;
    return true;
  }

  struct Placement {
    std::uint64_t alignment = 0, size = 0, arrayStride = 0, matrixStride = 0;
  };
  // Far above GL_MAX_UNIFORM_BLOCK_SIZE anywhere (64 KiB on common drivers), and small enough
  // that no offset arithmetic here can overflow.
  static constexpr std::uint64_t kMaxBlockBytes = 1u << 30;

  // Rules 1-8 of std140 for one member; nullopt for a type they do not cover here.
  static std::optional<Placement> std140Placement(const BlockMember& member) {
    const std::string& type = member.type;
    std::uint32_t components = 0;  // of a scalar or vector
    std::uint32_t columns = 0, rows = 0;
    if (type == "float" || type == "int" || type == "uint" || type == "bool") {
      components = 1;
    } else if (type.size() == 4 && type.starts_with("vec") && type[3] >= '2' && type[3] <= '4') {
      components = static_cast<std::uint32_t>(type[3] - '0');
    } else if (type.size() == 5 && (type[0] == 'i' || type[0] == 'u' || type[0] == 'b') &&
               type.substr(1, 3) == "vec" && type[4] >= '2' && type[4] <= '4') {
      components = static_cast<std::uint32_t>(type[4] - '0');
    } else if (type.size() == 4 && type.starts_with("mat") && type[3] >= '2' && type[3] <= '4') {
      columns = rows = static_cast<std::uint32_t>(type[3] - '0');
    } else if (type.size() == 6 && type.starts_with("mat") && type[4] == 'x' && type[3] >= '2' &&
               type[3] <= '4' && type[5] >= '2' && type[5] <= '4') {
      columns = static_cast<std::uint32_t>(type[3] - '0');
      rows = static_cast<std::uint32_t>(type[5] - '0');
    } else {
      return std::nullopt;  // double types, structures, opaque types
    }
    const std::uint64_t count = member.arraySize == 0 ? 1 : member.arraySize;
    Placement placement;
    if (components > 0) {
      const std::uint64_t size = 4 * components;
      if (member.arraySize == 0) {
        // Rules 1-3: a scalar aligns to 4, a vec2 to 8, a vec3 and vec4 to 16.
        placement.alignment = components == 1 ? 4 : components == 2 ? 8 : 16;
        placement.size = size;
      } else {
        // Rule 4: array elements are rounded up to a vec4.
        placement.alignment = 16;
        placement.arrayStride = 16;
        placement.size = 16 * count;
      }
      return placement;
    }
    // Rules 5-8: a column-major matrix is an array of its columns, a row-major one of its rows,
    // each vector rounded up to a vec4.
    const std::uint64_t vectors = member.rowMajor ? rows : columns;
    placement.alignment = 16;
    placement.matrixStride = 16;
    placement.arrayStride = member.arraySize == 0 ? 0 : 16 * vectors;
    placement.size = 16 * vectors * count;
    return placement;
  }

  void placeStd140(UniformBlockDeclaration& block) const {
    std::uint64_t offset = 0;
    for (BlockMember& member : block.members) {
      const auto named = [&](const std::vector<std::string>& names) {
        for (const std::string& name : names) {
          if (name == member.name) return true;
        }
        return false;
      };
      if (named(offsetQualified_)) {
        block.offsetsStop = member.name + " has an explicit offset or align qualifier";
        return;
      }
      if (named(unknownExtent_)) {
        block.offsetsStop = "the array size of " + member.name + " is not a literal number";
        return;
      }
      const auto placement = std140Placement(member);
      if (!placement) {
        block.offsetsStop = member.name + " is a " + member.type + " (not followed)";
        return;
      }
      offset = (offset + placement->alignment - 1) / placement->alignment * placement->alignment;
      if (offset + placement->size > kMaxBlockBytes) {
        block.offsetsStop = member.name + " ends beyond any uniform block's size";
        return;
      }
      member.offset = static_cast<std::uint32_t>(offset);
      member.arrayStride = static_cast<std::uint32_t>(placement->arrayStride);
      member.matrixStride = static_cast<std::uint32_t>(placement->matrixStride);
      offset += placement->size;
    }
  }

  std::vector<std::string> tokens_;
  std::size_t position_ = 0;
  BlockLayout defaultLayout_ = BlockLayout::kShared;
  bool defaultRowMajor_ = false;
  // Members (of the block being read) whose offsets cannot be computed here.
  std::vector<std::string> unknownExtent_, offsetQualified_;
};

}  // namespace

std::vector<UniformBlockDeclaration> parseUniformBlocks(std::string_view source) {
  return BlockReader(tokens(withoutCommentsAndDirectives(source))).read();
}

std::string_view blockLayoutName(BlockLayout layout) {
  switch (layout) {
    case BlockLayout::kStd140:
      return "std140";
    case BlockLayout::kStd430:
      return "std430";
    case BlockLayout::kPacked:
      return "packed";
    case BlockLayout::kShared:
      break;
  }
  return "shared";
}

std::string fixedFunctionTransformRead(std::string_view source) {
  const std::string code = withoutCommentsAndDirectives(source);
  const auto isNameChar = [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  };
  // Whole names only: gl_ProjectionMatrixInverse, say, maps no vertex to clip space.
  std::size_t first = std::string::npos;
  std::string found;
  for (const std::string_view name :
       {"ftransform", "gl_ModelViewProjectionMatrix", "gl_ModelViewProjectionMatrixTranspose",
        "gl_ProjectionMatrix", "gl_ProjectionMatrixTranspose"}) {
    for (std::size_t at = code.find(name); at != std::string::npos; at = code.find(name, at + 1)) {
      const std::size_t end = at + name.size();
      if ((at > 0 && isNameChar(code[at - 1])) || (end < code.size() && isNameChar(code[end]))) {
        continue;
      }
      if (at < first) {
        first = at;
        found = name == "ftransform" ? std::string("ftransform()") : std::string(name);
      }
      break;
    }
  }
  return found;
}

bool mentionsClipDistance(std::string_view source) {
  return withoutCommentsAndDirectives(source).find("gl_ClipDistance") != std::string::npos;
}

}  // namespace clipray::trace
