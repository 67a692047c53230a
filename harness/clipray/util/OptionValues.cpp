#include "clipray/util/OptionValues.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "clipray/InputError.hpp"

namespace clipray {

std::string sixDigits(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value + 0.0);  // + 0.0: no "-0"
  return buffer;
}

std::vector<std::string> splitCommaList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const auto first = item.find_first_not_of(' ');
    if (first == std::string::npos) continue;
    items.push_back(item.substr(first, item.find_last_not_of(' ') - first + 1));
  }
  return items;
}

std::string joinNames(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

Viewport parseViewportOption(const std::string& text, const std::string& option, int maxDimension) {
  int width = 0, height = 0;
  char x = 0;
  std::istringstream stream(text);
  if (!(stream >> width >> x >> height) || x != 'x' || !stream.eof() || width <= 0 || height <= 0) {
    throw InputError(option + ": expected WxH with positive integers (e.g. 1920x1080), got \"" +
                     text + "\"");
  }
  if (width > maxDimension || height > maxDimension) {
    throw InputError(option + ": " + text + " is larger than " + std::to_string(maxDimension) +
                     "x" + std::to_string(maxDimension) + ", the most this takes");
  }
  return {width, height};
}

std::string closestName(const std::string& word, const std::vector<std::string>& names) {
  // Levenshtein distance; a typo is at most a third of the word away (at least 1, at most 3).
  const auto distance = [](const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j) {
        const std::size_t above = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
        diagonal = above;
      }
    }
    return row[b.size()];
  };
  std::string best;
  std::size_t bestDistance =
      std::min<std::size_t>(3, std::max<std::size_t>(1, word.size() / 3)) + 1;
  for (const std::string& name : names) {
    const std::size_t d = distance(word, name);
    if (d < bestDistance) bestDistance = d, best = name;
  }
  return best;
}

std::vector<double> parseNumberList(const std::string& text, const std::string& option) {
  std::string spaced = text;
  for (char& c : spaced) c = c == ',' ? ' ' : c;
  std::istringstream stream(spaced);
  std::vector<double> numbers;
  std::string word;
  while (stream >> word) {
    char* end = nullptr;
    const double value = std::strtod(word.c_str(), &end);
    if (end == word.c_str() || *end != '\0') {
      throw InputError(option + ": \"" + word + "\" is not a number");
    }
    numbers.push_back(value);
  }
  return numbers;
}

glm::dmat4 parseMatrix16(const std::vector<double>& numbers, bool rowMajor,
                         const std::string& what) {
  if (numbers.size() != 16) {
    throw InputError(what + ": expected 16 numbers, got " + std::to_string(numbers.size()));
  }
  glm::dmat4 m(0.0);
  for (int i = 0; i < 16; ++i) {
    if (!std::isfinite(numbers[i])) {
      throw InputError(what + ": number " + std::to_string(i + 1) + " is " + sixDigits(numbers[i]) +
                       "; expected finite numbers");
    }
    // Column-major: element i is (row i % 4, column i / 4); row-major: (row i / 4, column i % 4).
    if (rowMajor) {
      m[i % 4][i / 4] = numbers[i];
    } else {
      m[i / 4][i % 4] = numbers[i];
    }
  }
  return m;
}

glm::dmat4 parseMatrixOption(const std::string& text, bool rowMajor, const std::string& option) {
  return parseMatrix16(parseNumberList(text, option), rowMajor, option);
}

}  // namespace clipray
