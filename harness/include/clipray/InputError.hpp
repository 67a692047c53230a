#pragma once
// Errors in what a user hands clipray (scene files, matrices, command-line values). The CLI turns
// them into a message on stderr and exit status 2. Hot paths never throw these.

#include <stdexcept>
#include <string>

namespace clipray {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
  // "scenes/a.json: /objects/2/radius: expected a positive number, got -1"
  InputError(const std::string& file, const std::string& jsonPointer, const std::string& message)
      : std::runtime_error(file + ": " + jsonPointer + ": " + message) {}
};

}  // namespace clipray
