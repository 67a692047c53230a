// clipray: reconciles OpenGL rasterization with ray picking. See README.md.

#include <algorithm>
#include <ctime>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "Commands.hpp"
#include "ParseErrors.hpp"
#include "clipray/util/ExitStatus.hpp"
#include "clipray/util/OptionValues.hpp"
#include "clipray/util/Version.hpp"

namespace clipray::cli {
std::vector<CommandRegistration>& commandRegistry() {
  static std::vector<CommandRegistration> registry;
  return registry;
}
namespace {
std::string& storedCommandLine() {
  static std::string line;
  return line;
}
}  // namespace

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

const std::string& commandLine() {
  return storedCommandLine();
}

void setCommandLine(int argc, char** argv) {
  std::string line;
  for (int k = 0; k < argc; ++k) {
    const std::string argument = argv[k];
    const bool plain =
        !argument.empty() && argument.find_first_not_of(
                                 "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOP"
                                 "QRSTUVWXYZ0123456789-_./=:,+@%") == std::string::npos;
    if (k > 0) line += ' ';
    if (plain) {
      line += argument;
      continue;
    }
    line += '\'';
    for (const char c : argument) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += '\'';
  }
  storedCommandLine() = line;
}
}  // namespace clipray::cli

int main(int argc, char** argv) {
  clipray::cli::setCommandLine(argc, argv);
  CLI::App app{"clipray: reconcile OpenGL rasterization with ray picking"};
  app.set_version_flag("--version", "clipray " + clipray::versionString(),
                       "Print the version (and git commit) and exit");
  app.require_subcommand(1);
  auto registry = clipray::cli::commandRegistry();
  std::sort(registry.begin(), registry.end(),
            [](const auto& a, const auto& b) { return a.order < b.order; });
  std::vector<std::pair<CLI::App*, clipray::cli::CommandRunner>> commands;
  std::vector<std::string> names;
  // An option given an empty value ("--size ''", a shell variable left unset) is a mistake, not
  // the option left out: every option that takes a value refuses the empty string.
  const CLI::Validator nonEmpty(
      [](const std::string& value) {
        return value.empty() ? std::string("expected a value, got an empty string") : std::string();
      },
      "", "non-empty");
  for (const auto& registration : registry) {
    CLI::App* sub = app.add_subcommand(registration.name, registration.description);
    commands.emplace_back(sub, registration.factory(*sub));
    names.push_back(registration.name);
    for (CLI::Option* option : sub->get_options()) {
      if (option->get_type_size() > 0 && option->get_name() != "--help") option->check(nonEmpty);
    }
  }
  // No command: the usage, then one line saying what is missing.
  if (argc < 2) {
    std::cerr << app.help()
              << "clipray: no command given; name one of: " << clipray::joinNames(names)
              << " (e.g. clipray reconcile; clipray COMMAND --help lists its options)\n";
    return 2;
  }
  // A mistyped command: CLI11 would say "A subcommand is required" or name the word as an
  // unexpected argument; say which command was probably meant.
  if (argv[1][0] != '-' && std::find(names.begin(), names.end(), argv[1]) == names.end()) {
    const std::string suggestion = clipray::closestName(argv[1], names);
    std::cerr << "clipray: unknown command \"" << argv[1] << "\""
              << (suggestion.empty() ? "" : "; did you mean \"" + suggestion + "\"?")
              << " (commands: " << clipray::joinNames(names) << ")\n";
    return 2;
  }
  // The command being parsed (argv[1] names one, else the options are clipray's own) and the
  // arguments after its name.
  const bool command = argv[1][0] != '-';
  const CLI::App* parsed = command ? app.get_subcommand(argv[1]) : &app;
  const std::vector<std::string> arguments(argv + (command ? 2 : 1), argv + argc);
  const std::string usage = command ? "clipray " + std::string(argv[1]) : "clipray";
  // An unknown option before any command: CLI11 would say "A subcommand is required".
  if (!command) {
    const std::string unknown =
        clipray::cli::unknownOptionText(arguments, clipray::cli::optionNames(app));
    if (!unknown.empty()) {
      std::cerr << "clipray: " << unknown << " (clipray --help lists the commands)\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help and --version print what they were asked for; every other parse error is one line
    // and status 2 (CLI11 has its own codes and a second line).
    if (error.get_exit_code() == 0) return app.exit(error);
    std::cerr << "clipray: " << clipray::cli::parseErrorText(error, *parsed, arguments, usage)
              << "\n";
    return 2;
  }
  try {
    for (const auto& [sub, run] : commands) {
      if (sub->parsed()) return run();
    }
  } catch (const std::bad_alloc&) {
    std::cerr << "clipray: out of memory: the runs need more memory than this machine has free; "
                 "try a smaller --size, fewer scenes or fewer --threads\n";
    return clipray::kExitUnusableInput;
  } catch (const std::exception& error) {
    // Bad input, a backend, GL, I/O: a message and status 2; a broken invariant (a bug): "internal
    // error, please report" and status 3. Never a crash.
    return clipray::reportFailure(error, std::cerr, "clipray");
  }
  return 2;
}
