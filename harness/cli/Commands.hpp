#pragma once
#include <CLI/CLI.hpp>

namespace clipray::cli {

// Each subcommand registers its options and returns the function that runs it (exit status).
// Exit status: 0 consistent / no errors, 1 inconsistent / errors found, 2 bad input or backend.
struct Subcommand {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

Subcommand addReconcileCommand(CLI::App& parent);

}  // namespace clipray::cli
