#pragma once
// The exit statuses of clipray's tools (clipray, clipray-pick), and the one line that reports the
// exception a command failed with (docs/reconcile.md, "Exit status").

#include <exception>
#include <ostream>
#include <string_view>

namespace clipray {

// 0 and 1 are the commands' own answers (consistent or not, errors found or not).
inline constexpr int kExitUnusableInput = 2;  // bad input, no backend, GL, I/O: nothing to fix here
inline constexpr int kExitInternalError = 3;  // a bug: internal error, please report

// Writes the line for a command that failed with `error` to `err` and returns its exit status:
// an InternalError or any std::logic_error (std::invalid_argument, std::out_of_range, ...: only
// bugs throw them) gives "<program>: internal error, please report: <what>" and 3; everything
// else (InputError, the backends' and GL's errors, I/O and other std::runtime_errors) gives
// "<program>: <what>" and 2.
int reportFailure(const std::exception& error, std::ostream& err, std::string_view program);

}  // namespace clipray
