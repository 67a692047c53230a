#pragma once
// One line of `apitrace dump --color=never --multiline=false`: a call as apitrace's text dumper
// writes it (apitrace/apitrace, lib/trace/trace_dump.cpp, Dumper::visit(Call*)):
//
//   37 glUniformMatrix4fv(location = 0, count = 1, transpose = GL_FALSE, value = {1.299038, ...})
//   8 glViewport(x = 0, y = 0, width = 64, height = 48) // fake
//   28 glGetUniformLocation(program = 1, name = "clipFromWorld") = 0
//
// Values: numbers, enum names, bitmasks ("GL_DEPTH_BUFFER_BIT | GL_COLOR_BUFFER_BIT"), NULL,
// strings with C escapes, arrays and structs in braces, a one-element array as "&value", blobs
// as "blob(36)". Floats are written with 7 significant digits (digits10 + 1 of float), doubles
// with 16, which is what the checker then reads them as.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace clipray::trace {

struct DumpValue {
  std::string text;  // a scalar as written (number, enum name, bitmask); a string's text
  std::vector<DumpValue> items;  // a list's elements ("{...}")
  bool isList = false;
  bool isString = false;

  // The number this scalar writes; nullopt for names, strings and lists.
  std::optional<double> number() const;
};

struct DumpCall {
  std::uint64_t number = 0;
  std::string name;
  std::vector<std::pair<std::string, DumpValue>> arguments;
  std::optional<DumpValue> result;

  // The argument of this name; nullptr when the call has none.
  const DumpValue* argument(std::string_view argumentName) const;
};

// The call number and function name of a call line, without parsing the arguments (most calls in
// a trace are not needed); nullopt for lines that are no call (the "// process.name" header,
// apitrace's "warning: ..." lines).
std::optional<std::pair<std::uint64_t, std::string_view>> dumpCallHead(std::string_view line);

// The file a blob value names when apitrace dumps with --blobs: `blob("blob_call45.bin")` gives
// "blob_call45.bin". nullopt for "blob(36)" (a dump without --blobs) and for any name other than
// blob_call<N>.bin, so a damaged dump cannot name a file outside the dump's folder.
std::optional<std::string> blobFileName(const DumpValue& value);
// Every blob file a dump line names (the files to remove once the line is read).
std::vector<std::string> blobFileNames(std::string_view line);

// The whole call. Throws std::invalid_argument "column N: ..." when the line does not follow the
// dumper's grammar.
DumpCall parseDumpCall(std::string_view line);

}  // namespace clipray::trace
