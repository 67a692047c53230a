#include "clipray/trace/FragDepthWrite.hpp"

#include <cctype>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace clipray::trace {

namespace {

// The source with // and /* */ comments replaced by a space (line breaks inside kept).
std::string withoutComments(std::string_view source) {
  std::string text;
  text.reserve(source.size());
  for (std::size_t k = 0; k < source.size(); ++k) {
    if (source[k] == '/' && k + 1 < source.size() && source[k + 1] == '/') {
      while (k < source.size() && source[k] != '\n') ++k;
      text += '\n';
    } else if (source[k] == '/' && k + 1 < source.size() && source[k + 1] == '*') {
      const std::size_t end = source.find("*/", k + 2);
      const std::size_t stop = end == std::string_view::npos ? source.size() : end + 2;
      for (std::size_t j = k; j < stop; ++j) text += source[j] == '\n' ? '\n' : ' ';
      k = stop - 1;
    } else {
      text += source[k];
    }
  }
  return text;
}

std::string trimmed(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

// An #if / #elif condition: defined(NAME), defined NAME, !defined(NAME), 0 or 1; anything else
// (expressions the check does not evaluate) true.
bool conditionHolds(const std::string& condition, const std::set<std::string>& defined) {
  static const std::regex definedName(R"(^(!?)\s*defined\s*(?:\(\s*(\w+)\s*\)|(\w+))$)");
  std::smatch match;
  const std::string text = trimmed(condition);
  if (std::regex_match(text, match, definedName)) {
    const std::string name = match[2].matched ? match[2].str() : match[3].str();
    return defined.contains(name) != (match[1].length() == 1);
  }
  if (text == "0") return false;
  return true;
}

}  // namespace

bool writesFragDepth(std::string_view source) {
  static const std::regex assignment(R"(\bgl_FragDepth\s*(?:\[[^\]]*\]\s*)?[-+*/]?=(?!=))");
  struct Branch {
    bool enclosingActive;  // the branch around this #if is kept
    bool taken;            // an earlier branch of this #if was kept
  };
  std::vector<Branch> branches;
  std::set<std::string> defined;
  bool active = true;
  std::istringstream lines(withoutComments(source));
  std::string line;
  while (std::getline(lines, line)) {
    const std::string text = trimmed(line);
    if (text.empty() || text[0] != '#') {
      if (active && std::regex_search(text, assignment)) return true;
      continue;
    }
    std::istringstream words(text.substr(1));
    std::string directive, rest;
    words >> directive;
    std::getline(words, rest);
    std::istringstream restWords(rest);
    std::string name;
    restWords >> name;
    if (directive == "define") {
      if (active && !name.empty()) defined.insert(name.substr(0, name.find('(')));
    } else if (directive == "undef") {
      if (active) defined.erase(name);
    } else if (directive == "ifdef" || directive == "ifndef" || directive == "if") {
      const bool holds = directive == "if"      ? conditionHolds(rest, defined)
                         : directive == "ifdef" ? defined.contains(name)
                                                : !defined.contains(name);
      branches.push_back({active, active && holds});
      active = active && holds;
    } else if (directive == "elif" && !branches.empty()) {
      Branch& branch = branches.back();
      active = branch.enclosingActive && !branch.taken && conditionHolds(rest, defined);
      branch.taken = branch.taken || active;
    } else if (directive == "else" && !branches.empty()) {
      Branch& branch = branches.back();
      active = branch.enclosingActive && !branch.taken;
      branch.taken = true;
    } else if (directive == "endif" && !branches.empty()) {
      active = branches.back().enclosingActive;
      branches.pop_back();
    }
  }
  return false;
}

}  // namespace clipray::trace
