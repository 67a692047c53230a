#pragma once
// Subcommands register themselves here, one file each (ReconcileCommand.cpp, ...), so adding a
// command touches no other file.

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace clipray::cli {

// Exit status: 0 consistent / no errors, 1 inconsistent / errors found, 2 bad input or backend.
using CommandRunner = std::function<int()>;
// Adds the subcommand's options to `app` and returns what runs it.
using CommandFactory = std::function<CommandRunner(CLI::App& app)>;

struct CommandRegistration {
  std::string name;
  std::string description;
  int order;  // position in --help
  CommandFactory factory;
};

std::vector<CommandRegistration>& commandRegistry();

// The command line the process was started with, each argument shell-quoted where it needs it
// (recorded in report.json); set by main() before any command runs.
const std::string& commandLine();
void setCommandLine(int argc, char** argv);
// Now in UTC, ISO 8601 to the second (when a report was started).
std::string utcNow();

// `static const bool registered = registerCommand({...});` in each command's file.
inline bool registerCommand(CommandRegistration registration) {
  commandRegistry().push_back(std::move(registration));
  return true;
}

}  // namespace clipray::cli
