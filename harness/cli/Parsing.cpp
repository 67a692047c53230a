#include "Parsing.hpp"

#include <cstdlib>
#include <sstream>

#include "clipray/check/ConventionCheck.hpp"
#include "clipray/scene/InputError.hpp"

namespace clipray::cli {

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

Viewport parseViewportOption(const std::string& text, const std::string& option) {
  int width = 0, height = 0;
  char x = 0;
  std::istringstream stream(text);
  if (!(stream >> width >> x >> height) || x != 'x' || !stream.eof() || width <= 0 || height <= 0) {
    throw InputError(option + ": expected WxH with positive integers (e.g. 1920x1080), got \"" +
                     text + "\"");
  }
  return {width, height};
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

glm::dmat4 parseMatrixOption(const std::string& text, bool rowMajor, const std::string& option) {
  return parseMatrix16(parseNumberList(text, option), rowMajor, option);
}

}  // namespace clipray::cli
