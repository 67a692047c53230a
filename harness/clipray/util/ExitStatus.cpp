#include "clipray/util/ExitStatus.hpp"

#include <stdexcept>

namespace clipray {

int reportFailure(const std::exception& error, std::ostream& err, std::string_view program) {
  // InternalError is a std::logic_error too.
  if (dynamic_cast<const std::logic_error*>(&error) != nullptr) {
    err << program << ": internal error, please report: " << error.what() << "\n";
    return kExitInternalError;
  }
  err << program << ": " << error.what() << "\n";
  return kExitUnusableInput;
}

}  // namespace clipray
