#pragma once
// Option values as a user types them (command line, check files), shared by the subcommands; every
// failure is an InputError naming the option and the value (exit status 2).

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "clipray/Conventions.hpp"

namespace clipray {

// A number as messages and check reports write it: six significant digits, no "-0", "nan", "inf".
std::string sixDigits(double value);
// "a, b,c" -> {"a", "b", "c"} (spaces around items trimmed, empty items dropped).
std::vector<std::string> splitCommaList(const std::string& text);
// {"a", "b"} -> "a, b"
std::string joinNames(const std::vector<std::string>& names);
// "WxH" with positive integers, each at most maxDimension (GL's viewports are at most 16384 wide on
// common drivers; the reconcile checks the driver's own GL_MAX_VIEWPORT_DIMS as well).
inline constexpr int kMaxViewportDimension = 16384;
Viewport parseViewportOption(const std::string& text, const std::string& option,
                             int maxDimension = kMaxViewportDimension);
// The closest of `names` to `word` by edit distance, if close enough to be a typo; else empty.
std::string closestName(const std::string& word, const std::vector<std::string>& names);
// Numbers separated by spaces and/or commas.
std::vector<double> parseNumberList(const std::string& text, const std::string& option);
// Parses 16 numbers in memory order. Column-major: a GL mat4 as glm::value_ptr or
// glUniformMatrix4fv(..., GL_FALSE, ...) reads it; a DirectXMath XMMATRIX in memory is this order
// too (it stores the transpose, row vectors times the matrix, row by row). Row-major: the matrix
// written out row by row, as in a maths text or a C array m[row][col] of a column-vector matrix.
// `what` names the option or field in messages.
glm::dmat4 parseMatrix16(const std::vector<double>& numbers, bool rowMajor,
                         const std::string& what);
// Sixteen numbers, column-major (GL) or row-major (D3D), all finite.
glm::dmat4 parseMatrixOption(const std::string& text, bool rowMajor, const std::string& option);

}  // namespace clipray
