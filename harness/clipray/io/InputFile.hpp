#pragma once
// Reading a file a user named, the same way for every reader (scene JSON, mesh files, `check`
// files, the pick script): regular files only, since a FIFO with no writer blocks forever and
// /dev/zero never ends; a size cap checked on the file's size before a byte is read; and text
// files free of NUL bytes, which parsers would otherwise take for the end of the text.

#include <cstdint>
#include <string>
#include <string_view>

namespace clipray {

// Caps per kind of file: far above any real file of the kind, far below what would exhaust
// memory (a scene holds its meshes inline at most; a check file is a few matrices).
inline constexpr std::uint64_t kMaxSceneFileBytes = 256ull << 20;
inline constexpr std::uint64_t kMaxCheckFileBytes = 1ull << 20;
inline constexpr std::uint64_t kMaxScriptFileBytes = 16ull << 20;
// JSON nested deeper than this is refused while parsing (clipray's formats need 5 levels); deeper
// values would take the recursive code that prints, copies and destroys them past the stack.
inline constexpr std::size_t kMaxJsonDepth = 100;

// The whole file. Throws InputError: "<path>: cannot open file", "<path>: is a directory, not a
// file", "<path>: is not a regular file (a FIFO, device or socket)", "<path>: <n> bytes, more than
// the <max> a <what> may have", "<path>: cannot read file".
std::string readInputFile(const std::string& path, std::uint64_t maxBytes, std::string_view what);

// A regular file the process may read, for readers that hand the path to another program
// (apitrace, RenderDoc's replay): the same messages as readInputFile, nothing read.
void requireReadableFile(const std::string& path);

// Throws InputError "<path>: byte <n>: a NUL byte in a text file" for the first NUL byte.
void requireNoNulBytes(std::string_view text, const std::string& path);

}  // namespace clipray
