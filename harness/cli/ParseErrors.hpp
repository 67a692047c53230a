#pragma once
// The option parser's (CLI11's) errors as one line, the way clipray's own errors read
// ("clipray: --size: ..."), with "did you mean" for a misspelt option name. Header-only: used by
// `clipray` (main.cpp) and `clipray-pick` (harness/demo/main.cpp).

#include <CLI/CLI.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "clipray/util/OptionValues.hpp"

namespace clipray::cli {

// The option names `app` takes, as typed: "--size", "-h".
inline std::vector<std::string> optionNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* option : app.get_options()) {
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
    for (const std::string& name : option->get_snames()) names.push_back("-" + name);
  }
  return names;
}

// The first of `arguments` that is written as an option ("--sise", "--sise=1", "-q") but is none
// of `known`, and the closest known name, as "--sise: unknown option; did you mean --size?";
// empty where there is none. Negative numbers and values with spaces are values, not options;
// nothing after "--" is an option.
inline std::string unknownOptionText(const std::vector<std::string>& arguments,
                                     const std::vector<std::string>& known) {
  for (const std::string& argument : arguments) {
    if (argument == "--") break;
    if (argument.size() < 2 || argument[0] != '-') continue;
    if (argument.find(' ') != std::string::npos) continue;
    if ((argument[1] >= '0' && argument[1] <= '9') || argument[1] == '.') continue;  // -1, -.5
    const std::string name = argument.substr(0, argument.find('='));
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    std::vector<std::string> longNames;
    for (const std::string& option : known) {
      if (option.rfind("--", 0) == 0) longNames.push_back(option);
    }
    const std::string suggestion = closestName(name, longNames);
    return name + ": unknown option" +
           (suggestion.empty() ? std::string() : "; did you mean " + suggestion + "?");
  }
  return "";
}

// One line (no newline) for a CLI11 error while parsing `app` (the command being parsed) from
// `arguments` (those after its name): "--sise: unknown option; did you mean --size? (clipray
// reconcile --help lists the options)", "--size: expected a value", else CLI11's message.
// `command` is how a person asks for help ("clipray reconcile").
inline std::string parseErrorText(const CLI::ParseError& error, const CLI::App& app,
                                  const std::vector<std::string>& arguments,
                                  const std::string& command) {
  const std::string message = error.what();
  const std::string help = " (" + command + " --help lists the options)";
  if (dynamic_cast<const CLI::ExtrasError*>(&error) != nullptr) {
    const std::string unknown = unknownOptionText(arguments, optionNames(app));
    if (!unknown.empty()) return unknown + help;
  }
  // "--size: 1 required TEXT missing": an option given last, without its value.
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&error) != nullptr &&
      message.ends_with(" missing") && message.find(" required ") != std::string::npos) {
    return message.substr(0, message.find(':')) + ": expected a value";
  }
  return message;
}

}  // namespace clipray::cli
